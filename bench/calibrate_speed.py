"""Cost of a calibration (docs/calibration.md, "Cost"): one surface of the narrow-band
validation spectrum carried through the pressures as :func:`fastline.calibrate` carries it, the
contact solve and the two flow solves (:func:`fastline.bem.reynolds_flow`, ``solver="auto"``,
each started from the last pressure's result and stopped on the conductance's error as the
calibration stops them) timed apart, with the iterations of each and the
solver that gave the answer (``i``: conjugate gradients, ``d``: direct); for the ratios, cold
contact solves at three of the pressures and ``solver="direct"`` (x only) at the middle one.

    python -m bench.calibrate_speed [--periods 4] [--pressures 15] [--no-flow]

Prints one line per pressure and a summary: iterations, seconds of contact and flow, and the
projected wall time of 8 surfaces on 2 processes (twice one surface's time per process pair).
"""

from __future__ import annotations

import argparse
import math
import time

import numpy as np

import fastline as fl
from fastline.bem import random_surface, reynolds_flow, solve_contact, spectral_grid
from fastline.bem.flow import CONDUCTANCE_TOL as CTOL


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--periods", type=float, default=4.0)
    ap.add_argument("--pressures", type=int, default=15)
    ap.add_argument("--no-flow", action="store_true")
    args = ap.parse_args()
    q0 = 2 * math.pi / 40e-6
    psd = fl.SelfAffinePSD(0.5e-6, 0.8, q0, q0, 32 * q0)
    g = spectral_grid(psd, periods=args.periods)
    h = random_surface(psd, g, 1).heights
    ps = np.geomspace(1e3, 3e5, args.pressures)
    solve_contact(-h, g, 10e6, ps[0] * g.lx * g.ly, max_iter=2)  # compile
    reynolds_flow(h[:64, :64] - h.min() + 1e-7, g.dx, g.dy, solver="iterative")  # compile
    warm = sx = sy = None
    t_solve, t_flow, its, flow_its, convs = 0.0, 0.0, [], [], 0
    n_direct, kinds = 0, ""
    print(f"grid {g.nx} x {g.ny}; {ps.size} pressures 1e3-3e5 Pa, E* 10 MPa")
    for i, p in enumerate(ps):
        t = time.perf_counter()
        r = solve_contact(-h, g, 10e6, p * g.lx * g.ly, p_init=warm)
        t1 = time.perf_counter()
        kx = ky = 0
        if not args.no_flow:
            sx = reynolds_flow(r.gap, g.dx, g.dy, start=sx, conductance_tol=CTOL)
            sy = reynolds_flow(r.gap.T, g.dy, g.dx, start=sy, conductance_tol=CTOL)
            kx, ky = sx.iterations, sy.iterations
            kinds = sx.solver[0] + sy.solver[0]
            n_direct += kinds.count("d")
        t2 = time.perf_counter()
        t_solve, t_flow = t_solve + t1 - t, t_flow + t2 - t1
        its.append(r.iterations)
        convs += r.convolutions
        flow_its.append(kx + ky)
        warm = r.pressure
        if i == ps.size // 2 and not args.no_flow:
            t3 = time.perf_counter()
            reynolds_flow(r.gap, g.dx, g.dy, solver="direct")
            direct = time.perf_counter() - t3
            print(f"  reynolds_flow(solver='direct') here (x only): {direct:.2f} s vs "
                  f"{(t2 - t1) / 2:.2f} s per direction in the sequence")  # fmt: skip
        print(
            f"p {p:9.3g} Pa  {r.iterations:4d} it  contact {t1 - t:6.2f} s  flow {kx:3d}+{ky:3d}"
            f" it ({kinds}) {t2 - t1:6.2f} s  A/A0 {r.contact_fraction:.3f}"
        )
    cold = []
    for p in ps[[0, ps.size // 2, -1]]:
        cold.append(solve_contact(-h, g, 10e6, p * g.lx * g.ly).iterations)
    print(
        f"one surface: {sum(its)} full-grid iterations warm ({convs} convolutions), contact "
        f"{t_solve:.1f} s, flow {sum(flow_its)} CG iterations and {n_direct} direct solves of "
        f"{2 * ps.size} {t_flow:.1f} s; cold solves at "
        f"3 pressures {cold} iterations vs "
        f"warm {[its[0], its[ps.size // 2], its[-1]]}; 8 surfaces on 2 processes ~ "
        f"{4 * (t_solve + t_flow):.0f} s"
    )


if __name__ == "__main__":
    main()
