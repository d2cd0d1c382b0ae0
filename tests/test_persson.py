"""Acceptance tests of fastline.theory.persson: P(q, p), u(p), its inverse p(u), the exponential
law.

Reference: ``naive.separation`` (SciPy quad double integral of docs/theory.md section 3).
"""

from __future__ import annotations

import functools
import math
import warnings

import naive
import numpy as np
import pytest
from scipy.special import erf, erfinv

from fastline.theory.persson import PerssonTheory
from fastline.theory.spectra import SelfAffinePSD, TabulatedPSD
from fastline.theory.tables import _quintic, _separation_and_slope, solver_law

RTOL_REF = 1e-6  # default-rtol PerssonTheory vs the quad reference
RTOL_ROUNDTRIP = 1e-6  # pressure(separation(p)) vs p, inside the tables and below them
# above the table (x = w(q1) p/E* > 12, u < 1e-60 m) pressure(u) is a fitted continuation of
# the large-x form of F; documented as such, held to this looser bound
RTOL_CONTINUATION = 1e-4
RTOL_TABLE_INVERSE = 1e-8  # separation_table(pressure(u)) vs u (both from the same tables)
RTOL_FIT_SLOPE = 1e-3  # -du/dln p at small p vs u0
RTOL_FIT_LAW = 1e-4  # u(p) vs u0 ln(beta E*/p) at p = 1e-9 E*
RTOL_FIT_REF = 1e-6  # closed-form u0 vs the reference's slope between 1e-11 and 1e-10 E*
RTOL_EXACT = 1e-12  # erf identities, quintic Hermite on polynomials
# T1's solver form (Horner) vs its Hermite data: the same polynomials up to round-off (measured
# <= 1.3e-12 in u and 2.4e-12 in du/dv over 5 surfaces x 3 rtols; one ulp of the cell coordinate
# times |d ln u/dv| ~ 300 near full contact)
RTOL_SOLVER_FORM = 1e-11
N_PRESSURES = 6

E_STAR = 1.33e9  # Pa, the paper's scenes
GAMMA = 0.45


def _surface(h_rms, hurst, q0=1e3, qr=1e4, q1=1e9):
    return SelfAffinePSD(h_rms, hurst, q0, qr, q1)


def _tabulated_surface1():
    s1 = _surface(10e-6, 0.8)
    nodes = np.geomspace(1e3, 1e9, 121)  # 20 per decade: contains 1e4 (to rounding)
    nodes[np.argmin(np.abs(nodes - 1e4))] = 1e4
    nodes[0], nodes[-1] = 1e3, 1e9
    return TabulatedPSD(nodes, s1(nodes))


CASES = {
    "surface1": lambda: _surface(10e-6, 0.8),
    "surface2": lambda: _surface(10e-6, 1.0),
    "surface3": lambda: _surface(1e-6, 0.8),
    "hurst0.3": lambda: _surface(10e-6, 0.3),
    "q1_over_q0_1e10": lambda: _surface(10e-6, 0.8, q1=1e13),
    "no_rolloff": lambda: _surface(10e-6, 0.8, qr=1e3),
    "tabulated1": _tabulated_surface1,
    "sum1+3": lambda: _surface(10e-6, 0.8) + _surface(1e-6, 0.8),
}
PAPER = ["surface1", "surface2", "surface3"]


@functools.cache
def _psd(name):
    return CASES[name]()


@functools.cache
def _theory(name, rtol=1e-6):
    return PerssonTheory(_psd(name), E_star=E_STAR, gamma=GAMMA, rtol=rtol)


def _p99(psd):
    """Pressure where P(q1, p) = 0.99."""
    return float(erfinv(0.99)) * E_STAR * math.sqrt(float(psd.cumulative(psd.q1)))


@functools.cache
def _reference(name):
    psd = _psd(name)
    p = np.geomspace(1e-7 * E_STAR, _p99(psd), N_PRESSURES)
    u = np.array([naive.separation(psd, E_STAR, float(pi), GAMMA) for pi in p])
    return p, u


# ------------------------------------------------------------------------------------------------
# u(p) against the reference
# ------------------------------------------------------------------------------------------------
@pytest.mark.parametrize("method", ["separation", "separation_table"])
@pytest.mark.parametrize("case", list(CASES))
def test_separation_vs_reference(case, method):
    th = _theory(case)
    p, ref = _reference(case)
    got = th.separation(p) if method == "separation" else th.separation_table(p)[0]
    assert np.all(ref > 0.0)
    np.testing.assert_allclose(got, ref, rtol=RTOL_REF, atol=0.0)


def test_separation_no_rolloff_transition():
    """qr == q0: extra pressures where P(q, p) changes fastest near q0 (1e-3..1e-2 E*)."""
    psd = _psd("no_rolloff")
    th = _theory("no_rolloff")
    p = np.array([2.15e-3, 4.64e-3]) * E_STAR
    ref = np.array([naive.separation(psd, E_STAR, float(pi), GAMMA) for pi in p])
    np.testing.assert_allclose(th.separation(p), ref, rtol=RTOL_REF, atol=0.0)
    np.testing.assert_allclose(th.separation_table(p)[0], ref, rtol=RTOL_REF, atol=0.0)


def test_separation_shapes():
    th = _theory("surface1")
    p = np.geomspace(1e-6, 1e-1, 6).reshape(2, 3) * E_STAR
    u = th.separation(p)
    assert u.shape == (2, 3)
    np.testing.assert_array_equal(u.ravel(), th.separation(p.ravel()))
    ut, dudv = th.separation_table(p)
    assert ut.shape == dudv.shape == (2, 3)
    assert np.shape(th.separation(1e5)) == ()


# ------------------------------------------------------------------------------------------------
# inverse p(u), monotonicity, robustness
# ------------------------------------------------------------------------------------------------
_ROUNDTRIP_REGIONS = ["below_table", "table", "above_table"]


@pytest.mark.parametrize("region", _ROUNDTRIP_REGIONS)
def test_pressure_inverts_separation(region):
    """pressure(separation(p)) == p on 1e-30 E* .. 20 E*, split by table region."""
    th = _theory("surface1")
    p = np.geomspace(1e-30 * E_STAR, 20.0 * E_STAR, 3001)
    p_lo, p_hi = th.p_range
    assert p[0] < p_lo < p_hi < p[-1]  # the grid covers both extensions
    sel = {"below_table": p < p_lo, "table": (p >= p_lo) & (p <= p_hi), "above_table": p > p_hi}
    p = p[sel[region]]
    u = th.separation(p)
    assert np.all(u > 0.0)
    rtol = RTOL_CONTINUATION if region == "above_table" else RTOL_ROUNDTRIP
    np.testing.assert_allclose(th.pressure(u), p, rtol=rtol, atol=0.0)


@pytest.mark.parametrize("case", PAPER)
def test_table_inverse_consistent(case):
    th = _theory(case)
    u = np.geomspace(1e-14, 1e-3, 4001)
    p = th.pressure(u)
    live = p > 1e-290  # leave out the subnormal tail of exp(-u/u0) at large u
    assert np.count_nonzero(live) > 3000
    back = th.separation_table(p[live])[0]
    np.testing.assert_allclose(back, u[live], rtol=RTOL_TABLE_INVERSE, atol=0.0)
    # and the other way round, from pressures across the whole table and beyond
    pp = np.geomspace(1e-20 * E_STAR, th.p_range[1] * 1.5, 4001)
    ut = th.separation_table(pp)[0]
    np.testing.assert_allclose(th.pressure(ut), pp, rtol=RTOL_TABLE_INVERSE, atol=0.0)


@pytest.mark.parametrize("case", ["surface1", "hurst0.3"])
def test_pressure_cells_join_continuously(case):
    """p(u) reads its cell from the float's bits: check every cell edge from both sides.

    At each edge ``u_e = 2^e (1 + j/2^m)`` the value just below comes from the end of one cell
    polynomial and the value at u_e from the start of the next one; both interpolate the same
    node, so they agree to rounding. A wrong shift, mask or base offset breaks this by the
    size of a cell.
    """
    th = _theory(case)
    Cf, base, logm = th._t2[:3]
    m = 1 << logm
    ks = np.arange(Cf.shape[0] + 1) + base
    edges = np.ldexp(1.0 + (ks % m) / m, ks // m - 1023)
    below = np.nextafter(edges, 0.0)
    p_at, p_below = th.pressure(edges), th.pressure(below)
    live = p_at > 1e-290
    np.testing.assert_allclose(p_below[live], p_at[live], rtol=1e-12, atol=0.0)
    # the cells agree with a plain Newton inversion of the table u(p) at their midpoints
    mid = 0.5 * (edges[:-1] + edges[1:])
    pm = th.pressure(mid)
    live = pm > 1e-290
    np.testing.assert_allclose(
        th.separation_table(pm[live])[0], mid[live], rtol=RTOL_TABLE_INVERSE, atol=0.0
    )
    # subnormal and strided input take the general paths
    assert np.isfinite(th.pressure(np.array([5e-324, 1e-310]))).all()
    u = np.geomspace(1e-12, 1e-4, 101)
    np.testing.assert_array_equal(th.pressure(u[::2]), th.pressure(u)[::2])


@pytest.mark.parametrize("case", PAPER)
def test_monotonic(case):
    th = _theory(case)
    p = np.geomspace(1e-30 * E_STAR, 20.0 * E_STAR, 20001)
    u = th.separation(p)
    pos = u > 0.0  # the direct quadrature may underflow to 0 at very high pressure
    assert np.all(pos[p <= th.p_range[1]])
    assert np.all(np.diff(u[pos]) < 0.0)
    ut, dudv = th.separation_table(p)
    posT = ut > 0.0
    assert np.all(np.diff(ut[posT]) < 0.0)
    assert np.all(dudv[posT] < 0.0)
    uu = np.geomspace(1e-15, 1e-2, 20001)
    pu = th.pressure(uu)
    assert np.all(pu[uu <= 500.0 * th.exponential_fit().u0] > 0.0)
    normal = pu > 1e-290  # subnormal p (u > ~700 u0) may repeat values
    assert np.all(np.diff(pu[normal]) < 0.0)
    assert np.all(np.diff(pu) <= 0.0)


@pytest.mark.parametrize("case", ["surface1", "surface3", "no_rolloff"])
def test_no_nan_or_inf(case):
    th = _theory(case)
    u = np.geomspace(1e-300, 1.0, 3001)
    p = th.pressure(u)
    assert np.all(np.isfinite(p)) and np.all(p >= 0.0)
    pp = np.geomspace(1e-300, 1e15, 3001)
    for arr in (th.separation(pp), *th.separation_table(pp)):
        assert np.all(np.isfinite(arr))
    assert np.all(th.separation(pp) >= 0.0)
    assert np.all(th.separation_table(pp)[0] >= 0.0)


# ------------------------------------------------------------------------------------------------
# exponential law
# ------------------------------------------------------------------------------------------------
@pytest.mark.parametrize("case", PAPER)
def test_exponential_fit(case):
    th = _theory(case)
    fit = th.exponential_fit()
    psd = _psd(case)
    assert 0.3 < fit.gamma_u < 0.8
    assert fit.gamma_u == pytest.approx(fit.u0 / psd.h_rms, rel=RTOL_EXACT)
    assert fit.beta > 0.0
    # independent estimate of u0: -du/dln p by central differences at small pressure
    for pe in (1e-9, 1e-8, 1e-7):
        p = pe * E_STAR
        d = 1e-3
        u_plus, u_minus = th.separation(np.array([p * math.exp(d), p * math.exp(-d)]))
        slope = -(u_plus - u_minus) / (2.0 * d)
        assert slope == pytest.approx(fit.u0, rel=RTOL_FIT_SLOPE)
    # the law is the small-p asymptote of the full u(p)
    p = 1e-9 * E_STAR
    law = fit.u0 * math.log(fit.beta * E_STAR / p)
    u = float(th.separation(p))
    assert abs(u - law) <= RTOL_FIT_LAW * u
    # and of the reference: u0, beta from two quad evaluations deep in the exponential regime
    pa, pb = 1e-11 * E_STAR, 1e-10 * E_STAR
    ua = naive.separation(psd, E_STAR, pa, GAMMA)
    ub = naive.separation(psd, E_STAR, pb, GAMMA)
    u0_ref = (ua - ub) / math.log(pb / pa)
    assert fit.u0 == pytest.approx(u0_ref, rel=RTOL_FIT_REF)
    beta_ref = math.exp(ua / u0_ref) * pa / E_STAR
    # ln beta = ua/u0 + ln(pa/E*): the u0 error is amplified by ua/u0
    assert fit.beta == pytest.approx(beta_ref, rel=RTOL_FIT_REF * ua / u0_ref)


# ------------------------------------------------------------------------------------------------
# contact area
# ------------------------------------------------------------------------------------------------
def test_contact_area_at_q1():
    psd = _psd("surface1")
    th = _theory("surface1")
    w1 = 1.0 / math.sqrt(float(psd.cumulative(psd.q1)))
    p = np.concatenate([[0.0], np.geomspace(1e-8, 10.0, 200) * E_STAR])
    P = th.contact_area(p)
    np.testing.assert_allclose(P, erf(w1 * p / E_STAR), rtol=RTOL_EXACT, atol=0.0)
    assert P[0] == 0.0
    assert np.all(np.diff(P) >= 0.0) and np.all(np.diff(P[:150]) > 0.0)
    assert np.all(P <= 1.0)
    # P(q1, p99) = 0.99
    assert th.contact_area(np.array([_p99(psd)]))[0] == pytest.approx(0.99, rel=1e-12)
    # small-p linear law P ~ (2/sqrt(pi)) w p / E*
    ps = np.array([1e-10, 1e-9, 1e-8]) * E_STAR
    lin = 2.0 / math.sqrt(math.pi) * w1 * ps / E_STAR
    np.testing.assert_allclose(th.contact_area(ps), lin, rtol=1e-12)
    # explicit q = q1 is the default
    np.testing.assert_allclose(th.contact_area(p, psd.q1), P, rtol=RTOL_EXACT, atol=0.0)


def test_contact_area_shapes():
    th = _theory("surface1")
    assert np.shape(th.contact_area(1e6)) == ()  # like separation(): a scalar in, 0-d out
    assert np.shape(th.contact_area(1e6, 1e5)) == ()
    assert th.contact_area(np.array([1e6, 2e6])).shape == (2,)
    assert th.contact_area(np.ones((3, 1)) * 1e6, np.array([1e4, 1e5])).shape == (3, 2)


@pytest.mark.parametrize("case", ["surface1", "sum1+3", "tabulated1"])
def test_contact_area_broadcast_and_q0(case):
    psd = _psd(case)
    th = _theory(case)
    q = np.array([psd.q0, 2e3, 1e4, 1e6, psd.q1])
    p = np.array([0.0, 1e3, 1e6, 1e8, 1e9]).reshape(-1, 1)
    P = th.contact_area(p, q)
    assert P.shape == (5, 5)
    w = 1.0 / np.sqrt(psd.cumulative(q[1:]))
    np.testing.assert_allclose(P[:, 1:], erf(w * p / E_STAR), rtol=RTOL_EXACT, atol=0.0)
    # at q0 the contact is complete for any p > 0 (w infinite), and 0 at p = 0
    assert P[0, 0] == 0.0
    np.testing.assert_array_equal(P[1:, 0], 1.0)
    # P decreases with magnification, increases with pressure
    assert np.all(np.diff(P[1:], axis=1) <= 0.0)
    assert np.all(np.diff(P, axis=0) >= 0.0)


def test_contact_area_rejects():
    th = _theory("surface1")
    for q in (999.0, 1.01e9, [1e4, 2e9]):
        with pytest.raises(ValueError, match=r"^q\b"):
            th.contact_area(1e6, q)
    for p in (-1.0, [1e6, -1e-3], math.nan, math.inf):
        with pytest.raises(ValueError, match=r"^p\b"):
            th.contact_area(p)


# ------------------------------------------------------------------------------------------------
# accuracy settings
# ------------------------------------------------------------------------------------------------
@pytest.mark.parametrize("rtol, epsrel", [(1e-4, 1e-10), (1e-8, 1e-12)])
def test_rtol_setting(rtol, epsrel):
    psd = _psd("surface1")
    th = _theory("surface1", rtol)
    default = _theory("surface1")
    n, n_def = th._t1[2].size, default._t1[2].size
    assert (n < n_def) if rtol > 1e-6 else (n > n_def)
    p = np.array([1e-6, 1e-3, 0.3]) * E_STAR
    ref = np.array([naive.separation(psd, E_STAR, float(pi), GAMMA, epsrel=epsrel) for pi in p])
    np.testing.assert_allclose(th.separation(p), ref, rtol=rtol, atol=0.0)
    np.testing.assert_allclose(th.separation_table(p)[0], ref, rtol=rtol, atol=0.0)


# ------------------------------------------------------------------------------------------------
# the solvers' form of table T1 (Horner)
# ------------------------------------------------------------------------------------------------
def _t1_probes(th):
    """v = ln p on every T1 node and one ulp either side, the cell midpoints, exactly on both
    table ends, and beyond them on both sides."""
    v0, h, L = th._t1[:3]
    nodes = v0 + h * np.arange(L.size)
    v_hi = nodes[-1]
    ulp = np.spacing(np.abs(nodes))
    beyond = np.array([v0 - 60.0, v0 - 1.0, v_hi + 0.1, v_hi + 0.5])  # u ~ 1e-185 m
    mids = 0.5 * (nodes[1:] + nodes[:-1])
    return np.concatenate([nodes, nodes - ulp, nodes + ulp, mids, [v0, v_hi], beyond])


@pytest.mark.parametrize("rtol", [1e-4, 1e-6, 1e-8])
@pytest.mark.parametrize("case", ["surface1", "hurst0.3", "tabulated1"])
def test_solver_form_equals_table(case, rtol):
    """The law the solvers evaluate (T1 as Horner polynomials, both extensions) against T1's
    Hermite data, and inside the table against the direct quadrature to the theory's rtol."""
    th = _theory(case, rtol)
    v = _t1_probes(th)
    u, dudv, ut, dt = (np.empty_like(v) for _ in range(4))
    solver_law(v, *th._t1_solver, u, dudv)
    _separation_and_slope(v, *th._t1, ut, dt)
    assert np.all(ut > 0.0) and np.all(dt < 0.0)
    np.testing.assert_allclose(u, ut, rtol=RTOL_SOLVER_FORM, atol=0.0)
    np.testing.assert_allclose(dudv, dt, rtol=RTOL_SOLVER_FORM, atol=0.0)
    v0, h, L, _, _, u0, _ = th._t1
    below = v <= v0  # the exponential law: slope -u0 exactly, joined to the table at v0
    assert np.all(dudv[below] == -u0)
    inside = np.linspace(v0, v0 + (L.size - 1) * h, 41)[1:-1] + 0.37 * h
    solver_law(inside, *th._t1_solver, u[:39], dudv[:39])
    np.testing.assert_allclose(u[:39], th.separation(np.exp(inside)), rtol=rtol, atol=0.0)


# ------------------------------------------------------------------------------------------------
# validation
# ------------------------------------------------------------------------------------------------
@pytest.mark.parametrize(
    "kwargs, name",
    [
        (dict(E_star=0.0), "E_star"),
        (dict(E_star=-1e9), "E_star"),
        (dict(E_star=math.nan), "E_star"),
        (dict(E_star=math.inf), "E_star"),
        (dict(gamma=0.0), "gamma"),
        (dict(gamma=1.2), "gamma"),
        (dict(gamma=-0.45), "gamma"),
        (dict(gamma=math.nan), "gamma"),
        (dict(gamma=math.inf), "gamma"),
        (dict(rtol=0.0), "rtol"),
        (dict(rtol=math.nan), "rtol"),
    ],
)
def test_constructor_rejects(kwargs, name):
    args = dict(psd=_psd("surface1"), E_star=E_STAR, gamma=GAMMA)
    args.update(kwargs)
    with pytest.raises(ValueError, match=rf"^{name}\b"):
        PerssonTheory(**args)


@pytest.mark.parametrize("psd", ["surface1", None, lambda q: q, np.ones(3)])
def test_constructor_rejects_what_is_not_a_spectrum(psd):
    """A wrong type is a TypeError naming psd (as everywhere else a spectrum is taken)."""
    with pytest.raises(TypeError, match=r"^psd must be a fastline PSD, got"):
        PerssonTheory(psd, E_STAR, gamma=GAMMA)


@pytest.mark.parametrize("bad", [0.0, -1.0, math.nan, math.inf, [1e6, 0.0], [math.nan, 1.0]])
def test_methods_reject(bad):
    th = _theory("surface1")
    with pytest.raises(ValueError, match=r"^p\b"):
        th.separation(bad)
    with pytest.raises(ValueError, match=r"^p\b"):
        th.separation_table(bad)
    with pytest.raises(ValueError, match=r"^u\b"):
        th.pressure(bad)


_COMPLEX = [np.array([1e5 + 1j]), [1e5 + 0j, 2e5], np.complex128(1e5), 1e5 + 1e-3j]
_COMPLEX_CALLS = {
    "separation": lambda th, z: th.separation(z),
    "separation_table": lambda th, z: th.separation_table(z),
    "pressure": lambda th, z: th.pressure(z),
    "contact_area p": lambda th, z: th.contact_area(z),
    "contact_area q": lambda th, z: th.contact_area(1e5, q=np.real(z) / 1e5 * 1e6 + 1j),
    "apparent_area zeta": lambda th, z: th.apparent_area(z, 1e5),
    "mean_separation p": lambda th, z: th.mean_separation(1.0, z),
    "edge_separation p": lambda th, z: th.edge_separation(2.0, z),
    "critical_gap": lambda th, z: th.critical_gap(z),
    "critical_gap threshold": lambda th, z: th.critical_gap(1e5, threshold=0.42 + 0j),
    "exponential_valid_range": lambda th, z: th.exponential_valid_range(rtol=0.05 + 0j),
}


@pytest.mark.parametrize("call", list(_COMPLEX_CALLS))
@pytest.mark.parametrize("z", _COMPLEX, ids=["array", "list", "np-scalar", "scalar"])
def test_methods_reject_complex(call, z):
    """Complex input is a TypeError naming the parameter (numpy would silently keep the real
    part), whatever its imaginary part, even 0."""
    th = _theory("surface1")
    with pytest.raises(TypeError, match=r"\b(p|u|q|zeta|threshold|rtol) must be real"):
        _COMPLEX_CALLS[call](th, z)


# ------------------------------------------------------------------------------------------------
# quintic Hermite kernel
# ------------------------------------------------------------------------------------------------
@pytest.mark.parametrize("seed", range(5))
def test_quintic_reproduces_quintics(seed):
    rng = np.random.default_rng(seed)
    c = rng.normal(size=6)  # f(x) = sum c_k (x - xa)^k
    xa, h = rng.uniform(-3, 3), rng.uniform(0.05, 2.0)
    f = np.polynomial.Polynomial(c)
    df, d2f = f.deriv(1), f.deriv(2)
    ends = (f(0.0), df(0.0), d2f(0.0), f(h), df(h), d2f(h))
    for t in np.linspace(0.0, 1.0, 11):
        val, der = _quintic(float(t), h, *(float(e) for e in ends))
        scale = np.sum(np.abs(c) * np.maximum(h, 1.0) ** np.arange(6))
        assert abs(val - f(t * h)) <= RTOL_EXACT * scale * 10
        assert abs(der - df(t * h)) <= RTOL_EXACT * scale * 10 / min(h, 1.0)
    del xa


def test_interface_arrays_of_one_value_raise_no_numpy_warning():
    """A one-element zeta with a scalar p (a broadcast view) reaches the compiled kernels
    without NumPy's warning about writing to broadcast arrays."""
    theory = PerssonTheory(SelfAffinePSD(1e-6, 0.8, 1e3, 1e4, 1e9), 1.33e9)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        u = theory.mean_separation(np.array([2.0]), 1e6)
        assert u.shape == (1,) and np.isfinite(u).all()
        assert theory.mean_separation(np.array([]), 1e6).shape == (0,)
