"""What the commands of :mod:`fastline.cli.app` share: option types and groups, the scene, outputs.

The option types (``_number``, ``_positive``, ...) check one value for argparse; the option
groups (spectrum, material, numerics, figures) are added to several commands; ``_scene`` turns
the options into (spectrum, E*, source), ``_check_outputs`` checks every output path before any
solve, and the printing helpers report results, warnings (once per cause) and convergence.

The command modules (:mod:`fastline.cli.leak`, :mod:`fastline.cli.psd`,
:mod:`fastline.cli.sphere`) import this one; the two options that belong to them (``--scan``
and ``--geometry``) are taken from them on use, so that no module imports another at import
time in a cycle. Nothing heavy is imported here at import time.

SI units throughout: m, 1/m, m^4, Pa, N/m (N for a sphere).
"""

from __future__ import annotations

import argparse
import math
import sys

#: defaults of the self-affine spectrum options (the paper's surface 1)
SPECTRUM_DEFAULTS = {"h_rms": 10e-6, "hurst": 0.8, "q0": 1e3, "qr": 1e4, "q1": 1e9}
_SPECTRUM_FLAGS = {"h_rms": "--h-rms", "hurst": "--hurst", "q0": "--q0", "qr": "--qr", "q1": "--q1"}


class CLIError(Exception):
    """A user error: reported as one line on stderr, exit status 2."""


# ----------------------------------------------------------------------------------------------
# option types
# ----------------------------------------------------------------------------------------------
def _number(text: str) -> float:
    try:
        v = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"not a number: {text!r}") from None
    if not math.isfinite(v):
        raise argparse.ArgumentTypeError(f"must be a finite number, got {text!r}")
    return v


def _positive(text: str) -> float:
    v = _number(text)
    if v <= 0.0:
        raise argparse.ArgumentTypeError(f"must be > 0, got {text!r}")
    return v


def _count(text: str) -> int:
    try:
        v = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"not an integer: {text!r}") from None
    if v < 1:
        raise argparse.ArgumentTypeError(f"must be >= 1, got {text!r}")
    return v


def _fraction(text: str) -> float:
    v = _number(text)
    if not 0.0 < v < 1.0:
        raise argparse.ArgumentTypeError(f"must lie in (0, 1), got {text!r}")
    return v


def _gamma(text: str) -> float:
    from fastline.theory.persson import GAMMA_RANGE

    v = _number(text)
    lo, hi = GAMMA_RANGE
    if not lo <= v <= hi:
        raise argparse.ArgumentTypeError(f"must lie in [{lo:g}, {hi:g}], got {text!r}")
    return v


# ----------------------------------------------------------------------------------------------
# parser
# ----------------------------------------------------------------------------------------------
def _spectrum_options(parser: argparse.ArgumentParser) -> None:
    g = parser.add_argument_group(
        "roughness spectrum",
        "Self-affine spectrum with roll-off: C(q) = C0 for q0 <= q < qr, C0 (q/qr)^(-2(1+H)) for "
        "qr <= q <= q1, normalised so that h_rms^2 = 2 pi int q C(q) dq (Persson's isotropic "
        "convention), or a measured spectrum (--psd, not combined with the others). Use the "
        "combined spectrum of both surfaces (C = C1 + C2). Defaults: the paper's surface 1.",
    )
    g.add_argument(
        "--h-rms", type=_positive, metavar="M", help="rms roughness h_rms [m] (default 10e-6)"
    )
    g.add_argument(
        "--hurst", type=_number, metavar="H", help="Hurst exponent H [-], 0 < H <= 1 (default 0.8)"
    )
    g.add_argument(
        "--q0", type=_positive, metavar="1/M", help="smallest wavenumber q0 [1/m] (default 1e3)"
    )
    g.add_argument(
        "--qr", type=_positive, metavar="1/M", help="roll-off wavenumber qr [1/m] (default 1e4)"
    )
    g.add_argument(
        "--q1",
        type=_positive,
        metavar="1/M",
        help="large-wavenumber cut-off q1 [1/m] (default 1e9)",
    )
    g.add_argument(
        "--psd",
        metavar="FILE",
        help="measured isotropic spectrum: two columns q [1/m] and C(q) [m^4], separated by "
        "blanks, tabs, ',' or ';'; header lines before the numbers and '#' comments skipped "
        "(e.g. examples/psd_example.txt)",
    )


def _material_options(parser: argparse.ArgumentParser, load: bool, geometry: bool = False) -> None:
    m = parser.add_argument_group(
        "material and geometry",
        "Give the effective modulus directly or the two solids' elastic constants "
        "(1/E* = (1-nu1^2)/E1 + (1-nu2^2)/E2).",
    )
    m.add_argument(
        "--E-star",
        type=_positive,
        metavar="PA",
        help="effective (plane-strain) modulus E* [Pa] (default 1.33e9 when no "
        "--E1/--nu1/--E2/--nu2 are given)",
    )
    m.add_argument("--E1", type=_positive, metavar="PA", help="Young's modulus of solid 1 [Pa]")
    m.add_argument("--nu1", type=_number, metavar="NU", help="Poisson ratio of solid 1 [-]")
    m.add_argument("--E2", type=_positive, metavar="PA", help="Young's modulus of solid 2 [Pa]")
    m.add_argument("--nu2", type=_number, metavar="NU", help="Poisson ratio of solid 2 [-]")
    if geometry:
        from fastline.cli.sphere import _geometry_options

        _geometry_options(m, load)
        return
    m.add_argument(
        "--radius",
        type=_positive,
        default=0.01,
        metavar="M",
        help="cylinder radius R [m] (default 0.01)",
    )
    if load:
        m.add_argument(
            "--load",
            type=_positive,
            default=1e4,
            metavar="N/M",
            help="normal load per unit cylinder length f_N [N/m] (default 1e4)",
        )


def _numerics_options(
    parser: argparse.ArgumentParser, model: bool = True, geometry: bool = False
) -> None:
    s = parser.add_argument_group("model and numerics")
    if model:
        s.add_argument(
            "--model",
            choices=("persson", "exponential", "hertz"),
            default="persson",
            help="pressure-separation law: full Persson theory (default), its exponential "
            "approximation p = beta E* exp(-u/u0), or smooth Hertz contact",
        )
    s.add_argument(
        "--gamma",
        type=_gamma,
        default=None,
        metavar="G",
        help="parameter gamma of the theory's correction S(P), in [0.05, 1] (default: the "
        "variant's, 0.45; 5/9 for wang-mueser)",
    )
    _variant_option(s)
    s.add_argument(
        "--n",
        type=_count,
        default=None if geometry else 1024,
        metavar="N",
        help="grid points across the contact (default 1024, at least 16)"
        + ("; with --geometry sphere: cells from the axis outwards (default 512, at most 4096)"
           if geometry else ""),
    )  # fmt: skip
    s.add_argument(
        "--max-iter",
        type=_count,
        metavar="K",
        help="Newton steps allowed per solve (default: the solver's, 100)",
    )
    s.add_argument(
        "--hardness",
        type=_positive,
        metavar="PA",
        help="indentation hardness of the softer solid [Pa]: warns when the elastic mean "
        "asperity pressure h' E*/2 exceeds it (plastic flow likely)",
    )


def _variant_option(group) -> None:
    from fastline.theory.variants import DEFAULT_VARIANT, VARIANTS

    group.add_argument(
        "--variant",
        choices=tuple(VARIANTS),
        default=None,  # fastline.cli.app.main fills in DEFAULT_VARIANT: None says 'not given'
        help="variant of the theory's u(p) (docs/theory.md, Variants): the bracket gamma + "
        "3(1-gamma)P^2 of the energy derivation (default, " + DEFAULT_VARIANT + "), the printed "
        "gamma + (1-gamma)P^2, or Wang & Mueser's correction, which also enters the contact "
        "area (not with leak)",
    )


#: options a smooth (--model hertz) solve does not use: the roughness and the theory's
_ROUGH_ONLY = {
    **_SPECTRUM_FLAGS,
    "psd": "--psd",
    "scan": "--scan",
    "gamma": "--gamma",
    "variant": "--variant",
    "hardness": "--hardness",
}


def _model_checks(args) -> None:
    """Refuse roughness and theory options that a smooth Hertz solve would ignore (before the
    defaults of --gamma and --variant are filled in: None means not given)."""
    if getattr(args, "model", None) != "hertz":
        return
    given = [flag for key, flag in _ROUGH_ONLY.items() if getattr(args, key, None) is not None]
    if given:
        it, has = ("it", "has") if len(given) == 1 else ("them", "have")
        raise CLIError(
            f"--model hertz solves smooth surfaces: {', '.join(given)} {has} no effect on a "
            f"Hertz solve (drop {it}, or use --model persson or exponential)"
        )


def _figure_options(parser: argparse.ArgumentParser) -> None:
    g = parser.add_argument_group("figures")
    g.add_argument(
        "--format",
        choices=("png", "pdf", "svg"),
        help="figure format (default: from the file name's extension, else png)",
    )
    g.add_argument(
        "--dpi",
        type=_positive,
        metavar="DPI",
        help="resolution of PNG figures in dots per inch (default 150)",
    )


# ----------------------------------------------------------------------------------------------
# scene, outputs, printing
# ----------------------------------------------------------------------------------------------
class _ScanSource(str):
    """The scan file a spectrum was measured from: its path (a str) with the analysis
    (``.scan``, a :class:`fastline.surfaces.scan.ScanSpectrum`) attached."""

    scan = None


def _scene(args):
    """(psd, E_star, source file or None) from the scene options."""
    import fastline as fl
    from fastline.cli.psd import _scan_checks, _scan_scene
    from fastline.io import read_spectrum

    elastic = [args.E1, args.nu1, args.E2, args.nu2]
    if any(v is not None for v in elastic):
        if args.E_star is not None:
            raise CLIError("give either --E-star or --E1/--nu1/--E2/--nu2, not both")
        if any(v is None for v in elastic):
            raise CLIError("--E1, --nu1, --E2 and --nu2 must be given together")
        E_star = fl.effective_modulus(args.E1, args.nu1, args.E2, args.nu2)
    else:
        E_star = 1.33e9 if args.E_star is None else args.E_star
    if _scan_checks(args):
        psd, source = _scan_scene(args)
        return psd, E_star, source
    given = [flag for key, flag in _SPECTRUM_FLAGS.items() if getattr(args, key) is not None]
    if args.psd is not None:
        if given:
            raise CLIError(
                f"--psd cannot be combined with {', '.join(given)}: the file defines the spectrum"
            )
        return read_spectrum(args.psd), E_star, args.psd
    spec = {
        k: v if getattr(args, k) is None else getattr(args, k) for k, v in SPECTRUM_DEFAULTS.items()
    }
    return fl.SelfAffinePSD(**spec), E_star, None


def _check_outputs(args) -> None:
    """Check every output path before any solve."""
    from fastline.io import check_output_dir, check_output_file

    for name in ("csv", "plot"):
        path = getattr(args, name, None)
        if path is not None:
            check_output_file(path)
    if getattr(args, "plot", None) is not None or getattr(args, "out", None) is not None:
        _require_matplotlib()
    if getattr(args, "out", None) is not None:
        check_output_dir(args.out)


def _require_matplotlib() -> None:
    import importlib.util

    if sys.modules.get("matplotlib", 0) is None or importlib.util.find_spec("matplotlib") is None:
        raise CLIError(
            'plotting needs matplotlib: pip install matplotlib (the "plot" extra of '
            "fastline-contact)"
        )


def _spectrum_line(psd, source, model: str | None = None) -> str:
    """The spectrum the scene uses; for ``--model hertz`` that there is none."""
    from fastline.io import spectrum_summary

    if model == "hertz":
        return "spectrum         none: --model hertz solves the smooth contact (no roughness)"
    s = spectrum_summary(psd)
    what = f"file {source}" if source else "self-affine"
    if isinstance(source, _ScanSource):
        what = f"measured, scan {source}"
    return (
        f"spectrum         {what}: h_rms {s['h_rms']:.4g} m, rms slope h' {s['rms_slope']:.4g}, "
        f"q {s['q0']:.4g}-{s['q1']:.4g} 1/m (longest wavelength {s['longest_wavelength']:.3g} m)"
    )


def _warn(msg: str) -> None:
    print(f"fastline: warning: {msg}", file=sys.stderr)


def _report_warnings(results) -> None:
    """Print what the diagnostics found, once per cause, naming the loads."""
    from fastline.contact.diagnostics import summarise_warnings

    for _cause, msg in summarise_warnings(results):
        _warn(msg)


def _convergence_status(results) -> int:
    bad = [r for r in results if not r.converged]
    if not bad:
        return 0
    loads = ", ".join(f"{r.load:.4g}" for r in bad[:5]) + (" ..." if len(bad) > 5 else "")
    symbol, unit = getattr(bad[0], "LOAD_SYMBOL", "f_N"), getattr(bad[0], "LOAD_UNIT", "N/m")
    print(
        f"fastline: error: {len(bad)} of {len(results)} solves did not converge ({symbol} = "
        f"{loads} {unit}): {bad[0].message}",
        file=sys.stderr,
    )
    return 1


def _progress(total: int, desc: str):
    """A tqdm bar on stderr; silent when stderr is not a terminal (log files, pipes)."""
    from tqdm import tqdm

    return tqdm(total=total, desc=desc, unit="solve", file=sys.stderr, disable=None, leave=False)


def _solve_kwargs(args, theory) -> dict:
    return dict(
        n=args.n,
        gamma=args.gamma,
        theory=theory,
        max_iter=args.max_iter,
        hardness=args.hardness,
        warn=False,
    )


def _theory(psd, E_star, args):
    if getattr(args, "model", "persson") == "hertz":
        return None
    from fastline.theory.persson import PerssonTheory

    return PerssonTheory(psd, E_star, gamma=args.gamma, variant=args.variant)


def _save(fig, path, args) -> None:
    from fastline.reports.plotting import save_figure

    save_figure(fig, path, format=args.format, dpi=args.dpi)


def run_profile(args, solve, result_lines, write_csv, meta) -> int:
    """One scene of ``fastline profile`` for either geometry: solve with ``solve(psd, E*, R,
    load, ...)``, print the spectrum and ``result_lines``, report the warnings, write the CSV
    (``write_csv(path, result, meta(psd, E*, args, source))``) and the figure; the exit status."""
    psd, E, source = _scene(args)
    _check_outputs(args)
    th = _theory(psd, E, args)
    r = solve(psd, E, args.radius, args.load, model=args.model, **_solve_kwargs(args, th))
    print(_spectrum_line(psd, source, args.model))
    print("\n".join(result_lines(r, r.diagnostics)))
    _report_warnings([r])
    if args.csv:
        write_csv(args.csv, r, meta(psd, E, args, source))
    if args.plot:
        from fastline.reports.plotting import plot_profile

        _save(plot_profile(r), args.plot, args)
    return _convergence_status([r])


# ----------------------------------------------------------------------------------------------
# results
# ----------------------------------------------------------------------------------------------
def _result_lines(r, diag) -> list[str]:
    lines = [
        f"model            {r.model} (method {r.method}, n = {r.diagnostics.get('n', '?')})",
        f"load f_N         {r.load:.6g} N/m",
        f"E*, R            {r.E_star:.6g} Pa, {r.radius:.6g} m",
        *_roughness_lines(r, diag),
        f"peak pressure p0 {r.p0:.6g} Pa",
        f"p0 / p0(Hertz)   {r.p0_ratio:.6g}",
        f"std. dev. s      {r.s:.6g} m",
        f"FWHM w           {r.fwhm:.6g} m ({diag['fwhm_cells']:.3g} grid cells)",
        f"w/s              {r.w_over_s:.6g}   (Hertz 3.464, Gaussian 2.355)",
    ]
    lines += _asperity_lines(diag)
    lines.append(f"half-width / R   {diag['half_width_over_radius']:.4g}")
    if diag.get("longest_wavelength") is not None:
        lines.append(
            f"width / (2pi/q0) {diag['contact_width'] / diag['longest_wavelength']:.3g} "
            "(contact width over the longest roughness wavelength; the theory wants >= 1)"
        )
    lines += _law_lines(diag)
    lines += [
        f"converged        {'yes' if r.converged else 'NO'} ({r.iterations} iterations, "
        f"{r.convolutions} FFT convolutions, residual {r.residual:.3g})",
        f"force error      {r.force_error:.3g} (relative); edge pressure {r.edge_pressure:.3g} p0",
    ]
    if r.message:
        lines.append(f"solver message   {r.message}")
    return lines


def _roughness_lines(r, diag, delta: str = "delta") -> list[str]:
    """alpha and the regime it puts the scene in (none for the smooth ``hertz`` model)."""
    if r.model == "hertz":
        return []
    return [
        f"alpha            {r.alpha:.6g}   (h_rms / delta, {delta} = {r.delta:.6g} m)",
        f"regime           {diag['regime']}",
    ]


def _alpha_cell(r, width: int) -> str:
    """alpha in a sweep table's column (``-`` for the smooth ``hertz`` model)."""
    return f"{'-':>{width}}" if r.model == "hertz" else f"{r.alpha:>{width}.4g}"


def _asperity_lines(diag) -> list[str]:
    """The elastic asperity pressure, the real area at the peak and the plasticity verdict."""
    lines = []
    if diag.get("rms_slope") is not None:
        lines += [
            f"h' E*/2          {diag['asperity_pressure']:.6g} Pa (elastic mean asperity pressure)",
            f"real area P(p0)  {diag['real_area_at_peak']:.6g} (fraction at the peak)",
        ]
    if diag.get("plastic_likely") is not None:
        lines.append(f"plastic likely   {'yes' if diag['plastic_likely'] else 'no'}")
    return lines


def _law_lines(diag) -> list[str]:
    """Where the peak sits against the exponential law, and whether that law holds."""
    lines = []
    if "p0_over_beta_E_star" in diag:
        note = ""
        if diag.get("beyond_exponential_law"):
            note = " (peak beyond the exponential law's range: w/s may fall below 2.355)"
        lines.append(f"p0 / (beta E*)   {diag['p0_over_beta_E_star']:.4g}{note}")
    if "exponential_valid" in diag:
        lo, hi = diag["pressure_range_met"]
        vr = diag["exponential_valid_range"]
        lines.append(
            f"exp. law valid   {'yes' if diag['exponential_valid'] else 'NO'} (pressures met "
            f"{lo:.3g}-{hi:.3g} Pa; law within 5% in u up to {vr[1]:.3g} Pa)"
        )
    return lines


def _meta(psd, E_star, args, source):
    from fastline.io import scene_metadata

    meta = scene_metadata(
        psd,
        E_star,
        args.radius,
        model=args.model,
        gamma=args.gamma,
        n=args.n,
        source=source,
        **_variant_meta(args),
    )
    if isinstance(source, _ScanSource):
        meta["spectrum"] = f"measured: scan {source}"
        meta.update(source.scan.metadata())
    return meta


def _variant_meta(args) -> dict:
    """The variant as a metadata entry when it is not the default (older files unchanged)."""
    from fastline.theory.variants import DEFAULT_VARIANT

    v = getattr(args, "variant", DEFAULT_VARIANT)
    return {} if v == DEFAULT_VARIANT else {"variant": v}
