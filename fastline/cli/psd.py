"""Measured surfaces on the command line: ``fastline psd SCAN`` and ``--scan FILE``.

``fastline psd`` reads a line scan, parallel line scans or a height map and prints its
spectrum C(q) (the data's h_rms and rms slope, the usable wavenumber range and why, the fitted
self-affine model), writes the table ``--psd`` reads and a figure. ``--scan FILE`` on
``profile``, ``sweep`` and ``leak`` takes the spectrum of a scene straight from a measurement.
Argument parsing and printing only: the analysis is :func:`fastline.surfaces.scan.analyse_scan`
(docs/topography.md), the table :func:`fastline.io.write_spectrum`, the figure
:func:`fastline.reports.plotting.plot_measured_psd`. :mod:`fastline.cli.app` wires :func:`psd_parser` and
:func:`cmd_psd` in.

SI units throughout: lengths in m whatever the file's units, wavenumbers in 1/m, C(q) in m^4.
"""

from __future__ import annotations

import argparse

from fastline.cli.common import (
    _SPECTRUM_FLAGS,
    CLIError,
    _check_outputs,
    _count,
    _figure_options,
    _positive,
    _require_matplotlib,
    _save,
    _ScanSource,
    _warn,
)

__all__ = ["psd_parser", "cmd_psd"]

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
}


def _wavenumber_or_auto(text: str):
    return None if text == "auto" else _positive(text)


def _scan_options(parser: argparse.ArgumentParser, standalone: bool = False) -> None:
    """The options that read a measured surface and take its spectrum: ``--scan FILE`` and its
    settings (profile, sweep, leak), or the settings of ``fastline psd SCAN`` (with --q1)."""
    g = parser.add_argument_group(
        "measured surface" + ("" if standalone else " (--scan)"),
        "A line scan, parallel line scans or a height map, read from a file and turned into the "
        "isotropic spectrum C(q) over the range the measurement can be trusted "
        "(fastline.surfaces.scan.analyse_scan; docs/topography.md). Lengths in m whatever the file's "
        "units; wavenumbers in 1/m."
        + (
            ""
            if standalone
            else " --scan replaces --psd and the self-affine options; --q1 then cuts the "
            "measured C(q) at q1 or, with --extend, continues it to q1."
        ),
    )
    if not standalone:
        g.add_argument(
            "--scan",
            metavar="FILE",
            help="measured surface to take the spectrum from (the formats of fastline psd SCAN)",
        )
    g.add_argument(
        "--dx",
        type=_positive,
        metavar="M",
        help="spacing of the heights along the scan [m] (metres whatever --units); needed "
        "when the file holds heights only, not x and h columns or an instrument format",
    )
    g.add_argument(
        "--dy",
        type=_positive,
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
        help="unit of the heights in a text or .npy file (default m; um for micrometres); "
        "instrument files carry their own",
    )
    g.add_argument(
        "--x-units",
        choices=_LENGTH_UNITS,
        help="unit of the x column of a two-column (x, h) file (default: --units)",
    )
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
        type=_count,
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
    g.add_argument(
        "--tip-radius",
        type=_positive,
        metavar="M",
        help="stylus tip radius [m]: the range ends where the tip cannot follow the surface",
    )
    g.add_argument(
        "--noise",
        type=_positive,
        metavar="M",
        help="rms instrument noise [m]: the range ends where C falls below 10x its floor",
    )
    if standalone:
        g.add_argument(
            "--q1",
            type=_positive,
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


def psd_parser(sub: argparse._SubParsersAction, fmt: type[argparse.HelpFormatter]) -> None:
    """The ``psd`` command: a measured surface's spectrum, its table and figure."""
    p = sub.add_parser(
        "psd",
        help="spectrum C(q) of a measured surface: summary, fit, table for --psd, figure",
        formatter_class=fmt,
        description="Read a line scan, parallel line scans or a height map and print its "
        "spectrum: h_rms and rms slope of the data, the usable wavenumber range and the rule "
        "behind each end, the fitted self-affine model (H, q_r, h_rms with standard errors) "
        "and the C(q) table. --out writes the table (q [1/m], C(q) [m^4], Persson's isotropic "
        "convention h_rms^2 = 2 pi int q C dq) that --psd reads; --plot a figure of C1D (line "
        "scans), C(q) and the fit. Exit status 0 done, 2 bad usage or input.",
    )
    p.add_argument(
        "scan",
        metavar="SCAN",
        help="the measurement: text (.txt .csv .dat .tsv .prn; one column of heights with "
        "--dx, two columns x and h, or one scan per line with --dx; '#' comments and header "
        "lines skipped), .npy, or an instrument file (X3P, SDF, OPDx, Mitutoyo, Keyence, Zygo, "
        'Sensofar, ...), which needs pip install "fastline-contact[topography]" to be read',
    )
    _scan_options(p, standalone=True)
    p.add_argument(
        "--out",
        metavar="FILE",
        help="write the isotropic C(q) table to FILE: two columns q [1/m], C(q) [m^4], the "
        "measurement and fit in '#' header lines (for --psd FILE)",
    )
    p.add_argument(
        "--plot",
        metavar="FILE",
        help="write a figure of C1D(k) (line scans), C(q) and the fit, log-log",
    )
    _figure_options(p)


def _scan_checks(args) -> bool:
    """Whether the spectrum comes from --scan; refuses combinations that cannot be meant."""
    given = [f for key, f in _SCAN_FLAGS.items() if getattr(args, key, None) not in (None, False)]
    if getattr(args, "scan", None) is None:
        if given:
            verb = "needs" if len(given) == 1 else "need"
            raise CLIError(f"{', '.join(given)} {verb} --scan FILE (options of a measured surface)")
        return False
    if getattr(args, "psd", None) is not None:
        raise CLIError("give either --psd (a spectrum table) or --scan (a measurement), not both")
    model = [f for key, f in _SPECTRUM_FLAGS.items() if key != "q1" and getattr(args, key, None)]
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
    """The options of fastline.surfaces.scan.analyse_scan that were given (the rest keep its defaults)."""
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


def _scan_analysis(args):
    """analyse_scan on --scan / SCAN; its warnings once each, its errors as usage errors."""
    import warnings

    from fastline.surfaces.scan import analyse_scan
    from fastline.surfaces.topography import TopographyWarning

    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        try:
            return analyse_scan(args.scan, **_scan_kwargs(args))
        except (FileNotFoundError, ImportError) as e:
            raise CLIError(str(e)) from None
        except OSError as e:
            raise CLIError(f"cannot read {args.scan}: {e.strerror or e}") from None
        except ValueError as e:
            raise CLIError(_cli_message(str(e))) from None
        finally:  # also when it failed: a unit slip warns first, then breaks a check
            _print_warnings(caught, TopographyWarning)


def _print_warnings(caught, unit_warning) -> None:
    """Each recorded warning once, those about units with the options that set them."""
    seen = set()
    for w in caught:
        text = str(w.message)
        if issubclass(w.category, unit_warning) and "wrong unit" in text:
            text += " (--units gives the unit of the file's heights; --dx is in m)"
        if text not in seen:
            seen.add(text)
            _warn(text)


def _scan_lines(scan, table: bool) -> list[str]:
    """The spectrum summary: what was read, the data, the range and why, the fit, the table."""
    from fastline.surfaces.scan import LIMIT_RULES

    lines = [f"scan             {scan.path}: {scan.describe()}"]
    if scan.spectrum is not None:
        s = scan.spectrum
        lines.append(
            f"data             h_rms {s.h_rms:.4g} m, rms slope {s.rms_slope:.4g} (detrended "
            "heights; slope from differences at dx)"
        )
    lo, hi = scan.q_range
    lines.append(
        f"q range used     {lo:.4g}-{hi:.4g} 1/m; low end: {LIMIT_RULES[scan.limits['low']]}; "
        f"high end: {LIMIT_RULES[scan.limits['high']]}"
    )
    f = scan.fit
    hurst = f"H {f.hurst:.3f} ± {f.hurst_err:.2g}"
    if f.hurst_at_bound:  # held there: no error bar
        steeper = "faster" if f.hurst >= 1.0 else "slower"
        hurst = f"H {f.hurst:g} (held at its bound: C falls {steeper} than self-affine can)"
    qr = f"q_r {f.qr:.4g} ± {f.qr_err:.2g} 1/m"
    if f.qr_at_bound:
        qr = f"q_r {f.qr:.4g} 1/m not resolved (the roll-off may lie anywhere below)"
    lines.append(
        f"fit              {hurst}, {qr}, h_rms {f.h_rms:.4g} ± {f.h_rms_err:.2g} m "
        f"(self-affine with roll-off fitted to {f.fitted_to} over {f.q_range[0]:.4g}-"
        f"{f.q_range[1]:.4g} 1/m; scatter of ln {f.fitted_to.split('(')[0]} "
        f"{f.rms_residual:.2g} rms, {f.n_points} points)"
    )
    if table:
        t = scan.psd
        lines.append(
            f"C(q) table       {t.q.size} points, q {t.q0:.4g}-{t.q1:.4g} 1/m: h_rms "
            f"{t.h_rms:.4g} m, rms slope {t.rms_slope:.4g}"
        )
    if scan.extended_from is not None:
        lines.append(
            f"continued        above {scan.extended_from:.4g} 1/m to q1 = {scan.psd.q1:.4g} 1/m "
            f"as C ~ q^-{2.0 * (1.0 + f.hurst):.3g} (the fitted H): an assumption, not a "
            "measurement"
        )
    return lines


def _scan_scene(args):
    """(psd, source) of --scan: output paths checked first, the analysis printed."""
    _check_outputs(args)
    scan = _scan_analysis(args)
    print("\n".join(_scan_lines(scan, table=False)))
    source = _ScanSource(args.scan)
    source.scan = scan
    return scan.psd, source


def cmd_psd(args: argparse.Namespace) -> int:
    """Run ``fastline psd SCAN``; returns the exit status (0 done)."""
    from fastline.io import check_output_file, write_spectrum

    _scan_checks(args)
    for path in (args.out, args.plot):
        if path is not None:
            check_output_file(path)
    if args.plot is not None:
        _require_matplotlib()
    scan = _scan_analysis(args)
    print("\n".join(_scan_lines(scan, table=True)))
    written = []
    if args.out:
        from fastline import __version__

        title = (
            f"fastline psd: isotropic power spectrum C(q) of {args.scan}\n"
            "Persson's convention, h_rms^2 = 2 pi int q C dq; columns q [1/m], C(q) [m^4]; "
            "read it with --psd FILE or fastline.io.read_spectrum"
        )
        meta = {"fastline_version": __version__, **scan.metadata()}
        write_spectrum(args.out, scan.psd, meta, title=title)
        written.append(args.out)
    if args.plot:
        from fastline.reports.plotting import plot_measured_psd

        _save(plot_measured_psd(scan), args.plot, args)
        written.append(args.plot)
    if written:
        print(f"wrote {', '.join(written)}")
    return 0
