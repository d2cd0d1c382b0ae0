"""The iterative stage of the Reynolds flow solve: multigrid-preconditioned conjugate gradients.

The finite-volume system of :mod:`fastline.bem.flow` on the full (nx, ny) grid as arrays: the
diagonal ``D``, the x-face and periodic y-face transmissibilities ``tx`` (nx-1, ny), ``ty``
(nx, ny), the cells on the flow path ``keep`` (the others decoupled, ``D = 1``, ``b = 0``).

Preconditioner: one V-cycle of unsmoothed aggregation multigrid on the grid's own structure
(2 x 2 cells per coarse cell, Galerkin coarse operators ``P^T A P`` with ``P`` the piecewise
constant prolongation over the cells on the flow path, which keeps the five-point stencil on
every level; P. Vanek, J. Mandel, M. Brezina, Computing 56, 179 (1996),
doi:10.1007/BF02238511), one forward Gauss-Seidel sweep before and one backward after the
coarse correction (a symmetric cycle), the coarse correction over-weighted by
``OVER_CORRECTION`` (plain aggregation underestimates it; Y. Notay, Electron. Trans. Numer.
Anal. 37, 123 (2010)), and a sparse LU on the coarsest level (at most ``COARSEST`` cells a
side, or where a side is odd).

The cycle converges fast while the open cells form a broad network (low contact fractions) and
slowly near the percolation threshold, where the conducting cluster is thin and tortuous and
2 x 2 aggregates join cells of different channels. :func:`iterate` therefore works to a
budget: every ``CHECK_EVERY`` iterations it extrapolates the residual's rate of decrease and
gives up as soon as the predicted total exceeds the budget, so that the caller
(:func:`fastline.bem.flow.reynolds_flow`) can take the direct solve instead. From a cold
(linear) start it extrapolates the rate of the last ``CHECK_EVERY`` iterations, since the first
ones remove the smooth error fast and the mean rate would flatter the rest; from a warm start
(the last pressure's field) the mean rate so far, since the rate of a few iterations varies
there and improves as CG resolves the extreme eigenvalues: in a calibration's sequence the last
8 iterations' rate stopped solves that then needed only 37 and 51 iterations in all.
"""

from __future__ import annotations

import math

import numba
import numpy as np
import scipy.sparse as sp
from scipy.sparse.linalg import splu

from fastline._lib.jit import JIT, JIT_SUMS

__all__ = ["iterate", "OVER_CORRECTION", "COARSEST", "CHECK_EVERY"]

#: weight of the coarse-grid correction of the V-cycle
OVER_CORRECTION = 1.7
#: coarsening stops at this many cells on the shorter side (or at an odd side)
COARSEST = 16
#: iterations between two checks of the predicted total against the budget
CHECK_EVERY = 8


@numba.njit(**JIT)
def _matvec(D, tx, ty, x, y):
    """``y = A x``: diagonal D, x faces tx (nx-1, ny), periodic y faces ty (nx, ny)."""
    nx, ny = D.shape
    for i in range(nx):
        for j in range(ny):
            jm = j - 1 if j > 0 else ny - 1
            jp = j + 1 if j < ny - 1 else 0
            s = D[i, j] * x[i, j] - ty[i, jm] * x[i, jm] - ty[i, j] * x[i, jp]
            if i > 0:
                s -= tx[i - 1, j] * x[i - 1, j]
            if i < nx - 1:
                s -= tx[i, j] * x[i + 1, j]
            y[i, j] = s


@numba.njit(**JIT)
def _gauss_seidel(D, tx, ty, b, x, backward):
    """One Gauss-Seidel sweep in place on x, in lexicographic order or its reverse."""
    nx, ny = D.shape
    for ii in range(nx):
        i = nx - 1 - ii if backward else ii
        for jj in range(ny):
            j = ny - 1 - jj if backward else jj
            jm = j - 1 if j > 0 else ny - 1
            jp = j + 1 if j < ny - 1 else 0
            s = b[i, j] + ty[i, jm] * x[i, jm] + ty[i, j] * x[i, jp]
            if i > 0:
                s += tx[i - 1, j] * x[i - 1, j]
            if i < nx - 1:
                s += tx[i, j] * x[i + 1, j]
            x[i, j] = s / D[i, j]


@numba.njit(**JIT)
def _restrict(D, tx, ty, b, x, keep, rc):
    """``rc`` = the residual ``b - A x`` summed over each 2 x 2 aggregate's cells on the path."""
    nx, ny = D.shape
    rc[:] = 0.0
    for i in range(nx):
        for j in range(ny):
            if not keep[i, j]:
                continue
            jm = j - 1 if j > 0 else ny - 1
            jp = j + 1 if j < ny - 1 else 0
            s = b[i, j] - D[i, j] * x[i, j] + ty[i, jm] * x[i, jm] + ty[i, j] * x[i, jp]
            if i > 0:
                s += tx[i - 1, j] * x[i - 1, j]
            if i < nx - 1:
                s += tx[i, j] * x[i + 1, j]
            rc[i // 2, j // 2] += s


@numba.njit(**JIT)
def _prolong(ec, keep, weight, x):
    """``x += weight * e_c`` of its aggregate, on the cells on the path."""
    nx, ny = x.shape
    for i in range(nx):
        for j in range(ny):
            if keep[i, j]:
                x[i, j] += weight * ec[i // 2, j // 2]


@numba.njit(**JIT_SUMS)
def _dot(a, b):
    """``sum a * b`` over two grids (a compiled loop: no BLAS threads to wait for)."""
    s = 0.0
    for i in range(a.shape[0]):
        for j in range(a.shape[1]):
            s += a[i, j] * b[i, j]
    return s


def _coarsen(D, tx, ty, keep):
    """The Galerkin operator of 2 x 2 aggregates of the cells on the flow path."""
    nx, ny = D.shape
    Dc = np.where(keep, D, 0.0).reshape(nx // 2, 2, ny // 2, 2).sum(axis=(1, 3))
    Dc -= 2.0 * tx[0::2, :].reshape(nx // 2, ny // 2, 2).sum(axis=2)
    Dc -= 2.0 * ty[:, 0::2].reshape(nx // 2, 2, ny // 2).sum(axis=1)
    txc = tx[1::2, :].reshape(nx // 2 - 1, ny // 2, 2).sum(axis=2)
    tyc = ty[:, 1::2].reshape(nx // 2, 2, ny // 2).sum(axis=1)
    keepc = keep.reshape(nx // 2, 2, ny // 2, 2).any(axis=(1, 3))
    return np.where(keepc, Dc, 1.0), txc, tyc, keepc


def _coarsest_lu(D, tx, ty):
    """Sparse LU of the five-point operator of the coarsest level."""
    nx, ny = D.shape
    idx = np.arange(nx * ny).reshape(nx, ny)
    right = np.roll(idx, -1, axis=1).ravel()
    rows = np.concatenate([idx.ravel(), idx[:-1].ravel(), idx[1:].ravel(), idx.ravel(), right])
    cols = np.concatenate([idx.ravel(), idx[1:].ravel(), idx[:-1].ravel(), right, idx.ravel()])
    vals = np.concatenate([D.ravel(), -tx.ravel(), -tx.ravel(), -ty.ravel(), -ty.ravel()])
    return splu(sp.csc_matrix((vals, (rows, cols)), shape=(nx * ny, nx * ny)))


class _Multigrid:
    """The levels of the V-cycle (module docstring)."""

    def __init__(self, D, tx, ty, keep):
        self.levels = [(D, tx, ty, keep)]
        while True:
            nx, ny = self.levels[-1][0].shape
            if nx % 2 or ny % 2 or min(nx, ny) <= COARSEST:
                break
            self.levels.append(_coarsen(*self.levels[-1]))
        self.lu = _coarsest_lu(*self.levels[-1][:3])

    def cycle(self, b, k=0):
        """One symmetric V-cycle from level k for the right-hand side b."""
        D, tx, ty, keep = self.levels[k]
        if k == len(self.levels) - 1:
            return self.lu.solve(b.ravel()).reshape(b.shape)
        nx, ny = b.shape
        x = np.zeros_like(b)
        _gauss_seidel(D, tx, ty, b, x, False)
        rc = np.empty((nx // 2, ny // 2))
        _restrict(D, tx, ty, b, x, keep, rc)
        _prolong(self.cycle(rc, k + 1), keep, OVER_CORRECTION, x)
        _gauss_seidel(D, tx, ty, b, x, True)
        return x


def _pcg(D, tx, ty, b, x, mg, tol, budget, warm):
    """Preconditioned conjugate gradients in place on x: (iterations, converged)."""
    r = np.empty_like(b)
    _matvec(D, tx, ty, x, r)
    r = b - r
    z = mg.cycle(r)
    d = z.copy()
    rz = _dot(r, z)
    goal = tol * math.sqrt(_dot(b, b))
    q = np.empty_like(b)
    it = 0
    res = first = last = math.sqrt(_dot(r, r))
    while res > goal:
        if it % CHECK_EVERY == 0 and it > 0:
            since = (it, first) if warm else (CHECK_EVERY, last)
            if it >= budget or it + _remaining(*since, res, goal) > budget:
                return it, False
            last = res
        _matvec(D, tx, ty, d, q)
        a = rz / _dot(d, q)
        x += a * d
        r -= a * q
        z = mg.cycle(r)
        rz_new = _dot(r, z)
        d = z + (rz_new / rz) * d
        rz = rz_new
        it += 1
        res = math.sqrt(_dot(r, r))
    return it, True


def _remaining(k: int, before: float, now: float, goal: float) -> float:
    """Iterations still needed at the rate of the last ``k`` (from ``before`` to ``now``; 0 if
    the residual has not fallen: its 2-norm may rise for a while in CG, so only the plain budget
    applies)."""
    if now >= before:
        return 0.0
    return k * math.log(goal / now) / math.log(now / before)


def iterate(
    D: np.ndarray,
    tx: np.ndarray,
    ty: np.ndarray,
    b: np.ndarray,
    keep: np.ndarray,
    x: np.ndarray,
    tol: float,
    budget: float,
    warm: bool = False,
) -> tuple[int, bool]:
    """Solve ``A x = b`` in place on ``x`` by multigrid-preconditioned CG (module docstring).

    Parameters
    ----------
    D, tx, ty, b, keep : ndarray
        The system (module docstring), scaled to a mean diagonal of order 1.
    x : ndarray, shape (nx, ny)
        The start (e.g. the last pressure's solution), overwritten by the iterate.
    tol : float
        Relative residual ``|b - A x| / |b|`` to reach.
    budget : float
        Iterations allowed; the solve stops early when the extrapolated total exceeds it.
    warm : bool
        Whether ``x`` is a warm start (module docstring: which rate is extrapolated).

    Returns
    -------
    iterations : int
    converged : bool
        False when the budget stopped it (``x`` then holds the last iterate).
    """
    x[~keep] = 0.0
    return _pcg(D, tx, ty, b, x, _Multigrid(D, tx, ty, keep), tol, budget, warm)
