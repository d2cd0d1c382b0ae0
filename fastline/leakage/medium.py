"""Effective-medium (Bruggeman) conductivity of a rough interface (docs/leakage.md §6).

The interface under a uniform nominal pressure p is a two-dimensional random medium: the real
contact area ``A1/A0 = P(q1, p)`` does not conduct, the rest is a film of local gap u with the
Poiseuille conductivity ``s(u) = u^3 / (12 eta)``. Its distribution of gaps is read off the
magnification picture of the critical junction: the area that leaves contact between the
apparent areas ``a`` and ``a - da`` (magnification zeta(a), ``P(zeta) = a``) sits at the gap
``u1(zeta(a))`` (:func:`fastline.theory.interface.edge_separation`), broadened by the rms height
``h(zeta)`` of the roughness not yet resolved (a Gaussian folded at u = 0):

    P(u) = (A1/A0) delta(u) + int_{A1/A0}^{1} da  [G_h(u - u1(a)) + G_h(u + u1(a))],
    h(zeta)^2 = 2 pi int_{zeta q0}^{q1} q C(q) dq.

The effective conductivity solves the effective-medium equation (Bruggeman for ``k = 1``; a
general coordination, S. Kirkpatrick, Rev. Mod. Phys. 45, 574 (1973), for other k)

    int du P(u) (s(u) - s_eff) / (s(u) + k s_eff) = 0,     k = a_c / (1 - a_c),

which has a root ``s_eff > 0`` exactly when ``A1/A0 < a_c``: the symmetric Bruggeman medium
(``a_c = 1/2``) stops conducting at half contact (B.N.J. Persson, Eur. Phys. J. E 43, 25
(2020)). The viscosity cancels: fastline works with the effective gap
``u_eff = (12 eta s_eff)^(1/3)``, a local gap measure like the critical junction's ``u_c``.

Since the real contact area has ``s = 0`` and the area about to leave contact (``a -> A1+``)
has ``u1 -> 0``, both give the integrand ``-1/k``: in the variable a over (0, 1), with
``u1(a) = 0`` for ``a <= A1`` (the critical gap of threshold a is 0 where sealed), the equation
is one integral of a continuous integrand, taken by the midpoint rule (:data:`NODES_AREA`
nodes) and Gauss-Hermite nodes for the broadening (:data:`NODES_SPREAD`).
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike

from fastline._lib.validate import finite_array, in_range, real_array
from fastline.theory.interface import THRESHOLD_BRUGGEMAN, check_threshold, interface_cache

if TYPE_CHECKING:  # annotations only
    from fastline.theory.persson import PerssonTheory

__all__ = ["effective_gap", "effective_gap_of", "medium_table"]

#: midpoint nodes in the apparent area a over (0, 1) (relative change of u_eff 1e-4 from 128
#: to 1024 nodes on the validation surface)
NODES_AREA = 128
#: Gauss-Hermite nodes of the broadening of each gap
NODES_SPREAD = 16
#: step of the table in z = ln(x1 / (x1_s - x1)) and its ends
TABLE_STEP, TABLE_LO, TABLE_HI = 0.25, -18.0, 14.0
#: bisection steps on ln s_eff over a bracket of LOG_SPAN below the largest ln s
BISECTIONS, LOG_SPAN = 72, 2000.0


def effective_gap(
    gaps: ArrayLike,
    weights: ArrayLike | None = None,
    contact_fraction: float = 0.0,
    threshold: float = THRESHOLD_BRUGGEMAN,
) -> float:
    """Effective-medium gap ``u_eff = (12 eta s_eff)^(1/3)`` (m) of a gap distribution.

    Solves ``f int P(u) (s(u) - s_eff) / (s(u) + k s_eff) = 0`` (module docstring), with
    ``s(u) = u^3 / (12 eta)``, a non-conducting phase of area fraction ``contact_fraction`` and
    the open area spread over ``gaps`` with ``weights``.

    Parameters
    ----------
    gaps : array_like
        Gaps u in m (>= 0; 0 conducts nothing, +inf conducts without limit: u_eff is +inf
        where such gaps cover at least ``1 - threshold`` of the area).
    weights : array_like, optional
        Area fractions of the gaps (>= 0); default equal. They are scaled to sum to
        ``1 - contact_fraction``.
    contact_fraction : float
        Area fraction in contact (s = 0), in [0, 1].
    threshold : float
        Contact fraction at which the medium stops conducting, in (0, 1); 0.5 is Bruggeman's
        symmetric medium (``k = 1``).

    Returns
    -------
    float
        u_eff in m: 0 when ``contact_fraction + (area of zero gap) >= threshold`` (so 0,
        without a warning, when every gap is 0: a closed interface conducts nothing); the gap
        itself for a single gap without contact (Poiseuille flow).
    """
    u = real_array("gaps", gaps)
    if u.ndim != 1 or u.size == 0 or np.any(np.isnan(u)) or np.any(u < 0.0):
        raise ValueError("gaps must be a non-empty 1-D array of gaps >= 0 m (inf allowed)")
    w = np.ones_like(u) if weights is None else finite_array("weights", weights, ndim=1)
    if w.shape != u.shape or np.any(w < 0.0) or w.sum() <= 0.0:
        raise ValueError("weights must be >= 0, one per gap, not all 0")
    c = in_range("contact_fraction", contact_fraction, 0.0, 1.0, lo_open=False)
    k = _coordination(check_threshold(threshold))
    w = np.concatenate([w * (1.0 - c) / w.sum(), [c]])
    with np.errstate(divide="ignore"):
        log_s = 3.0 * np.log(np.concatenate([u, [0.0]]))
    return float(np.exp(_solve(log_s[None, :], w[None, :], k)[0] / 3.0))


def _coordination(threshold: float) -> float:
    """``k = a_c / (1 - a_c)`` of the effective-medium equation (1 for Bruggeman)."""
    return threshold / (1.0 - threshold)


def _solve(log_s: np.ndarray, w: np.ndarray, k: float) -> np.ndarray:
    """ln s_eff per row (``-inf`` where the medium does not conduct) by bisection on ln s_eff:
    rows of ln s(u) (``-inf`` for u = 0, ``+inf`` allowed: ``+inf`` where those gaps hold at
    least ``1 - a_c`` of the area) with area weights summing to 1."""
    hi = np.max(log_s, axis=1, where=np.isfinite(log_s), initial=-np.inf)
    # infinite gaps raise s_eff above the largest finite s (without bound at their threshold)
    wide = np.where(np.any(log_s == np.inf, axis=1), LOG_SPAN, 0.0)
    hi = np.where(np.isfinite(hi), hi, 0.0) + 1.0 + wide  # every gap 0 or inf: any bracket
    lo = hi - LOG_SPAN - wide  # s_eff vanishes at the threshold: no bound from the gaps below
    # the residual at s_eff -> 0: every open gap +1, every closed one -1/k; at s_eff -> inf:
    # every infinite gap +1, every other -1/k
    blocked = np.sum(w * np.where(log_s == -np.inf, -1.0 / k, 1.0), axis=1) <= 0.0
    unbounded = np.sum(w * np.where(log_s == np.inf, 1.0, -1.0 / k), axis=1) >= 0.0
    for _ in range(BISECTIONS):
        mid = 0.5 * (lo + hi)
        up = _residual(log_s, w, mid, k) > 0.0  # s_eff below the root
        lo, hi = np.where(up, mid, lo), np.where(up, hi, mid)
    out = 0.5 * (lo + hi)
    out[unbounded] = np.inf
    out[blocked] = -np.inf
    return out


def _residual(log_s, w, log_eff, k) -> np.ndarray:
    """``sum w (s - s_eff) / (s + k s_eff)``, decreasing in s_eff, written with
    ``r = s / s_eff = exp(ln s - ln s_eff)`` clipped against overflow."""
    r = np.exp(np.clip(log_s - log_eff[:, None], -700.0, 700.0))
    return np.sum(w * (r - 1.0) / (r + k), axis=1)


def effective_gap_of(theory: PerssonTheory, p: ArrayLike, threshold: float = 0.5) -> np.ndarray:
    """Effective-medium gap u_eff(p) in m of the interface under uniform nominal pressures p
    (Pa, > 0), by direct quadrature (module docstring; 0 where ``P(q1, p) >= threshold``).
    :func:`fastline.leak_rate` uses a table of it (:func:`medium_table`)."""
    interface_cache(theory)
    p = np.atleast_1d(np.asarray(p, dtype=float))
    if p.ndim != 1 or not np.all(np.isfinite(p)) or np.any(p <= 0.0):
        raise ValueError("p must be finite pressures > 0 Pa")
    k = _coordination(check_threshold(threshold))
    log_s, w = _distribution(theory, p)
    return np.exp(_solve(log_s, w, k) / 3.0)


def _distribution(theory, p: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Rows (one per pressure) of ln s = 3 ln u and area weights of the theory's P(u): the
    contact (weight A1, u = 0), midpoint cells of width 1/N in a above A1 and the cell cut by
    A1, its open part at its own midpoint (so that the medium seals exactly at A1 = a_c)."""
    n = NODES_AREA
    a = (np.arange(n) + 0.5) / n
    gap, zeta = np.zeros((p.size, n + 1)), np.ones((p.size, n + 1))
    for j, a_j in enumerate(a):
        cg = theory.critical_gap(p, threshold=float(a_j))
        gap[:, j], zeta[:, j] = cg.u_c, cg.zeta
    area = np.asarray(theory.contact_area(p), dtype=float)  # A1 = P(q1, p)
    cut = np.minimum(np.floor(area * n).astype(int), n - 1)  # the cell A1 falls in
    weight = np.where(np.arange(n + 1) > cut[:, None], 1.0 / n, 0.0)
    weight[:, n] = 0.0
    rows = np.arange(p.size)
    weight[rows, cut] = (cut + 1.0) / n - area
    for i in rows:  # the open part of the cut cell, at its midpoint
        cg = theory.critical_gap(p[i : i + 1], threshold=float(0.5 * (area[i] + (cut[i] + 1) / n)))
        gap[i, cut[i]], zeta[i, cut[i]] = cg.u_c[0], cg.zeta[0]
    gap[:, n], weight[:, n] = 0.0, area  # the real contact
    h = _unresolved_rms(theory, zeta)
    xi, wi = np.polynomial.hermite_e.hermegauss(NODES_SPREAD)
    spread = np.abs(gap[..., None] + h[..., None] * xi)
    spread = np.where(gap[..., None] > 0.0, spread, 0.0)  # contact stays contact
    w = weight[..., None] * (wi / wi.sum())
    with np.errstate(divide="ignore"):
        log_s = 3.0 * np.log(spread)
    return log_s.reshape(p.size, -1), np.ascontiguousarray(w).reshape(p.size, -1)


def _unresolved_rms(theory, zeta: np.ndarray) -> np.ndarray:
    """``h(zeta) = (2 pi int_{zeta q0}^{q1} q C dq)^(1/2)`` in m (trapezoid in ln q, 4096
    intervals and the spectrum's kinks), cached on the theory."""
    cache = interface_cache(theory)
    tab = cache.get("unresolved_rms")
    psd = theory.psd
    if tab is None:
        q = np.unique(np.concatenate([np.geomspace(psd.q0, psd.q1, 4097), psd.breakpoints()]))
        q = q[(q >= psd.q0) & (q <= psd.q1)]
        f = q * q * np.asarray(psd(q), dtype=float)
        cum = np.concatenate([[0.0], np.cumsum(0.5 * (f[1:] + f[:-1]) * np.diff(np.log(q)))])
        tab = cache["unresolved_rms"] = (np.log(q), 2.0 * math.pi * (cum[-1] - cum))
    ln_q, h2 = tab
    return np.sqrt(np.maximum(np.interp(np.log(zeta * psd.q0), ln_q, h2), 0.0))


class _MediumTable:
    """``ln u_eff`` against ``x1 = w(q1) p / E*`` for one theory and threshold.

    Variable ``z = ln(x1 / (x1_s - x1))``, ``x1_s = erfinv(a_c)`` the sealing point; tabulated
    ``g = ln u_eff - ln(1 - x1/x1_s) / 3`` (u_eff vanishes like ``(x1_s - x1)^(1/3)`` in this
    mean-field medium), cubic spline on a uniform z grid; beyond its ends g continues linearly
    (above) and u_eff linearly in ln x1 (below, where u_eff follows ``u(p)``'s logarithm).
    """

    def __init__(self, theory, threshold: float):
        from scipy.interpolate import CubicSpline  # lazy: only when a table is built
        from scipy.special import erfinv

        self.threshold = threshold
        self.x1_s = float(erfinv(threshold))
        z = np.arange(TABLE_LO, TABLE_HI + 0.5 * TABLE_STEP, TABLE_STEP)
        x1 = self.x1_s / (1.0 + np.exp(-z))
        w1 = 1.0 / math.sqrt(float(theory.psd.cumulative(theory.psd.q1)))
        log_s, w = _distribution(theory, x1 * theory.E_star / w1)
        log_u = _solve(log_s, w, _coordination(threshold)) / 3.0
        self.spline = CubicSpline(z, log_u + np.log1p(np.exp(z)) / 3.0)
        self.z_lo, self.z_hi = float(z[0]), float(z[-1])
        u_lo, u_next = np.exp(log_u[:2])
        self.low = (float(u_lo), float((u_next - u_lo) / (np.log(x1[1]) - np.log(x1[0]))))
        self.ln_x1_lo = float(np.log(x1[0]))

    def summary(self) -> dict:
        """The table's z range and step (``LeakResult.diagnostics['gap_table']``)."""
        return {"z0": self.z_lo, "h": TABLE_STEP, "cells": int(self.spline.c.shape[1])}

    def log_gap(self, x1: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(ln u_eff, sealed) at ``x1 = w(q1) p / E*`` (``+inf`` gap where p = 0)."""
        sealed = x1 >= self.x1_s
        with np.errstate(divide="ignore", invalid="ignore"):
            z = np.log(x1) - np.log(self.x1_s - x1)
            zc = np.clip(z, self.z_lo, self.z_hi)
            g = self.spline(zc) + (z - zc) * np.where(z > self.z_hi, self.spline(self.z_hi, 1), 0.0)
            out = g - np.log1p(np.exp(np.minimum(z, 700.0))) / 3.0
            out = np.where(z > 700.0, g - z / 3.0, out)
            u_low = self.low[0] + self.low[1] * (np.log(x1) - self.ln_x1_lo)
            out = np.where(z < self.z_lo, np.log(np.maximum(u_low, 0.0)), out)
        out[x1 <= 0.0] = np.inf
        out[sealed] = -np.inf
        return out, sealed


def medium_table(theory: PerssonTheory, threshold: float) -> _MediumTable:
    """The effective-medium gap table of (theory, threshold), built on first use (about
    ``NODES_AREA`` critical-gap quadratures of 129 pressures: ~1 s) and cached on the theory."""
    cache = interface_cache(theory)
    key = ("medium_table", threshold)
    tab = cache.get(key)
    if tab is None:
        tab = cache[key] = _MediumTable(theory, threshold)
    return tab
