"""How a calibration's quantities move with the grid's resolution, on more surfaces than its
check: ``python -m bench.calibration_resolution [--surfaces 6] [--pressures 1.33e5 3e5]``.

The narrow-band spectrum of docs/calibration.md (H 0.8, h_rms 0.5 um, q1/q0 = 32, E* 10 MPa),
the same cell (4 longest wavelengths a side) at 4 and 8 cells per shortest wavelength 2 pi/q1
(512^2 and 1024^2 cells), ``--surfaces`` random surfaces each, cold contact solves at each
pressure and the flow along x and y (``conductance_tol`` as a calibration sets it). Prints per
surface the mean gap, the effective gaps and the contact fraction, then per pressure the change
of each ensemble mean from 4 to 8 cells and its size in combined standard errors.
"""

from __future__ import annotations

import argparse
import math

import numpy as np

import fastline as fl
from fastline import bem
from fastline.bem.flow import CONDUCTANCE_TOL

NAMES = ("u", "g_x", "g_y", "A/A0")


def _surface(psd, grid, seed: int, pressures) -> list[float]:
    """(u, g_x, g_y, A/A0) at each pressure, flattened."""
    h = bem.random_surface(psd, grid, seed).heights
    row: list[float] = []
    for p in pressures:
        r = bem.solve_contact(-h, grid, 10e6, p * grid.lx * grid.ly)
        fx = bem.reynolds_flow(r.gap, grid.dx, grid.dy, conductance_tol=CONDUCTANCE_TOL)
        fy = bem.reynolds_flow(r.gap.T, grid.dy, grid.dx, conductance_tol=CONDUCTANCE_TOL)
        row += [r.gap.mean(), fx.effective_gap, fy.effective_gap, r.contact_fraction]
    return row


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--surfaces", type=int, default=6)
    ap.add_argument("--pressures", type=float, nargs="+", default=[1.33e5, 3e5])
    args = ap.parse_args()
    q0 = 157079.63
    psd = fl.SelfAffinePSD(0.5e-6, 0.8, q0, q0, 5026548.2)
    runs = {}
    for ppw in (4, 8):
        grid = bem.spectral_grid(psd, points_per_wavelength=ppw, periods=4)
        rows = []
        for seed in range(args.surfaces):
            rows.append(_surface(psd, grid, seed, args.pressures))
            print(f"{ppw} cells, surface {seed}: " + " ".join(f"{v:.4g}" for v in rows[-1]))
        runs[ppw] = np.array(rows)
    n = args.surfaces
    for k in range(runs[4].shape[1]):
        a, b = runs[4][:, k], runs[8][:, k]
        se = math.sqrt(a.var(ddof=1) / n + b.var(ddof=1) / n)
        p = args.pressures[k // len(NAMES)]
        print(f"p {p:.3g} Pa {NAMES[k % len(NAMES)]:>5}: 4 cells {a.mean():.4g}, 8 cells "
              f"{b.mean():.4g}, change {b.mean() / a.mean() - 1:+.1%} "
              f"({(b.mean() - a.mean()) / se:+.1f} combined standard errors)")  # fmt: skip


if __name__ == "__main__":
    main()
