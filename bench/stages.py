"""Where a warm line-contact solve spends its compiled time: ``python -m bench.stages``.

Records the Newton kernel's arguments during one solve (surface 1, the given n and alpha) and
times, on this machine, in the same run (CPU time of this thread, best of several calls):

* the whole solve and the compiled Newton kernel alone, and the FFT convolutions it made
  times one convolution at that n (the FFT floor of the solve);
* one evaluation of the pressure law with ``p = exp(v)`` over the grid (each Newton step and
  line-search trial needs one);
* one Newton system (:func:`fastline.elastic.pcg.solve_newton_system`) on the converged
  iterate's diagonal D with a random right-hand side, stopped after 0, 4 and 8 CG iterations,
  with the solver's coarse level and without it (``nc = 0``): the set-up (0 iterations:
  smoother, coarse level, the projection's direction ``B~ 1`` and the first preconditioner
  application) and the cost of
  one CG iteration (the slope), each beside its FFT convolutions.

Options: ``--n 512 4096``, ``--alpha 1e-2 1``.
"""

from __future__ import annotations

import argparse
import math

import numba
import numpy as np

import fastline as fl
from bench.core import HARD, convolution_time, cpu_best
from fastline._lib import fftw as _fftw
from fastline.contact import line_newton
from fastline.contact.line_newton import _law
from fastline.elastic.pcg import CGSettings, solve_newton_system
from fastline.elastic.pcg import workspace_size as system_workspace
from fastline.reports.paper import E_STAR, RADIUS, load_for_alpha

CG_STEPS = (0, 4, 8)


def recorded_solve(n: int, alpha: float):
    """(the model, its load, the Newton kernel's arguments of a solve, its start ln p)."""
    captured = {}
    kernel = line_newton.newton_line

    def recording(*args):
        captured["args"], captured["v0"] = list(args), args[5].copy()
        return kernel(*args)

    line_newton.newton_line = recording
    try:
        lc = fl.LineContact(HARD["surface 1"], E_STAR, RADIUS, n=n, warn=False)
        load = load_for_alpha(alpha)
        lc.solve(load)
    finally:
        line_newton.newton_line = kernel
    return lc, load, captured["args"], captured["v0"]


@numba.njit
def _law_loop(kind, v, prm, A, B, C, E, u, dudv, reps):
    s = 0.0
    for _ in range(reps):
        _law(kind, v, prm, A, B, C, E, u, dudv)
        for i in range(v.shape[0]):
            s += math.exp(v[i])
    return s


def measure(n: int, alpha: float) -> dict:
    """The figures of the module docstring for one scene (times in s)."""
    lc, load, args, v0 = recorded_solve(n, alpha)
    kernel = line_newton.newton_line

    def run_kernel():
        args[5][:] = v0
        return kernel(*args)

    out = run_kernel()
    m = dict(
        solve=cpu_best(lambda: lc.solve(load), 9),
        kernel=cpu_best(run_kernel, 9),
        conv=convolution_time(n),
        steps=out[3],
        cg=out[4],
        convolutions=out[5] + out[6],
    )
    kind, prm, A, B, C, E = args[4].form
    v = args[5].copy()
    u, dudv = np.empty(n), np.empty(n)
    reps = max(10, int(1e5 / n))
    _law_loop(kind, v, prm, A, B, C, E, u, dudv, 1)
    m["law"] = cpu_best(lambda: _law_loop(kind, v, prm, A, B, C, E, u, dudv, reps), 5) / reps
    p = np.exp(v)
    D = np.minimum(np.maximum(-dudv, 1e-300 * args[4].u_ref) / np.maximum(p, 1e-300), 1e300)
    tables = args[1]
    rhs = np.random.default_rng(1).standard_normal(n) * 1e-9
    dp, ws = np.empty(n), np.empty(system_workspace(n))
    fft = _fftw.acquire(2 * n)
    try:
        for nc in (args[6].nc, 0):
            for its in CG_STEPS:
                settings = CGSettings(1e-14, its, nc)
                sys_args = (fft, tables, args[2], D, args[3].w, rhs, settings, dp, ws)
                done = solve_newton_system(*sys_args)
                t = cpu_best(lambda a=sys_args: solve_newton_system(*a), 9)
                m[("system", nc, its)] = (t, done[1], done[2] + done[3])
    finally:
        _fftw.release(2 * n)
    m["nc"] = args[6].nc
    return m


def report(n: int, alpha: float) -> None:
    m = measure(n, alpha)
    us, conv = 1e6, m["conv"]
    floor = m["convolutions"] * conv
    print(
        f"n = {n}, alpha = {alpha:g}: solve {m['solve'] * us:.0f} us, Newton kernel "
        f"{m['kernel'] * us:.0f} us; {m['steps']} Newton steps, {m['cg']} CG iterations, "
        f"{m['convolutions']} convolutions x {conv * us:.2f} us = {floor * us:.0f} us "
        f"({floor / m['solve']:.0%} of the solve)"
    )
    print(f"  law + exp over the grid: {m['law'] * us:.2f} us ({m['law'] / n * 1e9:.1f} ns/cell)")
    for nc in (m["nc"], 0):
        t0, _, c0 = m[("system", nc, 0)]
        t8, its8, c8 = m[("system", nc, CG_STEPS[-1])]
        t4, its4, c4 = m[("system", nc, CG_STEPS[1])]
        per_it = (t8 - t4) / max(its8 - its4, 1)
        conv_it = (c8 - c4) / max(its8 - its4, 1)
        label = f"{nc} aggregates" if nc else "no coarse level"
        print(
            f"  Newton system, {label}: set-up {t0 * us:.1f} us ({c0} convolutions, "
            f"{c0 * conv / t0:.0%} FFT); one CG iteration {per_it * us:.1f} us "
            f"({conv_it:.0f} convolutions, {conv_it * conv / per_it:.0%} FFT)"
        )


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--n", type=int, nargs="+", default=[512, 4096])
    ap.add_argument("--alpha", type=float, nargs="+", default=[1e-2, 1.0])
    a = ap.parse_args()
    for n in a.n:
        for alpha in a.alpha:
            report(n, alpha)


if __name__ == "__main__":
    main()
