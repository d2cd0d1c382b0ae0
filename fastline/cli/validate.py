"""``fastline validate``: the theory against a boundary-element simulation of the user's surface.

A line-contact scene (with ``--geometry sphere`` a sphere on a flat; with ``--leak`` a nominally
flat contact under uniform pressures) is solved by the theory with each law asked for and by an
ensemble of BEM realisations on random surfaces of the same spectrum
(:mod:`fastline.reports.validation`, :mod:`fastline.bem`); the differences are printed in units of
the BEM's standard error. Argument parsing and printing only.
"""

from __future__ import annotations

import argparse
import math
import os
import sys
import time
import warnings
from typing import Any

import fastline as fl
from fastline import bem, reports, theory
from fastline.cli.common import (
    CLIError,
    check_outputs,
    count,
    figure_options,
    gamma,
    material_options,
    number,
    open_executor,
    positive,
    save,
    spectrum_line,
    variant_option,
)
from fastline.cli.scene import scan_options, scene

__all__ = ["validate_parser", "cmd_validate", "VALIDATE_DEFAULTS"]

#: defaults of the spectrum, the narrow-band paper-like surface of docs/validation.md (a BEM
#: grid resolves q1/q0 up to ~100, not profile's 1e6), and of the load, alpha = 1 (floats in SI
#: units; None: derived from q0); E* (1.33e9 Pa) and R (0.01 m) are profile's
VALIDATE_DEFAULTS: dict[str, Any] = {
    "h_rms": 0.5e-6,
    "hurst": 0.8,
    "q0": 2.0 * math.pi / 40e-6,
    "qr": None,  # = q0 (no roll-off)
    "q1": None,  # = 32 q0
    "alpha": 1.0,
}
#: defaults that depend on the geometry (the theory's grid; the cell length along the axis)
GEOMETRY_DEFAULTS: dict[str, dict[str, Any]] = {
    "cylinder": {"n": 1024, "periods": 2.0},
    "sphere": {"n": 512, "periods": None},
}
#: largest BEM grid accepted (cells): about 1.5 GB of working arrays
MAX_CELLS = 2**24
#: fewest BEM realisations: fastline.reports.validation.MIN_REALIZATIONS (that module loads the
#: BEM, not wanted to build the parser; tests/test_validation.py holds the two equal)
MIN_REALIZATIONS = 2

DESCRIPTION = """\
Check the theory against an exact (boundary-element) simulation of the same scene on random
surfaces of the given spectrum: a rigid cylinder on a rough elastic half-space, periodic along
the cylinder's axis, solved by constrained conjugate gradients (Polonsky & Keer) on several
realisations. Prints the BEM's p0/p0_Hertz, s and w/s with standard errors, each law's values
and their difference in BEM standard errors (z; |z| <= 2 is agreement at about 95 %), and with
--plot the BEM's mean profile with its error band against the theory's p(x).

With --geometry sphere: a rigid sphere instead (an isolated square patch four contact widths on a
side), the BEM's pressure averaged over rings about the axis, p_bar(r), against the theory's p(r);
the load is the total load on the sphere in N, s^2 = int r^2 p dA / (2F), w the FWHM along a
diameter, alpha = h_rms / delta with delta = a^2/R. The patch grows like 1/alpha: a sphere at
alpha = 0.1 needs about ten times the cells of one at alpha = 1.

With --leak: a nominally flat contact under the uniform pressures --pressure, the BEM contact
fraction, mean gap and the effective gap of a Reynolds flow through the gap field against the
theory's real contact area, mean separation u(p) and critical-junction gap u_c.

With --law FILE: a law calibrated on flat-contact BEM ensembles of the same spectrum and E*
(fastline calibrate --out FILE) beside the theory's laws (with --leak also its hydraulic gap
against the effective gap). The table names the law closest to the BEM: the smallest mean |z|
of p0, s and w/s (--leak: of u(p)), and for --leak the leak gap whose leak rate (gap^3) is
closest to the BEM's (the typical factor exp(mean |3 ln(gap / BEM gap)|) over the pressures).

The BEM grid has --points-per-wavelength cells per shortest wavelength 2 pi/q1 and a period of
--periods longest wavelengths 2 pi/q0 along the axis: spectra with q1/q0 up to ~100 run in
seconds to minutes per realisation. The nominal pressure is averaged over bins that follow
the contact's own width (at least 20 across it, at most a quarter of 2 pi/q0, at least one
cell); a contact too narrow to compare widths (narrower than 2 pi/q0, or fewer than 10 cells
across) is named in the table and the figure. Defaults: the spectrum of the paper-like
narrow-band scene of docs/validation.md (H 0.8, q1/q0 = 32, h_rms 0.5 um), alpha = 1, and
profile's E* (1.33 GPa) and R (10 mm). Spectra: self-affine, --psd or --scan, as for profile."""

EPILOG = """\
examples:
  fastline validate --realizations 8 --plot validate.png
  fastline validate --E-star 10e6 --radius 32.8e-3 --realizations 40 \\
      --scheduler tcp://host:8786 --csv profile.csv
  fastline validate --alpha 0.1 --all-variants --gw --csv profile.csv
  fastline validate --E1 2.1e11 --nu1 0.3 --E2 5e6 --nu2 0.49 --radius 2e-3 --load 50 \\
      --q0 1e4 --qr 1e5 --q1 1e6 --points-per-wavelength 2
  fastline validate --scan examples/scan_example.txt --dx 1e-6 --units um --q1 1e6 \\
      --points-per-wavelength 2 --alpha 0.3
  fastline validate --geometry sphere --q1 1.26e6 --alpha 0.3 --workers 2 --plot sphere.png
  fastline validate --leak --pressure 2e3 1e4 5e4 --all-variants --plot flat.png
  fastline validate --E-star 10e6 --radius 32.8e-3 --alpha 3 --all-variants --law law.npz"""


def validate_parser(sub: argparse._SubParsersAction, fmt: type[argparse.HelpFormatter]) -> None:
    """The ``validate`` sub-command."""
    p = sub.add_parser(
        "validate",
        help="the theory against a boundary-element simulation of the same surface",
        formatter_class=fmt,
        description=DESCRIPTION,
        epilog=EPILOG,
    )
    _spectrum_group(p)
    scan_options(p)
    _scene_group(p)
    _theory_group(p)
    _bem_group(p)
    p.add_argument("--csv", metavar="FILE", help="write the profiles (or flat results) to FILE")
    p.add_argument("--plot", metavar="FILE", help="write a figure to FILE")
    figure_options(p)


def _spectrum_group(p: argparse.ArgumentParser) -> None:
    """The roughness spectrum: self-affine with roll-off, or measured (``--psd``)."""
    g = p.add_argument_group(
        "roughness spectrum",
        "Self-affine spectrum with roll-off (as for profile) or a measured one (--psd). "
        "Defaults: h_rms 0.5e-6 m, H 0.8, q0 = 2 pi/40e-6 1/m, qr = q0, q1 = 32 q0.",
    )
    g.add_argument("--h-rms", type=positive, metavar="M", help="rms roughness h_rms [m]")
    g.add_argument("--hurst", type=number, metavar="H", help="Hurst exponent H, 0 < H <= 1")
    g.add_argument("--q0", type=positive, metavar="1/M", help="smallest wavenumber q0 [1/m]")
    g.add_argument("--qr", type=positive, metavar="1/M", help="roll-off wavenumber [1/m]")
    g.add_argument("--q1", type=positive, metavar="1/M", help="cut-off wavenumber q1 [1/m]")
    g.add_argument("--psd", metavar="FILE", help="measured isotropic spectrum (q [1/m], C [m^4])")


def _scene_group(p: argparse.ArgumentParser) -> None:
    """Material and scene as for profile (E* or the solids' constants, geometry, radius), the
    load (or alpha), or the flat contact."""
    m = material_options(p, load=False, geometry=True)
    load = m.add_mutually_exclusive_group()
    load.add_argument(
        "--load",
        type=positive,
        metavar="LOAD",
        help="load per unit cylinder length f_N [N/m]; with --geometry sphere the total load "
        "F on the sphere [N]",
    )
    load.add_argument(
        "--alpha",
        type=positive,
        metavar="A",
        help="load from alpha = h_rms/delta (default 1): delta = 4 f_N/(pi E*) for a "
        "cylinder, delta = a^2/R with a = (3 F R/(4 E*))^(1/3) for a sphere",
    )
    m.add_argument(
        "--leak",
        action="store_true",
        help="nominally flat contact under the uniform pressures --pressure instead",
    )
    m.add_argument(
        "--pressure",
        type=positive,
        nargs="+",
        metavar="PA",
        help="nominal pressures of the flat contact [Pa] (with --leak)",
    )


def _theory_group(p: argparse.ArgumentParser) -> None:
    """The theory's variants, gamma, the Greenwood-Williamson law and its grid."""
    t = p.add_argument_group("theory")
    variant_option(t)
    t.add_argument(
        "--gamma",
        type=gamma,
        dest="validate_gamma",
        metavar="G",
        help="gamma of the variants' S(P) (default: each variant's own, 0.45; 5/9 wang-mueser)",
    )
    t.add_argument(
        "--all-variants", action="store_true", help="compare every variant of the theory"
    )
    t.add_argument(
        "--gw", action="store_true", help="also the Greenwood-Williamson law of the spectrum"
    )
    t.add_argument(
        "--law",
        dest="validate_law",
        metavar="FILE",
        help="also a law calibrated on boundary-element ensembles of this spectrum and E* "
        "(fastline calibrate --out FILE; checked against the scene); with --leak also its "
        "hydraulic gap",
    )
    t.add_argument(
        "--n",
        type=count,
        metavar="N",
        help="theory grid: cells across the cylinder's domain (1024), or from the sphere's "
        "axis (512)",
    )


def _bem_group(p: argparse.ArgumentParser) -> None:
    """The boundary-element ensemble: realisations, seed, where they run, resolution."""
    b = p.add_argument_group("boundary elements")
    b.add_argument(
        "--realizations",
        type=_realizations,
        default=8,
        metavar="K",
        help=f"random surfaces (8; at least {MIN_REALIZATIONS}: the differences are in units "
        "of their standard error)",
    )
    b.add_argument("--seed", type=int, default=0, metavar="S", help="root seed (0)")
    b.add_argument(
        "--workers",
        type=count,
        metavar="N",
        help="processes for the realisations (default: the CPUs, at most --realizations; 1: "
        "in this process)",
    )
    b.add_argument(
        "--scheduler",
        metavar="ADDRESS",
        help="solve the realisations on the dask.distributed cluster whose scheduler is at "
        'ADDRESS, e.g. tcp://host:8786 (needs dask: pip install "fastline-contact[dask]" for '
        "the extra)",
    )
    b.add_argument(
        "--points-per-wavelength",
        type=positive,
        default=4.0,
        metavar="P",
        help="cells per shortest wavelength 2 pi/q1 (default 4, at least 2)",
    )
    b.add_argument(
        "--periods",
        type=positive,
        metavar="K",
        help="cell length along the axis (flat: both ways) in 2 pi/q0 (default 2; not for "
        "the sphere, whose patch is sized from the contact)",
    )
    b.add_argument(
        "--progress",
        action="store_true",
        default=None,
        help="a progress bar over the realisations on stderr also when stderr is not a "
        "terminal (default: only on a terminal)",
    )


def _realizations(text: str) -> int:
    """--realizations: an integer >= MIN_REALIZATIONS (one surface has no standard error, and
    every z of the table would be NaN)."""
    k = count(text)
    if k < MIN_REALIZATIONS:
        raise argparse.ArgumentTypeError(
            f"must be >= {MIN_REALIZATIONS}, got {text!r}: the theory is compared in units of "
            "the BEM's standard error over the realisations, which one realisation does not have"
        )
    return k


# ----------------------------------------------------------------------------------------------
# scene
# ----------------------------------------------------------------------------------------------
def _scene(args):
    """(psd, E*, source) as profile's scene (E* or --E1/--nu1/--E2/--nu2, --psd, --scan), with
    the validate spectrum's defaults for a self-affine spectrum."""
    if args.psd is None and args.scan is None:
        d = VALIDATE_DEFAULTS
        q0 = d["q0"] if args.q0 is None else args.q0
        defaults = {"h_rms": d["h_rms"], "hurst": d["hurst"], "q0": q0, "qr": q0, "q1": 32 * q0}
        for key, value in defaults.items():
            if getattr(args, key) is None:
                setattr(args, key, value)
    return scene(args)


def _law(args, psd, E: float):
    """The calibrated law of ``--law FILE``, checked against the scene's spectrum and E*
    (None without --law)."""
    path = args.validate_law
    if path is None:
        return None
    if not os.path.isfile(path):
        raise CLIError(f"--law {path}: no such file")
    return fl.CalibratedLaw.load(path, psd=psd, E_star=E)


def _models(args) -> tuple[str, ...]:
    models = list(theory.VARIANTS) if args.all_variants else [args.variant]
    if args.gw:
        models.append("greenwood-williamson")
    return tuple(models)


def _check_grid(grid) -> None:
    cells = grid.nx * grid.ny
    if cells > MAX_CELLS:
        raise CLIError(
            f"the BEM grid would have {grid.nx} x {grid.ny} = {cells:.3g} cells (at most "
            f"{MAX_CELLS:.3g}): use a spectrum of smaller q1/q0, --points-per-wavelength 2-4 or "
            "--periods 1"
        )


def _workers(args) -> int:
    if args.workers is not None:
        return args.workers
    return max(1, min(os.cpu_count() or 1, args.realizations))


def _where(args) -> str:
    if args.scheduler is not None:
        return f"dask scheduler {args.scheduler}"
    workers = _workers(args)
    return f"{workers} process{'es' if workers > 1 else ''}"


# ----------------------------------------------------------------------------------------------
# commands
# ----------------------------------------------------------------------------------------------
def cmd_validate(args: argparse.Namespace) -> int:
    """``fastline validate``: exit status 0, or 1 when a BEM or theory solve did not converge."""
    if args.points_per_wavelength < 2.0:
        raise CLIError("--points-per-wavelength must be >= 2 (Nyquist)")
    if args.workers is not None and args.scheduler is not None:
        raise CLIError("give either --workers or --scheduler, not both")
    if args.validate_gamma is not None:
        _check_gamma(args.validate_gamma)
    if args.geometry == "sphere":
        if args.leak:
            raise CLIError("--leak is a flat contact: it cannot be combined with --geometry sphere")
        if args.periods is not None:
            raise CLIError(
                "--periods is for the cylinder and the flat contact (the sphere's patch is "
                "sized from the contact)"
            )
    for key, value in GEOMETRY_DEFAULTS[args.geometry].items():
        if getattr(args, key) is None:
            setattr(args, key, value)
    if args.leak:
        if args.pressure is None:
            raise CLIError("--leak needs --pressure (one or more nominal pressures in Pa)")
        if args.load is not None or args.alpha is not None:
            raise CLIError("--load/--alpha are for the cylinder: with --leak give --pressure")
        return _flat(args)
    if args.pressure is not None:
        raise CLIError("--pressure needs --leak")
    return _profile(args)


def _check_gamma(value: float) -> None:
    """gamma inside the theory's range (the message of the theory's own check)."""
    lo, hi = theory.GAMMA_RANGE
    if not lo <= value <= hi:
        raise ValueError(f"gamma must lie in [{lo:g}, {hi:g}] (dimensionless), got {value!r}")


def _header(psd, E, source, grid, args, what: str, law=None) -> list[str]:
    h_rms, slope = bem.lattice_moments(psd, grid)
    lines = [] if law is None else [f"law              {law.name} ({args.validate_law}): {law!r}"]
    return (
        [spectrum_line(psd, source)]
        + lines
        + [
            f"BEM              {what}: {args.realizations} realisations (seed {args.seed}) on "
            f"{grid.nx} x {grid.ny} cells of {grid.dx:.4g} m, {_where(args)}",
            f"BEM surfaces     h_rms {h_rms:.4g} m (spectrum {psd.h_rms:.4g} m), rms slope "
            f"{slope:.4g} (spectrum {psd.rms_slope:.4g})",
        ]
    )


def _run(args, validate, *params, **options):
    """``validate(*params, **options)`` on the workers or the dask scheduler of the options,
    with a progress bar on a terminal (or with --progress); a contact too narrow to compare
    widths is said by the table, not warned about a second time."""
    client, release = open_executor(args)
    try:
        workers = _workers(args) if client is None else None
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", fl.NarrowContactWarning)
            return validate(
                *params, executor=client, workers=workers, progress=args.progress, **options
            )
    finally:
        release()


#: per geometry: the BEM scene's words, the load's unit and the profile's coordinate
_PROFILE_WORDS = {
    "cylinder": ("rigid cylinder", "N/m", "x"),
    "sphere": ("rigid sphere (isolated patch)", "N (total load on the sphere)", "r"),
}


def _load(args, psd, E: float, R: float) -> float:
    """--load, or the load of --alpha (default 1) for the geometry (THEORY sections 5, 9)."""
    if args.load is not None:
        return args.load
    alpha = VALIDATE_DEFAULTS["alpha"] if args.alpha is None else args.alpha
    if args.geometry == "cylinder":
        return math.pi * E * psd.h_rms / (4.0 * alpha)  # delta = 4 f/(pi E*)
    a = math.sqrt(R * psd.h_rms / alpha)  # delta = a^2/R
    return 4.0 * E * a**3 / (3.0 * R)


def _profile_scene(args, psd, E: float, R: float, load: float):

    ppw = args.points_per_wavelength
    if args.geometry == "sphere":
        return bem.point_contact_scene(psd, E, R, load, points_per_wavelength=ppw)
    return bem.line_contact_scene(psd, E, R, load, points_per_wavelength=ppw, periods=args.periods)


def _profile(args) -> int:
    """A cylinder or a sphere: BEM ensemble against each model's profile."""
    psd, E, source = _scene(args)
    law = _law(args, psd, E)
    R = args.radius
    load = _load(args, psd, E, R)
    check_outputs(args)
    scene = _profile_scene(args, psd, E, R, load)
    _check_grid(scene.grid)
    what, unit, _ = _PROFILE_WORDS[args.geometry]
    print("\n".join(_header(psd, E, source, scene.grid, args, what, law)))
    print(f"scene            E* {E:.4g} Pa, R {R:.4g} m, load {load:.6g} {unit}")
    validation = reports.validation
    validate = (
        validation.validate_point_contact
        if args.geometry == "sphere"
        else validation.validate_line_contact
    )
    v = _run(
        args,
        validate,
        psd,
        E,
        R,
        load,
        models=_models(args),
        gamma=args.validate_gamma,
        law=law,
        realizations=args.realizations,
        seed=args.seed,
        n=args.n,
        scene=scene,
    )
    e = v.ensemble
    print(
        f"alpha            {e.alpha:.6g} (h_rms / delta, delta = {e.delta:.6g} m); BEM "
        f"{v.seconds_bem:.1f} s ({float(e.seconds.mean()):.2f} s per realisation), theory "
        f"{v.seconds_theory:.2f} s"
    )
    print(_bins_line(e))
    print(v.table())
    print("z = (theory - BEM) / BEM standard error; |z| <= 2: agreement at about 95 %")
    print(
        "chi2/bin: mean z^2 over the profile's core bins, (n-1)/(n-3) expected with n "
        f"realisations (n/a below {reports.validation.MIN_CHI2_REALIZATIONS})"
    )
    if args.csv:
        _profile_csv(args.csv, v, psd, E, R, source, args)
    if args.plot:
        save(fl.plotting.plot_validation(v), args.plot, args)
    ok = e.converged and all(r.converged for r in v.results.values())
    return _status(ok)


def _bins_line(e) -> str:
    """The bins (rings) of the BEM's p_bar and the contact's width they follow."""
    what = "bins" if e.geometry == "cylinder" else "rings"
    per_s = "4 s" if e.geometry == "cylinder" else "2 sqrt(5) s"
    return (
        f"BEM {what:<12} {e.bin_width:.4g} m ({e.bin_width / e.scene.grid.dx:.0f} cells): "
        f"{e.contact_width / e.bin_width:.3g} across the contact's width {e.contact_width:.4g} "
        f"m (= {per_s})"
    )


def _flat(args) -> int:
    import numpy as np

    psd, E, source = _scene(args)
    law = _law(args, psd, E)
    check_outputs(args)
    grid = bem.spectral_grid(
        psd, points_per_wavelength=args.points_per_wavelength, periods=args.periods
    )
    _check_grid(grid)
    print("\n".join(_header(psd, E, source, grid, args, "flat contact", law)))
    fv = _run(
        args,
        reports.validation.validate_flat_contact,
        psd,
        E,
        np.asarray(args.pressure),
        models=_models(args),
        gamma=args.validate_gamma,
        law=law,
        realizations=args.realizations,
        seed=args.seed,
        points_per_wavelength=args.points_per_wavelength,
        periods=args.periods,
    )
    per = float(np.mean(np.concatenate([e.seconds for e in fv.ensembles])))
    print(f"E*               {E:.4g} Pa; BEM {fv.seconds_bem:.1f} s ({per:.2f} s per realisation)")
    print(fv.table())
    print("z = (theory - BEM) / BEM standard error; the effective gap is (12 eta K)^(1/3) of the")
    print("Reynolds conductance K of the gap field, the theory's u_c its critical-junction gap")
    if args.csv:
        _flat_csv(args.csv, fv, psd, E, source, args)
    if args.plot:
        save(fl.plotting.plot_flat_validation(fv), args.plot, args)
    return _status(all(e.converged for e in fv.ensembles))


def _status(ok: bool) -> int:
    if ok:
        return 0
    print("fastline: error: a BEM realisation or a theory solve did not converge", file=sys.stderr)
    return 1


# ----------------------------------------------------------------------------------------------
# files
# ----------------------------------------------------------------------------------------------
def _meta(psd, E, args, source, **extra) -> dict:
    s = fl.io.spectrum_summary(psd)
    meta = {
        "spectrum": f"file {source}" if source else repr(psd),
        "h_rms_m": s["h_rms"],
        "E_star_Pa": E,
        "realizations": args.realizations,
        "seed": args.seed,
        "points_per_wavelength": args.points_per_wavelength,
        "periods": args.periods,
        "written": time.strftime("%Y-%m-%d %H:%M:%S"),
    }
    if args.periods is None:  # the sphere's patch
        del meta["periods"]
    meta.update(extra)
    return meta


def _key(model: str) -> str:
    """A model name as a CSV key (identifiers: read_csv keeps only those header keys)."""
    return model.replace("-", "_")


def _profile_csv(path, v, psd, E, R, source, args) -> None:
    e = v.ensemble
    sphere = v.geometry == "sphere"
    extra = {
        "geometry": v.geometry,
        "radius_m": R,
        "load_N" if sphere else "load_N_per_m": e.scene.load,
        "alpha": e.alpha,
        "bem_p0_ratio": f"{e.p0_ratio!r} +- {e.p0_ratio_error!r}",
        "bem_s_m": f"{e.s!r} +- {e.s_error!r}",
        "bem_w_over_s": f"{e.w_over_s!r} +- {e.w_over_s_error!r}",
        "bem_bin_width_m": e.bin_width,
        "bem_contact_width_m": e.contact_width,
    }
    if e.narrow:
        extra["bem_warning"] = e.narrow
    for name, c in v.comparisons.items():
        key = _key(name)
        extra[f"{key}_p0_ratio"] = v.results[name].p0_ratio
        extra[f"{key}_s_m"] = c.s.theory
        extra[f"{key}_w_over_s"] = c.w_over_s.theory
    x = _PROFILE_WORDS[v.geometry][2]
    cols = [f"{x}_m", "p_bem_Pa", "p_bem_se_Pa"] + [f"p_{_key(m)}_Pa" for m in v.comparisons]
    rows = zip(
        e.coordinate,
        e.pressure,
        e.pressure_error,
        *(c.theory_pressure for c in v.comparisons.values()),
        strict=True,
    )
    title = (
        "fastline validate --geometry sphere: BEM p_bar(r) (rings about the axis; r their mean "
        "radius) and the theory's p(r) averaged over them"
        if sphere
        else "fastline validate: BEM p_bar(x) (bins) and the theory's p(x) averaged over them"
    )
    fl.io.write_csv(path, cols, rows, _meta(psd, E, args, source, **extra), title=title)


def _flat_csv(path, fv, psd, E, source, args) -> None:
    cols = [
        "p_Pa",
        "bem_contact",
        "bem_contact_se",
        "bem_mean_gap_m",
        "bem_mean_gap_se_m",
        "bem_effective_gap_m",
        "bem_effective_gap_se_m",
        "bem_percolating_fraction",
    ]
    cols += [f"area_{_key(m)}" for m in fv.area] + [f"u_{_key(m)}_m" for m in fv.separation]
    cols += [f"u_c_{t:g}_m" for t in fv.critical_gap]
    cols += [f"g_{_key(m)}_m" for m in list(fv.laws)[-1:] if fv.hydraulic_gap]
    rows = []
    for i, (p, e) in enumerate(zip(fv.pressures, fv.ensembles, strict=True)):
        row = [p, e.contact_fraction, e.contact_fraction_error, e.mean_gap, e.mean_gap_error]
        row += [e.effective_gap, e.effective_gap_error, e.percolating_fraction]
        row += [fv.area[m][i].theory for m in fv.area]
        row += [fv.separation[m][i].theory for m in fv.separation]
        row += [fv.critical_gap[t][i].theory for t in fv.critical_gap]
        row += [fv.hydraulic_gap[i].theory] if fv.hydraulic_gap else []
        rows.append(row)
    fl.io.write_csv(
        path,
        cols,
        rows,
        _meta(psd, E, args, source, critical_gap_variant=fv.model),
        title="fastline validate --leak: flat contact, BEM against the theory",
    )
