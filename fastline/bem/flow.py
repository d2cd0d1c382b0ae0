"""Reynolds flow through a gap field: the effective conductance of a rough interface.

Thin-film, incompressible, isoviscous flow in the gap ``g(x, y)`` between two surfaces obeys
Reynolds' equation ``div( g^3 / (12 eta) grad P ) = 0`` for the fluid pressure ``P``.  Here it
is discretised with conservative finite volumes on the cells of the gap map:

* cell conductivity ``c = g^3 / (12 eta)`` [m^3/(Pa s)], zero on contact cells (``g = 0``);
* face transmissibility: harmonic mean of the two cells, ``2 c1 c2 / (c1 + c2)`` (zero if either
  is in contact), times ``dy/dx`` on x faces and ``dx/dy`` on y faces;
* fluid pressure ``dP`` on the inlet face ``x = 0`` and 0 on the outlet face ``x = Lx`` (each
  a half cell from the first/last cell centre), periodic along y.

Cells that are not connected to both the inlet and the outlet (closed islands, or everything
when no channel percolates) are removed before the solve with
:func:`scipy.sparse.csgraph.connected_components`; without them the matrix is singular.  The
remaining system is symmetric positive definite. Two solvers: conjugate gradients
preconditioned with one V-cycle of smoothed-aggregation algebraic multigrid (P. Vanek, J. Mandel,
M. Brezina, Computing 56, 179 (1996), doi:10.1007/BF02238511; the ``pyamg`` package, the
optional extra ``fastline-contact[flow]``) to a relative residual ``AMG_RTOL``, and SciPy's
sparse LU (:func:`scipy.sparse.linalg.spsolve`). They agree to ``1e-8`` relative in the
conductance (``tests/test_bem_solver.py``; measured 4e-11-7e-11). LU was the faster on the
measured grids (2.2 s against 3.8 s at 512^2 cells, 15.6 s against 19.1 s at 1024^2; the
multigrid's CG iterations grow, 33 to 53, because ``g^3`` spans many decades near contact:
``docs/performance.md``), so ``solver="auto"`` takes LU up to ``AMG_MIN_CELLS`` active cells
and the multigrid above, where LU's fill-in makes its memory the limit, if pyamg is installed.

Exact for piecewise-constant gaps: a uniform gap ``g`` gives ``Q = (Ly / Lx) g^3/(12 eta) dP``
(plane Poiseuille); strips across the flow give the harmonic mean of ``c`` (resistances in
series), strips along it the arithmetic mean.

The result is normalised like Persson's critical-junction leak rate ``Q = (Ly / Lx) u_c^3 /
(12 eta) dP`` (B. N. J. Persson, C. Yang, J. Phys.: Condens. Matter 20, 315011 (2008)):
``conductance = Q Lx / (Ly dP)`` and ``effective_gap = (12 eta conductance)^(1/3)`` compares
directly with ``u_c``; neither depends on ``dP`` and ``effective_gap`` not on ``eta``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
import scipy.sparse as sp
from numpy.typing import ArrayLike
from scipy.sparse.csgraph import connected_components
from scipy.sparse.linalg import spsolve

from fastline._lib.validate import finite_array, positive

__all__ = ["FlowResult", "reynolds_flow"]

#: relative residual ``|b - A x| / |b|`` at which the multigrid-preconditioned CG stops
AMG_RTOL = 1e-12
#: strength-of-connection threshold of the aggregation (0.1: 28 CG iterations on a 256^2 gap at
#: A/A0 = 0.1, against 74 at pyamg's default 0; ``python -m bench.bem_scaling --flow``)
AMG_THETA = 0.1
#: active cells from which ``solver="auto"`` takes the multigrid (when pyamg is installed)
AMG_MIN_CELLS = 2_000_000
#: the sparse solvers of :func:`reynolds_flow`
SOLVERS = ("auto", "amg", "direct")


@dataclass(frozen=True)
class FlowResult:
    """Steady Reynolds flow across x through one gap map.

    Attributes
    ----------
    conductance : float
        ``Q Lx / (Ly dP)`` [m^3/(Pa s)]; 0 if no channel percolates.
    effective_gap : float
        ``(12 eta conductance)^(1/3)`` [m], comparable with Persson's ``u_c``.
    flow_rate : float
        Volume flow ``Q`` [m^3/s] through the outlet for the given ``pressure_drop``.
    percolating : bool
        Whether any open path joins inlet and outlet.
    active_fraction : float
        Fraction of cells in the cluster connected to both inlet and outlet.
    balance_error : float
        ``|Q_in - Q_out| / Q`` (round-off of the solve; 0 if not percolating).
    pressure : ndarray, shape (nx, ny)
        Fluid pressure [Pa] on the active cells, NaN elsewhere.
    viscosity, pressure_drop : float
        As given [Pa s], [Pa].
    solver : str
        ``"amg"`` (multigrid-preconditioned CG) or ``"direct"`` (sparse LU).
    iterations : int
        CG iterations of the ``"amg"`` solve (0 for ``"direct"``).
    """

    conductance: float
    effective_gap: float
    flow_rate: float
    percolating: bool
    active_fraction: float
    balance_error: float
    pressure: np.ndarray = field(repr=False)
    viscosity: float
    pressure_drop: float
    solver: str = "direct"
    iterations: int = 0


def _harmonic(a, b):
    s = a + b
    return np.divide(2.0 * a * b, s, out=np.zeros_like(s), where=s > 0.0)


def _transmissibilities(c, dx, dy):
    """Face transmissibilities: x faces (nx-1, ny), y faces (nx, ny) (periodic), and inlet,
    outlet (ny,) [m^3/(Pa s)]."""
    tx = _harmonic(c[:-1, :], c[1:, :]) * (dy / dx)
    ty = _harmonic(c, np.roll(c, -1, axis=1)) * (dx / dy)
    t_in = c[0, :] * (2.0 * dy / dx)
    t_out = c[-1, :] * (2.0 * dy / dx)
    return tx, ty, t_in, t_out


def _face_pairs(nx, ny):
    idx = np.arange(nx * ny).reshape(nx, ny)
    return (idx[:-1, :], idx[1:, :]), (idx, np.roll(idx, -1, axis=1))


def _percolating_cells(tx, ty, t_in, t_out, nx, ny):
    """Boolean mask of cells connected to both inlet and outlet (virtual nodes n, n+1)."""
    n = nx * ny
    (ax, bx), (ay, by) = _face_pairs(nx, ny)
    rows = [ax[tx > 0], ay[ty > 0], np.full(np.count_nonzero(t_in > 0), n)]
    cols = [bx[tx > 0], by[ty > 0], np.arange(ny)[t_in > 0]]
    rows.append(np.full(np.count_nonzero(t_out > 0), n + 1))
    cols.append((nx - 1) * ny + np.arange(ny)[t_out > 0])
    r, c = np.concatenate(rows), np.concatenate(cols)
    graph = sp.coo_matrix((np.ones(r.size), (r, c)), shape=(n + 2, n + 2)).tocsr()
    _, label = connected_components(graph, directed=False)
    if label[n] != label[n + 1]:
        return np.zeros((nx, ny), dtype=bool)
    return (label[:n] == label[n]).reshape(nx, ny)


def _assemble(tx, ty, t_in, t_out, keep, pressure_drop):
    """Finite-volume matrix and right-hand side on the kept cells (local numbering)."""
    nx, ny = keep.shape
    local = np.full(nx * ny, -1)
    local[keep.ravel()] = np.arange(np.count_nonzero(keep))
    (ax, bx), (ay, by) = _face_pairs(nx, ny)
    a = np.concatenate([ax.ravel(), ay.ravel()])
    b = np.concatenate([bx.ravel(), by.ravel()])
    t = np.concatenate([tx.ravel(), ty.ravel()])
    live = (t > 0.0) & (local[a] >= 0) & (local[b] >= 0)
    a, b, t = local[a[live]], local[b[live]], t[live]
    m = int(keep.sum())
    diag = np.zeros(m)
    np.add.at(diag, a, t)
    np.add.at(diag, b, t)
    first = local[np.arange(ny)]
    last = local[(nx - 1) * ny + np.arange(ny)]
    rhs = np.zeros(m)
    on = first >= 0
    diag[first[on]] += t_in[on]
    rhs[first[on]] += t_in[on] * pressure_drop
    on = last >= 0
    diag[last[on]] += t_out[on]
    rows = np.concatenate([np.arange(m), a, b])
    cols = np.concatenate([np.arange(m), b, a])
    vals = np.concatenate([diag, -t, -t])
    return sp.csr_matrix((vals, (rows, cols)), shape=(m, m)), rhs, first, last


def reynolds_flow(
    gap: ArrayLike,
    dx: float,
    dy: float | None = None,
    *,
    viscosity: float = 1e-3,
    pressure_drop: float = 1.0,
    solver: str = "auto",
) -> FlowResult:
    """Flow across x through the gap map ``gap`` (module docstring).

    Parameters
    ----------
    gap : array_like, shape (nx, ny)
        Gap [m], >= 0 (0 marks contact), nx >= 2, ny >= 1; e.g. ``ContactResult.gap``.
    dx, dy : float
        Cell size [m], > 0 (``dy`` defaults to ``dx``).
    viscosity : float
        Dynamic viscosity ``eta`` [Pa s], > 0 (default 1e-3, water at 20 C).
    pressure_drop : float
        ``dP`` between inlet and outlet [Pa], > 0.
    solver : {"auto", "amg", "direct"}
        ``"amg"``: CG with an algebraic-multigrid preconditioner (needs pyamg, the extra
        ``fastline-contact[flow]``); ``"direct"``: sparse LU; ``"auto"`` (default):
        ``"amg"`` from ``AMG_MIN_CELLS`` active cells if pyamg is installed, else ``"direct"``.

    Returns
    -------
    FlowResult
    """
    g, dx, dy, eta, dp = _checked(gap, dx, dy, viscosity, pressure_drop, solver)
    nx, ny = g.shape
    c = g**3 / (12.0 * eta)
    tx, ty, t_in, t_out = _transmissibilities(c, dx, dy)
    keep = _percolating_cells(tx, ty, t_in, t_out, nx, ny)
    pressure = np.full((nx, ny), np.nan)
    if not keep.any():
        return FlowResult(0.0, 0.0, 0.0, False, 0.0, 0.0, pressure, eta, dp)
    A, rhs, first, last = _assemble(tx, ty, t_in, t_out, keep, dp)
    sol, used, iterations = _solve(A, rhs, solver)
    pressure[keep] = sol
    on_in, on_out = first >= 0, last >= 0
    q_in = float(np.sum(t_in[on_in] * (dp - sol[first[on_in]])))
    q_out = float(np.sum(t_out[on_out] * sol[last[on_out]]))
    lx, ly = nx * dx, ny * dy
    sigma = q_out * lx / (ly * dp)
    return FlowResult(
        conductance=sigma,
        effective_gap=(12.0 * eta * sigma) ** (1.0 / 3.0),
        flow_rate=q_out,
        percolating=True,
        active_fraction=float(keep.mean()),
        balance_error=abs(q_in - q_out) / abs(q_out) if q_out != 0.0 else math.inf,
        pressure=pressure,
        viscosity=eta,
        pressure_drop=dp,
        solver=used,
        iterations=iterations,
    )


def _checked(gap, dx, dy, viscosity, pressure_drop, solver):
    """The inputs of :func:`reynolds_flow` checked: ``(gap, dx, dy, eta, dP)``."""
    g = finite_array("gap", gap, ndim=2)
    if g.shape[0] < 2 or g.shape[1] < 1:
        raise ValueError(f"gap must have at least 2 x 1 cells, got shape {g.shape}")
    if np.any(g < 0.0):
        raise ValueError("gap must be >= 0 everywhere (allowed range [0, inf) m)")
    dx = positive("dx", dx, "m")
    dy = dx if dy is None else positive("dy", dy, "m")
    eta = positive("viscosity", viscosity, "Pa s")
    dp = positive("pressure_drop", pressure_drop, "Pa")
    if solver not in SOLVERS:
        raise ValueError(f"solver must be one of {SOLVERS}, got {solver!r}")
    return g, dx, dy, eta, dp


def _solve(A, rhs, solver):
    """``A x = rhs``: (x, the solver used, CG iterations)."""
    amg = None
    if solver == "amg" or (solver == "auto" and A.shape[0] >= AMG_MIN_CELLS):
        try:
            import pyamg as amg
        except ImportError:
            if solver == "amg":
                raise ValueError(
                    "solver='amg' needs pyamg (pip install 'fastline-contact[flow]'); "
                    "use solver='direct' or 'auto'"
                ) from None
    if amg is None or A.shape[0] < 2:
        return spsolve(A.tocsc(), rhs), "direct", 0
    ml = amg.smoothed_aggregation_solver(
        A.tocsr(),
        symmetry="hermitian",
        strength=("symmetric", {"theta": AMG_THETA}),
        max_coarse=500,
    )
    residuals: list[float] = []
    x = ml.solve(rhs, tol=AMG_RTOL, accel="cg", maxiter=500, residuals=residuals)
    if np.linalg.norm(rhs - A @ x) > 10.0 * AMG_RTOL * np.linalg.norm(rhs):
        return spsolve(A.tocsc(), rhs), "direct", 0  # stalled: fall back to the exact solve
    return x, "amg", len(residuals) - 1
