"""Hard frictionless contact of smooth surfaces (``model="hertz"``): every geometry.

On a :class:`fastline._core.Discretisation`, find ``p >= 0`` and the rigid approach ``u1``
with

    gap_i = g_i + (K p)_i + u1 >= 0,        p_i gap_i = 0,        sum_i w_i p_i = load.

:func:`hard_contact` uses the constrained conjugate gradient of I. A. Polonsky and L. M. Keer,
Wear 231, 206 (1999).
"""

from __future__ import annotations

import math

import numpy as np

from fastline._core import Discretisation, Outcome, dot

__all__ = ["hard_contact"]


def hard_contact(
    disc: Discretisation, p: np.ndarray, delta: float, tol: float, max_iter: int
) -> Outcome:
    """Constrained conjugate gradient for hard frictionless contact (Polonsky & Keer 1999).

    ``p`` is the starting pressure (any non-negative field inside the expected contact);
    ``delta`` a length scale of the scene (m). It stops when the relative change of the pressure
    in one iteration falls below ``tol``; the residual reported is the complementarity error
    (max of ``|gap|`` in the contact and of ``-gap`` outside) relative to ``delta``, and
    ``separation`` is the gap.
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
    err = max(float(np.max(np.abs(gap[c]))), float(max(0.0, -gap.min()))) / delta
    ok = change < tol
    msg = (
        f"{'converged' if ok else 'not converged'}: pressure change {change:.2e} "
        f"(tol {tol:.1e}) after {it} iterations"
    )
    return Outcome(None, u1, err, ok, it, msg, {"pressure_change": change}, p, gap)
