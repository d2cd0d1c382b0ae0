"""The Greenwood-Williamson law from the spectrum (fastline.theory.asperity).

References: ``naive.gw_pressure`` / ``naive.gw_area`` (the summit-height integrals by SciPy quad
in the height z), SciPy quad of the spectral moments, exact moments of the self-affine spectrum
(``SelfAffinePSD._moment``), summits counted on a synthesised surface, Hertz-sphere and load
balance invariants of the solvers.
"""

from __future__ import annotations

import math

import naive
import numpy as np
import pytest
from scipy.integrate import quad

import fastline as fl
from fastline.bem import random_surface, spectral_grid
from fastline.theory.asperity import (
    TAIL_T,
    GreenwoodWilliamsonLaw,
    SummitStatistics,
    summit_integral,
)

RTOL_REF = 1e-6  # p(u) and A/A0 against the quad reference
RTOL_INTEGRAL = 1e-10  # F_{3/2}(t) against quad
RTOL_MOMENT = 1e-10  # spectral moments against quad / closed forms
RTOL_INVERSE = 1e-12  # separation_and_slope and log_pressure are inverses
RTOL_SUMMITS = 0.03  # counted summits on a 16-points-per-wavelength map (~2000 summits):
# measured over seeds 7-9: density 0.982-1.004, curvature 0.995-1.007, spread 0.997-1.009
RTOL_SUMMIT_MEAN = 0.05  # mean summit height (measured 0.989-1.029)
E_STAR = 1e7
RADIUS = 32.8e-3
PSD_PAPERLIKE = fl.SelfAffinePSD(0.5e-6, 0.8, 1e4, 1e4, 3.2e5)


@pytest.fixture(scope="module")
def law():
    return GreenwoodWilliamsonLaw.from_psd(PSD_PAPERLIKE, E_STAR)


def _t_grid():
    t = np.linspace(-30.0, 30.0, 121)
    edges = [-8.0, 12.0, TAIL_T]  # table ends and the tail joint
    extra = [e + d for e in edges for d in (-1e-9, 0.0, 1e-9)]
    return np.unique(np.concatenate([t, extra, [-1e3, -100.0]]))


def test_summit_integral_vs_quad():
    t = _t_grid()
    t = t[t < 25.0]  # F underflows near t = 38
    ref = np.array([naive.gw_integral(float(ti), 1.5, 0.0, 1.0) for ti in t])
    got = summit_integral(t)
    np.testing.assert_allclose(got, ref[:, 0] * np.exp(-ref[:, 1]), rtol=RTOL_INTEGRAL, atol=0)


def test_summit_integral_limits():
    # t -> -inf: E[(Z - t)^1.5] -> |t|^1.5 (1 + 3/(8 t^2)); t = 0: 2^0.75 Gamma(5/4) / (2 sqrt(pi))
    t = -1e3
    assert float(summit_integral(t)) == pytest.approx(1e3**1.5 * (1 + 0.375e-6), rel=1e-12)
    half = 2.0**0.75 * math.gamma(1.25) / (2.0 * math.sqrt(math.pi))
    assert float(summit_integral(0.0)) == pytest.approx(half, rel=1e-13)
    assert np.shape(summit_integral(np.zeros((2, 3)))) == (2, 3)


# ------------------------------------------------------------------------------------------------
# summit statistics
# ------------------------------------------------------------------------------------------------
def test_moments_of_the_spectrum():
    psd = PSD_PAPERLIKE
    st = SummitStatistics.from_psd(psd)
    lq0, lq1 = math.log(psd.q0), math.log(psd.q1)

    def mom(k):  # int q^k C dq = int q^(k+1) C d ln q
        return quad(lambda s: math.exp((k + 1) * s) * psd(math.exp(s)), lq0, lq1, epsrel=1e-13)[0]

    m0, m2 = 2 * math.pi * mom(1), math.pi * mom(3)
    m4 = 0.75 * math.pi * float(psd._moment(5, np.float64(psd.q1)))  # closed form
    assert st.m0 == pytest.approx(m0, rel=RTOL_MOMENT)
    assert st.m2 == pytest.approx(m2, rel=RTOL_MOMENT)
    assert st.m4 == pytest.approx(m4, rel=RTOL_MOMENT)
    # h'^2 = 2 m2 (a profile sees half the mean-square gradient)
    assert 2.0 * st.m2 == pytest.approx(psd.rms_slope**2, rel=1e-12)
    assert st.alpha == pytest.approx(m0 * m4 / m2**2, rel=1e-9)
    assert st.height_mean == pytest.approx(4.0 * math.sqrt(m0 / (math.pi * st.alpha)), rel=1e-9)


def test_moments_of_a_tabulated_and_summed_spectrum():
    a, b = PSD_PAPERLIKE, fl.SelfAffinePSD(0.1e-6, 0.6, 3e4, 5e4, 1e6)
    q = np.geomspace(1e4, 1e6, 400)
    tab = fl.TabulatedPSD(q, (a + b)(q))
    s_sum = SummitStatistics.from_psd(a + b)
    s_tab = SummitStatistics.from_psd(tab)
    m4 = 0.75 * math.pi * (float(a._moment(5, np.float64(a.q1))) + float(b._moment(5, 1e6)))
    assert s_sum.m4 == pytest.approx(m4, rel=RTOL_MOMENT)
    assert s_tab.m4 == pytest.approx(m4, rel=2e-3)  # log-log interpolation of the table


def test_summits_of_a_synthesised_surface():
    """Counted summits (8-neighbour maxima): density, mean curvature, height mean and spread
    against eta, 1/beta, y_s and sigma_s (heights scaled by the map's own rms, which the
    discrete modes of one periodic map put a few % off h_rms)."""
    psd = fl.SelfAffinePSD(0.5e-6, 0.8, 1e4, 1e4, 1.6e5)
    st = SummitStatistics.from_psd(psd)
    grid = spectral_grid(psd, points_per_wavelength=16, periods=6)
    h = random_surface(psd, grid, seed=7).heights
    is_max = np.ones(h.shape, bool)
    for dx in (-1, 0, 1):
        for dy in (-1, 0, 1):
            if dx or dy:
                is_max &= h > np.roll(np.roll(h, dx, 0), dy, 1)
    density = is_max.sum() / (grid.lx * grid.ly)
    kx = 2 * np.pi * np.fft.fftfreq(grid.nx, grid.dx)
    ky = 2 * np.pi * np.fft.fftfreq(grid.ny, grid.dy)
    lap = np.real(np.fft.ifft2(-(kx[:, None] ** 2 + ky[None, :] ** 2) * np.fft.fft2(h)))
    curvature = float(np.mean(-0.5 * lap[is_max]))
    scale = h.std() / math.sqrt(st.m0)
    assert is_max.sum() > 2000
    assert density == pytest.approx(st.density, rel=RTOL_SUMMITS)
    assert curvature * st.radius == pytest.approx(1.0, rel=RTOL_SUMMITS)
    assert h[is_max].std() / scale == pytest.approx(st.height_std, rel=RTOL_SUMMITS)
    assert h[is_max].mean() / scale == pytest.approx(st.height_mean, rel=RTOL_SUMMIT_MEAN)


# ------------------------------------------------------------------------------------------------
# the law against the summit-height integrals
# ------------------------------------------------------------------------------------------------
def test_pressure_and_area_vs_quad(law):
    s = law.statistics
    t = np.linspace(-20.0, TAIL_T, 40)
    u = s.height_mean + s.height_std * t
    ref = [
        naive.gw_pressure(ui, s.density, s.radius, s.height_std, s.height_mean, E_STAR) for ui in u
    ]
    np.testing.assert_allclose(np.exp(law.log_pressure(u) - ref), 1.0, rtol=RTOL_REF, atol=0)
    # real area through the pressure: A/A0 at p(u)
    p = law.pressure(u[t > -3.0])
    area = [naive.gw_area(ui, s.density, s.radius, s.height_std, s.height_mean) for ui in u[t > -3]]
    np.testing.assert_allclose(law.real_area(p), np.minimum(area, 1.0), rtol=RTOL_REF, atol=0)


def test_inverse_slope_and_tail(law):
    v = np.sort(np.concatenate([np.linspace(-700.0, 30.0, 500), [math.log(1e-300)]]))
    u, dudv = law.separation_and_slope(v)
    np.testing.assert_allclose(law.log_pressure(u), v, rtol=RTOL_INVERSE, atol=1e-11)
    assert np.all(np.diff(u) < 0.0) and np.all(dudv < 0.0)
    h = 1e-6  # slope against central differences
    up, _ = law.separation_and_slope(v + h)
    um, _ = law.separation_and_slope(v - h)
    np.testing.assert_allclose((up - um) / (2 * h), dudv, rtol=1e-6, atol=0)
    # below the tail joint: exponential with decay length u0 = -du/dln p there (C1 joint)
    s = law.statistics
    tail = u > s.height_mean + TAIL_T * s.height_std
    assert tail.any() and (~tail).any()
    np.testing.assert_allclose(dudv[tail], -law.u0, rtol=1e-12)
    assert law.u0 == pytest.approx(s.height_std / (TAIL_T + 2.5 / TAIL_T), rel=2e-2)


# ------------------------------------------------------------------------------------------------
# solvers with the law
# ------------------------------------------------------------------------------------------------
@pytest.mark.parametrize("load", [0.5, 50.0])
def test_line_contact(law, load):
    r = fl.LineContact(PSD_PAPERLIKE, E_STAR, RADIUS, model=law, n=256, warn=False).solve(load)
    assert r.converged and r.model == "greenwood-williamson"
    assert r.force_error < 1e-10 and r.edge_pressure < 1e-6
    # the law holds on the solution
    np.testing.assert_allclose(law.pressure(r.separation), r.pressure, rtol=1e-9)


def test_point_contact_is_greenwood_tripp(law):
    """The rough sphere: at light load much wider and lower than Hertz, at heavy load Hertz."""
    pc = fl.PointContact(PSD_PAPERLIKE, E_STAR, RADIUS, model=law, n=256, warn=False)
    light, heavy = pc.solve(1e-4), pc.solve(10.0)
    assert light.converged and heavy.converged
    assert light.p0_ratio < 0.5 and light.alpha > 1.0
    assert heavy.p0_ratio == pytest.approx(1.0, abs=0.02) and heavy.alpha < 0.01


def test_bandwidth_moves_gw_not_persson():
    """q1 4x larger at the same h_rms: GW's u at fixed p moves by sigma_s-sized amounts, the
    Persson u0 ln(beta E*/p) by much less (docs/validation.md, "Bandwidth")."""
    p = 1e4
    u = {}
    for q1 in (8e4, 3.2e5):
        psd = fl.SelfAffinePSD(0.5e-6, 0.8, 1e4, 1e4, q1)
        gw = GreenwoodWilliamsonLaw.from_psd(psd, E_STAR)
        th = fl.PerssonTheory(psd, E_STAR)
        u[q1] = (float(gw.separation_and_slope(math.log(p))[0]), float(th.separation(p)))
    h = PSD_PAPERLIKE.h_rms
    assert u[3.2e5][0] - u[8e4][0] > 0.5 * h  # stiffer asperities hold the surfaces apart
    assert abs(u[3.2e5][1] - u[8e4][1]) < 0.2 * h


# ------------------------------------------------------------------------------------------------
# bad input
# ------------------------------------------------------------------------------------------------
def test_rejects():
    with pytest.raises(TypeError, match="psd"):
        GreenwoodWilliamsonLaw.from_psd("spectrum", E_STAR)
    with pytest.raises(ValueError, match="E_star"):
        GreenwoodWilliamsonLaw.from_psd(PSD_PAPERLIKE, -1.0)
    with pytest.raises(TypeError, match="statistics"):
        GreenwoodWilliamsonLaw({"eta": 1.0}, E_STAR)
    with pytest.raises(ValueError, match="m0 m4 / m2"):
        SummitStatistics.from_moments(1.0, 1.0, 0.5)
    with pytest.raises(ValueError, match="m2"):
        SummitStatistics.from_moments(1.0, -1.0, 1.0)
    with pytest.raises(ValueError, match="t must be finite"):
        summit_integral([0.0, math.nan])
