"""Line-contact solves: one per alpha and method, and the paper's sweep."""

from __future__ import annotations

import warnings

import pytest

import fastline as fl
from bench.conftest import ALPHAS, E_STAR, PICARD_CAP, RADIUS, SWEEP_LOADS, load_for_alpha, surfaces
from fastline.contact.line import solve_line_contact


@pytest.mark.filterwarnings("ignore:overflow encountered:RuntimeWarning")
@pytest.mark.parametrize("method", ["newton", "picard"])
@pytest.mark.parametrize("alpha", ALPHAS)
def test_solve(benchmark, psd1, theory1, alpha, method):
    benchmark.group = f"solve-{method}"
    load = load_for_alpha(alpha)
    kw = dict(method=method, theory=theory1, warn=False)
    if method == "picard":
        kw["max_iter"] = PICARD_CAP
    res = benchmark(solve_line_contact, psd1, E_STAR, RADIUS, load, **kw)
    benchmark.extra_info.update(
        alpha=alpha,
        convolutions=res.convolutions,
        converged=res.converged,
        residual=res.residual,
        iterations=res.iterations,
    )
    if method == "newton":
        assert res.converged


def _sweep(theories):
    out = []
    for psd, th in theories:
        for f in SWEEP_LOADS:
            out.append(solve_line_contact(psd, E_STAR, RADIUS, float(f), theory=th, warn=False))
    return out


def test_paper_sweep(benchmark):
    benchmark.group = "paper-sweep"
    theories = [(psd, fl.PerssonTheory(psd, E_STAR)) for psd in surfaces()]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        res = benchmark(_sweep, theories)
    benchmark.extra_info["solves"] = len(res)
    benchmark.extra_info["converged"] = sum(r.converged for r in res)
    benchmark.extra_info["convolutions_total"] = sum(r.convolutions for r in res)
    assert len(res) == 75
