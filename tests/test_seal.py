"""Tests of the molecular floor of the gap, the effective-medium leak rate and the seal under
pressure (fluid pressure in the interface coupled to a line contact).

Effective medium: the closed forms of a two-phase medium (a gap and contact: Bruggeman's
``s_eff = s (1 - c / a_c)``), a single gap gives Poiseuille flow, a narrow spread the mean
conductivity, the theory's distribution between the Wiener bounds (harmonic and arithmetic
means), sealing exactly at the threshold, the table against the direct quadrature, and a
uniform strip against the rectangle formula. Coupled seal: the limits (dP -> 0 and a rigid body
give the uncoupled strips in series), force balance and mass conservation to solver tolerance,
Q monotone in dP, lift-off monotone in load, bad input. Small grids (n = 64) on the O-ring
interface of docs/leakage.md.
"""

from __future__ import annotations

import math
import warnings

import numpy as np
import pytest

import fastline as fl
from fastline.cli.app import main
from fastline.leakage import medium, seal

#: closed forms of the effective-medium equation: the bisection's resolution
BISECT = 1e-12
#: the table of u_eff against the direct quadrature (spline step 0.25 in z)
TABLE = 2e-3
#: the coupled solve's own residual targets (force balance, face fluxes against Q)
SOLVER = 1e-8
#: a rigid body against the uncoupled leak rate (faces against cells: the two end half-cells)
RIGID = 1e-6

E_STAR = fl.effective_modulus(10e6, 0.5, 210e9, 0.3)
PSD = fl.SelfAffinePSD(0.3e-6, 0.85, q0=5e4, qr=5e5, q1=1e9)
RADIUS, ETA, LENGTH, N = 1.5e-3, 1e-3, 0.0785, 64


@pytest.fixture(scope="module")
def theory():
    return fl.PerssonTheory(PSD, E_STAR)


@pytest.fixture(scope="module")
def contact(theory):
    return fl.solve_line_contact(PSD, E_STAR, RADIUS, 300.0, n=N, theory=theory, warn=False)


# ---------------------------------------------------------------------------------------------
# the molecular floor
# ---------------------------------------------------------------------------------------------
def test_gap_floor_seals_below_and_only_below(theory):
    r = fl.solve_line_contact(PSD, E_STAR, RADIUS, 1500.0, n=N, theory=theory, warn=False)
    free = fl.leak_rate(r, 1e4, ETA, LENGTH, gap_floor=0.0, warn=False)
    assert not free.sealed and free.Q > 0.0 and free.sealed_by is None
    smallest = float(np.min(free.u_c))
    above = fl.leak_rate(r, 1e4, ETA, LENGTH, gap_floor=2.0 * smallest, warn=False)
    assert above.sealed and above.sealed_by == "gap floor" and above.Q == 0.0
    np.testing.assert_array_equal(above.sealed_strips, free.u_c < 2.0 * smallest)
    below = fl.leak_rate(r, 1e4, ETA, LENGTH, gap_floor=0.5 * smallest, warn=False)
    assert not below.sealed and below.Q == free.Q


def test_percolation_named_first(theory):
    r = fl.solve_line_contact(PSD, E_STAR, RADIUS, 6000.0, n=N, theory=theory, warn=False)
    leak = fl.leak_rate(r, 1e4, ETA, LENGTH, warn=False)
    assert leak.sealed_by == "percolation" and leak.Q == 0.0
    assert "(percolation)" in repr(leak)


def test_cli_names_the_floor(capsys):
    argv = ["leak", "--h-rms", 0.3e-6, "--hurst", 0.85, "--q0", 5e4, "--qr", 5e5, "--q1", 1e9]
    argv += ["--E-star", E_STAR, "--radius", RADIUS, "--load", 2000, "--n", N]
    argv += ["--pressure-drop", 1e4, "--viscosity", ETA, "--length", LENGTH]
    assert main([str(a) for a in argv]) == 0
    out = capsys.readouterr().out
    assert "leak rate Q      0 m^3/s (sealed)" in out and "below the molecular floor" in out


# ---------------------------------------------------------------------------------------------
# the effective medium
# ---------------------------------------------------------------------------------------------
@pytest.mark.parametrize("threshold", [0.5, 0.42])
@pytest.mark.parametrize("c", [0.0, 0.1, 0.3])
def test_two_phase_closed_form(c, threshold):
    u = 2e-6
    got = fl.effective_gap([u], contact_fraction=c, threshold=threshold)
    want = u * (1.0 - c / threshold) ** (1.0 / 3.0)  # s_eff = s (1 - c / a_c)
    assert got == pytest.approx(want, rel=BISECT)


def test_full_contact_and_threshold_seal():
    assert fl.effective_gap([1e-6], contact_fraction=1.0) == 0.0
    assert fl.effective_gap([1e-6], contact_fraction=0.5) == 0.0
    assert fl.effective_gap([1e-6], contact_fraction=0.499) > 0.0


def test_closed_and_infinite_gaps_without_numpy_warnings():
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # no "All-NaN slice" from the bracket
        assert fl.effective_gap([0.0, 0.0]) == 0.0  # a closed interface conducts nothing
        assert fl.effective_gap([math.inf]) == math.inf
        # infinite gaps on f < 1 - a_c of the area: s_eff = s / (1 - f (1 + k)), k = 1
        u, f = 1e-6, 0.3
        got = fl.effective_gap([math.inf, u], [f, 1.0 - f])
        assert got == pytest.approx(u * (1.0 / (1.0 - 2.0 * f)) ** (1.0 / 3.0), rel=BISECT)
        assert fl.effective_gap([math.inf, u], [0.5, 0.5]) == math.inf  # at its threshold


def test_effective_gap_refuses_strings():
    with pytest.raises(TypeError, match="gaps must hold real numbers"):
        fl.effective_gap("x")


def test_narrow_spread_gives_the_mean_conductivity():
    eps = 1e-3
    u = 1e-6 * (1.0 + eps * np.array([-1.0, 1.0]))
    mean = float(np.mean(u**3)) ** (1.0 / 3.0)
    assert fl.effective_gap(u) == pytest.approx(mean, rel=10 * eps**2)


def test_theory_distribution_within_wiener_bounds(theory):
    p = np.array([1e4, 1e5, 1e6])
    log_s, w = medium._distribution(theory, p)
    s = np.exp(log_s)
    u_eff = medium.effective_gap_of(theory, p)
    area = theory.contact_area(p)
    arithmetic = np.sum(w * s, axis=1) ** (1.0 / 3.0)
    assert np.all(u_eff**3 <= arithmetic**3 * (1 + 1e-9))
    assert np.all(u_eff > 0.0) and np.all(area < 0.5)
    # contact dilutes: the effective conductivity is below the open area's mean
    open_mean = (np.sum(w * s, axis=1) / (1.0 - area)) ** (1.0 / 3.0)
    assert np.all(u_eff < open_mean)


def test_table_against_direct_quadrature(theory):
    root = math.sqrt(float(PSD.cumulative(PSD.q1)))  # 1 / w(q1)
    p_seal = theory.E_star * 0.4769362762044699 * root  # erf(w(q1) p / E*) = 1/2
    p = p_seal * np.array([1e-4, 1e-2, 0.3, 0.9, 0.99, 1.01])
    x1 = p / (root * theory.E_star)
    log_u, sealed = medium.medium_table(theory, 0.5).log_gap(x1)
    direct = medium.effective_gap_of(theory, p)
    np.testing.assert_array_equal(sealed, [False] * 5 + [True])
    np.testing.assert_allclose(np.exp(log_u[:5]), direct[:5], rtol=TABLE)
    assert direct[5] == 0.0


def test_uniform_strip_is_the_rectangle_formula(theory):
    x = np.linspace(0.0, 1e-3, 50)
    p = np.full(x.size, 2e5)
    leak = fl.leak_rate_profile(x, p, theory, 1e4, ETA, LENGTH, method="effective_medium")
    u = medium.effective_gap_of(theory, [2e5])[0]
    width = x[-1] - x[0] + (x[1] - x[0])
    assert leak.threshold == 0.5 and leak.method == "effective-medium"
    assert leak.Q == pytest.approx(LENGTH / width * u**3 / (12 * ETA) * 1e4, rel=TABLE)


# ---------------------------------------------------------------------------------------------
# the seal under pressure
# ---------------------------------------------------------------------------------------------
@pytest.fixture(scope="module")
def swept(contact, theory):
    return fl.seal_leak(contact, [1e1, 1e4, 1e5, 3e5, 2e6], ETA, LENGTH, theory=theory)


def test_small_pressure_drop_is_the_uncoupled_leak(swept, contact):
    first = swept.results[0]
    dry = fl.leak_rate(contact, 1e1, ETA, LENGTH, warn=False)
    assert first.converged and first.Q == pytest.approx(dry.Q, rel=10 * 1e1 / contact.p0)


def test_rigid_body_is_the_uncoupled_leak(contact, theory):
    s = fl.seal_leak(contact, [1e4, 1e6], ETA, LENGTH, theory=theory, rigid=True)
    np.testing.assert_allclose(s.Q, s.uncoupled_Q, rtol=RIGID)
    assert s.lift_off_pressure is None


def test_force_balance_and_mass_conservation(swept):
    for r in swept.results[:-1]:  # the last is beyond lift-off
        assert r.converged
        assert r.diagnostics["force_error"] < SOLVER and r.diagnostics["mass_error"] < SOLVER
        assert r.fluid_pressure[0] == pytest.approx(r.pressure_drop, rel=SOLVER)
        assert abs(r.fluid_pressure[-1]) < SOLVER * r.pressure_drop
        assert np.all(r.contact_pressure >= 0.0)


def test_q_grows_with_pressure_and_the_seal_lifts_off(swept):
    q = swept.Q[:-1]
    assert np.all(np.diff(q) > 0.0) and np.all(np.isfinite(q))
    assert q[-1] > 1.5 * swept.uncoupled_Q[-2]  # the fluid opens the interface
    lift = swept.lift_off_pressure
    assert lift is not None and 3e5 < lift < 2e6
    assert [r.lifted_off for r in swept.results] == [False] * 4 + [True]
    assert swept.Q[-1] == math.inf and not swept.results[-1].converged


def test_lift_off_grows_with_load(theory, swept):
    r = fl.solve_line_contact(PSD, E_STAR, RADIUS, 600.0, n=N, theory=theory, warn=False)
    s = fl.seal_leak(r, [1e4, 4e6], ETA, LENGTH, theory=theory)
    assert s.lift_off_pressure > swept.lift_off_pressure


@pytest.mark.parametrize(
    "kwargs, name",
    [
        ({"pressure_drops": [0.0]}, "pressure_drops"),
        ({"pressure_drops": [-1e4]}, "pressure_drops"),
        ({"pressure_drops": [math.nan]}, "pressure_drops"),
        ({"viscosity": 0.0}, "viscosity"),
        ({"support": "wall"}, "support"),
    ],
)
def test_bad_input(contact, theory, kwargs, name):
    args = {"pressure_drops": [1e4], "viscosity": ETA} | kwargs
    with pytest.raises(ValueError, match=name):
        fl.seal_leak(contact, args["pressure_drops"], args["viscosity"], LENGTH, theory=theory,
                     **{k: v for k, v in kwargs.items() if k == "support"})  # fmt: skip


def test_bad_types_name_the_parameter(contact, theory):
    with pytest.raises(TypeError, match="pressure_drops must hold real numbers"):
        fl.seal_leak(contact, "x", ETA, LENGTH, theory=theory)
    with pytest.raises(TypeError, match="rigid must be True or False"):
        fl.seal_leak(contact, [1e4], ETA, LENGTH, theory=theory, rigid="x")


def test_pressure_drop_bounded_by_the_modulus(contact, theory):
    top = seal.MAX_DROP * contact.E_star
    for bad in ([1.001 * top], [1e4, 1e300]):
        with pytest.raises(ValueError, match=r"pressure_drops must lie in \(0, .*E\*"):
            fl.seal_leak(contact, bad, ETA, LENGTH, theory=theory)
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # no overflow at the bound, held or rigid
        s = fl.seal_leak(contact, [top], ETA, LENGTH, theory=theory)
        assert s.results[0].lifted_off and s.lift_off_pressure < contact.pressure.max()
        rigid = fl.seal_leak(contact, [1e4, top], ETA, LENGTH, theory=theory, rigid=True)
    assert np.all(np.isfinite(rigid.Q)) and rigid.Q[1] > rigid.Q[0] > 0.0


def test_inner_radius_is_refused(contact, theory):
    with pytest.raises(ValueError, match="inner_radius is for a point contact"):
        fl.seal_leak(contact, [1e4], ETA, inner_radius=1e-5, theory=theory)


def test_cli_coupled(capsys, tmp_path):
    argv = ["leak", "--h-rms", 0.3e-6, "--hurst", 0.85, "--q0", 5e4, "--qr", 5e5, "--q1", 1e9]
    argv += ["--E-star", E_STAR, "--radius", RADIUS, "--load", 300, "--n", N]
    argv += ["--viscosity", ETA, "--length", LENGTH, "--coupled", "--pressure-drop", 1e4, 2e6]
    assert main([str(a) for a in argv + ["--plot", tmp_path / "seal.png"]]) == 0
    out = capsys.readouterr().out
    assert "lift-off         dP = " in out and "lifted off" in out and "nan" not in out
    assert (tmp_path / "seal.png").read_bytes()[:4] == b"\x89PNG"
    assert main([str(a) for a in argv if a != "--coupled"]) == 2  # several dP need it


def test_cli_coupled_refuses_a_pressure_drop_beyond_the_bound(capsys):
    argv = ["leak", "--h-rms", 0.3e-6, "--hurst", 0.85, "--q0", 5e4, "--qr", 5e5, "--q1", 1e9]
    argv += ["--E-star", E_STAR, "--radius", RADIUS, "--load", 300, "--n", N, "--viscosity", ETA]
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # no overflow on the way
        assert main([str(a) for a in argv + ["--coupled", "--pressure-drop", 1e300]]) == 2
    err = capsys.readouterr().err
    assert "--pressure-drop must lie in" in err and "warning" not in err
