"""The calibrated law on the narrow-band scene of docs/validation.md ("A calibrated law on the
paper-like scene"): calibrate once, then the cylinder BEM ensemble against every law.

    python -m bench.calibrated_validation calibrate --out law.npz [--realizations 8]
    python -m bench.calibrated_validation profiles --law law.npz --alphas 0.1 1 10 \
        [--realizations 4]

``calibrate``: :func:`fastline.calibrate` of the spectrum (H 0.8, h_rms 0.5 um, q0 = 2 pi/40 um,
q1/q0 = 32; E* 10 MPa) over the pressures of the cylinder (R 32.8 mm) at alpha 0.1-10
(``radius=``, ``loads=``: 15 pressures), 4 x 4 longest wavelengths, 4 cells per shortest
(512 x 512), with its default convergence check; prints the wall time, the solves and the
check. ``profiles``: :func:`fastline.reports.validation.validate_line_contact` with ``law=``
at each alpha (the page's grid: 2 longest wavelengths along the axis, 4 cells per 2 pi/q1),
every theory variant and GW beside the law; prints each table and a Markdown summary.
The machine's load is printed with the times (they are noisy on a shared machine).
"""

from __future__ import annotations

import argparse
import json
import math
import os
import time

import numpy as np

import fastline as fl
from fastline.reports import validation

Q0 = 2 * math.pi / 40e-6
PSD = fl.SelfAffinePSD(0.5e-6, 0.8, Q0, Q0, 32 * Q0)
E_STAR, RADIUS = 10e6, 32.8e-3
ALPHAS = (0.1, 0.3, 1.0, 3.0, 10.0)


def load_of(alpha: float) -> float:
    """Load per length [N/m] of alpha = h_rms / delta, delta = 4 f / (pi E*)."""
    return math.pi * E_STAR * PSD.h_rms / (4.0 * alpha)


def cmd_calibrate(args) -> None:
    loads = [load_of(a) for a in (min(ALPHAS), max(ALPHAS))]
    print(f"load average {os.getloadavg()}", flush=True)
    t0 = time.perf_counter()
    law = fl.calibrate(
        PSD, E_STAR, radius=RADIUS, loads=loads, n_pressures=args.pressures,
        realizations=args.realizations, workers=args.workers,
        check=None if args.check == "none" else args.check,
        progress=lambda done, total: print(f"  surface {done}/{total} "
                                           f"{time.perf_counter() - t0:.0f} s", flush=True),
    )  # fmt: skip
    seconds = time.perf_counter() - t0
    law.save(args.out)
    print(f"calibration {seconds:.1f} s on {args.workers} processes; load average "
          f"{os.getloadavg()}")  # fmt: skip
    print(law)
    print(json.dumps(law.settings, indent=1, default=str))


def cmd_profiles(args) -> None:
    law = fl.CalibratedLaw.load(args.law, psd=PSD, E_star=E_STAR)
    models = (*fl.theory.VARIANTS, "greenwood-williamson")
    rows = []
    for a in args.alphas:
        t0 = time.perf_counter()
        v = validation.validate_line_contact(
            PSD, E_STAR, RADIUS, load_of(a), models=models, law=law,
            realizations=args.realizations, seed=args.seed, workers=args.workers,
            periods=args.periods,
        )  # fmt: skip
        print(f"alpha {a:g}: {time.perf_counter() - t0:.1f} s (BEM {v.seconds_bem:.1f} s), "
              f"grid {v.ensemble.scene.grid.nx} x {v.ensemble.scene.grid.ny}, load average "
              f"{os.getloadavg()}")  # fmt: skip
        print(v.table())
        rows.append(_summary(a, v))
    print("\n| alpha | law | p0 | s | w/s |\n|---|---|---|---|---|")
    print("\n".join(rows))


def _cell(d) -> str:
    return f"{100 * d.relative:+.1f}% (z {d.z:+.1f})"


def _summary(alpha, v) -> str:
    out = []
    for name, c in v.comparisons.items():
        out.append(f"| {alpha:g} | {name} | {_cell(c.p0)} | {_cell(c.s)} | {_cell(c.w_over_s)} |")
    return "\n".join(out)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    sub = ap.add_subparsers(dest="cmd", required=True)
    c = sub.add_parser("calibrate")
    c.add_argument("--out", required=True)
    c.add_argument("--realizations", type=int, default=4)
    c.add_argument("--workers", type=int, default=2)
    c.add_argument("--check", default="finer", choices=("finer", "larger", "none"))
    c.add_argument("--pressures", type=int, default=15)
    p = sub.add_parser("profiles")
    p.add_argument("--law", required=True)
    p.add_argument("--alphas", type=float, nargs="+", default=list(ALPHAS))
    p.add_argument("--realizations", type=int, default=4)
    p.add_argument("--seed", type=int, default=0)
    p.add_argument("--workers", type=int, default=2)
    p.add_argument("--periods", type=float, default=2.0)
    args = ap.parse_args()
    {"calibrate": cmd_calibrate, "profiles": cmd_profiles}[args.cmd](args)
    np.seterr(all="warn")


if __name__ == "__main__":
    main()
