"""Tests of fastline.diagnostics.assess (regimes, warnings, exponential-law range)."""

import math
import warnings

import pytest

import fastline as fl
from fastline.diagnostics import ValidityWarning, assess, regime
from fastline.line_contact import solve_line_contact

E_STAR = 1.33e9  # Pa
H_RMS = 1e-6  # m


@pytest.fixture(scope="module")
def psd():
    return fl.SelfAffinePSD(H_RMS, 0.8, 1e3, 1e4, 1e9)


@pytest.fixture(scope="module")
def theory(psd):
    return fl.PerssonTheory(psd, E_STAR)


def load_for(alpha, h_rms=H_RMS):
    """f_N [N/m] giving alpha = h_rms / delta with delta = 4 f_N / (pi E*)."""
    return math.pi / 4.0 * h_rms * E_STAR / alpha


def solve(psd, theory, alpha, radius=1.0, **kw):
    return solve_line_contact(psd, E_STAR, radius, load_for(alpha), theory=theory, n=256, **kw)


def test_regime_thresholds():
    assert regime(0.009) == "Hertz-like"
    assert regime(0.01) == regime(10.0) == "transition"
    assert regime(10.1) == "Gaussian-like"


@pytest.mark.parametrize(
    "alpha, expected", [(1e-3, "Hertz-like"), (1.0, "transition"), (100.0, "Gaussian-like")]
)
def test_regimes_from_solves(psd, theory, alpha, expected):
    # a big radius keeps the contact narrow compared with R: no warning expected
    r = solve(psd, theory, alpha, radius=10.0)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        d = assess(r, theory)
    assert d["regime"] == expected
    assert d["alpha"] == pytest.approx(alpha, rel=1e-12)
    assert d["half_space_ok"] and d["warnings"] == []
    assert d["plastic_likely"] is None
    assert d["asperity_pressure"] == pytest.approx(0.5 * psd.rms_slope * E_STAR, rel=1e-12)
    assert 0.0 < d["real_area_at_peak"] < 1.0
    assert d["real_area_at_peak"] == pytest.approx(float(theory.contact_area([r.p0])[0]))
    assert "exponential_valid" not in d  # only for the exponential model


def test_real_area_grows_with_load(psd, theory):
    a = [
        assess(solve(psd, theory, al, radius=10.0), theory)["real_area_at_peak"]
        for al in (10.0, 1.0, 0.1)
    ]
    assert a[0] < a[1] < a[2]


def test_hardness_warning(psd, theory):
    r = solve(psd, theory, 1.0)
    p_asp = 0.5 * psd.rms_slope * E_STAR
    with pytest.warns(ValidityWarning, match="hardness"):
        d = assess(r, theory, hardness=0.5 * p_asp)
    assert d["plastic_likely"] is True
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        d = assess(r, theory, hardness=2.0 * p_asp)
    assert d["plastic_likely"] is False
    with pytest.raises(ValueError):
        assess(r, theory, hardness=-1.0)


def test_half_width_warning_for_big_load(psd, theory):
    # Hertz half-width a = sqrt(R delta); R = 1 cm and f_N = 1e7 N/m give a ~ 0.98 R
    r = solve_line_contact(psd, E_STAR, 0.01, 1e7, theory=theory, n=256)
    with pytest.warns(ValidityWarning, match="half-space"):
        d = assess(r, theory)
    assert not d["half_space_ok"]
    assert d["half_width_over_radius"] > 0.1
    assert issubclass(ValidityWarning, UserWarning)


def test_exponential_range_flag(psd, theory):
    ok = assess(solve(psd, theory, 10.0, model="exponential"), theory)
    assert ok["exponential_valid"] is True
    assert ok["exponential_max_error"] <= 0.05
    lo, hi = ok["pressure_range_met"]
    assert lo < hi <= ok["exponential_valid_range"][1]
    # near full contact (alpha = 1e-3, peak pressure ~ E*/2) the law is far off
    r = solve(psd, theory, 1e-3, radius=10.0, model="exponential")
    bad = assess(r, theory)
    assert bad["exponential_valid"] is False
    assert bad["pressure_range_met"][1] > bad["exponential_valid_range"][1]


def test_without_theory_and_from_psd(psd, theory):
    r = solve(psd, theory, 1.0)
    d = assess(r)
    assert d["rms_slope"] is None and d["regime"] == "transition"
    d2 = assess(r, psd=psd)
    assert d2["real_area_at_peak"] == pytest.approx(
        assess(r, theory)["real_area_at_peak"], rel=1e-9
    )
    h = solve_line_contact(None, E_STAR, 10.0, load_for(1.0), model="hertz", n=256)
    assert assess(h)["regime"] == "Hertz-like"  # alpha = 0 for smooth surfaces
