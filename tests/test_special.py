"""Tests for fastline.theory.special: the universal function F(x0) of the Persson separation.

    F(x0) = int_{x0}^inf (1/x) [gamma + 3 (1 - gamma) erf(x)^2] exp(-x^2) dx  (docs/theory.md §3)

Reference: ``naive.universal_F`` (SciPy exp1 + quad).
"""

from __future__ import annotations

import math

import naive
import numpy as np
import pytest
from scipy.integrate import quad
from scipy.special import erf

from fastline.theory.special import G0, universal_F

RTOL_REF = 1e-10  # F vs the quad reference
RTOL_G0 = 1e-12  # G(0) vs quad
QUAD_EPSREL = 1e-13
EULER_GAMMA = 0.5772156649015329  # independent copy (not imported from the code under test)

GAMMAS = [0.45, 0.4, 1.0, 0.05]


def _x_grid():
    x = np.geomspace(1e-8, 25.0, 54)
    edges = []
    for b in (1.0, 6.0):  # region boundaries of the representation
        edges += [b * (1 - 1e-12), b, b * (1 + 1e-12)]
    return np.unique(np.concatenate([x, edges]))


@pytest.mark.parametrize("gamma", GAMMAS)
def test_F_matches_quad_reference(gamma):
    x = _x_grid()
    assert x.size >= 60
    ref = np.array([naive.universal_F(float(xi), gamma) for xi in x])
    got = universal_F(x, gamma)
    assert got.shape == x.shape
    np.testing.assert_allclose(got, ref, rtol=RTOL_REF, atol=0.0)


def test_F_scalar_and_shape():
    assert np.shape(universal_F(0.3)) == ()
    x = np.geomspace(0.01, 3, 12).reshape(3, 4)
    got = universal_F(x, 0.4)
    assert got.shape == (3, 4)
    np.testing.assert_array_equal(got.ravel(), universal_F(x.ravel(), 0.4))
    # default gamma is 0.45
    assert float(universal_F(0.7)) == float(universal_F(0.7, 0.45))


def _G0_quad():
    f = lambda x: erf(x) ** 2 * math.exp(-x * x) / x  # noqa: E731
    parts = [(0.0, 1.0), (1.0, 3.0), (3.0, 6.0), (6.0, np.inf)]
    return sum(quad(f, a, b, epsabs=0.0, epsrel=QUAD_EPSREL, limit=200)[0] for a, b in parts)


def test_G0_vs_quad():
    assert G0() == pytest.approx(_G0_quad(), rel=RTOL_G0)


@pytest.mark.parametrize("gamma", GAMMAS)
def test_small_x_asymptote(gamma):
    """F(x) + gamma ln x -> gamma (-gamma_E / 2) + 3 (1 - gamma) G(0), with an O(x^2) rest."""
    const = gamma * (-EULER_GAMMA / 2.0) + 3.0 * (1.0 - gamma) * _G0_quad()
    x = np.array([1e-2, 1e-3, 1e-4, 1e-6, 1e-8, 1e-12, 1e-100, 1e-300])
    rest = np.abs(universal_F(x, gamma) + gamma * np.log(x) - const)
    # E1(y)/2 = (-gamma_E - ln y + y - ...)/2 and G(x) = G(0) - (2/pi) x^2 + ...
    bound = (gamma / 2.0 + 6.0 * (1.0 - gamma) / math.pi) * x**2 * 1.01
    tol = 1e-13 * (abs(const) + gamma * np.abs(np.log(x)))
    assert np.all(rest <= bound + tol)
    assert rest[-1] <= tol[-1]
    # the same constant through the code's own G0()
    assert const == pytest.approx(gamma * (-EULER_GAMMA / 2.0) + 3 * (1 - gamma) * G0(), rel=1e-12)


@pytest.mark.parametrize("gamma", GAMMAS)
def test_large_x_asymptote(gamma):
    """F(x) 2 x^2 exp(x^2) / (3 - 2 gamma) -> 1 like y e^y E1(y) = 1 - 1/y + 2/y^2 - ..."""
    x = np.array([6.0, 8.0, 10.0, 15.0, 20.0, 25.0])
    ratio = universal_F(x, gamma) * 2.0 * x**2 * np.exp(x**2) / (3.0 - 2.0 * gamma)
    dev = np.abs(ratio - 1.0)
    assert dev[x == 20.0][0] < 1e-2
    assert np.all(np.diff(dev) < 0.0)
    y = x**2
    assert np.all(np.abs(ratio - (1.0 - 1.0 / y)) <= 2.0 / y**2)


@pytest.mark.parametrize("gamma", GAMMAS)
def test_F_finite_positive_decreasing(gamma):
    x = np.geomspace(1e-300, 1e3, 20001)
    f = universal_F(x, gamma)
    assert np.all(np.isfinite(f))
    assert np.all(f >= 0.0)
    # positive and strictly decreasing until exp(-x^2) underflows (x ~ 27)
    live = x <= 26.0
    assert np.all(f[live] > 0.0)
    dense = np.concatenate(
        [
            np.geomspace(1e-12, 26.0, 20001),
            np.linspace(1.0 - 1e-4, 1.0 + 1e-4, 201),  # region boundaries, step 1e-6
            np.linspace(6.0 - 1e-4, 6.0 + 1e-4, 201),
            np.linspace(1.0 + 0.5 - 1e-4, 1.0 + 0.5 + 1e-4, 201),  # a panel edge of region 2
        ]
    )
    dense = np.unique(dense)
    assert np.all(np.diff(universal_F(dense, gamma)) < 0.0)
    # beyond the underflow F is exactly 0, never negative or NaN
    assert np.all(universal_F(np.array([30.0, 100.0, 1e3, 1e300]), gamma) == 0.0)


@pytest.mark.parametrize("x0", [0.0, -1.0, math.nan, math.inf, [1.0, -2.0], [0.5, math.nan]])
def test_F_rejects_bad_x0(x0):
    with pytest.raises(ValueError, match=r"^x0\b"):
        universal_F(x0, 0.45)


@pytest.mark.parametrize("gamma", [0.0, -0.1, 1.5, 1.0 + 1e-12, math.nan, math.inf])
def test_F_rejects_bad_gamma(gamma):
    with pytest.raises(ValueError, match=r"^gamma\b"):
        universal_F(1.0, gamma)


def test_shipped_coefficients_are_the_computed_ones():
    """The gamma-free Chebyshev tables read from fastline/theory/special_tables.npz equal a fresh
    computation (a stale file after a change of degree or region would fail here)."""
    from fastline.theory.special import _TABLE_NAMES, _gamma_free_tables, compute_gamma_free_tables

    shipped, fresh = _gamma_free_tables(), compute_gamma_free_tables()
    assert len(shipped) == len(fresh) == len(_TABLE_NAMES)
    for name, a, b in zip(_TABLE_NAMES, shipped, fresh, strict=True):
        assert a.shape == b.shape, name
        np.testing.assert_allclose(a, b, rtol=1e-14, atol=1e-16 * np.abs(b).max(), err_msg=name)
