"""Iterations and times of the BEM contact solver over the grid, the warm-started load sequence
and the Reynolds flow solve: ``python -m bench.bem_scaling``.

One surface refined: a periodic square of side L = 1 mm, self-affine (H 0.8, h_rms 1 um,
q0 = qr = 4 (2 pi/L), q1 = 64 (2 pi/L)), E* = 10 MPa, on N = 256, 512, 1024 cells per side
(4, 8 and 16 cells per shortest wavelength). The nominal pressures give A/A0 = 0.02 ... 0.3 at
N = 256 (found once, by secant steps); the same pressures are used on every grid. tol 1e-8.
Times are CPU seconds of the process (``time.process_time``), best of ``--repeat``.

Options: ``--sizes 256 512 1024``, ``--ccg`` (also Polonsky & Keer's plain iterations),
``--variants`` (the preconditioner's restart choice at 256 and 512), ``--sequence N`` (15
warm-started pressures against cold solves), ``--warm-steps`` (a warm start's iterations
against the load step), ``--start-accuracy`` (the iterations against the start's distance
from the answer: what a warm-started sequence within a given multiple of a cold solve needs),
``--flow``, ``--save FILE`` (the problem as .npz for an external solver).
"""

from __future__ import annotations

import argparse
import math
import sys
import time

import numpy as np

import fastline as fl
from fastline import bem

L = 1e-3  # m
E_STAR = 1e7  # Pa
TOL = 1e-8
FRACTIONS = (0.02, 0.05, 0.1, 0.2, 0.3)
Q_L = 2.0 * math.pi / L
PSD = fl.SelfAffinePSD(1e-6, 0.8, 4.0 * Q_L, 4.0 * Q_L, 64.0 * Q_L)


def problem(n: int, seed: int = 1) -> tuple[bem.Grid, np.ndarray]:
    """The grid and undeformed gap ``-heights`` [m] of the test surface on ``n^2`` cells."""
    grid = bem.Grid(n, n, L / n, L / n)
    return grid, -bem.random_surface(PSD, grid, seed=seed).heights


def pressures_for(fractions, n: int = 256) -> list[float]:
    """Nominal pressures [Pa] giving the contact fractions on ``n^2`` cells (secant in log)."""
    grid, g0 = problem(n)
    area = grid.lx * grid.ly
    out = []
    for af in fractions:
        x0, f0 = 0.0, None
        x1 = math.log(af * E_STAR * 0.5)
        for _ in range(8):
            got = bem.solve_contact(g0, grid, E_STAR, math.exp(x1) * area, tol=1e-6)
            f1 = math.log(got.contact_fraction) - math.log(af)
            if abs(f1) < 0.005:
                break
            if f0 is None:
                x0, f0, x1 = x1, f1, x1 - f1 / 1.1
            else:
                x0, f0, x1 = x1, f1, x1 - f1 * (x1 - x0) / (f1 - f0)
        out.append(math.exp(x1))
    return out


def timed(repeat: int, *args, **kwargs):
    """Best CPU time of ``repeat`` calls of ``bem.solve_contact(*args, **kwargs)`` and a result."""
    best, res = math.inf, None
    for _ in range(repeat):
        t0 = time.process_time()
        res = bem.solve_contact(*args, **kwargs)
        best = min(best, time.process_time() - t0)
    return best, res


def scaling(sizes, pressures, repeat, ccg):
    print("\n## Iterations over the grid (cold solves, tol 1e-8)\n")
    head = "| N | A/A0 | pcg: iterations per level | full-grid equivalent | convolutions | CPU s |"
    if ccg:
        head += " ccg iterations | ccg CPU s | ratio |"
    print(head)
    print("|" + "---|" * (head.count("|") - 1))
    for n in sizes:
        grid, g0 = problem(n)
        area = grid.lx * grid.ly
        bem.solve_contact(g0, grid, E_STAR, pressures[0] * area, tol=1e-4)  # tables, compiling
        for P in pressures:
            t, r = timed(repeat, g0, grid, E_STAR, P * area, tol=TOL)
            k = len(r.stage_iterations) - 1
            equiv = sum(it / 4.0 ** (k - j) for j, it in enumerate(r.stage_iterations))
            row = (
                f"| {n} | {r.contact_fraction:.3f} | {'/'.join(map(str, r.stage_iterations))}"
                f" | {equiv:.1f} | {r.convolutions} | {t:.2f} |"
            )
            assert r.converged, r.message
            if ccg:
                tc, rc = timed(1, g0, grid, E_STAR, P * area, tol=TOL, method="ccg")
                dp = np.abs(rc.pressure - r.pressure).max() / r.pressure.max()
                row += f" {rc.iterations} | {tc:.2f} | {tc / t:.1f} (dp {dp:.0e}) |"
            print(row, flush=True)


def variants(pressures):
    """Full-grid iterations of the preconditioned solver without nested iteration, by its rule
    for restarting the conjugate directions (``fastline.bem._pcg.RESTARTS``)."""
    from fastline.bem._pcg import RESTARTS, pcg_solve

    print("\n## Conjugacy restarts (no nested iteration, uniform start, tol 1e-8)\n")
    print("| N | A/A0 | " + " | ".join(RESTARTS) + " |")
    print("|" + "---|" * (2 + len(RESTARTS)))
    for n in (256, 512):
        grid, g0 = problem(n)
        op = bem.ElasticHalfSpace(n, n, grid.dx, grid.dy, E_STAR)
        for P in (pressures[0], pressures[-1]):
            its = []
            for rule in RESTARTS:
                p = np.full(n * n, P)
                its.append(pcg_solve(op, g0.ravel(), P * n * n, TOL, 5000, p, restart=rule)[0])
            frac = np.mean(p > 0)
            print(f"| {n} | {frac:.3f} | " + " | ".join(map(str, its)) + " |", flush=True)


def equivalent(res) -> float:
    """Full-grid-equivalent iterations: a level of ``N/2^k`` cells per side weighs ``4^-k``."""
    k = len(res.stage_iterations) - 1
    return sum(it / 4.0 ** (k - j) for j, it in enumerate(res.stage_iterations))


def sequence(n, pressures, steps=15):
    """15 increasing pressures from the lowest to the highest fraction, warm-started."""
    grid, g0 = problem(n)
    area = grid.lx * grid.ly
    loads = np.geomspace(pressures[0], pressures[-1], steps) * area
    bem.solve_contact(g0, grid, E_STAR, loads[0], tol=1e-4)
    t_cold, cold = timed(1, g0, grid, E_STAR, loads[-1], tol=TOL)
    t0 = time.process_time()
    p, warm = None, []
    for W in loads:
        r = bem.solve_contact(g0, grid, E_STAR, W, tol=TOL, p_init=p)
        assert r.converged, r.message
        p = r.pressure
        warm.append(r)
    t_seq = time.process_time() - t0
    worst = np.abs(p - cold.pressure).max() / cold.pressure.max()
    t1 = time.process_time()
    colds = [bem.solve_contact(g0, grid, E_STAR, W, tol=TOL) for W in loads]
    t_cold_seq = time.process_time() - t1
    top, eq = cold.contact_fraction, equivalent(cold)
    print(f"\n## Warm-started sequence, N = {n}, {steps} pressures, A/A0 up to {top:.3f}\n")
    print(
        f"- one cold solve at the highest pressure: {t_cold:.2f} s, iterations per level "
        f"{'/'.join(map(str, cold.stage_iterations))} ({eq:.1f} full-grid equivalent, "
        f"{cold.convolutions} convolutions on all levels)"
    )
    for name, rs, t in (("the warm sequence", warm, t_seq), ("the same, cold", colds, t_cold_seq)):
        e, c = sum(map(equivalent, rs)), sum(r.convolutions for r in rs)
        print(
            f"- {name}: {t:.2f} s = {t / t_cold:.1f}x; {e:.0f} full-grid equivalent "
            f"iterations = {e / eq:.1f}x ({c} convolutions on all levels); "
            f"full-grid iterations {[r.iterations for r in rs]}"
        )
    print(f"- last warm against cold pressure: max |dp| / max p = {worst:.1e}")
    exact = bem.solve_contact(g0, grid, E_STAR, loads[-1], tol=1e-13).pressure
    off = [np.abs(q - exact).max() / exact.max() for q in (p, cold.pressure)]
    print(f"- against a solve to tol 1e-13: warm {off[0]:.1e}, cold {off[1]:.1e} of max p")


def warm_steps(n=256, ratios=(1.001, 1.01, 1.05, 1.1, 1.24, 1.5)):
    """Full-grid iterations of a solve at A/A0 ~ 0.2 started from the exact solution at a
    load ``ratio`` times lower (rescaled; no nested iteration), against the cold solve; and
    where the error is after 10 iterations (its share of power above a quarter of Nyquist)."""
    grid, g0 = problem(n)
    W = pressures_for([0.2], n)[0] * grid.lx * grid.ly
    cold = bem.solve_contact(g0, grid, E_STAR, W, tol=TOL)
    exact = bem.solve_contact(g0, grid, E_STAR, W, tol=1e-12).pressure
    q = np.hypot(*np.meshgrid(np.fft.fftfreq(n), np.fft.fftfreq(n), indexing="ij"))
    print(f"\n## Warm start against load step, N = {n}, A/A0 {cold.contact_fraction:.3f}\n")
    print(f"cold (nested): iterations per level {cold.stage_iterations}, {equivalent(cold):.1f}")
    print(
        "\n| load ratio | cells changing contact | start's error (L1) | full-grid iterations"
        " | error after 10 (L1) | its power above Nyquist/4 |"
    )
    print("|---|---|---|---|---|---|")
    for ratio in ratios:
        start = bem.solve_contact(g0, grid, E_STAR, W / ratio, tol=1e-12).pressure
        r = bem.solve_contact(g0, grid, E_STAR, W, tol=TOL, p_init=start, nested=False)
        ten = bem.solve_contact(g0, grid, E_STAR, W, p_init=start, nested=False, max_iter=10)
        e = ten.pressure - exact
        power = np.abs(np.fft.fft2(e)) ** 2
        high = power[q > 0.125].sum() / power.sum()
        changed = int(np.sum((start > 0) != (exact > 0)))
        err = np.abs(start * ratio - exact).sum() / exact.sum()
        print(
            f"| {ratio} | {changed} | {err:.1e} | {r.iterations} | "
            f"{np.abs(e).sum() / exact.sum():.1e} | {high:.2f} |",
            flush=True,
        )


def start_accuracy(n=256, ratio=1.24, shares=(1.0, 1e-1, 1e-2, 1e-3, 1e-4, 1e-5, 1e-6)):
    """Full-grid iterations at A/A0 ~ 0.2 from starts at a chosen distance from the answer:
    ``exact + share (previous - exact)``, ``previous`` the exact solution at a load ``ratio``
    lower, rescaled (the warm start of one step of the sequence), clipped at 0; against the
    budget per step of a sequence of 15 pressures within 3 cold solves (the first solved cold
    at the lowest pressure, the other 14 warm-started)."""
    grid, g0 = problem(n)
    W = pressures_for([0.2], n)[0] * grid.lx * grid.ly
    cold = bem.solve_contact(g0, grid, E_STAR, W, tol=TOL)
    lowest = pressures_for([0.02], n)[0] * grid.lx * grid.ly
    first = equivalent(bem.solve_contact(g0, grid, E_STAR, lowest, tol=TOL))
    budget = (3.0 * equivalent(cold) - first) / 14.0
    exact = bem.solve_contact(g0, grid, E_STAR, W, tol=1e-12).pressure
    previous = bem.solve_contact(g0, grid, E_STAR, W / ratio, tol=1e-12).pressure * ratio
    print(
        f"\n## Iterations against the start's accuracy, N = {n}, A/A0 {cold.contact_fraction:.3f}\n"
    )
    print(
        f"cold (nested): {equivalent(cold):.1f} full-grid equivalent; a sequence of 15 within 3 "
        f"cold solves leaves {budget:.1f} per warm step (the lowest pressure cold: {first:.1f})"
    )
    print(
        "\n| start: share of a 24 % step's error | start's error (L1, relative) "
        "| full-grid iterations |"
    )
    print("|---|---|---|")
    for share in shares:
        start = np.maximum(exact + share * (previous - exact), 0.0)
        r = bem.solve_contact(g0, grid, E_STAR, W, tol=TOL, p_init=start, nested=False)
        err = np.abs(start - exact).sum() / exact.sum()
        print(f"| {share:g} | {err:.1e} | {r.iterations} |", flush=True)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--sizes", type=int, nargs="+", default=[256, 512, 1024])
    ap.add_argument("--repeat", type=int, default=1)
    ap.add_argument("--ccg", action="store_true")
    ap.add_argument("--variants", action="store_true")
    ap.add_argument("--warm-steps", action="store_true")
    ap.add_argument("--start-accuracy", action="store_true")
    ap.add_argument("--sequence", type=int, default=0, metavar="N")
    ap.add_argument("--flow", type=int, nargs="*", default=None, metavar="N")
    ap.add_argument("--save", type=int, nargs=2, default=None, metavar=("N", "FRACTION_INDEX"))
    ap.add_argument("--skip-scaling", action="store_true")
    args = ap.parse_args(argv)
    pressures = pressures_for(FRACTIONS)
    print("nominal pressures [Pa]:", ", ".join(f"{P:.4g}" for P in pressures))
    if args.save:
        n, k = args.save
        grid, g0 = problem(n)
        np.savez(f"/tmp/bem_problem_{n}_{k}.npz", g0=g0, L=L, E_star=E_STAR, pressure=pressures[k])
        print(f"saved /tmp/bem_problem_{n}_{k}.npz")
        return 0
    if not args.skip_scaling:
        scaling(args.sizes, pressures, args.repeat, args.ccg)
    if args.variants:
        variants(pressures)
    if args.warm_steps:
        warm_steps()
    if args.start_accuracy:
        start_accuracy()
    if args.sequence:
        sequence(args.sequence, pressures)
    if args.flow is not None:
        from bench.bem_flow import flow_table

        flow_table(args.flow or [512, 1024])
    return 0


if __name__ == "__main__":
    sys.exit(main())
