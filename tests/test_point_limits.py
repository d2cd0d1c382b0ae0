"""Tests for the point-contact limits of fastline.theory.limits: Hertz sphere and Gaussian."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.integrate import quad
from scipy.optimize import brentq

from fastline.theory.limits import (
    WS_GAUSSIAN,
    WS_HERTZ_SPHERE,
    gaussian_point_contact,
    hertz_point_contact,
    p0_ratio_gaussian_sphere,
)

RTOL_EXACT = 1e-12  # closed-form identities
RTOL_QUAD = 1e-9  # adaptive quadrature of the profiles and root finding

E_STAR = 5.86e10  # Pa (steel on aluminium)
RADIUS = 0.02  # m
LOADS = [1e-3, 1.0, 500.0]  # N


def _radial_moments(pressure, edge):
    """(int p dA, int r^2 p dA / 2) over the disc r < edge by quadrature (dA = 2 pi r dr)."""
    kw = {"epsabs": 0.0, "epsrel": 1e-12, "limit": 200}
    force = quad(lambda r: 2 * math.pi * r * pressure(r), 0.0, edge, **kw)[0]
    second = quad(lambda r: math.pi * r**3 * pressure(r), 0.0, edge, **kw)[0]
    return force, second


@pytest.mark.parametrize("load", LOADS)
def test_hertz_sphere_closed_forms(load):
    h = hertz_point_contact(E_STAR, RADIUS, load)
    assert h.a**3 == pytest.approx(3 * load * RADIUS / (4 * E_STAR), rel=RTOL_EXACT)
    assert h.p0 == pytest.approx(3 * load / (2 * math.pi * h.a**2), rel=RTOL_EXACT)
    assert h.delta == pytest.approx(h.a**2 / RADIUS, rel=RTOL_EXACT)
    # Johnson: p0 = (6 F E*^2 / (pi^3 R^2))^(1/3), delta = (9 F^2 / (16 R E*^2))^(1/3)
    assert h.p0 == pytest.approx((6 * load * E_STAR**2 / (math.pi**3 * RADIUS**2)) ** (1 / 3))
    assert h.delta == pytest.approx((9 * load**2 / (16 * RADIUS * E_STAR**2)) ** (1 / 3))
    force, second = _radial_moments(h.pressure, h.a)
    assert force == pytest.approx(load, rel=RTOL_QUAD)
    assert math.sqrt(second / force) == pytest.approx(h.s, rel=RTOL_QUAD)  # a / sqrt(5)
    half = brentq(lambda r: h.pressure(r) - 0.5 * h.p0, 0.0, h.a, xtol=1e-16, rtol=1e-14)
    assert 2 * half == pytest.approx(h.fwhm, rel=RTOL_QUAD)  # sqrt(3) a
    assert h.fwhm / h.s == pytest.approx(WS_HERTZ_SPHERE, rel=RTOL_EXACT)
    assert WS_HERTZ_SPHERE == pytest.approx(math.sqrt(15.0), rel=RTOL_EXACT)


def test_hertz_sphere_profiles():
    h = hertz_point_contact(E_STAR, RADIUS, 500.0)
    r = np.array([-0.5, 0.0, 0.5, 0.999, 1.0, 2.0]) * h.a
    p = h.pressure(r)
    assert p[1] == h.p0 and p[0] == p[2] and p[4] == p[5] == 0.0 and p[3] > 0.0
    # the displacement inside is the rigid sphere's gap closed: delta - r^2 / (2R) ... (eq. 3.41)
    u = h.displacement(r[:4])
    assert np.allclose(u, h.delta - r[:4] ** 2 / (2 * RADIUS), rtol=RTOL_EXACT)
    assert np.isnan(h.displacement(2 * h.a))
    assert isinstance(h.pressure(0.0), float)


@pytest.mark.parametrize("load", LOADS)
def test_gaussian_sphere_closed_forms(load):
    u0 = 2e-6
    g = gaussian_point_contact(u0, RADIUS, load)
    assert g.s**2 == pytest.approx(RADIUS * u0, rel=RTOL_EXACT)
    force, second = _radial_moments(g.pressure, 40 * g.s)
    assert force == pytest.approx(load, rel=RTOL_QUAD)
    assert math.sqrt(second / force) == pytest.approx(g.s, rel=RTOL_QUAD)
    half = brentq(lambda r: g.pressure(r) - 0.5 * g.p0, 0.0, 5 * g.s, xtol=1e-16, rtol=1e-14)
    assert 2 * half / g.s == pytest.approx(WS_GAUSSIAN, rel=RTOL_QUAD)
    # the exponential law with a rigid sphere: p / p0 = exp(-r^2 / (2 R u0))
    r = np.linspace(0.0, 3 * g.s, 7)
    assert np.allclose(g.pressure(r), g.p0 * np.exp(-(r**2) / (2 * RADIUS * u0)), rtol=1e-15)


def test_p0_ratio_asymptote_is_gaussian_over_hertz():
    """1/(3 gamma_u alpha) with u0 = gamma_u h_rms and alpha = h_rms / delta, delta = a^2/R."""
    h_rms, gamma_u = 5e-6, 0.55
    for load in LOADS:
        h = hertz_point_contact(E_STAR, RADIUS, load)
        g = gaussian_point_contact(gamma_u * h_rms, RADIUS, load)
        alpha = h_rms / h.delta
        assert g.p0 / h.p0 == pytest.approx(p0_ratio_gaussian_sphere(alpha, gamma_u), rel=1e-12)
    a = np.array([1.0, 10.0, 100.0])
    assert np.allclose(p0_ratio_gaussian_sphere(a, 0.5), 2.0 / (3.0 * a), rtol=RTOL_EXACT)


@pytest.mark.parametrize(
    "call, match",
    [
        (lambda: hertz_point_contact(-1.0, RADIUS, 1.0), "E_star"),
        (lambda: hertz_point_contact(E_STAR, 0.0, 1.0), "radius"),
        (lambda: hertz_point_contact(E_STAR, RADIUS, float("nan")), "load"),
        (lambda: hertz_point_contact(E_STAR, RADIUS, 1.0).pressure([np.inf]), "r must"),
        (lambda: gaussian_point_contact(0.0, RADIUS, 1.0), "u0"),
        (lambda: gaussian_point_contact(1e-6, RADIUS, -2.0), "load must be > 0 N"),
        (lambda: p0_ratio_gaussian_sphere([1.0, -1.0], 0.5), "alpha"),
        (lambda: p0_ratio_gaussian_sphere(1.0, 0.0), "gamma_u"),
        # each input > 0 but the result under- or overflows (was a ZeroDivisionError)
        (lambda: hertz_point_contact(E_STAR, RADIUS, 5e-324), "load=5e-324 is not representable"),
        (
            lambda: hertz_point_contact(E_STAR, 5e-324, 1.0),
            "radius=5e-324, .* is not representable",
        ),
        (lambda: gaussian_point_contact(5e-324, RADIUS, 1.0), "u0=5e-324, .* is not representable"),
        (
            lambda: gaussian_point_contact(1e-6, RADIUS, 1e308),
            r"not representable in float64 \(p0 = ",
        ),
    ],
)
def test_bad_input(call, match):
    with pytest.raises(ValueError, match=match):
        call()
