"""The coupled seal's Newton: the compiled reduced system against NumPy's dense solve.

``python -m bench.seal [n ...]`` (default n = 256 512 2048): for the O-ring of docs/leakage.md
(300 N/m, line contact) and the ball on a seat (0.2 N, hole 20 um, point contact) on n cells,

1. one Newton step at the state of the first continuation step (dP = 1e5), both solvers
   (best of ``REPEAT`` interleaved calls, the matrix assembly included);
2. a sweep over ``DROPS`` with each solver: wall time, Newton steps, continuation steps, and
   the largest relative difference of Q between the two.

Counts are exact on any machine; times depend on its load (the ratio of the two solvers in one
run is the figure). NumPy's dense solve runs on as many BLAS threads as OpenBLAS starts.
"""

from __future__ import annotations

import sys
import time

import numpy as np

import fastline as fl
from fastline.leakage import seal, seal_kernels, seal_system

E_STAR = fl.effective_modulus(10e6, 0.5, 210e9, 0.3)
PSD = fl.SelfAffinePSD(0.3e-6, 0.85, q0=5e4, qr=5e5, q1=1e9)
DROPS = [1e4, 1e5, 3e5]
REPEAT = 3


def _scene(geometry: str, n: int, theory):
    if geometry == "line":
        r = fl.solve_line_contact(PSD, E_STAR, 1.5e-3, 300.0, n=n, theory=theory, warn=False)
        return r, {"length": 0.0785}
    r = fl.solve_point_contact(PSD, E_STAR, 10e-3, 0.2, n=n, theory=theory, warn=False)
    return r, {"inner_radius": 20e-6}


def _step_times(result, kw, theory) -> tuple[float, float]:
    """Best-of-REPEAT wall seconds of one Newton step: (compiled reduced, dense NumPy)."""
    leak = fl.leak_rate(result, 1e5, 1e-3, kw.get("length"), inner_radius=kw.get("inner_radius"),
                        theory=theory, warn=False)  # fmt: skip
    sys_ = seal._system(result, leak, theory, None, False, "edge")
    y, r0 = seal_system.start(sys_, 1e5)
    vals = seal_system.inverse_cube(sys_, y[: sys_.n])
    F = seal_system.residual(sys_, y, 1e5, r0, vals)
    best = [np.inf, np.inf]
    for _ in range(REPEAT):
        t = time.perf_counter()
        seal_kernels.reduced_step(sys_, y, vals, F, 1e5, r0)
        best[0] = min(best[0], time.perf_counter() - t)
        t = time.perf_counter()
        _, J = seal_system.equations(sys_, y, 1e5, r0, jac=True)
        np.linalg.solve(J, -F)
        best[1] = min(best[1], time.perf_counter() - t)
    return best[0], best[1]


def _sweeps(result, kw, theory) -> dict:
    """Per solver: (wall seconds, CPU seconds of the process, the sweep)."""
    out = {}
    for solver in ("compiled", "dense"):
        t, c = time.perf_counter(), time.process_time()
        s = fl.seal_leak(result, DROPS, 1e-3, theory=theory, solver=solver, **kw)
        out[solver] = (time.perf_counter() - t, time.process_time() - c, s)
    return out


def main(ns: list[int]) -> None:
    theory = fl.PerssonTheory(PSD, E_STAR)
    warm, kw = _scene("point", 32, theory)  # compile the kernels outside the timings
    fl.seal_leak(warm, [1e4], 1e-3, theory=theory, **kw)
    print("seconds: wall (CPU of the process); c/d: compiled / dense")
    print(f"{'scene':>6}{'n':>6}{'step c':>9}{'step d':>9}{'d/c':>6}{'sweep c':>16}"
          f"{'sweep d':>16}{'d/c':>13}{'Newton c/d':>12}{'max dQ/Q':>10}")  # fmt: skip
    for n in ns:
        for geometry in ("line", "point"):
            result, kw = _scene(geometry, n, theory)
            sc, sd = _step_times(result, kw, theory)
            runs = _sweeps(result, kw, theory)
            (tc, cc, c), (td, cd, d) = runs["compiled"], runs["dense"]
            dq = float(np.max(np.abs(c.Q / d.Q - 1.0)))
            steps = f"{c.diagnostics['newton_steps']}/{d.diagnostics['newton_steps']}"
            sweeps = f"{tc:>8.3g} ({cc:.3g}) {td:>7.3g} ({cd:.3g}) {td / tc:>5.2f} ({cd / cc:.2f})"
            print(f"{geometry:>6}{n:>6}{sc:>9.3g}{sd:>9.3g}{sd / sc:>6.1f} {sweeps}{steps:>12}"
                  f"{dq:>10.2g}", flush=True)  # fmt: skip


if __name__ == "__main__":
    main([int(a) for a in sys.argv[1:]] or [256, 512, 2048])
