"""The BEM contact solver: warm starts against cold solves, and the complementarity conditions
of every converged result (p >= 0, gap >= 0, p * gap = 0 to tolerance)."""

from __future__ import annotations

import math

import naive
import numpy as np
import pytest

import fastline as fl
from fastline import bem
from fastline.bem import contact as bem_contact
from fastline.bem import flow as bem_flow
from fastline.bem import pcg_flow
from fastline.bem._pcg import RESTARTS, pcg_solve

TOL = 1e-10  # solver tolerance (relative pressure change per iteration)
RTOL_WARM = 1e-6  # warm against cold pressure, relative to the peak pressure
RTOL_GAP = 1e-6  # complementarity residuals relative to the surface's peak-to-peak height

E_STAR = 1e7  # Pa
N = 64
DX = 1e-6  # m
Q0 = 2.0 * math.pi / (N * DX / 2.0)  # two wavelengths across the cell
PSD = fl.SelfAffinePSD(0.5e-6, 0.8, Q0, Q0, 2.0 * math.pi / (4.0 * DX))


@pytest.fixture(scope="module")
def flat():
    """A nominally flat rough contact: (grid, undeformed gap, nominal area)."""
    grid = bem.Grid(N, N, DX, DX)
    surf = bem.random_surface(PSD, grid, seed=7)
    return grid, -surf.heights, grid.lx * grid.ly


def check_complementarity(res, g0):
    """The complementarity conditions of a converged result, from its own fields."""
    scale = RTOL_GAP * np.ptp(g0)
    assert res.converged, res.message
    assert np.all(res.pressure >= 0.0)
    assert res.max_penetration <= scale and res.max_contact_gap <= scale
    assert np.all(res.gap >= 0.0) and np.all(res.pressure * res.gap == 0.0)


def check_same(warm, cold, g0):
    check_complementarity(warm, g0)
    check_complementarity(cold, g0)
    peak = cold.pressure.max()
    np.testing.assert_allclose(warm.pressure, cold.pressure, rtol=0.0, atol=RTOL_WARM * peak)
    assert warm.contact_fraction == pytest.approx(cold.contact_fraction, abs=2.0 / N**2)
    assert warm.load == pytest.approx(cold.load, rel=1e-12)


@pytest.mark.parametrize(
    "p_from, p_to",
    [(1e4, 1.5e4), (1.5e4, 1e4), (3e3, 1e5), (1e5, 3e3)],
    ids=["higher-load", "lower-load", "far-higher", "far-lower"],
)
def test_warm_start_equals_cold_solve(flat, p_from, p_to):
    """A converged solution at one nominal pressure [Pa] starts the solve at another; the
    contact set changes each time (cells enter at a higher load and leave at a lower one). A
    start at the optimum of its own contact set is the hard case: the conjugate-gradient step
    there is 0/0 and the penetrating cells must still enter with a positive pressure."""
    grid, g0, area = flat
    start = bem.solve_contact(g0, grid, E_STAR, p_from * area, tol=TOL)
    cold = bem.solve_contact(g0, grid, E_STAR, p_to * area, tol=TOL)
    warm = bem.solve_contact(g0, grid, E_STAR, p_to * area, tol=TOL, p_init=start.pressure)
    assert start.contact_fraction != pytest.approx(cold.contact_fraction, abs=2.0 / N**2)
    check_same(warm, cold, g0)


def test_warm_start_across_a_contact_set_change(flat):
    """The start's contact set is disjoint-ish from the answer's: the surface shifted by half a
    cell period, so every cell must leave or re-enter."""
    grid, g0, area = flat
    load = 3e4 * area
    other = bem.solve_contact(np.roll(g0, (N // 2, N // 3), axis=(0, 1)), grid, E_STAR, load)
    cold = bem.solve_contact(g0, grid, E_STAR, load, tol=TOL)
    warm = bem.solve_contact(g0, grid, E_STAR, load, tol=TOL, p_init=other.pressure)
    overlap = np.mean((other.pressure > 0) & (cold.pressure > 0)) / cold.contact_fraction
    assert overlap < 0.5
    check_same(warm, cold, g0)


def test_warm_sequence_stays_correct(flat):
    """Each step starts from the previous solution, up and then down in load."""
    grid, g0, area = flat
    p = None
    for nominal in [1e3, 1e4, 1e5, 3e5, 3e4, 3e3]:
        warm = bem.solve_contact(g0, grid, E_STAR, nominal * area, tol=TOL, p_init=p)
        cold = bem.solve_contact(g0, grid, E_STAR, nominal * area, tol=TOL)
        check_same(warm, cold, g0)
        p = warm.pressure


def test_warm_sequence_decreasing_and_jumping(flat):
    """Loads falling step by step, then jumping by up to 300x either way; each warm-started
    solve must equal the cold one (a wrong answer flagged converged fails here)."""
    grid, g0, area = flat
    p = None
    for nominal in [3e5, 2e5, 1e5, 5e4, 2e4, 1e3, 3e5, 2e3, 1e5]:
        warm = bem.solve_contact(g0, grid, E_STAR, nominal * area, tol=TOL, p_init=p)
        cold = bem.solve_contact(g0, grid, E_STAR, nominal * area, tol=TOL)
        check_same(warm, cold, g0)
        p = warm.pressure


@pytest.mark.parametrize("start", ["one-cell", "noise", "outside-contact"])
@pytest.mark.parametrize("nested", [True, False], ids=["nested", "flat"])
def test_warm_start_from_a_poor_start(flat, start, nested):
    """Starts far from any solution: the whole load on one cell, positive noise, and pressure
    only where the answer has none (the complement of the cold contact set)."""
    grid, g0, area = flat
    load = 2e4 * area
    cold = bem.solve_contact(g0, grid, E_STAR, load, tol=TOL)
    p = np.zeros(grid.shape)
    if start == "one-cell":
        p[3, 5] = 1.0
    elif start == "noise":
        p = np.random.default_rng(1).random(grid.shape)
    else:
        p[cold.pressure == 0.0] = 1.0
    warm = bem.solve_contact(g0, grid, E_STAR, load, tol=TOL, p_init=p, nested=nested)
    check_same(warm, cold, g0)


@pytest.mark.parametrize("restart", RESTARTS)
def test_restart_rules_give_one_answer(restart):
    """Each rule for restarting the conjugate directions (and the displacement carried over
    between iterations that change no contact cell) converges to Polonsky & Keer's pressure."""
    grid = bem.Grid(2 * N, 2 * N, DX / 2, DX / 2)
    g0 = -bem.random_surface(PSD, grid, seed=5).heights
    op = bem.ElasticHalfSpace(grid.nx, grid.ny, grid.dx, grid.dy, E_STAR)
    nominal = 3e4
    p = np.full(grid.nx * grid.ny, nominal)
    its, residual = pcg_solve(op, g0.ravel(), nominal * p.size, TOL, 5000, p, restart=restart)
    ccg = bem.solve_contact(g0, grid, E_STAR, nominal * grid.lx * grid.ly, tol=TOL, method="ccg")
    assert residual < TOL and its < 5000
    atol = RTOL_WARM * ccg.pressure.max()
    np.testing.assert_allclose(p.reshape(grid.shape), ccg.pressure, rtol=0.0, atol=atol)


def test_diagnostics_report_complementarity(flat):
    grid, g0, area = flat
    res = bem.solve_contact(g0, grid, E_STAR, 1e4 * area, tol=TOL)
    assert res.min_pressure == res.pressure.min() >= 0.0
    assert res.gap_tolerance == pytest.approx(math.sqrt(TOL) * np.ptp(g0), rel=1e-12)
    assert max(res.max_penetration, res.max_contact_gap) <= res.gap_tolerance


# ---- the preconditioned, nested solver against Polonsky & Keer's ---------------------------------
@pytest.mark.parametrize("nominal", [3e3, 1e5])
def test_pcg_equals_polonsky_keer(nominal):
    """The default solver (preconditioned, nested from 64^2) and the plain CCG on 128^2 cells
    give the same pressure; the coarse levels appear in the diagnostics."""
    grid = bem.Grid(128, 128, DX / 2, DX / 2)
    g0 = -bem.random_surface(PSD, grid, seed=3).heights
    load = nominal * grid.lx * grid.ly
    pcg = bem.solve_contact(g0, grid, E_STAR, load, tol=TOL)
    ccg = bem.solve_contact(g0, grid, E_STAR, load, tol=TOL, method="ccg")
    flat = bem.solve_contact(g0, grid, E_STAR, load, tol=TOL, nested=False)
    other = bem.solve_contact(g0, grid, E_STAR, 3.0 * load, tol=TOL, method="ccg")
    warm = bem.solve_contact(g0, grid, E_STAR, load, tol=TOL, p_init=other.pressure)
    for res in (pcg, ccg, flat, warm):
        check_complementarity(res, g0)
    peak = ccg.pressure.max()
    np.testing.assert_allclose(pcg.pressure, ccg.pressure, rtol=0.0, atol=RTOL_WARM * peak)
    np.testing.assert_allclose(flat.pressure, ccg.pressure, rtol=0.0, atol=RTOL_WARM * peak)
    np.testing.assert_allclose(warm.pressure, ccg.pressure, rtol=0.0, atol=RTOL_WARM * peak)
    assert len(pcg.stage_iterations) == 2 and pcg.stage_iterations[-1] == pcg.iterations
    assert ccg.stage_iterations == (ccg.iterations,) and ccg.convolutions == 2 * ccg.iterations + 1
    assert pcg.iterations < ccg.iterations


@pytest.mark.parametrize("ratio", [1.2, 0.85, 3.0])
def test_warm_start_near_load_skips_coarse_levels(ratio):
    """A start from a load within 1 + WARM_FULL_GRID_CELLS / n of the new one enters the full
    grid directly (one stage), a farther one the nested levels; both give the cold answer."""
    grid = bem.Grid(128, 128, DX / 2, DX / 2)
    g0 = -bem.random_surface(PSD, grid, seed=3).heights
    load = 2e4 * grid.lx * grid.ly
    start = bem.solve_contact(g0, grid, E_STAR, load / ratio, tol=TOL).pressure
    warm = bem.solve_contact(g0, grid, E_STAR, load, tol=TOL, p_init=start)
    cold = bem.solve_contact(g0, grid, E_STAR, load, tol=TOL)
    near = max(ratio, 1.0 / ratio) <= 1.0 + bem_contact.WARM_FULL_GRID_CELLS / grid.nx
    assert len(warm.stage_iterations) == (1 if near else 2) and len(cold.stage_iterations) == 2
    check_complementarity(warm, g0)
    peak = cold.pressure.max()
    np.testing.assert_allclose(warm.pressure, cold.pressure, rtol=0.0, atol=RTOL_WARM * peak)


def test_isolated_patch_pcg_equals_polonsky_keer():
    """The sphere (isolated patch): the padded preconditioner gives Polonsky & Keer's answer."""
    grid = bem.Grid(128, 128, 2e-6, 2e-6)
    g0 = bem.sphere_gap(grid, 0.01) - bem.random_surface(PSD, grid, seed=4).heights
    pcg = bem.solve_contact(g0, grid, E_STAR, 0.05, periodic=False, tol=TOL)
    ccg = bem.solve_contact(g0, grid, E_STAR, 0.05, periodic=False, tol=TOL, method="ccg")
    check_complementarity(pcg, g0)
    peak = ccg.pressure.max()
    np.testing.assert_allclose(pcg.pressure, ccg.pressure, rtol=0.0, atol=RTOL_WARM * peak)


def test_bad_method():
    grid = bem.Grid(8, 8, DX, DX)
    with pytest.raises(ValueError, match="method"):
        bem.solve_contact(np.zeros(grid.shape), grid, E_STAR, 1.0, method="cg")


# ---- Reynolds flow: the conjugate gradients, the switch to the direct solve -------------------
RTOL_FLOW = 1e-7  # conductance of the iterations (relative residual 1e-8) against sparse LU
RTOL_ROUND = 1e-12  # the same direct solve reached two ways
RTOL_BALANCE_LU = 1e-9  # inlet vs outlet flux of LU: round-off times conditioning (meas. 1e-11)
ATOL_FLOW_PRESSURE = 1e-5  # CG against LU fluid pressure, per unit pressure drop


@pytest.fixture(scope="module")
def flow_gaps(flat):
    """Gap fields of the flat contact at A/A0 0.013, 0.10 and 0.27 (increasing loads)."""
    grid, g0, area = flat
    return [bem.solve_contact(g0, grid, E_STAR, p * area, tol=TOL).gap for p in (1e4, 1e5, 3e5)]


def test_flow_iterative_equals_direct(flat, flow_gaps):
    grid = flat[0]
    start = None
    for gap in flow_gaps:  # warm starts through the sequence, as a calibration runs it
        it = bem.reynolds_flow(gap, grid.dx, solver="iterative", start=start)
        direct = bem.reynolds_flow(gap, grid.dx, solver="direct")
        assert it.solver == "iterative" and it.iterations > 0 and direct.iterations == 0
        assert it.conductance == pytest.approx(direct.conductance, rel=RTOL_FLOW, abs=0.0)
        assert direct.balance_error < RTOL_BALANCE_LU and it.balance_error < 1e3 * RTOL_FLOW
        np.testing.assert_allclose(it.pressure, direct.pressure, rtol=0.0, atol=ATOL_FLOW_PRESSURE)
        start = it


def test_flow_warm_start_saves_iterations(flat, flow_gaps):
    grid = flat[0]
    first = bem.reynolds_flow(flow_gaps[0], grid.dx, solver="iterative")
    again = bem.reynolds_flow(flow_gaps[0], grid.dx, solver="iterative", start=first)
    assert again.iterations == 0 and again.conductance == pytest.approx(first.conductance, 1e-12)


def test_flow_auto_takes_the_direct_solve_when_iterations_cost_more(flat, flow_gaps, monkeypatch):
    grid = flat[0]
    gap = flow_gaps[1]
    direct = bem.reynolds_flow(gap, grid.dx, solver="direct")
    assert bem.reynolds_flow(gap, grid.dx).solver == "direct"  # 64^2: below DIRECT_BELOW
    monkeypatch.setattr(bem_flow, "DIRECT_BELOW", 0)
    monkeypatch.setattr(bem_flow, "ITERATION_BUDGET", 1e4)  # iterations cheap at any count
    auto = bem.reynolds_flow(gap, grid.dx)
    assert auto.solver == "iterative" and auto.iterations > 0
    monkeypatch.setattr(bem_flow, "ITERATION_BUDGET", 1e-6)  # any iteration is too dear
    switched = bem.reynolds_flow(gap, grid.dx)
    assert switched.solver == "direct" and switched.iterations == pcg_flow.CHECK_EVERY
    assert switched.conductance == pytest.approx(direct.conductance, rel=RTOL_ROUND, abs=0.0)


RTOL_CONDUCTANCE_EST = 10.0  # conductance error against conductance_tol (measured within 6x)


@pytest.mark.parametrize("ctol", [1e-4, 1e-6])
def test_flow_stops_on_the_conductance_error(flat, flow_gaps, ctol):
    grid = flat[0]
    for gap in flow_gaps:
        direct = bem.reynolds_flow(gap, grid.dx, solver="direct")
        full = bem.reynolds_flow(gap, grid.dx, solver="iterative")
        fast = bem.reynolds_flow(gap, grid.dx, solver="iterative", conductance_tol=ctol)
        assert fast.solver == "iterative" and 0 < fast.iterations <= full.iterations
        err = fast.conductance / direct.conductance - 1.0
        assert -RTOL_FLOW <= err <= RTOL_CONDUCTANCE_EST * ctol  # above it: the dissipation
    looser = bem.reynolds_flow(flow_gaps[1], grid.dx, solver="iterative", conductance_tol=1e-2)
    assert looser.iterations < full.iterations or full.iterations <= pcg_flow.DELAY


def _wrap_channel(nx, ny):
    """A map closed but for two half-columns joined only across the periodic y boundary."""
    gap = np.zeros((nx, ny))
    gap[: nx // 2 + 1, 0] = 1.0
    gap[nx // 2 :, ny - 1] = 2.0
    return gap


@pytest.mark.parametrize("seed", range(6))
def test_flow_path_equals_a_search_by_sets(seed):
    """Random maps at the percolation threshold of site percolation (open fraction 0.55-0.65),
    and (seed 5) a channel that joins inlet and outlet only across the periodic side."""
    rng = np.random.default_rng(seed)
    nx, ny = 23, 17
    gap = np.where(rng.random((nx, ny)) < 0.55 + 0.02 * seed, rng.random((nx, ny)) + 0.1, 0.0)
    if seed == 5:
        gap = _wrap_channel(nx, ny)
    keep = naive.flow_path_cells(gap)
    res = bem.reynolds_flow(gap, 1e-6)
    np.testing.assert_array_equal(np.isfinite(res.pressure), keep)
    assert res.percolating == keep.any()
    if seed == 5:
        assert keep.sum() == nx + 1
    if keep.any():
        ref = naive.reynolds_dense(gap, 1e-6, 1e-6, 1e-3, 1.0)
        assert res.conductance == pytest.approx(ref, rel=RTOL_ROUND, abs=0.0)


@pytest.mark.parametrize("shape", [(9, 7), (6, 2), (5, 1)])
@pytest.mark.parametrize("backward", [False, True])
def test_flow_smoother_equals_a_sweep_cell_by_cell(shape, backward):
    rng = np.random.default_rng(3)
    tx, ty = rng.random((shape[0] - 1, shape[1])), rng.random(shape)
    D = 4.0 + rng.random(shape)
    b, x = rng.standard_normal(shape), rng.standard_normal(shape)
    ref = x.copy()
    naive.gauss_seidel_sweep(D, tx, ty, b, ref, backward)
    pcg_flow._gauss_seidel(1.0 / D, tx, ty, b, x, backward)
    np.testing.assert_allclose(x, ref, rtol=1e-13, atol=1e-13)


@pytest.mark.parametrize("shape", [(8, 6), (4, 2), (6, 1)])
def test_flow_operator_and_restriction_equal_cell_by_cell_sums(shape):
    rng = np.random.default_rng(4)
    tx, ty = rng.random((shape[0] - 1, shape[1])), rng.random(shape)
    D = 4.0 + rng.random(shape)
    b, x = rng.standard_normal(shape), rng.standard_normal(shape)
    ref = naive.five_point_apply(D, tx, ty, x)
    y = np.empty(shape)
    pcg_flow._matvec(D, tx, ty, x, y)
    np.testing.assert_allclose(y, ref, rtol=1e-13, atol=1e-13)
    if shape[1] % 2 == 0:
        nx, ny = shape
        rc = np.empty((nx // 2, ny // 2))
        pcg_flow._restrict(D, tx, ty, b, x, rc)
        agg = (b - ref).reshape(nx // 2, 2, ny // 2, 2).sum(axis=(1, 3))
        np.testing.assert_allclose(rc, agg, rtol=1e-13, atol=1e-12)


def test_flow_bad_solver_and_start(flat, flow_gaps):
    grid = flat[0]
    with pytest.raises(ValueError, match="solver must be one of"):
        bem.reynolds_flow(flow_gaps[0], grid.dx, solver="amg")
    for bad in (0.0, 1.0, -1e-3, float("nan")):
        with pytest.raises(ValueError, match="conductance_tol must be in"):
            bem.reynolds_flow(flow_gaps[0], grid.dx, conductance_tol=bad)
    other = bem.reynolds_flow(flow_gaps[0][:32], grid.dx)
    with pytest.raises(ValueError, match="start must be a FlowResult"):
        bem.reynolds_flow(flow_gaps[0], grid.dx, start=other)
    with pytest.raises(ValueError, match="start must be a FlowResult"):
        bem.reynolds_flow(flow_gaps[0], grid.dx, start=np.zeros((N, N)))
