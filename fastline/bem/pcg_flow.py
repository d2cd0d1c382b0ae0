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

Where only the conductance is wanted (a calibration), ``conductance_tol`` stops the iterations
on its own error instead of the residual's. The conductance is the dissipation
``phi(x) = x.Ax - 2 b.x + c`` of the iterate, which exceeds the solution's by the error's energy
norm ``|x - x*|_A^2``; each CG step lowers it by exactly ``a_k r_k . z_k``, and the sum of the
next ``d`` such decrements is a lower bound of that energy norm which converges to it (M. R.
Hestenes, E. Stiefel, J. Res. Nat. Bur. Standards 49, 409 (1952); Z. Strakos, P. Tichy,
Electron. Trans. Numer. Anal. 13, 56 (2002)). The loop stops once the last ``DELAY``
decrements sum to less than ``conductance_tol`` times the current dissipation; measured on a
calibration's sequences at 512^2, the conductance was then within 6 ``conductance_tol``
(``conductance_tol`` 1e-8 to 1e-6) of the direct solve's, and above it, as it must be.

Each sweep of the smoother runs a row at a time: the neighbours across x summed in a
vectorisable pass, then the recurrence along y with the inverse diagonal (half the time of a
cell-by-cell sweep with the periodic neighbours chosen by branches).
"""

from __future__ import annotations

import math

import numba
import numpy as np
import scipy.sparse as sp
from scipy.sparse.linalg import splu

from fastline._lib.jit import JIT, JIT_SUMS

__all__ = ["iterate", "OVER_CORRECTION", "COARSEST", "CHECK_EVERY", "DELAY"]

#: weight of the coarse-grid correction of the V-cycle
OVER_CORRECTION = 1.7
#: coarsening stops at this many cells on the shorter side (or at an odd side)
COARSEST = 16
#: iterations between two checks of the predicted total against the budget
CHECK_EVERY = 8
#: CG steps whose decrease of the dissipation estimates its remaining error (the delay ``d`` of
#: Strakos and Tichy; at most ``CHECK_EVERY``)
DELAY = 4


@numba.njit(**JIT)
def _add_x_neighbours(tx, x, i, v):
    """``v += tx[i-1] x[i-1] + tx[i] x[i+1]``: row i's neighbours across x (a row at a time:
    the work along y is then one pass, or one recurrence in a sweep)."""
    nx, ny = x.shape
    if i > 0:
        for j in range(ny):
            v[j] += tx[i - 1, j] * x[i - 1, j]
    if i < nx - 1:
        for j in range(ny):
            v[j] += tx[i, j] * x[i + 1, j]


@numba.njit(**JIT)
def _gauss_seidel(Dinv, tx, ty, b, x, backward):
    """One Gauss-Seidel sweep in place on x, in lexicographic order or its reverse; ``Dinv`` the
    inverse diagonal. Each row is a recurrence along the periodic y (its wrap-around cells
    apart), after the neighbours across x are summed in a vectorisable pass."""
    nx, ny = Dinv.shape
    v = np.empty(ny)
    for ii in range(nx):
        i = nx - 1 - ii if backward else ii
        v[:] = b[i]
        _add_x_neighbours(tx, x, i, v)
        xi, ti, di = x[i], ty[i], Dinv[i]
        if ny == 1:  # the periodic y faces join the cell to itself
            xi[0] = (v[0] + 2.0 * ti[0] * xi[0]) * di[0]
            continue
        if not backward:
            xi[0] = (v[0] + ti[ny - 1] * xi[ny - 1] + ti[0] * xi[1]) * di[0]
            prev = xi[0]
            for j in range(1, ny - 1):
                prev = (v[j] + ti[j - 1] * prev + ti[j] * xi[j + 1]) * di[j]
                xi[j] = prev
            j = ny - 1
            xi[j] = (v[j] + ti[j - 1] * xi[j - 1] + ti[j] * xi[0]) * di[j]
        else:
            j = ny - 1
            xi[j] = (v[j] + ti[j - 1] * xi[j - 1] + ti[j] * xi[0]) * di[j]
            nxt = xi[j]
            for j in range(ny - 2, 0, -1):
                nxt = (v[j] + ti[j - 1] * xi[j - 1] + ti[j] * nxt) * di[j]
                xi[j] = nxt
            xi[0] = (v[0] + ti[ny - 1] * xi[ny - 1] + ti[0] * xi[1]) * di[0]


@numba.njit(**JIT)
def _y_apply(d, t, x, v):
    """``v += t[j-1] x[j-1] + t[j] x[j+1] - d[j] x[j]`` along one periodic row."""
    ny = x.shape[0]
    if ny == 1:
        v[0] += (2.0 * t[0] - d[0]) * x[0]
        return
    v[0] += t[ny - 1] * x[ny - 1] + t[0] * x[1] - d[0] * x[0]
    for j in range(1, ny - 1):
        v[j] += t[j - 1] * x[j - 1] + t[j] * x[j + 1] - d[j] * x[j]
    v[ny - 1] += t[ny - 2] * x[ny - 2] + t[ny - 1] * x[0] - d[ny - 1] * x[ny - 1]


@numba.njit(**JIT)
def _matvec(D, tx, ty, x, y):
    """``y = A x``: diagonal D, x faces tx (nx-1, ny), periodic y faces ty (nx, ny)."""
    nx, ny = D.shape
    v = np.empty(ny)
    for i in range(nx):
        v[:] = 0.0
        _add_x_neighbours(tx, x, i, v)
        _y_apply(D[i], ty[i], x[i], v)
        for j in range(ny):
            y[i, j] = -v[j]


@numba.njit(**JIT)
def _restrict(D, tx, ty, b, x, rc):
    """``rc`` = the residual ``b - A x`` summed over each 2 x 2 aggregate (the decoupled cells
    off the flow path hold ``x = 0`` and ``b = 0``: no residual)."""
    nx, ny = D.shape
    v = np.empty(ny)
    rc[:] = 0.0
    for i in range(nx):
        v[:] = b[i]
        _add_x_neighbours(tx, x, i, v)
        _y_apply(D[i], ty[i], x[i], v)
        r = rc[i // 2]
        for j in range(ny // 2):
            r[j] += v[2 * j] + v[2 * j + 1]


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


@numba.njit(**JIT_SUMS)
def _step(x, r, d, q, a):
    """``x += a d``, ``r -= a q`` in place; returns ``r . r``."""
    s = 0.0
    for i in range(x.shape[0]):
        for j in range(x.shape[1]):
            x[i, j] += a * d[i, j]
            r[i, j] -= a * q[i, j]
            s += r[i, j] * r[i, j]
    return s


@numba.njit(**JIT)
def _direction(d, z, beta):
    """``d = z + beta d`` in place."""
    for i in range(d.shape[0]):
        for j in range(d.shape[1]):
            d[i, j] = z[i, j] + beta * d[i, j]


class _Multigrid:
    """The levels of the V-cycle (module docstring): per level ``(D, 1/D, tx, ty, keep)`` and the
    level's work arrays (the iterate and the restricted residual)."""

    def __init__(self, D, tx, ty, keep):
        levels = [(D, tx, ty, keep)]
        while True:
            nx, ny = levels[-1][0].shape
            if nx % 2 or ny % 2 or min(nx, ny) <= COARSEST:
                break
            levels.append(_coarsen(*levels[-1]))
        self.lu = _coarsest_lu(*levels[-1][:3])
        self.levels = [(lv[0], 1.0 / lv[0]) + lv[1:] for lv in levels]
        self.work = [
            (np.empty(lv[0].shape), np.empty((lv[0].shape[0] // 2, lv[0].shape[1] // 2)))
            for lv in levels[:-1]
        ]

    def cycle(self, b, k=0, out=None):
        """One symmetric V-cycle from level k for the right-hand side b (into ``out``, or a
        work array of the level)."""
        D, Dinv, tx, ty, keep = self.levels[k]
        if k == len(self.levels) - 1:
            return self.lu.solve(b.ravel()).reshape(b.shape)
        x, rc = self.work[k]
        x = x if out is None else out
        x[:] = 0.0
        _gauss_seidel(Dinv, tx, ty, b, x, False)
        _restrict(D, tx, ty, b, x, rc)
        _prolong(self.cycle(rc, k + 1), keep, OVER_CORRECTION, x)
        _gauss_seidel(Dinv, tx, ty, b, x, True)
        return x


class _Progress:
    """What the CG loop stops on (module docstring): the residual's 2-norm against ``tol |b|``,
    and with ``conductance_tol`` also the dissipation's estimated error, the sum of the last
    ``DELAY`` decrements ``a_k r_k . z_k``, against ``conductance_tol`` times the dissipation."""

    def __init__(self, b, x, r, tol, conductance_tol):
        self.goal = tol * math.sqrt(_dot(b, b))
        self.ctol = conductance_tol
        # the start's dissipation x.Ax - 2 b.x + sum(t_in) = -x.r - b.x + sum(b[0]) for the
        # unit-drop system (b = t_in on the inlet row only)
        self.phi = -_dot(x, r) - _dot(b, x) + float(b[0].sum())
        self.drops: list[float] = []

    def take(self, drop: float) -> None:
        """One CG step's decrease of the dissipation."""
        self.phi -= drop
        self.drops.append(drop)

    def measure(self, res: float) -> tuple[float, float]:
        """(the quantity that must fall, its goal): the residual, or with ``conductance_tol``
        (once ``DELAY`` steps were made) the dissipation's estimated error."""
        if self.ctol is None or len(self.drops) < DELAY:
            return res, self.goal
        return math.fsum(self.drops[-DELAY:]), self.ctol * self.phi

    def done(self, res: float) -> bool:
        if res <= self.goal:
            return True
        now, goal = self.measure(res)
        return self.ctol is not None and now <= goal


def _pcg(D, tx, ty, b, x, mg, tol, budget, warm, conductance_tol=None):
    """Preconditioned conjugate gradients in place on x: (iterations, converged)."""
    r = np.empty_like(b)
    _matvec(D, tx, ty, x, r)
    r = b - r
    stop = _Progress(b, x, r, tol, conductance_tol)
    d = mg.cycle(r).copy()
    z, q = np.empty_like(b), np.empty_like(b)
    rz = _dot(r, d)
    it = 0
    res = math.sqrt(_dot(r, r))
    # the budget's rate: from the start (warm) or over the last CHECK_EVERY iterations (cold),
    # of the residual or, with conductance_tol, of the error estimate (from the first check)
    first = last = (0, res) if conductance_tol is None else None
    while not stop.done(res):
        if it % CHECK_EVERY == 0 and it > 0:
            now, goal = stop.measure(res)
            ref = first if warm else last
            more = 0.0 if ref is None else _remaining(it - ref[0], ref[1], now, goal)
            if it >= budget or it + more > budget:
                return it, False
            first, last = first or (it, now), (it, now)
        _matvec(D, tx, ty, d, q)
        a = rz / _dot(d, q)
        res = math.sqrt(_step(x, r, d, q, a))
        stop.take(a * rz)
        mg.cycle(r, out=z)
        rz_new = _dot(r, z)
        _direction(d, z, rz_new / rz)
        rz = rz_new
        it += 1
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
    conductance_tol: float | None = None,
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
    conductance_tol : float, optional
        Also stop once the dissipation's estimated relative error is below this (module
        docstring).

    Returns
    -------
    iterations : int
    converged : bool
        False when the budget stopped it (``x`` then holds the last iterate).
    """
    x[~keep] = 0.0
    mg = _Multigrid(D, tx, ty, keep)
    return _pcg(D, tx, ty, b, x, mg, tol, budget, warm, conductance_tol)
