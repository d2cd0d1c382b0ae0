"""The interface at magnification zeta: Persson's statistics of the gaps between the surfaces.

The interface at magnification zeta (roughness with ``q < zeta q0`` resolved), for a uniform
nominal pressure p (docs/leakage.md; B.N.J. Persson, C. Yang, J. Phys.: Condens. Matter 20,
315011 (2008), doi:10.1088/0953-8984/20/31/315011; B. Lorenz, B.N.J. Persson, EPL 86, 44006
(2009), doi:10.1209/0295-5075/86/44006), with the moment ``A(q) = pi int_{q0}^q q'^3 C dq'`` of
:mod:`fastline.theory.spectra` written ``B(q)`` here (A is the contact area below), ``a = zeta q0``
and ``m = B(a)``:

* apparent relative contact area ``P(zeta) = erf(y)``, ``y = p / (E* sqrt(m))`` (the P(q, p) of
  the full theory at ``q = a``);
* mean separation in the apparent contact, the Yang-Persson separation of the unresolved
  roughness (q from a to q1) under the pressure ``s E* = p / P(zeta)`` acting there,

      u_bar(zeta) = sqrt(pi) int_a^{q1} dq q^2 C(q) w F(w s),   w = (B(q) - m)^(-1/2),

  with the universal F of :mod:`fastline.theory.special` (the same gamma);
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
up (the same two devices as the q quadrature of :mod:`fastline.theory.persson`, in the variable
where they are needed). Q comes from a compiled table: ``ln q`` as a cubic Hermite polynomial of
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
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numba
import numpy as np
from numpy.typing import ArrayLike

from fastline._lib.validate import finite_array, in_range, positive_array
from fastline.theory.special import _F, JIT, f_coefficients

if TYPE_CHECKING:  # annotations only: persson imports this module
    from fastline.theory.persson import PerssonTheory

__all__ = ["CriticalGap", "apparent_area", "mean_separation", "edge_separation", "critical_gap",
           "THRESHOLD_PERSSON", "THRESHOLD_NUMERICAL", "THRESHOLD_BRUGGEMAN", "check_threshold",
           "gap_table", "interface_cache", "sealing_argument"]  # fmt: skip

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
#: the critical gap's moment m = B(zeta_c q0) solved directly down to this; below (p < ~1e-100
#: E*, where m underflows) u_c continues linearly in ln p: the exponential law u0 ln(p_ref / p)
_M_LOW = 1e-200
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


#: geometric grading of the top panel (as the q quadrature of fastline.theory.persson)
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
def _critical_vec(x1, X_t, t, spectrum, gap, qc, sealed):
    """u_c = u1(zeta_c) and q_c = zeta_c q0 for x1 = w(q1) p / E* (docs/leakage.md §3).

    ``P(zeta_c) = t`` has the closed-form root ``B(q_c) = m = B1 (x1 / X_t)^2``,
    ``X_t = erfinv(t)``; sealed where ``erf(x1) >= t`` (gap 0, q_c = q1). ``spectrum = (E_star,
    band, rule, fc, qtab)`` as :meth:`_Spectrum.kernel_args` gives it: E* (Pa), ``band = (B1,
    q1, B_breaks)`` (B dimensionless, q1 in 1/m), the tau rule, F's coefficients ``(gamma, c1,
    c2, c3, b2)`` and the Q table. Written: ``gap`` (u_c, m), ``qc`` (1/m), ``sealed``."""
    E_star, band, rule, fc, qtab = spectrum
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
def _log_gap_kernel(x1, t, X_t, table, out, sealed):
    """ln u_c at ``x1 = w(q1) p / E*`` from the gap table (see :class:`_GapTable`).

    ``table = (kappa0, z0, h, cf, slope_hi, low)``: the sealing exponent's factor kappa0, the
    first node and the step of the uniform z grid (all dimensionless), the spline's Horner
    coefficients of ``g(z) = ln u_c + kappa0 e^z`` per cell (n x 4, u_c in m), g's slope at
    the grid's end, and ``low = (u_lo, v_lo, u0, ln(E* sqrt(B1)))`` (m, ln Pa, m, ln Pa): below
    ``z0`` the law ``u_c = u_lo + u0 (v_lo - ln p)``. Sealed where ``erf(x1) >= t`` (ln u_c =
    -inf); p = 0 gives ln u_c = +inf (no contact, no resistance). Written: ``out`` (ln u_c),
    ``sealed``."""
    kappa0, z0, h, cf, slope_hi, low = table
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


def interface_cache(theory: PerssonTheory) -> dict:
    """The leakage cache of a theory (a dict stored on the theory object itself)."""
    if not isinstance(theory, InterfaceStatistics):
        raise TypeError(f"theory must be a fastline PerssonTheory, got {type(theory).__name__}")
    return theory.__dict__.setdefault("_leakage_cache", {})


def _spectrum(theory) -> _Spectrum:
    cache = interface_cache(theory)
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
    # a copy of p: a view of a broadcast array is flagged read-only-to-be (NumPy warns when the
    # compiled kernel's typing looks at it)
    return shape, np.ascontiguousarray(m), np.array(p.ravel(), dtype=np.float64)


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
    interface_cache(theory)
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


def check_threshold(threshold: float) -> float:
    return in_range("threshold", threshold, 0.0, 1.0, lo_open=True, hi_open=True)


def sealing_argument(theory: PerssonTheory, p: np.ndarray) -> np.ndarray:
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
    threshold = check_threshold(threshold)
    interface_cache(theory)
    p = positive_array("p", p)
    sp = _spectrum(theory)
    x1 = sealing_argument(theory, p.ravel())
    gap, qc = np.empty_like(x1), np.empty_like(x1)
    sealed = np.empty(x1.shape, dtype=np.bool_)
    X_t = _erfinv(threshold)
    _critical_vec(x1, X_t, threshold, sp.kernel_args(), gap, qc, sealed)
    with np.errstate(over="ignore", under="ignore"):  # m of sealed or vanishing pressures
        m = sp.table.B1 * (x1 / X_t) ** 2
    low = ~sealed & (m < _M_LOW)
    if low.any():  # the line through u_c at m = _M_LOW and e^4 _M_LOW, in ln x1 (ln p)
        x_ref = X_t * math.sqrt(_M_LOW / sp.table.B1) * np.array([1.0, math.e**2])
        ref, q_ref = np.empty(2), np.empty(2)
        _critical_vec(x_ref, X_t, threshold, sp.kernel_args(), ref, q_ref, np.zeros(2, np.bool_))
        gap[low] = ref[0] + 0.5 * (ref[0] - ref[1]) * np.log(x_ref[0] / x1[low])
    qc = _polish_root(theory.psd, qc, m, ~sealed)
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
        _critical_vec(x1, self.X_t, self.threshold, self._args, gap, qc, np.empty(x1.size, bool))
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
        table = (self.kappa0, self.z0, self.h, self.cf, self.slope_hi, self.low)
        _log_gap_kernel(x1, self.threshold, self.X_t, table, out, sealed)
        return out, sealed


def gap_table(theory: PerssonTheory, threshold: float) -> _GapTable:
    """The gap table of (theory, threshold), built on first use and cached on the theory."""
    cache = interface_cache(theory)
    key = ("gap_table", threshold)
    tab = cache.get(key)
    if tab is None:
        tab = cache[key] = _GapTable(theory, threshold)
    return tab


class InterfaceStatistics:
    """The interface at magnification zeta as methods of a theory (docs/leakage.md sections
    1-3): :class:`~fastline.PerssonTheory` inherits them. ``P(zeta)`` is
    :meth:`apparent_area`, ``u_bar(zeta, p)`` :meth:`mean_separation`, ``u1(zeta)``
    :meth:`edge_separation`, and the critical junction :meth:`critical_gap`."""

    def apparent_area(self, zeta: ArrayLike, p: ArrayLike) -> np.ndarray:
        """Apparent relative contact area ``P(zeta)`` at magnification zeta for a uniform
        nominal pressure p in Pa; ``contact_area(p, zeta * q0)`` (docs/leakage.md §1).
        """
        return apparent_area(self, zeta, p)

    def mean_separation(self, zeta: ArrayLike, p: ArrayLike) -> np.ndarray:
        """Mean separation ``u_bar(zeta, p)`` in m inside the apparent contact at magnification
        zeta (docs/leakage.md §2); ``mean_separation(1, p) == separation(p)``.
        """
        return mean_separation(self, zeta, p)

    def edge_separation(self, zeta: ArrayLike, p: ArrayLike) -> np.ndarray:
        """Persson's ``u1(zeta) = u_bar + u_bar' P / P'`` in m: the separation in the area
        leaving contact at magnification zeta (docs/leakage.md §2); ``>= mean_separation``.
        """
        return edge_separation(self, zeta, p)

    def critical_gap(self, p: ArrayLike, threshold: float = 0.42) -> CriticalGap:
        """The critical constriction for uniform nominal pressures p in Pa (docs/leakage.md §3):
        a :class:`CriticalGap` with ``u_c`` (the gap in m), ``zeta``
        (zeta_c), ``sealed`` (``P(q1, p) >= threshold``, where ``u_c`` is 0) and
        ``threshold``.
        """
        return critical_gap(self, p, threshold)
