"""The coupled seal's Newton system, reduced to the gaps and solved by compiled kernels.

:func:`fastline.leakage.seal_system.equations` writes the full Jacobian of the n gaps, N fluid
pressures, the change of approach and the flux (n + N + 2 unknowns). The links in series make
the fluid pressures a cumulative sum: from the inlet ``dp_f,0 = -dP F_inlet`` and each link,

    dp_f,j+1 = dp_f,j + dP F_j + g_j . du - (R_j / R_0) dphi,
    g_j = -(phi / R_0) (A_j d(g^-3)/du [ia_j] e_ia + B_j d(g^-3)/du [ib_j] e_ib),

so ``dp_f = c + S du + s dphi`` with S the running sum of the sparse rows g_j. Substituted into
the gap rows, ``KL dp_f`` needs ``KL S``, whose column k is a sum of the suffix sums
``T[:, j] = sum_{i > j} KL[:, i]`` (fixed per contact) weighted by the ``g_j[k]``: O(n N) to
assemble. With the force row and the outlet ``dp_f,N-1 = -dP F_outlet`` the system has n + 2
unknowns (du, d_delta, dphi), a dense matrix

    [ I - K diag(dp_c/du) - KL S     1      -KL s  ] [ du      ]
    [ w diag(dp_c/du) + wL S         0       wL s  ] [ d_delta ]
    [ S_{N-1}                        0      s_{N-1}] [ dphi    ],

solved by Gaussian elimination with partial pivoting in a compiled, single-threaded loop
(columns scaled by u_0, u_0, dP and rows equilibrated first): (n + 2)^3 / 3 multiply-adds
against the (n + N + 2)^3 / 3 of the full system, and no BLAS, whose threads wait for cores on
a busy machine (at n = 256 NumPy's dense solve of the full system took 0.2-0.6 s of wall time
on a loaded 2-core machine, this reduced one 13 ms; docs/leakage.md, "Performance of the
coupled Newton"). The fluid pressures then follow from the links. The same products with K in
the residual run compiled too (:func:`stiffness_product`).
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numba
import numpy as np

from fastline._lib.jit import JIT

if TYPE_CHECKING:  # annotations only
    from fastline.leakage.seal_system import System

__all__ = ["lu_solve", "reduced_step", "stiffness_product"]


@numba.njit(**JIT)
def _matvec(a, v, out):
    """``out = a @ v`` for a C-contiguous matrix, one row at a time (single-threaded)."""
    m, k = a.shape
    for i in range(m):
        row = a[i]
        acc = 0.0
        for j in range(k):
            acc += row[j] * v[j]
        out[i] = acc
    return out


def stiffness_product(K: np.ndarray, v: np.ndarray) -> np.ndarray:
    """``K @ v`` by a compiled loop (no BLAS threads)."""
    return _matvec(K, np.ascontiguousarray(v, dtype=np.float64), np.empty(K.shape[0]))


#: columns of a panel of the blocked elimination (:func:`lu_solve`), and of a tile of its
#: update (a tile of the panel's rows of U, 64 x 256 x 8 bytes = 128 kB, stays in cache while
#: the rows below stream past it)
BLOCK, TILE = 64, 256


@numba.njit(**JIT)
def _panel(a, b, k0, k1):
    """Eliminate the columns ``k0 .. k1-1`` of ``a`` with partial pivoting, updating only
    those columns (the multipliers are stored below the diagonal, rows swapped whole, ``b``
    with them); False if a pivot is zero."""
    m = a.shape[0]
    for k in range(k0, k1):
        p = k
        big = abs(a[k, k])
        for i in range(k + 1, m):
            if abs(a[i, k]) > big:
                big, p = abs(a[i, k]), i
        if not big > 0.0:
            return False
        if p != k:
            for j in range(m):
                a[k, j], a[p, j] = a[p, j], a[k, j]
            b[k], b[p] = b[p], b[k]
        rk = a[k]
        inv = 1.0 / rk[k]
        for i in range(k + 1, m):
            ri = a[i]
            f = ri[k] * inv
            ri[k] = f
            if f != 0.0:
                for j in range(k + 1, k1):
                    ri[j] -= f * rk[j]
    return True


@numba.njit(**JIT)
def _rows_update(a, i, k0, k1, j0, m):
    """``a[i, j0:m] -= sum_{k0 <= k < k1} a[i, k] a[k, j0:m]`` (the panel's own rows)."""
    ri = a[i]
    for k in range(k0, k1):
        f, rk = ri[k], a[k]
        for j in range(j0, m):
            ri[j] -= f * rk[j]


@numba.njit(**JIT)
def _tile_update(a, ub, fb, rb, i, k0, j0):
    """``a[i, j0:j0+w] -= a[i, k0:k0+kb] @ ub`` for the copied tile ``ub`` (kb x w) of the
    panel's rows of U, through the buffers ``fb`` (kb) and ``rb`` (w): in separate arrays the
    loop over j vectorises (on the rows of ``a`` itself LLVM cannot rule out aliasing)."""
    kb, w = ub.shape
    for k in range(kb):
        fb[k] = a[i, k0 + k]
    for j in range(w):
        rb[j] = a[i, j0 + j]
    for k in range(kb):
        f = fb[k]
        if f != 0.0:
            for j in range(w):
                rb[j] -= f * ub[k, j]
    for j in range(w):
        a[i, j0 + j] = rb[j]


@numba.njit(**JIT)
def lu_solve(a: np.ndarray, b: np.ndarray) -> bool:
    """Solve ``a z = b`` in place (``b`` becomes z) by Gaussian elimination with partial
    pivoting, blocked by ``BLOCK`` columns (right-looking: a panel, its rows of U, then the
    rank-``BLOCK`` update of the rest, ``TILE`` columns at a time), on the C-contiguous ``a``
    (destroyed); False if singular. Single-threaded, no BLAS."""
    m = a.shape[0]
    fb, rb = np.empty(BLOCK), np.empty(TILE)
    for k0 in range(0, m, BLOCK):
        k1 = min(k0 + BLOCK, m)
        if not _panel(a, b, k0, k1):
            return False
        for i in range(k0 + 1, k1):  # the panel's rows of U right of it: L11^-1 A12
            _rows_update(a, i, k0, i, k1, m)
        for j0 in range(k1, m, TILE):  # the trailing matrix, a tile at a time: A22 - L21 U12
            ub = a[k0:k1, j0 : min(j0 + TILE, m)].copy()
            for i in range(k1, m):
                _tile_update(a, ub, fb[: k1 - k0], rb[: ub.shape[1]], i, k0, j0)
    for i in range(m):  # L y = b (unit lower triangle)
        ri = a[i]
        acc = b[i]
        for j in range(i):
            acc -= ri[j] * b[j]
        b[i] = acc
    for i in range(m - 1, -1, -1):  # U z = y
        ri = a[i]
        acc = b[i]
        for j in range(i + 1, m):
            acc -= ri[j] * b[j]
        b[i] = acc / ri[i]
    return True


@numba.njit(**JIT)
def _assemble_t(mt, K, T, dpc, w, tau, gi, gv, rr):
    """The reduced matrix, transposed (``mt[k, i] = M[i, k]``; module docstring), unscaled:
    ``gi``, ``gv`` (links x 2) the indices and values of the rows g_j, ``rr = R_j / R_0``."""
    n = K.shape[0]
    for k in range(n + 2):
        for i in range(n + 2):
            mt[k, i] = 0.0
    for i in range(n):  # - K diag(dp_c/du), written by rows of K into columns of mt
        row = K[i]
        for k in range(n):
            mt[k, i] = -row[k] * dpc[k]
    for k in range(n):
        mt[k, k] += 1.0
        mt[k, n] = w[k] * dpc[k]
        mt[n, k] = 1.0  # the d_delta column of the gap rows
    for j in range(rr.size):
        tj = T[:, j]
        for e in range(2):
            k, g = gi[j, e], gv[j, e]
            if g != 0.0:
                col = mt[k]
                for i in range(n):
                    col[i] -= tj[i] * g
                col[n] += tau[j] * g
                col[n + 1] += g
        col = mt[n + 1]
        for i in range(n):
            col[i] += tj[i] * rr[j]
        col[n] -= tau[j] * rr[j]
        col[n + 1] -= rr[j]


@numba.njit(**JIT)
def _scaled_solve(mt, rhs, su, dP):
    """Transpose ``mt`` into a row-major matrix, scale the columns (u_0 for du and d_delta,
    dP for dphi) and equilibrate the rows, then solve; rhs becomes the unscaled solution.
    False if singular."""
    m = mt.shape[0]
    a = np.empty((m, m))
    for i in range(m):
        row = a[i]
        for k in range(m):
            row[k] = mt[k, i] * (dP if k == m - 1 else su)
        big = 0.0
        for k in range(m):
            big = max(big, abs(row[k]))
        if not big > 0.0:
            return False
        for k in range(m):
            row[k] /= big
        rhs[i] /= big
    if not lu_solve(a, rhs):
        return False
    for k in range(m):
        rhs[k] *= dP if k == m - 1 else su
    return True


def reduced_step(
    sys: System, y: np.ndarray, vals: tuple, F: np.ndarray, dP: float, r0: float
) -> np.ndarray | None:
    """The Newton step ``(du, dp_f, d_delta, dphi)`` of the coupled seal at ``y`` from its law
    values and scaled residual F (module docstring); None if the reduced system is singular."""
    n, N = sys.n, sys.nodes.size
    _, dpc, inv, dinv = vals
    phi = y[n + N + 1]
    su, sf = sys.scales()
    Fl = F[n + 1 : n + N] * dP  # the links' residuals in Pa
    c = -F[n + N] * dP + np.concatenate([[0.0], np.cumsum(Fl)])
    rr = sys.resistances(inv) / r0
    gi = np.ascontiguousarray(np.stack([sys.ia, sys.ib], axis=1), dtype=np.int64)
    gv = np.ascontiguousarray(np.stack([sys.A * dinv[sys.ia], sys.B * dinv[sys.ib]], axis=1))
    gv *= -phi / r0
    if sys.rigid:
        dd = -su * F[n]
        du = -su * F[:n] - dd
        dphi = _rigid_flux(c, gv, gi, du, rr, -F[n + N + 1] * dP)
    else:
        mt = np.empty((n + 2, n + 2))
        _assemble_t(mt, sys.K, sys.T, dpc, sys.w, sys.tau, gi, gv, rr)
        kl_c = c[0] * sys.KL1 + _matvec(sys.T, Fl, np.empty(n))
        rhs = np.concatenate([-su * F[:n] + kl_c, [-sf * F[n] - c[0] * sys.wL.sum()
                              - float(sys.tau @ Fl), -F[n + N + 1] * dP - c[-1]]])  # fmt: skip
        if not _scaled_solve(mt, rhs, su, dP):
            return None
        du, dd, dphi = rhs[:n], rhs[n], rhs[n + 1]
    gdu = np.sum(gv * du[gi], axis=1)
    dpf = c + np.concatenate([[0.0], np.cumsum(gdu - rr * dphi)])
    return np.concatenate([du, dpf, [dd, dphi]])


def _rigid_flux(c, gv, gi, du, rr, outlet) -> float:
    """dphi of a rigid body: the outlet condition with du known."""
    total = float(c[-1] + np.sum(gv * du[gi]))
    return (total - outlet) / float(np.sum(rr))
