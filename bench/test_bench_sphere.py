"""Point contact (sphere on flat): ring-operator products, solves over alpha, the paper sweep."""

from __future__ import annotations

import numpy as np
import pytest

import fastline as fl
from bench.conftest import ALPHAS, E_STAR, RADIUS, surfaces
from fastline.elastic import ring
from fastline.reports.paper import sphere_load_for_alpha


@pytest.mark.parametrize("n", [256, 512, 1024, 2048])
def test_ring_product(benchmark, n):
    benchmark.group = "ring-operator-product"
    op = fl.RingKernelOperator(n, 1e-6, E_STAR)
    p = np.random.default_rng(0).random(n)
    out = np.empty(n)
    op.apply(p, out=out)
    benchmark(op.apply, p, out)
    assert np.all(np.isfinite(out))


@pytest.mark.parametrize("alpha", ALPHAS)
def test_sphere_solve(benchmark, psd1, theory1, alpha):
    """A solve from the cold start at the default n = 512 (coefficients and JIT warm)."""
    benchmark.group = "sphere-solve"
    model = fl.PointContact(psd1, E_STAR, RADIUS, theory=theory1, warn=False)
    load = float(sphere_load_for_alpha(alpha, psd1.h_rms))
    res = benchmark(model.solve, load)
    benchmark.extra_info.update(
        alpha=alpha,
        convolutions=res.convolutions,
        k_applications=res.diagnostics["k_applications"],
        iterations=res.iterations,
    )
    assert res.converged


def _sweeps(models, loads):
    return [m.sweep(f) for m, f in zip(models, loads, strict=True)]


def test_sphere_paper_sweep(benchmark):
    """The sphere version of Figs. 4-5: 3 surfaces x 25 loads, alpha 1e-3..1e3, continuation."""
    benchmark.group = "sphere-paper-sweep"
    alphas = np.geomspace(1e-3, 1e3, 25)
    psds = surfaces()
    models = [fl.PointContact(p, E_STAR, RADIUS, warn=False) for p in psds]
    loads = [sphere_load_for_alpha(alphas, p.h_rms) for p in psds]
    res = benchmark(_sweeps, models, loads)
    flat = [r for rs in res for r in rs]
    benchmark.extra_info["convolutions_total"] = sum(r.convolutions for r in flat)
    assert all(r.converged for r in flat)


def test_sphere_cold_large_n(benchmark):
    """A first solve at the largest grid, n = 4096: the coefficient matrices (4096 and the
    nested start's 1024 and 256) built from nothing, the nested start and the Newton solve, on
    the scene whose steep contact edge took 100 Newton steps from the blended cold start."""
    benchmark.group = "sphere-cold-large-n"
    psd = fl.SelfAffinePSD(1.6252659152708667e-07, 0.7507584274033539, 11.838074501303021,
                           11.838074501303021, 1457256.6822658174)  # fmt: skip
    scene = (psd, 9467232.038449507, 1.8499331365511182e-05, 6.008112696548577e-08)

    def cold():
        ring._matrices.clear()
        ring._coarse.clear()
        return fl.solve_point_contact(*scene, n=4096, warn=False)

    res = benchmark.pedantic(cold, rounds=1, iterations=1)
    benchmark.extra_info.update(
        iterations=res.iterations,
        convolutions=res.convolutions,
        nested=res.diagnostics["nested_start"],
    )
    assert res.converged
