"""The Reynolds flow solve of a contact's gap field, multigrid-preconditioned CG against sparse
LU: ``python -m bench.bem_scaling --skip-scaling --flow 512 1024``.

The gap of the surface of :mod:`bench.bem_scaling` at A/A0 = 0.1 (the third nominal pressure),
solved by :func:`fastline.bem.reynolds_flow` with ``solver="amg"`` and ``solver="direct"``;
CPU seconds (``time.process_time``), the CG iterations and the conductances' relative
difference.
"""

from __future__ import annotations

import time

from bench.bem_scaling import E_STAR, FRACTIONS, pressures_for, problem
from fastline import bem


def flow_table(sizes, fraction_index: int = 2) -> None:
    pressure = pressures_for(FRACTIONS[fraction_index : fraction_index + 1])[0]
    print("\n## Reynolds flow through the gap\n")
    print("| N | A/A0 | unknowns | amg: CG iterations | amg s | direct s | ratio | rel. diff |")
    print("|---|---|---|---|---|---|---|---|")
    for n in sizes:
        grid, g0 = problem(n)
        gap = bem.solve_contact(g0, grid, E_STAR, pressure * grid.lx * grid.ly, tol=1e-8).gap
        bem.reynolds_flow(gap[:64, :64], grid.dx, solver="amg")  # imports outside the timing
        t0 = time.process_time()
        amg = bem.reynolds_flow(gap, grid.dx, solver="amg")
        t1 = time.process_time()
        direct = bem.reynolds_flow(gap, grid.dx, solver="direct")
        t2 = time.process_time()
        diff = abs(amg.conductance / direct.conductance - 1.0)
        print(
            f"| {n} | {(gap == 0).mean():.3f} | {round(amg.active_fraction * n * n)} | "
            f"{amg.iterations} | {t1 - t0:.2f} | {t2 - t1:.2f} | {(t2 - t1) / (t1 - t0):.2f} | "
            f"{diff:.1e} |",
            flush=True,
        )
