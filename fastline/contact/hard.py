"""Hard frictionless contact of smooth surfaces (``model="hertz"``): every geometry.

On a :class:`fastline.contact.core.Discretisation`, find ``p >= 0`` and the rigid approach ``u1``
with

    gap_i = g_i + (K p)_i + u1 >= 0,        p_i gap_i = 0,        sum_i w_i p_i = load.

Two algorithms (:func:`hard_contact` chooses):

* :func:`active_set` - the primal-dual active-set method (M. Hintermueller, K. Ito and
  K. Kunisch, SIAM J. Optim. 13, 865 (2002), doi:10.1137/S1052623401383558): guess the contact
  set A, solve the *linear* contact problem on it (``K p + u1 = -g`` on A, ``p = 0`` off it,
  the load carried), then move cells with ``p < 0`` out of A and cells with ``gap < 0`` into
  it, until A settles. The linear problem is the Newton system of the rough contact,
  ``(D + K) dp + du1 = r``, with ``D`` ~ 0 in the contact and decoupled (huge) outside, so the
  operator's own compiled solver does it (:mod:`fastline.elastic.pcg` for the line contact:
  its two-level preconditioner was built for the near-hard core of high loads). Started from
  Hertz's profile, A settles in 1-2 steps on every grid measured. Line contact, tol 1e-8, loads
  1e2-1e6 N/m: at most 18 / 9 / 18 / 9 FFT convolutions at n = 256 / 1024 / 4096 / 16384
  (0.2 ms at n = 1024, 5 ms at 16384); constrained CG from the same start takes 55 / 89 / 119 /
  133 (from the flat start used before, 131-605), 6-14x the time, and stops with pressure
  errors of 2e-7 to 1e-4 of p0 where the active set agrees with a dense direct solve to 2e-10
  (``python -m bench.hard``; tests/test_solver.py holds the count and the dense comparison).
* :func:`constrained_cg` - the constrained conjugate gradient of I. A. Polonsky and
  L. M. Keer, Wear 231, 206 (1999): the geometries whose operator has no compiled Newton
  system (the sphere), and the fallback if the active set does not settle.
"""

from __future__ import annotations

import math

import numpy as np

from fastline.contact.core import MAX_CG, Discretisation, Outcome, dot

__all__ = ["active_set", "complementarity_error", "constrained_cg", "hard_contact"]

#: active-set steps before :func:`hard_contact` falls back to constrained CG (2 are typical)
ACTIVE_SET_STEPS = 30
#: D of the linear system on contact cells, in units of K_00: hard contact is D = 0; a tiny
#: positive value keeps the preconditioner's logarithms finite and changes p by ~1e-14
D_CONTACT = 1e-14
#: D off the contact: decoupled from CG (above the compiled solver's frozen threshold, 1e10
#: K_00), dp ~ r / D = 0 there. The sphere's operator has no such solver: its projected PCG
#: (:mod:`fastline.elastic.ring`) keeps every cell, and with D = 1e8 K_ii off the contact it
#: took 1-4 steps and 20-945 CG iterations at n = 16-2048, at times 2.6x the time of
#: constrained CG, so the sphere stays with constrained CG
D_FREE = 1e300
#: each linear solve's accuracy: a gap mismatch of RTOL_SCALE tol delta (absolute, so that a
#: solve from an iterate already close, e.g. after one cell joined the contact, asks CG for a
#: small reduction instead of 1e-9 of a round-off-sized residual: that stagnated for 20-40
#: iterations at n = 4096 with 64 coarse aggregates, 24 -> 83 convolutions); the reduction
#: asked is kept in [RTOL_MIN, RTOL_MAX]. 1e-3: the pressure is ~100x as sensitive as the gap
#: (0.1 left 1.7e-8 of p0 against the dense solve at n = 64; 1e-3 costs 0-2 CG iterations)
RTOL_SCALE, RTOL_MIN, RTOL_MAX = 1e-3, 1e-14, 0.1


def hard_contact(
    disc: Discretisation, p: np.ndarray, delta: float, tol: float, max_iter: int
) -> Outcome:
    """Hard frictionless contact (module docstring): the active-set method where the operator
    solves its Newton system in compiled code, constrained CG otherwise or as a fallback.

    Parameters
    ----------
    disc : Discretisation
        The scene (gap in m, weights, operator, load).
    p : ndarray
        Starting pressure in Pa, >= 0; its support is the first contact set (the Hertz profile
        of the geometry is a good one).
    delta : float
        Length scale of the scene in m (the Hertz approach): residuals are in its units.
    tol : float
        Active set: the gap mismatch in the contact and the penetration outside, in units of
        ``delta``, and the relative error of the load. Constrained CG: the relative change of
        the pressure in one iteration.
    max_iter : int
        Iterations allowed (active-set steps at most :data:`ACTIVE_SET_STEPS`).
    """
    out = active_set(disc, p, delta, tol, min(max_iter, ACTIVE_SET_STEPS))
    if out is not None and out.converged:
        return out
    start = p if out is None else np.maximum(out.pressure, 0.0)
    return constrained_cg(disc, start, delta, tol, max_iter)


def complementarity_error(gap: np.ndarray, contact: np.ndarray) -> float:
    """Largest violation of hard contact in m: ``|gap|`` on the contact cells and the
    penetration ``-gap`` anywhere (``p >= 0`` holds by construction in both algorithms; the
    tests check it)."""
    inside = float(np.max(np.abs(gap[contact]))) if contact.any() else 0.0
    return max(inside, float(max(0.0, -gap.min())))


def active_set(
    disc: Discretisation, p: np.ndarray, delta: float, tol: float, max_steps: int
) -> Outcome | None:
    """Primal-dual active set (module docstring); None if the operator has no compiled Newton
    system (:data:`D_FREE`) or no step is allowed.

    Converged when a step leaves the contact set unchanged and the residual is below ``tol``
    (the larger of the complementarity error in units of ``delta`` and the relative error of
    the load carried); a settled set above it is solved again from the last pressure. Not
    converged when a contact set repeats (a cycle) or ``max_steps`` pass. ``iterations``
    counts the linear solves; ``info`` holds the CG iterations and each step's contact cells.
    """
    if getattr(disc.op, "solve_newton", None) is None or max_steps < 1:
        return None
    A = p > 0.0
    if not A.any():  # a contact narrower than a cell: start from the lowest gap
        A[int(np.argmin(disc.gap))] = True
    seen = {A.tobytes()}
    sizes: list[int] = []
    cg_total, steps, err, settled = 0, 0, math.inf, False
    while steps < max_steps:
        steps += 1
        solved = _contact_on(disc, A, p, RTOL_SCALE * tol * delta)
        if solved is None:
            return None
        p, u1, its = solved
        cg_total += its
        sizes.append(int(A.sum()))
        gap = disc.gap + disc.op.apply(p) + u1
        # the load too: dp off the contact is zeroed, so what it carried would be lost
        err = max(complementarity_error(gap, A) / delta, abs(dot(disc.weights, p) / disc.load - 1))
        A_new = (A & (p > 0.0)) | (~A & (gap < 0.0))
        settled = bool(np.array_equal(A_new, A))
        if settled and err < tol:
            break
        if not settled:  # a settled set with err >= tol is solved again (refinement)
            if A_new.tobytes() in seen or not A_new.any():
                break  # a cycle
            seen.add(A_new.tobytes())
            A = A_new
    ok = settled and err < tol
    msg = (
        f"{'converged' if ok else 'not converged'}: residual {err:.2e} (tol {tol:.1e}; gap "
        f"mismatch in units of delta, load error) after {steps} active-set steps"
        + ("" if ok or settled or steps >= max_steps else " (the contact set cycled)")
    )
    info = {"cg_iterations": cg_total, "contact_cells": sizes}
    return Outcome(None, u1, err, ok, steps, msg, info, p, gap)


def _contact_on(disc: Discretisation, A: np.ndarray, p: np.ndarray, accuracy: float):
    """The linear contact problem on the cells ``A`` (``K p + g + u1 = 0`` there, ``p = 0``
    elsewhere, ``sum(w p) = load``) from ``p``, by one Newton-system solve to a gap mismatch of
    about ``accuracy`` (m): ``(p, u1, CG iterations)``, or None if the operator's compiled
    solver is unavailable."""
    op, w, load = disc.op, disc.weights, disc.load
    p = np.where(A, p, 0.0)
    carried = dot(w, p)
    p = p * (load / carried) if carried > 0.0 else np.where(A, load / w[A].sum(), 0.0)
    h = disc.gap + op.apply(p)
    u1 = -dot(w[A], h[A]) / w[A].sum()
    D = np.where(A, D_CONTACT * op.diagonal, D_FREE)
    rhs = np.where(A, -(h + u1), 0.0)
    size = float(np.max(np.abs(rhs)))
    rtol = RTOL_MAX if size == 0.0 else min(RTOL_MAX, max(RTOL_MIN, accuracy / size))
    solved = op.solve_newton(D, w, rhs, rtol, MAX_CG)
    if solved is None:  # no compiled FFT path in this process
        return None
    dp, du1, its = solved
    return np.where(A, p + dp, 0.0), u1 + du1, its


def constrained_cg(
    disc: Discretisation, p: np.ndarray, delta: float, tol: float, max_iter: int
) -> Outcome:
    """Constrained conjugate gradient for hard frictionless contact (Polonsky & Keer 1999).

    ``p`` is the starting pressure (any non-negative field inside the expected contact);
    ``delta`` a length scale of the scene (m). It stops when the relative change of the pressure
    in one iteration falls below ``tol``; the residual reported is the complementarity error
    relative to ``delta`` (:func:`complementarity_error`), and ``separation`` is the gap.
    """
    op, g, w, load = disc.op, disc.gap, disc.weights, disc.load
    p = p * (load / dot(w, p))
    d = np.zeros_like(p)
    G_old = 1.0
    restart = True
    change = math.inf
    it = 0
    while it < max_iter:
        it += 1
        h = g + op.apply(p)
        c = p > 0.0
        hbar = dot(w[c], h[c]) / w[c].sum()
        r = np.where(c, h - hbar, 0.0)
        G = dot(w * r, r)
        d = np.where(c, r + (0.0 if restart else G / G_old) * d, 0.0)
        G_old = G
        t = op.apply(d)
        t = np.where(c, t - dot(w[c], t[c]) / w[c].sum(), 0.0)
        td = dot(w * t, d)
        tau = dot(w * r, d) / td if td > 0.0 else 0.0
        p_old = p
        p = np.maximum(p - tau * d, 0.0)
        entering = (~c) & (h - hbar < 0.0)
        restart = bool(np.any(entering))
        p = np.where(entering, p - tau * (h - hbar), p)
        p *= load / dot(w, p)
        change = dot(w, np.abs(p - p_old)) / load
        if change < tol:
            break
    h = g + op.apply(p)
    c = p > 0.0
    u1 = -dot(w[c], h[c]) / w[c].sum()
    gap = h + u1
    err = complementarity_error(gap, c) / delta
    ok = change < tol
    msg = (
        f"{'converged' if ok else 'not converged'}: pressure change {change:.2e} "
        f"(tol {tol:.1e}) after {it} iterations"
    )
    return Outcome(None, u1, err, ok, it, msg, {"pressure_change": change}, p, gap)
