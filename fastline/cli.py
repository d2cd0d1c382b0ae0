"""Command-line interface: ``fastline paper | profile | sweep | leak | batch | psd`` (``python -m
fastline``).

Argument parsing and printing only: the scenes of the paper live in :mod:`fastline.paper`,
files in :mod:`fastline.io`, figures in :mod:`fastline.plotting`, validity checks in
:mod:`fastline.diagnostics`, measured surfaces in :mod:`fastline.scan`.

Exit status: 0 done; 1 a solve did not converge or a scene of a batch failed (results are still
printed and written); 2 bad usage or input (one ``fastline: error: ...`` line on stderr,
nothing solved).

SI units throughout: lengths in m, wavenumbers in 1/m, spectra C(q) in m^4, pressures and
moduli in Pa, loads per unit cylinder length in N/m.
"""

from __future__ import annotations

import argparse
import math
import re
import sys
import time

DESCRIPTION = """\
fastline: nominal contact pressure of a rigid cylinder (radius R) pressed onto a randomly rough
elastic half-space, from Persson's contact theory (Tiwari & Persson, "Cylinder-flat contact
mechanics with surface roughness"). The roughness enters through its power spectrum C(q); the
result is the pressure profile p(x) across the contact line, its peak p0, width (standard
deviation s, full width at half maximum w) and how far it is from the smooth Hertz solution,
measured by alpha = h_rms / delta (delta = 4 f_N / (pi E*), the Hertz penetration).

With --geometry sphere (profile, sweep, paper) the same for a rigid sphere on the flat (a point
contact): p(r), the FWHM w along a diameter, s^2 = int r^2 p dA / (2F), delta = a^2/R; the load
is then the total load F on the sphere in N.

From a measurement: fastline psd SCAN turns a line scan or height map into the spectrum C(q)
(summary, fit, a table for --psd, a figure); --scan SCAN on profile, sweep and leak solves
straight from it.

SI units everywhere: m, 1/m, m^4, Pa, N/m (load per unit cylinder length), N (load on a sphere).
Exit status: 0 done, 1 a solve did not converge (or a scene of a batch failed), 2 bad usage
or input."""

EPILOG = """\
examples:
  fastline profile --h-rms 10e-6 --hurst 0.8 --load 1e4 --csv p.csv --plot p.png
  fastline profile --psd examples/psd_example.txt --E1 2.1e11 --nu1 0.3 --E2 5e6 --nu2 0.49 \\
                   --load 500
  fastline sweep --h-rms 1e-6 --loads-from 1e3 --loads-to 1e6 --loads-num 30 --csv sweep.csv
  fastline profile --geometry sphere --load 500 --E1 2.1e11 --nu1 0.3 --E2 7e10 --nu2 0.33
  fastline leak --h-rms 1e-6 --load 1e4 --pressure-drop 1e4 --viscosity 1e-3 --plot leak.png
  fastline sweep --loads-num 400 --workers 2 --csv sweep.csv
  fastline batch scenes.csv --out results.csv --workers 2
  fastline validate --alpha 1 --all-variants --gw --realizations 8 --plot validate.png
  fastline paper --out figs/ --format pdf
  fastline psd examples/scan_example.txt --dx 1e-6 --units um --out psd.csv --plot psd.png
  fastline profile --scan examples/scan_example.txt --dx 1e-6 --units um --q1 1e9 --extend"""

#: defaults of the self-affine spectrum options (the paper's surface 1)
SPECTRUM_DEFAULTS = {"h_rms": 10e-6, "hurst": 0.8, "q0": 1e3, "qr": 1e4, "q1": 1e9}
_SPECTRUM_FLAGS = {"h_rms": "--h-rms", "hurst": "--hurst", "q0": "--q0", "qr": "--qr", "q1": "--q1"}
# a negative number as an option value ("--load -1e4"): argparse would take it for an option
_NEGATIVE_NUMBER = re.compile(r"^-(\d+\.?\d*|\.\d+)([eE][-+]?\d+)?$|^-(inf|nan)$", re.IGNORECASE)


class CLIError(Exception):
    """A user error: reported as one line on stderr, exit status 2."""


class _Parser(argparse.ArgumentParser):
    """argparse that reports errors as a single line (no usage dump), exit status 2."""

    def error(self, message):  # noqa: D102
        raise CLIError(message)


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
    from fastline.persson import GAMMA_RANGE

    v = _number(text)
    lo, hi = GAMMA_RANGE
    if not lo <= v <= hi:
        raise argparse.ArgumentTypeError(f"must lie in [{lo:g}, {hi:g}], got {text!r}")
    return v


def _join_negative_values(argv: list[str]) -> list[str]:
    """``["--load", "-1e4"]`` -> ``["--load=-1e4"]`` so the option's own check reports it."""
    out: list[str] = []
    for tok in argv:
        prev = out[-1] if out else ""
        if _NEGATIVE_NUMBER.match(tok) and prev.startswith("--") and "=" not in prev:
            out[-1] = f"{prev}={tok}"
        else:
            out.append(tok)
    return out


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
        help="measured isotropic spectrum: two columns q [1/m] and C(q) [m^4], whitespace- or "
        "comma-separated, '#' starts a comment (e.g. examples/psd_example.txt)",
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
    from fastline.variants import DEFAULT_VARIANT, VARIANTS

    group.add_argument(
        "--variant",
        choices=tuple(VARIANTS),
        default=DEFAULT_VARIANT,
        help="variant of the theory's u(p) (docs/theory.md, Variants): the bracket gamma + "
        "3(1-gamma)P^2 of the energy derivation (default), the printed gamma + (1-gamma)P^2, or "
        "Wang & Mueser's correction, which also enters the contact area (not with leak)",
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


def _parallel_options(parser: argparse.ArgumentParser, default: str) -> None:
    g = parser.add_argument_group(
        "parallel execution",
        "Solve on several processes or a dask.distributed cluster (fastline.sweep): scenes of "
        "one model are cut into tasks of consecutive loads; the numbers do not depend on "
        f"where the tasks are solved. Default: {default}.",
    )
    g.add_argument(
        "--workers",
        type=_count,
        metavar="N",
        help="solve on N local processes (1: in this process)",
    )
    g.add_argument(
        "--scheduler",
        metavar="ADDRESS",
        help="solve on the dask.distributed cluster whose scheduler is at ADDRESS, e.g. "
        'tcp://host:8786 (needs dask: pip install "fastline-contact[dask]" for the extra)',
    )
    g.add_argument(
        "--chunksize",
        type=_count,
        metavar="K",
        help="scenes per task at most (default: about 64 tasks, 8 to 256 scenes each)",
    )


def build_parser() -> argparse.ArgumentParser:
    """The ``fastline`` argument parser (commands ``paper``, ``profile``, ``sweep``,
    ``batch``, ``leak``, ``psd``)."""
    from fastline import __version__

    fmt = argparse.RawDescriptionHelpFormatter
    parser = _Parser(prog="fastline", description=DESCRIPTION, epilog=EPILOG, formatter_class=fmt)
    parser.add_argument("--version", action="version", version=f"fastline {__version__}")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND")

    p = sub.add_parser(
        "paper",
        help="reproduce the paper's Figs. 2-5 (a figure + CSV each)",
        formatter_class=fmt,
        description="Reproduce Figs. 2-5 of Tiwari & Persson: C(q) of surfaces 1-3 (fig2_psd), "
        "p(x) rough vs Hertz at f_N = 1e4 N/m (fig3_profile), w/s vs alpha (fig4_ws) and "
        "p0(rough)/p0(Hertz) vs alpha with the Gaussian asymptote, eq. 14 (fig5_p0ratio). "
        "E* = 1.33 GPa, R = 1 cm, q0 = 1e3 1/m, qr = 1e4 1/m. With --geometry sphere: their "
        "sphere versions (fig3_profile_sphere, fig4_ws_sphere, fig5_p0ratio_sphere; R = 1 cm "
        "the sphere's radius), loads F [N] chosen per surface so that alpha = h_rms / delta "
        "(delta = a^2/R) is log-spaced over 1e-3..1e3.",
    )
    p.add_argument("--out", required=True, metavar="DIR", help="output directory (created)")
    p.add_argument(
        "--loads",
        type=_count,
        default=40,
        metavar="N",
        help="loads per surface, log-spaced from 1e3 to 1.5e6 N/m (default 40); with --geometry "
        "sphere: loads F [N] log-spaced so that alpha runs over 1e-3..1e3",
    )
    p.add_argument(
        "--q1",
        type=_positive,
        default=1e9,
        metavar="1/M",
        help="large-wavenumber cut-off q1 [1/m] (the paper does not state it; default 1e9)",
    )
    p.add_argument(
        "--geometry",
        choices=GEOMETRIES,
        default="cylinder",
        help="cylinder on a flat (the paper's figures, default) or sphere on a flat",
    )
    _numerics_options(p, model=False, geometry=True)
    _figure_options(p)

    p = sub.add_parser(
        "profile",
        help="solve one scene: p(x), p0, widths, regime, diagnostics",
        formatter_class=fmt,
        description="Solve one cylinder-on-flat scene (or, with --geometry sphere, "
        "sphere-on-flat) and print the spectrum, the peak pressure, widths, alpha, regime, "
        "validity diagnostics and solver convergence.",
    )
    _spectrum_options(p)
    _scan_options(p)
    _material_options(p, load=True, geometry=True)
    _numerics_options(p, geometry=True)
    p.add_argument(
        "--csv",
        metavar="FILE",
        help="write x [m], p [Pa], u [m] columns to FILE (a sphere: r [m] from the axis)",
    )
    p.add_argument("--plot", metavar="FILE", help="write a figure of p(x) with Hertz to FILE")
    _figure_options(p)

    p = sub.add_parser(
        "sweep",
        help="solve a log-spaced series of loads",
        formatter_class=fmt,
        description="Solve the scene for log-spaced loads and tabulate alpha, p0, p0 ratio, "
        "s, w and w/s.",
    )
    _spectrum_options(p)
    _scan_options(p)
    _material_options(p, load=False, geometry=True)
    p.add_argument(
        "--loads-from",
        type=_positive,
        metavar="LOAD",
        help="smallest load: per unit length [N/m] (default 1e3); with --geometry sphere the "
        "total load F [N] (default 0.1)",
    )
    p.add_argument(
        "--loads-to",
        type=_positive,
        metavar="LOAD",
        help="largest load: per unit length [N/m] (default 1.5e6); with --geometry sphere the "
        "total load F [N] (default 1e3)",
    )
    p.add_argument(
        "--loads-num", type=_count, default=20, metavar="N", help="number of loads (default 20)"
    )
    _numerics_options(p, geometry=True)
    p.add_argument(
        "--csv",
        metavar="FILE",
        help="write the table (load [N/m] or, for a sphere, [N], alpha, p0 [Pa], p0_ratio, "
        "s [m], w [m], w_over_s, converged) to FILE",
    )
    p.add_argument("--plot", metavar="FILE", help="write a figure of w/s and p0 ratio vs alpha")
    _figure_options(p)
    _parallel_options(
        p,
        "one continuation sweep in this process (its numbers differ from the tasks' within "
        "the solver tolerance)",
    )

    p = sub.add_parser(
        "batch",
        help="solve a table of scenes from a CSV file (in parallel)",
        formatter_class=fmt,
        description="Solve every scene (row) of a CSV file and write one row of results per "
        "scene. Columns (header row; units in the name optional, e.g. E_star or E_star_Pa): "
        "the spectrum as h_rms, hurst, q0, qr, q1 or as psd (a spectrum file, relative to the "
        "CSV file); E_star [Pa], radius [m], load [N/m]; optional label, geometry (cylinder), "
        "model, method, n, gamma, tol, max_iter, hardness [Pa]; an empty cell takes the "
        "default. A scene that fails (a value out of range, an unreadable spectrum file) is "
        "reported in its row's error column; the others are solved.",
    )
    p.add_argument("scenes", metavar="SCENES.csv", help="the scene table")
    p.add_argument("--out", required=True, metavar="FILE", help="write the results (CSV) to FILE")
    _parallel_options(p, "a local process per CPU")

    _leak_parser(sub, fmt)
    _psd_parser(sub, fmt)
    from fastline.cli_validate import validate_parser

    validate_parser(sub, fmt)
    return parser


def _leak_parser(sub, fmt) -> None:
    """The ``leak`` command: the options of ``profile``, the fluid and seal, ``--sweep``."""
    from fastline.leakage import THRESHOLD_PERSSON

    p = sub.add_parser(
        "leak",
        help="leak rate of a seal (Persson's critical-junction theory); --sweep: against load",
        formatter_class=fmt,
        description="Solve one scene and compute the leak rate of the seal it forms: the volume "
        "flow Q [m^3/s] of a fluid across the contact line (along x) for a seal of length "
        "--length, from Persson's critical-junction theory with the strips of the contact in "
        "series (docs/leakage.md). Prints Q, the conductance, whether the contact is sealed and "
        "where along x the flow resistance sits. With --sweep: Q against a log-spaced series of "
        "loads (--loads-from/--loads-to/--loads-num instead of --load), how much squeeze stops "
        "the leak.",
    )
    _spectrum_options(p)
    _scan_options(p)
    _material_options(p, load=True)
    p.set_defaults(load=None)  # 1e4 for one scene; not combined with --sweep
    g = p.add_argument_group("fluid and seal")
    g.add_argument(
        "--pressure-drop",
        type=_positive,
        required=True,
        metavar="PA",
        help="fluid pressure difference across the seal dP [Pa] (required)",
    )
    g.add_argument(
        "--viscosity",
        type=_positive,
        required=True,
        metavar="PA_S",
        help="dynamic viscosity of the fluid eta [Pa s] (required; water at 20 C: 1e-3)",
    )
    g.add_argument(
        "--length",
        type=_positive,
        default=1.0,
        metavar="M",
        help="seal length L_y across the flow [m] (an O-ring's circumference; default 1)",
    )
    g.add_argument(
        "--threshold",
        type=_fraction,
        default=THRESHOLD_PERSSON,
        metavar="A",
        help="percolation threshold of the apparent contact area [-], in (0, 1) (default "
        f"{THRESHOLD_PERSSON:g}, Persson; 0.415 numerical studies; 0.5 Bruggeman)",
    )
    g.add_argument(
        "--mean-free-path",
        type=_positive,
        metavar="M",
        help="mean free path of a gas [m] (about 70e-9 for air at 1 bar): warns when the flow "
        "is not viscous; omit for liquids",
    )
    g = p.add_argument_group("load sweep")
    g.add_argument(
        "--sweep",
        action="store_true",
        help="leak rate against log-spaced loads instead of one --load",
    )
    g.add_argument(
        "--loads-from",
        type=_positive,
        metavar="N/M",
        help="smallest load per unit length [N/m] (with --sweep; default 1e3)",
    )
    g.add_argument(
        "--loads-to",
        type=_positive,
        metavar="N/M",
        help="largest load per unit length [N/m] (with --sweep; default 1.5e6)",
    )
    g.add_argument(
        "--loads-num",
        type=_count,
        metavar="N",
        help="number of loads (with --sweep; default 20)",
    )
    _numerics_options(p)
    p.add_argument(
        "--csv",
        metavar="FILE",
        help="write x [m], p [Pa], u_c [m], sigma [m^3/(Pa s)], resistance share and sealed "
        "columns (with --sweep: load [N/m], alpha, p0 [Pa], Q [m^3/s], conductance "
        "[m^2/(Pa s)], sealed, share in FWHM, 90%% width [m], min gap [m], converged) to FILE",
    )
    p.add_argument(
        "--plot",
        metavar="FILE",
        help="write a figure of p(x) and u_c(x) (with --sweep: Q against load, log-log)",
    )
    _figure_options(p)


# ----------------------------------------------------------------------------------------------
# scene, outputs, printing
# ----------------------------------------------------------------------------------------------
def _scene(args):
    """(psd, E_star, source file or None) from the scene options."""
    import fastline as fl
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


def _spectrum_line(psd, source) -> str:
    from fastline.io import spectrum_summary

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
    from fastline.diagnostics import summarise_warnings

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
    from fastline.persson import PerssonTheory

    return PerssonTheory(psd, E_star, gamma=args.gamma, variant=args.variant)


def _save(fig, path, args) -> None:
    from fastline.plotting import save_figure

    save_figure(fig, path, format=args.format, dpi=args.dpi)


# ----------------------------------------------------------------------------------------------
# commands
# ----------------------------------------------------------------------------------------------
def _result_lines(r, diag) -> list[str]:
    lines = [
        f"model            {r.model} (method {r.method}, n = {r.diagnostics.get('n', '?')})",
        f"load f_N         {r.load:.6g} N/m",
        f"E*, R            {r.E_star:.6g} Pa, {r.radius:.6g} m",
        f"alpha            {r.alpha:.6g}   (h_rms / delta, delta = {r.delta:.6g} m)",
        f"regime           {diag['regime']}",
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
    from fastline.variants import DEFAULT_VARIANT

    v = getattr(args, "variant", DEFAULT_VARIANT)
    return {} if v == DEFAULT_VARIANT else {"variant": v}


def cmd_profile(args) -> int:
    from fastline.line_contact import solve_line_contact

    if _geometry_defaults(args) == "sphere":
        return _sphere_profile(args)
    psd, E, source = _scene(args)
    _check_outputs(args)
    th = _theory(psd, E, args)
    r = solve_line_contact(
        psd, E, args.radius, args.load, model=args.model, **_solve_kwargs(args, th)
    )
    print(_spectrum_line(psd, source))
    print("\n".join(_result_lines(r, r.diagnostics)))
    _report_warnings([r])
    if args.csv:
        from fastline.io import write_profile_csv

        write_profile_csv(args.csv, r, _meta(psd, E, args, source))
    if args.plot:
        from fastline.plotting import plot_profile

        _save(plot_profile(r), args.plot, args)
    return _convergence_status([r])


def _executor(args):
    """(executor for fastline.sweep, a function that releases it) from --scheduler."""
    if args.workers is not None and args.scheduler is not None:
        raise CLIError("give either --workers or --scheduler, not both")
    if args.scheduler is None:
        return None, lambda: None
    try:
        from distributed import Client
    except ImportError:
        raise CLIError(
            '--scheduler needs dask.distributed: pip install "fastline-contact[dask]" (the '
            "dask extra)"
        ) from None
    try:
        client = Client(args.scheduler, timeout=10)
    except (OSError, ValueError, TypeError) as e:
        raise CLIError(f"cannot connect to the dask scheduler at {args.scheduler}: {e}") from None
    return client, client.close


def _run_table(scenes, args):
    """fastline.sweep on the executor the options name; bad tables are usage errors."""
    from fastline.batch import sweep

    executor, release = _executor(args)
    try:
        return sweep(
            scenes,
            executor,
            workers=args.workers if executor is None else None,
            chunksize=args.chunksize,
            progress=None,
            warn=False,
        )
    except TypeError as e:
        raise CLIError(str(e)) from None
    finally:
        release()


def _table_status(table) -> int:
    """Print the failed and non-converged scenes of a sweep table (as errors); 0 or 1."""
    status = 0
    for cause, msg in table.warnings:
        if cause in ("failed", "not_converged"):
            print(f"fastline: error: {msg}", file=sys.stderr)
            status = 1
        else:
            _warn(msg)
    return status


def _sweep_in_parallel(psd, E, args, loads):
    """The loads of the sweep command as a scene table on --workers/--scheduler: rows with
    the attributes of a result (load, alpha, p0, ...) and the table."""
    import numpy as np

    k = len(loads)
    scenes = {
        "psd": [psd] * k,
        "E_star": [E] * k,
        "radius": [args.radius] * k,
        "load": [float(f) for f in loads],
        "model": [args.model] * k,
        "n": [args.n] * k,
        "gamma": [args.gamma] * k,
        "max_iter": [args.max_iter or 0] * k,
        "hardness": [math.nan if args.hardness is None else args.hardness] * k,
    }
    table = _run_table(scenes, args)
    return table.table.view(np.recarray), table


def cmd_sweep(args) -> int:
    import numpy as np

    from fastline.line_contact import LineContact

    if _geometry_defaults(args) == "sphere":
        return _sphere_sweep(args)
    psd, E, source = _scene(args)
    if args.loads_to < args.loads_from:
        raise CLIError("--loads-to must be >= --loads-from")
    _check_outputs(args)
    loads = np.geomspace(args.loads_from, args.loads_to, args.loads_num)
    th = _theory(psd, E, args)
    table = None
    if args.workers is None and args.scheduler is None:
        model = LineContact(psd, E, args.radius, model=args.model, **_solve_kwargs(args, th))
        with _progress(len(loads), "sweep") as bar:
            results = model.sweep(loads, progress=bar.update)
    else:
        if args.variant != "yang-persson-energy":
            raise CLIError("--variant is not available with --workers/--scheduler yet")
        results, table = _sweep_in_parallel(psd, E, args, loads)
    print(_spectrum_line(psd, source))
    print(
        f"{'load [N/m]':>12}{'alpha':>12}{'p0 [Pa]':>13}{'p0 ratio':>10}{'s [m]':>12}"
        f"{'w [m]':>12}{'w/s':>8}{'conv':>6}"
    )
    for r in results:
        print(
            f"{r.load:>12.4g}{r.alpha:>12.4g}{r.p0:>13.5g}{r.p0_ratio:>10.5f}{r.s:>12.4g}"
            f"{r.fwhm:>12.4g}{r.w_over_s:>8.4f}{'yes' if r.converged else 'NO':>6}"
        )
    if table is None:
        _report_warnings(results)
    if args.csv:
        from fastline.io import write_sweep_csv

        write_sweep_csv(args.csv, results, _meta(psd, E, args, source))
    if args.plot:
        from fastline.plotting import plot_sweep

        gu = th.exponential_fit().gamma_u if th is not None else None
        _save(plot_sweep(results, gamma_u=gu), args.plot, args)
    return _convergence_status(results) if table is None else _table_status(table)


def cmd_batch(args) -> int:
    from fastline.batch import read_scenes
    from fastline.io import check_output_file

    check_output_file(args.out)
    table = _run_table(read_scenes(args.scenes), args)
    table.to_csv(args.out)
    st = table.stats
    failed = int(table.failed.sum())
    ok = int(table.ok.sum())
    print(
        f"fastline batch: {st.scenes} scenes from {args.scenes}: {ok} converged, "
        f"{st.scenes - ok - failed} not converged, {failed} failed; {st.wall_seconds:.2f} s "
        f"({st.scenes_per_second:.0f} scenes/s, {st.tasks} task(s)) on {st.executor}"
    )
    status = _table_status(table)
    print(f"wrote {args.out}")
    return status


def _paper_files(data, args) -> list[str]:
    """Write the four figures and their CSVs; returns the file names."""
    import os

    import numpy as np

    from fastline import paper, plotting
    from fastline.io import scene_metadata, sweep_rows, write_csv
    from fastline.limits import p0_ratio_gaussian

    out, ext = args.out, args.format or "png"
    surfs = data.surfaces
    meta = scene_metadata(
        None,
        paper.E_STAR,
        paper.RADIUS,
        model="persson",
        gamma=args.gamma,
        n=args.n,
        **_variant_meta(args),
    )
    meta.pop("spectrum")
    meta.update(q0_1_per_m=paper.Q0, qr_1_per_m=paper.QR, q1_1_per_m=args.q1)
    for s in surfs:
        meta[s.label.replace(" ", "_")] = f"h_rms {s.h_rms:g} m, H {s.hurst:g}"
    written = []

    def path(name, suffix):
        written.append(f"{name}.{suffix}")
        return os.path.join(out, f"{name}.{suffix}")

    q = np.geomspace(paper.Q0, args.q1, 400)
    cols = [s.psd(q) for s in surfs]
    write_csv(
        path("fig2_psd", "csv"),
        ["q_1_per_m", "C1_m4", "C2_m4", "C3_m4"],
        zip(q, *cols, strict=True),
        meta,
        title="Fig. 2: C(q) of surfaces 1-3",
    )
    fig = plotting.plot_psd({_surface_label(s): s.psd for s in surfs})
    _save(fig, path("fig2_psd", ext), args)

    r3 = data.fig3
    from fastline.limits import hertz_line_contact

    hz = hertz_line_contact(paper.E_STAR, paper.RADIUS, paper.FIG3_LOAD)
    write_csv(
        path("fig3_profile", "csv"),
        ["x_m", "p_rough_Pa", "p_hertz_Pa"],
        zip(r3.x, r3.pressure, hz.pressure(r3.x), strict=True),
        {**meta, "load_N_per_m": paper.FIG3_LOAD, "alpha": r3.alpha},
        title="Fig. 3: p(x) of surface 1, rough and smooth (Hertz)",
    )
    _save(plotting.plot_profile(r3, label="rough (surface 1)"), path("fig3_profile", ext), args)

    header = [
        "surface",
        "h_rms_m",
        "hurst",
        "load_N_per_m",
        "alpha",
        "p0_Pa",
        "p0_ratio",
        "s_m",
        "w_m",
        "w_over_s",
        "converged",
        "gamma_u",
        "p0_ratio_eq14",
    ]
    rows = []
    for i, s in enumerate(surfs):
        for row in sweep_rows(s.results):
            eq14 = float(p0_ratio_gaussian(row[1], s.gamma_u))
            rows.append((str(i + 1), s.h_rms, s.hurst, *row[:7], row[7], s.gamma_u, eq14))
    title = "Figs. 4-5: load sweeps 1e3..1.5e6 N/m (log-spaced)"
    write_csv(path("fig4_ws", "csv"), header, rows, meta, title=title)
    write_csv(path("fig5_p0ratio", "csv"), header, rows, meta, title=title)
    series = {s.label: s.results for s in surfs}
    _save(plotting.plot_w_over_s(series), path("fig4_ws", ext), args)
    fig = plotting.plot_p0_ratio(series, gamma_u={s.label: s.gamma_u for s in surfs})
    _save(fig, path("fig5_p0ratio", ext), args)
    return written


def _surface_label(s) -> str:
    return f"{s.label}: $h_\\mathrm{{rms}}$ = {s.h_rms * 1e6:g} µm, $H$ = {s.hurst:g}"


def cmd_paper(args) -> int:
    from fastline import paper
    from fastline.io import spectrum_summary

    if _geometry_defaults(args) == "sphere":
        return _sphere_paper(args)
    _check_outputs(args)
    t0 = time.perf_counter()
    with _progress(len(paper.SURFACES) * args.loads, "paper") as bar:
        data = paper.paper_data(
            q1=args.q1,
            loads=args.loads,
            n=args.n,
            gamma=args.gamma,
            max_iter=args.max_iter,
            hardness=args.hardness,
            progress=lambda _label: bar.update(),
            variant=args.variant,
        )
    elapsed = time.perf_counter() - t0
    t1 = time.perf_counter()
    written = _paper_files(data, args)
    t_files = time.perf_counter() - t1
    print(
        f"fastline paper: E* = {paper.E_STAR:g} Pa, R = {paper.RADIUS:g} m, q0 = {paper.Q0:g} "
        f"1/m, qr = {paper.QR:g} 1/m, q1 = {args.q1:g} 1/m, gamma = {args.gamma:g}, "
        f"n = {args.n}; {args.loads} loads per surface; solved in {elapsed:.2f} s, files in "
        f"{t_files:.2f} s"
    )
    print(
        f"{'surface':<10}{'h_rms [m]':>10}{'H':>5}{'rms slope':>10}{'gamma_u':>9}"
        f"{'alpha range':>20}{'w/s range':>17}{'p0 ratio range':>17}{'not conv.':>10}"
    )
    for s in data.surfaces:
        rs = s.results
        a, ws, pr = ([getattr(r, k) for r in rs] for k in ("alpha", "w_over_s", "p0_ratio"))
        bad = sum(not r.converged for r in rs)
        slope = spectrum_summary(s.psd)["rms_slope"]
        print(
            f"{s.label:<10}{s.h_rms:>10.3g}{s.hurst:>5.2g}{slope:>10.4g}{s.gamma_u:>9.4f}"
            f"{min(a):>10.3g}-{max(a):<9.3g}{min(ws):>8.4f}-{max(ws):<8.4f}"
            f"{min(pr):>8.4f}-{max(pr):<8.4f}{bad:>10d}"
        )
    print(
        f"spectra          q {paper.Q0:g}-{args.q1:g} 1/m (longest wavelength "
        f"{spectrum_summary(data.surfaces[0].psd)['longest_wavelength']:.3g} m)"
    )
    _report_warnings(data.results)
    print(f"wrote {', '.join(written)} to {args.out}")
    return _convergence_status(data.results)


# ----------------------------------------------------------------------------------------------
# leak
# ----------------------------------------------------------------------------------------------
#: defaults of the load-sweep options of ``leak --sweep`` (those of ``sweep``)
LEAK_SWEEP_DEFAULTS = {"loads_from": 1e3, "loads_to": 1.5e6, "loads_num": 20}
_DEFAULT_LOAD = 1e4


def _leak_checks(args) -> None:
    """Reject what cannot give a leak rate, before any work; fill in the load defaults."""
    from fastline.variants import get_variant

    if get_variant(args.variant).area_correction:
        raise CLIError(
            f"--variant {args.variant} corrects the contact area, which the critical-junction "
            "leak theory does not: use yang-persson-energy or yang-persson-printed"
        )
    if args.model == "hertz":
        raise CLIError(
            "--model hertz is for smooth surfaces: a leak rate needs a roughness spectrum "
            "(use --model persson or exponential)"
        )
    given = [f"--{k.replace('_', '-')}" for k in LEAK_SWEEP_DEFAULTS if getattr(args, k)]
    if not args.sweep:
        if given:
            raise CLIError(f"{', '.join(given)} need --sweep")
        args.load = _DEFAULT_LOAD if args.load is None else args.load
        return
    if args.load is not None:
        raise CLIError("--load is for one scene: with --sweep give --loads-from/--loads-to")
    for key, value in LEAK_SWEEP_DEFAULTS.items():
        if getattr(args, key) is None:
            setattr(args, key, value)
    if args.loads_to < args.loads_from:
        raise CLIError("--loads-to must be >= --loads-from")


def _leak_of(r, th, args):
    from fastline.leakage import leak_rate

    return leak_rate(
        r,
        args.pressure_drop,
        args.viscosity,
        args.length,
        theory=th,
        threshold=args.threshold,
        mean_free_path=args.mean_free_path,
        warn=False,
    )


def _leak_meta(psd, E, args, source) -> dict:
    meta = _meta(psd, E, args, source)
    if args.mean_free_path is not None:
        meta["mean_free_path_m"] = args.mean_free_path
    return meta


def _fluid_line(args) -> str:
    return (
        f"fluid, seal      pressure drop {args.pressure_drop:.6g} Pa, viscosity "
        f"{args.viscosity:.6g} Pa s, seal length {args.length:.6g} m, threshold "
        f"{args.threshold:g} (critical-junction theory)"
    )


def _leak_lines(leak) -> list[str]:
    d, t = leak.diagnostics, leak.threshold
    if leak.sealed:
        lines = [
            "leak rate Q      0 m^3/s (sealed)",
            f"sealed           yes: {d['n_sealed']} of {d['n_strips']} strips have a real contact "
            f"area P(q1, p) >= {t:g} (no channel percolates there)",
            f"resistance       infinite in the sealed strips, {leak.resistance_width:.4g} m of "
            "the contact",
        ]
    else:
        lines = [
            f"leak rate Q      {leak.Q:.6g} m^3/s",
            f"conductance      {leak.conductance:.6g} m^2/(Pa s) per unit seal length "
            "(Q = conductance * length * pressure drop)",
            f"sealed           no (real contact area P(q1, p) < {t:g} in every strip)",
            f"resistance       {leak.share_in_fwhm:.1%} of it inside the FWHM of p; 90% of it "
            f"within {leak.resistance_width:.4g} m",
            f"critical gap     {d['min_gap']:.6g} m (u_c at the strip of highest resistance)",
            f"junctions across {d['junctions_across']:.3g} (roll-off wavelengths 2pi/qr = "
            f"{d['rolloff_wavelength']:.3g} m across the 90% width; the theory wants >= 5)",
        ]
    lines.append(
        f"dP / p0          {d['fluid_pressure_ratio']:.3g} (pressure drop over the peak contact "
        "pressure; the theory wants it small)"
    )
    if d["knudsen"] is not None:
        lines.append(
            f"Knudsen number   {d['knudsen']:.3g} (mean free path / u_c; viscous flow below 0.1)"
        )
    return lines


def _loads_span(loads: list[float], total: int) -> str:
    if total == 1:
        return f"f_N = {loads[0]:.4g} N/m"
    head = f"{len(loads)} of {total} loads: f_N"
    if len(loads) <= 4:
        return f"{head} = {', '.join(f'{f:.4g}' for f in loads)} N/m"
    return f"{head} from {min(loads):.4g} to {max(loads):.4g} N/m"


def _report_leak_warnings(results, leaks) -> None:
    """The solves' diagnostics, then each leakage warning once, naming the loads."""
    _report_warnings(results)
    found: dict[str, list[float]] = {}
    for r, k in zip(results, leaks, strict=True):
        for msg in k.diagnostics["warnings"]:
            found.setdefault(msg, []).append(r.load)
    for msg, loads in found.items():
        _warn(f"{msg} [{_loads_span(loads, len(leaks))}]")


def _sealing_line(results, leaks) -> str:
    sealed = [r.load for r, k in zip(results, leaks, strict=True) if k.sealed]
    open_ = [r for r, k in zip(results, leaks, strict=True) if not k.sealed]
    if not sealed:
        p0 = max(r.p0 for r in results)
        return f"sealing          no load of the sweep seals (largest p0 {p0:.4g} Pa)"
    if not open_:
        return f"sealing          every load of the sweep seals (from f_N = {min(sealed):.4g} N/m)"
    below = [r.load for r in open_ if r.load < min(sealed)]
    last = f" (the largest load that leaks below it: {max(below):.4g} N/m)" if below else ""
    return f"sealing          sealed from f_N = {min(sealed):.4g} N/m on{last}"


def _leak_one(args, psd, E, source, th) -> int:
    from fastline.line_contact import solve_line_contact

    r = solve_line_contact(
        psd, E, args.radius, args.load, model=args.model, **_solve_kwargs(args, th)
    )
    leak = _leak_of(r, th, args)
    print(_spectrum_line(psd, source))
    print("\n".join(_result_lines(r, r.diagnostics)))
    print(_fluid_line(args))
    print("\n".join(_leak_lines(leak)))
    _report_leak_warnings([r], [leak])
    if args.csv:
        from fastline.io import write_leak_csv

        write_leak_csv(args.csv, leak, _leak_meta(psd, E, args, source), result=r)
    if args.plot:
        from fastline.plotting import plot_leak

        _save(plot_leak(leak), args.plot, args)
    return _convergence_status([r])


def _leak_sweep(args, psd, E, source, th) -> int:
    import numpy as np

    from fastline.line_contact import LineContact

    loads = np.geomspace(args.loads_from, args.loads_to, args.loads_num)
    model = LineContact(psd, E, args.radius, model=args.model, **_solve_kwargs(args, th))
    with _progress(len(loads), "leak sweep") as bar:
        results = model.sweep(loads, progress=bar.update)
    leaks = [_leak_of(r, th, args) for r in results]
    print(_spectrum_line(psd, source))
    print(_fluid_line(args))
    print(
        f"{'load [N/m]':>12}{'alpha':>11}{'p0 [Pa]':>12}{'Q [m^3/s]':>13}{'sealed':>8}"
        f"{'in FWHM':>9}{'90% width [m]':>15}{'conv':>6}"
    )
    for r, k in zip(results, leaks, strict=True):
        # where the resistance sits is meaningless once it is infinite
        where = (
            f"{'-':>9}{'-':>15}"
            if k.sealed
            else f"{k.share_in_fwhm:>9.3f}{k.resistance_width:>15.4g}"
        )
        print(
            f"{r.load:>12.4g}{r.alpha:>11.4g}{r.p0:>12.5g}{k.Q:>13.4e}"
            f"{'yes' if k.sealed else 'no':>8}{where}{'yes' if r.converged else 'NO':>6}"
        )
    print(_sealing_line(results, leaks))
    _report_leak_warnings(results, leaks)
    if args.csv:
        from fastline.io import write_leak_sweep_csv

        write_leak_sweep_csv(args.csv, results, leaks, _leak_meta(psd, E, args, source))
    if args.plot:
        from fastline.plotting import plot_leak_sweep

        _save(plot_leak_sweep(loads, leaks), args.plot, args)
    return _convergence_status(results)


def cmd_leak(args) -> int:
    psd, E, source = _scene(args)
    _leak_checks(args)
    _check_outputs(args)
    th = _theory(psd, E, args)
    if args.sweep:
        return _leak_sweep(args, psd, E, source, th)
    return _leak_one(args, psd, E, source, th)


# ----------------------------------------------------------------------------------------------
# sphere on a flat (--geometry sphere)
# ----------------------------------------------------------------------------------------------
GEOMETRIES = ("cylinder", "sphere")
#: defaults that depend on the geometry (loads in N/m for a cylinder, N for a sphere)
GEOMETRY_DEFAULTS = {
    "cylinder": {"load": 1e4, "loads_from": 1e3, "loads_to": 1.5e6, "n": 1024},
    "sphere": {"load": 10.0, "loads_from": 0.1, "loads_to": 1e3, "n": 512},
}


def _geometry_options(m, load: bool) -> None:
    """--geometry, --radius and (``load``) --load, whose unit follows the geometry."""
    m.add_argument(
        "--geometry",
        choices=GEOMETRIES,
        default="cylinder",
        help="rigid cylinder on a flat (line contact, default) or sphere on a flat (point "
        "contact); the load is per unit length [N/m] for a cylinder, the total load [N] for a "
        "sphere",
    )
    m.add_argument(
        "--radius",
        type=_positive,
        default=0.01,
        metavar="M",
        help="cylinder radius R [m], or the sphere's with --geometry sphere (default 0.01)",
    )
    if load:
        m.add_argument(
            "--load",
            type=_positive,
            metavar="LOAD",
            help="normal load per unit cylinder length f_N [N/m] (default 1e4); with "
            "--geometry sphere the total load F on the sphere [N] (default 10)",
        )


def _geometry_defaults(args) -> str:
    """Fill the options whose default depends on the geometry; returns the geometry."""
    geometry = getattr(args, "geometry", "cylinder")
    for key, value in GEOMETRY_DEFAULTS[geometry].items():
        if hasattr(args, key) and getattr(args, key) is None:
            setattr(args, key, value)
    return geometry


def _sphere_result_lines(r, diag) -> list[str]:
    a = r.hertz_radius
    r99, r1 = r.load_radius(0.99), r.pressure_radius(0.01)
    lines = [
        f"model            {r.model} (method {r.method}, n = {r.diagnostics.get('n', '?')} "
        "cells from the axis)",
        "geometry         sphere on a flat (point contact)",
        f"load F           {r.load:.6g} N (total load on the sphere)",
        f"E*, R            {r.E_star:.6g} Pa, {r.radius:.6g} m (sphere radius)",
        f"alpha            {r.alpha:.6g}   (h_rms / delta, delta = a^2/R = {r.delta:.6g} m)",
        f"Hertz radius a   {a:.6g} m (Hertz contact diameter {2 * a:.6g} m)",
        f"regime           {diag['regime']}",
        f"peak pressure p0 {r.p0:.6g} Pa",
        f"p0 / p0(Hertz)   {r.p0_ratio:.6g}",
        f"std. dev. s      {r.s:.6g} m (s^2 = int r^2 p dA / 2F, along a diameter)",
        f"FWHM w           {r.fwhm:.6g} m along a diameter ({diag['fwhm_cells']:.3g} grid cells)",
        f"w/s              {r.w_over_s:.6g}   (Hertz sphere 3.873, Gaussian 2.355)",
        f"99% of F within  r = {r99:.6g} m (diameter {2 * r99:.6g} m)",
        f"p = 1% p0 at     r = {r1:.6g} m (diameter {2 * r1:.6g} m)",
    ]
    lines += _asperity_lines(diag)
    lines.append(f"contact radius/R {diag['half_width_over_radius']:.4g}")
    if diag.get("longest_wavelength") is not None:
        lines.append(
            f"width / (2pi/q0) {diag['contact_width'] / diag['longest_wavelength']:.3g} "
            "(contact diameter over the longest roughness wavelength; the theory wants >= 1)"
        )
    lines += _law_lines(diag)
    d = r.diagnostics
    lines += [
        f"converged        {'yes' if r.converged else 'NO'} ({r.iterations} iterations, "
        f"{r.convolutions} operator applications: {d['k_applications']} products with K, "
        f"{d['preconditioner_solves']} preconditioner solves; residual {r.residual:.3g})",
        f"force error      {r.force_error:.3g} (relative); edge pressure {r.edge_pressure:.3g} p0",
    ]
    if r.message:
        lines.append(f"solver message   {r.message}")
    return lines


def _sphere_meta(psd, E_star, args, source):
    return {**_meta(psd, E_star, args, source), "geometry": "sphere"}


def _sphere_profile(args) -> int:
    from fastline.point_contact import solve_point_contact

    psd, E, source = _scene(args)
    _check_outputs(args)
    th = _theory(psd, E, args)
    r = solve_point_contact(
        psd, E, args.radius, args.load, model=args.model, **_solve_kwargs(args, th)
    )
    print(_spectrum_line(psd, source))
    print("\n".join(_sphere_result_lines(r, r.diagnostics)))
    _report_warnings([r])
    if args.csv:
        from fastline.io import write_point_profile_csv

        write_point_profile_csv(args.csv, r, _sphere_meta(psd, E, args, source))
    if args.plot:
        from fastline.plotting import plot_profile

        _save(plot_profile(r), args.plot, args)
    return _convergence_status([r])


def _sphere_sweep(args) -> int:
    import numpy as np

    from fastline.point_contact import PointContact

    psd, E, source = _scene(args)
    if args.loads_to < args.loads_from:
        raise CLIError("--loads-to must be >= --loads-from")
    _check_outputs(args)
    loads = np.geomspace(args.loads_from, args.loads_to, args.loads_num)
    th = _theory(psd, E, args)
    model = PointContact(psd, E, args.radius, model=args.model, **_solve_kwargs(args, th))
    with _progress(len(loads), "sweep") as bar:
        results = model.sweep(loads, progress=bar.update)
    print(_spectrum_line(psd, source))
    print(f"geometry         sphere on a flat, R = {args.radius:.6g} m; loads F in N")
    print(
        f"{'load F [N]':>12}{'alpha':>12}{'p0 [Pa]':>13}{'p0 ratio':>10}{'s [m]':>12}"
        f"{'w [m]':>12}{'w/s':>8}{'conv':>6}"
    )
    for r in results:
        print(
            f"{r.load:>12.4g}{r.alpha:>12.4g}{r.p0:>13.5g}{r.p0_ratio:>10.5f}{r.s:>12.4g}"
            f"{r.fwhm:>12.4g}{r.w_over_s:>8.4f}{'yes' if r.converged else 'NO':>6}"
        )
    _report_warnings(results)
    if args.csv:
        from fastline.io import write_point_sweep_csv

        write_point_sweep_csv(args.csv, results, _sphere_meta(psd, E, args, source))
    if args.plot:
        from fastline.plotting import plot_sweep

        gu = th.exponential_fit().gamma_u if th is not None else None
        _save(plot_sweep(results, gamma_u=gu), args.plot, args)
    return _convergence_status(results)


def _sphere_paper_files(data, args) -> list[str]:
    """The sphere versions of Figs. 3-5 and their CSVs; returns the file names."""
    import os

    from fastline import paper, plotting
    from fastline.io import scene_metadata, sweep_rows, write_csv
    from fastline.limits import hertz_point_contact, p0_ratio_gaussian_sphere

    out, ext = args.out, args.format or "png"
    meta = scene_metadata(
        None,
        paper.E_STAR,
        paper.RADIUS,
        model="persson",
        gamma=args.gamma,
        n=args.n,
        **_variant_meta(args),
    )
    meta.pop("spectrum")
    meta.update(geometry="sphere", q0_1_per_m=paper.Q0, qr_1_per_m=paper.QR, q1_1_per_m=args.q1)
    for s in data.surfaces:
        meta[s.label.replace(" ", "_")] = f"h_rms {s.h_rms:g} m, H {s.hurst:g}"
    written = []

    def path(name, suffix):
        written.append(f"{name}.{suffix}")
        return os.path.join(out, f"{name}.{suffix}")

    r3 = data.fig3
    hz = hertz_point_contact(paper.E_STAR, paper.RADIUS, r3.load)
    write_csv(
        path("fig3_profile_sphere", "csv"),
        ["r_m", "p_rough_Pa", "p_hertz_Pa"],
        zip(r3.r, r3.pressure, hz.pressure(r3.r), strict=True),
        {**meta, "load_N": r3.load, "alpha": r3.alpha},
        title="Sphere version of Fig. 3: p(r) of surface 1, rough and smooth (Hertz)",
    )
    fig = plotting.plot_profile(r3, label="rough (surface 1)")
    _save(fig, path("fig3_profile_sphere", ext), args)

    header = ["surface", "h_rms_m", "hurst", "load_N", "alpha", "p0_Pa", "p0_ratio", "s_m"]
    header += ["w_m", "w_over_s", "converged", "gamma_u", "p0_ratio_gaussian"]
    rows = []
    for i, s in enumerate(data.surfaces):
        for row in sweep_rows(s.results):
            gauss = float(p0_ratio_gaussian_sphere(row[1], s.gamma_u))
            rows.append((str(i + 1), s.h_rms, s.hurst, *row, s.gamma_u, gauss))
    lo, hi = paper.SPHERE_ALPHA_RANGE
    title = (
        f"Sphere versions of Figs. 4-5: loads F [N] per surface with alpha log-spaced over "
        f"{lo:g}..{hi:g} (F = (4/3) E* R^(1/2) (h_rms/alpha)^(3/2)); p0_ratio_gaussian = "
        "1/(3 gamma_u alpha)"
    )
    write_csv(path("fig4_ws_sphere", "csv"), header, rows, meta, title=title)
    write_csv(path("fig5_p0ratio_sphere", "csv"), header, rows, meta, title=title)
    series = {s.label: s.results for s in data.surfaces}
    _save(plotting.plot_w_over_s(series), path("fig4_ws_sphere", ext), args)
    fig = plotting.plot_p0_ratio(series, gamma_u={s.label: s.gamma_u for s in data.surfaces})
    _save(fig, path("fig5_p0ratio_sphere", ext), args)
    return written


def _sphere_paper(args) -> int:
    from fastline import paper
    from fastline.io import spectrum_summary

    _check_outputs(args)
    t0 = time.perf_counter()
    with _progress(len(paper.SURFACES) * args.loads, "paper (sphere)") as bar:
        data = paper.sphere_paper_data(
            q1=args.q1,
            loads=args.loads,
            n=args.n,
            gamma=args.gamma,
            max_iter=args.max_iter,
            hardness=args.hardness,
            progress=lambda _label: bar.update(),
            variant=args.variant,
        )
    elapsed = time.perf_counter() - t0
    written = _sphere_paper_files(data, args)
    lo, hi = paper.SPHERE_ALPHA_RANGE
    print(
        f"fastline paper (sphere): E* = {paper.E_STAR:g} Pa, R = {paper.RADIUS:g} m (sphere), "
        f"q0 = {paper.Q0:g} 1/m, qr = {paper.QR:g} 1/m, q1 = {args.q1:g} 1/m, gamma = "
        f"{args.gamma:g}, n = {args.n}; {args.loads} loads per surface, alpha {lo:g}..{hi:g}; "
        f"solved in {elapsed:.2f} s"
    )
    print(
        f"{'surface':<10}{'h_rms [m]':>10}{'H':>5}{'gamma_u':>9}{'load F range [N]':>23}"
        f"{'w/s range':>17}{'p0 ratio range':>21}{'not conv.':>10}"
    )
    for s in data.surfaces:
        rs = s.results
        f, ws, pr = ([getattr(r, k) for r in rs] for k in ("load", "w_over_s", "p0_ratio"))
        bad = sum(not r.converged for r in rs)
        print(
            f"{s.label:<10}{s.h_rms:>10.3g}{s.hurst:>5.2g}{s.gamma_u:>9.4f}"
            f"{min(f):>11.3g}-{max(f):<11.3g}{min(ws):>8.4f}-{max(ws):<8.4f}"
            f"{min(pr):>10.4g}-{max(pr):<10.4g}{bad:>10d}"
        )
    print(
        f"spectra          q {paper.Q0:g}-{args.q1:g} 1/m (longest wavelength "
        f"{spectrum_summary(data.surfaces[0].psd)['longest_wavelength']:.3g} m)"
    )
    _report_warnings(data.results)
    print(f"wrote {', '.join(written)} to {args.out}")
    return _convergence_status(data.results)


# ----------------------------------------------------------------------------------------------
# measured surfaces (psd, --scan)
# ----------------------------------------------------------------------------------------------
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
        "(fastline.scan.analyse_scan; docs/topography.md). Lengths in m whatever the file's "
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


def _psd_parser(sub, fmt) -> None:
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


class _ScanSource(str):
    """The scan file a spectrum was measured from: its path (a str) with the analysis
    (``.scan``, a :class:`fastline.scan.ScanSpectrum`) attached."""

    scan = None


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
    """The options of fastline.scan.analyse_scan that were given (the rest keep its defaults)."""
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

    from fastline.scan import analyse_scan
    from fastline.topography import TopographyWarning

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
    from fastline.scan import LIMIT_RULES

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
    if f.at_bound:  # held there: no error bar
        steeper = "faster" if f.hurst >= 1.0 else "slower"
        hurst = f"H {f.hurst:g} (held at its bound: C falls {steeper} than self-affine can)"
    lines.append(
        f"fit              {hurst}, q_r {f.qr:.4g} ± {f.qr_err:.2g} 1/m, h_rms {f.h_rms:.4g} ± "
        f"{f.h_rms_err:.2g} m (self-affine with roll-off fitted to C(q) over "
        f"{f.q_range[0]:.4g}-{f.q_range[1]:.4g} 1/m; scatter of ln C {f.rms_residual:.2g} rms, "
        f"{f.n_points} points)"
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


def cmd_psd(args) -> int:
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
        from fastline.plotting import plot_measured_psd

        _save(plot_measured_psd(scan), args.plot, args)
        written.append(args.plot)
    if written:
        print(f"wrote {', '.join(written)}")
    return 0


COMMANDS = {
    "paper": cmd_paper,
    "profile": cmd_profile,
    "sweep": cmd_sweep,
    "leak": cmd_leak,
    "batch": cmd_batch,
    "psd": cmd_psd,
}


def _cmd_validate(args) -> int:
    from fastline.cli_validate import cmd_validate

    return cmd_validate(args)


COMMANDS["validate"] = _cmd_validate


def main(argv: list[str] | None = None) -> int:
    """Run the command line; returns the exit status (0 done, 1 not converged, 2 bad input)."""
    argv = list(sys.argv[1:] if argv is None else argv)
    parser = build_parser()
    try:
        args = parser.parse_args(_join_negative_values(argv))
        if args.command is None:
            parser.print_help()
            return 2
        if getattr(args, "gamma", 0.0) is None:  # the variant's own gamma
            from fastline.variants import get_variant

            args.gamma = get_variant(args.variant).default_gamma
        return COMMANDS[args.command](args)
    except (CLIError, ValueError) as e:
        msg = " ".join(str(e).split())
        print(f"fastline: error: {msg}", file=sys.stderr)
        return 2


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
