"""fastline.bem: one convolution, the periodic kernel table, one Reynolds solve, and one whole
realisation (surface + CCG contact (+ flow)) at the sizes a validation page needs.

The realisations at validation size take seconds to a minute each: they run only when timing
(``--benchmark-enable``); the default (disabled) run makes a smoke call of the small cases.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

import fastline as fl
from bench.bem_scaling import E_STAR as FLAT_E_STAR
from bench.bem_scaling import problem
from fastline import bem
from fastline.bem.halfspace import ALIAS_ORDER, _alias_sum

# The paper-like narrow-band surface of docs/validation.md: H 0.8, q1/q0 = 32, h_rms 0.5 um,
# E* 10 MPa, R 32.8 mm. q0 is a choice: 2 pi/q0 = 40 um keeps the roughness wavelength well
# below the contact width (Hertz a = 128 um at alpha = 1, Gaussian-limit s = 81 um).
PAPER_E_STAR = 10e6  # Pa
PAPER_RADIUS = 32.8e-3  # m
PAPER_Q0 = 2.0 * math.pi / 40e-6  # 1/m
PAPER_PSD = fl.SelfAffinePSD(0.5e-6, 0.8, PAPER_Q0, PAPER_Q0, 32.0 * PAPER_Q0)


def paper_load(alpha):
    """f_N [N/m] with h_rms / delta = alpha, delta = 4 f_N / (pi E*)."""
    return math.pi / 4.0 * PAPER_PSD.h_rms * PAPER_E_STAR / alpha


def _large_only(benchmark):
    if benchmark.disabled:
        pytest.skip("validation-size realisation: timed with --benchmark-enable only")


@pytest.mark.parametrize("n", [256, 512])
def test_bem_convolution(benchmark, n):
    benchmark.group = "bem-convolution"
    op = bem.ElasticHalfSpace(n, n, 1e-6, 1e-6, PAPER_E_STAR)
    p = np.random.default_rng(0).random((n, n))
    out = np.empty((n, n))
    op.apply(p, out=out)
    benchmark(op.apply, p, out)
    assert np.all(np.isfinite(out))


def test_alias_table(benchmark):
    benchmark.group = "bem-kernel-table"
    _alias_sum(8, 8, 1.0, ALIAS_ORDER)  # compile outside the timing
    table = benchmark(_alias_sum, 256, 256, 1.0, ALIAS_ORDER)
    assert np.all(np.isfinite(table))


@pytest.mark.parametrize("n", [128, 512])
def test_reynolds_flow(benchmark, n):
    benchmark.group = "bem-reynolds"
    g = np.abs(np.random.default_rng(1).standard_normal((n, n))) * 1e-6
    g[g < 0.5e-6] = 0.0  # ~38 % contact
    res = benchmark(bem.reynolds_flow, g, 1e-6)
    benchmark.extra_info.update(active_fraction=res.active_fraction)
    assert res.percolating


@pytest.mark.parametrize("periods", [1, 4])
def test_flat_realization(benchmark, periods):
    """Nominally flat seal scene at 1 MPa (128^2 and 512^2 cells), CCG and Reynolds flow."""
    if periods > 1:
        _large_only(benchmark)
    benchmark.group = "bem-realization"
    scene = bem.flat_contact_scene(PAPER_PSD, PAPER_E_STAR, 1e6, periods=periods)
    bem.run_realization(0, scene)  # kernel table and compilation outside the timing
    run = benchmark.pedantic(bem.run_realization, args=(1, scene), rounds=1, iterations=1)
    benchmark.extra_info.update(
        grid=f"{scene.grid.nx}x{scene.grid.ny}",
        iterations=run.iterations,
        contact_fraction=run.contact_fraction,
    )
    assert run.converged


@pytest.mark.parametrize("alpha", [0.1, 1.0, 10.0])
def test_line_realization(benchmark, alpha):
    """The paper-like rough cylinder on its default grid (4 cells per 2 pi/q1, Ly = 2 pi/q0 x 2,
    Lx = 4 widths)."""
    _large_only(benchmark)
    benchmark.group = "bem-realization"
    scene = bem.line_contact_scene(PAPER_PSD, PAPER_E_STAR, PAPER_RADIUS, paper_load(alpha))
    bem.run_realization(0, scene)
    run = benchmark.pedantic(bem.run_realization, args=(1, scene), rounds=1, iterations=1)
    benchmark.extra_info.update(
        grid=f"{scene.grid.nx}x{scene.grid.ny}",
        iterations=run.iterations,
        contact_fraction=run.contact_fraction,
    )
    assert run.converged


@pytest.mark.parametrize("method", ["pcg", "ccg"])
def test_flat_contact_solve(benchmark, method):
    """One 256^2 nominally flat contact at A/A0 ~ 0.3 (the surface of bench.bem_scaling): the
    preconditioned nested solver against Polonsky & Keer's plain iterations."""
    benchmark.group = "bem-contact-solver"
    grid, g0 = problem(256)
    load = 1.04e5 * grid.lx * grid.ly
    bem.solve_contact(g0, grid, FLAT_E_STAR, load, tol=1e-4, method=method)  # compile, tables
    res = benchmark.pedantic(
        bem.solve_contact,
        args=(g0, grid, FLAT_E_STAR, load),
        kwargs={"tol": 1e-8, "method": method},
        rounds=1,
        iterations=1,
    )
    benchmark.extra_info.update(iterations=res.stage_iterations, convolutions=res.convolutions)
    assert res.converged
