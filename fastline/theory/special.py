"""The universal function F(x0) of the Persson separation integral (docs/theory.md section 3).

    F(x0) = int_{x0}^inf (1/x) [gamma + 3 (1 - gamma) erf(x)^2] exp(-x^2) dx
          = gamma * E1(x0^2) / 2 + 3 (1 - gamma) * G(x0),
    G(x0) = int_{x0}^inf erf(x)^2 exp(-x^2) / x dx.

(The printed-bracket variant of :mod:`fastline.theory.variants` has ``1 - gamma`` for ``3 (1 -
gamma)``; the coefficient is the ``b2`` argument of :func:`f_coefficients`.)

With it the Yang-Persson separation is one quadrature over q per pressure:
``u(p) = sqrt(pi) int dq q^2 C(q) w(q) F(w(q) p / E*)``.

Representation (relative error below 1e-13 on (0, inf), checked against SciPy quadrature in
``tests/test_special.py``), in three regions, each a Chebyshev series of gamma-free parts that
are combined once per gamma:

* ``0 < x0 <= 1``: ``F = phi(x0^2) - gamma ln x0`` where ``phi`` is an entire function of
  ``y = x0^2`` (the log singularity of E1 is split off exactly);
* ``1 < x0 <= 6``: ``F = f(x0) exp(-x0^2) / x0^2``, ``f`` smooth and of order one, on 10 panels;
* ``x0 > 6``: ``erf(x)^2 = 1`` to within 2e-16 relative, so ``F = (3 - 2 gamma) E1(x0^2) / 2``,
  written as ``exp(-x0^2)/x0^2`` times a series in ``t = 36 / x0^2``. It underflows to 0 for
  ``x0 > 26.6`` without producing NaN.

The coefficients are computed once per process (a few milliseconds, NumPy/SciPy) from the
definitions: the E1 part from its power series / Laguerre quadrature, G by composite
Gauss-Legendre quadrature of its smooth integrand.
"""

from __future__ import annotations

import functools
import math
from pathlib import Path
from typing import TYPE_CHECKING

import numba
import numpy as np
from numpy.polynomial import chebyshev as _cheb
from numpy.typing import ArrayLike

from fastline._lib.jit import JIT
from fastline._lib.validate import in_range, positive_array
from fastline.theory.variants import get_variant

if TYPE_CHECKING:
    from fastline.theory.variants import Variant, VariantName

__all__ = ["universal_F", "f_coefficients", "G0", "area_tables", "area_functions", "AreaTables"]

EULER_GAMMA = 0.5772156649015329

# region layout (shared by the coefficient builder and the kernels)
_X1 = 1.0  # end of region 1 (in x0)
_X2 = 6.0  # end of region 2
_N2 = 10  # panels in region 2
_H2 = (_X2 - _X1) / _N2
_DEG1, _DEG2, _DEG3 = 18, 15, 14


def _g_integral(x: np.ndarray) -> np.ndarray:
    """G(x) for x in [0, 9] by composite Gauss-Legendre (panels <= 0.25 wide, 24 nodes)."""
    from scipy.special import erf  # here: a solve needs SciPy only to build these tables

    t_ref, w_ref = np.polynomial.legendre.leggauss(24)
    out = np.empty(x.shape)
    for n, a in enumerate(x.ravel()):
        inner = np.arange(math.ceil(a * 4.0) / 4.0, 9.0 + 1e-12, 0.25)
        edges = np.unique(np.concatenate([[a], inner[inner > a]]))
        lo, hi = edges[:-1, None], edges[1:, None]
        t = 0.5 * (hi - lo) * t_ref + 0.5 * (hi + lo)
        w = 0.5 * (hi - lo) * w_ref
        out.flat[n] = np.sum(w * erf(t) ** 2 * np.exp(-t * t) / t)
    return out


def _phi_a(y: np.ndarray) -> np.ndarray:
    """(E1(y) + ln y) / 2, an entire function of y, by its power series (y <= 1)."""
    s = np.zeros_like(y)
    term = np.ones_like(y)
    for k in range(1, 40):
        term = term * (-y) / k
        s += term / k
    return 0.5 * (-EULER_GAMMA - s)


def _scaled_e1(z: np.ndarray) -> np.ndarray:
    """z exp(z) E1(z) = int_0^inf exp(-s) / (1 + s/z) ds for z >= 36 (Gauss-Laguerre)."""
    t, w = np.polynomial.laguerre.laggauss(80)
    return np.sum(w / (1.0 + t / z[:, None]), axis=1)


#: the gamma-free Chebyshev coefficients, computed once by :func:`compute_gamma_free_tables`
#: and shipped with the package: building them needs ``scipy.special.exp1``, whose import
#: (~0.13 s) and the interpolation (~0.04 s) were a fifth of a fresh process's first answer.
#: ``tests/test_special.py`` recomputes them; regenerate with :func:`write_gamma_free_tables`.
_TABLES_FILE = Path(__file__).with_name("special_tables.npz")
_TABLE_NAMES = ("c1a", "c1b", "c2a", "c2b", "c3")


@functools.lru_cache(maxsize=1)
def _gamma_free_tables():
    """Chebyshev coefficients of the gamma-free parts, (region1 a/b, region2 a/b, region3),
    read from the shipped file (computed afresh if it is missing)."""
    try:
        with np.load(_TABLES_FILE) as data:
            return tuple(np.array(data[name]) for name in _TABLE_NAMES)
    except OSError:
        return compute_gamma_free_tables()


def write_gamma_free_tables(path: Path = _TABLES_FILE) -> None:
    """Recompute the shipped coefficient file (after changing a degree or a region)."""
    np.savez(path, **dict(zip(_TABLE_NAMES, compute_gamma_free_tables(), strict=True)))


def compute_gamma_free_tables() -> tuple:
    """The coefficients of :func:`_gamma_free_tables` by Chebyshev interpolation of the
    gamma-free parts of F (``scipy.special.exp1`` for E1 in region 2)."""
    from scipy.special import exp1

    c1a = _cheb.chebinterpolate(lambda s: _phi_a(0.5 * (s + 1.0)), _DEG1)
    c1b = _cheb.chebinterpolate(lambda s: _g_integral(np.sqrt(0.5 * (s + 1.0))), _DEG1)
    c2a = np.empty((_N2, _DEG2 + 1))
    c2b = np.empty((_N2, _DEG2 + 1))
    for k in range(_N2):
        lo = _X1 + k * _H2
        mid, half = lo + 0.5 * _H2, 0.5 * _H2

        def part_a(s, mid=mid, half=half):
            x = mid + half * s
            return x * x * np.exp(x * x) * exp1(x * x) / 2.0

        def part_b(s, mid=mid, half=half):
            x = mid + half * s
            return x * x * np.exp(x * x) * _g_integral(x)

        c2a[k] = _cheb.chebinterpolate(part_a, _DEG2)
        c2b[k] = _cheb.chebinterpolate(part_b, _DEG2)
    c3 = _cheb.chebinterpolate(lambda s: _scaled_e1(_X2**2 / (0.5 * (s + 1.0))) / 2.0, _DEG3)
    return c1a, c1b, c2a, c2b, c3


def G0() -> float:
    """G(0) = int_0^inf erf(x)^2 exp(-x^2)/x dx, the constant term of F at small x0."""
    c1b = _gamma_free_tables()[1]
    return float(_cheb.chebval(-1.0, c1b))


@functools.lru_cache(maxsize=16)
def f_coefficients(
    gamma: float, b2: float | None = None
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Coefficient arrays ``(c1, c2, c3)`` of F for one value of gamma (read-only).

    ``b2`` is the coefficient of ``erf(x)^2`` in the bracket, ``F = gamma E1(x0^2)/2 + b2 G(x0)``:
    ``3 (1 - gamma)`` (default, the energy derivation) or ``1 - gamma`` (the bracket as printed
    in several papers; :mod:`fastline.theory.variants`).
    """
    c1a, c1b, c2a, c2b, c3 = _gamma_free_tables()
    b = 3.0 * (1.0 - gamma) if b2 is None else b2
    out = (gamma * c1a + b * c1b, gamma * c2a + b * c2b, (gamma + b) * c3)
    for arr in out:
        arr.setflags(write=False)
    return out


@numba.njit(**JIT)
def _clenshaw(c, s):
    """Chebyshev series sum_k c[k] T_k(s) for s in [-1, 1]."""
    b1 = 0.0
    b2 = 0.0
    for k in range(c.shape[0] - 1, 0, -1):
        b1, b2 = 2.0 * s * b1 - b2 + c[k], b1
    return s * b1 - b2 + c[0]


@numba.njit(**JIT)
def _F(x, gamma, c1, c2, c3):
    """F(x) for x > 0 (F(0) = inf is never asked for: callers keep x >= 1e-300)."""
    if x <= _X1:
        return _clenshaw(c1, 2.0 * x * x - 1.0) - gamma * math.log(x)
    x2 = x * x
    if x <= _X2:
        k = min(int((x - _X1) / _H2), _N2 - 1)
        mid = _X1 + (k + 0.5) * _H2
        return _clenshaw(c2[k], (x - mid) / (0.5 * _H2)) * math.exp(-x2) / x2
    if x2 > 745.0:  # exp(-x^2) underflows
        return 0.0
    return _clenshaw(c3, 2.0 * (_X2 * _X2 / x2) - 1.0) * math.exp(-x2) / x2


@numba.njit(**JIT)
def _F_vec(x, gamma, c1, c2, c3, out):
    for i in range(x.shape[0]):
        out[i] = _F(x[i], gamma, c1, c2, c3)


def universal_F(
    x0: ArrayLike, gamma: float = 0.45, variant: VariantName | Variant = "yang-persson-energy"
) -> np.ndarray:
    """Evaluate F(x0) (docs/theory.md section 3) for x0 > 0, vectorised.

    Parameters
    ----------
    x0 : array_like
        Argument, ``x0 = w(q) p / E*`` (dimensionless), > 0.
    gamma : float
        The parameter of the correction S(P), in (0, 1].
    variant : str
        The variant of the theory (:mod:`fastline.theory.variants`); for ``"wang-mueser"`` F is that
        of :mod:`fastline.theory.special` (gamma then in [0.05, 1]).

    Returns
    -------
    ndarray
        F(x0), same shape as ``x0``; ``F ~ -gamma ln x0`` at small x0 and
        ``~ (3 - 2 gamma) exp(-x0^2) / (2 x0^2)`` at large x0 (default variant).
    """
    var = get_variant(variant)
    gamma = in_range("gamma", gamma, 0.0, 1.0)
    x = positive_array("x0", x0)
    flat = np.ascontiguousarray(x.ravel())
    out = np.empty_like(flat)
    if var.area_correction:
        out = area_functions(flat, *var.correction(gamma))[1]
    else:
        b2 = var.bracket(gamma)[1]
        _F_vec(flat, gamma, *f_coefficients(gamma, b2), out)
    return out.reshape(x.shape)


# ----------------------------------------------------------------------------------------------
# The universal functions of the area-corrected variant
# ----------------------------------------------------------------------------------------------
# Universal functions of a Persson theory whose correction S(P) also enters the contact area.
#
# The Wang-Mueser variant (:mod:`fastline.theory.variants`) applies the correction
# ``S(P) = gamma + s2 P^2 + s4 P^4`` (with ``S(1) = 1``) both to the elastic energy and to the
# growth of the variance of the contact pressure with magnification, ``dV = S(P) dV_full``, where
# the plain theory has ``dV = dV_full`` (docs/theory.md, "Variants"). With ``P = erf(y)`` and
# ``y = p / sqrt(2 V)`` that recursion integrates in closed form in y:
#
#     Phi(y) = int_y^inf 2 t^(-3) / S(erf t) dt = 1 / x^2,      x = w(q) p / E*,
#
# so ``y = Y(x)`` is a universal function of the same variable x as in
# :mod:`fastline.theory.special` (``Y(x) = x`` when ``S = 1``) and the contact area is ``P(q, p) =
# erf(Y(x))``. The elastic energy ``U = (pi/2) E* int dq q^2 C P S`` and ``u(p) = int_p^inf dp'/p'
# dU/dp'`` give, exactly as for the plain theory,
#
#     u(p) = sqrt(pi) int dq q^2 C(q) w(q) F(w(q) p / E*),
#     F(x0) = int_{Y(x0)}^inf b(erf y) exp(-y^2) Phi(y)^(1/2) dy,    b(P) = d/dP [P S(P)],
#
# and ``-x F'(x) = b S exp(-Y^2) (Y/x)^3`` (from ``Y' = S Y^3 / x^3``).
#
# Limits: for small x, ``Y = x / sqrt(gamma) (1 + O(x^2 ln x))`` and
# ``F = -sqrt(gamma) ln x + c0 + O(x^2 ln x)`` (the exponential law has ``u0 = sqrt(gamma) int dq
# q^2 C w``, not ``gamma int ...``); for ``x > 6``, ``erf(Y)^2 = 1`` to 2e-16, so ``Y = x`` and
# ``F = b(1) E1(x^2) / 2``.
#
# Representation (relative error ~1e-13 against an ODE reference, ``tests/test_variants.py``):
#
# * ``x < 1``: 27 panels ``[2^-(k+1), 2^-k)``, Chebyshev series of ``F + sqrt(gamma) ln x`` and
#   ``Y / x`` on each; below ``2^-27`` their limits (the ``x^2 ln x`` terms are < 1e-15 there);
# * ``1 <= x <= 6``: the 10 panels of :mod:`fastline.theory.special`, series of ``F x^2 exp(x^2)``
# and   ``Y / x``;
# * ``x > 6``: ``b(1)`` times the E1 series of :mod:`fastline.theory.special`, ``Y = x``.
#
# Construction (once per (gamma, s2, s4), about 30 ms with NumPy): Phi and the y-form of F on
# panels of width 0.25 in ``ln y`` from y = 1e-9 to 1 and 0.1 in y from 1 to 7, each a Chebyshev
# series integrated spectrally from the top (where ``Phi = 1/y^2`` and ``F = b(1) E1(y^2)/2``),
# then ``Y(x)`` at the Chebyshev nodes in x by Newton's method on Phi.

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


def area_functions(
    x: np.ndarray, gamma: float, s2: float, s4: float
) -> tuple[np.ndarray, np.ndarray]:
    """``(Y(x), F(x))`` for a contiguous float64 array of x > 0 (no checks)."""
    Y, F = np.empty_like(x), np.empty_like(x)
    _area_vec(x, area_tables(gamma, s2, s4), Y, F)
    return Y, F
