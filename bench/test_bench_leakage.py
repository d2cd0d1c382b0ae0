"""Seal leakage: critical gaps of uniform pressures, and the leak rate of a solved line contact
against the solve it post-processes (same scene, same group)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.special import erfinv

import fastline as fl
from bench.conftest import E_STAR, RADIUS, load_for_alpha
from fastline.theory import interface

N_PRESSURES = 10_000
DP, ETA = 1e5, 1e-3  # Pa, Pa s (water)


@pytest.fixture(scope="module")
def pressures(theory1):
    """1e4 pressures from 1e-9 E* to the sealing pressure of surface 1."""
    psd = theory1.psd
    p_seal = float(erfinv(0.42)) * E_STAR * math.sqrt(float(psd.cumulative(psd.q1)))
    return np.geomspace(1e-9 * E_STAR, p_seal, N_PRESSURES)


def test_critical_gap_direct_1e4(benchmark, theory1, pressures):
    benchmark.group = "leakage-critical-gap"
    theory1.critical_gap(pressures[:10])  # compile outside the timing
    cg = benchmark(theory1.critical_gap, pressures)
    benchmark.extra_info["pressures"] = pressures.size
    assert np.all(np.isfinite(cg.u_c)) and not cg.sealed[:-1].any()


def test_critical_gap_table_1e4(benchmark, theory1, pressures):
    """What leak_rate uses: the cached table of ln u_c (built outside the timing)."""
    benchmark.group = "leakage-critical-gap"
    table = interface.gap_table(theory1, 0.42)
    x1 = interface.sealing_argument(theory1, pressures)
    log_gap, _ = benchmark(table.log_gap, x1)
    direct = theory1.critical_gap(pressures).u_c
    ok = direct > 1e-250
    benchmark.extra_info["max_rel_err_vs_direct"] = float(
        np.max(np.abs(np.exp(log_gap[ok]) / direct[ok] - 1.0))
    )


def test_gap_table_build(benchmark, psd1):
    """First leak rate of a theory: the table of u_c (once per theory and threshold)."""
    benchmark.group = "leakage-table-build"
    interface.gap_table(fl.PerssonTheory(psd1, E_STAR), 0.42)  # compile outside the timing

    def build():
        return interface.gap_table(fl.PerssonTheory(psd1, E_STAR), 0.42)

    table = benchmark(build)
    benchmark.extra_info["cells"] = int(table.cf.shape[0])


@pytest.mark.parametrize("alpha", [1e-3, 1e-1, 10.0])
@pytest.mark.parametrize("step", ["solve", "leak_rate"])
def test_leak_rate_vs_solve(benchmark, psd1, theory1, alpha, step):
    benchmark.group = f"leakage-vs-solve-alpha{alpha:g}"
    load = load_for_alpha(alpha)
    res = fl.solve_line_contact(psd1, E_STAR, RADIUS, load, theory=theory1, warn=False)
    fl.leak_rate(res, DP, ETA, theory=theory1, warn=False)  # table and compile outside
    if step == "solve":
        out = benchmark(
            fl.solve_line_contact, psd1, E_STAR, RADIUS, load, theory=theory1, warn=False
        )
        assert out.converged
    else:
        out = benchmark(fl.leak_rate, res, DP, ETA, theory=theory1, warn=False)
        benchmark.extra_info["rate"] = out.Q
        assert out.Q > 0.0 or out.sealed
    benchmark.extra_info["n"] = res.x.size
