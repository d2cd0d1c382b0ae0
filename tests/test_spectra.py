"""Tests for fastline.theory.spectra: the roughness power spectra C(q) and effective_modulus.

Every moment is checked against SciPy quadrature of its definition (docs/theory.md section 2):
``h_rms^2 = 2 pi int q C dq``, ``h'^2 = 2 pi int q^3 C dq``, ``A(q) = pi int_0^q q^3 C dq``.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.integrate import quad

from fastline.errors import ImplausibleSpectrumError
from fastline.theory.spectra import PSD, SelfAffinePSD, SumPSD, TabulatedPSD, effective_modulus

RTOL_QUAD = 1e-10  # closed-form / exact moments vs adaptive quadrature of the definition
RTOL_EXACT = 1e-12  # identities that hold to rounding (same power law, sums, formulas)
QUAD_EPSREL = 1e-13  # requested accuracy of the reference quadratures

Q0, QR, Q1 = 1e3, 1e4, 1e9  # the paper's surfaces (1/m)


# ------------------------------------------------------------------------------------------------
# reference quadrature
# ------------------------------------------------------------------------------------------------
def _quad_moment(C, k, a, b, cuts=()):
    """int_a^b q^k C(q) dq by quad in ln q, split at every decade and at the given cuts."""
    if b <= a:
        return 0.0
    edges = {a, b}
    edges.update(c for c in cuts if a < c < b)
    lo, hi = math.floor(math.log10(a)), math.ceil(math.log10(b))
    edges.update(10.0**d for d in range(lo, hi + 1) if a < 10.0**d < b)
    edges = sorted(edges)
    total = 0.0
    for x, y in zip(edges[:-1], edges[1:], strict=True):
        total += quad(
            lambda s: math.exp((k + 1) * s) * float(C(math.exp(s))),
            math.log(x),
            math.log(y),
            epsabs=0.0,
            epsrel=QUAD_EPSREL,
            limit=200,
        )[0]
    return total


def _ref_moments(psd, cuts, q_eval):
    """(h_rms, rms slope, A(q_eval)) from quadrature of psd(q) over [q0, q1]."""
    m1 = _quad_moment(psd, 1, psd.q0, psd.q1, cuts)
    m3 = _quad_moment(psd, 3, psd.q0, psd.q1, cuts)
    A = [math.pi * _quad_moment(psd, 3, psd.q0, min(q, psd.q1), cuts) for q in q_eval]
    return math.sqrt(2.0 * math.pi * m1), math.sqrt(2.0 * math.pi * m3), np.array(A)


def _q_probe(psd):
    """Wavenumbers at which A(q) is checked: below, inside each region, at kinks, beyond."""
    return np.array(
        [
            0.5 * psd.q0,
            psd.q0,
            1.7 * psd.q0,
            0.5 * (psd.q0 + psd.qr) if psd.qr > psd.q0 else 1.2 * psd.q0,
            psd.qr,
            3.1 * psd.qr,
            math.sqrt(psd.qr * psd.q1),
            0.9 * psd.q1,
            psd.q1,
            2.0 * psd.q1,
        ]
    )


# ------------------------------------------------------------------------------------------------
# SelfAffinePSD
# ------------------------------------------------------------------------------------------------
@pytest.mark.parametrize("hurst", [0.3, 0.8, 1.0, 1.0 - 1e-9])
@pytest.mark.parametrize("qr", [QR, Q0], ids=["rolloff", "no_rolloff"])
def test_self_affine_moments_vs_quad(hurst, qr):
    h = 7e-6
    psd = SelfAffinePSD(h, hurst, Q0, qr, Q1)
    q = _q_probe(psd)
    h_ref, slope_ref, A_ref = _ref_moments(psd, (Q0, qr, Q1), q)
    # C0 is derived from h_rms: the quadrature of C must give back the input h_rms
    assert h_ref == pytest.approx(h, rel=RTOL_QUAD)
    # the generic moment path of the base class (int q C dq in closed form) agrees too
    assert PSD.h_rms.fget(psd) == pytest.approx(h, rel=RTOL_QUAD)
    assert psd.h_rms == h
    assert psd.rms_slope == pytest.approx(slope_ref, rel=RTOL_QUAD)
    A = psd.cumulative(q)
    assert A.shape == q.shape
    assert A[0] == 0.0 and A[1] == 0.0  # nothing below q0
    np.testing.assert_allclose(A, A_ref, rtol=RTOL_QUAD, atol=0.0)
    # A(q1) = h'^2 / 2 (module docstring)
    assert float(psd.cumulative(Q1)) == pytest.approx(0.5 * slope_ref**2, rel=RTOL_QUAD)


@pytest.mark.parametrize("qr", [QR, Q0], ids=["rolloff", "no_rolloff"])
def test_self_affine_values(qr):
    h, H = 3e-6, 0.8
    psd = SelfAffinePSD(h, H, Q0, qr, Q1)
    C0 = psd.C0
    q = np.array([0.5 * Q0, Q0, 0.5 * (Q0 + qr), qr, 10 * qr, Q1, 1.01 * Q1])
    expect = np.where(
        (q >= Q0) & (q <= Q1), C0 * (np.maximum(q, qr) / qr) ** (-2.0 * (1.0 + H)), 0.0
    )
    np.testing.assert_allclose(psd(q), expect, rtol=RTOL_EXACT, atol=0.0)
    # C0 in closed form (independent algebra):
    # h^2 = 2 pi C0 [(qr^2 - q0^2)/2 + qr^2 (1 - (q1/qr)^-2H) / (2H)]
    c0 = h**2 / (
        2 * math.pi * (0.5 * (qr**2 - Q0**2) + qr**2 * (1 - (Q1 / qr) ** (-2 * H)) / (2 * H))
    )
    assert C0 == pytest.approx(c0, rel=RTOL_EXACT)
    np.testing.assert_array_equal(psd.breakpoints(), np.unique([Q0, qr, Q1]))


@pytest.mark.parametrize("qr", [QR, Q0], ids=["rolloff", "no_rolloff"])
def test_hurst_one_is_continuous(qr):
    """H = 1 (logarithm branch) vs H = 1 - 1e-9 (power branch): the moments move by O(1e-9)."""
    q = _q_probe(SelfAffinePSD(1e-6, 1.0, Q0, qr, Q1))

    def moments(H):
        psd = SelfAffinePSD(1e-6, H, Q0, qr, Q1)
        return np.concatenate([[psd.rms_slope, psd.C0], psd.cumulative(q[2:])])

    m1 = moments(1.0)
    dH = 1e-9
    slope = np.abs(m1 - moments(1.0 - 1e-3)) / 1e-3  # |dm/dH| scale
    diff = np.abs(m1 - moments(1.0 - dH))
    assert np.all(diff <= 10.0 * dH * slope + RTOL_EXACT * np.abs(m1))
    np.testing.assert_allclose(moments(1.0 - dH), m1, rtol=1e-7)


# ------------------------------------------------------------------------------------------------
# TabulatedPSD
# ------------------------------------------------------------------------------------------------
def test_tabulated_power_law_is_exact():
    c, s = 2.5e-20, -3.4  # h_rms ~ 1e-11 m
    nodes = np.array([1e2, 4e2, 1e4, 3e6])
    psd = TabulatedPSD(nodes, c * nodes**s)
    rng = np.random.default_rng(7)
    q = np.exp(rng.uniform(math.log(nodes[0]), math.log(nodes[-1]), 200))
    np.testing.assert_allclose(psd(q), c * q**s, rtol=RTOL_EXACT, atol=0.0)
    # moments of the power law in closed form: int_a^b q^k c q^s dq
    for k in (1, 3):
        e = k + 1 + s
        exact = c * (q**e - nodes[0] ** e) / e
        np.testing.assert_allclose(psd._moment(k, q), exact, rtol=RTOL_EXACT, atol=0.0)
    e = 4 + s
    A1 = math.pi * c * (nodes[-1] ** e - nodes[0] ** e) / e
    assert psd.rms_slope == pytest.approx(math.sqrt(2.0 * A1), rel=RTOL_EXACT)


@pytest.mark.parametrize("hurst", [0.3, 0.8, 1.0])
@pytest.mark.parametrize("qr", [QR, Q0], ids=["rolloff", "no_rolloff"])
def test_tabulated_copy_of_self_affine(hurst, qr):
    ref = SelfAffinePSD(5e-6, hurst, Q0, qr, Q1)
    nodes = np.unique(np.concatenate([np.geomspace(Q0, Q1, 37), [qr]]))
    tab = TabulatedPSD(nodes, ref(nodes))
    assert tab.q0 == Q0 and tab.q1 == Q1
    q = _q_probe(ref)
    np.testing.assert_allclose(tab.cumulative(q), ref.cumulative(q), rtol=RTOL_EXACT, atol=0.0)
    assert tab.h_rms == pytest.approx(ref.h_rms, rel=RTOL_EXACT)
    assert tab.rms_slope == pytest.approx(ref.rms_slope, rel=RTOL_EXACT)
    qq = np.geomspace(0.5 * Q0, 2 * Q1, 501)
    np.testing.assert_allclose(tab(qq), ref(qq), rtol=RTOL_EXACT, atol=0.0)


def test_tabulated_zero_outside_table():
    nodes = np.array([10.0, 100.0, 1000.0])
    tab = TabulatedPSD(nodes, np.array([1e-20, 3e-22, 1e-25]))
    outside = np.array([0.0, 1e-3, 9.999, 1000.001, 1e9, 1e300])
    with np.errstate(all="raise"):  # q = 0 (an FFT grid's mean) is not 0 ** -slope
        np.testing.assert_array_equal(tab(outside), 0.0)
    assert np.all(tab(np.array([10.0, 50.0, 1000.0])) > 0.0)
    np.testing.assert_array_equal(tab.cumulative(np.array([1e-3, 5.0, 10.0])), 0.0)
    total = float(tab.cumulative(1000.0))
    np.testing.assert_array_equal(tab.cumulative(np.array([1000.0, 2e3, 1e12])), total)


def _generic_table():
    rng = np.random.default_rng(42)
    q = np.geomspace(1e2, 1e8, 25) * np.exp(rng.uniform(-0.2, 0.2, 25))
    C = 1e-18 * (q / 1e2) ** -3.0 * np.exp(rng.uniform(-1.5, 1.5, 25))
    C[[0, 10, 11, 24]] = 0.0  # zero end points: leading, a gap inside, trailing
    return q, C


def test_tabulated_generic_moments_vs_quad():
    q, C = _generic_table()
    tab = TabulatedPSD(q, C)
    # support: the first and last intervals whose both end points are > 0
    assert tab.q0 == q[1] and tab.q1 == q[23]
    # an interval with a zero end point is zero
    np.testing.assert_array_equal(tab(np.geomspace(q[9] * 1.0001, q[12] * 0.9999, 50)), 0.0)
    probe = np.concatenate([[0.5 * q[0], q[5], math.sqrt(q[10] * q[11])], q[15:25:3], [2 * q[-1]]])
    h_ref, slope_ref, A_ref = _ref_moments(tab, tuple(q), probe)
    assert tab.h_rms == pytest.approx(h_ref, rel=RTOL_QUAD)
    assert tab.rms_slope == pytest.approx(slope_ref, rel=RTOL_QUAD)
    np.testing.assert_allclose(tab.cumulative(probe), A_ref, rtol=RTOL_QUAD, atol=0.0)
    # interpolation is log-log: midpoint (in ln q) value is the geometric mean of the ends
    mid = math.sqrt(q[3] * q[4])
    assert float(tab(mid)) == pytest.approx(math.sqrt(C[3] * C[4]), rel=RTOL_EXACT)


# ------------------------------------------------------------------------------------------------
# SumPSD
# ------------------------------------------------------------------------------------------------
def _sum_parts():
    a = SelfAffinePSD(10e-6, 0.8, 1e3, 1e4, 1e9)
    b = SelfAffinePSD(2e-6, 1.0, 3e3, 3e3, 1e10)
    q, C = _generic_table()
    return a, b, TabulatedPSD(q, C)


def test_sum_adds():
    a, b, c = _sum_parts()
    s = a + b + c
    assert isinstance(s, SumPSD)
    assert len(s.parts) == 3  # nested sums are flattened
    assert s.q0 == min(a.q0, b.q0, c.q0) and s.q1 == max(a.q1, b.q1, c.q1)
    q = np.geomspace(10.0, 1e11, 777)
    np.testing.assert_allclose(s(q), a(q) + b(q) + c(q), rtol=RTOL_EXACT, atol=0.0)
    A = a.cumulative(q) + b.cumulative(q) + c.cumulative(q)
    np.testing.assert_allclose(s.cumulative(q), A, rtol=RTOL_EXACT, atol=0.0)
    h2 = a.h_rms**2 + b.h_rms**2 + c.h_rms**2
    assert s.h_rms**2 == pytest.approx(h2, rel=RTOL_EXACT)
    slope2 = a.rms_slope**2 + b.rms_slope**2 + c.rms_slope**2
    assert s.rms_slope**2 == pytest.approx(slope2, rel=RTOL_EXACT)
    union = np.unique(np.concatenate([a.breakpoints(), b.breakpoints(), c.breakpoints()]))
    np.testing.assert_array_equal(s.breakpoints(), union)


def test_sum_moments_vs_quad():
    a, b, _ = _sum_parts()
    s = a + b
    probe = np.array([2e3, 5e3, 1e6, 1e9, 5e9, 1e10])
    h_ref, slope_ref, A_ref = _ref_moments(s, (1e3, 3e3, 1e4, 1e9, 1e10), probe)
    assert s.h_rms == pytest.approx(h_ref, rel=RTOL_QUAD)
    assert s.rms_slope == pytest.approx(slope_ref, rel=RTOL_QUAD)
    np.testing.assert_allclose(s.cumulative(probe), A_ref, rtol=RTOL_QUAD, atol=0.0)


def test_sum_rejects_non_psd():
    with pytest.raises(ValueError, match="parts"):
        SumPSD(SelfAffinePSD(1e-6, 0.8, 1e3, 1e4, 1e9), 3.0)
    with pytest.raises(ValueError, match="parts"):
        SumPSD()


# ------------------------------------------------------------------------------------------------
# effective_modulus
# ------------------------------------------------------------------------------------------------
def test_effective_modulus_steel_rubber():
    E_steel, nu_steel = 210e9, 0.3
    E_rubber, nu_rubber = 10e6, 0.5
    expect = 1.0 / ((1 - 0.3**2) / 210e9 + (1 - 0.5**2) / 10e6)
    got = effective_modulus(E_steel, nu_steel, E_rubber, nu_rubber)
    assert got == pytest.approx(expect, rel=RTOL_EXACT)
    # rubber dominates: close to E/(1 - nu^2) of the rubber alone
    assert got == pytest.approx(10e6 / 0.75, rel=1e-3)
    assert effective_modulus(E_rubber, nu_rubber, E_steel, nu_steel) == pytest.approx(
        got, rel=RTOL_EXACT
    )
    # two identical bodies: E / (2 (1 - nu^2))
    assert effective_modulus(70e9, 0.33, 70e9, 0.33) == pytest.approx(
        70e9 / (2 * (1 - 0.33**2)), rel=RTOL_EXACT
    )


# ------------------------------------------------------------------------------------------------
# validation
# ------------------------------------------------------------------------------------------------
GOOD = dict(h_rms=1e-6, hurst=0.8, q0=1e3, qr=1e4, q1=1e9)


def _raises(name):
    return pytest.raises(ValueError, match=rf"^{name}\b")


@pytest.mark.parametrize(
    "name, value",
    [
        ("h_rms", 0.0),
        ("h_rms", -1e-6),
        ("hurst", 0.0),
        ("hurst", 1.5),
        ("hurst", -1.0),
        ("q0", 0.0),
        ("q0", -1e3),
        ("qr", 0.5e3),
        ("q1", 1e4),
        ("q1", 1e3),
    ],
)
def test_self_affine_rejects_out_of_range(name, value):
    with _raises(name):
        SelfAffinePSD(**{**GOOD, name: value})


@pytest.mark.parametrize("value", [math.nan, math.inf, -math.inf])
@pytest.mark.parametrize("name", list(GOOD))
def test_self_affine_rejects_non_finite(name, value):
    with _raises(name):
        SelfAffinePSD(**{**GOOD, name: value})


@pytest.mark.parametrize(
    "q, C, name",
    [
        ([1.0, 2.0, 2.0], [1.0, 1.0, 1.0], "q"),  # not strictly increasing
        ([1.0, 3.0, 2.0], [1.0, 1.0, 1.0], "q"),  # decreasing
        ([0.0, 1.0, 2.0], [1.0, 1.0, 1.0], "q"),  # q <= 0
        ([-1.0, 1.0, 2.0], [1.0, 1.0, 1.0], "q"),
        ([1.0, 2.0, 3.0], [1.0, -1e-30, 1.0], "C"),  # negative C
        ([1.0], [1.0], "q"),  # fewer than 2 points
        ([1.0, 2.0, 3.0], [1.0, 1.0], "C"),  # mismatched lengths
        ([1.0, 2.0], [1.0, 1.0, 1.0], "C"),
        ([1.0, math.nan, 3.0], [1.0, 1.0, 1.0], "q"),
        ([1.0, 2.0, math.inf], [1.0, 1.0, 1.0], "q"),
        ([1.0, 2.0, 3.0], [1.0, math.nan, 1.0], "C"),
        ([1.0, 2.0, 3.0], [math.inf, 1.0, 1.0], "C"),
        ([1.0, 2.0, 3.0], [0.0, 0.0, 0.0], "C"),  # no interval with C > 0
    ],
)
def test_tabulated_rejects_bad_input(q, C, name):
    with _raises(name):
        TabulatedPSD(q, C)


GOOD_MOD = dict(E1=210e9, nu1=0.3, E2=10e6, nu2=0.5)


@pytest.mark.parametrize(
    "name, value",
    [
        ("E1", 0.0),
        ("E1", -1.0),
        ("E2", 0.0),
        ("E2", -5e6),
        ("nu1", 0.51),
        ("nu1", -1.0),
        ("nu1", -1.5),
        ("nu2", 0.6),
        ("nu2", -1.0),
    ]
    + [(n, v) for n in GOOD_MOD for v in (math.nan, math.inf)],
)
def test_effective_modulus_rejects(name, value):
    with _raises(name):
        effective_modulus(**{**GOOD_MOD, name: value})


def test_an_implausible_table_names_its_h_rms_by_type():
    """C(q) in um^4 read as m^4: refused as an ImplausibleSpectrumError (a ValueError) that
    carries the h_rms it implies and the span it left, for callers to reword."""
    q = np.geomspace(1e3, 1e8, 40)
    C = 1e-18 * (q / 1e3) ** -3.0 * 1e24  # a micrometre-scale table scaled by (1e6)^4
    with pytest.raises(ImplausibleSpectrumError, match="C gives h_rms") as info:
        TabulatedPSD(q, C)
    err = info.value
    assert isinstance(err, ValueError) and err.h_rms > err.span[1]
    assert err.h_rms == pytest.approx(TabulatedPSD(q, C * 1e-24).h_rms * 1e12, rel=1e-9)
