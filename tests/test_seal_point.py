"""Tests of the seal under pressure around a point contact (radial flow out of a hole) and of
the coupled Newton's compiled reduced system (both geometries).

Limits: dP -> 0 gives the uncoupled leak rate of the rings in series (`fl.leak_rate` with
``inner_radius``); a rigid body gives the closed form ``Q = 2 pi dP / (12 eta int dr / (r
g^3))`` at every dP; a uniform gap gives radial Poiseuille flow, ``Q = 2 pi g^3 dP / (12 eta
ln(r_o / r_h))`` and ``p_f = dP ln(r_o / r) / ln(r_o / r_h)``; force balance and mass
conservation hold to solver tolerance; Q grows with dP up to lift-off, lift-off grows with the
load; a calibrated law's hydraulic gap takes the critical gap's place. The compiled reduced
Newton step equals the dense Jacobian's solve. Small grids (n = 48) on the ball-on-seat scene
of docs/leakage.md.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

import fastline as fl
from fastline.cli.app import main
from fastline.leakage import seal, seal_kernels, seal_system
from fastline.theory.calibrated import CalibrationPoints

#: the coupled solve's own residual targets (force balance, link fluxes against Q)
SOLVER = 1e-8
#: the same discrete sums in another order (rigid body against leak_rate, Poiseuille)
ROUND_OFF = 1e-10
#: leak_rate's table of the critical gap against the direct critical gap (cubed)
GAP_TABLE = 1e-5
#: the reduced Newton step against the dense solve (conditioning of the full Jacobian)
STEP = 1e-6

E_STAR = fl.effective_modulus(10e6, 0.5, 210e9, 0.3)
PSD = fl.SelfAffinePSD(0.3e-6, 0.85, q0=5e4, qr=5e5, q1=1e9)
RADIUS, ETA, HOLE, N = 10e-3, 1e-3, 20e-6, 48
DROPS = [1e1, 1e4, 1e5, 3e5, 2e6]


@pytest.fixture(scope="module")
def theory():
    return fl.PerssonTheory(PSD, E_STAR)


@pytest.fixture(scope="module")
def ball(theory):
    return fl.solve_point_contact(PSD, E_STAR, RADIUS, 0.2, theory=theory, n=N, warn=False)


@pytest.fixture(scope="module")
def swept(ball, theory):
    return fl.seal_leak(ball, DROPS, ETA, inner_radius=HOLE, theory=theory)


def _rings_in_series(r, g, hole, dP):
    """Q of rings in series with the gap g piecewise constant on the cells (closed form)."""
    e = np.concatenate([[0.0], (np.arange(r.size) + 0.5) * (r[1] - r[0])])  # the ring edges
    lo, hi = np.maximum(e[:-1], hole), np.maximum(e[1:], hole)
    integral = np.sum(np.log(hi / lo) / g**3)  # int dr / (r g^3)
    return dP * 2.0 * math.pi / (12.0 * ETA * integral)


# ---------------------------------------------------------------------------------------------
# limits
# ---------------------------------------------------------------------------------------------
def test_small_pressure_drop_is_the_uncoupled_leak(swept, ball):
    first = swept.results[0]
    dry = fl.leak_rate(ball, DROPS[0], ETA, inner_radius=HOLE, warn=False)
    assert first.converged and first.Q == pytest.approx(dry.Q, rel=10 * DROPS[0] / ball.p0)
    assert swept.geometry == "point" and swept.inner_radius == HOLE


def test_rigid_body_is_the_closed_form_of_rings_in_series(ball, theory):
    s = fl.seal_leak(ball, [1e4, 1e6], ETA, inner_radius=HOLE, theory=theory, rigid=True)
    np.testing.assert_allclose(s.Q, s.uncoupled_Q, rtol=SOLVER)
    g = theory.critical_gap(ball.pressure).u_c
    want = [_rings_in_series(ball.r, g, HOLE, d) for d in (1e4, 1e6)]
    np.testing.assert_allclose(s.Q, want, rtol=GAP_TABLE)
    assert s.lift_off_pressure is None


def test_uniform_gap_is_radial_poiseuille(ball, theory):
    p = np.full(ball.r.size, 2e5)
    flat = dataclasses.replace(ball, pressure=p, separation=theory.separation(p))
    s = fl.seal_leak(flat, [1e4], ETA, inner_radius=HOLE, theory=theory, rigid=True)
    g = float(theory.critical_gap(2e5).u_c)
    r_o = (ball.r.size - 0.5) * ball.dr
    k = s.results[0]
    assert k.Q == pytest.approx(2 * math.pi * g**3 * 1e4 / (12 * ETA * math.log(r_o / HOLE)),
                                rel=GAP_TABLE)  # fmt: skip
    want = 1e4 * np.log(r_o / k.nodes) / math.log(r_o / HOLE)
    np.testing.assert_allclose(k.node_pressure, want, rtol=SOLVER, atol=SOLVER * 1e4)


def test_force_balance_and_mass_conservation(swept):
    for r in swept.results[:-1]:  # the last is beyond lift-off
        assert r.converged
        assert r.diagnostics["force_error"] < SOLVER and r.diagnostics["mass_error"] < SOLVER
        assert r.node_pressure[0] == pytest.approx(r.pressure_drop, rel=SOLVER)
        assert abs(r.node_pressure[-1]) < SOLVER * r.pressure_drop
        assert np.all(r.contact_pressure >= 0.0)
        assert r.fluid_pressure[0] == r.pressure_drop  # the hole is at dP


def test_q_grows_with_pressure_and_the_seal_lifts_off(swept):
    q = swept.Q[:-1]
    assert np.all(np.diff(q) > 0.0) and np.all(np.isfinite(q))
    assert q[-1] > 1.5 * swept.uncoupled_Q[-2]  # the fluid opens the interface
    lift = swept.lift_off_pressure
    assert lift is not None and 3e5 < lift < 2e6
    assert [r.lifted_off for r in swept.results] == [False] * 4 + [True]
    assert swept.Q[-1] == math.inf and not swept.results[-1].converged


def test_lift_off_grows_with_load(theory, swept):
    r = fl.solve_point_contact(PSD, E_STAR, RADIUS, 0.8, theory=theory, n=N, warn=False)
    s = fl.seal_leak(r, [1e4, 4e6], ETA, inner_radius=HOLE, theory=theory)
    assert s.lift_off_pressure > swept.lift_off_pressure


def test_calibrated_law_gap_takes_the_critical_gap_place(theory):
    p = np.geomspace(3e3, 3e6, 7)
    g = 0.7 * theory.critical_gap(p).u_c  # a hydraulic gap 0.7 of Persson's
    u, a = theory.separation(p), theory.contact_area(p)
    law = fl.CalibratedLaw(CalibrationPoints(p, u, 0.01 * u, a, 0 * p, g, 0.02 * g, g, 0.02 * g),
                           PSD, E_STAR)  # fmt: skip
    r = fl.solve_point_contact(PSD, E_STAR, RADIUS, 0.2, model=law, n=N, warn=False)
    s = fl.seal_leak(r, [1e1], ETA, inner_radius=HOLE, law=law)
    dry = fl.leak_rate(r, 1e1, ETA, inner_radius=HOLE, warn=False, law=law)
    assert s.Q[0] == pytest.approx(dry.Q, rel=10 * 1e1 / r.p0)
    persson = fl.leak_rate(r, 1e1, ETA, inner_radius=HOLE, theory=theory, warn=False)
    assert s.Q[0] < 0.5 * persson.Q  # the calibrated gap, not u_c: 0.7^3 = 0.34
    with pytest.raises(ValueError, match="model='calibrated'"):
        fl.seal_leak(fl.solve_point_contact(PSD, E_STAR, RADIUS, 0.2, n=N, warn=False), [1e4],
                     ETA, inner_radius=HOLE, law=law)  # fmt: skip


# ---------------------------------------------------------------------------------------------
# the compiled reduced Newton system
# ---------------------------------------------------------------------------------------------
def _perturbed_state(result, theory, hole, rigid):
    leak = fl.leak_rate(result, 1e5, ETA, None if hole else 0.1, inner_radius=hole,
                        theory=theory, warn=False)  # fmt: skip
    sys = seal._system(result, leak, theory, None, rigid, "edge")
    y, r0 = seal_system.start(sys, 1e5)
    rng = np.random.default_rng(7)
    y[: sys.n] *= 1.0 + 0.02 * rng.standard_normal(sys.n)
    y[sys.n : -2] *= 1.0 + 0.1 * rng.standard_normal(y.size - sys.n - 2)
    y[-2], y[-1] = 1e-3 * np.median(sys.u0), 1.3 * y[-1]
    return sys, y, r0


@pytest.mark.parametrize("rigid", [False, True])
@pytest.mark.parametrize("geometry", ["line", "point"])
def test_reduced_step_is_the_dense_newton_step(geometry, rigid, ball, theory):
    if geometry == "point":
        result, hole = ball, HOLE
    else:
        result = fl.solve_line_contact(PSD, E_STAR, 1.5e-3, 300.0, n=N, theory=theory,
                                       warn=False)  # fmt: skip
        hole = None
    sys, y, r0 = _perturbed_state(result, theory, hole, rigid)
    F, J = seal_system.equations(sys, y, 1e5, r0, jac=True)
    dense = np.linalg.solve(J, -F)
    vals = seal_system.inverse_cube(sys, y[: sys.n])
    step = seal_kernels.reduced_step(sys, y, vals, F, 1e5, r0)
    scale = np.abs(dense).max()
    np.testing.assert_allclose(step[: sys.n], dense[: sys.n], atol=STEP * np.abs(y[: sys.n]).max())
    np.testing.assert_allclose(step[sys.n :], dense[sys.n :], atol=STEP * scale)


def test_lu_solve_against_numpy():
    rng = np.random.default_rng(3)
    a = rng.standard_normal((40, 40)) + 40 * np.eye(40)
    a[[0, 5]] = a[[5, 0]]  # needs pivoting
    b = rng.standard_normal(40)
    z = b.copy()
    assert seal_kernels.lu_solve(a.copy(), z)
    np.testing.assert_allclose(z, np.linalg.solve(a, b), rtol=ROUND_OFF)
    assert not seal_kernels.lu_solve(np.zeros((3, 3)), np.ones(3))


def test_compiled_and_dense_sweeps_agree(ball, theory, swept):
    d = fl.seal_leak(ball, DROPS[1:3], ETA, inner_radius=HOLE, theory=theory, solver="dense")
    np.testing.assert_allclose(d.Q, swept.Q[1:3], rtol=SOLVER)


# ---------------------------------------------------------------------------------------------
# bad input
# ---------------------------------------------------------------------------------------------
def test_hole_larger_than_the_contact_is_refused(ball, theory):
    edge = seal_system.contact_radius(ball)
    with pytest.raises(ValueError, match="inner_radius must lie inside the contact"):
        fl.seal_leak(ball, [1e4], ETA, inner_radius=1.01 * edge, theory=theory)
    with pytest.raises(ValueError, match="inner_radius"):  # beyond the profile: leak_rate's
        fl.seal_leak(ball, [1e4], ETA, inner_radius=10 * ball.r[-1], theory=theory)
    with pytest.warns(fl.LeakageWarning, match="orifice_share"):  # inside, but wide: flagged
        s = fl.seal_leak(ball, [1e4], ETA, inner_radius=0.5 * edge, theory=theory)
    assert s.diagnostics["orifice_share"] > 0.1 and s.results[0].converged


@pytest.mark.parametrize(
    "kwargs, error, name",
    [
        ({}, ValueError, "inner_radius is required"),
        ({"inner_radius": HOLE, "length": 0.1}, ValueError, "length"),
        ({"inner_radius": HOLE, "support": "axis"}, ValueError, "support"),
        ({"inner_radius": HOLE, "viscosity": -1.0}, ValueError, "viscosity"),
        ({"inner_radius": HOLE, "pressure_drops": [0.0]}, ValueError, "pressure_drops"),
        ({"inner_radius": HOLE, "solver": "lapack"}, ValueError, "solver"),
    ],
)
def test_bad_input(ball, theory, kwargs, error, name):
    args = {"pressure_drops": [1e4], "viscosity": ETA} | kwargs
    with pytest.raises(error, match=name):
        fl.seal_leak(ball, args.pop("pressure_drops"), args.pop("viscosity"), theory=theory,
                     **args)  # fmt: skip


def test_not_a_contact_is_refused():
    with pytest.raises(TypeError, match="LineContactResult or a PointContactResult"):
        fl.seal_leak(object(), [1e4], ETA)


def test_cli_coupled_sphere(capsys, tmp_path):
    argv = ["leak", "--geometry", "sphere", "--h-rms", 0.3e-6, "--hurst", 0.85, "--q0", 5e4]
    argv += ["--qr", 5e5, "--q1", 1e9, "--E-star", E_STAR, "--radius", RADIUS, "--load", 0.2]
    argv += ["--n", N, "--viscosity", ETA, "--inner-radius", HOLE, "--coupled"]
    argv += ["--pressure-drop", 1e4, 2e6, "--plot", tmp_path / "ball.png"]
    assert main([str(a) for a in argv]) == 0
    out = capsys.readouterr().out
    assert "lift-off         dP = " in out and "lifted off" in out and "nan" not in out
    assert "orifice share" in out and "radial flow" in out
    assert (tmp_path / "ball.png").read_bytes()[:4] == b"\x89PNG"
    bad = [str(a) for a in argv[:-2]]
    bad[bad.index(str(HOLE))] = "7e-4"  # inside the profile, outside the contact
    assert main(bad) == 2
