"""Pressure-separation laws p(u): what the contact solvers consume (``model=`` argument).

A law relates the nominal pressure p [Pa] acting on a patch of the rough interface to the mean
separation u [m] of the surfaces there. The solvers work on ``v = ln p`` (p > 0 for free, 100+
decades between the contact centre and the domain edge without underflow), so the central
method takes arrays of ln p.

The protocol (:class:`PressureLaw`)
-----------------------------------
``u0`` : float
    A decay length in m: the scale of u over which p changes by a factor e at low pressure
    (``-du/dln p`` there). The solvers measure their residual in units of it.
``separation_and_slope(v) -> (u, dudv)``
    u [m] and ``du/d(ln p)`` [m] at ``v = ln p`` (float64 arrays of the same shape). The law must
    be strictly decreasing in p: ``dudv < 0`` everywhere.
``pressure(u) -> p`` and ``log_pressure(u) -> ln p``
    The inverse, for any finite u (the laws here extend beyond their tables so it never fails).
``real_area(p) -> A/A0 or None``
    Real contact area fraction at nominal pressure p, if the law knows it.

Subclass :class:`PressureLaw` and implement ``u0`` and ``separation_and_slope``: the base class
inverts it for ``pressure`` (vectorised safeguarded Newton) and returns None for
``real_area``. The solvers use nothing else, so a user's own law never needs fastline's
internals.

Laws shipped
------------
* :class:`PerssonLaw` - the full Persson theory through the tables of a
  :class:`~fastline.theory.persson.PerssonTheory` (default).
* :class:`ExponentialLaw` - ``p = beta E* exp(-u/u0)`` (paper eq. 5; Persson, PRL 99, 125502
  (2007)): u is linear in ln p, it makes the large-alpha Gaussian limit exact.
* :class:`~fastline.theory.asperity.GreenwoodWilliamsonLaw` (in :mod:`fastline.theory.asperity`) -
  the Greenwood-Williamson asperity model with summit statistics from the same spectrum.
* :class:`TabulatedLaw` - a p(u) curve measured or computed elsewhere, interpolated
  monotonically (piecewise cubic Hermite of u in ln p, Fritsch-Butland slopes) with exponential
  extensions at both ends.

Smooth surfaces (hard contact) are not a p(u) law: ``model="hertz"`` is handled by the solvers.
"""

from __future__ import annotations

import abc
import math
from typing import Any

import numba
import numpy as np
from numpy.typing import ArrayLike

from fastline._lib.jit import JIT
from fastline._lib.validate import E_STAR_RANGE, finite_array, in_span, positive, real_array
from fastline.theory.persson import PerssonTheory
from fastline.theory.tables import _log_pressure_from_table, _pressure_from_table, solver_law

__all__ = ["PressureLaw", "PerssonLaw", "ExponentialLaw", "TabulatedLaw", "check_law", "hermite"]

#: ranges of user-given exponential-law parameters
U0_RANGE = (1e-15, 1.0)  # m
BETA_RANGE = (1e-12, 1e12)  # dimensionless


class PressureLaw(abc.ABC):
    """Base class of the pressure-separation laws (module docstring for the protocol)."""

    #: short name used in results and messages
    name: str = "custom"
    #: decay length in m (see the module docstring)
    u0: float

    @abc.abstractmethod
    def separation_and_slope(self, v: ArrayLike) -> tuple[np.ndarray, np.ndarray]:
        """u [m] and du/d(ln p) [m] at ``v = ln p`` (arrays, same shape as v)."""

    def log_pressure(self, u: ArrayLike) -> np.ndarray:
        """ln p(u) (p in Pa) by safeguarded Newton on :meth:`separation_and_slope`."""
        u = real_array("u", u)
        v = np.zeros_like(u)
        for _ in range(200):
            U, dU = self.separation_and_slope(v)
            step = np.clip((U - u) / dU, -5.0, 5.0)
            v = v - step
            if np.all(np.abs(step) < 1e-13 * np.maximum(1.0, np.abs(v))):
                break
        return v

    def pressure(self, u: ArrayLike) -> np.ndarray:
        """p(u) in Pa for separations u in m."""
        return np.exp(self.log_pressure(u))

    def real_area(self, p: ArrayLike) -> np.ndarray | None:
        """Real contact area fraction at pressure p, or None if the law does not know it."""
        return None


def check_law(law: Any) -> PressureLaw:
    """Check that ``law`` satisfies the protocol (duck typing allowed); return it.

    Raises a ``TypeError`` naming what is missing and a ``ValueError`` when a probe evaluation
    at three pressures gives non-finite values, a wrong shape or a slope that is positive
    anywhere or nowhere negative (a slope of 0 is allowed where u has underflowed to full
    contact, e.g. a Persson law of a soft solid at 1e8 Pa).
    """
    for attr in ("u0", "separation_and_slope", "pressure"):
        if not hasattr(law, attr):
            raise TypeError(
                f"model must be 'persson', 'exponential', 'hertz' or a pressure law with u0, "
                f"separation_and_slope(v) and pressure(u); {type(law).__name__} has no {attr!r}"
            )
    positive("model.u0", law.u0, "m")
    v = np.log(np.array([1e2, 1e5, 1e8]))
    try:
        u, d = law.separation_and_slope(v)
    except Exception as e:  # a user's law: report what went wrong in its terms
        raise ValueError(f"model.separation_and_slope failed on ln p = {v}: {e}") from e
    u, d = np.asarray(u, dtype=np.float64), np.asarray(d, dtype=np.float64)
    if u.shape != v.shape or d.shape != v.shape:
        raise ValueError("model.separation_and_slope(v) must return two arrays shaped like v")
    decreasing = np.all(d <= 0.0) and np.any(d < 0.0)
    if not (np.all(np.isfinite(u)) and np.all(np.isfinite(d)) and decreasing):
        raise ValueError(
            "model.separation_and_slope(v) must return finite u and a slope du/dln p < 0 "
            f"(got u = {u}, slope = {d} at p = 1e2, 1e5, 1e8 Pa)"
        )
    return law


# ----------------------------------------------------------------------------------------------
# laws shipped with fastline
# ----------------------------------------------------------------------------------------------
class PerssonLaw(PressureLaw):
    """The full Persson u(p) through the tables of a
    :class:`~fastline.theory.persson.PerssonTheory`.

    ``separation_and_slope`` reads table T1 (quintic Hermite in ln p), ``pressure`` table T2
    (its inverse); both to the theory's ``rtol`` (docs/theory.md, "Persson's law").
    """

    name = "persson"

    def __init__(self, theory: PerssonTheory) -> None:
        if not isinstance(theory, PerssonTheory):
            raise TypeError(f"theory must be a PerssonTheory, got {type(theory).__name__}")
        self.theory = theory
        self.u0 = theory.exponential_fit().u0

    def __repr__(self):
        return f"PerssonLaw({self.theory!r})"

    def separation_and_slope(self, v: ArrayLike) -> tuple[np.ndarray, np.ndarray]:
        v = np.ascontiguousarray(real_array("v", v))
        u = np.empty_like(v)
        d = np.empty_like(v)
        solver_law(v.ravel(), *self.theory._t1_solver, u.ravel(), d.ravel())
        return u, d

    def log_pressure(self, u: ArrayLike) -> np.ndarray:
        u = np.ascontiguousarray(np.maximum(real_array("u", u), 1e-300))
        return _log_pressure_from_table(u.ravel(), self.theory._t2).reshape(u.shape)

    def pressure(self, u: ArrayLike) -> np.ndarray:
        u = np.ascontiguousarray(np.maximum(real_array("u", u), 1e-300))
        return _pressure_from_table(u.ravel(), self.theory._t2).reshape(u.shape)

    def real_area(self, p: ArrayLike) -> np.ndarray:
        p = real_array("p", p)
        if p.ndim == 1 and (p.size == 0 or p.min() >= 0.0):  # a solver's own: the fast path
            return self.theory._real_area(p)
        return self.theory.contact_area(p)

    def _compiled_form(self):
        """``(kind, prm, A, B, C, E)`` for the compiled line-contact Newton
        (:mod:`fastline.contact.line_newton`): table T1 in its solver form (``A`` the Horner
        coefficients; :func:`fastline.theory.tables._solver_form`)."""
        prm, Cf = self.theory._t1_solver
        dummy = np.zeros(1)
        return 0, prm, Cf, dummy, dummy, dummy


class ExponentialLaw(PressureLaw):
    """``p = beta E* exp(-u/u0)`` (paper eq. 5; Persson, PRL 99, 125502 (2007)).

    Parameters
    ----------
    u0 : float
        Decay length in m, in [1e-15, 1].
    beta : float
        Dimensionless prefactor, in [1e-12, 1e12].
    E_star : float
        Effective modulus in Pa, in [1, 1e13].
    theory : PerssonTheory, optional
        Only used to report the real contact area.

    See Also
    --------
    ExponentialLaw.from_theory : u0 and beta of the full theory's small-p asymptote.
    """

    name = "exponential"

    def __init__(
        self, u0: float, beta: float, E_star: float, theory: PerssonTheory | None = None
    ) -> None:
        if theory is not None and not isinstance(theory, PerssonTheory):
            raise TypeError(f"theory must be a PerssonTheory or None, got {type(theory).__name__}")
        self._set(
            in_span("u0", u0, U0_RANGE, "m"),
            in_span("beta", beta, BETA_RANGE, "(dimensionless)"),
            in_span("E_star", E_star, E_STAR_RANGE, "Pa"),
            theory,
        )

    def _set(self, u0: float, beta: float, E_star: float, theory) -> None:
        self.u0, self.beta, self.E_star, self.theory = u0, beta, E_star, theory
        self._lnpb = math.log(beta) + math.log(E_star)

    @classmethod
    def from_theory(
        cls, theory: PerssonTheory, u0: float | None = None, beta: float | None = None
    ) -> ExponentialLaw:
        """The law of ``theory.exponential_fit()``; u0 and/or beta may be overridden (then
        checked against the ranges of the constructor). The theory's own values are used as
        they are: for extreme spectra its beta can lie outside the range a user may give."""
        if not isinstance(theory, PerssonTheory):
            raise TypeError(f"theory must be a PerssonTheory, got {type(theory).__name__}")
        fit = theory.exponential_fit()
        law = cls.__new__(cls)
        law._set(
            fit.u0 if u0 is None else in_span("u0", u0, U0_RANGE, "m"),
            fit.beta if beta is None else in_span("beta", beta, BETA_RANGE, "(dimensionless)"),
            theory.E_star,
            theory,
        )
        return law

    def __repr__(self):
        return f"ExponentialLaw(u0={self.u0!r}, beta={self.beta!r}, E_star={self.E_star!r})"

    def separation_and_slope(self, v: ArrayLike) -> tuple[np.ndarray, np.ndarray]:
        v = real_array("v", v)
        return self.u0 * (self._lnpb - v), np.full_like(v, -self.u0)

    def log_pressure(self, u: ArrayLike) -> np.ndarray:
        return self._lnpb - real_array("u", u) / self.u0

    def pressure(self, u: ArrayLike) -> np.ndarray:
        return np.exp(self.log_pressure(u))

    def real_area(self, p: ArrayLike) -> np.ndarray | None:
        return None if self.theory is None else self.theory.contact_area(p)

    def _compiled_form(self):
        """``(kind, prm, ...)`` for the compiled line-contact Newton: u0 and ln(beta E*)."""
        dummy = np.zeros(1)
        return 1, np.array([self.u0, self._lnpb]), dummy, dummy, dummy, dummy


# ----------------------------------------------------------------------------------------------
# tabulated law: monotone cubic Hermite of u in v = ln p
# ----------------------------------------------------------------------------------------------
def _monotone_slopes(v: np.ndarray, u: np.ndarray) -> np.ndarray:
    """Node slopes du/dv of a monotone piecewise cubic Hermite interpolant.

    Interior nodes: the weighted harmonic mean of the neighbouring secants (Fritsch & Butland,
    SIAM J. Sci. Stat. Comput. 5, 300 (1984)), which keeps every cell monotone for strictly
    monotone data; end nodes: the end cell's secant, which is also the slope of the exponential
    extension, so the law is C1 everywhere.
    """
    h = np.diff(v)
    delta = np.diff(u) / h
    d = np.empty_like(u)
    d[0], d[-1] = delta[0], delta[-1]
    w1 = 2.0 * h[1:] + h[:-1]
    w2 = h[1:] + 2.0 * h[:-1]
    d[1:-1] = (w1 + w2) / (w1 / delta[:-1] + w2 / delta[1:])
    return d


@numba.njit(**JIT)
def hermite(v: float, V: np.ndarray, U: np.ndarray, S: np.ndarray, k: int) -> tuple[float, float]:
    """u and du/dv on cell k of the cubic Hermite with values U and slopes S at nodes V."""
    h = V[k + 1] - V[k]
    t = (v - V[k]) / h
    t2 = t * t
    t3 = t2 * t
    u = (
        (2.0 * t3 - 3.0 * t2 + 1.0) * U[k]
        + (t3 - 2.0 * t2 + t) * h * S[k]
        + (-2.0 * t3 + 3.0 * t2) * U[k + 1]
        + (t3 - t2) * h * S[k + 1]
    )
    du = (
        (6.0 * t2 - 6.0 * t) * (U[k] - U[k + 1]) / h
        + (3.0 * t2 - 4.0 * t + 1.0) * S[k]
        + (3.0 * t2 - 2.0 * t) * S[k + 1]
    )
    return u, du


@numba.njit(**JIT)
def _tabulated_u(v, V, U, S, u_out, d_out):
    """u(v), du/dv: the Hermite cells inside the table, straight lines (exponential law) outside."""
    n = V.shape[0]
    for i in range(v.shape[0]):
        x = v[i]
        if x <= V[0]:
            d_out[i] = S[0]
            u_out[i] = U[0] + S[0] * (x - V[0])
        elif x >= V[n - 1]:
            d_out[i] = S[n - 1]
            u_out[i] = U[n - 1] + S[n - 1] * (x - V[n - 1])
        else:
            k = min(np.searchsorted(V, x, side="right") - 1, n - 2)
            u_out[i], d_out[i] = hermite(x, V, U, S, k)


@numba.njit(**JIT)
def _tabulated_v(u, V, U, S, out):
    """ln p(u): the exact inverse of :func:`_tabulated_u` (U decreasing in V).

    Inside the table: the cell by bisection on U, then Newton on the cubic safeguarded by the
    cell's bracket (the cubic is monotone on each cell).
    """
    n = V.shape[0]
    for i in range(u.shape[0]):
        x = u[i]
        if x >= U[0]:
            out[i] = V[0] + (x - U[0]) / S[0]
        elif x <= U[n - 1]:
            out[i] = V[n - 1] + (x - U[n - 1]) / S[n - 1]
        else:
            lo, hi = 0, n - 1  # U[lo] > x > U[hi]
            while hi - lo > 1:
                mid = (lo + hi) // 2
                if U[mid] > x:
                    lo = mid
                else:
                    hi = mid
            a, b = V[lo], V[lo + 1]
            vk = a + (b - a) * (U[lo] - x) / (U[lo] - U[lo + 1])
            for _ in range(60):
                uk, dk = hermite(vk, V, U, S, lo)
                if uk > x:
                    a = vk
                else:
                    b = vk
                step = (uk - x) / dk if dk < 0.0 else 0.0
                vn = vk - step
                if not (a < vn < b):
                    vn = 0.5 * (a + b)
                if abs(vn - vk) <= 1e-15 * (1.0 + abs(vk)):
                    vk = vn
                    break
                vk = vn
            out[i] = vk


class TabulatedLaw(PressureLaw):
    """A p(u) curve given as points, e.g. measured or computed by another code.

    Interpolation is monotone: u as a piecewise cubic Hermite function of ``ln p`` with
    Fritsch-Butland slopes (no overshoot, C1), and ``pressure`` is its exact inverse. Beyond
    the table, u continues linearly in ln p with the end slope, i.e. exponentially in p
    (``p = p_end exp(-(u - u_end)/u0_end)``) at both ends.

    Parameters
    ----------
    u : array_like
        Separations in m (finite, at least 3 points).
    p : array_like
        Nominal pressures in Pa (> 0, same length). Any order; after sorting by p the
        separations must strictly decrease (a law must be monotone).
    real_area : array_like, optional
        Real contact area fraction at each point (in [0, 1]), interpolated linearly in ln p and
        held constant beyond the ends.

    Attributes
    ----------
    u0 : float
        ``-du/dln p`` at the low-pressure end of the table, in m.

    Notes
    -----
    Interpolation error: third order in the spacing of ln p. For the Persson u(p) of the
    paper's surface 1 sampled at 5 / 10 / 20 / 40 points per decade of p the largest error is
    1.3e-3 / 1.6e-4 / 2.0e-5 / 2.5e-6 u0, and 1e-2 / 1.3e-3 / 1.5e-4 / 1.7e-5 relative below
    p = 0.1 E* (near full contact u falls by decades within one cell, so there the error is
    small in u0 but not relative); tests/test_laws.py holds the 20-point figures.
    """

    name = "tabulated"

    def __init__(self, u: ArrayLike, p: ArrayLike, real_area: ArrayLike | None = None) -> None:
        u = finite_array("u", u, ndim=1)
        p = finite_array("p", p, ndim=1)
        if u.size < 3:
            raise ValueError(f"u must hold at least 3 points, got {u.size}")
        if p.shape != u.shape:
            raise ValueError(f"p must have the same length as u ({u.size}), got {p.size}")
        if np.any(p <= 0.0):
            raise ValueError("p must be > 0 Pa everywhere (allowed range (0, inf))")
        order = np.argsort(p, kind="stable")
        v, u = np.log(p[order]), u[order]
        if np.any(np.diff(v) <= 0.0):
            raise ValueError("p must not contain repeated values")
        if np.any(np.diff(u) >= 0.0):
            bad = int(np.flatnonzero(np.diff(u) >= 0.0)[0])
            raise ValueError(
                "u must strictly decrease as p increases (a pressure law is monotone); it does "
                f"not between p = {math.exp(v[bad]):.6g} Pa and p = {math.exp(v[bad + 1]):.6g} Pa"
            )
        self._V = np.ascontiguousarray(v)
        self._U = np.ascontiguousarray(u)
        self._S = np.ascontiguousarray(_monotone_slopes(v, u))
        self.u0 = float(-self._S[0])
        self._area = None
        if real_area is not None:
            a = finite_array("real_area", real_area, ndim=1)
            if a.shape != u.shape:
                raise ValueError(f"real_area must have the same length as u ({u.size})")
            if np.any((a < 0.0) | (a > 1.0)):
                raise ValueError("real_area must lie in [0, 1] everywhere")
            self._area = a[order]

    def __repr__(self):
        p = np.exp(self._V)
        return f"TabulatedLaw(<{p.size} points, p from {p[0]:.3g} to {p[-1]:.3g} Pa>)"

    def separation_and_slope(self, v: ArrayLike) -> tuple[np.ndarray, np.ndarray]:
        v = np.ascontiguousarray(real_array("v", v))
        u = np.empty_like(v)
        d = np.empty_like(v)
        _tabulated_u(v.ravel(), self._V, self._U, self._S, u.ravel(), d.ravel())
        return u, d

    def log_pressure(self, u: ArrayLike) -> np.ndarray:
        u = np.ascontiguousarray(real_array("u", u))
        out = np.empty_like(u)
        _tabulated_v(u.ravel(), self._V, self._U, self._S, out.ravel())
        return out

    def pressure(self, u: ArrayLike) -> np.ndarray:
        return np.exp(self.log_pressure(u))

    def _compiled_form(self):
        """``(kind, prm, V, U, S, -)`` for the compiled line-contact Newton."""
        return 2, np.zeros(1), self._V, self._U, self._S, np.zeros(1)

    def real_area(self, p: ArrayLike) -> np.ndarray | None:
        if self._area is None:
            return None
        v = np.log(np.maximum(real_array("p", p), 1e-300))
        return np.interp(v, self._V, self._area)
