"""An asperity model from the same spectrum: the Greenwood-Williamson pressure law.

Greenwood & Williamson (Proc. R. Soc. Lond. A 295, 300 (1966), doi:10.1098/rspa.1966.0242):
summits of equal radius ``beta`` and areal density ``eta`` with Gaussian heights (mean
``y_s`` above the mean plane of the surface, standard deviation ``sigma_s``), each a Hertz
contact, no interaction between them. A rigid flat at the separation u from the mean plane
carries the nominal pressure and real contact area fraction

    p(u) = (4/3) eta E* sqrt(beta) sigma_s^(3/2) F_{3/2}(t),
    A/A0 = pi eta beta sigma_s F_1(t),                          t = (u - y_s) / sigma_s,

with ``F_n(t) = int_t^inf (z - t)^n phi(z) dz`` (phi the standard normal density).

Summit statistics from the spectrum (P.R. Nayak, J. Lubr. Technol. 93, 398 (1971); J.I. McCool,
Wear 107, 37 (1986), doi:10.1016/0043-1648(86)90045-1; A.W. Bush, R.D. Gibson, T.R. Thomas,
Wear 35, 87 (1975)), written with the moments of a *profile* of the isotropic surface. In
Persson's convention (``h_rms^2 = 2 pi int q C dq``, fastline.theory.spectra) they are

    m0 = 2 pi int q C dq = h_rms^2,
    m2 = pi int q^3 C dq = h'^2 / 2          (a profile sees half the mean-square gradient),
    m4 = (3 pi / 4) int q^5 C dq            (= 3/8 of the mean-square Laplacian),

and, with Nayak's bandwidth ``alpha = m0 m4 / m2^2``,

    eta = m4 / (6 pi sqrt(3) m2),           beta = (3/8) sqrt(pi / m4),
    sigma_s = sqrt(m0 (1 - 0.8968 / alpha)), y_s = 4 m2 / sqrt(pi m4) = 4 sqrt(m0 / (pi alpha)).

(McCool's large-alpha forms; beta is the inverse of the mean summit curvature (8/3) sqrt(m4/pi).)
Checked on random-phase surfaces of the paper-like spectrum (H 0.8, q1/q0 = 32, alpha = 28;
``fastline.bem.random_surface``, 32 points per shortest wavelength, 3 realisations): summits
counted as 8-neighbour maxima have the density 1.000 eta, mean curvature 0.998 / beta, mean
height 1.01 y_s and spread 1.00 sigma_s (docs/validation.md).

The separation u is that of the flat from the mean plane: the asperities deform locally and the
deformation of the bulk at the nominal scale is the contact solver's (Greenwood & Tripp, J. Appl.
Mech. 34, 153 (1967): the rough sphere). Unlike Persson's u(p), this law depends strongly on
the short-wavelength cut-off q1 through m4 (docs/validation.md, "Bandwidth").

Numerics: ``F_{3/2}(t) = Gamma(5/2) exp(-t^2/4) D_{-5/2}(t) / sqrt(2 pi)`` (D the parabolic
cylinder function) has no elementary form; ``ln F_{3/2}`` is tabulated as Chebyshev series on
20 unit panels of t in [-8, 12] (values by Gauss-Legendre quadrature in ``r = sqrt(z - t)``),
with the expansion
``|t|^(3/2) sum_k C(3/2, 2k) (2k-1)!! t^(-2k)`` below and the asymptotic series
``phi(t) sum_k (-1)^k Gamma(5/2 + 2k) / (2^k k! t^(5/2 + 2k))`` above (both to < 1e-12 there).
p(u) evaluates the series; u(p) inverts it by safeguarded Newton (compiled kernels).
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass

import numba
import numpy as np
from numpy.polynomial import chebyshev as _cheb
from numpy.typing import ArrayLike

from fastline._lib.jit import JIT
from fastline._lib.validate import E_STAR_RANGE, in_span, positive, real_array
from fastline.theory.laws import PressureLaw
from fastline.theory.spectra import PSD

__all__ = ["SummitStatistics", "GreenwoodWilliamsonLaw", "summit_integral"]

_T_LO, _T_HI = -8.0, 12.0  # table range of t
_NPANEL = 20  # unit panels
_DEG = 20
_N_NEG = 8  # terms of the expansion below _T_LO
_N_POS = 14  # terms of the asymptotic series above _T_HI
_LN_SQRT_2PI = 0.5 * math.log(2.0 * math.pi)
#: t where the law continues exponentially (class Notes)
TAIL_T = 6.0
#: McCool's constant in the summit-height variance (1 - 0.8968 / alpha)
MCCOOL_VARIANCE = 0.8968


# ----------------------------------------------------------------------------------------------
# summit statistics
# ----------------------------------------------------------------------------------------------
def _moment(psd: PSD, k: int) -> float:
    """``int q^k C dq`` over the spectrum, Gauss-Legendre in ln q on panels (<= 0.25 decade)
    between the kinks of C (exact to ~1e-15 for the power-law pieces)."""
    t, w = np.polynomial.legendre.leggauss(20)
    edges = []
    bps = np.unique(np.concatenate([[psd.q0], psd.breakpoints(), [psd.q1]]))
    bps = bps[(bps >= psd.q0) & (bps <= psd.q1)]
    for a, b in zip(bps[:-1], bps[1:], strict=True):
        n = max(1, math.ceil(4.0 * math.log10(b / a)))
        edges.append(np.geomspace(a, b, n + 1)[:-1])
    edges = np.log(np.append(np.concatenate(edges), bps[-1]))
    lo, hi = edges[:-1, None], edges[1:, None]
    lq = 0.5 * (hi + lo) + 0.5 * (hi - lo) * t
    q = np.exp(lq)
    return float(np.sum(0.5 * (hi - lo) * w * q ** (k + 1) * psd(q)))


@dataclass(frozen=True)
class SummitStatistics:
    """Summit statistics of an isotropic Gaussian surface from its spectrum (module docstring).

    Attributes
    ----------
    m0, m2, m4 : float
        Profile spectral moments [m^2, -, 1/m^2].
    alpha : float
        Nayak's bandwidth parameter ``m0 m4 / m2^2`` (>= 1.5 for a Gaussian surface).
    density : float
        Summit density eta [1/m^2].
    radius : float
        Summit radius beta [m].
    height_std, height_mean : float
        sigma_s and y_s of the (Gaussian) summit heights [m].
    """

    m0: float
    m2: float
    m4: float
    alpha: float
    density: float
    radius: float
    height_std: float
    height_mean: float

    @classmethod
    def from_moments(cls, m0: float, m2: float, m4: float) -> SummitStatistics:
        """From the profile moments (McCool's relations, module docstring)."""
        m0, m2, m4 = positive("m0", m0, "m^2"), positive("m2", m2), positive("m4", m4, "1/m^2")
        alpha = m0 * m4 / (m2 * m2)
        if alpha <= MCCOOL_VARIANCE:
            raise ValueError(f"m0 m4 / m2^2 must exceed {MCCOOL_VARIANCE} (got {alpha:.6g})")
        return cls(
            m0=m0,
            m2=m2,
            m4=m4,
            alpha=alpha,
            density=m4 / (6.0 * math.pi * math.sqrt(3.0) * m2),
            radius=0.375 * math.sqrt(math.pi / m4),
            height_std=math.sqrt(m0 * (1.0 - MCCOOL_VARIANCE / alpha)),
            height_mean=4.0 * m2 / math.sqrt(math.pi * m4),
        )

    @classmethod
    def from_psd(cls, psd: PSD) -> SummitStatistics:
        """From an isotropic spectrum in Persson's convention (module docstring)."""
        if not isinstance(psd, PSD):
            raise TypeError(f"psd must be a fastline PSD, got {type(psd).__name__}")
        m0 = psd.h_rms**2
        m2 = float(psd.cumulative(psd.q1))
        m4 = 0.75 * math.pi * _moment(psd, 5)
        return cls.from_moments(m0, m2, m4)


# ----------------------------------------------------------------------------------------------
# the summit integral F_{3/2}
# ----------------------------------------------------------------------------------------------
def _ln_summit_quadrature(t: np.ndarray) -> np.ndarray:
    """``ln F_{3/2}(t)`` for t in [-8, 13] by composite Gauss-Legendre in r (``z - t = r^2``):
    ``F = int_0^inf 2 r^4 phi(r^2 + t) dr``, a smooth integrand, with ``exp(-t^2/2)`` taken
    out for t > 0; 60 panels of 20 nodes on [0, sqrt(max(-t, 0)) + 7] (relative error ~1e-15;
    SciPy's parabolic cylinder function ``pbdv`` was off by up to 1e-9 near t = 6)."""
    x, w = np.polynomial.legendre.leggauss(20)
    out = np.empty(t.shape)
    for i, ti in enumerate(t):
        top = math.sqrt(max(-ti, 0.0)) + 7.0
        edges = np.linspace(0.0, top, 61)
        a, b = edges[:-1, None], edges[1:, None]
        r = 0.5 * (a + b) + 0.5 * (b - a) * x
        shift = 0.5 * ti * ti if ti > 0.0 else 0.0
        z = r * r + ti
        f = 2.0 * r**4 * np.exp(shift - 0.5 * z * z)
        out[i] = math.log(float(np.sum(0.5 * (b - a) * w * f))) - shift - _LN_SQRT_2PI
    return out


@functools.cache
def _tables():
    """(panel series of ln F, of d ln F/dt, coefficients below and above the table)."""
    tau = _cheb.chebpts1(_DEG + 1)
    V = _cheb.chebvander(tau, _DEG)
    c = np.empty((_NPANEL, _DEG + 1))
    for k in range(_NPANEL):
        lnF = _ln_summit_quadrature(_T_LO + k + 0.5 * (tau + 1.0))
        c[k] = lnF @ V * (2.0 / (_DEG + 1))
        c[k, 0] *= 0.5
    dc = np.zeros_like(c)
    dc[:, :-1] = np.array([_cheb.chebder(row, scl=2.0) for row in c])  # d/dt, panel width 1
    # below: |t|^1.5 sum_k binom(1.5, 2k) (2k-1)!! t^(-2k); above: asymptotic series / Gamma(5/2)
    neg = np.array(
        [math.prod(1.5 - j for j in range(2 * k)) / math.factorial(2 * k) for k in range(_N_NEG)]
    )
    neg *= np.array([math.prod(range(1, 2 * k, 2)) for k in range(_N_NEG)], dtype=float)
    pos = np.array(
        [
            (-1) ** k * math.gamma(2.5 + 2 * k) / (2.0**k * math.factorial(k) * math.gamma(2.5))
            for k in range(_N_POS)
        ]
    )
    for arr in (c, dc, neg, pos):
        arr.setflags(write=False)
    return c, dc, neg, pos


@numba.njit(**JIT)
def _clenshaw(c, s):
    b1 = 0.0
    b2 = 0.0
    for k in range(c.shape[0] - 1, 0, -1):
        b1, b2 = 2.0 * s * b1 - b2 + c[k], b1
    return s * b1 - b2 + c[0]


@numba.njit(**JIT)
def _ln_summit(t, c, dc, neg, pos):
    """``ln F_{3/2}(t)`` and its t-derivative."""
    if t < _T_LO:  # ln(|t|^1.5 s(x)), x = t^-2; d/dt = 1.5/t - 2 x/t s'(x)/s
        x = 1.0 / (t * t)
        s = 0.0
        dsdx = 0.0
        for k in range(neg.shape[0] - 1, -1, -1):
            s = s * x + neg[k]
        for k in range(neg.shape[0] - 1, 0, -1):
            dsdx = dsdx * x + k * neg[k]
        return 1.5 * math.log(-t) + math.log(s), 1.5 / t - 2.0 * x / t * dsdx / s
    if t > _T_HI:
        x = 1.0 / (t * t)
        s = 0.0
        dsdx = 0.0
        for k in range(pos.shape[0] - 1, -1, -1):
            s = s * x + pos[k]
        for k in range(pos.shape[0] - 1, 0, -1):
            dsdx = dsdx * x + k * pos[k]
        lnphi = -0.5 * t * t - _LN_SQRT_2PI
        val = lnphi + math.log(1.329340388179137) - 2.5 * math.log(t) + math.log(s)
        return val, -t - 2.5 / t - 2.0 * x / t * dsdx / s
    k = min(int(t - _T_LO), _NPANEL - 1)
    u = 2.0 * (t - (_T_LO + k)) - 1.0
    return _clenshaw(c[k], u), _clenshaw(dc[k], u)


@numba.njit(**JIT)
def _t_of_ln(L, c, dc, neg, pos):
    """The t with ``ln F_{3/2}(t) = L`` (ln F decreases from +inf to -inf): Newton with a
    bracket, from an asymptotic first guess."""
    if L > 3.0:  # t < -4: F ~ |t|^1.5
        t = -math.exp(L / 1.5)
    elif L < -10.0:  # t > 3: ln F ~ -t^2/2
        t = math.sqrt(-2.0 * L)
    else:
        t = 0.0
    lo, hi = -math.inf, math.inf
    for _ in range(100):
        f, d = _ln_summit(t, c, dc, neg, pos)
        r = f - L
        if r > 0.0:
            lo = t
        else:
            hi = t
        step = r / d
        tn = t - step
        if not (lo < tn < hi):
            tn = 0.5 * (lo + hi) if math.isfinite(lo) and math.isfinite(hi) else t - 2.0 * step
        if abs(tn - t) <= 1e-15 * (1.0 + abs(t)):
            return tn
        t = tn
    return t


@numba.njit(**JIT)
def _gw_u(v, lnK, mean, std, tail, tab, u, dudv):
    """u and du/dv at v = ln p; ``tail = (L_c, u_c, u0)``: below ``ln F = L_c`` the straight
    line ``u = u_c + u0 (L_c - L)``."""
    c, dc, neg, pos = tab
    L_c, u_c, u0 = tail
    for i in range(v.shape[0]):
        L = v[i] - lnK
        if L < L_c:
            u[i] = u_c + u0 * (L_c - L)
            dudv[i] = -u0
            continue
        t = _t_of_ln(L, c, dc, neg, pos)
        _, d = _ln_summit(t, c, dc, neg, pos)
        u[i] = mean + std * t
        dudv[i] = std / d


@numba.njit(**JIT)
def _gw_lnp(u, lnK, mean, std, tail, tab, out):
    """ln p(u), the inverse of :func:`_gw_u`."""
    c, dc, neg, pos = tab
    L_c, u_c, u0 = tail
    for i in range(u.shape[0]):
        if u[i] > u_c:
            out[i] = lnK + L_c - (u[i] - u_c) / u0
        else:
            out[i] = lnK + _ln_summit((u[i] - mean) / std, c, dc, neg, pos)[0]


def summit_integral(t: ArrayLike) -> np.ndarray:
    """``F_{3/2}(t) = int_t^inf (z - t)^(3/2) phi(z) dz`` (compiled; relative error < 1e-11
    against quadrature, tests/test_asperity.py), vectorised over finite t."""
    t = real_array("t", t)
    if not np.all(np.isfinite(t)):
        raise ValueError("t must be finite")
    flat = np.ascontiguousarray(t.ravel())
    out = np.empty_like(flat)
    _gw_lnp(flat, 0.0, 0.0, 1.0, (-math.inf, math.inf, 1.0), _tables(), out)
    return np.exp(out).reshape(t.shape)


# ----------------------------------------------------------------------------------------------
# the law
# ----------------------------------------------------------------------------------------------
class GreenwoodWilliamsonLaw(PressureLaw):
    """Greenwood-Williamson p(u) with summit statistics from the spectrum (module docstring).

    A :class:`~fastline.theory.laws.PressureLaw`: pass it as ``model=`` to
    :class:`~fastline.LineContact` or :class:`~fastline.PointContact` (the sphere with it is
    Greenwood & Tripp's rough sphere).

    Parameters
    ----------
    statistics : SummitStatistics
        Summit density, radius and height distribution (``SummitStatistics.from_psd``).
    E_star : float
        Effective modulus E* in Pa, in [1, 1e13].

    Attributes
    ----------
    u0 : float
        ``-du/dln p`` at low pressure, in m: ``sigma_s / 6.4``, that of the Gaussian summit
        tail at ``t = 6`` where the law goes over into its exponential tail (below). The law
        has no constant decay length: ``-du/dln p = sigma_s F_{3/2} / (1.5 F_{1/2})`` grows
        from there to 0.70 sigma_s at t = 0 and like ``(2/3)(y_s - u)`` at high pressure.

    Notes
    -----
    Beyond ``t = 6`` (p below 2e-10 of its value at t = 0, where half the summits touch) u
    continues linearly in ln p with that slope: the Gaussian tail alone reaches only
    ``u = y_s + 37 sigma_s`` at the smallest positive double, while the solvers, which work
    with ln p, need every separation of the domain to have a pressure.

    Examples
    --------
    >>> import fastline as fl
    >>> psd = fl.SelfAffinePSD(0.5e-6, 0.8, 1e4, 1e4, 3.2e5)
    >>> law = fl.GreenwoodWilliamsonLaw.from_psd(psd, E_star=1e7)
    >>> res = fl.LineContact(psd, 1e7, 32.8e-3, model=law, n=256).solve(50.0)
    """

    name = "greenwood-williamson"

    def __init__(self, statistics: SummitStatistics, E_star: float) -> None:
        if not isinstance(statistics, SummitStatistics):
            raise TypeError(
                f"statistics must be a SummitStatistics, got {type(statistics).__name__}"
            )
        self.statistics = statistics
        self.E_star = in_span("E_star", E_star, E_STAR_RANGE, "Pa")
        s = statistics
        K = (4.0 / 3.0) * s.density * self.E_star * math.sqrt(s.radius) * s.height_std**1.5
        self._lnK = math.log(K)
        self._area = math.pi * s.density * s.radius * s.height_std
        L_c, slope = _ln_summit(TAIL_T, *_tables())
        self.u0 = float(s.height_std / -slope)
        self._tail = (float(L_c), s.height_mean + s.height_std * TAIL_T, self.u0)

    @classmethod
    def from_psd(cls, psd: PSD, E_star: float) -> GreenwoodWilliamsonLaw:
        """The law of an isotropic spectrum (McCool's summit statistics)."""
        return cls(SummitStatistics.from_psd(psd), E_star)

    def __repr__(self):
        s = self.statistics
        return (
            f"GreenwoodWilliamsonLaw(eta={s.density:.4g} 1/m^2, beta={s.radius:.4g} m, "
            f"sigma_s={s.height_std:.4g} m, y_s={s.height_mean:.4g} m, E_star={self.E_star!r})"
        )

    def _args(self):
        s = self.statistics
        return self._lnK, s.height_mean, s.height_std, self._tail, _tables()

    def separation_and_slope(self, v: ArrayLike) -> tuple[np.ndarray, np.ndarray]:
        v = real_array("v", v)
        flat = np.ascontiguousarray(v.ravel())
        u, d = np.empty_like(flat), np.empty_like(flat)
        _gw_u(flat, *self._args(), u, d)
        return u.reshape(v.shape), d.reshape(v.shape)

    def log_pressure(self, u: ArrayLike) -> np.ndarray:
        u = real_array("u", u)
        flat = np.ascontiguousarray(u.ravel())
        out = np.empty_like(flat)
        _gw_lnp(flat, *self._args(), out)
        return out.reshape(u.shape)

    def pressure(self, u: ArrayLike) -> np.ndarray:
        return np.exp(self.log_pressure(u))

    def real_area(self, p: ArrayLike) -> np.ndarray:
        """``pi eta beta sigma_s F_1(t)`` at the separation of pressure p, capped at 1 (GW
        does not know full contact)."""
        p = real_array("p", p)
        with np.errstate(divide="ignore"):
            u, _ = self.separation_and_slope(np.log(np.maximum(p, 1e-300)))
        s = self.statistics
        t = (u - s.height_mean) / s.height_std
        from scipy.special import erfc

        F1 = np.exp(-0.5 * t * t) / math.sqrt(2.0 * math.pi) - 0.5 * t * erfc(t / math.sqrt(2.0))
        return np.minimum(self._area * np.maximum(F1, 0.0), 1.0)
