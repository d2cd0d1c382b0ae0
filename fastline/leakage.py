"""Seal leakage from the nominal contact pressure: Persson's critical-junction theory.

The interface at magnification zeta (roughness with ``q < zeta q0`` resolved), for a uniform
nominal pressure p (docs/leakage.md; B.N.J. Persson, C. Yang, J. Phys.: Condens. Matter 20,
315011 (2008), doi:10.1088/0953-8984/20/31/315011; B. Lorenz, B.N.J. Persson, EPL 86, 44006
(2009), doi:10.1209/0295-5075/86/44006), with the moment ``A(q) = pi int_{q0}^q q'^3 C dq'`` of
:mod:`fastline.spectra` written ``B(q)`` here (A is the contact area below), ``a = zeta q0`` and
``m = B(a)``:

* apparent relative contact area ``P(zeta) = erf(y)``, ``y = p / (E* sqrt(m))`` (the P(q, p) of
  the full theory at ``q = a``);
* mean separation in the apparent contact, the Yang-Persson separation of the unresolved
  roughness (q from a to q1) under the pressure ``s E* = p / P(zeta)`` acting there,

      u_bar(zeta) = sqrt(pi) int_a^{q1} dq q^2 C(q) w F(w s),   w = (B(q) - m)^(-1/2),

  with the universal F of :mod:`fastline._special` (the same gamma);
* the separation in the area that leaves contact between zeta and zeta + d zeta,
  ``u1 = u_bar + u_bar'(zeta) P / P'(zeta)`` (area balance; u1 >= u_bar);
* the critical junction: ``P(zeta_c) = a_c`` (percolation threshold, default 0.42), gap
  ``u_c = u1(zeta_c)``; sealed (no percolating channel) when ``P(q1, p) >= a_c``.

Numerics: the moment variable
-----------------------------
Writing the band integral in ``b = B(q) - m = tau^2`` (so ``q^2 C dq = db / (pi q)``) gives

    u_bar = (2/sqrt(pi)) int_0^{T} F(s/tau) / Q(m + tau^2) d tau,    T = sqrt(B(q1) - m),

with ``Q = B^(-1)`` the inverse moment. The ``(q - a)^(-1/2)`` of w and the cancellation in
``B(q) - B(a)`` of the q form are gone: tau^2 *is* the moment counted from a. The integrand is 0
to double precision below ``tau = s / 27.3`` (F underflows). The tau quadrature is Gauss-Legendre
on panels uniform in ln tau from there to T, split where Q has a kink (the breakpoints of C) and
graded geometrically towards T, where at high pressure ``exp(-s^2/tau^2)`` piles the integrand
up (the same two devices as the q quadrature of :mod:`fastline.persson`, in the variable where
they are needed). Q comes from a compiled table: ``ln q`` as a cubic Hermite polynomial of
``ln B`` with the exact slope ``B / (pi q^4 C)`` at every node (nodes at every breakpoint of C,
graded towards q0, below which ``Q = q0 + B / B'(q0)``); exact for power-law pieces of C.

Derivatives in closed form: with ``g(b) = b^(-1/2) F(s b^(-1/2))`` and ``x F'(x) = -beta(x)
exp(-x^2)``, ``beta = gamma + 3 (1 - gamma) erf(x)^2``,

    s du_bar/ds |_m = -(2/sqrt(pi)) int beta(s/tau) exp(-s^2/tau^2) / Q d tau,
    du_bar/dm |_s   = -(1/sqrt(pi)) [ g(T^2) / q1 + 2 int F(s/tau) Q'/Q^2 d tau ],

the second after an integration by parts in b (differentiating ``1/Q(m + b)`` instead of g: the
direct form is a difference of two terms of order 1/s that cancel to order ln s). With
``dP/dm = -y exp(-y^2) / (sqrt(pi) m)`` this gives

    u1 = u_bar - s du_bar/ds - du_bar/dm sqrt(pi) m P exp(y^2) / y,

a sum of non-negative terms (so u1 >= u_bar exactly, and no cancellation anywhere).
"""

from __future__ import annotations

import math
import warnings
from dataclasses import dataclass
from typing import TYPE_CHECKING, Literal

import numba
import numpy as np
from numpy.typing import ArrayLike

from fastline._special import _F, JIT, f_coefficients
from fastline._validate import finite_array, in_range, positive, positive_array
from fastline.diagnostics import ValidityWarning

if TYPE_CHECKING:  # annotations only: persson and the solver are imported on first use
    from fastline.line_contact import LineContactResult
    from fastline.persson import PerssonTheory
    from fastline.point_contact import PointContactResult

__all__ = [
    "LeakResult",
    "CriticalGap",
    "LeakageWarning",
    "leak_rate",
    "leak_rate_profile",
    "apparent_area",
    "mean_separation",
    "edge_separation",
    "critical_gap",
    "THRESHOLD_PERSSON",
    "THRESHOLD_NUMERICAL",
    "THRESHOLD_BRUGGEMAN",
]

#: percolation threshold of the apparent contact area: Persson & Yang 2008 ("about 0.4"),
#: Dapp et al., PRL 108, 244301 (2012) (0.42)
THRESHOLD_PERSSON = 0.42
#: the critical contact area of numerical studies (A. Wang, M.H. Mueser, Tribol. Lett. (2021),
#: doi:10.1007/s11249-020-01378-7, arXiv:2010.13470: "near 0.415")
THRESHOLD_NUMERICAL = 0.415
#: Bruggeman effective-medium threshold (a two-phase 2D medium percolates at 1/2; B.N.J. Persson,
#: Eur. Phys. J. E 43, 25 (2020), arXiv:2003.02007: the effective-medium flow conductivity
#: vanishes at A/A0 = 0.5)
THRESHOLD_BRUGGEMAN = 0.5

_SQRT_PI = math.sqrt(math.pi)
_LN10 = math.log(10.0)
#: F(x) and exp(-x^2) underflow to 0 beyond this argument (exp(-27.3^2) < 1e-323)
_X_CUT = 27.3
#: the gap table stops where u_c falls below this (m): further down the quadrature sums nearly
#: subnormal terms and loses digits
_GAP_FLOOR = 1e-280
#: Q table: first node at q0 (1 + _Q0_GAP); below it Q = q0 + B/B'(q0) (error ~1.5 _Q0_GAP^2)
_Q0_GAP = 1e-7


# ----------------------------------------------------------------------------------------------
# the inverse moment q = Q(B)
# ----------------------------------------------------------------------------------------------
class _MomentTable:
    """``q = Q(B)``, the inverse of the moment ``B(q) = pi int_{q0}^q q'^3 C dq'``, compiled.

    Cells between nodes ``q_j`` (log-uniform in q, graded towards q0, every breakpoint of C),
    each a cubic Hermite polynomial of ``ln q`` in ``y = ln B`` with the exact end slopes
    ``d ln q / d ln B = B / (pi q^4 C(q))`` (one-sided where C jumps). Exact on power-law pieces.
    """

    def __init__(self, psd, per_decade: int = 256):
        # 256 nodes per decade (and 32 per decade of q - q0 near q0): q to 3e-9 and dq/dB to
        # 3e-6 on the paper's surfaces; 64 and 8 gave 3e-7 and 2e-4
        q0, q1 = psd.q0, psd.q1
        bps = psd.breakpoints()
        bps = bps[(bps > q0) & (bps < q1)]
        graded = q0 * (1.0 + np.geomspace(_Q0_GAP, 1.0, 32 * 7 + 1))
        n_log = max(2, int(math.ceil(per_decade * math.log10(q1 / q0))) + 1)
        q = np.unique(np.concatenate([graded, np.geomspace(q0, q1, n_log)[1:], bps, [q1]]))
        q = q[q >= graded[0]]
        B = np.asarray(psd.cumulative(q), dtype=np.float64)
        c_right = np.asarray(psd(q[:-1] * (1.0 + 1e-13)), dtype=np.float64)
        c_left = np.asarray(psd(q[1:] * (1.0 - 1e-13)), dtype=np.float64)
        if np.any(np.diff(B) <= 0.0) or np.any(c_right <= 0.0) or np.any(c_left <= 0.0):
            bad = q[1:][(np.diff(B) <= 0.0) | (c_right <= 0.0) | (c_left <= 0.0)][0]
            raise ValueError(
                f"the leakage theory needs C(q) > 0 on (q0, q1); this spectrum vanishes near "
                f"q = {bad:.4g} 1/m (a gap in the roughness)"
            )
        y = np.log(B)
        lq = np.log(q)
        h = np.diff(y)
        s0 = B[:-1] / (math.pi * q[:-1] ** 4 * c_right)  # d ln q / d ln B at each cell's ends
        s1 = B[1:] / (math.pi * q[1:] ** 4 * c_left)
        d = np.diff(lq)
        coef = np.empty((h.size, 4))
        coef[:, 0] = lq[:-1]
        coef[:, 1] = h * s0
        coef[:, 2] = 3.0 * d - h * (2.0 * s0 + s1)
        coef[:, 3] = -2.0 * d + h * (s0 + s1)
        slope0 = math.pi * q0**3 * float(psd(q0 * (1.0 + 1e-13)))  # B'(q0)
        self.y = np.ascontiguousarray(y)
        self.coef = coef
        self.q_nodes = q
        self.B_nodes = B
        self.lin = np.array([q0, slope0])
        self.B1 = float(B[-1])
        self.q1 = float(q1)
        self.B_breaks = np.ascontiguousarray(psd.cumulative(bps), dtype=np.float64)

    def arrays(self):
        """The tuple the kernels take: (y, coef, (q0, B'(q0)))."""
        return self.y, self.coef, self.lin


def _erfinv(t: float) -> float:
    """erfinv(t) for a threshold in (0, 1) (SciPy imported here, not with the module)."""
    from scipy.special import erfinv

    return float(erfinv(t))


@numba.njit(**JIT)
def _inverse_moment(B, k, qtab):
    """Q(B) and dQ/dB for B > 0 from ``qtab = (y, coef, (q0, B'(q0)))``, with k a cell index
    hint (walks forward: callers ask in increasing B). Returns q, dq/dB, the new hint."""
    y, coef, lin = qtab
    ly = math.log(B)
    if ly <= y[0]:
        return lin[0] + B / lin[1], 1.0 / lin[1], 0
    n = coef.shape[0]
    if k >= n or y[k] > ly:
        k = 0
    while k < n - 1 and y[k + 1] < ly:
        k += 1
    h = y[k + 1] - y[k]
    t = min((ly - y[k]) / h, 1.0)
    c = coef[k]
    lq = c[0] + t * (c[1] + t * (c[2] + t * c[3]))
    dl = (c[1] + t * (2.0 * c[2] + 3.0 * t * c[3])) / h  # d ln q / d ln B
    q = math.exp(lq)
    return q, q * dl / B, k


# ----------------------------------------------------------------------------------------------
# band integrals in tau (see the module docstring)
# ----------------------------------------------------------------------------------------------
class _TauRule:
    """Reference Gauss-Legendre rules on [0, 1] and panel densities, sized by ``rtol``."""

    def __init__(self, rtol: float):
        # max relative error of u_c against a 20-point, 8-panels-per-decade, 12-level rule,
        # 103 pressures from 1e-10 E* to near sealing on the paper's three surfaces:
        # 1.4e-6 / 2.8e-9 / 6.3e-10 for the three settings; the top grading sets it
        if rtol >= 1e-4:
            order, per_decade, levels, graded = 8, 1.5, 5, 8
        elif rtol >= 1e-7:
            order, per_decade, levels, graded = 10, 2.0, 6, 12
        else:
            order, per_decade, levels, graded = 14, 4.0, 8, 16
        t, w = np.polynomial.legendre.leggauss(order)
        tg, wg = np.polynomial.legendre.leggauss(graded)
        self.t, self.w = 0.5 * (t + 1.0), 0.5 * w
        self.tg, self.wg = 0.5 * (tg + 1.0), 0.5 * wg
        self.per_decade = per_decade
        self.levels = levels


#: geometric grading of the top panel (as the q quadrature of fastline.persson)
_TOP_RATIO = 0.15


@numba.njit(**JIT)
def _panel(la, lb, m, s, t, w, fc, qtab, k, acc):
    """Add one Gauss-Legendre panel [la, lb] in ln tau to acc = (I0, I2, J);
    ``fc = (gamma, c1, c2, c3, b2)`` are F's parameters (bracket ``gamma + b2 erf^2``).
    Returns the Q-table hint."""
    gamma, c1, c2, c3, b3 = fc
    width = lb - la
    for i in range(t.shape[0]):
        tau = math.exp(la + width * t[i])
        wt = w[i] * width * tau
        x = s / tau
        if x > _X_CUT:
            continue
        q, dq, k = _inverse_moment(m + tau * tau, k, qtab)
        F = _F(max(x, 1e-300), gamma, c1, c2, c3)
        er = math.erf(x)
        acc[0] += wt * F / q
        acc[1] += wt * (gamma + b3 * er * er) * math.exp(-x * x) / q
        acc[2] += wt * F * dq / (q * q)
    return k


@numba.njit(**JIT)
def _graded_top(lo, lb, m, s, rule, fc, qtab, k, acc):
    """The top panel [lo, lb] in ln tau, split geometrically towards lb (widths shrinking by
    _TOP_RATIO), where near sealing exp(-s^2/tau^2) piles the integrand up against tau = T."""
    tg, wg, levels = rule[2], rule[3], rule[5]
    h = lb - lo
    a = lo
    for lev in range(1, levels + 1):
        b = lb - h * _TOP_RATIO**lev
        k = _panel(a, b, m, s, tg, wg, fc, qtab, k, acc)
        a = b
    return _panel(a, lb, m, s, tg, wg, fc, qtab, k, acc)


@numba.njit(**JIT)
def _band_integrals(m, s, band, rule, fc, qtab, acc):
    """acc <- (I0, I2, J) = int over tau in (0, sqrt(B1 - m)) of F/Q, beta e^(-x^2)/Q and
    F Q'/Q^2 (x = s/tau), ``band = (B1, q1, B at the breakpoints of C)``. Panels uniform in
    ln tau from s/27.3 (below, every integrand is 0), split at the breakpoints, the top one
    graded."""
    B1, _, B_breaks = band
    t, w, per_decade = rule[0], rule[1], rule[4]
    acc[0] = acc[1] = acc[2] = 0.0
    delta = B1 - m
    tau_lo = s / _X_CUT
    if delta <= tau_lo * tau_lo:
        return
    la = math.log(tau_lo)
    k = 0
    nb = B_breaks.shape[0]
    for j in range(nb + 1):  # segments between the breakpoints above m, then the last one
        d = B_breaks[j] - m if j < nb else delta
        if d <= tau_lo * tau_lo:
            continue
        lb = 0.5 * math.log(d)
        if lb <= la:
            continue
        n = max(1, int(math.ceil(per_decade * (lb - la) / _LN10)))
        h = (lb - la) / n
        plain = n if j < nb else n - 1
        for i in range(plain):
            k = _panel(la + i * h, la + (i + 1) * h, m, s, t, w, fc, qtab, k, acc)
        if j == nb:
            k = _graded_top(la + plain * h, lb, m, s, rule, fc, qtab, k, acc)
        la = lb


@numba.njit(**JIT)
def _interface(m, p, E_star, band, rule, fc, qtab, acc):
    """(P, u_bar, u1) at moment m = B(zeta q0) >= 0 and nominal pressure p > 0."""
    B1, q1, _ = band
    yy = p / (E_star * math.sqrt(m)) if m > 0.0 else math.inf  # m = 0 at zeta = 1
    P = math.erf(yy)
    s = p / (E_star * P)
    _band_integrals(m, s, band, rule, fc, qtab, acc)
    two = 2.0 / _SQRT_PI
    u_bar = two * acc[0]
    delta = B1 - m
    edge = 0.0
    if delta > 0.0 and s * s < 745.0 * delta:  # g(T^2)/q1, the boundary term at q1
        x = s / math.sqrt(delta)
        edge = _F(max(x, 1e-300), fc[0], fc[1], fc[2], fc[3]) / (math.sqrt(delta) * q1)
    dm = edge + 2.0 * acc[2]  # = -sqrt(pi) du_bar/dm at fixed s, >= 0
    if dm == 0.0:  # every scale in contact: nothing left to separate
        return P, u_bar, u_bar + two * acc[1]
    # P / (dP/dm) = -sqrt(pi) m P exp(y^2) / y: +inf where P = 1 to double precision (y > 26.6)
    growth = yy * yy + math.log(m * P / yy) if m > 0.0 and yy < 27.0 else math.inf
    factor = math.exp(growth) if growth < 709.0 else math.inf
    return P, u_bar, u_bar + two * acc[1] + dm * factor


@numba.njit(**JIT)
def _interface_vec(m, p, E_star, band, rule, fc, qtab, P, u_bar, u1):
    acc = np.empty(3)
    for i in range(m.shape[0]):
        P[i], u_bar[i], u1[i] = _interface(m[i], p[i], E_star, band, rule, fc, qtab, acc)


@numba.njit(**JIT)
def _critical_vec(x1, X_t, t, E_star, band, rule, fc, qtab, gap, qc, sealed):
    """u_c = u1(zeta_c) and q_c = zeta_c q0 for x1 = w(q1) p / E* (docs/leakage.md §3).

    ``P(zeta_c) = t`` has the closed-form root ``B(q_c) = m = B1 (x1 / X_t)^2``,
    ``X_t = erfinv(t)``; sealed where ``erf(x1) >= t`` (gap 0, q_c = q1)."""
    B1, q1, _ = band
    acc = np.empty(3)
    for i in range(x1.shape[0]):
        sealed[i] = math.erf(x1[i]) >= t
        if sealed[i]:
            gap[i] = 0.0
            qc[i] = q1
            continue
        r = x1[i] / X_t
        m = B1 * r * r
        p = x1[i] * E_star * math.sqrt(B1)
        gap[i] = _interface(m, p, E_star, band, rule, fc, qtab, acc)[2]
        qc[i] = _inverse_moment(m, 0, qtab)[0] if m > 0.0 else qtab[2][0]


@numba.njit(**JIT)
def _log_gap_kernel(x1, t, X_t, kappa0, z0, h, cf, slope_hi, low, out, sealed):
    """ln u_c at ``x1 = w(q1) p / E*`` from the gap table (see :class:`_GapTable`).

    ``low = (u_lo, v_lo, u0, ln(E* sqrt(B1)))``: below ``z0`` the law
    ``u_c = u_lo + u0 (v_lo - ln p)``. Sealed where ``erf(x1) >= t`` (ln u_c = -inf); p = 0
    gives ln u_c = +inf (no contact, no resistance)."""
    n = cf.shape[0]
    z_hi = z0 + n * h
    for i in range(x1.shape[0]):
        x = x1[i]
        sealed[i] = math.erf(x) >= t
        if sealed[i]:
            out[i] = -math.inf
            continue
        if x <= 0.0:
            out[i] = math.inf
            continue
        r = x / X_t
        if r >= 1.0:  # erf(x) < t within an ulp of the threshold: the gap closes to 0
            out[i] = -math.inf
            continue
        z = math.log(r * r) - math.log((1.0 - r) * (1.0 + r))
        if z < z0:
            out[i] = math.log(low[0] + low[2] * (low[1] - math.log(x) - low[3]))
            continue
        if z >= z_hi:
            c = cf[n - 1]
            g = c[0] + h * (c[1] + h * (c[2] + h * c[3])) + slope_hi * (z - z_hi)
        else:
            k = min(int((z - z0) / h), n - 1)
            tt = z - (z0 + k * h)
            c = cf[k]
            g = c[0] + tt * (c[1] + tt * (c[2] + tt * c[3]))
        out[i] = g - kappa0 * math.exp(min(z, 709.0))


# ----------------------------------------------------------------------------------------------
# per-theory state (built lazily, cached on the theory object)
# ----------------------------------------------------------------------------------------------
class _Spectrum:
    """What the kernels need of one theory: the Q table, the tau rule, F's coefficients."""

    def __init__(self, theory):
        if theory._area is not None:
            raise ValueError(
                f"leakage needs a theory whose contact area is erf(x): variant "
                f"{theory.variant!r} corrects the contact-area recursion, which the "
                "critical-junction interface (docs/leakage.md) does not; use 'yang-persson-energy' "
                "or 'yang-persson-printed'"
            )
        self.table = _MomentTable(theory.psd)
        r = _TauRule(theory.rtol)
        self.rule = (r.t, r.w, r.tg, r.wg, r.per_decade, r.levels)
        self.b2 = theory._bracket[1]
        self.coef = f_coefficients(theory.gamma, self.b2)
        self.E_star = theory.E_star
        self.gamma = theory.gamma

    def kernel_args(self):
        """(E*, band, rule, fc, qtab): what the interface kernels take after their arrays."""
        tb = self.table
        band = (tb.B1, tb.q1, tb.B_breaks)
        return self.E_star, band, self.rule, (self.gamma, *self.coef, self.b2), tb.arrays()


def _state(theory) -> dict:
    """The leakage cache of a theory (a dict stored on the theory object itself)."""
    from fastline.persson import PerssonTheory

    if not isinstance(theory, PerssonTheory):
        raise TypeError(f"theory must be a fastline PerssonTheory, got {type(theory).__name__}")
    return theory.__dict__.setdefault("_leakage_cache", {})


def _spectrum(theory) -> _Spectrum:
    cache = _state(theory)
    sp = cache.get("spectrum")
    if sp is None:
        sp = cache["spectrum"] = _Spectrum(theory)
    return sp


def _zeta_moment(theory, zeta, p):
    """Validated, broadcast (zeta, p) and the moment m = B(zeta q0), all flat float64."""
    psd = theory.psd
    zeta = finite_array("zeta", zeta)
    zmax = psd.q1 / psd.q0
    if np.any((zeta < 1.0) | (zeta > zmax)):
        raise ValueError(f"zeta must lie in [1, q1/q0] = [1, {zmax:.6g}]")
    p = positive_array("p", p)
    zeta, p = np.broadcast_arrays(zeta, p)
    shape = zeta.shape
    m = np.asarray(psd.cumulative(zeta.ravel() * psd.q0), dtype=np.float64)
    return shape, np.ascontiguousarray(m), np.ascontiguousarray(p.ravel(), dtype=np.float64)


def _interface_arrays(theory, zeta, p):
    shape, m, p = _zeta_moment(theory, zeta, p)
    sp = _spectrum(theory)
    P, u_bar, u1 = np.empty_like(m), np.empty_like(m), np.empty_like(m)
    _interface_vec(m, p, *sp.kernel_args(), P, u_bar, u1)
    return shape, P, u_bar, u1


# ----------------------------------------------------------------------------------------------
# public: the interface at magnification zeta (PerssonTheory methods delegate here)
# ----------------------------------------------------------------------------------------------
def apparent_area(theory: PerssonTheory, zeta: ArrayLike, p: ArrayLike) -> np.ndarray:
    """Apparent relative contact area ``P(zeta) = erf(w(zeta q0) p / E*)`` (dimensionless).

    docs/leakage.md §1; the ``P(q, p)`` of the full theory at ``q = zeta q0``, so it equals
    ``theory.contact_area(p, zeta * q0)``. It falls from 1 at ``zeta = 1`` to the real contact
    area at ``zeta = q1/q0``.

    Parameters
    ----------
    theory : PerssonTheory
    zeta : array_like
        Magnification, in ``[1, q1/q0]``.
    p : array_like
        Uniform nominal pressure in Pa (> 0); broadcasts against ``zeta``.

    Returns
    -------
    ndarray
        P(zeta) in [0, 1], shaped like the broadcast of ``zeta`` and ``p``.
    """
    _state(theory)
    shape, m, p = _zeta_moment(theory, zeta, p)
    from scipy.special import erf  # here, not at import (~0.2 s)

    with np.errstate(divide="ignore"):
        x = p / (theory.E_star * np.sqrt(m))
    return erf(x).reshape(shape)


def mean_separation(theory: PerssonTheory, zeta: ArrayLike, p: ArrayLike) -> np.ndarray:
    """Mean separation ``u_bar(zeta, p)`` in m of the surfaces inside the apparent contact at
    magnification zeta (docs/leakage.md §2; Persson & Yang 2008, with the separation of Yang &
    Persson, J. Phys.: Condens. Matter 20, 215214 (2008)).

    The Yang-Persson separation of the roughness not resolved at zeta (q from ``zeta q0`` to q1)
    under the pressure ``p / P(zeta)`` acting on the apparent contact; ``u_bar(1, p)`` is
    ``theory.separation(p)`` and ``u_bar(q1/q0, p) = 0``. Vectorised and compiled; relative
    accuracy ``theory.rtol`` (checked against a SciPy quad reference in the tests).

    Parameters
    ----------
    theory : PerssonTheory
    zeta : array_like
        Magnification, in ``[1, q1/q0]``.
    p : array_like
        Uniform nominal pressure in Pa (> 0); broadcasts against ``zeta``.

    Returns
    -------
    ndarray
        u_bar in m (>= 0), shaped like the broadcast of ``zeta`` and ``p``.
    """
    shape, _, u_bar, _ = _interface_arrays(theory, zeta, p)
    return u_bar.reshape(shape)


def edge_separation(theory: PerssonTheory, zeta: ArrayLike, p: ArrayLike) -> np.ndarray:
    """Persson's ``u1(zeta) = u_bar + u_bar'(zeta) P(zeta) / P'(zeta)`` in m (docs/leakage.md §2).

    The mean separation in the area that leaves the apparent contact when the magnification
    grows from zeta to zeta + d zeta (the edges of the contact patches); at the critical
    magnification it is the gap of the critical constriction. ``u1 >= u_bar``. The derivatives
    are in closed form (module docstring). It is ``+inf`` where ``P(zeta)`` rounds to 1
    (``w p/E* > 27``, e.g. ``zeta = 1``): no area leaves contact there.

    Parameters
    ----------
    theory : PerssonTheory
    zeta : array_like
        Magnification, in ``[1, q1/q0]``.
    p : array_like
        Uniform nominal pressure in Pa (> 0); broadcasts against ``zeta``.

    Returns
    -------
    ndarray
        u1 in m (>= u_bar; +inf where P(zeta) = 1), shaped like the broadcast of ``zeta``, ``p``.
    """
    shape, _, _, u1 = _interface_arrays(theory, zeta, p)
    return u1.reshape(shape)


# ----------------------------------------------------------------------------------------------
# the critical junction (docs/leakage.md §3)
# ----------------------------------------------------------------------------------------------
@dataclass(frozen=True)
class CriticalGap:
    """The critical constriction of a uniform nominal pressure (arrays shaped like ``p``).

    Attributes
    ----------
    u_c : ndarray
        ``u_c = u1(zeta_c)`` in m; 0 where sealed (and where it underflows, below 1e-308 m).
    zeta : ndarray
        Critical magnification ``zeta_c`` (``P(zeta_c) = threshold``); ``q1/q0`` where sealed.
    sealed : ndarray of bool
        ``P(q1, p) >= threshold``: no non-contact channel percolates at any magnification.
    threshold : float
        The percolation threshold used.
    """

    u_c: np.ndarray
    zeta: np.ndarray
    sealed: np.ndarray
    threshold: float


def _threshold(threshold) -> float:
    return in_range("threshold", threshold, 0.0, 1.0, lo_open=True, hi_open=True)


def _x1(theory, p: np.ndarray) -> np.ndarray:
    """``w(q1) p / E*``, computed exactly as :meth:`PerssonTheory.contact_area` does, so that
    the sealed flag agrees with ``contact_area(p) >= threshold`` to the last bit."""
    w1 = 1.0 / math.sqrt(float(theory.psd.cumulative(theory.psd.q1)))
    return np.ascontiguousarray(w1 * p / theory.E_star, dtype=np.float64)


def critical_gap(
    theory: PerssonTheory, p: ArrayLike, threshold: float = THRESHOLD_PERSSON
) -> CriticalGap:
    """Gap ``u_c`` of the critical constriction at a uniform nominal pressure p (leakage.md §3).

    Solves ``P(zeta_c) = threshold`` (P falls monotonically with zeta; the root is in closed
    form, ``A(zeta_c q0) = (p / (E* erfinv(threshold)))^2``, with the inverse moment table) and
    returns ``u_c = u1(zeta_c)`` (:func:`edge_separation`). Where the real contact area already
    exceeds the threshold, ``P(q1, p) >= threshold``, no channel percolates: sealed, ``u_c = 0``.
    Direct quadrature (about 20 us per pressure); :func:`leak_rate` uses a table instead.

    Parameters
    ----------
    theory : PerssonTheory
    p : array_like
        Nominal pressure in Pa (> 0).
    threshold : float
        Percolation threshold of the apparent contact area, in (0, 1): 0.42 (Persson & Yang
        2008, "about 0.4"; Dapp et al., PRL 108, 244301 (2012)), 0.415 (numerical studies),
        0.5 (Bruggeman effective medium).

    Returns
    -------
    CriticalGap
    """
    threshold = _threshold(threshold)
    _state(theory)
    p = positive_array("p", p)
    sp = _spectrum(theory)
    x1 = _x1(theory, p.ravel())
    gap, qc = np.empty_like(x1), np.empty_like(x1)
    sealed = np.empty(x1.shape, dtype=np.bool_)
    X_t = _erfinv(threshold)
    _critical_vec(x1, X_t, threshold, *sp.kernel_args(), gap, qc, sealed)
    qc = _polish_root(theory.psd, qc, sp.table.B1 * (x1 / X_t) ** 2, ~sealed)
    shape = p.shape
    return CriticalGap(
        u_c=gap.reshape(shape),
        zeta=(qc / theory.psd.q0).reshape(shape),
        sealed=sealed.reshape(shape),
        threshold=threshold,
    )


def _polish_root(psd, q, m, live, steps: int = 2):
    """Newton steps on ``A(q) = m`` with the spectrum itself (the table's q is good to ~1e-9;
    near q0, where A ~ q - q0, zeta_c - 1 needs the absolute accuracy)."""
    q = np.clip(q, psd.q0, psd.q1)
    for _ in range(steps):
        qs = q[live]
        slope = math.pi * qs**3 * psd(qs)
        step = np.divide(
            psd.cumulative(qs) - m[live], slope, out=np.zeros_like(qs), where=slope > 0
        )
        q[live] = np.clip(qs - step, psd.q0, psd.q1)
    return q


class _GapTable:
    """``ln u_c(p)`` for one theory and threshold, for the leak rate of a pressure profile.

    Variable ``z = ln(m / (B1 - m))`` with ``m = A(zeta_c q0) = B1 (x1 / X_t)^2``: about
    ``2 ln p`` at low pressure and ``-ln(B1 - m)`` as the seal closes. Tabulated:
    ``g(z) = ln u_c + kappa0 e^z``, ``kappa0 e^z = s^2 / (B1 - m)`` the exponent with which
    u_c vanishes at sealing (module docstring), a cubic spline on a uniform z grid (error
    O(h^4): measured 1.1e-6 / 1.3e-7 / 7e-8 in ln u_c at h = 0.1 on the paper's surfaces, H = 1
    the worst; ``h`` is chosen from the theory's rtol). Below ``z_lo`` (where u_c follows
    ``u_c(p) = u(p/a_c) + u0`` to within rtol, the theory's exponential law shifted by u0) the
    law ``u_c = u_lo + u0 ln(p_lo/p)``. The grid ends where ``kappa0 e^z = 600`` (or u_c =
    1e-280 m if that comes first: the quadrature sums nearly subnormal terms beyond); above it
    g continues linearly (u_c < 1e-250 m: a seal that is closed for any practical purpose).
    """

    def __init__(self, theory, threshold: float):
        sp = _spectrum(theory)
        self.threshold = threshold
        self.X_t = _erfinv(threshold)
        self.kappa0 = (self.X_t / threshold) ** 2
        rtol = theory.rtol
        h = 0.2 if rtol >= 1e-4 else (0.075 if rtol >= 1e-7 else 0.03)
        self._args = sp.kernel_args()
        B1 = sp.table.B1
        self._ln_pz = math.log(theory.E_star * math.sqrt(B1))
        u0 = theory.exponential_fit().u0
        z_lo = self._low_end(u0, rtol)
        z_hi = math.log(600.0 / self.kappa0)
        n = max(4, int(math.ceil((z_hi - z_lo) / h)) + 1)
        z = z_lo + h * np.arange(n)
        gap = self._direct(z)
        good = gap > _GAP_FLOOR
        if not good.all():  # near underflow before z_hi (only for extreme spectra)
            n = max(4, int(np.argmin(good)))
            z, gap = z[:n], gap[:n]
        g = np.log(gap) + self.kappa0 * np.exp(z)
        from scipy.interpolate import CubicSpline  # lazy: only when a table is built

        spline = CubicSpline(z, g)
        self.cf = np.ascontiguousarray(spline.c[::-1].T)  # Horner order in (z - z_k)
        self.slope_hi = float(spline(z[-1], 1))
        self.z0, self.h = float(z[0]), h
        self.low = np.array([gap[0], self._ln_p(z[0]), u0, self._ln_pz])

    def _x1_of(self, z):
        r = np.sqrt(1.0 / (1.0 + np.exp(-np.asarray(z, dtype=np.float64))))
        return np.ascontiguousarray(r * self.X_t)

    def _ln_p(self, z) -> float:
        return float(np.log(self._x1_of([z]))[0]) + self._ln_pz

    def _direct(self, z):
        x1 = self._x1_of(z)
        gap, qc = np.empty_like(x1), np.empty_like(x1)
        _critical_vec(x1, self.X_t, self.threshold, *self._args, gap, qc, np.empty(x1.size, bool))
        return gap

    def _low_end(self, u0: float, rtol: float) -> float:
        """Highest z (steps of 2 from -20) below which u_c = u_lo + u0 ln(p_lo/p) holds."""
        z = -20.0
        while z > -300.0:
            u_a, u_b = self._direct([z, z + 2.0])
            if abs(u_a - u_b - u0 * (self._ln_p(z + 2.0) - self._ln_p(z))) <= 0.1 * rtol * u_a:
                break
            z -= 2.0
        return z

    def log_gap(self, x1: np.ndarray):
        """(ln u_c, sealed) at ``x1 = w(q1) p / E*`` (contiguous float64)."""
        out = np.empty_like(x1)
        sealed = np.empty(x1.shape, dtype=np.bool_)
        _log_gap_kernel(
            x1,
            self.threshold,
            self.X_t,
            self.kappa0,
            self.z0,
            self.h,
            self.cf,
            self.slope_hi,
            self.low,
            out,
            sealed,
        )
        return out, sealed


def _gap_table(theory, threshold: float) -> _GapTable:
    """The gap table of (theory, threshold), built on first use and cached on the theory."""
    cache = _state(theory)
    key = ("gap_table", threshold)
    tab = cache.get(key)
    if tab is None:
        tab = cache[key] = _GapTable(theory, threshold)
    return tab


# ----------------------------------------------------------------------------------------------
# leak rate of a pressure profile: strips in series (docs/leakage.md §4)
# ----------------------------------------------------------------------------------------------
METHODS = ("critical-junction",)
#: warn when fewer roll-off wavelengths 2 pi/qr than this fit across the region holding 90 % of
#: the flow resistance (the theory averages over many junctions in series)
MIN_JUNCTIONS = 5.0
#: warn when the Knudsen number (mean free path / u_c at the strip of highest resistance)
#: exceeds this: the flow is no longer viscous (slip flow starts near 0.01-0.1)
MAX_KNUDSEN = 0.1
#: warn when the fluid pressure drop exceeds this fraction of the peak contact pressure
MAX_FLUID_PRESSURE_RATIO = 0.1
#: radial flow (point contacts): an orifice wider than this share of the pressure's half width at
#: half maximum changes the contact pressure, which is taken from the solid (unperforated) contact
MAX_ORIFICE_SHARE = 0.1


class LeakageWarning(ValidityWarning):
    """A leak-rate estimate is outside the assumptions of the critical-junction theory."""


#: the warning of a leak rate computed from a solve that did not converge (one text for every
#: scene, so that a loop shows it once)
UNCONVERGED = (
    "fastline.leak_rate: the contact's solve did not converge (result.converged is False): "
    "the leak rate is that of an unconverged pressure profile (LeakResult.converged says so)"
)


@dataclass
class LeakResult:
    """The leak rate of a seal and where along the contact it is decided.

    Arrays are per strip (cell) of the pressure profile: strips across a line contact
    (``inner_radius`` None), or rings around a point contact's axis (radial flow from
    ``inner_radius`` outwards). Units: m, Pa, s.

    Attributes
    ----------
    Q : float
        Volume flow across the contact in m^3/s: along x for the seal length given,
        ``Q = conductance * length * pressure_drop``; radially outwards through the whole ring,
        ``Q = conductance * pressure_drop``. 0 when sealed.
    conductance : float
        Conductance per unit seal length ``1 / int dx (12 eta / u_c^3)`` in m^2/(Pa s); radial
        flow: of the whole contact, ``1 / int_{r_in} dr 12 eta / (2 pi r u_c^3)`` in
        m^3/(Pa s).
    sealed : bool
        Some strip has ``P(q1, p) >= threshold``: no channel percolates there, no leak.
    x, pressure : ndarray
        Strip centres in m (radii of the ring cells for radial flow) and the nominal pressure
        in Pa.
    u_c : ndarray
        Critical gap ``u_c(p(x))`` in m (0 in sealed strips; +inf where p = 0).
    sigma : ndarray
        Local conductance ``u_c^3 / (12 eta)`` in m^3/(Pa s).
    sealed_strips : ndarray of bool
        The strips with ``P(q1, p) >= threshold`` (radial flow: only those the flow crosses,
        outside ``inner_radius``).
    resistance_share, cumulative_share : ndarray
        Each strip's share of the flow resistance ``int dx / sigma`` and its running sum from
        ``x[0]`` (when sealed, the sealed strips share it equally; 0 inside ``inner_radius``).
    share_in_fwhm : float
        Share of the resistance in the strips where ``p >= max(p) / 2``.
    resistance_width : float
        Width in m of the region holding the central 90 % of the resistance (between 5 % and 95 %
        of ``cumulative_share``): where the leak is decided.
    pressure_drop, viscosity, length, threshold : float
        The inputs (Pa, Pa s, m, -); ``length`` is None for radial flow.
    method : str
    converged : bool
        Whether the pressure profile it post-processes converged (True for a given profile).
    diagnostics : dict
        ``n_strips``, ``n_sealed``, ``peak_pressure`` (Pa), ``fluid_pressure_ratio``
        (``pressure_drop / peak_pressure``), ``rolloff_wavelength`` (m, ``2 pi/qr``),
        ``junctions_across`` (``resistance_width / rolloff_wavelength``), ``min_gap`` (m, u_c
        at the strip of highest resistance), ``knudsen`` (or None), ``gap_table`` (z range and
        step of the table), ``warnings`` (the messages behind the :class:`LeakageWarning` s);
        radial flow adds ``orifice_share`` (``inner_radius`` over the half width at half
        maximum of p).
    inner_radius : float or None
        Radial flow: the radius in m where the fluid enters (the orifice of a seat); None for
        flow across a line contact.
    """

    Q: float
    conductance: float
    sealed: bool
    x: np.ndarray
    pressure: np.ndarray
    u_c: np.ndarray
    sigma: np.ndarray
    sealed_strips: np.ndarray
    resistance_share: np.ndarray
    cumulative_share: np.ndarray
    share_in_fwhm: float
    resistance_width: float
    pressure_drop: float
    viscosity: float
    length: float | None
    threshold: float
    method: str
    converged: bool
    diagnostics: dict
    inner_radius: float | None = None

    def __repr__(self):
        radial = "" if self.inner_radius is None else f", inner_radius={self.inner_radius:.4g} m"
        return (
            f"LeakResult(Q={self.Q:.4g} m^3/s{radial}, sealed={self.sealed}, "
            f"share_in_fwhm={self.share_in_fwhm:.3g}, resistance_width={self.resistance_width:.4g}"
            f" m, converged={self.converged})"
        )


#: points per decade of q where a spectrum without a known roll-off is searched for it
_ROLLOFF_SEARCH_PER_DECADE = 64


def _rolloff_wavenumber(psd) -> float:
    """The roll-off wavenumber qr (1/m): where ``q^2 C(q)``, the height variance per unit
    ln q, peaks. That is qr itself for a self-affine spectrum (C flat below qr, falling as
    ``q^(-2 - 2H)`` above), the smallest over the parts of a sum; for any other spectrum
    (a measured table) the peak is searched on its nodes or on a log grid. A spectrum that
    rises to its lowest wavenumber has it at q0: the roll-off is then not resolved, and
    ``2 pi / q0`` (the longest wavelength the spectrum holds) is a lower bound of the roll-off
    wavelength."""
    parts = getattr(psd, "parts", None)
    if parts is not None:
        return min(_rolloff_wavenumber(part) for part in parts)
    qr = getattr(psd, "qr", None)
    if qr is not None:
        return float(qr)
    q = getattr(psd, "q", None)
    if q is None or np.ndim(q) != 1:
        decades = math.log10(psd.q1 / psd.q0)
        q = np.geomspace(psd.q0, psd.q1, max(2, int(decades * _ROLLOFF_SEARCH_PER_DECADE) + 1))
    q = np.asarray(q, dtype=float)
    q = q[(q >= psd.q0) & (q <= psd.q1)]
    return float(q[int(np.argmax(q * q * np.asarray(psd(q), dtype=float)))])


def _cell_edges(x: np.ndarray, inner_radius: float | None) -> tuple[np.ndarray, np.ndarray]:
    """Lower and upper edges (m) of the cells centred at x: halfway between centres, the end
    cells symmetric (width dx on a uniform grid). Radial flow: the edges are radii, clipped at
    0 (the axis cell of a point contact is a disc) and at ``inner_radius`` (the flow starts
    there; cells inside it have zero width)."""
    mid = 0.5 * (x[1:] + x[:-1])
    edges = np.concatenate([[2.0 * x[0] - mid[0]], mid, [2.0 * x[-1] - mid[-1]]])
    if inner_radius is not None:
        edges = np.maximum(edges, inner_radius)
    return edges[:-1], edges[1:]


def _log_geometry(lo: np.ndarray, hi: np.ndarray, radial: bool) -> np.ndarray:
    """ln of each cell's geometric factor of resistance: its width (strips, per unit seal
    length: ``R = width 12 eta / u_c^3``) or ``ln(hi / lo) / (2 pi)`` (a ring crossed
    radially: ``R = int dr 12 eta / (2 pi r u_c^3)``); -inf for the cells the flow does not
    cross."""
    with np.errstate(divide="ignore"):
        if not radial:
            return np.log(hi - lo)
        return np.log(np.log(hi / lo)) - math.log(2.0 * math.pi)


def _scalars(pressure_drop, viscosity, length, threshold, method, mean_free_path):
    pressure_drop = positive("pressure_drop", pressure_drop, "Pa")
    viscosity = positive("viscosity", viscosity, "Pa s")
    length = None if length is None else positive("length", length, "m")
    threshold = _threshold(threshold)
    if method not in METHODS:
        raise ValueError(
            f"method must be one of {METHODS}, got {method!r} (the effective-medium method is "
            "not implemented: the theory's gap distribution P(u) could not be sourced; see "
            "docs/leakage.md, 'The effective-medium method: not included, and why')"
        )
    if mean_free_path is not None:
        mean_free_path = positive("mean_free_path", mean_free_path, "m")
    return pressure_drop, viscosity, length, threshold, mean_free_path


def _profile(x, p, inner_radius=None):
    x = finite_array("x", x, ndim=1)
    p = finite_array("p", p, ndim=1)
    if x.size < 2:
        raise ValueError(f"x must hold at least 2 strip centres, got {x.size}")
    if p.shape != x.shape:
        raise ValueError(f"p must have the same length as x ({x.size}), got {p.size}")
    if np.any(np.diff(x) <= 0.0):
        raise ValueError("x must be strictly increasing (strip centres in m)")
    if np.any(p < 0.0):
        raise ValueError("p must be >= 0 Pa everywhere (allowed range [0, inf))")
    if not np.any(p > 0.0):
        raise ValueError("p must be > 0 somewhere (an unloaded profile has no contact)")
    if inner_radius is None:
        return x, p, None
    if x[0] < 0.0:
        raise ValueError(f"x must be radii >= 0 m for radial flow, got x[0] = {x[0]:.6g}")
    inner_radius = positive("inner_radius", inner_radius, "m")
    outer = float(_cell_edges(x, None)[1][-1])
    if inner_radius >= outer:
        raise ValueError(
            f"inner_radius must be below the outer edge of the profile, {outer:.6g} m "
            f"(allowed range (0, {outer:.6g}) m), got {inner_radius:.6g}"
        )
    return x, p, inner_radius


def _resistance(log_geometry, log_gap, sealed, viscosity):
    """ln of the total resistance (the cells' geometric factors times 12 eta / u_c^3, summed)
    and each cell's share of it."""
    if sealed.any():
        share = sealed / float(sealed.sum())
        return math.inf, share
    with np.errstate(over="ignore", invalid="ignore"):
        log_r = log_geometry + math.log(12.0 * viscosity) - 3.0 * log_gap
    log_r[np.isneginf(log_geometry)] = -math.inf  # not crossed (also where the gap is +inf)
    top = float(np.max(log_r))
    log_total = top + math.log(float(np.sum(np.exp(log_r - top))))
    return log_total, np.exp(log_r - log_total)


def _where(lo, hi, p, share):
    """Cumulative share, the share inside the FWHM and the width holding the central 90 %."""
    cum = np.cumsum(share)
    cum /= cum[-1]
    in_fwhm = float(np.sum(share[p >= 0.5 * p.max()]))
    edges = np.concatenate([lo[:1], hi])
    c_edges = np.concatenate([[0.0], cum])
    lo, hi = np.interp([0.05, 0.95], c_edges, edges)
    return cum, in_fwhm, float(hi - lo)


def _half_width(hi: np.ndarray, p: np.ndarray) -> float:
    """Half width at half maximum (m) of a radial pressure profile: the outer edge of the
    outermost cell with ``p >= max(p) / 2``."""
    return float(hi[np.nonzero(p >= 0.5 * p.max())[0][-1]])


def _orifice(hi, p, inner_radius) -> tuple[dict, list[str]]:
    """Radial flow: the orifice's size against the contact it perforates (``hi``: the cells'
    outer edges in m, clipped at the orifice: a half width inside it gives a share of 1)."""
    share = inner_radius / _half_width(hi, p)
    msgs = []
    if share > MAX_ORIFICE_SHARE:
        msgs.append(
            "the orifice (inner_radius) is wider than 0.1 of the pressure's half width at half "
            "maximum (diagnostics['orifice_share']): the contact pressure is that of the solid "
            "contact, which an orifice of that size changes"
        )
    return {"orifice_share": share}, msgs


def _validity(theory, p, pressure_drop, width90, min_gap, sealed, mean_free_path):
    """Out-of-range checks (docs/leakage.md, "When the model is out of its range"): numbers for
    the diagnostics, messages for warnings."""
    lam_r = 2.0 * math.pi / _rolloff_wavenumber(theory.psd)
    p_max = float(p.max())
    out = {
        "peak_pressure": p_max,
        "fluid_pressure_ratio": pressure_drop / p_max,
        "rolloff_wavelength": lam_r,
        "junctions_across": None if sealed else width90 / lam_r,
        "min_gap": min_gap,
        "knudsen": None,
    }
    msgs = []
    if out["fluid_pressure_ratio"] > MAX_FLUID_PRESSURE_RATIO:
        msgs.append(
            "the fluid pressure drop exceeds 10% of the peak contact pressure "
            "(diagnostics['fluid_pressure_ratio']): the theory neglects the fluid pressure on "
            "the walls, which lowers the contact pressure and can open the seal"
        )
    if not sealed and out["junctions_across"] < MIN_JUNCTIONS:
        msgs.append(
            "fewer than 5 roll-off wavelengths 2 pi/qr fit across the region holding 90% of the "
            "flow resistance (diagnostics['junctions_across']): the critical-junction theory "
            "averages over many junctions and is only an estimate for so narrow a contact"
        )
    if mean_free_path is not None and not sealed and min_gap > 0.0:
        out["knudsen"] = mean_free_path / min_gap
        if out["knudsen"] > MAX_KNUDSEN:
            msgs.append(
                "the mean free path exceeds 0.1 of the critical gap (diagnostics['knudsen']): "
                "gas rarefaction (slip or Knudsen flow) is not in the viscous flow model"
            )
    return out, msgs


def leak_rate_profile(
    x: ArrayLike,
    p: ArrayLike,
    theory: PerssonTheory,
    pressure_drop: float,
    viscosity: float,
    length: float | None = None,
    *,
    inner_radius: float | None = None,
    threshold: float = THRESHOLD_PERSSON,
    method: Literal["critical-junction"] = "critical-junction",
    mean_free_path: float | None = None,
    warn: bool = True,
) -> LeakResult:
    """Leak rate of a seal with a nominal pressure profile p(x) (docs/leakage.md §3-5).

    Each strip of the profile is a uniform-pressure seal of local conductance
    ``sigma = u_c(p)^3 / (12 eta)`` (Persson & Yang 2008; Lorenz & Persson, EPL 86, 44006
    (2009)), and the strips are in series across the contact:

        Q / L_y = dP / int dx (1 / sigma(x)),

    which for a constant pressure over a width L_x is Persson's rectangle formula
    ``Q = (L_y / L_x) dP u_c^3 / (12 eta)``. With ``inner_radius`` the profile is axisymmetric,
    p(r) at radii x, and the fluid enters at ``r = inner_radius`` (the orifice of a seat) and
    flows outwards through rings in series (each ring of width dr is a rectangle of length
    2 pi r):

        Q = dP / int_{inner_radius} dr / (2 pi r sigma(r)).

    u_c comes from a table of the critical gap built once per theory and threshold (relative
    error below the theory's rtol; see :class:`_GapTable`). A sealed strip
    (``P(q1, p) >= threshold``) on the flow path seals the contact.

    Parameters
    ----------
    x : array_like
        Strip (cell) centres in m, strictly increasing, at least 2; the strip edges lie halfway
        between centres (a uniform grid of spacing dx gives strips of width dx). Radial flow:
        radii >= 0 of ring cells (edges clipped at 0: a first cell centred on the axis is a
        disc).
    p : array_like
        Nominal contact pressure at x in Pa (>= 0; p = 0 is out of contact and adds no
        resistance).
    theory : PerssonTheory
        The theory of the interface (spectrum, E*, gamma).
    pressure_drop : float
        Fluid pressure difference across the seal in Pa (> 0).
    viscosity : float
        Dynamic viscosity of the fluid in Pa s (> 0); 1e-3 for water at 20 C.
    length : float, optional
        Seal length L_y in m (> 0), perpendicular to the flow (the circumference of an O-ring);
        default 1 m. Not for radial flow (the rings' circumferences are the length).
    inner_radius : float, optional
        Radial flow (a point contact): the radius in m where the fluid enters, in
        (0, outer edge of the profile); p inside it is not on the flow path. The pressure
        profile is that of the solid contact: a warning says when the orifice is wider than
        ``MAX_ORIFICE_SHARE`` of the half width at half maximum of p. None (default): flow
        across a line contact.
    threshold : float
        Percolation threshold of the apparent contact area, in (0, 1) (see :func:`critical_gap`).
    method : {"critical-junction"}
        The only method implemented (the effective-medium alternative is not; see the docs).
    mean_free_path : float, optional
        Mean free path of a gas in m (about 70e-9 for air at 1 bar): warns when the flow is not
        viscous. None for liquids.
    warn : bool
        Emit the :class:`LeakageWarning` s (listed in ``diagnostics['warnings']`` either way).

    Returns
    -------
    LeakResult
    """
    length = _length(length, inner_radius)
    pressure_drop, viscosity, length, threshold, mean_free_path = _scalars(
        pressure_drop, viscosity, length, threshold, method, mean_free_path
    )
    _state(theory)
    x, p, inner_radius = _profile(x, p, inner_radius)
    flow = _Flow(pressure_drop, viscosity, length, inner_radius, threshold, method, mean_free_path)
    return _leak(x, p, theory, flow, warn, converged=True)


def _length(length, inner_radius) -> float | None:
    """The seal length: 1 m by default across a line contact; none for radial flow."""
    if inner_radius is None:
        return 1.0 if length is None else length
    if length is not None:
        raise ValueError(
            "length is for flow across a line contact; radial flow (inner_radius given) goes "
            "round the whole ring: leave length at None"
        )
    return None


@dataclass(frozen=True)
class _Flow:
    """The fluid and flow path of a leak-rate call (validated)."""

    pressure_drop: float
    viscosity: float
    length: float | None
    inner_radius: float | None
    threshold: float
    method: str
    mean_free_path: float | None


def _leak(x, p, theory, flow: _Flow, warn: bool, converged: bool) -> LeakResult:
    radial = flow.inner_radius is not None
    table = _gap_table(theory, flow.threshold)
    log_gap, sealed_strips = table.log_gap(_x1(theory, p))
    lo, hi = _cell_edges(x, flow.inner_radius)
    log_geometry = _log_geometry(lo, hi, radial)
    sealed_strips &= ~np.isneginf(log_geometry)  # only the cells the flow crosses
    sealed = bool(sealed_strips.any())
    log_total, share = _resistance(log_geometry, log_gap, sealed_strips, flow.viscosity)
    conductance = 0.0 if sealed else math.exp(-log_total)
    cum, in_fwhm, width90 = _where(lo, hi, p, share)
    with np.errstate(over="ignore"):
        gap = np.exp(log_gap)
        sigma = gap**3 / (12.0 * flow.viscosity)
    min_gap = 0.0 if sealed else float(gap[int(np.argmax(share))])
    diag, msgs = _validity(
        theory, p, flow.pressure_drop, width90, min_gap, sealed, flow.mean_free_path
    )
    if radial:
        more, more_msgs = _orifice(hi, p, flow.inner_radius)
        diag.update(more)
        msgs += more_msgs
    diag.update(
        n_strips=int(x.size),
        n_sealed=int(sealed_strips.sum()),
        gap_table={"z0": table.z0, "h": table.h, "cells": int(table.cf.shape[0])},
        warnings=msgs,
    )
    for msg in msgs if warn else ():
        warnings.warn(f"fastline.leak_rate: {msg}", LeakageWarning, stacklevel=3)
    if warn and not converged:  # not in diagnostics: the solve's own diagnostics say it
        warnings.warn(UNCONVERGED, LeakageWarning, stacklevel=3)
    return LeakResult(
        Q=conductance * (1.0 if radial else flow.length) * flow.pressure_drop,
        conductance=conductance,
        sealed=sealed,
        x=x,
        pressure=p,
        u_c=gap,
        sigma=sigma,
        sealed_strips=sealed_strips,
        resistance_share=share,
        cumulative_share=cum,
        share_in_fwhm=in_fwhm,
        resistance_width=width90,
        pressure_drop=flow.pressure_drop,
        viscosity=flow.viscosity,
        length=flow.length,
        threshold=flow.threshold,
        method=flow.method,
        converged=converged,
        diagnostics=diag,
        inner_radius=flow.inner_radius,
    )


def leak_rate(
    result: LineContactResult | PointContactResult,
    pressure_drop: float,
    viscosity: float,
    length: float | None = None,
    *,
    inner_radius: float | None = None,
    theory: PerssonTheory | None = None,
    threshold: float = THRESHOLD_PERSSON,
    method: Literal["critical-junction"] = "critical-junction",
    mean_free_path: float | None = None,
    warn: bool = True,
) -> LeakResult:
    """Leak rate of a solved contact: across a line contact (along x), or radially out of the
    orifice of a point contact.

    The post-processing step of a seal calculation: the nominal pressure of a
    :class:`~fastline.line_contact.LineContactResult` or a
    :class:`~fastline.point_contact.PointContactResult` (any model with a roughness spectrum)
    and the Persson theory of its interface give the leak rate by :func:`leak_rate_profile`
    (strips in series across a line contact, rings in series around a point contact;
    docs/leakage.md §4-5). Costs well under the solve it post-processes once the gap table of
    the theory is built (first call per theory and threshold: ~10 ms).

    Parameters
    ----------
    result : LineContactResult or PointContactResult
        A solved contact (``model="persson"`` or ``"exponential"``).
    pressure_drop, viscosity, threshold, method, mean_free_path, warn
        As in :func:`leak_rate_profile` (Pa, Pa s, -, str, m, bool). With ``warn``, a result
        that did not converge also gets a :class:`LeakageWarning` (one text for every scene:
        a loop shows it once); ``LeakResult.converged`` says so either way.
    length : float, optional
        Line contact: the seal length in m (default 1 m). Not for a point contact.
    inner_radius : float, optional
        Point contact (required there): the radius in m where the fluid enters, e.g. the
        orifice of a valve seat closed by a ball; the fluid flows outwards through the contact.
        Not for a line contact.
    theory : PerssonTheory, optional
        The theory the contact was solved with; default ``result.theory``.

    Returns
    -------
    LeakResult

    Raises
    ------
    TypeError
        For anything but a line- or point-contact result.
    ValueError
        For a Hertz result (smooth surfaces: no spectrum), a result without a theory when none
        is given, a theory of another E*, spectrum (h_rms), gamma or variant,
        ``inner_radius`` missing for a point contact or given for a line contact, or an input
        outside its range.
    """
    coords = _coordinates(result, inner_radius)
    length = _length(length, inner_radius)
    pressure_drop, viscosity, length, threshold, mean_free_path = _scalars(
        pressure_drop, viscosity, length, threshold, method, mean_free_path
    )
    theory = _result_theory(result, theory)
    x, p, inner_radius = _profile(coords, result.pressure, inner_radius)
    flow = _Flow(pressure_drop, viscosity, length, inner_radius, threshold, method, mean_free_path)
    return _leak(x, p, theory, flow, warn, converged=bool(result.converged))


def _coordinates(result, inner_radius) -> np.ndarray:
    """The cell centres of a contact result (x of a line contact, r of a point contact), with
    the check that ``inner_radius`` comes with the point contact only."""
    line = hasattr(result, "x") and hasattr(result, "pressure")
    point = hasattr(result, "r") and hasattr(result, "pressure")
    if not (line or point):
        raise TypeError(
            "result must be a LineContactResult or a PointContactResult (from "
            f"solve_line_contact / solve_point_contact), got {type(result).__name__}; for a "
            "pressure profile of your own use leak_rate_profile"
        )
    if point and inner_radius is None:
        raise ValueError(
            "inner_radius is required for a point contact: the radius in m where the fluid "
            "enters (e.g. the orifice of a seat); the leak is the radial flow from there "
            "outwards"
        )
    if line and inner_radius is not None:
        raise ValueError(
            "inner_radius is for a point contact (radial flow); a line contact leaks across x"
        )
    return result.r if point else result.x


def _result_theory(result, theory):
    """The PerssonTheory of a result's interface, checked against its E*."""
    if getattr(result, "model", None) == "hertz":
        raise ValueError(
            "leak_rate needs a roughness spectrum: a model='hertz' result is for smooth surfaces "
            "(solve with model='persson' or 'exponential')"
        )
    if theory is None:
        theory = getattr(result, "theory", None)
    if theory is None:
        raise ValueError(
            "leak_rate needs the PerssonTheory of the interface: pass theory=... (the one the "
            "contact was solved with)"
        )
    _state(theory)
    if not math.isclose(theory.E_star, result.E_star, rel_tol=1e-12):
        raise ValueError(
            f"theory.E_star = {theory.E_star:g} Pa differs from the result's E* = "
            f"{result.E_star:g} Pa"
        )
    _check_same_interface(result, theory)
    return theory


def _check_same_interface(result, theory) -> None:
    """The theory must describe the surface the result was solved for: its h_rms (which the
    result carries as ``alpha * delta``) and, when the result holds a theory, its gamma and
    variant. A theory of another spectrum would give a leak rate decades off, silently."""
    h_rms = result.alpha * result.delta  # NaN for a law of your own without a spectrum
    if math.isfinite(h_rms) and not math.isclose(theory.psd.h_rms, h_rms, rel_tol=1e-9):
        raise ValueError(
            f"theory is of another spectrum: its h_rms = {theory.psd.h_rms:.6g} m, the result's "
            f"{h_rms:.6g} m (alpha * delta); pass the theory the contact was solved with"
        )
    own = getattr(result, "theory", None)
    if own is not None and (own.gamma, own.variant) != (theory.gamma, theory.variant):
        raise ValueError(
            f"theory has gamma = {theory.gamma:g}, variant {theory.variant!r}; the result was "
            f"solved with gamma = {own.gamma:g}, variant {own.variant!r}: pass the theory the "
            "contact was solved with"
        )
