"""Preconditioned constrained conjugate gradients with nested iteration (the default solver of
:func:`fastline.bem.solve_contact`).

The iteration is Polonsky & Keer's (Wear 231, 206 (1999)): conjugate gradients on the cells in
contact for the gap equation with the mean gap there removed, projection onto ``p >= 0``,
re-entry of penetrating cells and rescaling to the load. Two changes make its iteration count
nearly independent of the grid:

1. A preconditioner. The compliance ``K`` is diagonal in Fourier space, ``Khat ~ 2/(E*|q|)``,
   so its condition number grows like the number of cells per side. Each gradient ``g`` (the
   gap on the contact set, zero elsewhere) is multiplied by the stiffness ``1/Khat`` in Fourier
   space and restricted back to the contact set with its mean there removed, ``z = P_c K^-1
   P_c g``: the restriction of the exact inverse, the preconditioner of E. A. H. Vollebregt,
   J. Comput. Phys. 257, 333 (2014), doi:10.1016/j.jcp.2013.10.005. One convolution more per
   iteration (three in all; two after an iteration that changed no contact cell, whose
   displacement follows from the last one and the step's).
2. The conjugate directions are restarted along the preconditioned gradient (see
   :data:`RESTARTS`) once the contact set has settled, i.e. at the first iteration that
   changes no cell after ones that did (from there on the iterations are conjugate gradients
   for one linear problem, and directions built on an earlier set only slow them down), and
   whenever more than ``RESTART_FRACTION`` of the contact cells enter at once. Polonsky &
   Keer restart whenever a cell re-enters, which with the preconditioner costs more than it
   saves except from a poor start at small contact fractions. Full-grid iterations at
   A/A0 = 0.3, 256^2 cells: nested 26 (37 never restarting, 32 only once settled); without
   nested iteration 29, against 31 never, 42 at every re-entry (512^2: 34, 36, 51); at
   A/A0 = 0.02 without nesting 28 against 23 at every re-entry
   (``python -m bench.bem_scaling --variants``).

Nested iteration: a start first solves the same problem on cells twice as large (``g0``
averaged over 2 x 2 cells, the load unchanged), recursively down to ``NESTED_MIN_CELLS`` cells
per side, each level to the tolerance ``sqrt(tol)``, and starts from the coarse pressure
repeated on the 2 x 2 children; the finest level then only refines the contact edges. A warm
start (``p_init``) enters at the coarsest level as its 2 x 2 means, or, from a load close to
the new one, the full grid directly (``fastline.bem.contact.WARM_FULL_GRID_CELLS``).

A warm start saves little, and no start could save much: each full-grid iteration reduces the
error by about 0.5 whatever the start, and what remains after the first few is at high
wavenumbers (about 90 % of its power above a quarter of the Nyquist wavenumber after 10
iterations), which a coarse grid cannot represent. From the exact solution at a load 0.1 %
lower, the full grid still needs 16 iterations to ``tol = 1e-8`` at 256^2 cells and A/A0 = 0.2
(a cold nested solve: 25); from one 24 % lower, as many as cold
(``python -m bench.bem_scaling --warm-steps``). Entering the full grid directly pays for small
steps, less so on finer grids (full-grid-equivalent iterations over a sequence of steps of
24 % in load: -11 % at 256^2 cells, -3 % at 512^2, +7 % at 1024^2; of 5.5 %: -22 % and -17 %
at 256^2 and 512^2); correcting the start by the change of the coarse solution, or
extrapolating from the last two solutions (secant), gained at most 3-7 %.
"""

from __future__ import annotations

import math

import numba
import numpy as np

from fastline._lib.jit import JIT
from fastline.bem.halfspace import ElasticHalfSpace

#: smallest number of cells per side of a nested-iteration level
NESTED_MIN_CELLS = 64


@numba.njit(**JIT)
def _masked_gradient(p, g, gc):
    """Centre ``g`` on the contact cells (``p > 0``) in place; ``gc`` = g there, 0 elsewhere."""
    n = 0
    s = 0.0
    for i in range(p.size):
        if p[i] > 0.0:
            s += g[i]
            n += 1
    mean = s / n if n > 0 else 0.0
    for i in range(p.size):
        g[i] -= mean
        gc[i] = g[i] if p[i] > 0.0 else 0.0


@numba.njit(**JIT)
def contact_mean(p, x):
    """Mean of ``x`` over the contact cells (``p > 0``); 0 where there are none."""
    n = 0
    s = 0.0
    for i in range(p.size):
        if p[i] > 0.0:
            s += x[i]
            n += 1
    return s / n if n > 0 else 0.0


@numba.njit(**JIT)
def _preconditioned_direction(p, gc, z, t, G_old, conjugate):
    """Centre ``z`` on the contact cells, ``t = z + beta t`` there (0 elsewhere); return G.

    ``G = sum gc z`` (the preconditioned residual norm), ``beta = G / G_old`` if ``conjugate``.
    """
    mean = contact_mean(p, z)
    G = 0.0
    for i in range(p.size):
        if p[i] > 0.0:
            z[i] -= mean
            G += gc[i] * z[i]
    beta = G / G_old if conjugate and G_old > 0.0 else 0.0
    for i in range(p.size):
        t[i] = z[i] + beta * t[i] if p[i] > 0.0 else 0.0
    return G


@numba.njit(**JIT)
def _step_length(p, g, t, r):
    """``tau = sum g t / sum r' t`` over the contact cells, ``r'`` = r minus its mean there."""
    rbar = contact_mean(p, r)
    num = 0.0
    den = 0.0
    for i in range(p.size):
        if p[i] > 0.0:
            num += g[i] * t[i]
            den += (r[i] - rbar) * t[i]
    return num / den if den != 0.0 else 0.0


@numba.njit(**JIT)
def _update_pressure(p, g, t, tau, p_old, stiffness):
    """Step, project on ``p >= 0``, let penetrating cells re-enter; return the numbers of cells
    that re-entered (penetrating with no pressure after the projection), that entered the
    contact set and that left it over the step, and of cells in contact after it.

    A penetrating cell re-enters with ``-tau g`` (Polonsky & Keer), or with the local closing
    pressure ``-g stiffness`` (``stiffness`` = 1 / self coefficient) when ``tau`` is not
    positive (the gap on the contact set already uniform: a warm start at its optimum).
    """
    for i in range(p.size):
        p_old[i] = p[i]
        if p[i] > 0.0:
            p[i] = max(p[i] - tau * t[i], 0.0)
    reentered = entered = left = contact = 0
    for i in range(p.size):
        if p[i] <= 0.0 and g[i] < 0.0:
            p[i] = -(tau if tau > 0.0 else stiffness) * g[i]
            reentered += 1
        if p[i] > 0.0:
            contact += 1
            entered += p_old[i] <= 0.0
        else:
            left += p_old[i] > 0.0
    return reentered, entered, left, contact


@numba.njit(**JIT)
def _rescale(p, p_old, target_sum):
    """Scale ``p`` to ``sum p = target_sum``; return ``sum |p - p_old| / target_sum``."""
    s = 0.0
    for i in range(p.size):
        s += p[i]
    f = target_sum / s
    dev = 0.0
    for i in range(p.size):
        p[i] *= f
        dev += abs(p[i] - p_old[i])
    return dev / target_sum


#: conjugacy restarts of :func:`pcg_solve`: "adaptive" (the default) once the contact set has
#: settled and whenever more than ``RESTART_FRACTION`` of the contact cells re-enter at once;
#: "settled" only the first; "never"; "reentry" at every re-entry (Polonsky & Keer's rule)
RESTARTS = ("adaptive", "settled", "never", "reentry")

#: re-entering cells, as a fraction of the contact cells, that restart the conjugacy
RESTART_FRACTION = 0.01


def pcg_solve(op: ElasticHalfSpace, g0, target_sum, tol, max_iter, p, restart="adaptive"):
    """Preconditioned iterations in place on ``p`` (1D view). Returns (iterations, residual).

    ``restart``: one of :data:`RESTARTS`. After an iteration that changed no cell of the
    contact set, the displacement follows from the last one and the step's (two convolutions
    instead of three).
    """
    n = p.size
    u = np.empty(op.shape)
    r = np.empty(op.shape)
    z = np.empty(op.shape)
    g = np.empty(n)
    gc = np.empty(n)
    t = np.zeros(n)
    p_old = np.empty(n)
    p2 = p.reshape(op.shape)
    G_old, conjugate, changed, fresh = 1.0, False, False, False
    stiffness = 1.0 / op.self_coefficient
    residual = math.inf
    for it in range(1, max_iter + 1):
        if not fresh:
            op.apply(p2, out=u)
        np.add(u.ravel(), g0, out=g)
        _masked_gradient(p, g, gc)
        op.apply_inverse(gc.reshape(op.shape), out=z)
        G_old = _preconditioned_direction(p, gc, z.ravel(), t, G_old, conjugate)
        op.apply(t.reshape(op.shape), out=r)
        tau = _step_length(p, g, t, r.ravel())
        if not tau > 0.0:  # not a descent direction: restart along the preconditioned gradient
            op.apply_inverse(gc.reshape(op.shape), out=z)
            G_old = _preconditioned_direction(p, gc, z.ravel(), t, G_old, False)
            op.apply(t.reshape(op.shape), out=r)
            tau = _step_length(p, g, t, r.ravel())
        counts = _update_pressure(p, g, t, tau, p_old, stiffness)
        settled = changed and counts[1] + counts[2] == 0
        changed = counts[1] + counts[2] > 0
        conjugate = not _restarts(restart, settled, counts)
        fresh = sum(counts[:3]) == 0  # then p = f (p_old - tau t): K p from K p_old, r = K t
        if fresh:
            _shift(u.ravel(), r.ravel(), tau, target_sum / p.sum())
        residual = _rescale(p, p_old, target_sum)
        if residual < tol:
            return it, residual
    return max_iter, residual


def _restarts(rule, settled, counts):
    """Whether the conjugate directions restart after a step (``rule`` in :data:`RESTARTS`,
    ``counts`` from :func:`_update_pressure`)."""
    reentered, entered, _, contact = counts
    if rule == "adaptive":
        return settled or entered > RESTART_FRACTION * contact
    if rule == "settled":
        return settled
    return rule == "reentry" and reentered > 0


@numba.njit(**JIT)
def _shift(u, r, tau, f):
    """``u = f (u - tau r)`` in place."""
    for i in range(u.size):
        u[i] = f * (u[i] - tau * r[i])


def coarsen(a: np.ndarray) -> np.ndarray:
    """Means over 2 x 2 cells (even sizes)."""
    return 0.25 * (a[0::2, 0::2] + a[1::2, 0::2] + a[0::2, 1::2] + a[1::2, 1::2])


def nested_levels(nx: int, ny: int) -> int:
    """Number of coarser levels: halve while both sides are even and >= 2 NESTED_MIN_CELLS."""
    levels = 0
    while nx % 2 == 0 and ny % 2 == 0 and min(nx, ny) >= 2 * NESTED_MIN_CELLS:
        nx, ny = nx // 2, ny // 2
        levels += 1
    return levels


def nested_start(op, g0, load, tol, max_iter, levels, p_start=None):
    """Start for ``op``'s grid from the coarser levels (the coarsest from ``p_start``'s 2 x 2
    means if given, else uniform).

    Returns (pressure of ``op``'s grid [Pa], iterations per coarse level coarsest first,
    convolutions made on them).
    """
    nx, ny = op.shape
    dx, dy = op.dx, op.dy
    g0s = [g0]
    for _ in range(levels):
        g0s.append(coarsen(g0s[-1]))
    p = None
    if p_start is not None:
        for _ in range(levels):
            p_start = coarsen(p_start)
        p = p_start * (load / (p_start.sum() * dx * dy * 4**levels))
    stages: list[int] = []
    convolutions = 0
    coarse_tol = max(tol, math.sqrt(tol))
    for k in range(levels, 0, -1):
        f = 2**k
        cop = ElasticHalfSpace(nx // f, ny // f, dx * f, dy * f, op.E_star, op.periodic)
        area = dx * dy * f * f
        if p is None:
            p = np.full(cop.shape, load / (area * cop.nx * cop.ny))
        elif p.shape != cop.shape:
            p = np.repeat(np.repeat(p, 2, axis=0), 2, axis=1)
        flat = p.ravel()
        g = np.ascontiguousarray(g0s[k]).ravel()
        its, _ = pcg_solve(cop, g, load / area, coarse_tol, max_iter, flat)
        stages.append(its)
        convolutions += cop.convolutions
    assert p is not None
    return np.repeat(np.repeat(p, 2, axis=0), 2, axis=1), stages, convolutions
