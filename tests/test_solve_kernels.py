"""The compiled stages around the Newton kernel against the NumPy expressions they replaced."""

from __future__ import annotations

import math

import naive
import numpy as np
import pytest

from fastline.contact.kernels import (
    LN_FLOOR,
    cold_start_into,
    cold_start_normalised,
    hertz_line_gap,
    largest,
    largest_abs,
    line_cells,
    line_measures,
    normalise_into,
    normalise_pressure_into,
    pressure_into,
)
from fastline.contact.model import std as _std

RTOL_ROUNDOFF = 1e-12  # loops against NumPy: summation order and FMA only

X = np.linspace(-3e-4, 3e-4, 257)


def test_cold_start_is_the_logaddexp_blend():
    """Hertz part vanishing outside |x| < a (floor 0, the line) and floored (the sphere); the
    tail outside |x| < a added in (the line) or not (ln_t = -inf, the sphere)."""
    a, ln_h, ln_g, s = 2e-4, math.log(3e7), math.log(1e7), 8e-5
    ln_t, k_t = math.log(2e6), 40.0
    xi = np.abs(X) / a
    with np.errstate(invalid="ignore"):
        gap = xi * np.sqrt(xi * xi - 1.0) - np.arccosh(xi)
    tail = np.where(xi >= 1.0, ln_t - k_t * gap, -np.inf)
    for floor, with_tail in ((0.0, True), (0.0, False), (1e-100, False)):
        out = np.empty_like(X)
        lt, kt = (ln_t, k_t) if with_tail else (-math.inf, 0.0)
        cold_start_into(X, a, ln_h, floor, ln_g, 2.0 * s * s, lt, kt, out)
        with np.errstate(divide="ignore"):
            lh = ln_h + 0.5 * np.log(np.maximum(1 - (X / a) ** 2, floor))
        ref = np.logaddexp(lh, ln_g - X * X / (2.0 * s * s))
        if with_tail:
            ref = np.logaddexp(ref, tail)
        np.testing.assert_allclose(out, ref, rtol=RTOL_ROUNDOFF, atol=0.0)


RTOL_HERTZ_GAP = 1e-3  # the hard-contact solve at n = 256 (7e-5 at n = 1024)


def test_hertz_line_gap_is_the_hard_contact_solution_gap():
    """The closed form of the gap outside a Hertz line contact against fastline's own
    hard-contact (model="hertz") solve, which knows nothing of it; and its edge asymptote."""
    import fastline as fl
    from fastline.theory.limits import hertz_line_contact

    E, R, f = 1e9, 0.01, 1e3
    res = fl.LineContact(None, E, R, model="hertz", n=256).solve(f)
    a = hertz_line_contact(E, R, f).a
    out = np.abs(res.x) > 1.05 * a
    ref = np.array([a * a / (2.0 * R) * hertz_line_gap(t) for t in np.abs(res.x[out]) / a])
    np.testing.assert_allclose(res.separation[out], ref, rtol=RTOL_HERTZ_GAP)
    assert hertz_line_gap(1.0) == 0.0
    e = 1e-6
    assert hertz_line_gap(1.0 + e) == pytest.approx(4.0 * math.sqrt(2.0) / 3.0 * e**1.5, rel=1e-5)


def test_logaddexp_like_numpy_and_exact_where_a_term_is_dropped():
    from fastline.contact.kernels import _LOGADDEXP_CUT, _logaddexp

    rng = np.random.default_rng(3)
    for a, b in zip(rng.uniform(-60, 60, 400), rng.uniform(-60, 60, 400), strict=True):
        b = a + (b - a) * 1.5  # differences on both sides of the cut
        ref = np.logaddexp(a, b)
        got = _logaddexp(a, b)
        if abs(a - b) > _LOGADDEXP_CUT:
            assert got == max(a, b)
        assert got == pytest.approx(ref, rel=RTOL_ROUNDOFF, abs=1e-17)
    inf = math.inf
    for a, b in [(-inf, -inf), (-inf, 3.0), (3.0, -inf), (inf, 2.0), (inf, inf), (1.0, 1.0)]:
        assert _logaddexp(a, b) == np.logaddexp(a, b)
    assert math.isnan(_logaddexp(math.nan, 1.0)) and math.isnan(_logaddexp(1.0, math.nan))


def test_normalise_restores_the_load_and_flushes_like_numpy():
    v = -0.5 * (X / 5e-5) ** 2 * 300.0  # 1e-300 of the peak at the edges: below LN_FLOOR
    w = np.full(X.size, X[1] - X[0])
    out = v.copy()
    normalise_into(out, 2.5e3, w)
    share = np.exp(np.maximum(v - v.max(), -LN_FLOOR))
    ref = v + (math.log(2.5e3) - (v.max() + math.log(np.sum(w * share))))
    np.testing.assert_allclose(out, ref, rtol=RTOL_ROUNDOFF)
    assert np.sum(w * np.exp(out)) == pytest.approx(2.5e3, rel=RTOL_ROUNDOFF)


def test_cold_start_normalised_is_the_two_stages_bit_for_bit():
    a, ln_h, ln_g, s, load = 2e-4, math.log(3e7), math.log(1e7), 8e-5, 4e3
    w = np.full(X.size, X[1] - X[0])
    two = np.empty_like(X)
    cold_start_into(X, a, ln_h, 0.0, ln_g, 2.0 * s * s, math.log(1e6), 40.0, two)
    normalise_into(two, load, w)
    one = np.empty_like(X)
    profiles = (a, ln_h, 0.0, ln_g, 2.0 * s * s, math.log(1e6), 40.0)
    cold_start_normalised(X, profiles, load, w, one)
    np.testing.assert_array_equal(one, two)
    assert np.sum(w * np.exp(one)) == pytest.approx(load, rel=RTOL_ROUNDOFF)


RTOL_EXP_PRODUCT = 1e-13  # exp(a) exp(b) against exp(a + b), |a + b| < 30: a few ulp


def test_normalise_pressure_is_the_two_stages():
    """The shift of :func:`normalise_into` bit for bit, the pressure of :func:`pressure_into`
    to a few ulp with the same flushed cells; a NaN gives NaN v and zero p as they do."""
    v = -0.5 * (X / 5e-5) ** 2 * 300.0 + 3.0  # below LN_FLOOR of the peak at the edges
    v[:3] = v.max() - LN_FLOOR + np.array([0.01, -0.01, 0.5])  # cells at the flush floor
    w = np.full(X.size, X[1] - X[0])
    two, p_two = v.copy(), np.empty_like(v)
    normalise_into(two, 2.5e3, w)
    pressure_into(two, p_two)
    one, p_one = v.copy(), np.full_like(v, np.nan)
    normalise_pressure_into(one, 2.5e3, w, p_one)
    np.testing.assert_array_equal(one, two)
    assert np.any(p_two == 0.0) and np.any(p_two > 0.0)
    np.testing.assert_array_equal(p_one == 0.0, p_two == 0.0)
    assert p_two[1] == 0.0 and p_two[0] > 0.0 and p_two[2] > 0.0
    np.testing.assert_allclose(p_one, p_two, rtol=RTOL_EXP_PRODUCT, atol=0.0)
    v[7] = np.nan
    normalise_pressure_into(v, 2.5e3, w, p_one)
    assert np.all(np.isnan(v)) and np.all(p_one == 0.0)


@pytest.mark.parametrize("n", [0, 1, 3, 4, 5, 9])
def test_largest_is_the_serial_maximum_bit_for_bit(n):
    """Four chains of max give the serial loop's value, NaN skipped, ``start`` included."""
    x = np.random.default_rng(n).standard_normal(n) * 10.0
    if n > 2:
        x[2] = np.nan
    finite = x[~np.isnan(x)]
    for start in (-np.inf, 0.0, 100.0):
        assert largest(x, start) == max([start, *finite])
        assert largest_abs(x, start) == max([start, *np.abs(finite)])


def test_pressure_flushes_below_the_floor_and_on_nan():
    v = np.array([10.0, 10.0 - LN_FLOOR + 1.0, 10.0 - LN_FLOOR - 1.0, -np.inf, -700.0])
    p = np.empty_like(v)
    pressure_into(v, p)
    np.testing.assert_array_equal(p, [math.exp(10.0), math.exp(v[1]), 0.0, 0.0, 0.0])
    pressure_into(np.array([1.0, np.nan]), p[:2])
    np.testing.assert_array_equal(p[:2], 0.0)  # as the NumPy form (v > NaN is False)


def test_cells_and_measures_equal_the_numpy_forms():
    n, dx, radius = 64, 1e-5, 0.01
    x, gap, w = np.empty(n), np.empty(n), np.empty(n)
    line_cells(dx, 2.0 * radius, x, gap, w)
    ref = (np.arange(n) - 0.5 * (n - 1)) * dx
    np.testing.assert_array_equal(x, ref)
    np.testing.assert_allclose(gap, ref * ref / (2.0 * radius), rtol=RTOL_ROUNDOFF)  # 1/(2R) x^2
    np.testing.assert_array_equal(w, dx)
    p = np.maximum(1.0 - (x / 2.2e-4) ** 2, 0.0) ** 0.5 * 1e6 + np.exp(-((x / 1e-4) ** 2)) * 3e5
    p0, s, width, total = line_measures(x, p, dx)
    assert p0 == pytest.approx(naive.peak_parabola(p), rel=RTOL_ROUNDOFF)
    assert p0 > p.max()  # the parabola through the top three cells
    assert s == pytest.approx(_std(x, p, dx), rel=RTOL_ROUNDOFF)
    assert width == pytest.approx(naive.fwhm_crossings(x, p, p0), rel=RTOL_ROUNDOFF)
    assert total == pytest.approx(p.sum(), rel=RTOL_ROUNDOFF)
    assert math.isnan(line_measures(x, np.ones(n), dx)[2])  # no half-maximum crossing


def test_peak_and_fwhm_wrappers_against_the_references():
    """The public measures (fastline.contact.model.peak / fwhm, used by the point contact and the
    error estimates) on a skewed profile, a peak at the grid's end and a plateau."""
    from fastline.contact.model import fwhm, peak

    x = np.linspace(-1.0, 2.0, 301)
    skewed = np.exp(-((x - 0.3) ** 2) / 0.08) * (1.0 + 0.4 * x)
    for p in (skewed, np.exp(-x), np.where(np.abs(x) < 0.5, 1.0, 0.0)):
        p0 = peak(p)
        assert p0 == pytest.approx(naive.peak_parabola(p), rel=RTOL_ROUNDOFF)
        ref = naive.fwhm_crossings(x, p, p0)
        got = fwhm(x, p, p0)
        assert (math.isnan(got) and math.isnan(ref)) or got == pytest.approx(ref, rel=1e-12)
    assert math.isnan(fwhm(x, np.exp(-x), 1.0))  # half maximum reached at the grid's end
