"""Pressure-separation laws p(u) the line-contact solver can use (``model=`` argument).

Each model answers two questions on the solver's unknown ``v = ln p``:
``u_and_slope(v) -> (u [m], du/dv [m])`` (the u(p) form of the residual) and
``pressure(u) -> p [Pa]`` (the p(u) form, used by the plain damped fixed point).

* :class:`PerssonModel` - the full Persson theory through its tables (default).
* :class:`ExponentialModel` - ``p = beta E* exp(-u/u0)`` (paper eq. 5): exact in v (u is
  linear in ln p), cheaper, and it makes the large-alpha Gaussian limit exact.

Smooth surfaces (hard contact) are not a p(u) law; the solver treats ``model="hertz"``
separately (see :mod:`fastline.solver`).
"""

from __future__ import annotations

import math

import numpy as np

from fastline.persson import PerssonTheory, _pressure_from_table, _separation_and_slope

__all__ = ["PerssonModel", "ExponentialModel"]


class PerssonModel:
    """The full Persson u(p) (tables of a :class:`~fastline.persson.PerssonTheory`)."""

    name = "persson"

    def __init__(self, theory: PerssonTheory):
        self.theory = theory
        self.u0 = theory.exponential_fit().u0

    def u_and_slope(self, v: np.ndarray):
        u = np.empty_like(v)
        d = np.empty_like(v)
        _separation_and_slope(v, *self.theory._t1, u, d)
        return u, d

    def pressure(self, u: np.ndarray) -> np.ndarray:
        return _pressure_from_table(np.maximum(u, 1e-300), self.theory._t2)

    def real_area(self, p: np.ndarray) -> np.ndarray:
        return self.theory.contact_area(p)


class ExponentialModel:
    """``p = beta E* exp(-u/u0)`` (paper eq. 5; Persson, PRL 99, 125502 (2007)).

    Parameters
    ----------
    u0 : float
        Decay length in m.
    beta : float
        Dimensionless prefactor.
    E_star : float
        Effective modulus in Pa.
    theory : PerssonTheory, optional
        Only used to report the real contact area.
    """

    name = "exponential"

    def __init__(self, u0: float, beta: float, E_star: float, theory: PerssonTheory | None = None):
        self.u0 = u0
        self.beta = beta
        self.E_star = E_star
        self.theory = theory
        self._lnpb = math.log(beta * E_star)

    def u_and_slope(self, v: np.ndarray):
        return self.u0 * (self._lnpb - v), np.full_like(v, -self.u0)

    def pressure(self, u: np.ndarray) -> np.ndarray:
        return np.exp(self._lnpb - u / self.u0)

    def real_area(self, p: np.ndarray):
        return None if self.theory is None else self.theory.contact_area(p)
