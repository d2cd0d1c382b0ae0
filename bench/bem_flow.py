"""The Reynolds flow solve of a gap field, every option against SciPy's ``spsolve`` in one run:
``python -m bench.bem_flow [--sizes 512 1024]`` (``python -m bench.bem_scaling --flow`` runs it
too).

The gap fields: one surface of the narrow-band validation spectrum (H 0.8, h_rms 0.5 um,
2 pi/q0 = 40 um, q1/q0 = 32, E* 10 MPa; :func:`fastline.bem.spectral_grid` with 4 periods per
side: 512^2 cells, 8 periods: 1024^2) pressed by a rigid flat at 10, 130 and 450 kPa (A/A0 about
0.01, 0.1 and 0.3). For each, wall seconds (``time.perf_counter``) and CG iterations of

* ``spsolve``: SciPy's default sparse solve (SuperLU, column ordering COLAMD);
* ``mmd-sym``: ``solver="direct"`` of :func:`fastline.bem.reynolds_flow` (SuperLU, minimum
  degree on ``A + A^T``, symmetric mode); its fill ``nnz(L + U)``;
* ``nd``: SuperLU of the matrix permuted by a geometric nested dissection of the grid
  (recursive bisection by grid lines, separators last, two separators across the periodic y)
  with the natural column order and symmetric mode; its fill;
* ``iterative``: ``solver="iterative"`` (multigrid-preconditioned CG from a linear start, no
  budget);
* ``auto``: ``solver="auto"`` (the CG within its budget, else the direct solve), cold.

Each option's conductance is compared with ``spsolve``'s (largest relative difference).
Run with ``OPENBLAS_NUM_THREADS=1``.
"""

from __future__ import annotations

import argparse
import math
import time

import numpy as np
import scipy.sparse as sp
from scipy.sparse.linalg import splu, spsolve

import fastline as fl
from fastline import bem
from fastline.bem import flow as bem_flow

PRESSURES = (1e4, 1.3e5, 4.5e5)  # Pa: A/A0 about 0.01, 0.1, 0.3
E_STAR = 10e6
Q0 = 2.0 * math.pi / 40e-6
PSD = fl.SelfAffinePSD(0.5e-6, 0.8, Q0, Q0, 32.0 * Q0)


def nested_dissection(nx: int, ny: int, leaf: int = 4) -> np.ndarray:
    """Cells of an (nx, ny) grid, periodic along y, in nested-dissection order."""
    idx = np.arange(nx * ny).reshape(nx, ny)
    out: list[np.ndarray] = []

    def split(i0, i1, j0, j1):
        if (i1 - i0) * (j1 - j0) <= leaf * leaf or min(i1 - i0, j1 - j0) < 3:
            out.append(idx[i0:i1, j0:j1].ravel())
        elif i1 - i0 >= j1 - j0:
            m = (i0 + i1) // 2
            split(i0, m, j0, j1)
            split(m + 1, i1, j0, j1)
            out.append(idx[m, j0:j1])
        else:
            m = (j0 + j1) // 2
            split(i0, i1, j0, m)
            split(i0, i1, m + 1, j1)
            out.append(idx[i0:i1, m])

    h = ny // 2
    split(0, nx, 1, h)
    split(0, nx, h + 1, ny)
    out += [idx[:, h], idx[:, 0]]
    return np.concatenate(out)


def _matrix(gap, dx):
    """The direct path's sparse system on the flow path: (A, b, keep, t_out, scale)."""
    nx, ny = gap.shape
    tx, ty, t_in, t_out = bem_flow._transmissibilities(gap**3 / 12e-3, dx, dx)
    keep = bem_flow._percolating_cells(tx, ty, t_in, t_out, nx, ny)
    D, tx, ty, b, t_in, t_out, s = bem_flow._system(tx, ty, t_in, t_out, keep)
    local = np.full(nx * ny, -1)
    local[keep.ravel()] = np.arange(np.count_nonzero(keep))
    (ax, bx), (ay, by) = bem_flow._face_pairs(nx, ny)
    a = local[np.concatenate([ax.ravel(), ay.ravel()])]
    c = local[np.concatenate([bx.ravel(), by.ravel()])]
    t = np.concatenate([tx.ravel(), ty.ravel()])
    live = (t > 0.0) & (a >= 0) & (c >= 0)
    a, c, t = a[live], c[live], t[live]
    m = int(keep.sum())
    d = np.arange(m)
    rows, cols = np.concatenate([d, a, c]), np.concatenate([d, c, a])
    A = sp.csc_matrix((np.concatenate([D[keep], -t, -t]), (rows, cols)), shape=(m, m))
    return A, b[keep], keep, t_out, s


def _conductance(x, keep, t_out, nx, ny):
    full = np.zeros(keep.shape)
    full[keep] = x
    return float(np.sum(t_out * full[-1])) * nx / ny  # square cells


def _row(n, frac, active, name, seconds, its, k, k_ref, fill=None):
    fill = "" if fill is None else f"{fill / 1e6:.1f}"
    print(
        f"| {n} | {frac:.3f} | {active} | {name} | {seconds:.2f} | {its} | {fill} | "
        f"{abs(k / k_ref - 1.0):.1e} |",
        flush=True,
    )


def one_gap(gap, dx, n, frac):
    """Every option on one gap field (one table row each)."""
    A, b, keep, t_out, _ = _matrix(gap, dx)
    nx, ny = gap.shape
    t = time.perf_counter()
    k_ref = _conductance(spsolve(A, b), keep, t_out, nx, ny)
    t_ref = time.perf_counter() - t
    _row(n, frac, A.shape[0], "spsolve", t_ref, 0, k_ref, k_ref)
    t = time.perf_counter()
    direct = bem.reynolds_flow(gap, dx, viscosity=1e-3, solver="direct")
    t_dir = time.perf_counter() - t
    lu = splu(A, permc_spec="MMD_AT_PLUS_A", options={"SymmetricMode": True})
    _row(n, frac, A.shape[0], "mmd-sym", t_dir, 0, direct.conductance, k_ref, lu.L.nnz + lu.U.nnz)
    t = time.perf_counter()
    local = np.full(keep.size, -1)
    local[keep.ravel()] = np.arange(A.shape[0])
    perm = local[nested_dissection(nx, ny)]
    perm = perm[perm >= 0]
    lu = splu(A[perm][:, perm].tocsc(), permc_spec="NATURAL", options={"SymmetricMode": True})
    x = np.empty(A.shape[0])
    x[perm] = lu.solve(b[perm])
    t_nd = time.perf_counter() - t
    k_nd = _conductance(x, keep, t_out, nx, ny)
    _row(n, frac, A.shape[0], "nd", t_nd, 0, k_nd, k_ref, lu.L.nnz + lu.U.nnz)
    for solver in ("iterative", "auto"):
        t = time.perf_counter()
        res = bem.reynolds_flow(gap, dx, viscosity=1e-3, solver=solver)
        name = f"{solver} ({res.solver})"
        _row(
            n,
            frac,
            A.shape[0],
            name,
            time.perf_counter() - t,
            res.iterations,
            res.conductance,
            k_ref,
        )


def flow_table(sizes) -> None:
    print("\n## Reynolds flow through the gap: every option against spsolve\n")
    print("| N | A/A0 | unknowns | solver | s | CG iterations | nnz(L+U) / 1e6 | rel. diff |")
    print("|---|---|---|---|---|---|---|---|")
    for n in sizes:
        grid = bem.spectral_grid(PSD, periods=4.0 * n / 512)
        g0 = -bem.random_surface(PSD, grid, 1).heights
        bem.reynolds_flow(g0[:64, :64] - g0.min() + 1e-7, grid.dx, solver="iterative")  # compile
        for p in PRESSURES:
            res = bem.solve_contact(g0, grid, E_STAR, p * grid.lx * grid.ly)
            one_gap(res.gap, grid.dx, n, res.contact_fraction)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--sizes", type=int, nargs="+", default=[512, 1024])
    flow_table(ap.parse_args().sizes)


if __name__ == "__main__":
    main()
