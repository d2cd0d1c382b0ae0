"""Isotropic surface-roughness power spectra C(q).

Convention (Persson's; docs/theory.md section 2). ``C(q)`` is the isotropic 2D power spectrum in
m^4 as a function of the wavenumber magnitude q in 1/m, normalised so that

    h_rms^2 = 2 pi int q C(q) dq,        h'^2 = 2 pi int q^3 C(q) dq  (rms slope squared).

Other codes use other factors (SurfaceTopography's isotropic PSD is (2 pi)^2 times this C, for
example); convert before building a :class:`TabulatedPSD`.

The Persson theory needs the cumulative moment

    A(q) = pi int_0^q q'^3 C(q') dq'      (dimensionless; A(q1) = h'^2 / 2),

which every spectrum here returns exactly: in closed form for :class:`SelfAffinePSD`, by exact
integration of the log-log interpolant for :class:`TabulatedPSD`.

Spectra add (``psd1 + psd2``), the combined roughness of two uncorrelated surfaces (paper eq. 2).
"""

from __future__ import annotations

import math
import warnings

import numpy as np
from numpy.typing import ArrayLike

from fastline._lib.validate import (
    E_STAR_RANGE,
    LENGTH_RANGE,
    WAVENUMBER_RANGE,
    finite_array,
    in_range,
    in_span,
    positive,
    real_array,
)
from fastline.errors import ImplausibleSpectrumError, UnitWarning
from fastline.theory.quadrature import interval_moments

__all__ = [
    "PSD",
    "SelfAffinePSD",
    "TabulatedPSD",
    "SumPSD",
    "effective_modulus",
    "check_modulus",
    "E_STAR_PLAUSIBLE",
]

#: effective moduli (Pa) of real solid pairs: soft gels and foams ~1e4, seal elastomers 1e6-1e8,
#: polymers ~1e9, metals ~1e11, diamond on diamond ~6e11. Outside, a unit slip is likely.
E_STAR_PLAUSIBLE = (1e4, 1.2e12)


def _power_integral(t, e):
    """``int_1^t tau^(e-1) d tau`` for t >= 1, stable as e -> 0 (it becomes ln t)."""
    log_t = np.log(t)
    if e == 0.0:
        return log_t
    return np.expm1(e * log_t) / e


class PSD:
    """Base class of the power spectra. Subclasses implement ``_moment``, ``__call__``.

    Attributes
    ----------
    q0, q1 : float
        Support of the spectrum in 1/m: ``C(q) = 0`` outside ``[q0, q1]``.
    """

    q0: float
    q1: float

    def __call__(self, q: ArrayLike) -> np.ndarray:  # pragma: no cover - abstract
        raise NotImplementedError

    def _moment(self, k: int, q: np.ndarray) -> np.ndarray:  # pragma: no cover - abstract
        """``int_0^q q'^k C(q') dq'`` for k in (1, 3), vectorised over q."""
        raise NotImplementedError

    def breakpoints(self) -> np.ndarray:  # pragma: no cover - abstract
        """Wavenumbers (1/m) where C(q) is not smooth, including q0 and q1."""
        raise NotImplementedError

    @property
    def _theories(self) -> dict:
        """Persson theories built for this spectrum by the one-call solvers, keyed by
        (E*, gamma, variant) (:func:`fastline.contact.line.shared_theory`); not pickled."""
        cache = self.__dict__.get("_theory_cache")
        if cache is None:
            cache = self.__dict__.setdefault("_theory_cache", {})
        return cache

    def __getstate__(self):
        state = self.__dict__.copy()
        state.pop("_theory_cache", None)
        return state

    # -- derived quantities (shared) ------------------------------------------------------------
    def cumulative(self, q: ArrayLike) -> np.ndarray:
        """``A(q) = pi int_0^q q'^3 C(q') dq'`` (dimensionless), docs/theory.md section 3."""
        q = real_array("q", q)
        return math.pi * self._moment(3, q)

    @property
    def h_rms(self) -> float:
        """Root-mean-square roughness amplitude in m."""
        return math.sqrt(2.0 * math.pi * float(self._moment(1, np.float64(self.q1))))

    @property
    def rms_slope(self) -> float:
        """Root-mean-square slope h' (dimensionless), ``h'^2 = 2 A(q1)``."""
        return math.sqrt(2.0 * float(self.cumulative(self.q1)))

    def __add__(self, other: PSD) -> SumPSD:
        if not isinstance(other, PSD):
            return NotImplemented
        return SumPSD(self, other)


class SelfAffinePSD(PSD):
    """Self-affine fractal spectrum with a roll-off (the paper's surfaces, Fig. 2).

    ``C(q) = C0`` for ``q0 <= q < qr``, ``C0 (q/qr)^(-2(1+H))`` for ``qr <= q <= q1``, zero
    outside. ``qr == q0`` means no roll-off region.

    Parameters
    ----------
    h_rms : float
        Root-mean-square roughness in m, in [1e-12, 0.1]. ``C0`` is derived from it in closed
        form.
    hurst : float
        Hurst exponent H in (0, 1]; H = 1 is handled exactly (logarithms).
    q0, qr, q1 : float
        Lowest wavenumber, roll-off wavenumber and cut-off in 1/m, ``q0 <= qr < q1``, each in
        [1e-3, 1e13].
    """

    def __init__(self, h_rms: float, hurst: float, q0: float, qr: float, q1: float) -> None:
        self._h_rms = in_span("h_rms", h_rms, LENGTH_RANGE, "m")
        self.hurst = in_range("hurst", hurst, 0.0, 1.0)
        self.q0 = in_span("q0", q0, WAVENUMBER_RANGE, "1/m")
        self.qr = in_span("qr", qr, WAVENUMBER_RANGE, "1/m")
        if self.qr < self.q0:
            raise ValueError(f"qr must satisfy qr >= q0 = {self.q0:g} 1/m, got {self.qr!r}")
        self.q1 = in_span("q1", q1, WAVENUMBER_RANGE, "1/m")
        if self.q1 <= self.qr:
            raise ValueError(f"q1 must satisfy q1 > qr = {self.qr:g} 1/m, got {self.q1!r}")
        H = self.hurst
        # h_rms^2 = 2 pi C0 [ (qr^2 - q0^2)/2 + qr^2 int_1^(q1/qr) t^(-1-2H) dt ]
        tail = _power_integral(self.q1 / self.qr, -2.0 * H)  # = (1 - (q1/qr)^(-2H)) / (2H)
        self.C0 = self._h_rms**2 / (
            2.0 * math.pi * (0.5 * (self.qr**2 - self.q0**2) + self.qr**2 * tail)
        )

    @property
    def h_rms(self) -> float:
        return self._h_rms

    def __repr__(self):
        return (
            f"SelfAffinePSD(h_rms={self._h_rms!r}, hurst={self.hurst!r}, q0={self.q0!r}, "
            f"qr={self.qr!r}, q1={self.q1!r})"
        )

    def __call__(self, q: ArrayLike) -> np.ndarray:
        """C(q) in m^4 for q in 1/m (vectorised)."""
        q = real_array("q", q)
        ratio = np.maximum(q, self.qr) / self.qr
        c = self.C0 * ratio ** (-2.0 * (1.0 + self.hurst))
        return np.where((q >= self.q0) & (q <= self.q1), c, 0.0)

    def _moment(self, k, q):
        q = np.asarray(q, dtype=np.float64)
        m = np.clip(q, self.q0, self.qr)
        flat = (m ** (k + 1) - self.q0 ** (k + 1)) / (k + 1)
        t = np.clip(q, self.qr, self.q1) / self.qr
        power = self.qr ** (k + 1) * _power_integral(t, k - 1 - 2.0 * self.hurst)
        return self.C0 * (flat + power)

    def breakpoints(self) -> np.ndarray:
        return np.unique(np.array([self.q0, self.qr, self.q1]))


class TabulatedPSD(PSD):
    """A spectrum given as (q, C) pairs, interpolated log-log, zero outside the table.

    On each interval ``[q_i, q_i+1]`` the spectrum is the power law through the two end
    points, so the moments are integrated exactly. An interval with a zero end point is zero.

    Parameters
    ----------
    q : array_like
        Wavenumbers in 1/m, strictly increasing, > 0, at least 2 points.
    C : array_like
        Power spectrum in m^4 at ``q``, >= 0 (same length).
    """

    def __init__(self, q: ArrayLike, C: ArrayLike) -> None:
        q = finite_array("q", q, ndim=1)
        C = finite_array("C", C, ndim=1)
        if q.size < 2:
            raise ValueError(f"q must hold at least 2 points, got {q.size}")
        if C.shape != q.shape:
            raise ValueError(f"C must have the same length as q ({q.size}), got {C.size}")
        if np.any(q <= 0.0):
            raise ValueError("q must be > 0 everywhere (allowed range (0, inf) 1/m)")
        if np.any(np.diff(q) <= 0.0):
            raise ValueError("q must be strictly increasing")
        if np.any(C < 0.0):
            raise ValueError("C must be >= 0 everywhere (allowed range [0, inf) m^4)")
        live = (C[:-1] > 0.0) & (C[1:] > 0.0)
        if not np.any(live):
            raise ValueError("C must be > 0 on at least one interval of q")
        self.q = q
        self.C = C
        self._live = live
        with np.errstate(divide="ignore", invalid="ignore"):
            self._dt = np.log(q[1:] / q[:-1])
            slope = np.log(C[1:] / C[:-1]) / self._dt
        self._slope = np.where(live, slope, 0.0)
        first = int(np.argmax(live))
        last = len(live) - 1 - int(np.argmax(live[::-1]))
        self.q0 = float(q[first])
        self.q1 = float(q[last + 1])
        # exact moments of each whole interval (k = 1, 3 cumulated) and the per-interval
        # moments of the Persson measure that make the theory's quadrature table-size free
        cum1, cum3, self._measure = interval_moments(q, C, self._dt, self._slope, live)
        self._cum = {1: cum1, 3: cum3}
        with np.errstate(over="ignore", invalid="ignore"):  # absurd tables: checked here
            self._check_plausible()

    def _check_plausible(self):
        """Wavenumbers and the h_rms the table implies inside fastline's ranges."""
        lo, hi = WAVENUMBER_RANGE
        if not (lo <= self.q[0] and self.q[-1] <= hi):
            raise ValueError(f"q must lie in [{lo:g}, {hi:g}] 1/m (check the units: 1/m)")
        h = self.h_rms
        if not (LENGTH_RANGE[0] <= h <= LENGTH_RANGE[1]) or not math.isfinite(self.rms_slope):
            raise ImplausibleSpectrumError(
                f"C gives h_rms = {h:.3g} m, outside [{LENGTH_RANGE[0]:g}, {LENGTH_RANGE[1]:g}] m "
                "(check the units: C in m^4, q in 1/m, Persson's convention h_rms^2 = "
                "2 pi int q C dq)",
                h,
                LENGTH_RANGE,
            )

    def __repr__(self):
        return f"TabulatedPSD(<{self.q.size} points, q from {self.q[0]:g} to {self.q[-1]:g} 1/m>)"

    def _index(self, q):
        return np.clip(np.searchsorted(self.q, q, side="right") - 1, 0, self.q.size - 2)

    def _partial(self, k, i, b):
        """Exact ``int_{q_i}^{b} q^k C dq`` on intervals i, with b inside each (vectorised)."""
        qi = self.q[i]
        e = k + 1 + self._slope[i]
        log_t = np.log(b / qi)
        safe_e = np.where(e == 0.0, 1.0, e)
        part = np.where(e == 0.0, log_t, np.expm1(safe_e * log_t) / safe_e)
        return np.where(self._live[i], self.C[i] * qi ** (k + 1) * part, 0.0)

    def __call__(self, q: ArrayLike) -> np.ndarray:
        """C(q) in m^4 for q in 1/m (vectorised), log-log interpolated."""
        q = real_array("q", q)
        i = self._index(q)
        qc = np.clip(q, self.q[0], self.q[-1])  # no 0 ** -slope (q = 0 of an FFT grid) outside
        c = self.C[i] * (qc / self.q[i]) ** self._slope[i]
        inside = (q >= self.q[0]) & (q <= self.q[-1]) & self._live[i]
        return np.where(inside, c, 0.0)

    def _moment(self, k, q):
        q = np.asarray(q, dtype=np.float64)
        qc = np.clip(q, self.q[0], self.q[-1])
        i = self._index(qc)
        return self._cum[k][i] + self._partial(k, i, qc)

    def breakpoints(self) -> np.ndarray:
        return self.q[(self.q >= self.q0) & (self.q <= self.q1)].copy()


class SumPSD(PSD):
    """The spectrum of the combined roughness of uncorrelated surfaces (paper eq. 2).

    ``C(q) = sum_i C_i(q)``; all moments add. Usually made with ``psd1 + psd2``.
    """

    def __init__(self, *parts: PSD) -> None:
        flat = []
        for p in parts:
            if not isinstance(p, PSD):
                raise ValueError(f"parts must be PSD instances, got {type(p).__name__}")
            flat.extend(p.parts if isinstance(p, SumPSD) else [p])
        if not flat:
            raise ValueError("parts must hold at least one spectrum")
        self.parts = tuple(flat)
        self.q0 = min(p.q0 for p in flat)
        self.q1 = max(p.q1 for p in flat)

    def __repr__(self):
        return " + ".join(repr(p) for p in self.parts)

    def __call__(self, q: ArrayLike) -> np.ndarray:
        return sum(p(q) for p in self.parts)

    def _moment(self, k, q):
        return sum(p._moment(k, q) for p in self.parts)

    def breakpoints(self) -> np.ndarray:
        return np.unique(np.concatenate([p.breakpoints() for p in self.parts]))


def effective_modulus(E1: float, nu1: float, E2: float, nu2: float) -> float:
    """Effective plane-strain modulus E* in Pa of two elastic bodies (paper eq. 1).

    ``1/E* = (1 - nu1^2)/E1 + (1 - nu2^2)/E2``.

    Parameters
    ----------
    E1, E2 : float
        Young's moduli in Pa (> 0).
    nu1, nu2 : float
        Poisson ratios in (-1, 0.5].
    """
    E1 = positive("E1", E1, "Pa")
    E2 = positive("E2", E2, "Pa")
    nu1 = in_range("nu1", nu1, -1.0, 0.5)
    nu2 = in_range("nu2", nu2, -1.0, 0.5)
    return 1.0 / ((1.0 - nu1**2) / E1 + (1.0 - nu2**2) / E2)


def check_modulus(E_star: float, name: str = "E_star", *, stacklevel: int = 1) -> float:
    """An effective modulus E* in Pa, checked: a ValueError outside ``[1, 1e13]`` Pa, one
    :class:`~fastline.errors.UnitWarning` naming the likely unit slip outside the plausible
    ``E_STAR_PLAUSIBLE`` = [1e4, 1.2e12] Pa (``E_star = 5`` is 5 Pa, softer than any seal
    material: 5 MPa is ``5e6``).

    Parameters
    ----------
    E_star : float
        Effective (plane-strain) modulus in Pa.
    name : str
        How messages name it.
    stacklevel : int
        Where the warning points: 1 the caller of ``check_modulus``, 2 its caller, and so on.

    Returns
    -------
    float
        ``E_star`` as a float.
    """
    E = in_span(name, E_star, E_STAR_RANGE, "Pa")
    hint = modulus_slip(E)
    if hint is not None:
        warnings.warn(f"fastline: {name} = {E:g} Pa {hint}", UnitWarning, stacklevel=stacklevel + 1)
    return E


def modulus_slip(E_star: float) -> str | None:
    """Why an effective modulus in Pa is implausible and the units it was likely typed in, or
    None inside ``E_STAR_PLAUSIBLE``."""
    lo, hi = E_STAR_PLAUSIBLE
    if E_star < lo:
        units = (("kPa", 1e3), ("MPa", 1e6)) if E_star >= 1e3 else (("MPa", 1e6), ("GPa", 1e9))
        guesses = " or ".join(f"{E_star:g} {u} = {E_star * f:g} Pa" for u, f in units)
        return (
            f"is softer than any solid seal material (plausible E* {lo:g} to {hi:g} Pa): a "
            f"unit slip? E* is in Pa ({guesses})"
        )
    if E_star > hi:
        return (
            f"is stiffer than diamond on diamond (plausible E* {lo:g} to {hi:g} Pa): a unit "
            f"slip? E* is in Pa ({E_star:g} Pa = {E_star * 1e-9:g} GPa)"
        )
    return None
