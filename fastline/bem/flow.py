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
when no channel percolates) are removed before the solve (a compiled depth-first search labels
the clusters); without them the matrix is singular.  The
remaining system is symmetric positive definite and has one solver path (``solver="auto"``):

1. Conjugate gradients preconditioned by a geometric aggregation multigrid
   (:mod:`fastline.bem.pcg_flow`), started from ``start`` (a previous result, e.g. the last
   pressure's of a load sequence) to a relative residual ``FLOW_TOL`` (or, with
   ``conductance_tol``, until the conductance's estimated error is below it), within a budget of
   iterations worth about one direct solve (``ITERATION_BUDGET`` times the fraction of cells on
   the flow path). Every few iterations the budget is checked against the total predicted from
   the residual's rate, so a hopeless solve stops after a handful of iterations. This is the fast
   path at low contact fractions, where the open cells form a broad network.
2. Otherwise, or below ``DIRECT_BELOW`` cells on the flow path, SciPy's sparse LU (SuperLU,
   J. W. Demmel et al., SIAM J. Matrix Anal. Appl. 20, 720 (1999), doi:10.1137/S0895479895291765)
   with the minimum-degree ordering of ``A + A^T`` and symmetric mode (diagonal pivots): half
   the time of :func:`~scipy.sparse.linalg.spsolve` (column ordering) at A/A0 0.01, about the
   same at 0.1-0.3, and 1.3-3x less fill than a nested dissection of the grid. Near the
   percolation threshold, where the cluster is thin and tortuous, it beats the iterations.

``solver="direct"`` always takes step 2, ``solver="iterative"`` step 1 without the budget
(up to ``MAX_ITER`` iterations, or until the rate shows that more would be needed, then step 2).

The conductance is the dissipation ``sum t (P_i - P_j)^2 / dP^2`` over all faces (inlet and
outlet included): by the power balance it equals ``Q / dP`` at the solution, and since the
pressure minimises the dissipation, its error at an iterate is of the order of the squared
error of the pressure. The iterations' conductance thus agrees with the direct solve's to a few
1e-9 at ``FLOW_TOL`` = 1e-8 where they converge fast (``tests/test_bem_solver.py`` asserts
1e-7), and to 7e-7 near the percolation threshold (where ``auto`` solves directly);
``balance_error`` (inlet against outlet flux) shows the residual itself (up to ~1e-5 for the
iterations).
Measured times and iterations: ``docs/performance.md``.

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

import numba
import numpy as np
import scipy.sparse as sp
from numpy.typing import ArrayLike
from scipy.sparse.linalg import splu

from fastline._lib.jit import JIT
from fastline._lib.validate import finite_array, positive
from fastline.bem.pcg_flow import iterate

__all__ = ["FlowResult", "reynolds_flow", "FLOW_TOL", "SOLVERS", "CONDUCTANCE_TOL"]

#: relative residual ``|b - A x| / |b|`` at which the conjugate gradients stop; the
#: conductance, taken from the dissipation, is then within a few 1e-9 of the direct solve's
#: (``python -m bench.bem_flow``)
FLOW_TOL = 1e-8
#: CG iterations allowed with every cell on the flow path, about the cost of one direct solve
#: (the measured ratio of a direct solve's time to one CG iteration's, per cell on the path:
#: 100-205 at A/A0 0.1-0.33 at 512^2 and 1024^2, ``python -m bench.bem_flow``); scaled by the
#: fraction of the cells on the flow path
ITERATION_BUDGET = 180
#: below this many cells on the flow path ``solver="auto"`` takes the direct solve at once
#: (about 100 x 100: there the budget is under 20 iterations and the LU takes milliseconds)
DIRECT_BELOW = 10_000
#: iteration cap of ``solver="iterative"`` (beyond it, the direct solve)
MAX_ITER = 5000
#: the solvers of :func:`reynolds_flow`
SOLVERS = ("auto", "iterative", "direct")
#: largest gap [m] :func:`reynolds_flow` takes (far beyond a thin film; its cube would
#: overflow far above)
MAX_GAP = 1e3
#: ``conductance_tol`` of the package's own solves that want only the conductance (calibration,
#: validation ensembles): the conductances are then within ~1e-5 of the exact solve's (measured:
#: the effective gaps of a calibration within 1.1e-6 of the residual criterion's), far inside an
#: ensemble's spread of a few per cent
CONDUCTANCE_TOL = 1e-6


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
        ``|Q_in - Q_out| / Q`` (round-off of the solve, or the residual of the iterations;
        0 if not percolating).
    pressure : ndarray, shape (nx, ny)
        Fluid pressure [Pa] on the active cells, NaN elsewhere.
    viscosity, pressure_drop : float
        As given [Pa s], [Pa].
    solver : str
        What gave the answer: ``"iterative"`` (multigrid-preconditioned CG) or ``"direct"``
        (sparse LU); ``"none"`` when nothing percolates.
    iterations : int
        CG iterations made (also those before a switch to the direct solve).
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


@numba.njit(**JIT)
def _clusters(tx, ty, label):
    """Label the clusters of cells joined by open faces (``tx > 0``, ``ty > 0``; periodic along
    y) into ``label`` (int64, (nx, ny)), by depth-first search; returns the number of clusters."""
    nx, ny = label.shape
    label[:] = -1
    stack = np.empty(nx * ny, np.int64)
    count = 0
    for seed in range(nx * ny):
        if label[seed // ny, seed % ny] >= 0:
            continue
        label[seed // ny, seed % ny] = count
        top = 0
        stack[0] = seed
        while top >= 0:
            c = stack[top]
            top -= 1
            i, j = c // ny, c % ny
            jm = j - 1 if j > 0 else ny - 1
            jp = j + 1 if j < ny - 1 else 0
            for k in range(4):
                if k == 0 and i > 0 and tx[i - 1, j] > 0.0:
                    a, b = i - 1, j
                elif k == 1 and i < nx - 1 and tx[i, j] > 0.0:
                    a, b = i + 1, j
                elif k == 2 and ty[i, jm] > 0.0:
                    a, b = i, jm
                elif k == 3 and ty[i, j] > 0.0:
                    a, b = i, jp
                else:
                    continue
                if label[a, b] < 0:
                    label[a, b] = count
                    top += 1
                    stack[top] = a * ny + b
        count += 1
    return count


def _percolating_cells(tx, ty, t_in, t_out, nx, ny):
    """Boolean mask of the cells connected to both inlet and outlet: the clusters that touch
    the inlet or the outlet, all of them joined through the two faces, if one cluster touches
    both (else none)."""
    label = np.empty((nx, ny), np.int64)
    count = _clusters(tx, ty, label)
    at_in = np.zeros(count, bool)
    at_out = np.zeros(count, bool)
    at_in[label[0][t_in > 0]] = True
    at_out[label[-1][t_out > 0]] = True
    if not np.any(at_in & at_out):
        return np.zeros((nx, ny), dtype=bool)
    return (at_in | at_out)[label]


def _system(tx, ty, t_in, t_out, keep):
    """``(D, tx, ty, b, t_in, t_out, scale)``: the system for a unit pressure drop on the cells
    on the flow path (the others decoupled: ``D = 1``, ``b = 0``), scaled by ``scale`` to a unit
    mean diagonal (``t_in``, ``t_out`` unscaled)."""
    tx = np.where(keep[:-1] & keep[1:], tx, 0.0)
    ty = np.where(keep & np.roll(keep, -1, axis=1), ty, 0.0)
    t_in, t_out = t_in * keep[0], t_out * keep[-1]
    D = np.zeros(keep.shape)
    D[:-1] += tx
    D[1:] += tx
    D += ty + np.roll(ty, 1, axis=1)
    D[0] += t_in
    D[-1] += t_out
    s = 1.0 / float(np.mean(D[keep]))
    D *= s
    D[~keep] = 1.0
    b = np.zeros(keep.shape)
    b[0] = t_in * s
    return D, tx * s, ty * s, b, t_in, t_out, s


def _dissipation(x, tx, ty, t_in, t_out):
    """``sum t (p_i - p_j)^2`` over all faces for the unit-drop pressure ``x``: the flow rate
    ``Q`` for ``dP = 1`` (power balance). At the solution it equals the outlet flux; at an
    approximate one its error is of the order of the residual squared (the pressure minimises
    the dissipation), so the iterations' conductance is as good as the direct solve's."""
    out = float(np.sum(tx * np.diff(x, axis=0) ** 2))
    out += float(np.sum(ty * (np.roll(x, -1, axis=1) - x) ** 2))
    return out + float(np.sum(t_in * (1.0 - x[0]) ** 2) + np.sum(t_out * x[-1] ** 2))


def _direct(D, tx, ty, b, keep):
    """The exact solve of the system on the kept cells (sparse LU): the full-grid solution."""
    nx, ny = keep.shape
    local = np.full(nx * ny, -1)
    local[keep.ravel()] = np.arange(np.count_nonzero(keep))
    (ax, bx), (ay, by) = _face_pairs(nx, ny)
    a = local[np.concatenate([ax.ravel(), ay.ravel()])]
    c = local[np.concatenate([bx.ravel(), by.ravel()])]
    t = np.concatenate([tx.ravel(), ty.ravel()])
    live = (t > 0.0) & (a >= 0) & (c >= 0)
    a, c, t = a[live], c[live], t[live]
    m = int(np.count_nonzero(keep))
    diag = np.arange(m)
    A = sp.csc_matrix(
        (
            np.concatenate([D[keep], -t, -t]),
            (np.concatenate([diag, a, c]), np.concatenate([diag, c, a])),
        ),
        shape=(m, m),
    )
    x = np.zeros((nx, ny))
    if m == 1:
        x[keep] = b[keep] / D[keep]
        return x
    lu = splu(A, permc_spec="MMD_AT_PLUS_A", options={"SymmetricMode": True})
    x[keep] = lu.solve(b[keep])
    return x


def _budget(active: int, cells: int) -> float:
    """CG iterations worth one direct solve of ``active`` unknowns on a grid of ``cells``."""
    return ITERATION_BUDGET * active / cells


def reynolds_flow(
    gap: ArrayLike,
    dx: float,
    dy: float | None = None,
    *,
    viscosity: float = 1e-3,
    pressure_drop: float = 1.0,
    solver: str = "auto",
    start: FlowResult | None = None,
    conductance_tol: float | None = None,
) -> FlowResult:
    """Flow across x through the gap map ``gap`` (module docstring).

    Parameters
    ----------
    gap : array_like, shape (nx, ny)
        Gap [m], >= 0 (0 marks contact), nx >= 2, ny >= 1; e.g. ``ContactResult.gap``.
        For the flow along y, pass ``gap.T`` with ``dx`` and ``dy`` swapped.
    dx, dy : float
        Cell size [m], > 0 (``dy`` defaults to ``dx``).
    viscosity : float
        Dynamic viscosity ``eta`` [Pa s], > 0 (default 1e-3, water at 20 C).
    pressure_drop : float
        ``dP`` between inlet and outlet [Pa], > 0.
    solver : {"auto", "iterative", "direct"}
        ``"auto"`` (default): conjugate gradients while they are cheaper than a direct solve,
        else sparse LU; ``"direct"``: sparse LU; ``"iterative"``: conjugate gradients to
        convergence (module docstring).
    start : FlowResult, optional
        A result on a gap map of the same shape (e.g. the previous pressure's): its fluid
        pressure starts the iterations.
    conductance_tol : float, optional
        In (0, 1): also stop the iterations once the conductance's estimated relative error is
        below this (:mod:`fastline.bem.pcg_flow`), where only the conductance is wanted; the
        pressure field is then less converged than ``FLOW_TOL`` says. Default: the residual
        criterion alone.

    Returns
    -------
    FlowResult
    """
    g, dx, dy, eta, dp = _checked(gap, dx, dy, viscosity, pressure_drop, solver, start)
    if conductance_tol is not None and not 0.0 < conductance_tol < 1.0:
        raise ValueError(f"conductance_tol must be in (0, 1) or None, got {conductance_tol!r}")
    nx, ny = g.shape
    tx, ty, t_in, t_out = _transmissibilities(g**3 / (12.0 * eta), dx, dy)
    keep = _percolating_cells(tx, ty, t_in, t_out, nx, ny)
    if not keep.any():
        return FlowResult(
            0.0, 0.0, 0.0, False, 0.0, 0.0, np.full((nx, ny), np.nan), eta, dp, "none"
        )
    D, tx, ty, b, t_in, t_out, scale = _system(tx, ty, t_in, t_out, keep)
    x, used, iterations = _solve(D, tx, ty, b, keep, solver, start, conductance_tol)
    faces = (tx / scale, ty / scale, t_in, t_out)
    return _result(x, keep, faces, nx * dx / (ny * dy), eta, dp, used, iterations)


def _result(x, keep, faces, aspect, eta, dp, used, iterations) -> FlowResult:
    """The :class:`FlowResult` of the unit-drop solution ``x``; ``faces`` = the unscaled
    ``(tx, ty, t_in, t_out)``, ``aspect`` = ``Lx / Ly``."""
    pressure = np.full(keep.shape, np.nan)
    pressure[keep] = dp * x[keep]
    t_in, t_out = faces[2], faces[3]
    q_in = float(np.sum(t_in * (1.0 - x[0]))) * dp
    q_out = float(np.sum(t_out * x[-1])) * dp
    sigma = _dissipation(x, *faces) * aspect
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


def _checked(gap, dx, dy, viscosity, pressure_drop, solver, start):
    """The inputs of :func:`reynolds_flow` checked: ``(gap, dx, dy, eta, dP)``."""
    g = finite_array("gap", gap, ndim=2)
    if g.shape[0] < 2 or g.shape[1] < 1:
        raise ValueError(f"gap must have at least 2 x 1 cells, got shape {g.shape}")
    if np.any(g < 0.0) or np.any(g > MAX_GAP):
        raise ValueError(
            f"gap must lie in [0, {MAX_GAP:g}] m everywhere (Reynolds' thin-film equation), "
            f"got values in [{g.min():.4g}, {g.max():.4g}] m"
        )
    dx = positive("dx", dx, "m")
    dy = dx if dy is None else positive("dy", dy, "m")
    eta = positive("viscosity", viscosity, "Pa s")
    dp = positive("pressure_drop", pressure_drop, "Pa")
    if solver not in SOLVERS:
        raise ValueError(f"solver must be one of {SOLVERS}, got {solver!r}")
    if start is not None and (not isinstance(start, FlowResult) or start.pressure.shape != g.shape):
        raise ValueError(f"start must be a FlowResult of a gap map of shape {g.shape} (or None)")
    return g, dx, dy, eta, dp


def _solve(D, tx, ty, b, keep, solver, start, conductance_tol=None):
    """The unit-drop fluid pressure on the full grid: (x, the solver used, CG iterations)."""
    active = int(np.count_nonzero(keep))
    if solver == "direct" or (solver == "auto" and active < DIRECT_BELOW):
        return _direct(D, tx, ty, b, keep), "direct", 0
    nx = keep.shape[0]
    if start is None or not start.percolating:
        x = np.repeat(1.0 - (np.arange(nx) + 0.5)[:, None] / nx, keep.shape[1], axis=1)
    else:
        x = np.nan_to_num(start.pressure / start.pressure_drop)
    budget = MAX_ITER if solver == "iterative" else _budget(active, keep.size)
    warm = start is not None and start.percolating
    iterations, converged = iterate(D, tx, ty, b, keep, x, FLOW_TOL, budget, warm, conductance_tol)
    if converged:
        return x, "iterative", iterations
    return _direct(D, tx, ty, b, keep), "direct", iterations
