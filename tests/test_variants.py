"""Variants of the Persson u(p) (fastline.theory.variants): the printed bracket and Wang & Mueser's
correction, which also enters the contact-area recursion.

References: ``naive.separation`` with each variant's own universal function (``naive.universal_F``
with the printed bracket; ``naive.area_functions``, an ODE solve of the area recursion in the
variable y, for Wang-Mueser), ``naive.area_recursion`` (the recursion solved in q, not in the
universal variable) and ``naive.separation_from_energy`` (u(p) from the elastic energy by
integration by parts: checks the reduction of the recursion to one universal function).
"""

from __future__ import annotations

import functools
import math

import naive
import numpy as np
import pytest
from scipy.integrate import quad
from scipy.special import erf

import fastline as fl
from fastline.theory.persson import PerssonTheory
from fastline.theory.special import universal_F
from fastline.theory.variants import VARIANTS, get_variant

RTOL_REF = 1e-6  # u(p) against the quad reference
RTOL_UNIVERSAL = 1e-10  # F and Y of the area variant against the ODE reference
RTOL_RECURSION = 1e-10  # contact area against the recursion solved in q
RTOL_ENERGY = 1e-7  # u(p) against the energy route (nested quad of ODE solves)
RTOL_SHIFT = 1e-4  # small-p shift between the two brackets, in units of u0
RTOL_FIT_LAW = 1e-4  # u(p) against the variant's exponential law at p = 1e-9 E*
RTOL_ROUNDTRIP = 1e-6  # pressure(separation(p)) against p
RTOL_HERTZ_LIKE = 1e-2  # p0 of two variants at alpha = 1e-2 (the shift of u absorbed)
MIN_VARIANT_EFFECT = 0.03  # least change of p0 by a variant at alpha = 1 (expected: several %)
E_STAR = 1.33e9
E_PAPERLIKE = 1e7  # Pa, the narrow-band validation surface (docs/validation.md)
N_PRESSURES = 5

SURFACES = {
    "surface1": lambda: fl.SelfAffinePSD(10e-6, 0.8, 1e3, 1e4, 1e9),
    "paper-like": lambda: fl.SelfAffinePSD(0.5e-6, 0.8, 1e4, 1e4, 3.2e5),
    "band8": lambda: fl.SelfAffinePSD(0.5e-6, 0.8, 1e4, 1e4, 8e4),
}
E_OF = {"surface1": E_STAR, "paper-like": E_PAPERLIKE, "band8": E_PAPERLIKE}
WM = VARIANTS["wang-mueser"]


@functools.cache
def _psd(name):
    return SURFACES[name]()


@functools.cache
def _theory(name, variant, gamma=None):
    return PerssonTheory(_psd(name), E_OF[name], gamma=gamma, variant=variant)


def _x1_pressures(name, lo=1e-4, hi=3.0, n=N_PRESSURES):
    """Pressures with w(q1) p / E* from lo to hi (small contact to nearly full contact)."""
    psd = _psd(name)
    w1 = 1.0 / math.sqrt(float(psd.cumulative(psd.q1)))
    return np.geomspace(lo, hi, n) * E_OF[name] / w1


def _reference_F(variant, gamma):
    var = get_variant(variant)
    if var.area_correction:
        corr = var.correction(gamma)
        return lambda x0: naive.area_functions(x0, *corr)[1]
    b2 = var.bracket(gamma)[1]
    return lambda x0: naive.universal_F(x0, gamma, b2)


# ------------------------------------------------------------------------------------------------
# the default is fastline 0.1's theory
# ------------------------------------------------------------------------------------------------
def test_default_variant_is_the_energy_bracket():
    psd = _psd("surface1")
    a = PerssonTheory(psd, E_STAR)
    b = PerssonTheory(psd, E_STAR, gamma=0.45, variant="yang-persson-energy")
    assert a.variant == "yang-persson-energy" and a.gamma == 0.45
    for x, y in zip((*a._t1[2:5], a._t2[0]), (*b._t1[2:5], b._t2[0]), strict=True):
        np.testing.assert_array_equal(x, y)
    assert "variant" not in repr(a)
    assert "wang-mueser" in repr(_theory("surface1", "wang-mueser"))


def test_gamma_defaults_per_variant():
    assert _theory("surface1", "yang-persson-printed").gamma == 0.45
    assert _theory("surface1", "wang-mueser").gamma == pytest.approx(5.0 / 9.0, rel=1e-15)
    assert _theory("surface1", "wang-mueser", 0.5).gamma == 0.5
    for name in ("yang-persson-energy", "wang-mueser"):  # S(1) = 1: full contact stores U_full
        v = VARIANTS[name]
        assert sum(v.correction(v.default_gamma)) == pytest.approx(1.0, rel=1e-15)
    # the printed bracket is d/dP [P S] of S = gamma + (1 - gamma) P^2 / 3: S(1) = (1 + 2 gamma)/3
    s = VARIANTS["yang-persson-printed"].correction(0.45)
    assert sum(s) == pytest.approx((1.0 + 2.0 * 0.45) / 3.0, rel=1e-15)


# ------------------------------------------------------------------------------------------------
# u(p) against each variant's own quad reference
# ------------------------------------------------------------------------------------------------
@pytest.mark.slow
@pytest.mark.parametrize("variant", ["yang-persson-printed", "wang-mueser"])
@pytest.mark.parametrize("name", ["surface1", "paper-like", "band8"])
def test_separation_vs_reference(name, variant):
    th = _theory(name, variant)
    F = _reference_F(variant, th.gamma)
    p = _x1_pressures(name)
    ref = np.array([naive.separation(_psd(name), E_OF[name], float(pi), F=F) for pi in p])
    np.testing.assert_allclose(th.separation(p), ref, rtol=RTOL_REF, atol=0.0)
    np.testing.assert_allclose(th.separation_table(p)[0], ref, rtol=RTOL_REF, atol=0.0)


@pytest.mark.parametrize("gamma", [5.0 / 9.0, 0.3])
def test_area_universal_functions_vs_ode(gamma):
    corr = WM.correction(gamma)
    x = np.concatenate([np.geomspace(1e-9, 20.0, 40), [2.0**-27, 0.5, 1.0, 6.0]])
    ref = np.array([naive.area_functions(float(xi), *corr) for xi in x])
    F = universal_F(x, gamma, variant="wang-mueser")
    np.testing.assert_allclose(F, ref[:, 1], rtol=RTOL_UNIVERSAL, atol=0.0)
    # the contact area erf(Y) through the theory: P(q1, p) at x = w(q1) p / E*
    th = _theory("band8", "wang-mueser", gamma)
    psd = _psd("band8")
    w1 = 1.0 / math.sqrt(float(psd.cumulative(psd.q1)))
    P = th.contact_area(x * E_PAPERLIKE / w1)
    np.testing.assert_allclose(P, erf(ref[:, 0]), rtol=RTOL_UNIVERSAL, atol=0.0)


def test_area_recursion_in_q():
    """P(q1, p) of the theory = the recursion dA/dq = S(P) pi q^3 C solved as an ODE in q."""
    th = _theory("paper-like", "wang-mueser")
    c = WM.correction(th.gamma)
    for p in _x1_pressures("paper-like", 1e-3, 3.0, 4):
        P_ref, _ = naive.area_recursion(_psd("paper-like"), E_PAPERLIKE, p, *c)
        assert float(th.contact_area(p)) == pytest.approx(P_ref, rel=RTOL_RECURSION)
    # small p: the area is erf(x / sqrt(gamma)), larger than the plain theory's by 1/sqrt(gamma)
    p = _x1_pressures("paper-like", 1e-6, 1e-6, 1)[0]
    plain = _theory("paper-like", "yang-persson-energy").contact_area(p)
    assert float(th.contact_area(p) / plain) == pytest.approx(1.0 / math.sqrt(th.gamma), 1e-9)


@pytest.mark.slow
def test_separation_from_the_elastic_energy():
    """u(p) = int_p^inf dp'/p' dU/dp' with U from the recursion in q (no universal function)."""
    th = _theory("band8", "wang-mueser")
    c = WM.correction(th.gamma)
    for p in _x1_pressures("band8", 0.3, 1.5, 2):
        ref = naive.separation_from_energy(_psd("band8"), E_PAPERLIKE, float(p), *c)
        assert float(th.separation(p)) == pytest.approx(ref, rel=RTOL_ENERGY)


# ------------------------------------------------------------------------------------------------
# the variants against each other and against their exponential laws
# ------------------------------------------------------------------------------------------------
def _G0_quad():
    f = lambda x: erf(x) ** 2 * math.exp(-x * x) / x  # noqa: E731
    return sum(quad(f, a, b, epsabs=0.0, epsrel=1e-13)[0] for a, b in [(0, 1), (1, 6), (6, 30)])


@pytest.mark.parametrize("gamma", [0.45, 0.4])
def test_printed_bracket_shifts_u_at_small_p(gamma):
    """Same u0; at small p u differs by 2 (1 - gamma) G(0) / gamma u0 (docs/theory.md)."""
    energy = _theory("surface1", "yang-persson-energy", gamma)
    printed = _theory("surface1", "yang-persson-printed", gamma)
    u0 = energy.exponential_fit().u0
    assert printed.exponential_fit().u0 == u0
    shift = 2.0 * (1.0 - gamma) * _G0_quad() / gamma
    p = np.array([1e-10, 1e-9]) * E_STAR
    got = (energy.separation(p) - printed.separation(p)) / u0
    np.testing.assert_allclose(got, shift, rtol=0.0, atol=RTOL_SHIFT)
    # and the printed bracket gives a smaller u everywhere (its bracket is smaller)
    p = np.geomspace(1e-9, 1e-1, 30) * E_STAR
    assert np.all(printed.separation(p) < energy.separation(p))


@pytest.mark.parametrize("variant", list(VARIANTS))
def test_exponential_law_is_the_small_p_limit(variant):
    th = _theory("surface1", variant)
    fit = th.exponential_fit()
    p = 1e-9 * E_STAR
    u = float(th.separation(p))
    assert abs(u - fit.u0 * math.log(fit.beta * E_STAR / p)) <= RTOL_FIT_LAW * u
    d = 1e-3  # slope -du/dln p by central differences
    up, um = th.separation(np.array([p * math.exp(d), p * math.exp(-d)]))
    assert -(up - um) / (2.0 * d) == pytest.approx(fit.u0, rel=1e-3)


def test_wang_mueser_u0_is_sqrt_gamma():
    """u0 = sqrt(gamma) int q^2 C w against gamma int q^2 C w of the bracket-only variants."""
    wm = _theory("surface1", "wang-mueser")
    plain = _theory("surface1", "yang-persson-energy", wm.gamma)
    ratio = wm.exponential_fit().u0 / plain.exponential_fit().u0
    assert ratio == pytest.approx(1.0 / math.sqrt(wm.gamma), rel=RTOL_REF)  # different q rules


@pytest.mark.parametrize("variant", list(VARIANTS))
def test_tables_invert_and_decrease(variant):
    th = _theory("paper-like", variant)
    p = _x1_pressures("paper-like", 1e-8, 4.0, 300)
    u = th.separation(p)
    assert np.all(np.diff(u) < 0.0) and np.all(u > 0.0)
    np.testing.assert_allclose(th.pressure(u), p, rtol=RTOL_ROUNDTRIP)
    _, dudv = th.separation_table(p)
    assert np.all(dudv < 0.0)


# ------------------------------------------------------------------------------------------------
# solvers and leakage with a variant
# ------------------------------------------------------------------------------------------------
def test_line_contact_with_a_variant_theory():
    psd = _psd("paper-like")
    th = _theory("paper-like", "wang-mueser")
    lc = fl.LineContact(psd, E_PAPERLIKE, 32.8e-3, theory=th, n=256)
    r = lc.solve(50.0)
    assert r.converged and r.force_error < 1e-8
    # the law's own u(p) holds on the solution
    np.testing.assert_allclose(r.real_area, th.contact_area(r.pressure), rtol=1e-12)


@pytest.mark.parametrize("geometry", ["line", "point"])
def test_contact_models_take_a_variant(geometry):
    """``variant=`` on the models is ``theory=PerssonTheory(..., variant=...)``, bit for bit;
    None is the default variant; gamma defaults to the variant's own; one shared theory per
    (spectrum, E*, gamma, variant)."""
    psd = fl.SelfAffinePSD(10e-6, 0.8, 1e3, 1e4, 1e9)  # a fresh object: an empty theory cache
    Model, n, load = (fl.LineContact, 96, 1e4) if geometry == "line" else (fl.PointContact, 64, 50)
    default = Model(psd, E_STAR, 0.01, n=n, variant=None)
    assert default.theory.variant == "yang-persson-energy" and default.theory.gamma == 0.45
    for name in VARIANTS:
        model = Model(psd, E_STAR, 0.01, n=n, variant=name)
        assert model.theory.variant == name
        assert model.theory.gamma == VARIANTS[name].default_gamma
        assert Model(psd, E_STAR, 0.01, n=n, variant=name).theory is model.theory  # shared
        ref = Model(psd, E_STAR, 0.01, n=n, theory=PerssonTheory(psd, E_STAR, variant=name))
        a, b = model.solve(load), ref.solve(load)
        assert np.array_equal(a.pressure, b.pressure) and a.p0 == b.p0
    assert len({id(Model(psd, E_STAR, 0.01, variant=v).theory) for v in VARIANTS}) == 3
    hertz = Model(None, E_STAR, 0.01, n=n, model="hertz", variant="wang-mueser")
    assert hertz.theory is None  # the variant of a theory: nothing to apply


def test_variants_move_the_line_contact_where_they_should():
    """At alpha = 1e-2 (Hertz-like) the variants agree: their u(p) differ by a near-constant
    shift, which the rigid approach absorbs; at alpha = 1 the printed bracket raises p0 and the
    Wang-Mueser correction lowers it by several per cent (docs/theory.md, Variants)."""
    psd = fl.SelfAffinePSD(10e-6, 0.8, 1e3, 1e4, 1e9)

    def p0(variant, alpha):
        load = fl.paper.load_for_alpha(alpha, psd.h_rms)
        return fl.solve_line_contact(psd, E_STAR, 0.01, load, n=96, variant=variant).p0

    for alpha in (1e-2, 1.0):
        ref = p0(None, alpha)
        printed, wm = p0("yang-persson-printed", alpha) / ref, p0("wang-mueser", alpha) / ref
        if alpha < 0.1:
            assert abs(printed - 1.0) < RTOL_HERTZ_LIKE and abs(wm - 1.0) < RTOL_HERTZ_LIKE
        else:
            assert printed > 1.0 + MIN_VARIANT_EFFECT and wm < 1.0 - MIN_VARIANT_EFFECT


def test_leakage_printed_bracket_vs_quad():
    th = _theory("paper-like", "yang-persson-printed")
    psd, zeta, p = th.psd, 4.0, 2e4
    b2 = 1.0 - th.gamma
    ref = naive.mean_separation(psd, E_PAPERLIKE, zeta, p, th.gamma, b2=b2)
    assert float(th.mean_separation(zeta, p)) == pytest.approx(ref, rel=RTOL_REF)
    ref = naive.edge_separation(psd, E_PAPERLIKE, zeta, p, th.gamma, b2=b2)
    assert float(th.edge_separation(zeta, p)) == pytest.approx(ref, rel=RTOL_REF)


def test_leakage_rejects_the_area_variant():
    th = _theory("paper-like", "wang-mueser")
    with pytest.raises(ValueError, match="wang-mueser"):
        th.critical_gap(1e4)


# ------------------------------------------------------------------------------------------------
# bad input
# ------------------------------------------------------------------------------------------------
@pytest.mark.parametrize("variant", ["persson", "", None, 3, "Wang-Mueser"])
def test_rejects_unknown_variant(variant):
    with pytest.raises(ValueError, match=r"^variant must be one of"):
        PerssonTheory(_psd("band8"), E_PAPERLIKE, variant=variant)
    with pytest.raises(ValueError, match=r"^variant"):
        universal_F(1.0, variant=variant)


@pytest.mark.parametrize("solve", [fl.solve_line_contact, fl.solve_point_contact])
@pytest.mark.parametrize("variant", ["persson", "", 3, "Wang-Mueser"])
def test_contact_models_reject_unknown_variant(solve, variant):
    psd = _psd("surface1")
    with pytest.raises(ValueError, match=r"^variant must be one of \('yang-persson-energy'"):
        solve(psd, E_STAR, 0.01, 10.0, variant=variant, n=64)


def test_contact_models_reject_a_variant_unlike_their_theory():
    th = _theory("surface1", "wang-mueser")
    for Model in (fl.LineContact, fl.PointContact):
        with pytest.raises(ValueError, match=r"^variant='yang-persson-printed' differs"):
            Model(th.psd, E_STAR, 0.01, theory=th, variant="yang-persson-printed")
        assert Model(th.psd, E_STAR, 0.01, theory=th, variant="wang-mueser").theory is th


@pytest.mark.parametrize("gamma", [0.0, 0.01, 1.5, math.nan])
def test_rejects_gamma_out_of_range(gamma):
    with pytest.raises(ValueError, match=r"^gamma"):
        PerssonTheory(_psd("band8"), E_PAPERLIKE, gamma=gamma, variant="wang-mueser")
