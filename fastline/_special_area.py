"""Universal functions of a Persson theory whose correction S(P) also enters the contact area.

The Wang-Mueser variant (:mod:`fastline.variants`) applies the correction
``S(P) = gamma + s2 P^2 + s4 P^4`` (with ``S(1) = 1``) both to the elastic energy and to the
growth of the variance of the contact pressure with magnification, ``dV = S(P) dV_full``, where
the plain theory has ``dV = dV_full`` (docs/theory.md, "Variants"). With ``P = erf(y)`` and
``y = p / sqrt(2 V)`` that recursion integrates in closed form in y:

    Phi(y) = int_y^inf 2 t^(-3) / S(erf t) dt = 1 / x^2,      x = w(q) p / E*,

so ``y = Y(x)`` is a universal function of the same variable x as in :mod:`fastline._special`
(``Y(x) = x`` when ``S = 1``) and the contact area is ``P(q, p) = erf(Y(x))``. The elastic
energy ``U = (pi/2) E* int dq q^2 C P S`` and ``u(p) = int_p^inf dp'/p' dU/dp'`` give, exactly as
for the plain theory,

    u(p) = sqrt(pi) int dq q^2 C(q) w(q) F(w(q) p / E*),
    F(x0) = int_{Y(x0)}^inf b(erf y) exp(-y^2) Phi(y)^(1/2) dy,    b(P) = d/dP [P S(P)],

and ``-x F'(x) = b S exp(-Y^2) (Y/x)^3`` (from ``Y' = S Y^3 / x^3``).

Limits: for small x, ``Y = x / sqrt(gamma) (1 + O(x^2 ln x))`` and
``F = -sqrt(gamma) ln x + c0 + O(x^2 ln x)`` (the exponential law has ``u0 = sqrt(gamma) int dq
q^2 C w``, not ``gamma int ...``); for ``x > 6``, ``erf(Y)^2 = 1`` to 2e-16, so ``Y = x`` and
``F = b(1) E1(x^2) / 2``.

Representation (relative error ~1e-13 against an ODE reference, ``tests/test_variants.py``):

* ``x < 1``: 27 panels ``[2^-(k+1), 2^-k)``, Chebyshev series of ``F + sqrt(gamma) ln x`` and
  ``Y / x`` on each; below ``2^-27`` their limits (the ``x^2 ln x`` terms are < 1e-15 there);
* ``1 <= x <= 6``: the 10 panels of :mod:`fastline._special`, series of ``F x^2 exp(x^2)`` and
  ``Y / x``;
* ``x > 6``: ``b(1)`` times the E1 series of :mod:`fastline._special`, ``Y = x``.

Construction (once per (gamma, s2, s4), about 30 ms with NumPy): Phi and the y-form of F on
panels of width 0.25 in ``ln y`` from y = 1e-9 to 1 and 0.1 in y from 1 to 7, each a Chebyshev
series integrated spectrally from the top (where ``Phi = 1/y^2`` and ``F = b(1) E1(y^2)/2``),
then ``Y(x)`` at the Chebyshev nodes in x by Newton's method on Phi.
"""

from __future__ import annotations

import functools
import math

import numba
import numpy as np
from numpy.polynomial import chebyshev as _cheb

from fastline._jit import JIT
from fastline._special import _H2, _N2, _X1, _X2, _clenshaw, _gamma_free_tables

__all__ = ["area_tables", "area_functions", "AreaTables"]

_Y_TOP = 7.0  # top of the y panels: erf(7)^2 = 1 in double precision
_Y_BOTTOM = 1e-9  # below every y needed (x >= 2^-27, Y >= x)
_S_WIDTH = 0.25  # panel width in ln y below y = 1
_Y_WIDTH = 0.1  # panel width in y above y = 1
_DEG_Y = 24  # Chebyshev degree of the y panels
_K1 = 27  # panels of region 1 (x in [2^-27, 1))
_X_MIN = 2.0**-_K1
_DEG_X = 18  # Chebyshev degree of the x panels (both regions)
_TWO_OVER_SQRT_PI = 2.0 / math.sqrt(math.pi)

#: ``(lam, c0, r0, fa, ya, c3)``: F's log coefficient ``sqrt(gamma)`` and constant, the limit
#: ``Y/x -> 1/sqrt(gamma)``, the x-panel series of F and Y/x (27 + 10 rows), b(1) times E1's
#: series for x > 6.
AreaTables = tuple


def _s_poly(P, gamma, s2, s4):
    P2 = P * P
    return gamma + s2 * P2 + s4 * P2 * P2


def _b_poly(P, gamma, s2, s4):
    P2 = P * P
    return gamma + 3.0 * s2 * P2 + 5.0 * s4 * P2 * P2


def _interpolate(values: np.ndarray) -> np.ndarray:
    """Chebyshev coefficients from values at the first-kind points (rows: panels)."""
    n = values.shape[-1]
    V = _cheb.chebvander(_cheb.chebpts1(n), n - 1)
    c = values @ V * (2.0 / n)
    c[..., 0] *= 0.5
    return c


class _YPanels:
    """Phi(y) and the y-form of F as piecewise Chebyshev series in s = ln y (module docstring)."""

    def __init__(self, gamma: float, s2: float, s4: float):
        from scipy.special import erf, exp1  # here: only the area-corrected variant needs it

        # uniform in ln y up to y = 1, uniform in y above (where exp(-y^2) sets the scale)
        n = math.ceil(-math.log(_Y_BOTTOM) / _S_WIDTH)
        top = np.log(np.linspace(1.0, _Y_TOP, math.ceil((_Y_TOP - 1.0) / _Y_WIDTH) + 1))
        self.edges = np.concatenate([np.linspace(math.log(_Y_BOTTOM), 0.0, n + 1), top[1:]])
        self.half = 0.5 * np.diff(self.edges)
        mid = 0.5 * (self.edges[:-1] + self.edges[1:])
        tau = _cheb.chebpts1(_DEG_Y + 1)
        y = np.exp(mid[:, None] + self.half[:, None] * tau[None, :])
        P = erf(y)
        # -dPhi/ds = 2 y^-2 / S: integrate each panel from its top, then add the panels above
        self.f = _interpolate(2.0 / (y * y * _s_poly(P, gamma, s2, s4)))
        self.phi = self._downward(self.f, 1.0 / _Y_TOP**2)
        # -dF/ds = b exp(-y^2) y Phi^(1/2), with Phi from its series at the same nodes
        phi_nodes = _cheb.chebval(tau, self.phi.T)
        g = _b_poly(P, gamma, s2, s4) * np.exp(-y * y) * y * np.sqrt(phi_nodes)
        b1 = _b_poly(1.0, gamma, s2, s4)
        self.F = self._downward(_interpolate(g), b1 * exp1(_Y_TOP**2) / 2.0)
        self.phi_bottom = _cheb.chebval(-1.0, self.phi.T)  # increasing downwards

    def _downward(self, c, top_value):
        """Series of ``top_value + int_s^{s_top} f ds'`` on every panel (f's series ``c``)."""
        pairs = zip(c, self.half, strict=True)
        A = np.array([_cheb.chebint(row, lbnd=1.0, scl=h) for row, h in pairs])  # 0 at the top
        drop = -_cheb.chebval(-1.0, A.T)  # integral over each panel
        above = np.concatenate([np.cumsum(drop[::-1])[::-1][1:], [0.0]])
        out = -A
        out[:, 0] += top_value + above
        return out

    def invert(self, x: np.ndarray):
        """(Y(x), F(x)) for 1e-9 < Y < 7, by Newton's method in the panel holding Phi = 1/x^2."""
        target = 1.0 / (x * x)
        # panel k has Phi(bottom) >= target > Phi(top) (Phi decreases upwards)
        k = np.searchsorted(-self.phi_bottom, -target) - 1
        k = np.clip(k, 0, self.edges.size - 2)
        phi_c, f_c = self.phi[k].T, self.f[k].T
        tau = np.zeros_like(x)
        for _ in range(40):
            val = _cheb.chebval(tau, phi_c, tensor=False)
            slope = -self.half[k] * _cheb.chebval(tau, f_c, tensor=False)
            step = (val - target) / slope
            tau = np.clip(tau - step, -1.0, 1.0)
            if np.all(np.abs(step) < 1e-15):
                break
        s = 0.5 * (self.edges[k] + self.edges[k + 1]) + self.half[k] * tau
        return np.exp(s), _cheb.chebval(tau, self.F[k].T, tensor=False)


@functools.lru_cache(maxsize=8)
def area_tables(gamma: float, s2: float, s4: float) -> AreaTables:
    """The x-panel series of F and Y for ``S = gamma + s2 P^2 + s4 P^4`` (read-only arrays)."""
    yp = _YPanels(gamma, s2, s4)
    lam = math.sqrt(gamma)
    fa = np.empty((_K1 + _N2, _DEG_X + 1))
    ya = np.empty_like(fa)
    tau = _cheb.chebpts1(_DEG_X + 1)
    for k in range(_K1):  # [2^-(k+1), 2^-k): x = 2^-(k+2) (t + 3)
        x = 2.0 ** -(k + 2) * (tau + 3.0)
        Y, F = yp.invert(x)
        fa[k] = _interpolate(F + lam * np.log(x))
        ya[k] = _interpolate(Y / x)
    for k in range(_N2):
        x = _X1 + (k + 0.5) * _H2 + 0.5 * _H2 * tau
        Y, F = yp.invert(x)
        fa[_K1 + k] = _interpolate(F * x * x * np.exp(x * x))
        ya[_K1 + k] = _interpolate(Y / x)
    c0 = float(_cheb.chebval(-1.0, fa[_K1 - 1]))
    r0 = float(_cheb.chebval(-1.0, ya[_K1 - 1]))
    c3 = _b_poly(1.0, gamma, s2, s4) * _gamma_free_tables()[4]
    for arr in (fa, ya, c3):
        arr.setflags(write=False)
    return (lam, c0, r0, fa, ya, c3)


# ----------------------------------------------------------------------------------------------
# compiled evaluation
# ----------------------------------------------------------------------------------------------
@numba.njit(**JIT)
def _panel(x):
    """(row, local coordinate) of x in [2^-27, 6] for the x-panel series."""
    if x < _X1:
        m, e = math.frexp(x)  # x = m 2^e, m in [0.5, 1): panel -e
        return -e, 4.0 * m - 3.0
    k = min(int((x - _X1) / _H2), _N2 - 1)
    return _K1 + k, (x - (_X1 + (k + 0.5) * _H2)) / (0.5 * _H2)


@numba.njit(**JIT)
def _F_area(x, at):
    """F(x) for x > 0 (module docstring)."""
    lam, c0, _, fa, _, c3 = at
    if x < _X_MIN:
        return c0 - lam * math.log(x)
    if x <= _X2:
        k, t = _panel(x)
        if x < _X1:
            return _clenshaw(fa[k], t) - lam * math.log(x)
        x2 = x * x
        return _clenshaw(fa[k], t) * math.exp(-x2) / x2
    x2 = x * x
    if x2 > 745.0:
        return 0.0
    return _clenshaw(c3, 2.0 * (_X2 * _X2 / x2) - 1.0) * math.exp(-x2) / x2


@numba.njit(**JIT)
def _Y_area(x, at):
    """Y(x) for x > 0: ``P(q, p) = erf(Y(w p / E*))``."""
    r0, ya = at[2], at[4]
    if x < _X_MIN:
        return r0 * x
    if x <= _X2:
        k, t = _panel(x)
        return _clenshaw(ya[k], t) * x
    return x


@numba.njit(**JIT)
def _beta_area(x, at, gamma, s2, s4):
    """``beta = -x F'(x)`` and ``x d ln(beta)/dx`` (module docstring)."""
    Y = _Y_area(x, at)
    P = math.erf(Y)
    P2 = P * P
    S = gamma + s2 * P2 + s4 * P2 * P2
    b = gamma + 3.0 * s2 * P2 + 5.0 * s4 * P2 * P2
    dS = 2.0 * s2 * P + 4.0 * s4 * P2 * P
    db = 6.0 * s2 * P + 20.0 * s4 * P2 * P
    r = Y / x
    e = math.exp(-Y * Y)
    beta = b * S * e * r * r * r
    sr2 = S * r * r  # x Y'/Y
    dlog = (db / b + dS / S) * _TWO_OVER_SQRT_PI * e * Y * sr2 - 2.0 * Y * Y * sr2 + 3.0 * sr2 - 3.0
    return beta, dlog


@numba.njit(**JIT)
def _area_vec(x, at, Y, F):
    for i in range(x.shape[0]):
        Y[i] = _Y_area(x[i], at)
        F[i] = _F_area(x[i], at)


def area_functions(x: np.ndarray, gamma: float, s2: float, s4: float):
    """``(Y(x), F(x))`` for a contiguous float64 array of x > 0 (no checks)."""
    Y, F = np.empty_like(x), np.empty_like(x)
    _area_vec(x, area_tables(gamma, s2, s4), Y, F)
    return Y, F
