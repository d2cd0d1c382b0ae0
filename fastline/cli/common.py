"""What the commands of the command line share: option types and groups, outputs, printing.

The option types (:func:`number`, :func:`positive`, ...) check one value for argparse; the
option groups (spectrum, material and geometry, numerics, figures) are added to several
commands; :func:`check_outputs` checks every output path before any solve; the printing helpers
report results, warnings (once per cause) and convergence; :func:`sweep_in_parallel` runs a
sweep's loads on ``--workers``/``--scheduler`` through :func:`fastline.sweep`.

The bottom of :mod:`fastline.cli`: it imports no other module of it. :mod:`fastline.cli.scene`
builds on it (the scene of the options, measured surfaces), the command modules
(:mod:`~fastline.cli.leak`, :mod:`~fastline.cli.psd`, :mod:`~fastline.cli.sphere`,
:mod:`~fastline.cli.validate`) on both, and :mod:`fastline.cli.app` (the parser and
:func:`~fastline.cli.app.main`) on all. Nothing heavy is imported here at import time: the
names of fastline load their modules on first use.

SI units throughout: m, 1/m, m^4, Pa, N/m (N for a sphere).
"""

from __future__ import annotations

import argparse
import importlib.util
import math
import os
import sys
from typing import TYPE_CHECKING

import fastline as fl
from fastline import contact, theory

if TYPE_CHECKING:  # annotations only: matplotlib, numpy, tqdm and dask load on first use
    import os
    from collections.abc import Callable, Iterable, Sequence
    from types import SimpleNamespace
    from typing import TypeAlias

    import numpy as np
    from distributed import Client
    from matplotlib.figure import Figure
    from tqdm import tqdm

    from fastline import PSD, LineContactResult, PerssonTheory, PointContactResult, SweepTable

    #: the result of one solve, a cylinder's or a sphere's
    ContactResult: TypeAlias = LineContactResult | PointContactResult

__all__ = [
    # option types and groups
    "CLIError",
    "number",
    "positive",
    "count",
    "fraction",
    "gamma",
    "SPECTRUM_DEFAULTS",
    "SPECTRUM_FLAGS",
    "GEOMETRIES",
    "GEOMETRY_DEFAULTS",
    "geometry_defaults",
    "spectrum_options",
    "material_options",
    "numerics_options",
    "law_option",
    "model_name",
    "model_line",
    "variant_option",
    "model_checks",
    "figure_options",
    # outputs and printing
    "ScanSource",
    "check_outputs",
    "require_matplotlib",
    "spectrum_line",
    "warn",
    "report_warnings",
    "convergence_status",
    "progress",
    "solve_kwargs",
    "persson_theory",
    "save",
    "result_lines",
    "roughness_lines",
    "alpha_cell",
    "asperity_lines",
    "law_lines",
    "metadata",
    # sweeps on executors
    "open_executor",
    "run_table",
    "table_status",
    "sweep_in_parallel",
]
#: defaults of the self-affine spectrum options (the paper's surface 1)
SPECTRUM_DEFAULTS = {"h_rms": 10e-6, "hurst": 0.8, "q0": 1e3, "qr": 1e4, "q1": 1e9}
SPECTRUM_FLAGS = {"h_rms": "--h-rms", "hurst": "--hurst", "q0": "--q0", "qr": "--qr", "q1": "--q1"}
GEOMETRIES = ("cylinder", "sphere")
#: defaults that depend on the geometry (loads in N/m for a cylinder, N for a sphere)
GEOMETRY_DEFAULTS = {
    "cylinder": {"load": 1e4, "loads_from": 1e3, "loads_to": 1.5e6, "n": 1024},
    "sphere": {"load": 10.0, "loads_from": 0.1, "loads_to": 1e3, "n": 512},
}


class CLIError(Exception):
    """A user error: reported as one line on stderr, exit status 2."""


# ----------------------------------------------------------------------------------------------
# option types
# ----------------------------------------------------------------------------------------------
def number(text: str) -> float:
    """A finite number."""
    try:
        v = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"not a number: {text!r}") from None
    if not math.isfinite(v):
        raise argparse.ArgumentTypeError(f"must be a finite number, got {text!r}")
    return v


def positive(text: str) -> float:
    """A finite number > 0."""
    v = number(text)
    if v <= 0.0:
        raise argparse.ArgumentTypeError(f"must be > 0, got {text!r}")
    return v


def count(text: str) -> int:
    """An integer >= 1."""
    try:
        v = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"not an integer: {text!r}") from None
    if v < 1:
        raise argparse.ArgumentTypeError(f"must be >= 1, got {text!r}")
    return v


def fraction(text: str) -> float:
    """A number inside (0, 1)."""
    v = number(text)
    if not 0.0 < v < 1.0:
        raise argparse.ArgumentTypeError(f"must lie in (0, 1), got {text!r}")
    return v


def gamma(text: str) -> float:
    """gamma of the theory's correction S(P), inside the theory's range."""
    v = number(text)
    lo, hi = theory.GAMMA_RANGE
    if not lo <= v <= hi:
        raise argparse.ArgumentTypeError(f"must lie in [{lo:g}, {hi:g}], got {text!r}")
    return v


# ----------------------------------------------------------------------------------------------
# parser
# ----------------------------------------------------------------------------------------------
def spectrum_options(parser: argparse.ArgumentParser) -> None:
    """The roughness spectrum: self-affine with roll-off, or a measured table (--psd)."""
    g = parser.add_argument_group(
        "roughness spectrum",
        "Self-affine spectrum with roll-off: C(q) = C0 for q0 <= q < qr, C0 (q/qr)^(-2(1+H)) for "
        "qr <= q <= q1, normalised so that h_rms^2 = 2 pi int q C(q) dq (Persson's isotropic "
        "convention), or a measured spectrum (--psd, not combined with the others). Use the "
        "combined spectrum of both surfaces (C = C1 + C2). Defaults: the paper's surface 1.",
    )
    g.add_argument(
        "--h-rms", type=positive, metavar="M", help="rms roughness h_rms [m] (default 10e-6)"
    )
    g.add_argument(
        "--hurst", type=number, metavar="H", help="Hurst exponent H [-], 0 < H <= 1 (default 0.8)"
    )
    g.add_argument(
        "--q0", type=positive, metavar="1/M", help="smallest wavenumber q0 [1/m] (default 1e3)"
    )
    g.add_argument(
        "--qr", type=positive, metavar="1/M", help="roll-off wavenumber qr [1/m] (default 1e4)"
    )
    g.add_argument(
        "--q1",
        type=positive,
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


def material_options(
    parser: argparse.ArgumentParser, load: bool, geometry: bool = False
) -> argparse._ArgumentGroup:
    """E* or the solids' constants, the radius, the load (``load``), --geometry (``geometry``);
    returns the group (``validate`` adds its load options to it)."""
    m = parser.add_argument_group(
        "material and geometry",
        "Give the effective modulus directly or the two solids' elastic constants "
        "(1/E* = (1-nu1^2)/E1 + (1-nu2^2)/E2).",
    )
    m.add_argument(
        "--E-star",
        type=positive,
        metavar="PA",
        help="effective (plane-strain) modulus E* [Pa] (default 1.33e9 when no "
        "--E1/--nu1/--E2/--nu2 are given)",
    )
    m.add_argument("--E1", type=positive, metavar="PA", help="Young's modulus of solid 1 [Pa]")
    m.add_argument("--nu1", type=number, metavar="NU", help="Poisson ratio of solid 1 [-]")
    m.add_argument("--E2", type=positive, metavar="PA", help="Young's modulus of solid 2 [Pa]")
    m.add_argument("--nu2", type=number, metavar="NU", help="Poisson ratio of solid 2 [-]")
    if geometry:
        _geometry_options(m, load)
        return m
    m.add_argument(
        "--radius",
        type=positive,
        default=0.01,
        metavar="M",
        help="cylinder radius R [m] (default 0.01)",
    )
    if load:
        m.add_argument(
            "--load",
            type=positive,
            default=1e4,
            metavar="N/M",
            help="normal load per unit cylinder length f_N [N/m] (default 1e4)",
        )
    return m


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
        type=positive,
        default=0.01,
        metavar="M",
        help="cylinder radius R [m], or the sphere's with --geometry sphere (default 0.01)",
    )
    if load:
        m.add_argument(
            "--load",
            type=positive,
            metavar="LOAD",
            help="normal load per unit cylinder length f_N [N/m] (default 1e4); with "
            "--geometry sphere the total load F on the sphere [N] (default 10)",
        )


def geometry_defaults(args: argparse.Namespace) -> str:
    """Fill the options whose default depends on the geometry; returns the geometry."""
    geometry = getattr(args, "geometry", "cylinder")
    for key, value in GEOMETRY_DEFAULTS[geometry].items():
        if hasattr(args, key) and getattr(args, key) is None:
            setattr(args, key, value)
    return geometry


def numerics_options(
    parser: argparse.ArgumentParser, model: bool = True, geometry: bool = False
) -> None:
    """--model (when ``model``), --gamma, --variant, --n, --max-iter and --hardness."""
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
            "--law",
            metavar="FILE",
            help="a law calibrated on boundary-element ensembles of this spectrum and E* "
            "(fastline calibrate --out FILE) in place of --model; leak uses its hydraulic gap; "
            "on sweep's --workers/--scheduler it travels to the workers with the tasks",
        )
    s.add_argument(
        "--gamma",
        type=gamma,
        default=None,
        metavar="G",
        help="parameter gamma of the theory's correction S(P), in [0.05, 1] (default: the "
        "variant's, 0.45; 5/9 for wang-mueser)",
    )
    variant_option(s)
    s.add_argument(
        "--n",
        type=count,
        default=None if geometry else 1024,
        metavar="N",
        help="grid points across the contact (default 1024, at least 16)"
        + ("; with --geometry sphere: cells from the axis outwards (default 512, at most 4096)"
           if geometry else ""),
    )  # fmt: skip
    s.add_argument(
        "--max-iter",
        type=count,
        metavar="K",
        help="Newton steps allowed per solve (default: the solver's, 100)",
    )
    s.add_argument(
        "--hardness",
        type=positive,
        metavar="PA",
        help="indentation hardness of the softer solid [Pa]: warns when the elastic mean "
        "asperity pressure h' E*/2 exceeds it (plastic flow likely)",
    )


def variant_option(group: argparse._ArgumentGroup) -> None:
    """--variant, the theory's u(p) (None when not given: main fills in the default)."""
    group.add_argument(
        "--variant",
        choices=tuple(theory.VARIANTS),
        default=None,  # fastline.cli.app.main fills in DEFAULT_VARIANT: None says 'not given'
        help="variant of the theory's u(p) (docs/theory.md, Variants): the bracket gamma + "
        "3(1-gamma)P^2 of the energy derivation (default, "
        + theory.DEFAULT_VARIANT
        + "), the printed gamma + (1-gamma)P^2, or Wang & Mueser's correction, which also "
        "enters the contact area (not with leak)",
    )


#: options a smooth (--model hertz) solve does not use: the roughness and the theory's
_ROUGH_ONLY = {
    **SPECTRUM_FLAGS,
    "psd": "--psd",
    "scan": "--scan",
    "gamma": "--gamma",
    "variant": "--variant",
    "hardness": "--hardness",
}


def model_checks(args: argparse.Namespace) -> None:
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


def figure_options(parser: argparse.ArgumentParser) -> None:
    """--format and --dpi of the figures."""
    g = parser.add_argument_group("figures")
    g.add_argument(
        "--format",
        choices=("png", "pdf", "svg"),
        help="figure format (default: from the file name's extension, else png)",
    )
    g.add_argument(
        "--dpi",
        type=positive,
        metavar="DPI",
        help="resolution of PNG figures in dots per inch (default 150)",
    )


# ----------------------------------------------------------------------------------------------
# outputs, printing
# ----------------------------------------------------------------------------------------------
class ScanSource(str):
    """The scan file a spectrum was measured from: its path (a str) with the analysis
    (``.scan``, the :class:`~fastline.surfaces.ScanSpectrum` of
    :func:`fastline.surfaces.analyse_scan`) attached."""

    scan = None


def check_outputs(args: argparse.Namespace) -> None:
    """Check every output path before any solve."""
    for name in ("csv", "plot"):
        path = getattr(args, name, None)
        if path is not None:
            fl.io.check_output_file(path)
    if getattr(args, "plot", None) is not None or getattr(args, "out", None) is not None:
        require_matplotlib()
    if getattr(args, "plot", None) is not None:  # a .jpg refused before any solve
        fl.plotting.figure_format(args.plot, getattr(args, "format", None))
    if getattr(args, "out", None) is not None:
        fl.io.check_output_dir(args.out)


def require_matplotlib() -> None:
    """Refuse a figure when matplotlib (an optional dependency) is not installed."""
    if sys.modules.get("matplotlib", 0) is None or importlib.util.find_spec("matplotlib") is None:
        raise CLIError(
            'plotting needs matplotlib: pip install matplotlib (the "plot" extra of '
            "fastline-contact)"
        )


def spectrum_line(psd: PSD, source: str | None, model: str | None = None) -> str:
    """The spectrum the scene uses; for ``--model hertz`` that there is none."""
    if model == "hertz":
        return "spectrum         none: --model hertz solves the smooth contact (no roughness)"
    s = fl.io.spectrum_summary(psd)
    what = f"file {source}" if source else "self-affine"
    if isinstance(source, ScanSource):
        what = f"measured, scan {source}"
    return (
        f"spectrum         {what}: h_rms {s['h_rms']:.4g} m, rms slope h' {s['rms_slope']:.4g}, "
        f"q {s['q0']:.4g}-{s['q1']:.4g} 1/m (longest wavelength {s['longest_wavelength']:.3g} m)"
    )


def warn(msg: str) -> None:
    """One ``fastline: warning: ...`` line on stderr."""
    print(f"fastline: warning: {msg}", file=sys.stderr)


def report_warnings(results: Iterable[ContactResult]) -> None:
    """Print what the diagnostics found, once per cause, naming the loads."""
    for _cause, msg in contact.summarise_warnings(results):
        warn(msg)


def convergence_status(results: Sequence[ContactResult]) -> int:
    """0, or 1 after an error line naming the loads whose solve did not converge."""
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


def progress(total: int, desc: str) -> tqdm:
    """A tqdm bar on stderr; silent when stderr is not a terminal (log files, pipes)."""
    from tqdm import tqdm

    return tqdm(total=total, desc=desc, unit="solve", file=sys.stderr, disable=None, leave=False)


def solve_kwargs(args: argparse.Namespace, th: PerssonTheory | None) -> dict:
    """The solver settings of the options, with the scene's theory ``th``."""
    return dict(
        n=args.n,
        gamma=args.gamma,
        theory=th,
        max_iter=args.max_iter,
        hardness=args.hardness,
        warn=False,
    )


def law_option(args: argparse.Namespace, psd: PSD, E_star: float) -> None:
    """``--law FILE``: the calibrated law, checked against the scene's spectrum and E*, in
    ``args.model`` (nothing without --law)."""
    path = getattr(args, "law", None)
    if path is None:
        return
    if args.model != "persson":
        raise CLIError(f"--law replaces --model: drop --model {args.model}")
    if not os.path.isfile(path):
        raise CLIError(f"--law {path}: no such file")
    args.model = fl.CalibratedLaw.load(path, psd=psd, E_star=E_star)


def model_name(args: argparse.Namespace) -> str:
    """The name of the scene's law (a calibrated law's file is named beside it)."""
    return getattr(args.model, "name", args.model)


def persson_theory(psd: PSD, E_star: float, args: argparse.Namespace) -> PerssonTheory | None:
    """The theory of the scene (None for the smooth ``--model hertz``)."""
    if getattr(args, "model", "persson") == "hertz":
        return None
    return fl.PerssonTheory(psd, E_star, gamma=args.gamma, variant=args.variant)


def save(fig: Figure, path: str | os.PathLike, args: argparse.Namespace) -> None:
    """Write a figure in the format and resolution of the figure options."""
    fl.plotting.save_figure(fig, path, format=args.format, dpi=args.dpi)


# ----------------------------------------------------------------------------------------------
# results
# ----------------------------------------------------------------------------------------------
def model_line(r: ContactResult) -> str:
    """The printed model of a solve: the pressure law (``persson``, ``exponential``,
    ``calibrated``, ...), the method and the grid (a row of a table sweep: the law only)."""
    method, diag = getattr(r, "method", None), getattr(r, "diagnostics", None)
    n = diag.get("n", "?") if isinstance(diag, dict) else getattr(r, "n", "?")
    if method is None:
        return f"model            {r.model}"
    return f"model            {r.model} (method {method}, n = {n})"


def result_lines(r: LineContactResult, diag: dict) -> list[str]:
    """The printed result of a cylinder's solve (``profile``, ``leak``)."""
    lines = [
        model_line(r),
        f"load f_N         {r.load:.6g} N/m",
        f"E*, R            {r.E_star:.6g} Pa, {r.radius:.6g} m",
        *roughness_lines(r, diag),
        f"peak pressure p0 {r.p0:.6g} Pa",
        f"p0 / p0(Hertz)   {r.p0_ratio:.6g}",
        f"std. dev. s      {r.s:.6g} m",
        f"FWHM w           {r.fwhm:.6g} m ({diag['fwhm_cells']:.3g} grid cells)",
        f"w/s              {r.w_over_s:.6g}   (Hertz 3.464, Gaussian 2.355)",
    ]
    lines += asperity_lines(diag)
    lines.append(f"half-width / R   {diag['half_width_over_radius']:.4g}")
    if diag.get("longest_wavelength") is not None:
        lines.append(
            f"width / (2pi/q0) {diag['contact_width'] / diag['longest_wavelength']:.3g} "
            "(contact width over the longest roughness wavelength; the theory wants >= 1)"
        )
    lines += law_lines(diag)
    lines += [
        f"converged        {'yes' if r.converged else 'NO'} ({r.iterations} iterations, "
        f"{r.convolutions} FFT convolutions, residual {r.residual:.3g})",
        f"force error      {r.force_error:.3g} (relative); edge pressure {r.edge_pressure:.3g} p0",
    ]
    if r.message:
        lines.append(f"solver message   {r.message}")
    return lines


def roughness_lines(r: ContactResult, diag: dict, delta: str = "delta") -> list[str]:
    """alpha and the regime it puts the scene in (none for the smooth ``hertz`` model)."""
    if r.model == "hertz":
        return []
    return [
        f"alpha            {r.alpha:.6g}   (h_rms / delta, {delta} = {r.delta:.6g} m)",
        f"regime           {diag['regime']}",
    ]


def alpha_cell(r: ContactResult | np.record | SimpleNamespace, width: int) -> str:
    """alpha in a sweep table's column (``-`` for the smooth ``hertz`` model)."""
    return f"{'-':>{width}}" if r.model == "hertz" else f"{r.alpha:>{width}.4g}"


def asperity_lines(diag: dict) -> list[str]:
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


def law_lines(diag: dict) -> list[str]:
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


def metadata(psd: PSD, E_star: float, args: argparse.Namespace, source: str | None) -> dict:
    """The scene's ``# key: value`` lines of a result file (a scan's analysis included)."""
    meta = fl.io.scene_metadata(
        psd,
        E_star,
        args.radius,
        model=model_name(args),
        gamma=args.gamma,
        n=args.n,
        source=source,
        **_variant_meta(args),
    )
    if getattr(args, "law", None) is not None:
        meta["law_file"] = args.law
    if isinstance(source, ScanSource):
        meta["spectrum"] = f"measured: scan {source}"
        meta.update(source.scan.metadata())
    return meta


def _variant_meta(args) -> dict:
    """The variant as a metadata entry when it is not the default (older files unchanged)."""
    v = getattr(args, "variant", theory.DEFAULT_VARIANT)
    return {} if v == theory.DEFAULT_VARIANT else {"variant": v}


# ----------------------------------------------------------------------------------------------
# sweeps on executors
# ----------------------------------------------------------------------------------------------
def open_executor(args: argparse.Namespace) -> tuple[Client | None, Callable[[], object]]:
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


def run_table(scenes: dict[str, list], args: argparse.Namespace) -> SweepTable:
    """fastline.sweep on the executor the options name; bad tables are usage errors."""
    executor, release = open_executor(args)
    try:
        return fl.sweep(
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


def table_status(table: SweepTable) -> int:
    """Print the failed and non-converged scenes of a sweep table (as errors); 0 or 1."""
    status = 0
    for cause, msg in table.warnings:
        if cause in ("failed", "not_converged"):
            print(f"fastline: error: {msg}", file=sys.stderr)
            status = 1
        else:
            warn(msg)
    return status


def sweep_in_parallel(
    psd: PSD, E: float, args: argparse.Namespace, loads: np.ndarray
) -> tuple[np.recarray, SweepTable]:
    """The loads of the sweep command (either geometry) as a scene table on
    --workers/--scheduler: rows with the attributes of a result (load, alpha, p0, ...) and the
    table. With --law the law (loaded and checked against the spectrum and E* by
    :func:`law_option`) is the table's law column: it travels to the workers as arrays."""
    import numpy as np

    law = None if isinstance(args.model, str) else args.model
    k = len(loads)
    scenes = {
        "geometry": [args.geometry] * k,
        "psd": [psd] * k,
        "E_star": [E] * k,
        "radius": [args.radius] * k,
        "load": [float(f) for f in loads],
        "model": [args.model if law is None else "persson"] * k,
        "n": [args.n] * k,
        "gamma": [args.gamma] * k,
        "variant": [args.variant] * k,
        "max_iter": [args.max_iter or 0] * k,
        "hardness": [math.nan if args.hardness is None else args.hardness] * k,
    }
    if law is not None:
        scenes["law"] = [law] * k
    table = run_table(scenes, args)
    return table.table.view(np.recarray), table
