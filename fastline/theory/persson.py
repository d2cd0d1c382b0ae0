"""Persson contact theory for randomly rough surfaces: P(q, p), u(p) and its inverse p(u).

Equations (docs/theory.md section 3; Persson, J. Chem. Phys. 115, 3840 (2001); Yang & Persson,
J. Phys.: Condens. Matter 20, 215214 (2008)), with ``A(q) = pi int_{q0}^q q'^3 C dq'`` and
``w(q) = A(q)^(-1/2)``:

* relative contact area ``P(q, p) = erf(w(q) p / E*)``;
* mean interfacial separation, from the elastic energy with the correction
  ``S = gamma + (1 - gamma) P^2`` and ``p = -dU/du``:

      u(p) = sqrt(pi) int_{q0}^{q1} dq q^2 C(q) w(q) F(w(q) p / E*),

  where F is the universal function of :mod:`fastline.theory.special`. The bracket
  ``gamma + 3 (1 - gamma) P^2`` inside F is d/dP [P S] from the energy derivation; some papers
  print it without the factor 3. fastline follows the derivation by default; ``variant=``
  selects the printed bracket or Wang & Mueser's correction (:mod:`fastline.theory.variants`).

Numerics
--------
* q-quadrature: Gauss-Legendre panels uniform in ln q, split at every kink of C(q). On the
  first panel ``w ~ (q - q0)^(-1/2)``: the substitution ``q = q0 + L tau^2`` removes that and a
  geometric grading of tau towards 0 resolves the logarithm of F at small pressure. There A is
  integrated from q0 directly (no cancellation in ``A(q) - A(q0)``).
* Table T1: ``ln u`` on a uniform grid of ``v = ln p`` with exact first and second
  derivatives from the quadrature (quintic Hermite interpolation). Below the grid the
  exponential law ``u = u0 ln(beta E*/p)`` continues it (the theory's own small-p asymptote),
  above it the near-full-contact form ``ln u = ln u_hi - k (p^2 - p_hi^2) - m ln(p/p_hi)``
  (the large-x behaviour of F, with k and m matching the table's slope and curvature).
  The solvers read T1 with each cell's quintic in Horner form (:func:`_solver_form`): one
  polynomial and one ``exp`` per cell inside the table, none below it.
* Table T2, for p(u): ``v`` as a cubic Hermite polynomial in u on cells that split every
  binade ``[2^e, 2^(e+1))`` of u into ``2^m`` equal parts. The cell index and the local
  coordinate are read off the bits of the float64 (exponent and leading mantissa bits), so
  evaluating p(u) costs one ``exp`` and no ``log``. Both tables share the same extensions, so
  ``pressure`` and the table u(p) are inverses.
"""

from __future__ import annotations

import math
import threading
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from fastline._lib.validate import E_STAR_RANGE, finite_array, in_range, in_span, positive_array
from fastline.theory.interface import InterfaceStatistics
from fastline.theory.quadrature import EtaRule, tabulated_quadrature
from fastline.theory.special import (
    EULER_GAMMA,
    G0,
    area_tables,
    f_coefficients,
)
from fastline.theory.spectra import PSD, TabulatedPSD
from fastline.theory.tables import (
    PerssonTables,
    _area_fraction_vec,
    _build_inverse,
    _erf_vec,
    _lnu_nodes,
    _lnu_nodes_area,
    _lnu_table,
    _pressure_from_table,
    _separation_and_slope,
    _separation_area,
    _separation_kernel,
    _solver_form,
    pressure_at,
    separation_at,
)
from fastline.theory.variants import DEFAULT_VARIANT, Variant, VariantName, get_variant

__all__ = [
    "PerssonTheory",
    "ExponentialFit",
    "TableSettings",
    "PerssonTables",
    "pressure_at",
    "separation_at",
    "GAMMA_RANGE",
]

_SQRT_PI = math.sqrt(math.pi)
#: guards the lazy build of table T2 (several threads may ask for p(u) at once)
_T2_LOCK = threading.Lock()
#: allowed range of the Yang-Persson parameter gamma
GAMMA_RANGE = (0.05, 1.0)
#: graded sub-panels towards q1; the integrand's pile-up there is ~1/(0.4 x^2) wide in ln q
_TOP_LEVELS = 5


@dataclass(frozen=True)
class TableSettings:
    """Grid sizes of the quadrature and tables (chosen from ``rtol``; see :meth:`for_rtol`)."""

    panels_per_decade: int  # Gauss-Legendre panels per decade of q
    order: int  # points per panel
    grading_levels: int  # geometric sub-panels towards q0
    graded_order: int  # points per graded sub-panel
    h_v: float  # T1 spacing in v = ln p
    log2_cells_per_binade: int  # T2: m, with 2^m cells in each binade [2^e, 2^(e+1)) of u
    tabulated: EtaRule  # q quadrature of a TabulatedPSD (fastline.theory.quadrature)

    @classmethod
    def for_rtol(cls, rtol: float) -> TableSettings:
        """Settings whose measured error is below ``rtol`` (tests/test_persson.py checks)."""
        if rtol >= 1e-4:
            return cls(
                panels_per_decade=2,
                order=6,
                grading_levels=6,
                graded_order=6,
                h_v=0.2,
                log2_cells_per_binade=4,
                tabulated=EtaRule(order=8, edge_order=6, width=1.25, bins=24, top_levels=5),
            )
        if rtol >= 1e-6:
            return cls(
                panels_per_decade=2,
                order=12,
                grading_levels=12,
                graded_order=10,
                h_v=0.1,
                log2_cells_per_binade=6,
                tabulated=EtaRule(order=10, edge_order=10, width=1.0, bins=64, top_levels=6),
            )
        return cls(
            panels_per_decade=5,
            order=14,
            grading_levels=16,
            graded_order=14,
            h_v=0.05,
            log2_cells_per_binade=7,
            tabulated=EtaRule(order=14, edge_order=12, width=1.0, bins=128, top_levels=8),
        )


@dataclass(frozen=True)
class ExponentialFit:
    """The exponential law ``p = beta E* exp(-u/u0)`` (paper eq. 5) of the theory.

    Attributes
    ----------
    u0 : float
        Decay length in m (``u0 = gamma_u h_rms``).
    beta : float
        Dimensionless prefactor.
    gamma_u : float
        ``u0 / h_rms``, the paper's gamma (about 0.4).
    """

    u0: float
    beta: float
    gamma_u: float


# ----------------------------------------------------------------------------------------------
# q quadrature
# ----------------------------------------------------------------------------------------------
def _q_quadrature(psd: PSD, settings: TableSettings):
    """Nodes q_j and weights of ``int f(q) q^2 C(q) dq`` over [q0, q1], plus A(q_j).

    Returns ``q, weight, A`` sorted by increasing q. A table takes the eta quadrature of
    :mod:`fastline.theory.quadrature` (cost independent of its size); the analytic spectra Gauss
    panels in ln q split at their few kinks.
    """
    if isinstance(psd, TabulatedPSD):
        return tabulated_quadrature(psd, settings.tabulated)
    t_ref, w_ref = np.polynomial.legendre.leggauss(settings.order)
    t_ref = 0.5 * (t_ref + 1.0)
    w_ref = 0.5 * w_ref
    q0, q1 = psd.q0, psd.q1
    bps = psd.breakpoints()
    bps = np.unique(np.concatenate([[q0], bps[(bps > q0) & (bps < q1)], [q1]]))
    edges = [q0]
    for a, b in zip(bps[:-1], bps[1:], strict=False):
        n = max(1, math.ceil(settings.panels_per_decade * math.log10(b / a)))
        edges.extend(np.geomspace(a, b, n + 1)[1:])
    edges = np.asarray(edges)
    # first panel: q = q0 + L tau^2, graded in tau
    L = edges[1] - q0
    ratio = 0.15
    tg, wg = np.polynomial.legendre.leggauss(settings.graded_order)
    tg, wg = 0.5 * (tg + 1.0), 0.5 * wg
    tau_edges = np.concatenate([[0.0], ratio ** np.arange(settings.grading_levels, -1, -1)])
    ta, tb = tau_edges[:-1, None], tau_edges[1:, None]
    tau = (ta + (tb - ta) * tg).ravel()
    dtau = ((tb - ta) * wg).ravel()
    delta = L * tau * tau
    q_first = q0 + delta
    w_first = 2.0 * L * tau * dtau
    # A(q0 + delta) = pi delta int_0^1 (q0 + delta t)^3 C(q0 + delta t) dt, no cancellation
    qq = q0 + delta[:, None] * t_ref[None, :]
    A_first = math.pi * delta * np.sum(w_ref * qq**3 * psd(qq), axis=1)
    # remaining panels: Gauss-Legendre in ln q. The last one is graded geometrically towards
    # q1: at high pressure exp(-(w p/E*)^2) concentrates the integrand against q1.
    lnq = np.log(edges[1:])
    if lnq.size >= 2:
        width = lnq[-1] - lnq[-2]
        top = lnq[-1] - width * ratio ** np.arange(_TOP_LEVELS + 1)
    else:
        top = lnq[-1:]
    la = lnq[:-2, None]
    lb = lnq[1:-1, None]
    ga = top[:, None]
    gb = np.append(top[1:], lnq[-1])[:, None]
    lq = np.concatenate([(la + (lb - la) * t_ref).ravel(), (ga + (gb - ga) * tg).ravel()])
    q_rest = np.exp(lq)
    w_rest = np.concatenate([((lb - la) * w_ref).ravel(), ((gb - ga) * wg).ravel()]) * q_rest
    A_rest = psd.cumulative(q_rest)
    q = np.concatenate([q_first, q_rest])
    return q, np.concatenate([w_first, w_rest]) * q * q * psd(q), np.concatenate([A_first, A_rest])


# ----------------------------------------------------------------------------------------------
# public class
# ----------------------------------------------------------------------------------------------
class PerssonTheory(InterfaceStatistics):
    """The full Persson contact theory for one spectrum and one material.

    Building it computes the q-quadrature and the tables (a few milliseconds); the methods are
    vectorised and cheap afterwards.

    Parameters
    ----------
    psd : PSD
        The combined roughness spectrum (m^4 vs 1/m).
    E_star : float
        Effective modulus E* in Pa (paper eq. 1), > 0.
    gamma : float, optional
        The parameter of the correction S(P), in [0.05, 1] (below 0.05 the exponential law's
        beta ~ exp(3 (1 - gamma) G(0) / gamma) overflows). Default: the variant's own, 0.45
        for the Yang-Persson variants and 5/9 for ``"wang-mueser"``.
    rtol : float, optional
        Wanted relative accuracy of the tables (default 1e-6), in [1e-9, 1e-2]; it sizes the
        quadrature and the table grids.
    variant : str, optional
        Which correction S(P) and where it enters (:mod:`fastline.theory.variants`):
        ``"yang-persson-energy"`` (default; bracket ``gamma + 3 (1 - gamma) P^2``),
        ``"yang-persson-printed"`` (bracket ``gamma + (1 - gamma) P^2``) or ``"wang-mueser"``
        (S also in the contact-area recursion; changes ``contact_area`` too).

    Notes
    -----
    ``separation(p)`` evaluates the quadrature directly (no table); ``pressure(u)`` and the
    solver use the tables, whose error against ``separation`` is below ``rtol``.
    """

    def __init__(
        self,
        psd: PSD,
        E_star: float,
        gamma: float | None = None,
        rtol: float = 1e-6,
        *,
        variant: VariantName | Variant = DEFAULT_VARIANT,
    ) -> None:
        if not isinstance(psd, PSD):
            raise TypeError(f"psd must be a fastline PSD, got {type(psd).__name__}")
        var = get_variant(variant)
        self.psd = psd
        self.E_star = in_span("E_star", E_star, E_STAR_RANGE, "Pa")
        gamma = var.default_gamma if gamma is None else gamma
        self.gamma = in_span("gamma", gamma, GAMMA_RANGE, "(dimensionless)")
        self.rtol = in_range("rtol", rtol, 1e-9, 1e-2, lo_open=False)
        self.variant = var.name
        # the area-corrected F is steeper (Y ~ x / sqrt(gamma)): at rtol 1e-6 the default
        # grids gave 1.1e-6 against the quad reference on a band of q1/q0 = 8, so one notch finer
        self.settings = TableSettings.for_rtol(self.rtol * (0.1 if var.area_correction else 1.0))
        self._bracket = var.bracket(self.gamma)
        self._correction = var.correction(self.gamma)
        if var.area_correction:  # F and the contact area of fastline.theory.special
            self._coef, self._area = None, area_tables(*self._correction)
        else:  # F of fastline.theory.special; the contact area erf(x)
            self._coef, self._area = f_coefficients(self.gamma, self._bracket[1]), None

        q, dm, A = _q_quadrature(psd, self.settings)  # dm: weights of q^2 C dq
        keep = A > 0.0
        q, dm, A = q[keep], dm[keep], A[keep]
        w = 1.0 / np.sqrt(A)
        self._q = q
        self._W = np.ascontiguousarray(_SQRT_PI * dm * w)
        self._s = np.ascontiguousarray(w / self.E_star)  # x_j = s_j p
        self._w1 = 1.0 / math.sqrt(float(psd.cumulative(psd.q1)))

        # exponential law from the small-x expansion of F (docs/theory.md section 3)
        total = float(self._W.sum())
        ln_w_mean = float(np.dot(self._W, np.log(w))) / total
        if self._area is None:  # F = -gamma ln x - gamma gamma_E / 2 + b2 G(0) + O(x^2)
            u0 = self.gamma * total
            ln_beta = -ln_w_mean - 0.5 * EULER_GAMMA + self._bracket[1] * G0() / self.gamma
        else:  # F = -lam ln x + c0 + O(x^2 ln x), lam = sqrt(gamma)
            lam, c0 = self._area[0], self._area[1]
            u0 = lam * total
            ln_beta = -ln_w_mean + c0 / lam
        self._fit = ExponentialFit(u0=u0, beta=math.exp(ln_beta), gamma_u=u0 / psd.h_rms)
        self._build_tables()

    # -- tables ---------------------------------------------------------------------------------
    def _u_direct(self, p: np.ndarray) -> np.ndarray:
        p = np.ascontiguousarray(p, dtype=np.float64)
        out = np.empty_like(p)
        if self._area is None:
            _separation_kernel(p, self._s, self._W, self.gamma, *self._coef, out)
        else:
            _separation_area(p, self._s, self._W, self._area, out)
        return out

    def _lnu(self, v: np.ndarray, L: np.ndarray, L1: np.ndarray, L2: np.ndarray) -> None:
        """ln u and its first two derivatives in v = ln p into L, L1, L2 (the quadrature)."""
        if self._area is None:
            _lnu_nodes(v, self._s, self._W, self.gamma, self._bracket[1], self._coef, L, L1, L2)
        else:
            _lnu_nodes_area(v, self._s, self._W, self._area, self._correction, L, L1, L2)

    def _build_tables(self):
        """Table T1 (u of ln p) now; table T2 (p of u) on first use (:attr:`_t2`): a Newton solve
        never needs it, and its kernels then need not be compiled or built (lazy tables)."""
        st = self.settings
        u0 = self._fit.u0
        E = self.E_star
        # low end: where the full u(p) meets the exponential law to within rtol/10
        law = lambda p: u0 * math.log(self._fit.beta * E / p)  # noqa: E731
        p_lo = 1e-6 * E
        one = np.empty(1), np.empty(1), np.empty(1)
        while p_lo > 1e-40 * E:
            self._lnu(np.array([math.log(p_lo)]), *one)
            if abs(math.exp(one[0][0]) - law(p_lo)) <= 0.1 * self.rtol * u0:
                break
            p_lo *= 1e-2
        # high end: x = w(q1) p / E* = 12, u ~ exp(-144) h_rms: beyond any physical closure
        p_hi = 12.0 * E / self._w1
        v0 = math.log(p_lo)
        n = int(math.ceil((math.log(p_hi) - v0) / st.h_v)) + 1
        h = (math.log(p_hi) - v0) / (n - 1)
        v = v0 + h * np.arange(n)
        L, L1, L2 = np.empty(n), np.empty(n), np.empty(n)
        self._lnu(v, L, L1, L2)
        # continuation above: match ln u, its slope and curvature at p_hi
        k = -L2[-1] / (4.0 * p_hi * p_hi)
        kappa = np.array([k, -L1[-1] - 2.0 * k * p_hi * p_hi])
        self._t1 = (v0, h, L, L1, L2, u0, kappa)
        self._t1_solver = _solver_form(self._t1)
        self.p_range = (p_lo, p_hi)

    @property
    def _t2(self):
        """Table T2 (module docstring), built on first use under a lock and kept."""
        t2 = self.__dict__.get("_t2_table")
        if t2 is None:
            with _T2_LOCK:
                t2 = self.__dict__.get("_t2_table")
                if t2 is None:
                    t2 = self.__dict__["_t2_table"] = self._build_t2()
        return t2

    def _build_t2(self):
        """T2 over whole binades of u, from the one holding u(x = 5) (P(q1, p) = erf(5); above,
        p(u) inverts T1) to the one holding u(p_lo)."""
        v0, h, L, L1, L2, u0, kappa = self._t1
        p_t2 = 5.0 * self.E_star / self._w1
        lu_t2, _ = _lnu_table(math.log(p_t2), v0, h, L, L1, L2, u0, kappa)
        e0 = max(math.frexp(math.exp(lu_t2))[1] - 1, -1022)  # subnormal u: T1 branch
        e1 = math.frexp(math.exp(L[0]))[1] - 1
        logm = self.settings.log2_cells_per_binade
        ncell = (e1 - e0 + 1) << logm
        V, V1 = np.empty(ncell + 1), np.empty(ncell + 1)
        _build_inverse(e0, logm, ncell, self._t1, V, V1)
        # cubic Hermite per cell in Horner form: v = c0 + t (c1 + t (c2 + t c3)), t in [0, 1)
        hu = np.ldexp(1.0, e0 - logm + np.arange(ncell) // (1 << logm))  # cell widths in u
        dV = np.diff(V)
        Cf = np.empty((ncell, 4))
        Cf[:, 0] = V[:-1]
        Cf[:, 1] = hu * V1[:-1]
        Cf[:, 2] = 3.0 * dV - hu * (2.0 * V1[:-1] + V1[1:])
        Cf[:, 3] = -2.0 * dV + hu * (V1[:-1] + V1[1:])
        base = (e0 + 1023) << logm
        return (Cf, base, logm, 1.0 / u0, math.exp(L[0]), v0, V[0], self._t1)

    # -- public methods -------------------------------------------------------------------------
    def separation(self, p: ArrayLike) -> np.ndarray:
        """Mean interfacial separation u(p) in m for nominal pressures p in Pa (> 0).

        Evaluates the Yang-Persson integral directly (quadrature over q with the universal
        function F), not the table. Vectorised; returns an array shaped like ``p``.
        """
        p = positive_array("p", p)
        return self._u_direct(p.ravel()).reshape(p.shape)

    def pressure(self, u: ArrayLike) -> np.ndarray:
        """Nominal pressure p(u) in Pa for separations u in m (> 0): the inverse of u(p).

        From the tables (relative accuracy ``rtol``) up to ``w(q1) p/E* = 12`` (u < 1e-60 m for
        the paper's surfaces); above, a continuation fitted to the large-x form of F (relative
        error ~1e-4 at twice that pressure). Beyond them: the exponential law at large
        u (p decays like exp(-u/u0), underflowing to 0 rather than turning negative) and the
        near-full-contact form ``p = sqrt(p_hi^2 + ln(u_hi/u)/kappa)`` at small u, which grows
        without bound but stays finite for every u > 0.
        """
        u = positive_array("u", u)
        flat = np.ascontiguousarray(u.ravel())
        return _pressure_from_table(flat, self._t2).reshape(u.shape)

    def separation_table(self, p: ArrayLike) -> tuple[np.ndarray, np.ndarray]:
        """u(p) in m and du/dv (v = ln p) from the table T1 (its Hermite data; the solvers
        evaluate the same polynomials in Horner form, round-off apart: :func:`solver_law`)."""
        p = positive_array("p", p)
        v = np.ascontiguousarray(np.log(p.ravel()))
        u, d = np.empty_like(v), np.empty_like(v)
        _separation_and_slope(v, *self._t1, u, d)
        return u.reshape(p.shape), d.reshape(p.shape)

    @property
    def rms_slope(self) -> float:
        """Root-mean-square slope h' of the spectrum (dimensionless), ``h'^2 = 2 A(q1)``; kept
        from the construction (the solvers' diagnostics ask for it on every solve)."""
        return math.sqrt(2.0) / self._w1

    def contact_area(self, p: ArrayLike, q: ArrayLike | None = None) -> np.ndarray:
        """Relative contact area ``P(q, p) = erf(w(q) p / E*)`` (dimensionless); for the
        ``"wang-mueser"`` variant ``erf(Y(w(q) p / E*))`` (:mod:`fastline.theory.special`).

        Parameters
        ----------
        p : array_like
            Nominal pressure in Pa (>= 0).
        q : array_like, optional
            Magnification wavenumber in 1/m, in [q0, q1]; default q1 (the real contact area).
            ``p`` and ``q`` broadcast against each other.
        """
        p = finite_array("p", p)
        if np.any(p < 0.0):
            raise ValueError("p must be >= 0 Pa everywhere (allowed range [0, inf))")
        if q is None:
            w = self._w1
        else:
            q = finite_array("q", q)
            if np.any((q < self.psd.q0) | (q > self.psd.q1)):
                raise ValueError(f"q must lie in [q0, q1] = [{self.psd.q0:g}, {self.psd.q1:g}] 1/m")
            A = self.psd.cumulative(q)
            with np.errstate(divide="ignore"):
                w = np.where(A > 0.0, 1.0 / np.sqrt(np.maximum(A, 0.0)), np.inf)
        with np.errstate(invalid="ignore"):
            x = np.asarray(w * p / self.E_star, dtype=np.float64)
        x = np.where(np.isnan(x), 0.0, x)  # inf * 0 at q = q0, p = 0
        flat = np.ascontiguousarray(x.ravel())
        out = np.empty_like(flat)
        if self._area is None:
            _erf_vec(flat, out)
        else:
            _area_fraction_vec(flat, self._area, out)
        return out.reshape(x.shape)

    def _real_area(self, p: np.ndarray) -> np.ndarray:
        """``P(q1, p)`` for a contiguous float64 array of p >= 0 (no checks: the solvers'
        own pressures)."""
        out = np.empty_like(p)
        x = self._w1 * p  # then / E*, as contact_area rounds (one temporary: GIL held)
        x /= self.E_star
        if self._area is None:
            _erf_vec(x, out)
        else:
            _area_fraction_vec(x, self._area, out)
        return out

    def exponential_fit(self) -> ExponentialFit:
        """u0 and beta of ``p = beta E* exp(-u/u0)`` (paper eq. 5) from the theory itself.

        From the small-argument expansion ``F(x) = -gamma ln x - gamma gamma_E/2
        + b2 G(0) + O(x^2)`` (``b2 = 3 (1-gamma)``, or ``1 - gamma`` for the printed bracket):
        ``u0 = sqrt(pi) gamma int dq q^2 C w`` and ``ln beta = -<ln w> - gamma_E/2 +
        b2 G(0)/gamma`` (the mean weighted by ``q^2 C w``). For ``"wang-mueser"``,
        ``F = -sqrt(gamma) ln x + c0 + O(x^2 ln x)``: gamma becomes sqrt(gamma) in u0 and
        ``ln beta = -<ln w> + c0 / sqrt(gamma)``. The full u(p) approaches this law as p -> 0.
        """
        return self._fit

    def exponential_valid_range(self, rtol: float = 0.05) -> tuple[float, float]:
        """``(0, p_top)`` in Pa: where ``u0 ln(beta E*/p)`` is within ``rtol`` of the full u(p).

        The exponential law is the small-p asymptote, so the range starts at 0; it ends at the
        first of 400 log-spaced pressures over the table range where the mismatch exceeds
        ``rtol``. Computed once per theory and ``rtol`` (400 direct evaluations, ~3 ms) and kept
        on the instance. ``(nan, nan)`` if the law fails already at the bottom of the table.
        """
        rtol = in_span("rtol", rtol, (1e-12, 1.0), "(relative)")
        cache = self.__dict__.setdefault("_exp_ranges", {})
        if rtol not in cache:
            fit = self._fit
            lo, hi = self.p_range
            p = np.logspace(math.log10(lo), math.log10(hi), 400)
            L, L1, L2 = np.empty(400), np.empty(400), np.empty(400)
            self._lnu(np.log(p), L, L1, L2)
            with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
                u_full = np.exp(L)  # the direct quadrature (the kernel the tables use)
                ok = np.abs(fit.u0 * np.log(fit.beta * self.E_star / p) - u_full) <= rtol * u_full
            bad = np.nonzero(~ok)[0]
            if not ok[0]:
                cache[rtol] = (math.nan, math.nan)
            else:
                cache[rtol] = (0.0, float(p[bad[0] - 1] if bad.size else p[-1]))
        return cache[rtol]

    def jit(self) -> PerssonTables:
        """The tables as a :data:`PerssonTables` namedtuple for users' own ``@njit`` code.

        Pass it to :func:`fastline.pressure_at` and :func:`fastline.separation_at` inside
        compiled loops (docs/embedding.md)::

            tables = theory.jit()

            @numba.njit
            def pressures(u, tables):
                out = np.empty_like(u)
                for i in range(u.size):
                    out[i] = fastline.pressure_at(tables, u[i])
                return out

        The arrays are read-only views of the theory's own tables (no copy).
        """
        v0, h, L, L1, L2, u0, kappa = self._t1
        Cf, base, logm, inv_u0, u_lo, v_lo, v_first, _ = self._t2
        views = []
        for a in (L, L1, L2, kappa, Cf):
            a = a.view()
            a.flags.writeable = False
            views.append(a)
        L, L1, L2, kappa, Cf = views
        return PerssonTables(
            float(v0),
            float(h),
            L,
            L1,
            L2,
            float(u0),
            kappa,
            Cf,
            np.int64(base),
            np.int64(logm),
            float(inv_u0),
            float(u_lo),
            float(v_lo),
            float(v_first),
        )

    def __repr__(self):
        extra = "" if self.variant == DEFAULT_VARIANT else f", variant={self.variant!r}"
        return f"PerssonTheory({self.psd!r}, E_star={self.E_star!r}, gamma={self.gamma!r}{extra})"
