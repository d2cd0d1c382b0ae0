"""The scene the options describe: its spectrum (self-affine, a ``--psd`` table or a ``--scan``
measurement) and material, and measured surfaces on the command line.

:func:`scene` turns the options of ``profile``, ``sweep`` and ``leak`` into (spectrum, E*,
source); :func:`run_profile` solves one scene of ``profile`` for either geometry. The options of
a measured surface (:func:`scan_options`), their checks (:func:`scan_checks`), the analysis
(:func:`scan_analysis`, :func:`fastline.surfaces.analyse_scan`; docs/topography.md) and its
summary (:meth:`fastline.surfaces.ScanSpectrum.summary`) serve both ``--scan FILE`` and
``fastline psd SCAN`` (:mod:`fastline.cli.psd`).

SI units throughout: lengths in m whatever the file's units, wavenumbers in 1/m, C(q) in m^4.
"""

from __future__ import annotations

import argparse
import warnings
from typing import TYPE_CHECKING

import fastline as fl
from fastline import surfaces
from fastline.cli.common import (
    SPECTRUM_DEFAULTS,
    SPECTRUM_FLAGS,
    CLIError,
    ScanSource,
    check_outputs,
    convergence_status,
    count,
    law_option,
    persson_theory,
    positive,
    report_warnings,
    save,
    solve_kwargs,
    spectrum_line,
    warn,
)

if TYPE_CHECKING:  # annotations only
    from collections.abc import Callable
    from typing import TypeVar

    from fastline import PSD, LineContactResult, PointContactResult
    from fastline.surfaces import ScanSpectrum

    #: the result of one solve: a cylinder's or a sphere's, the same throughout run_profile
    _Result = TypeVar("_Result", LineContactResult, PointContactResult)

__all__ = [
    "scene",
    "run_profile",
    "scan_options",
    "scan_checks",
    "scan_analysis",
]

#: the options of a measured surface (dest -> flag); all default to None (False for switches)
_SCAN_FLAGS = {
    "dx": "--dx",
    "dy": "--dy",
    "map": "--map",
    "units": "--units",
    "x_units": "--x-units",
    "window": "--window",
    "detrend": "--detrend",
    "nan": "--nan",
    "bins_per_decade": "--bins-per-decade",
    "q_range": "--q-range",
    "tip_radius": "--tip-radius",
    "noise": "--noise",
    "extend": "--extend",
}
_LENGTH_UNITS = ("m", "mm", "um", "nm")
#: the library's spelling of an option in its messages -> the command line's
_CLI_SPELLING = {
    "nan='interpolate'": "--nan interpolate",
    "extend=True (--extend on the command line)": "--extend",
    "as_map=True (--map)": "--map",
    "dx (m)": "--dx [m]",
    ": dx = ": ": --dx = ",
}


def _wavenumber_or_auto(text: str):
    return None if text == "auto" else positive(text)


def scan_options(parser: argparse.ArgumentParser, standalone: bool = False) -> None:
    """The options that read a measured surface and take its spectrum: ``--scan FILE`` and its
    settings (profile, sweep, leak), or the settings of ``fastline psd SCAN`` (with --q1)."""
    g = parser.add_argument_group(
        "measured surface" + ("" if standalone else " (--scan)"),
        "A line scan, parallel line scans or a height map, read from a file and turned into the "
        "isotropic spectrum C(q) over the range the measurement can be trusted "
        "(fastline.surfaces.analyse_scan; docs/topography.md). Lengths in m whatever the file's "
        "units; wavenumbers in 1/m."
        + (
            ""
            if standalone
            else " --scan replaces --psd and the self-affine options; --q1 then cuts the "
            "measured C(q) at q1 or, with --extend, continues it to q1."
        ),
    )
    _scan_file_options(g, standalone)
    _scan_spectrum_options(g)
    _scan_range_options(g, standalone)


def _scan_file_options(g, standalone: bool) -> None:
    """What to read and how: --scan (not for ``fastline psd``), spacings, map, units."""
    if not standalone:
        g.add_argument(
            "--scan",
            metavar="FILE",
            help="measured surface to take the spectrum from (the formats of fastline psd SCAN)",
        )
    g.add_argument(
        "--dx",
        type=positive,
        metavar="M",
        help="spacing of the heights along the scan [m] (metres whatever --units); needed "
        "when the file holds heights only, not x and h columns or an instrument format",
    )
    g.add_argument(
        "--dy",
        type=positive,
        metavar="M",
        help="spacing between the rows of a height map [m] (with --map; default --dx)",
    )
    g.add_argument(
        "--map",
        action="store_true",
        help="analyse a 2D file as a height map (ring-averaged 2D spectrum); default: its rows "
        "are parallel line scans along x (1D spectra averaged, exact inverse Abel transform)",
    )
    g.add_argument(
        "--units",
        choices=_LENGTH_UNITS,
        help="unit of the heights in a text or .npy file (um for micrometres); default: the "
        'unit the file\'s header names for them ("h [um]", a units line), else m; given with '
        "such a header it must agree with it; instrument files carry their own",
    )
    g.add_argument(
        "--x-units",
        choices=_LENGTH_UNITS,
        help="unit of the x column of a two-column (x, h) file; default: the unit the "
        "header names for x, else the heights' unit (with a warning when that is not m)",
    )


def _scan_spectrum_options(g) -> None:
    """How the spectrum is taken: window, detrending, dropouts, averaging, range override."""
    g.add_argument(
        "--window",
        metavar="NAME",
        help="window applied to each scan: hann (default), none, or a scipy.signal window "
        "name (blackman, hamming, ...)",
    )
    g.add_argument(
        "--detrend",
        choices=("linear", "mean", "parabola", "circle", "plane"),
        help="form removed first: for line scans linear (default), mean, parabola or circle (a "
        "cylinder's own form); for a map (--map) plane (default) or mean",
    )
    g.add_argument(
        "--nan",
        choices=("raise", "interpolate"),
        help="missing heights (dropouts: empty fields, nan): refuse the file (default) or "
        "bridge them by straight lines (at most 20%% of the points)",
    )
    g.add_argument(
        "--bins-per-decade",
        type=count,
        metavar="N",
        help="points per decade of wavenumber the spectrum is averaged into (default 20; "
        "fewer give a smoother C(q) from few scans)",
    )
    g.add_argument(
        "--q-range",
        nargs=2,
        type=_wavenumber_or_auto,
        metavar=("LO", "HI"),
        help="override the usable wavenumber range [1/m]; 'auto' keeps the rule for that end "
        "(e.g. --q-range 2e4 auto)",
    )


def _scan_range_options(g, standalone: bool) -> None:
    """Where the usable range ends (tip, noise) and what lies above it (--q1, --extend)."""
    g.add_argument(
        "--tip-radius",
        type=positive,
        metavar="M",
        help="stylus tip radius [m]: the range ends where the tip cannot follow the surface",
    )
    g.add_argument(
        "--noise",
        type=positive,
        metavar="M",
        help="rms instrument noise [m]: the range ends where C falls below 10x its floor",
    )
    if standalone:
        g.add_argument(
            "--q1",
            type=positive,
            metavar="1/M",
            help="cut the C(q) table at q1 [1/m], or with --extend continue it to q1 (e.g. "
            "1e9 1/m, atomic scale)",
        )
    g.add_argument(
        "--extend",
        action="store_true",
        help="continue C(q) above the usable range to --q1 as the power law of the fitted H "
        "(an assumption, not a measurement: the contact depends on it through the rms slope)",
    )


def scan_checks(args: argparse.Namespace) -> bool:
    """Whether the spectrum comes from --scan; refuses combinations that cannot be meant."""
    given = [f for key, f in _SCAN_FLAGS.items() if getattr(args, key, None) not in (None, False)]
    if getattr(args, "scan", None) is None:
        if given:
            verb = "needs" if len(given) == 1 else "need"
            raise CLIError(f"{', '.join(given)} {verb} --scan FILE (options of a measured surface)")
        return False
    if getattr(args, "psd", None) is not None:
        raise CLIError("give either --psd (a spectrum table) or --scan (a measurement), not both")
    model = [f for key, f in SPECTRUM_FLAGS.items() if key != "q1" and getattr(args, key, None)]
    if model:
        raise CLIError(
            f"--scan cannot be combined with {', '.join(model)}: the scan defines the spectrum "
            "(--q1 cuts it, with --extend continues it)"
        )
    if args.extend and args.q1 is None:
        raise CLIError("--extend needs --q1 [1/m], the wavenumber to continue C(q) to (e.g. 1e9)")
    if args.dy is not None and not args.map:
        raise CLIError("--dy is the row spacing of a height map: it needs --map")
    return True


def _scan_kwargs(args) -> dict:
    """The options of fastline.surfaces.analyse_scan that were given (the rest keep its
    defaults)."""
    q_range = None if args.q_range is None else tuple(args.q_range)
    kw = {
        "dx": args.dx,
        "dy": args.dy,
        "unit": args.units,
        "x_unit": args.x_units,
        "window": args.window,
        "detrend": args.detrend,
        "nan": args.nan,
        "bins_per_decade": args.bins_per_decade,
        "q_range": None if q_range in (None, (None, None)) else q_range,
        "tip_radius": args.tip_radius,
        "noise": args.noise,
        "q1": args.q1,
    }
    return {**{k: v for k, v in kw.items() if v is not None}, "as_map": args.map,
            "extend": args.extend}  # fmt: skip


def _cli_message(text: str) -> str:
    for api, cli in _CLI_SPELLING.items():
        text = text.replace(api, cli)
    return text


def scan_analysis(args: argparse.Namespace) -> ScanSpectrum:
    """analyse_scan on --scan / SCAN; its warnings once each, its errors as usage errors."""

    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        try:
            return surfaces.analyse_scan(args.scan, **_scan_kwargs(args))
        except (FileNotFoundError, ImportError) as e:
            raise CLIError(str(e)) from None
        except OSError as e:
            raise CLIError(f"cannot read {args.scan}: {e.strerror or e}") from None
        except ValueError as e:
            raise CLIError(_cli_message(str(e))) from None
        finally:  # also when it failed: a unit slip warns first, then breaks a check
            _print_warnings(caught, fl.topography.TopographyWarning)


def _print_warnings(caught, unit_warning) -> None:
    """Each recorded warning once, those about units with the options that set them."""
    seen = set()
    for w in caught:
        text = str(w.message)
        text = text.removeprefix("fastline: ")
        if issubclass(w.category, unit_warning) and "wrong unit" in text:
            text += " (--units gives the unit of the file's heights; --dx is in m)"
        if text not in seen:
            seen.add(text)
            warn(text)


def _scan_scene(args):
    """(psd, source) of --scan: output paths checked first, the analysis printed."""
    check_outputs(args)
    scan = scan_analysis(args)
    print(scan.summary(table=False))
    source = ScanSource(args.scan)
    source.scan = scan
    return scan.psd, source


def checked_modulus(E_star: float, name: str) -> float:
    """E* checked by :func:`fastline.check_modulus`; its unit-slip warning printed once."""
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        E_star = fl.check_modulus(E_star, name)
    _print_warnings(caught, fl.UnitWarning)
    return E_star


def scene(args: argparse.Namespace) -> tuple[PSD, float, str | None]:
    """(psd, E_star, source file or None) from the scene options; with ``--law FILE`` the
    calibrated law, checked against them, becomes ``args.model``."""
    psd, E_star, source = _scene(args)
    law_option(args, psd, E_star)
    return psd, E_star, source


def _scene(args: argparse.Namespace) -> tuple[PSD, float, str | None]:
    elastic = [args.E1, args.nu1, args.E2, args.nu2]
    if any(v is not None for v in elastic):
        if args.E_star is not None:
            raise CLIError("give either --E-star or --E1/--nu1/--E2/--nu2, not both")
        if any(v is None for v in elastic):
            raise CLIError("--E1, --nu1, --E2 and --nu2 must be given together")
        E_star = checked_modulus(fl.effective_modulus(args.E1, args.nu1, args.E2, args.nu2),
                                 "E* of --E1/--nu1/--E2/--nu2")  # fmt: skip
    else:
        E_star = 1.33e9 if args.E_star is None else checked_modulus(args.E_star, "--E-star")
    if scan_checks(args):
        psd, source = _scan_scene(args)
        return psd, E_star, source
    given = [flag for key, flag in SPECTRUM_FLAGS.items() if getattr(args, key) is not None]
    if args.psd is not None:
        if given:
            raise CLIError(
                f"--psd cannot be combined with {', '.join(given)}: the file defines the spectrum"
            )
        return fl.io.read_spectrum(args.psd), E_star, args.psd
    spec = {
        k: v if getattr(args, k) is None else getattr(args, k) for k, v in SPECTRUM_DEFAULTS.items()
    }
    return fl.SelfAffinePSD(**spec), E_star, None


def run_profile(
    args: argparse.Namespace,
    solve: Callable[..., _Result],
    result_lines: Callable[[_Result, dict], list[str]],
    write_csv: Callable[[str, _Result, dict], None],
    meta: Callable[[PSD, float, argparse.Namespace, str | None], dict],
) -> int:
    """One scene of ``fastline profile`` for either geometry: solve with ``solve(psd, E*, R,
    load, ...)``, print the spectrum and ``result_lines``, report the warnings, write the CSV
    (``write_csv(path, result, meta(psd, E*, args, source))``) and the figure; the exit status."""
    psd, E, source = scene(args)
    check_outputs(args)
    th = persson_theory(psd, E, args)
    r = solve(psd, E, args.radius, args.load, model=args.model, **solve_kwargs(args, th))
    print(spectrum_line(psd, source, args.model))
    print("\n".join(result_lines(r, r.diagnostics)))
    report_warnings([r])
    if args.csv:
        write_csv(args.csv, r, meta(psd, E, args, source))
    if args.plot:
        save(fl.plotting.plot_profile(r), args.plot, args)
    return convergence_status([r])
