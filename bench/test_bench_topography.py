"""Measured spectra: the theory build of a 100,000-point table against the analytic build.

Run with ``pytest bench/test_bench_topography.py --benchmark-enable``; the group
``table-vs-analytic`` holds the three builds of one run side by side (same machine, same load),
and ``extra_info`` the quadrature node counts and the table's error against the analytic theory.
"""

from __future__ import annotations

import numpy as np
import pytest

import fastline as fl
from bench.conftest import E_STAR

N_TABLE = 100_000
PROBE_P = np.geomspace(1e-8, 1e-1, 8) * E_STAR


def _periodogram(psd, n, seed=0):
    """A raw periodogram's shape: k_m = m dk up to q1, chi-squared(2) scatter on every point."""
    k = np.arange(1, n + 1) * (psd.q1 / n)
    return k, psd(k) * np.random.default_rng(seed).exponential(size=n)


@pytest.fixture(scope="module")
def tables(psd1):
    q = np.geomspace(psd1.q0, psd1.q1, N_TABLE)
    return {
        "smooth": fl.TabulatedPSD(q, psd1(q)),
        "periodogram": fl.TabulatedPSD(*_periodogram(psd1, N_TABLE)),
    }


@pytest.mark.parametrize("rtol", [1e-4, 1e-6])
@pytest.mark.parametrize("kind", ["analytic", "smooth", "periodogram"])
def test_theory_build(benchmark, psd1, tables, kind, rtol):
    benchmark.group = f"table-vs-analytic rtol={rtol:g}"
    psd = psd1 if kind == "analytic" else tables[kind]
    fl.PerssonTheory(psd, E_STAR, rtol=rtol)  # compile outside the timing
    th = benchmark(fl.PerssonTheory, psd, E_STAR, rtol=rtol)
    benchmark.extra_info["table_points"] = 0 if kind == "analytic" else N_TABLE
    benchmark.extra_info["quadrature_nodes"] = int(th._q.size)
    if kind == "smooth":  # a dense table of psd1 must give psd1's theory
        exact = fl.PerssonTheory(psd1, E_STAR, rtol=rtol).separation(PROBE_P)
        err = float(np.max(np.abs(th.separation(PROBE_P) / exact - 1.0)))
        benchmark.extra_info["max_rel_err_vs_analytic"] = err
        assert err < 10 * rtol


def test_read_table(benchmark, psd1):
    """Reading the table: validation and the exact per-interval moments (O(N), once)."""
    benchmark.group = "table-read"
    k, C = _periodogram(psd1, N_TABLE)
    benchmark(fl.TabulatedPSD, k, C)
