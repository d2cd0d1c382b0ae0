"""The universal function F(x0) of the Persson separation integral (docs/theory.md section 3).

    F(x0) = int_{x0}^inf (1/x) [gamma + 3 (1 - gamma) erf(x)^2] exp(-x^2) dx
          = gamma * E1(x0^2) / 2 + 3 (1 - gamma) * G(x0),
    G(x0) = int_{x0}^inf erf(x)^2 exp(-x^2) / x dx.

(The printed-bracket variant of :mod:`fastline.variants` has ``1 - gamma`` for ``3 (1 - gamma)``;
the coefficient is the ``b2`` argument of :func:`f_coefficients`.)

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

from fastline._jit import JIT

if TYPE_CHECKING:
    from fastline.variants import Variant, VariantName

__all__ = ["universal_F", "f_coefficients", "G0"]

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
_TABLES_FILE = Path(__file__).with_name("_special_tables.npz")
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
def f_coefficients(gamma: float, b2: float | None = None):
    """Coefficient arrays ``(c1, c2, c3)`` of F for one value of gamma (read-only).

    ``b2`` is the coefficient of ``erf(x)^2`` in the bracket, ``F = gamma E1(x0^2)/2 + b2 G(x0)``:
    ``3 (1 - gamma)`` (default, the energy derivation) or ``1 - gamma`` (the bracket as printed
    in several papers; :mod:`fastline.variants`).
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
        The variant of the theory (:mod:`fastline.variants`); for ``"wang-mueser"`` F is that
        of :mod:`fastline._special_area` (gamma then in [0.05, 1]).

    Returns
    -------
    ndarray
        F(x0), same shape as ``x0``; ``F ~ -gamma ln x0`` at small x0 and
        ``~ (3 - 2 gamma) exp(-x0^2) / (2 x0^2)`` at large x0 (default variant).
    """
    from fastline._validate import in_range, positive_array
    from fastline.variants import get_variant

    var = get_variant(variant)
    gamma = in_range("gamma", gamma, 0.0, 1.0)
    x = positive_array("x0", x0)
    flat = np.ascontiguousarray(x.ravel())
    out = np.empty_like(flat)
    if var.area_correction:
        from fastline._special_area import area_functions

        out = area_functions(flat, *var.correction(gamma))[1]
    else:
        b2 = var.bracket(gamma)[1]
        _F_vec(flat, gamma, *f_coefficients(gamma, b2), out)
    return out.reshape(x.shape)
