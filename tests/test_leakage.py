"""Seal leakage (docs/leakage.md): the interface at magnification zeta and the critical junction
(fastline.theory.interface), and the leak rate of a pressure profile (fastline.leakage.flow).

References: ``naive.mean_separation`` / ``naive.edge_separation`` (SciPy quad in the q variable,
the derivative under the integral in q: an independent route from the package's moment
variable), closed forms (rectangle formula, the small-pressure limit of u_c) and invariants.
"""

from __future__ import annotations

import copy
import dataclasses
import functools
import math
import warnings

import naive
import numpy as np
import pytest
from scipy.optimize import brentq
from scipy.special import erfinv

import fastline as fl
from fastline.leakage import flow as leakage
from fastline.theory import interface

RTOL_REF = 1e-6  # u_bar and u1 against the quad reference
RTOL_SEPARATION = 1e-6  # u_bar(1, p) against separation(p) (the theory's rtol)
RTOL_EXACT = 1e-13  # identities computed two ways in floating point
RTOL_RECTANGLE = 1e-10  # leak rate of a constant pressure against the rectangle formula
RTOL_GAP_TABLE = 1e-6  # u_c from the leak-rate table against the direct quadrature
RTOL_ZETA_C = 1e-8  # P(zeta_c) against the threshold (the inverse-moment table's accuracy)
RTOL_LIMIT = 1e-6  # u_c(p) against u(p/a_c) + u0 at p = 1e-9 E*
RTOL_MOMENT_Q, RTOL_MOMENT_SLOPE = 1e-8, 1e-5  # inverse-moment table: q and dq/dB
RTOL_BALANCE = 1e-6  # int u1 (-dP) over zeta against P u_bar (quad of the package's u1)

E_STAR, RADIUS = 1.33e9, 0.01
ETA, DP = 1e-3, 1e5  # water, 1 bar
SURFACES = {
    "surface1": lambda: fl.SelfAffinePSD(10e-6, 0.8, 1e3, 1e4, 1e9),
    "surface2": lambda: fl.SelfAffinePSD(10e-6, 1.0, 1e3, 1e4, 1e9),
    "surface3": lambda: fl.SelfAffinePSD(1e-6, 0.8, 1e3, 1e4, 1e9),
}
PAPER = list(SURFACES)
OTHER = {
    "hurst0.3_q1e13": lambda: fl.SelfAffinePSD(10e-6, 0.3, 1e3, 1e4, 1e13),
    "no_rolloff": lambda: fl.SelfAffinePSD(10e-6, 0.8, 1e3, 1e3, 1e9),
    "sum1+3": lambda: (
        fl.SelfAffinePSD(10e-6, 0.8, 1e3, 1e4, 1e9) + fl.SelfAffinePSD(1e-6, 0.8, 3e3, 1e5, 1e8)
    ),
}
ALL = {**SURFACES, **OTHER}


@functools.cache
def _theory(name):
    return fl.PerssonTheory(ALL[name](), E_STAR)


def _p_seal(th, threshold=0.42):
    """Pressure where P(q1, p) = threshold."""
    return float(erfinv(threshold)) * E_STAR * math.sqrt(float(th.psd.cumulative(th.psd.q1)))


@functools.cache
def _line_contact(name, load):
    return fl.solve_line_contact(
        _theory(name).psd, E_STAR, RADIUS, load, theory=_theory(name), n=256, warn=False
    )


# ----------------------------------------------------------------------------------------------
# the interface at magnification zeta
# ----------------------------------------------------------------------------------------------
REF_POINTS = [
    ("surface1", 3.0, 1e-4),
    ("surface1", 1e4, 5e-3),
    ("surface2", 30.0, 1e-3),
    ("surface3", 1.5, 1e-8),
    ("hurst0.3_q1e13", 1e6, 1e-3),
    ("sum1+3", 20.0, 1e-4),
]


@pytest.mark.slow
@pytest.mark.parametrize("name, zeta, p_rel", REF_POINTS)
def test_mean_and_edge_separation_against_quad(name, zeta, p_rel):
    th = _theory(name)
    p = p_rel * E_STAR
    ref_bar = naive.mean_separation(th.psd, E_STAR, zeta, p, th.gamma)
    ref_u1 = naive.edge_separation(th.psd, E_STAR, zeta, p, th.gamma)
    assert th.mean_separation(zeta, p) == pytest.approx(ref_bar, rel=RTOL_REF)
    assert th.edge_separation(zeta, p) == pytest.approx(ref_u1, rel=RTOL_REF)


@pytest.mark.parametrize("name", list(ALL))
def test_mean_separation_at_zeta_one_is_the_separation(name):
    th = _theory(name)
    p = np.geomspace(1e-9, 1e-1, 9) * E_STAR
    np.testing.assert_allclose(th.mean_separation(1.0, p), th.separation(p), rtol=RTOL_SEPARATION)


@pytest.mark.parametrize("name", PAPER)
def test_apparent_area_is_contact_area_at_zeta_q0(name):
    th = _theory(name)
    zeta = np.geomspace(1.0, th.psd.q1 / th.psd.q0, 13)[:, None]
    p = np.geomspace(1e-6, 1.0, 7)[None, :] * E_STAR
    np.testing.assert_allclose(
        th.apparent_area(zeta, p), th.contact_area(p, zeta * th.psd.q0), rtol=RTOL_EXACT
    )


@pytest.mark.parametrize("name", list(ALL))
def test_edge_separation_exceeds_mean_and_both_fall_with_zeta(name):
    th = _theory(name)
    zeta = np.geomspace(1.001, th.psd.q1 / th.psd.q0, 40)[:, None]
    p = np.geomspace(1e-8, 1e-1, 6)[None, :] * E_STAR
    u_bar = th.mean_separation(zeta, p)
    u1 = th.edge_separation(zeta, p)
    assert np.all(np.isfinite(u_bar)) and np.all(u1 >= u_bar)
    assert np.all(np.diff(u_bar, axis=0) <= 0.0)


@pytest.mark.parametrize("name", ["surface1", "surface3", "hurst0.3_q1e13", "sum1+3"])
@pytest.mark.parametrize("p_rel", [1e-4, 1e-2])
@pytest.mark.parametrize("area", [0.999, 0.5])
def test_area_leaving_contact_carries_the_mean_separation(name, p_rel, area):
    """The balance behind u1, ``d(P u_bar)/dzeta = P' u1``, integrated from zeta_a (where
    P = area) to q1/q0: ``int u1 (-dP) = P(zeta_a) u_bar(zeta_a)``. It checks the closed-form
    zeta-derivatives inside u1 against the value u_bar over the whole band (a P(u) built on
    the area balance, weights -dP at u1 and P(q1) at u = 0, has this first moment)."""
    th = _theory(name)
    p = p_rel * E_STAR
    if th.contact_area(p) >= area:
        pytest.skip("the real contact area already exceeds the area asked for")
    target = (p / (E_STAR * float(erfinv(area)))) ** 2  # A(zeta_a q0)
    top = math.log(th.psd.q1 / th.psd.q0)
    lz = brentq(lambda t: float(th.psd.cumulative(th.psd.q0 * math.exp(t))) - target, 0.0, top)
    zeta_a = math.exp(lz)
    moment = naive.leaving_area_moment(th.psd, E_STAR, p, th.edge_separation, zeta_a)
    expected = float(th.apparent_area(zeta_a, p) * th.mean_separation(zeta_a, p))
    assert moment == pytest.approx(expected, rel=RTOL_BALANCE)


def test_interface_end_points():
    th = _theory("surface1")
    top = th.psd.q1 / th.psd.q0
    assert th.mean_separation(top, 1e6) == 0.0 and th.edge_separation(top, 1e6) == 0.0
    assert th.edge_separation(1.0, 1e6) == math.inf  # P(1) = 1: no area leaves contact


@pytest.mark.parametrize("name", list(ALL))
def test_inverse_moment_table(name):
    psd = ALL[name]()
    tab = interface._MomentTable(psd)
    q = np.concatenate(
        [psd.q0 * (1.0 + np.geomspace(1e-9, 1.0, 50)), np.geomspace(2 * psd.q0, psd.q1, 400)]
    )
    got = np.array([interface._inverse_moment(b, 0, tab.arrays())[:2] for b in psd.cumulative(q)])
    np.testing.assert_allclose(got[:, 0], q, rtol=RTOL_MOMENT_Q)
    slope = 1.0 / (math.pi * q**3 * psd(q))
    np.testing.assert_allclose(got[:, 1], slope, rtol=RTOL_MOMENT_SLOPE)


# ----------------------------------------------------------------------------------------------
# the critical junction
# ----------------------------------------------------------------------------------------------
@pytest.mark.parametrize("name", list(ALL))
def test_critical_gap_monotone_finite_and_at_the_threshold(name):
    th = _theory(name)
    p_seal = _p_seal(th)
    p = np.sort(
        np.concatenate([np.geomspace(1e-9 * E_STAR, p_seal, 200), [10 * p_seal, 10 * E_STAR]])
    )
    cg = th.critical_gap(p)
    assert np.all(np.isfinite(cg.u_c)) and np.all(cg.u_c >= 0.0)
    assert np.all(np.isfinite(cg.zeta)) and np.all(cg.zeta >= 1.0)
    assert np.all(np.diff(cg.u_c) <= 0.0)
    assert np.all(cg.u_c[cg.sealed] == 0.0) and cg.sealed[-1]
    # P(zeta_c) = threshold; near zeta_c = 1, A(zeta q0) ~ (zeta - 1) and zeta_c itself cannot
    # be represented finely enough in float64 (1e-16 / (zeta_c - 1)), so check away from there
    resolved = ~cg.sealed & (cg.zeta > 1.0 + 1e-4)
    assert resolved.sum() > 20 and cg.zeta[0] < 1.0 + 1e-6
    np.testing.assert_allclose(
        th.apparent_area(cg.zeta[resolved], p[resolved]), 0.42, rtol=RTOL_ZETA_C
    )


@pytest.mark.parametrize("threshold", [0.415, 0.42, 0.5])
def test_sealed_exactly_when_real_area_reaches_threshold(threshold):
    th = _theory("surface1")
    p_seal = _p_seal(th, threshold)
    around = p_seal * (1.0 + np.linspace(-4e-16, 4e-16, 17))
    p = np.concatenate([around, p_seal * np.array([0.5, 0.999, 1.001, 2.0])])
    expect = th.contact_area(p) >= threshold
    assert expect.any() and not expect.all()
    assert np.array_equal(th.critical_gap(p, threshold).sealed, expect)
    x = np.arange(p.size) * 1e-5
    res = fl.leak_rate_profile(
        x, p, th, DP, ETA, threshold=threshold, gap_floor=0.0, warn=False
    )  # the percolation criterion alone
    assert np.array_equal(res.sealed_strips, expect) and res.sealed and res.Q == 0.0


@pytest.mark.parametrize("name", PAPER)
def test_small_pressure_limit(name):
    """u_c -> u(p/a_c) + u0 as p -> 0 (docs/leakage.md; fastline.theory.interface)."""
    th = _theory(name)
    p = 1e-9 * E_STAR
    limit = th.separation(p / 0.42) + th.exponential_fit().u0
    assert th.critical_gap(p).u_c == pytest.approx(limit, rel=RTOL_LIMIT)


@pytest.mark.parametrize("name", list(ALL))
def test_gap_table_against_direct(name):
    th = _theory(name)
    p_seal = _p_seal(th)
    p = np.concatenate(
        [np.geomspace(1e-12 * E_STAR, 0.99 * p_seal, 300), p_seal * (1 - np.geomspace(1e-2, 1e-4))]
    )
    direct = th.critical_gap(p).u_c
    log_gap, sealed = interface.gap_table(th, 0.42).log_gap(interface.sealing_argument(th, p))
    assert not sealed.any() and np.all(np.isfinite(log_gap))
    assert np.all(np.diff(log_gap) <= 0.0)
    # the table ends near u_c = 1e-260 m (a closed seal); beyond, a linear continuation
    tabulated = direct > 1e-250
    assert tabulated.sum() > 300
    np.testing.assert_allclose(np.exp(log_gap[tabulated]), direct[tabulated], rtol=RTOL_GAP_TABLE)


# ----------------------------------------------------------------------------------------------
# leak rate
# ----------------------------------------------------------------------------------------------
@pytest.mark.parametrize("n", [2, 7, 64])
def test_uniform_pressure_is_the_rectangle_formula(n):
    th = _theory("surface1")
    Lx, Ly, p0 = 3e-3, 0.2, 2e6
    x = (np.arange(n) + 0.5) * Lx / n
    res = fl.leak_rate_profile(x, np.full(n, p0), th, DP, ETA, Ly, warn=False)
    u_c = res.u_c[0]
    assert np.all(res.u_c == u_c) and not res.sealed
    assert res.Q == pytest.approx(Ly / Lx * DP * u_c**3 / (12.0 * ETA), rel=RTOL_RECTANGLE)
    assert u_c == pytest.approx(th.critical_gap(p0).u_c, rel=RTOL_GAP_TABLE)
    assert res.share_in_fwhm == pytest.approx(1.0, rel=RTOL_EXACT)
    assert res.resistance_width == pytest.approx(0.9 * Lx, rel=RTOL_RECTANGLE)


def test_strips_in_series_on_a_nonuniform_grid():
    """Two pressure levels on unequal strips: resistances add (Q/Ly = dP / sum w_i / sigma_i)."""
    th = _theory("surface1")
    x = np.array([0.0, 1e-3, 3e-3, 4e-3])  # widths 1, 1.5, 1.5, 1 mm
    p = np.array([1e6, 1e6, 4e6, 4e6])
    res = fl.leak_rate_profile(x, p, th, DP, ETA, warn=False)
    g = th.critical_gap([1e6, 4e6]).u_c
    R = 12.0 * ETA * (2.5e-3 / g[0] ** 3 + 2.5e-3 / g[1] ** 3)
    assert res.Q == pytest.approx(DP / R, rel=10 * RTOL_GAP_TABLE)
    np.testing.assert_allclose(res.resistance_share.sum(), 1.0, rtol=RTOL_EXACT)
    assert res.cumulative_share[-1] == 1.0


@pytest.mark.parametrize("name", PAPER)
def test_line_contact_leak_falls_with_load_and_sits_at_the_peak(name):
    loads = np.geomspace(1e3, 1.5e6, 6)
    out = [
        fl.leak_rate(_line_contact(name, f), DP, ETA, theory=_theory(name), warn=False)
        for f in loads
    ]
    rates = np.array([r.Q for r in out])
    assert np.all(np.diff(rates) <= 0.0) and rates[0] > 0.0
    assert all(r.share_in_fwhm > 0.5 for r in out)
    assert all(r.converged for r in out)


def test_exact_scaling_with_pressure_drop_viscosity_and_length():
    th = _theory("surface1")
    res = _line_contact("surface1", 1e4)
    a = fl.leak_rate(res, DP, ETA, 1.0, theory=th, warn=False)
    b = fl.leak_rate(res, 3.0 * DP, 0.25 * ETA, 0.01, theory=th, warn=False)
    assert b.Q == pytest.approx(a.Q * 3.0 / 0.25 * 0.01, rel=RTOL_EXACT * 100)
    assert b.conductance == pytest.approx(a.conductance / 0.25, rel=RTOL_EXACT * 100)
    np.testing.assert_array_equal(a.u_c, b.u_c)
    np.testing.assert_allclose(b.resistance_share, a.resistance_share, rtol=1e-12, atol=0.0)


def test_leak_rate_is_leak_rate_profile_of_the_result():
    th = _theory("surface2")
    res = _line_contact("surface2", 3e4)
    a = fl.leak_rate(res, DP, ETA, 0.05, theory=th, warn=False)
    b = fl.leak_rate_profile(res.x, res.pressure, th, DP, ETA, 0.05, warn=False)
    assert a.Q == b.Q and np.array_equal(a.u_c, b.u_c)


def test_theory_from_the_result_and_cached_tables():
    """leak_rate takes result.theory when no theory is given (the solver will attach it); the
    gap table is built once per theory and threshold."""
    th = _theory("surface1")
    res = copy.copy(_line_contact("surface1", 1e4))
    res.theory = th
    a = fl.leak_rate(res, DP, ETA, warn=False)
    assert a.Q == fl.leak_rate(res, DP, ETA, theory=th, warn=False).Q
    assert interface.gap_table(th, 0.42) is interface.gap_table(th, 0.42)
    assert interface.gap_table(th, 0.5) is not interface.gap_table(th, 0.42)


def test_zero_pressure_strips_add_no_resistance():
    th = _theory("surface1")
    x = np.arange(5) * 1e-4
    with_zeros = fl.leak_rate_profile(x, [0.0, 1e6, 2e6, 1e6, 0.0], th, DP, ETA, warn=False)
    assert with_zeros.u_c[0] == math.inf and with_zeros.resistance_share[0] == 0.0
    core = fl.leak_rate_profile(x[1:4], [1e6, 2e6, 1e6], th, DP, ETA, warn=False)
    assert with_zeros.Q == pytest.approx(core.Q, rel=RTOL_EXACT * 100)


# ----------------------------------------------------------------------------------------------
# radial flow: a point contact's orifice
# ----------------------------------------------------------------------------------------------
@functools.cache
def _point_contact(name, load):
    th = _theory(name)
    return fl.solve_point_contact(th.psd, E_STAR, RADIUS, load, theory=th, n=128, warn=False)


@pytest.mark.parametrize("n", [3, 40])
def test_uniform_pressure_annulus_is_the_log_formula(n):
    """Constant p on rings from r_in to r_out: Q = 2 pi dP u_c^3 / (12 eta ln(r_out / r_in))."""
    th = _theory("surface1")
    dr, p0 = 1e-3, 2e6
    r = np.arange(n) * dr  # cells of a point contact: a disc on the axis, then rings
    r_in, r_out = 0.3 * dr, (n - 0.5) * dr
    res = fl.leak_rate_profile(r, np.full(n, p0), th, DP, ETA, inner_radius=r_in, warn=False)
    u_c = th.critical_gap(p0).u_c
    expected = 2.0 * math.pi * DP * u_c**3 / (12.0 * ETA * math.log(r_out / r_in))
    assert res.Q == pytest.approx(expected, rel=RTOL_RECTANGLE + RTOL_GAP_TABLE * 3)
    assert res.conductance == pytest.approx(res.Q / DP, rel=RTOL_EXACT)
    assert res.inner_radius == r_in and res.length is None
    np.testing.assert_allclose(res.resistance_share.sum(), 1.0, rtol=RTOL_EXACT)


def test_rings_in_series_against_the_quadrature_reference():
    """Two pressure levels, an orifice inside the third cell: against naive.radial_leak_rate."""
    th = _theory("surface1")
    r = np.arange(12) * 2e-4
    p = np.where(r < 1e-3, 4e6, 1e6)
    r_in = 2.3 * 2e-4
    res = fl.leak_rate_profile(r, p, th, DP, ETA, inner_radius=r_in, warn=False)
    ref = naive.radial_leak_rate(r, res.u_c, r_in, DP, ETA)
    assert res.Q == pytest.approx(ref, rel=RTOL_REF)
    inside = r + 1e-4 <= r_in  # cells wholly inside the orifice: not on the flow path
    assert inside.sum() == 2 and np.all(res.resistance_share[inside] == 0.0)


def test_point_contact_leak_falls_with_load_and_with_a_smaller_orifice():
    name = "surface1"
    loads = [0.3, 1.0, 3.0]
    rates = []
    for f in loads:
        res = _point_contact(name, f)
        hwhm = 0.5 * res.fwhm
        leak = fl.leak_rate(res, DP, ETA, inner_radius=0.05 * hwhm, warn=False)
        assert leak.converged and leak.share_in_fwhm > 0.5
        assert leak.diagnostics["orifice_share"] == pytest.approx(0.05, rel=0.2)
        smaller = fl.leak_rate(res, DP, ETA, inner_radius=0.01 * hwhm, warn=False)
        assert 0.0 < smaller.Q < leak.Q  # more of the high-pressure core on the path
        rates.append(leak.Q)
    assert rates[0] > rates[1] > rates[2] > 0.0
    res = _point_contact(name, 1.0)
    b = fl.leak_rate(res, 3.0 * DP, 0.25 * ETA, inner_radius=1e-5, warn=False)
    a = fl.leak_rate(res, DP, ETA, inner_radius=1e-5, warn=False)
    assert b.Q == pytest.approx(a.Q * 3.0 / 0.25, rel=RTOL_EXACT * 100)
    same = fl.leak_rate_profile(res.r, res.pressure, res.theory, DP, ETA, inner_radius=1e-5)
    assert same.Q == a.Q


def test_leak_of_an_unconverged_solve_warns_once():
    """A leak rate from a pressure that did not converge says so (LeakageWarning), once for a
    loop of such scenes; a converged solve's leak rate does not."""
    th = _theory("surface1")
    kw = dict(theory=th, n=128, warn=False)
    bad = [fl.solve_line_contact(th.psd, E_STAR, RADIUS, f, max_iter=1, **kw) for f in (1e3, 2e3)]
    assert not any(r.converged for r in bad)
    with warnings.catch_warnings(record=True) as seen:
        warnings.simplefilter("default")
        leaks = [fl.leak_rate(r, DP, ETA) for r in bad + bad]
    texts = [str(w.message) for w in seen if "did not converge" in str(w.message)]
    assert texts == [leakage.UNCONVERGED] and not any(k.converged for k in leaks)
    assert all(issubclass(w.category, fl.LeakageWarning) for w in seen)
    good = fl.solve_line_contact(th.psd, E_STAR, RADIUS, 1e3, **kw)
    with warnings.catch_warnings(record=True) as seen:
        warnings.simplefilter("always")
        fl.leak_rate(good, DP, ETA)
    assert not [w for w in seen if "did not converge" in str(w.message)]


def test_orifice_warning():
    th = _theory("surface1")
    r = np.arange(64) * 5e-4
    p = 2e6 * np.exp(-((r / 1e-2) ** 2))  # half width at half maximum ~8.3 mm
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        small = fl.leak_rate_profile(r, p, th, DP, ETA, inner_radius=2e-4)
    assert small.diagnostics["warnings"] == []
    with pytest.warns(fl.LeakageWarning, match="orifice_share"):
        wide = fl.leak_rate_profile(r, p, th, DP, ETA, inner_radius=2e-3)
    assert wide.diagnostics["orifice_share"] > leakage.MAX_ORIFICE_SHARE


def test_radial_bad_input():
    th = _theory("surface1")
    point = _point_contact("surface1", 1.0)
    line = _line_contact("surface1", 1e4)
    with pytest.raises(ValueError, match="inner_radius is required"):
        fl.leak_rate(point, DP, ETA)
    with pytest.raises(ValueError, match="inner_radius is for a point contact"):
        fl.leak_rate(line, DP, ETA, inner_radius=1e-5)
    with pytest.raises(ValueError, match="length"):
        fl.leak_rate(point, DP, ETA, 0.1, inner_radius=1e-5)
    for bad in (0.0, -1e-5, math.nan, 1.0):
        with pytest.raises(ValueError, match="inner_radius"):
            fl.leak_rate(point, DP, ETA, inner_radius=bad)
    for bad in (None, np.zeros(5), "result"):
        with pytest.raises(TypeError, match="LineContactResult or a PointContactResult"):
            fl.leak_rate(bad, DP, ETA, theory=th)
    with pytest.raises(ValueError, match="radii >= 0"):
        fl.leak_rate_profile([-1e-4, 0.0, 1e-4], [1e6] * 3, th, DP, ETA, inner_radius=1e-5)
    for bad in (None, "no", 2):  # a flag is a bool ("no" would be truthy)
        with pytest.raises(TypeError, match="warn must be True or False"):
            fl.leak_rate(line, DP, ETA, theory=th, warn=bad)
        with pytest.raises(TypeError, match="warn must be True or False"):
            fl.leak_rate_profile(line.x, line.pressure, th, DP, ETA, warn=bad)


def test_radial_figure_and_file(tmp_path):
    """The figure of a radial leak is drawn against r with the orifice shaded; its CSV header
    holds inner_radius_m (no seal length) and the conductance of the whole contact."""
    pytest.importorskip("matplotlib")
    from fastline import io
    from fastline.reports import plotting

    res = _point_contact("surface1", 1.0)
    leak = fl.leak_rate(res, DP, ETA, inner_radius=1e-5, warn=False)
    top, bottom = plotting.plot_leak(leak).axes
    assert bottom.get_xlabel().startswith("$r$")
    labels = [t.get_text() for t in top.get_legend().get_texts()]
    assert any(t.startswith("orifice") for t in labels)
    assert any(t.startswith("half width at half maximum") for t in labels)
    io.write_leak_csv(tmp_path / "leak.csv", leak)
    meta, columns = io.read_csv(tmp_path / "leak.csv")
    assert float(meta["inner_radius_m"]) == pytest.approx(1e-5) and "length_m" not in meta
    assert float(meta["conductance_m3_per_Pa_s"]) == pytest.approx(leak.conductance, rel=1e-6)
    np.testing.assert_allclose(columns[next(iter(columns))], leak.x)


@pytest.mark.parametrize("name", ["surface1", "no_rolloff", "sum1+3"])
def test_rolloff_of_a_measured_table(name):
    """The roll-off of a spectrum without a known qr (a table) is where q^2 C peaks: that of
    the self-affine spectrum it samples (to the table's node spacing), q0 without a roll-off."""
    psd = ALL[name]()
    q = np.geomspace(psd.q0, psd.q1, 301)
    table = fl.TabulatedPSD(q, psd(q))
    step = q[1] / q[0]
    assert leakage._rolloff_wavenumber(table) == pytest.approx(
        leakage._rolloff_wavenumber(psd), rel=step - 1.0
    )


# ----------------------------------------------------------------------------------------------
# range of validity (warnings)
# ----------------------------------------------------------------------------------------------
def _punch(th, width, p0=2e6, n=32):
    return (np.arange(n) + 0.5) * width / n, np.full(n, p0)


def test_no_warning_inside_the_range():
    th = _theory("surface1")  # roll-off wavelength 0.63 mm
    x, p = _punch(th, 20e-3)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        res = fl.leak_rate_profile(x, p, th, DP, ETA, mean_free_path=None)
    assert res.diagnostics["warnings"] == []


@pytest.mark.parametrize(
    "kwargs, key",
    [
        ({"width": 1e-3}, "junctions_across"),
        ({"pressure_drop": 1e6}, "fluid_pressure_ratio"),
        ({"mean_free_path": 1e-5}, "knudsen"),
    ],
)
def test_one_warning_per_cause(kwargs, key):
    th = _theory("surface1")
    x, p = _punch(th, kwargs.pop("width", 20e-3))
    args = {"pressure_drop": DP, **kwargs}
    with pytest.warns(fl.LeakageWarning) as record:
        res = fl.leak_rate_profile(x, p, th, viscosity=ETA, **args)
    assert len(record) == 1 and key in str(record[0].message)
    assert issubclass(fl.LeakageWarning, fl.ValidityWarning)
    assert len(res.diagnostics["warnings"]) == 1


# ----------------------------------------------------------------------------------------------
# bad input
# ----------------------------------------------------------------------------------------------
@pytest.mark.parametrize(
    "kwargs, match",
    [
        ({"viscosity": 0.0}, "viscosity"),
        ({"viscosity": -1e-3}, "viscosity"),
        ({"pressure_drop": 0.0}, "pressure_drop"),
        ({"pressure_drop": math.nan}, "pressure_drop"),
        ({"length": -1.0}, "length"),
        ({"threshold": 0.0}, "threshold"),
        ({"threshold": 1.0}, "threshold"),
        ({"threshold": 1.5}, "threshold"),
        ({"method": "effective medium"}, "method"),
        ({"gap_floor": -1e-9}, "gap_floor"),
        ({"mean_free_path": 0.0}, "mean_free_path"),
    ],
)
def test_bad_scalars(kwargs, match):
    th = _theory("surface1")
    res = _line_contact("surface1", 1e4)
    args = {"pressure_drop": DP, "viscosity": ETA, **kwargs}
    with pytest.raises(ValueError, match=match):
        fl.leak_rate(res, theory=th, **args)
    with pytest.raises(ValueError, match=match):
        fl.leak_rate_profile(res.x, res.pressure, th, **args)


def test_bad_results_and_profiles():
    th = _theory("surface1")
    hertz = fl.solve_line_contact(None, E_STAR, RADIUS, 1e4, model="hertz", n=64)
    with pytest.raises(ValueError, match="hertz"):
        fl.leak_rate(hertz, DP, ETA, theory=th)
    res = _line_contact("surface1", 1e4)
    assert fl.leak_rate(res, DP, ETA).Q > 0.0  # the result carries its theory
    with pytest.raises(ValueError, match="PerssonTheory"):
        fl.leak_rate(dataclasses.replace(res, theory=None), DP, ETA)  # none on it, none given
    with pytest.raises(ValueError, match="E_star"):
        fl.leak_rate(res, DP, ETA, theory=fl.PerssonTheory(th.psd, 2 * E_STAR))
    with pytest.raises(TypeError, match="PerssonTheory"):
        fl.leak_rate(res, DP, ETA, theory="surface1")
    x = np.arange(4) * 1e-4
    for xx, pp, match in [
        (x[::-1], [1e6] * 4, "increasing"),
        (x, [1e6, -1.0, 1e6, 1e6], "p must be >= 0"),
        (x, [1e6] * 3, "same length"),
        (x[:1], [1e6], "at least 2"),
        (x, [0.0] * 4, "> 0 somewhere"),
        (x, [1e6, math.nan, 1e6, 1e6], "finite"),
    ]:
        with pytest.raises(ValueError, match=match):
            fl.leak_rate_profile(xx, pp, th, DP, ETA)


def test_bad_interface_input():
    th = _theory("surface1")
    for fn in (th.apparent_area, th.mean_separation, th.edge_separation):
        with pytest.raises(ValueError, match="zeta"):
            fn(0.5, 1e6)
        with pytest.raises(ValueError, match="zeta"):
            fn(2e6, 1e6)  # beyond q1/q0 = 1e6
        with pytest.raises(ValueError, match="p must be > 0"):
            fn(2.0, 0.0)
    with pytest.raises(ValueError, match="p must be > 0"):
        th.critical_gap([1e6, -1.0])
    with pytest.raises(ValueError, match="threshold"):
        th.critical_gap(1e6, threshold=0.0)
    with pytest.raises(TypeError, match="PerssonTheory"):
        interface.critical_gap(None, 1e6)


def test_spectrum_with_a_gap_is_refused():
    q = np.array([1e3, 1e4, 1e5, 1e6, 1e7])
    C = np.array([1e-20, 1e-24, 0.0, 1e-30, 1e-34])  # C = 0 on (1e4, 1e6)
    th = fl.PerssonTheory(fl.TabulatedPSD(q, C), E_STAR)
    with pytest.raises(ValueError, match="gap"):
        th.critical_gap(1e6)


def test_a_theory_of_another_interface_is_refused():
    """``theory=`` of another spectrum (or gamma) than the solve's would give a leak rate
    decades off without a word; it is refused like a theory of another E*."""
    res = _line_contact("surface1", 1e4)
    with pytest.raises(ValueError, match="h_rms"):
        fl.leak_rate(res, DP, ETA, theory=_theory("surface3"))  # h_rms 1 um, not 10 um
    with pytest.raises(ValueError, match="gamma"):
        fl.leak_rate(res, DP, ETA, theory=fl.PerssonTheory(res.theory.psd, E_STAR, gamma=0.3))
    point = _point_contact("surface1", 1.0)
    with pytest.raises(ValueError, match="h_rms"):
        fl.leak_rate(point, DP, ETA, inner_radius=1e-5, theory=_theory("surface3"))
    same = fl.PerssonTheory(ALL["surface1"](), E_STAR)  # an equal spectrum, another object
    assert fl.leak_rate(res, DP, ETA, theory=same, warn=False).Q > 0.0
