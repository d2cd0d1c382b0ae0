"""The Reynolds conductance of a gap field by multigrid-preconditioned conjugate gradients.

The same finite-volume system as :func:`fastline.bem.flow.reynolds_flow` (cell conductivity
``g^3 / (12 eta)``, harmonic-mean faces, pressure drop across x, periodic in y, the cells not
joined to both inlet and outlet removed), solved iteratively instead of by a sparse LU, whose
fill-in makes a 512 x 512 gap field cost tens of seconds. A calibration solves one gap field
per pressure, surface and direction, each close to the last, so the previous fluid pressure is
the start (:func:`conductance`).

Preconditioner: one V-cycle of unsmoothed aggregation multigrid on the grid's own structure
(2 x 2 cells per coarse cell, Galerkin coarse operators ``P^T A P`` with ``P`` the piecewise
constant prolongation over the cells on the flow path, which keeps the five-point stencil on
every level; P. Vanek, J. Mandel, M. Brezina, Computing 56, 179 (1996),
doi:10.1007/BF02238511), one forward Gauss-Seidel sweep before and one backward after the
coarse correction (a symmetric cycle), the coarse correction over-weighted by
``OVER_CORRECTION`` (plain aggregation underestimates it; Y. Notay, Electron. Trans. Numer.
Anal. 37, 123 (2010)), and a sparse LU on the coarsest level (at most ``COARSEST`` cells a
side, or where a side is odd). Conjugate gradients stop at a relative residual of ``tol``
(default 1e-10): the conductance then agrees with the direct solve to 1e-9, and to 1e-7 near
percolation, where the system is ill-conditioned (``tests/test_calibrate.py``).
"""

from __future__ import annotations

import math

import numba
import numpy as np
import scipy.sparse as sp
from scipy.sparse.linalg import splu

from fastline._lib.jit import JIT, JIT_SUMS
from fastline.bem.flow import _percolating_cells, _transmissibilities, reynolds_flow

__all__ = ["conductance", "FLOW_TOL"]

#: default relative residual ``|b - A x| / |b|`` of the flow solve
FLOW_TOL = 1e-10
#: weight of the coarse-grid correction of the V-cycle
OVER_CORRECTION = 1.7
#: coarsening stops at this many cells on the shorter side (or at an odd side)
COARSEST = 16
#: iteration cap of the conjugate gradients (beyond it, :func:`~fastline.bem.flow.reynolds_flow`)
MAX_ITER = 2000


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


def _system(gap, dx, dy, viscosity):
    """``(D, tx, ty, b, keep, t_out, scale)``: the flow system for a unit pressure drop on the
    cells on the flow path (the others decoupled, ``D = 1``), scaled to a unit mean diagonal
    (``t_out`` unscaled); None when no channel percolates."""
    nx, ny = gap.shape
    tx, ty, t_in, t_out = _transmissibilities(gap**3 / (12.0 * viscosity), dx, dy)
    keep = _percolating_cells(tx, ty, t_in, t_out, nx, ny)
    if not keep.any():
        return None
    tx = np.where(keep[:-1] & keep[1:], tx, 0.0)
    ty = np.where(keep & np.roll(keep, -1, axis=1), ty, 0.0)
    t_in, t_out = t_in * keep[0], t_out * keep[-1]
    D = np.zeros((nx, ny))
    D[:-1] += tx
    D[1:] += tx
    D += ty + np.roll(ty, 1, axis=1)
    D[0] += t_in
    D[-1] += t_out
    s = 1.0 / float(np.mean(D[keep]))
    D *= s
    D[~keep] = 1.0
    b = np.zeros((nx, ny))
    b[0] = t_in * s
    return D, tx * s, ty * s, b, keep, t_out


def _pcg(D, tx, ty, b, x, mg, tol):
    """Preconditioned conjugate gradients in place on x; the iterations made."""
    r = np.empty_like(b)
    _matvec(D, tx, ty, x, r)
    r = b - r
    z = mg.cycle(r)
    d = z.copy()
    rz = _dot(r, z)
    bn = math.sqrt(_dot(b, b))
    q = np.empty_like(b)
    it = 0
    while math.sqrt(_dot(r, r)) > tol * bn and it < MAX_ITER:
        _matvec(D, tx, ty, d, q)
        a = rz / _dot(d, q)
        x += a * d
        r -= a * q
        z = mg.cycle(r)
        rz_new = _dot(r, z)
        d = z + (rz_new / rz) * d
        rz = rz_new
        it += 1
    return it


def conductance(
    gap: np.ndarray,
    dx: float,
    dy: float,
    viscosity: float,
    start: np.ndarray | None = None,
    tol: float = FLOW_TOL,
) -> tuple[float, np.ndarray, int]:
    """Conductance ``Q Lx / (Ly dP)`` [m^3/(Pa s)] of a gap field for flow across x.

    Parameters
    ----------
    gap : ndarray, shape (nx, ny)
        Gap [m], finite and >= 0 (a BEM gap field: the caller's own).
    dx, dy, viscosity : float
        Cell size [m] and viscosity [Pa s], > 0.
    start : ndarray, optional
        Fluid pressure for a unit drop to start from (the last call's); default linear in x.
    tol : float
        Relative residual at which the iterations stop.

    Returns
    -------
    conductance : float
        0 when no channel percolates (as :func:`~fastline.bem.flow.reynolds_flow`).
    pressure : ndarray
        The fluid pressure for a unit drop (0 off the flow path): the next call's start.
    iterations : int
    """
    nx, ny = gap.shape
    system = _system(gap, dx, dy, viscosity)
    if system is None:
        return 0.0, np.zeros((nx, ny)), 0
    D, tx, ty, b, keep, t_out = system
    if start is None:
        x = np.repeat(1.0 - (np.arange(nx) + 0.5)[:, None] / nx, ny, axis=1)
    else:
        x = np.array(start, dtype=np.float64)
    x[~keep] = 0.0
    it = _pcg(D, tx, ty, b, x, _Multigrid(D, tx, ty, keep), tol)
    if it >= MAX_ITER:  # not converged: the direct solve of the same system
        res = reynolds_flow(gap, dx, dy, viscosity=viscosity)
        return res.conductance, np.nan_to_num(res.pressure), it
    q_out = float(np.sum(t_out * x[-1]))
    return q_out * (nx * dx) / (ny * dy), x, it
