"""Persson theory: table build (per rtol) and pressure(u) evaluation."""

from __future__ import annotations

import numpy as np
import pytest

import fastline as fl
from bench.conftest import E_STAR

PROBE_P = np.geomspace(1e-3, 1e8, 7)  # Pa


@pytest.fixture(scope="module")
def reference(psd1):
    ref = fl.PerssonTheory(psd1, E_STAR, rtol=1e-9)
    return ref.separation(PROBE_P)


@pytest.mark.parametrize("rtol", [1e-4, 1e-6, 1e-8])
def test_table_build(benchmark, psd1, reference, rtol):
    benchmark.group = "persson-table-build"
    fl.PerssonTheory(psd1, E_STAR, rtol=rtol)  # compile outside the timing
    th = benchmark(fl.PerssonTheory, psd1, E_STAR, rtol=rtol)
    sep = th.separation(PROBE_P)
    tab = th.separation_table(PROBE_P)[0]
    benchmark.extra_info["max_rel_err_separation"] = float(np.max(np.abs(sep / reference - 1)))
    benchmark.extra_info["max_rel_err_table"] = float(np.max(np.abs(tab / reference - 1)))
    assert np.all(np.isfinite(sep))


def test_pressure_1e5(benchmark, theory1):
    benchmark.group = "persson-pressure"
    u = np.geomspace(1e-3, 10.0, 100_000) * theory1.exponential_fit().u0
    theory1.pressure(u[:10])
    p = benchmark(theory1.pressure, u)
    assert p.shape == u.shape and np.all(p >= 0.0)
