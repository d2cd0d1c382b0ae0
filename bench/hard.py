"""Hard (hertz) contact of smooth surfaces: active set against constrained CG.

``python -m bench.hard`` prints the section of docs/performance.md that ``bench.report``
writes. Line contact, E* and R of the report, loads 1e2 / 1e4 / 1e6 N/m, tol 1e-8: FFT
convolutions and warm time per solve of :func:`fastline.contact.hard.hard_contact` (the
active set) and of :func:`fastline.contact.hard.constrained_cg` from the same Hertz start,
and each one's largest pressure error against a solve to tol 1e-13 by the active set.
"""

from __future__ import annotations

import math
import time

import numpy as np

import fastline as fl
from bench.conftest import E_STAR, RADIUS
from fastline.contact import hard as _hard_contact

NS = (256, 1024, 4096, 16384)
LOADS = (1e2, 1e4, 1e6)
TOL = 1e-8


def _run(solver, grid, start, tol):
    """(convolutions, best time in s over 3 calls, pressure) of one solver on one grid."""
    op, best = grid.disc.op, math.inf
    for _ in range(3):
        before = op.convolutions
        t = time.perf_counter()
        out = solver(grid.disc, start, grid.hertz.delta, tol, 100 * grid.x.size)
        best = min(best, time.perf_counter() - t)
    assert out.converged, out.message
    return op.convolutions - before, best, out.pressure


def measure() -> dict:
    """``{n: {"active": (conv, s, err), "cg": (conv, s, err)}}``, the worst over the loads
    (largest count, time and error; err: max |p - p_ref| / max p_ref)."""
    rows = {}
    for n in NS:
        worst = {"active": (0, 0.0, 0.0), "cg": (0, 0.0, 0.0)}
        for load in LOADS:
            model = fl.LineContact(None, E_STAR, RADIUS, model="hertz", n=n, warn=False)
            grid = model._grid(load)
            start = np.exp(model._cold_start(grid))
            ref = _hard_contact.active_set(grid.disc, start, grid.hertz.delta, 1e-13, 30).pressure
            for name, solver in (
                ("active", _hard_contact.active_set),
                ("cg", _hard_contact.constrained_cg),
            ):
                c, t, p = _run(solver, grid, start, TOL)
                err = float(np.max(np.abs(p - ref)) / np.max(ref))
                pairs = zip(worst[name], (c, t, err), strict=True)
                worst[name] = tuple(max(a, b) for a, b in pairs)
        rows[n] = worst
    return rows


def _err(e: float) -> str:
    return f"{e:.0e}" if e > 0.0 else "0 (the same iterate)"


def markdown(rows: dict) -> list[str]:
    """The report's section on hard contact."""
    lines = [
        '## Hard contact of smooth surfaces (model="hertz")\n',
        "Line contact, loads 1e2 / 1e4 / 1e6 N/m (the worst of the three), tol 1e-8, both from "
        "Hertz's profile: FFT convolutions, warm time per solve and the largest pressure error "
        "(relative to p0) against a solve to tol 1e-13. The active set "
        "(`fastline/contact/hard.py`, the default) solves the linear contact problem on a "
        "contact set with the rough contact's compiled Newton-system solver; constrained CG "
        "(Polonsky & Keer) is its fallback and the sphere's method.\n",
        "| n | active set | constrained CG | speed-up |",
        "|---|---|---|---|",
    ]
    for n, r in rows.items():
        (ca, ta, ea), (cc, tc, ec) = r["active"], r["cg"]
        lines.append(
            f"| {n} | {ca} conv, {ta * 1e3:.2f} ms, err {_err(ea)} | "
            f"{cc} conv, {tc * 1e3:.2f} ms, err {_err(ec)} | {tc / ta:.0f}x |"
        )
    lines.append("")
    return lines


if __name__ == "__main__":
    print("\n".join(markdown(measure())))
