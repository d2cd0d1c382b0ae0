"""Pressure laws: the protocol, the shipped laws and user laws inside the solver."""

from __future__ import annotations

import numpy as np
import pytest

import fastline as fl
from fastline.theory.laws import check_law

# tiered tolerances
RTOL_EXACT = 1e-13  # a law against its own inverse, identical arithmetic
# PerssonLaw reads table T1 in Horner form, separation_table its Hermite data: the same
# polynomials, apart by round-off (measured <= 1.3e-12; near full contact |d ln u/dv| ~ 300
# turns one ulp of the cell coordinate into ~1e-12 of u)
RTOL_SOLVER_FORM = 1e-11
RTOL_ROUND_TRIP = 1e-10  # a law reading the table through exp(ln p) vs the table itself
RTOL_INVERSE = 1e-12  # TabulatedLaw: pressure(separation(v)) vs p
# TabulatedLaw from 20 points per decade of the Persson curve vs the theory (third order in the
# spacing: 5/10/20/40 points per decade measured 1.3e-3/1.6e-4/2.0e-5/2.5e-6 in |du|/u0)
ATOL_TABLE_LAW = 4e-5  # max |du| / u0 over the whole table (the solver's unit)
RTOL_TABLE_LAW = 3e-4  # relative in u below p = 0.1 E* (near full contact u falls by decades)
RTOL_TABLE_SOLVE = 1e-4  # p0 ratio and w/s solved with that TabulatedLaw vs the Persson law

E_STAR, RADIUS = 1.33e9, 0.01
PSD = fl.paper.surfaces()[0]


@pytest.fixture(scope="module")
def theory():
    return fl.PerssonTheory(PSD, E_STAR)


def load_for(alpha):
    return fl.paper.load_for_alpha(alpha, PSD.h_rms, E_STAR)


def persson_curve(theory, per_decade=20):
    p = np.logspace(-1, 9.5, int(10.5 * per_decade) + 1)
    return theory.separation(p), p


# ---- the shipped laws -----------------------------------------------------------------------
def test_persson_law_is_the_theory(theory):
    law = fl.PerssonLaw(theory)
    p = np.logspace(2, 9, 30)
    u, dudv = law.separation_and_slope(np.log(p))
    u_ref, d_ref = theory.separation_table(p)
    assert np.allclose(u, u_ref, rtol=RTOL_SOLVER_FORM, atol=0)
    assert np.allclose(dudv, d_ref, rtol=RTOL_SOLVER_FORM, atol=0)
    assert np.allclose(law.pressure(u), theory.pressure(u), rtol=RTOL_EXACT, atol=0)
    assert np.allclose(np.exp(law.log_pressure(u)), law.pressure(u), rtol=RTOL_EXACT)
    assert law.u0 == theory.exponential_fit().u0
    assert np.array_equal(law.real_area(p), theory.contact_area(p))


def test_exponential_law_closed_form(theory):
    law = fl.ExponentialLaw.from_theory(theory)
    fit = theory.exponential_fit()
    u = np.array([0.0, fit.u0, 10 * fit.u0, -3 * fit.u0])
    assert np.allclose(law.pressure(u), fit.beta * E_STAR * np.exp(-u / fit.u0), rtol=RTOL_EXACT)
    v = np.log(np.array([1e3, 1e6]))
    uu, d = law.separation_and_slope(v)
    assert np.allclose(uu, fit.u0 * np.log(fit.beta * E_STAR / np.exp(v)), rtol=RTOL_EXACT)
    assert np.all(d == -fit.u0)
    # a huge negative u (deep inside the contact) does not overflow ln p
    assert np.isfinite(law.log_pressure(np.array([-1e3]))).all()


def test_tabulated_law_interpolates_monotonically(theory):
    u, p = persson_curve(theory)
    law = fl.TabulatedLaw(u, p)
    # through the points, exact inverse, monotone between the points
    assert np.allclose(law.separation_and_slope(np.log(p))[0], u, rtol=RTOL_EXACT, atol=0)
    v = np.linspace(np.log(p[0]) - 5, np.log(p[-1]) + 5, 4001)
    uu, d = law.separation_and_slope(v)
    assert np.all(d < 0.0) and np.all(np.diff(uu) < 0.0)
    assert np.allclose(law.log_pressure(uu), v, rtol=0, atol=RTOL_INVERSE * np.abs(v).max())
    # against the theory between the points (stated accuracy at 20 points per decade)
    inner = (v > np.log(p[0])) & (v < np.log(p[-1]))
    ref = theory.separation(np.exp(v[inner]))
    assert np.max(np.abs(uu[inner] - ref)) < ATOL_TABLE_LAW * law.u0
    low = np.exp(v[inner]) < 0.1 * E_STAR
    assert np.max(np.abs(uu[inner][low] / ref[low] - 1.0)) < RTOL_TABLE_LAW
    # exponential extensions with the end slopes
    lo, hi = np.log(p[0]), np.log(p[-1])
    assert law.separation_and_slope(np.array([lo - 1.0]))[0][0] == pytest.approx(
        u[0] + law.u0, rel=RTOL_EXACT
    )
    assert law.u0 > 0 and law.separation_and_slope(np.array([hi + 1.0]))[1][0] < 0


def test_laws_reject_complex(theory):
    """Each law's evaluations refuse complex input with a TypeError naming the argument."""
    u, p = persson_curve(theory, per_decade=5)
    laws = [
        fl.PerssonLaw(theory),
        fl.ExponentialLaw.from_theory(theory),
        fl.TabulatedLaw(u, p, real_area=theory.contact_area(p)),
    ]
    z = np.array([1e-6 + 1e-9j, 2e-6])
    for law in laws:
        for method, name in [
            (law.separation_and_slope, "v"),
            (law.log_pressure, "u"),
            (law.pressure, "u"),
            (law.real_area, "p"),
        ]:
            with pytest.raises(TypeError, match=rf"^{name} must be real"):
                method(z)
    with pytest.raises(TypeError, match="u0 must be real"):
        fl.ExponentialLaw(1e-6 + 0j, 1.0, 1e9)
    with pytest.raises(TypeError, match="^u must be real"):
        fl.TabulatedLaw(u + 0j, p)


def test_tabulated_law_any_order_and_area(theory):
    u, p = persson_curve(theory, per_decade=5)
    perm = np.random.default_rng(1).permutation(p.size)
    area = theory.contact_area(p)
    a = fl.TabulatedLaw(u, p, real_area=area)
    b = fl.TabulatedLaw(u[perm], p[perm], real_area=area[perm])
    v = np.log(np.logspace(0, 9, 50))
    assert np.array_equal(a.separation_and_slope(v)[0], b.separation_and_slope(v)[0])
    assert np.allclose(a.real_area(p), area, rtol=RTOL_EXACT)


@pytest.mark.parametrize(
    "u, p, match",
    [
        ([1e-6, 2e-6], [1e5, 1e4], "at least 3"),
        ([3e-6, 2e-6, 1e-6], [1e4, 1e5], "same length"),
        ([3e-6, 2e-6, 1e-6], [1e4, 0.0, 1e6], "p must be > 0"),
        ([3e-6, 2e-6, 2.5e-6], [1e4, 1e5, 1e6], "strictly decrease"),
        ([3e-6, 2e-6, 1e-6], [1e4, 1e4, 1e6], "repeated"),
        ([3e-6, np.nan, 1e-6], [1e4, 1e5, 1e6], "finite"),
    ],
)
def test_tabulated_law_bad_input(u, p, match):
    with pytest.raises(ValueError, match=match):
        fl.TabulatedLaw(u, p)


# ---- user laws in the solver ----------------------------------------------------------------
class TableOnlyLaw(fl.PressureLaw):
    """A user's law: only u0 and separation_and_slope, through the public theory methods."""

    name = "user"

    def __init__(self, theory):
        self.theory = theory
        self.u0 = theory.exponential_fit().u0

    def separation_and_slope(self, v):
        return self.theory.separation_table(np.exp(v))


@pytest.mark.parametrize("alpha", [0.01, 1.0])
def test_user_law_reproduces_persson(theory, alpha):
    ref = fl.solve_line_contact(PSD, E_STAR, RADIUS, load_for(alpha), theory=theory)
    mine = fl.solve_line_contact(PSD, E_STAR, RADIUS, load_for(alpha), model=TableOnlyLaw(theory))
    # the Newton solver only uses separation_and_slope, the same table up to an exp/log round
    # trip of ln p
    assert np.allclose(mine.pressure, ref.pressure, rtol=RTOL_ROUND_TRIP, atol=0)
    assert mine.model == "user" and mine.real_area is None
    # the base class inverts the law for pressure(u)
    u = ref.separation[::64]
    law = TableOnlyLaw(theory)
    assert np.allclose(law.pressure(u), theory.pressure(u), rtol=1e-7)


class DuckLaw:
    """A law by duck typing, with only what check_law asks for (no name, log_pressure or
    real_area, no base class)."""

    def __init__(self, theory):
        self._law = TableOnlyLaw(theory)
        self.u0 = self._law.u0

    def separation_and_slope(self, v):
        return self._law.separation_and_slope(v)

    def pressure(self, u):
        return self._law.pressure(u)


def test_duck_typed_law_solves_and_sweeps(theory):
    """It failed on the missing attributes (name, real_area; the cold start's log_pressure)."""
    lc = fl.LineContact(PSD, E_STAR, RADIUS, model=DuckLaw(theory), n=256, warn=False)
    ref = fl.LineContact(PSD, E_STAR, RADIUS, model=TableOnlyLaw(theory), n=256, warn=False)
    loads = [load_for(a) for a in (0.01, 0.012, 1.0)]
    mine, theirs = lc.sweep(loads), ref.sweep(loads)
    for a, b in zip(mine, theirs, strict=True):
        assert a.converged and a.model == "custom" and a.real_area is None
        assert np.allclose(a.pressure, b.pressure, rtol=RTOL_ROUND_TRIP, atol=0)
    assert "regime" in lc.solve(loads[0]).diagnostics


@pytest.mark.parametrize("alpha", [0.01, 1.0, 30.0])
def test_tabulated_law_reproduces_persson(theory, alpha):
    u, p = persson_curve(theory)
    ref = fl.solve_line_contact(PSD, E_STAR, RADIUS, load_for(alpha), theory=theory)
    tab = fl.solve_line_contact(PSD, E_STAR, RADIUS, load_for(alpha), model=fl.TabulatedLaw(u, p))
    assert tab.converged and tab.model == "tabulated"
    assert tab.p0_ratio == pytest.approx(ref.p0_ratio, rel=RTOL_TABLE_SOLVE)
    assert tab.w_over_s == pytest.approx(ref.w_over_s, rel=RTOL_TABLE_SOLVE)


def test_exponential_instance_equals_name(theory):
    f = load_for(3.0)
    a = fl.solve_line_contact(PSD, E_STAR, RADIUS, f, model="exponential", theory=theory)
    b = fl.solve_line_contact(PSD, E_STAR, RADIUS, f, model=fl.ExponentialLaw.from_theory(theory))
    assert np.array_equal(a.pressure, b.pressure)


class NoSlope:
    u0 = 1e-6


class Increasing:
    u0 = 1e-6

    def separation_and_slope(self, v):
        return 1e-6 * v, np.full_like(v, 1e-6)

    def pressure(self, u):
        return np.exp(u / 1e-6)


@pytest.mark.parametrize(
    "law, exc, match",
    [(NoSlope(), TypeError, "separation_and_slope"), (Increasing(), ValueError, "< 0")],
)
def test_bad_user_law(law, exc, match):
    with pytest.raises(exc, match=match):
        check_law(law)
    with pytest.raises(exc, match=match):
        fl.LineContact(PSD, E_STAR, RADIUS, model=law)


# ---- a user law that is not finite: the error or the message names it --------------------------
P_CUT = 5e8  # Pa: NaNAbove fails above it, beyond check_law's probes (1e2, 1e5, 1e8 Pa)
#: loads whose start iterate reaches P_CUT (Hertz p0 6.5e8 Pa on the line, 1.2e9 Pa on the
#: sphere) and loads whose solution stays below it
LOAD_ABOVE_CUT = {"line": 1e7, "point": 1e4}
LOAD_BELOW_CUT = {"line": 1e6, "point": 100.0}


class NaNAbove(fl.PressureLaw):
    """An exponential law (u linear in ln p, decay length u0) that returns ``bad`` (NaN or
    inf) above P_CUT: a user's law with a hole in its domain."""

    u0 = 4e-6

    def __init__(self, bad=np.nan):
        self.bad = bad

    def separation_and_slope(self, v):
        v = np.asarray(v, dtype=np.float64)
        ok = v < np.log(P_CUT)
        with np.errstate(invalid="ignore"):
            u = np.where(ok, self.u0 * (np.log(1e9) - v), self.bad)
            return u, np.where(ok, -self.u0, self.bad)


class FailsMidSolve(NaNAbove):
    """Finite at its first evaluation on the solver's ``n`` cells (the start), NaN at every
    later one: a law that breaks where the iteration goes."""

    def __init__(self, n):
        super().__init__()
        self.n, self.calls = n, 0

    def separation_and_slope(self, v):
        u, d = super().separation_and_slope(v)
        if np.size(v) == self.n:
            self.calls += 1
            if self.calls > 1:
                return np.full_like(u, np.nan), np.full_like(d, np.nan)
        return u, d


def _model(geometry, law, **kw):
    if geometry == "line":
        return fl.LineContact(PSD, E_STAR, RADIUS, model=law, n=64, warn=False, **kw)
    return fl.PointContact(PSD, E_STAR, RADIUS, model=law, n=32, warn=False, **kw)


@pytest.mark.parametrize("method", ["newton", "picard"])
@pytest.mark.parametrize("bad", [np.nan, np.inf])
@pytest.mark.parametrize("geometry", ["line", "point"])
def test_nonfinite_law_at_the_start_is_a_value_error(geometry, bad, method):
    """Before: a result with "residual nan" that did not say why."""
    model = _model(geometry, NaNAbove(bad), method=method)
    with pytest.raises(ValueError, match=r"^model: .*NaNAbove returned non-finite values"):
        model.solve(LOAD_ABOVE_CUT[geometry])
    if method == "newton":  # finite where the solution lies (Picard: see the test below)
        assert model.solve(LOAD_BELOW_CUT[geometry]).converged


@pytest.mark.parametrize("geometry", ["line", "point"])
def test_law_failing_mid_solve_is_named_in_the_message(geometry):
    n = 64 if geometry == "line" else 32
    res = _model(geometry, FailsMidSolve(n)).solve(LOAD_BELOW_CUT[geometry])
    assert not res.converged
    assert "line search failed: the pressure law FailsMidSolve returned non-finite" in res.message
    assert "FailsMidSolve" in res.diagnostics["law_fault"]


def test_fixed_point_stops_at_a_nonfinite_law():
    """Picard inverts the law (the base class's Newton on u(ln p)), which walks into the NaN
    above P_CUT on the sphere: it stops at once, naming the law (it used to run on NaN)."""
    res = _model("point", NaNAbove(), method="picard", max_iter=20).solve(LOAD_BELOW_CUT["point"])
    assert not res.converged and res.iterations < 20
    assert "the pressure law NaNAbove returned non-finite values" in res.message
