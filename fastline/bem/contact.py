"""Rigid indenter on an elastic half-space: constrained conjugate gradients under load control.

Problem (all fields on the cells of a :class:`~fastline.bem.surface.Grid`)::

    gap = g0 - d + K p,       p >= 0,   gap >= 0,   p * gap = 0,   sum(p) dx dy = W,

``g0`` the undeformed gap [m] (indenter shape minus surface heights), ``d`` the rigid-body
approach [m] (an unknown: load control), ``K`` the compliance of
:class:`~fastline.bem.halfspace.ElasticHalfSpace` (pressure opens the gap) and ``W`` the total
load on the cell [N].  Combined roughness and moduli of two bodies map onto a rigid rough
indenter on a smooth half-space of modulus ``E*`` (small slopes, frictionless).

Solver: the constrained conjugate-gradient method of I. A. Polonsky and L. M. Keer, Wear 231,
206-219 (1999), doi:10.1016/S0043-1648(99)00113-1: conjugate gradients on the cells in contact
for the gap equation with the mean gap in contact removed (which eliminates ``d``), projection
onto ``p >= 0``, re-entry of penetrating cells with the steepest-descent step (which resets the
conjugacy), and rescaling to the load.  Each iteration makes two convolutions. By default
(``method="pcg"``) the iterations are preconditioned in Fourier space on the contact set and
started from coarser grids (nested iteration), which keeps their number nearly independent of
the grid; :mod:`fastline.bem._pcg` describes both and ``docs/performance.md`` the counts. The
stopping
test is theirs: the relative pressure change ``sum |p - p_old| / sum p`` below ``tol``; a
result is reported converged only if, in addition, ``p >= 0`` and the penetration and the gap
on the contact cells are within ``sqrt(tol)`` of the undeformed gap's peak-to-peak.

A warm start (``p_init``, e.g. the solution at another load) is rescaled to the load first;
at a load within a factor ``1 + WARM_FULL_GRID_CELLS / n`` of its own (``n`` cells on the
shorter side) it starts the full grid directly. A start at the optimum of its own contact set
makes the conjugate-gradient step ``0/0``; then penetrating cells re-enter with their local
closing pressure ``-g / K_00`` instead of ``-tau g``, and a conjugate direction that is not a
descent direction is replaced by the gradient, so no cell can be left with a negative
pressure.

Geometry helpers return ``g0`` for the three scenes of :mod:`fastline.bem`: a cylinder of axis
y (``x^2 / 2R``), a sphere (``r^2 / 2R``) and a nominally flat indenter (zero), each centred on
the grid's origin.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numba
import numpy as np
from numpy.typing import ArrayLike

from fastline._lib.jit import JIT
from fastline._lib.validate import MAX_ITER_RANGE, finite_array, finite_scalar, integer, positive
from fastline.bem._pcg import (
    _rescale,
    _step_length,
    _update_pressure,
    contact_mean,
    nested_levels,
    nested_start,
    pcg_solve,
)
from fastline.bem.halfspace import ElasticHalfSpace
from fastline.bem.surface import Grid

__all__ = ["ContactResult", "solve_contact", "cylinder_gap", "sphere_gap", "image_curvature"]

#: Default stopping tolerance on the relative pressure change per iteration (Polonsky & Keer).
DEFAULT_TOL = 1e-9

#: A warm start whose load is within a factor ``1 + WARM_FULL_GRID_CELLS / n`` of the new load
#: (``n`` cells on the shorter side) starts the full grid directly, without nested iteration:
#: 1.25 at n = 256, 1.125 at 512 (the measured break-even, ``docs/performance.md``).
WARM_FULL_GRID_CELLS = 64

#: Largest nominal pressure, load over the grid's area, in units of E* (dimensionless): far
#: beyond any linear-elastic contact; above it the solve's numbers would overflow.
MAX_NOMINAL_PRESSURE = 1e6


def cylinder_gap(grid: Grid, radius: float, image_curvature: float = 0.0) -> np.ndarray:
    """Undeformed gap ``(1 - kappa) x^2 / (2R)`` [m] of a rigid cylinder with axis along y.

    Parameters
    ----------
    grid : Grid
    radius : float
        Cylinder radius ``R`` [m], > 0.
    image_curvature : float
        ``kappa`` from :func:`image_curvature` to cancel the leading effect of the periodic
        images in x (default 0: no correction), in [0, 0.5).
    """
    _check_grid(grid)
    radius = positive("radius", radius, "m")
    kappa = finite_scalar("image_curvature", image_curvature)
    if not 0.0 <= kappa < 0.5:
        raise ValueError(f"image_curvature must lie in [0, 0.5), got {kappa!r}")
    x = grid.x
    return np.repeat(((1.0 - kappa) * x * x / (2.0 * radius))[:, None], grid.ny, axis=1)


def image_curvature(E_star: float, load: float, radius: float, lx: float) -> float:
    """Curvature of the periodic images' displacement near a line contact, in units of 1/R.

    A load per length ``f`` [N/m] repeated with period ``Lx`` along x displaces the surface
    near the contact by its images (plane strain, ``u = -(2/(pi E*)) int p ln|x - x'|``)

        sum_{n != 0} -(2/(pi E*)) int p(x') ln|x - x' - n Lx| dx'
            = const + (pi f / (3 E* Lx^2)) (x - x_c)^2 + O(Lx^-4)

    (from ``sum_{n>=1} 1/n^2 = pi^2/6``), whatever the profile, so the images act like a
    change of the cylinder's curvature by ``kappa / R`` with

        kappa = 2 pi f R / (3 E* Lx^2).

    Uncorrected, ``s`` and the contact width shrink by ``kappa / 2`` relative (Hertz,
    ``s ~ R^(1/2)``, and the Gaussian limit, ``s^2 = R u0``, alike; Hertz:
    ``kappa / 2 = (pi^2 / 12)(a / Lx)^2``); :func:`cylinder_gap` with ``image_curvature=kappa``
    cancels it (``tests/test_bem.py``: at ``Lx = 4 a`` the Hertz ``s`` moves from -5.0 % to
    -0.27 %, at ``Lx = 8 a`` from -1.3 % to +0.002 %).

    Parameters
    ----------
    E_star : float
        Effective modulus [Pa], > 0.
    load : float
        Load per unit length [N/m], > 0.
    radius : float
        Cylinder radius [m], > 0.
    lx : float
        Period along x [m], > 0.

    Returns
    -------
    float
        ``kappa`` (dimensionless).
    """
    E_star = positive("E_star", E_star, "Pa")
    load = positive("load", load, "N/m")
    radius = positive("radius", radius, "m")
    lx = positive("lx", lx, "m")
    return 2.0 * math.pi * load * radius / (3.0 * E_star * lx * lx)


def sphere_gap(grid: Grid, radius: float) -> np.ndarray:
    """Undeformed gap ``(x^2 + y^2) / (2R)`` [m] of a rigid sphere centred on the origin.

    Parameters
    ----------
    grid : Grid
    radius : float
        Sphere radius ``R`` [m], > 0.
    """
    _check_grid(grid)
    radius = positive("radius", radius, "m")
    x, y = grid.x[:, None], grid.y[None, :]
    return (x * x + y * y) / (2.0 * radius)


def _check_grid(grid):
    if not isinstance(grid, Grid):
        raise TypeError(f"grid must be a fastline.bem.Grid, got {type(grid).__name__}")


@dataclass(frozen=True)
class ContactResult:
    """Solution of one BEM contact problem.

    Attributes
    ----------
    pressure : ndarray, shape (nx, ny)
        Contact pressure [Pa], >= 0.
    gap : ndarray, shape (nx, ny)
        Gap [m] after deformation, set to exactly 0 on the contact cells (``pressure > 0``)
        and >= 0 elsewhere up to the residual ``max_penetration``.
    approach : float
        Rigid-body approach ``d`` [m] (relative to the kernel's free constant: meaningful as a
        difference between loads on one grid).
    load : float
        Total load ``sum(p) dx dy`` [N].
    contact_fraction : float
        Fraction of cells in contact.
    converged : bool
        Whether the relative pressure change fell below ``tol`` within ``max_iter`` *and* the
        complementarity conditions hold: ``min_pressure >= 0`` and ``max_penetration``,
        ``max_contact_gap`` both within ``gap_tolerance``.
    iterations : int
        Iterations on the full grid (``"pcg"``: three convolutions each, two after an
        iteration that changed no contact cell; ``"ccg"``: two).
    residual : float
        Last relative pressure change ``sum |dp| / sum p``.
    max_penetration : float
        ``max(0, -min gap)`` over the non-contact cells before clipping [m].
    max_contact_gap : float
        ``max |gap|`` over the contact cells before zeroing [m] (the gap equation's residual).
    message : str
    grid : Grid
    min_pressure : float
        Smallest cell pressure [Pa] (>= 0 for a converged result).
    gap_tolerance : float
        Bound [m] on ``max_penetration`` and ``max_contact_gap`` for ``converged``:
        ``sqrt(tol)`` times the peak-to-peak undeformed gap.
    stage_iterations : tuple of int
        Iterations on each grid level, coarsest first; the last is ``iterations`` (one entry
        without nested iteration).
    convolutions : int
        FFT convolutions on all levels (a level of ``n/2^k`` cells per side costs about
        ``4^-k`` of one on the full grid).
    """

    pressure: np.ndarray = field(repr=False)
    gap: np.ndarray = field(repr=False)
    approach: float
    load: float
    contact_fraction: float
    converged: bool
    iterations: int
    residual: float
    max_penetration: float
    max_contact_gap: float
    message: str
    grid: Grid
    min_pressure: float = 0.0
    gap_tolerance: float = math.inf
    stage_iterations: tuple[int, ...] = ()
    convolutions: int = 0


# ---- CCG stages (compiled; 1D views of the cell arrays) ----------------------------------------
@numba.njit(**JIT)
def _center_gap(p, g):
    """Subtract the mean gap over the contact cells from ``g``; return (mean, sum of g^2 there)."""
    mean = contact_mean(p, g)
    G = 0.0
    for i in range(p.size):
        g[i] -= mean
        if p[i] > 0.0:
            G += g[i] * g[i]
    return mean, G


@numba.njit(**JIT)
def _new_direction(p, g, t, beta):
    """``t = g + beta t`` on the contact cells, 0 elsewhere."""
    for i in range(p.size):
        t[i] = g[i] + beta * t[i] if p[i] > 0.0 else 0.0


def _ccg(op, g0, target_sum, tol, max_iter, p):
    """Polonsky-Keer iterations in place on ``p`` (1D view). Returns (iterations, residual)."""
    n = p.size
    u = np.empty(op.shape)
    r = np.empty(op.shape)
    g = np.empty(n)
    t = np.zeros(n)
    p_old = np.empty(n)
    p2 = p.reshape(op.shape)
    G_old, conjugate = 1.0, False
    residual = math.inf
    for it in range(1, max_iter + 1):
        op.apply(p2, out=u)
        np.add(u.ravel(), g0, out=g)
        _, G = _center_gap(p, g)
        _new_direction(p, g, t, G / G_old if conjugate else 0.0)
        G_old = G
        op.apply(t.reshape(op.shape), out=r)
        tau = _step_length(p, g, t, r.ravel())
        if conjugate and not tau > 0.0:  # not a descent direction: restart along the gradient
            _new_direction(p, g, t, 0.0)
            op.apply(t.reshape(op.shape), out=r)
            tau = _step_length(p, g, t, r.ravel())
        reentered = _update_pressure(p, g, t, tau, p_old, 1.0 / op.self_coefficient)[0]
        conjugate = reentered == 0
        residual = _rescale(p, p_old, target_sum)
        if residual < tol:
            return it, residual
    return max_iter, residual


def solve_contact(
    g0: ArrayLike,
    grid: Grid,
    E_star: float,
    load: float,
    *,
    periodic: bool = True,
    tol: float = DEFAULT_TOL,
    max_iter: int = 5000,
    p_init: ArrayLike | None = None,
    method: str = "pcg",
    nested: bool = True,
) -> ContactResult:
    """Frictionless normal contact of a rigid indenter and an elastic half-space, load control.

    Constrained conjugate gradients (Polonsky & Keer, Wear 231, 206 (1999); module docstring)
    with the compliance of :class:`~fastline.bem.halfspace.ElasticHalfSpace`, by default
    preconditioned in Fourier space and nested (:mod:`fastline.bem._pcg`).

    Parameters
    ----------
    g0 : array_like, shape (nx, ny)
        Undeformed gap [m] (indenter shape minus surface heights, e.g.
        ``cylinder_gap(grid, R) - surface.heights``); finite. Only differences matter.
    grid : Grid
        The cells.
    E_star : float
        Effective modulus [Pa], > 0.
    load : float
        Total normal load on the grid [N], > 0 (a cylinder: load per length times ``grid.ly``;
        a nominally flat contact: nominal pressure times ``grid.lx * grid.ly``).
    periodic : bool
        Periodic cell (default) or isolated patch (:class:`ElasticHalfSpace`).
    tol : float
        Stop when the relative pressure change of an iteration is below ``tol``, in (0, 0.1).
    max_iter : int
        Iteration cap per grid level, >= 1.
    p_init : array_like, optional
        Starting pressure [Pa], >= 0 with a positive sum (a warm start, e.g. the solution at
        another load), rescaled to ``load``. It starts the full grid if its load is within a
        factor ``1 + 64/n`` (``n`` cells per shorter side), else (nested) the coarsest level.
    method : {"pcg", "ccg"}
        ``"pcg"`` (default): Fourier-preconditioned iterations, two or three convolutions each;
        ``"ccg"``: Polonsky & Keer's plain iterations, two convolutions each.
    nested : bool
        Start a ``"pcg"`` solve from the solution on cells twice as large, recursively
        (default True; grids with even sides of >= 128 cells).

    Returns
    -------
    ContactResult
        ``converged`` is False if ``max_iter`` was reached or the complementarity conditions
        fail (no warning: check the flag).
    """
    g0, E_star, load, tol, max_iter = _checked(g0, grid, E_star, load, tol, max_iter)
    if method not in ("pcg", "ccg"):
        raise ValueError(f"method must be 'pcg' or 'ccg', got {method!r}")
    op = ElasticHalfSpace(grid.nx, grid.ny, grid.dx, grid.dy, E_star, periodic=periodic)
    levels = nested_levels(grid.nx, grid.ny) if nested and method == "pcg" else 0
    return _solve(op, g0, grid, load, (tol, max_iter, method, levels), p_init)


def _solve(op, g0, grid, load, settings, p_init):
    """The levels' iterations and the diagnostics; ``settings`` = (tol, max_iter, method,
    number of coarser levels)."""
    tol, max_iter, method, levels = settings
    stages: list[int] = []
    coarse_convolutions = 0
    p = None if p_init is None else _start_pressure(p_init, grid, load)
    near = 1.0 + WARM_FULL_GRID_CELLS / min(grid.nx, grid.ny)
    if p is not None and _load_ratio(p_init, grid, load) <= near:
        levels = 0  # a start at a nearby load: the full grid from it directly
    if levels > 0:
        p, stages, coarse_convolutions = nested_start(op, g0, load, tol, max_iter, levels, p)
    elif p is None:
        p = _start_pressure(None, grid, load)
    p_flat = np.ascontiguousarray(p).ravel()
    g0_flat = np.ascontiguousarray(g0).ravel()
    solve = pcg_solve if method == "pcg" else _ccg
    iterations, residual = solve(op, g0_flat, load / grid.cell_area, tol, max_iter, p_flat)
    stats = (iterations, residual, tuple(stages) + (iterations,), coarse_convolutions)
    return _finish(op, g0, p_flat.reshape(grid.shape), grid, load, stats, tol)


def _checked(g0, grid, E_star, load, tol, max_iter):
    """The inputs of :func:`solve_contact` checked, in order: ``(g0, E_star, load, tol,
    max_iter)`` (``g0`` as a float array of the grid's shape)."""
    _check_grid(grid)
    g0 = finite_array("g0", g0, ndim=2)
    if g0.shape != grid.shape:
        raise ValueError(f"g0 must have the grid's shape {grid.shape}, got {g0.shape}")
    E_star = positive("E_star", E_star, "Pa")
    load = positive("load", load, "N")
    most = MAX_NOMINAL_PRESSURE * E_star * grid.lx * grid.ly
    if load > most:
        raise ValueError(
            f"load must be <= {most:.4g} N (a nominal pressure of {MAX_NOMINAL_PRESSURE:g} E*, "
            f"far beyond linear elasticity), got {load!r}"
        )
    tol = positive("tol", tol)
    if tol >= 0.1:
        raise ValueError(f"tol must lie in (0, 0.1), got {tol!r}")
    return g0, E_star, load, tol, integer("max_iter", max_iter, *MAX_ITER_RANGE)


def _load_ratio(p_init, grid, load) -> float:
    """``max(W / W0, W0 / W)`` of the load ``W`` and the load ``W0`` of a checked ``p_init``."""
    w0 = float(np.sum(p_init)) * grid.cell_area
    return max(load / w0, w0 / load)


def _start_pressure(p_init, grid, load) -> np.ndarray:
    """The starting pressure [Pa]: ``p_init`` checked and copied, or uniform at the load."""
    if p_init is None:
        return np.full(grid.shape, load / (grid.lx * grid.ly))
    p = finite_array("p_init", p_init, ndim=2).copy()
    if p.shape != grid.shape or np.any(p < 0.0) or p.sum() <= 0.0:
        raise ValueError(f"p_init must have shape {grid.shape}, be >= 0 and not all zero")
    return p * (load / (p.sum() * grid.cell_area))


def _finish(op, g0, p, grid, load, stats, tol):
    """Gap, approach and complementarity diagnostics of the final pressure; ``stats`` =
    (iterations, residual, iterations per level, convolutions on the coarser levels)."""
    iterations, residual, stages, coarse_convolutions = stats
    gap = g0 + op.apply(p)
    contact = p > 0.0
    approach = float(gap[contact].mean())
    gap -= approach
    max_contact_gap = float(np.abs(gap[contact]).max())
    outside = gap[~contact]
    max_pen = float(max(0.0, -outside.min())) if outside.size else 0.0
    gap[contact] = 0.0
    np.maximum(gap, 0.0, out=gap)
    gap_tol = math.sqrt(tol) * float(np.ptp(g0)) if np.ptp(g0) > 0.0 else math.inf
    p_min = float(p.min())
    complementary = p_min >= 0.0 and max(max_pen, max_contact_gap) <= gap_tol
    converged = residual < tol and complementary
    if converged:
        msg = f"converged in {iterations} iterations (relative pressure change {residual:.2e})"
    elif residual < tol:
        msg = (
            f"not converged: complementarity violated after {iterations} iterations (min p "
            f"{p_min:.3g} Pa, penetration {max_pen:.3g} m, contact gap {max_contact_gap:.3g} m)"
        )
    else:
        msg = f"not converged: {iterations} iterations, relative pressure change {residual:.2e}"
    return ContactResult(
        pressure=p,
        gap=gap,
        approach=approach,
        load=float(p.sum() * grid.cell_area),
        contact_fraction=float(contact.mean()),
        converged=converged,
        iterations=iterations,
        residual=float(residual),
        max_penetration=max_pen,
        max_contact_gap=max_contact_gap,
        message=msg,
        grid=grid,
        min_pressure=p_min,
        gap_tolerance=gap_tol,
        stage_iterations=stages,
        convolutions=op.convolutions + coarse_convolutions,
    )
