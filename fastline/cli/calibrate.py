"""A pressure law calibrated on the boundary-element method: ``fastline calibrate``.

``fastline calibrate --psd FILE | --scan SCAN | --h-rms ... --out law.npz`` runs flat-contact
BEM ensembles of the spectrum over a pressure range (given with ``--pressure``, or chosen from
the loads and radius of the scenes to be solved), prints the calibration points and the check,
and writes the law file that ``--law`` on ``profile``, ``sweep`` and ``leak`` reads. Argument
parsing and printing only: the work is :func:`fastline.calibrate` (docs/calibration.md).
:mod:`fastline.cli.app` wires :func:`calibrate_parser` and :func:`cmd_calibrate` in.

SI units throughout: m, 1/m, m^4, Pa; loads in N/m (cylinder) or N (sphere).
"""

from __future__ import annotations

import argparse
import sys
import time

import fastline as fl
from fastline.cli.common import (
    CLIError,
    count,
    material_options,
    positive,
    spectrum_line,
    spectrum_options,
    warn,
)
from fastline.cli.scene import scan_options, scene

__all__ = ["calibrate_parser", "cmd_calibrate"]


def calibrate_parser(sub: argparse._SubParsersAction, fmt: type[argparse.HelpFormatter]) -> None:
    """The ``calibrate`` command: a law file from BEM ensembles of the spectrum."""
    p = sub.add_parser(
        "calibrate",
        help="calibrate the pressure law and hydraulic gap on BEM ensembles of a spectrum",
        formatter_class=fmt,
        description="Press a rigid flat on --realizations random surfaces of the spectrum at "
        "each pressure (boundary-element method, warm-started from pressure to pressure), "
        "measure the mean gap, the contact fraction and the Reynolds effective gap of each gap "
        "field, and write the law (a monotone fit joined to Persson's law outside the range) "
        "to --out for --law on profile, sweep and leak. The pressures: --pressure, or "
        "--pressures values spread over the range of the scenes given by --radius and --loads. "
        "Exit status 0 done, 1 the check or a solve warned, 2 bad usage or input.",
    )
    spectrum_options(p)
    scan_options(p)
    material_options(p, load=False, geometry=True)
    g = p.add_argument_group("calibration")
    g.add_argument("--out", metavar="FILE", required=True, help="the law file to write (.npz)")
    g.add_argument("--pressure", type=positive, nargs="+", metavar="PA",
                   help="nominal pressures to simulate [Pa] (at least 3)")  # fmt: skip
    g.add_argument("--loads", type=positive, nargs="+", metavar="LOAD",
                   help="loads of the scenes to be solved (N/m; N with --geometry sphere): the "
                   "range is chosen from them and --radius")  # fmt: skip
    g.add_argument("--pressures", type=count, default=15, metavar="N",
                   help="pressures over the range of --loads (default 15)")  # fmt: skip
    g.add_argument("--realizations", type=count, default=8, metavar="N",
                   help="random surfaces (default 8)")  # fmt: skip
    g.add_argument("--seed", type=int, default=0, help="root seed of the surfaces (default 0)")
    g.add_argument("--points-per-wavelength", type=positive, default=4.0, metavar="K",
                   help="cells per shortest wavelength 2 pi/q1, >= 4 (default 4)")  # fmt: skip
    g.add_argument("--periods", type=positive, default=4.0, metavar="L",
                   help="cell length in longest wavelengths 2 pi/q0 (default 4)")  # fmt: skip
    g.add_argument("--check", choices=("finer", "larger", "none"), default="finer",
                   help="the companion grid of the convergence check (default finer)")  # fmt: skip
    g.add_argument("--workers", type=count, metavar="N", help="local processes (default 1)")
    g.add_argument("--scheduler", metavar="ADDRESS", help="a dask.distributed scheduler")


def cmd_calibrate(args: argparse.Namespace) -> int:
    """Run ``fastline calibrate``; returns the exit status."""
    fl.io.check_output_file(args.out)
    psd, E, source = scene(args)
    if (args.pressure is None) == (args.loads is None):
        raise CLIError("give either --pressure (Pa) or --loads with --radius")
    geometry = "point" if getattr(args, "geometry", "cylinder") == "sphere" else "line"
    where = {"radius": args.radius, "loads": args.loads} if args.loads else {}
    from tqdm import tqdm

    t0 = time.perf_counter()
    with tqdm(total=1, desc="calibrate", unit="surface", file=sys.stderr, disable=None,
              leave=False) as bar:  # fmt: skip

        def progress(done: int, total: int) -> None:
            bar.total = total
            bar.update(done - bar.n)

        import warnings

        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always", fl.CalibrationWarning)
            law = fl.calibrate(
                psd, E, args.pressure, geometry=geometry, n_pressures=args.pressures,
                realizations=args.realizations, seed=args.seed,
                points_per_wavelength=args.points_per_wavelength, periods=args.periods,
                check=None if args.check == "none" else args.check,
                executor=args.scheduler, workers=args.workers, progress=progress, **where,
            )  # fmt: skip
    print(spectrum_line(psd, source))
    print("\n".join(_lines(law, time.perf_counter() - t0)))
    law.save(args.out)
    print(f"wrote {args.out}")
    for w in caught:
        if issubclass(w.category, fl.CalibrationWarning):
            warn(str(w.message))
    return 1 if any(issubclass(w.category, fl.CalibrationWarning) for w in caught) else 0


def _lines(law: fl.CalibratedLaw, seconds: float) -> list[str]:
    """The calibration's grid, cost, points and check, as printed."""
    st = law.settings
    g, sv = st["grid"], st["solves"]
    out = [
        f"grid             {g['nx']} x {g['ny']} cells of {g['dx']:.4g} m "
        f"({g['cells_per_wavelength']:.3g} per 2 pi/q1, {g['periods']:.3g} longest wavelengths)",
        f"ensemble         {st['realizations']} surfaces x {law.points.p.size} pressures: "
        f"{sv['solves']} solves, {sv['iterations']} CCG iterations, "
        f"{'converged' if sv['converged'] else str(sv['unconverged']) + ' NOT converged'}; "
        f"{seconds:.1f} s",
        f"{'p [Pa]':>12}{'u [m]':>12}{'+-':>10}{'A/A0':>9}{'g_x [m]':>12}{'g_y [m]':>12}"
        f"{'u/u_P':>8}",
    ]
    pt = law.points
    u_p = law.theory.separation(pt.p)
    for i in range(pt.p.size):
        out.append(
            f"{pt.p[i]:>12.4g}{pt.u[i]:>12.4g}{pt.u_error[i]:>10.2g}"
            f"{pt.contact_fraction[i]:>9.4f}{pt.gap_x[i]:>12.4g}{pt.gap_y[i]:>12.4g}"
            f"{pt.u[i] / u_p[i]:>8.3f}"
        )
    chk = st.get("check")
    if chk is not None:
        du = ", ".join(f"{100 * d:+.1f}" for d in chk["u_change"])
        dg = ", ".join(f"{100 * d:+.1f}" for d in chk["gap_x_change"])
        out.append(
            f"check ({chk['kind']})   u {du} %, g_x {dg} % at p = "
            + ", ".join(f"{p:.3g}" for p in chk["p"])
            + f" Pa: {'passed' if chk['passed'] else 'NOT passed'}"
        )
    return out
