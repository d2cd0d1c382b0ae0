"""The pressure law inside the compiled Newton solve, per grid cell.

Each Newton step and line-search trial evaluates the law once over the grid
(:func:`fastline.contact.line_newton._evaluate`: ``p = exp(v)``, the law's u and du/dv, one FFT
convolution, the residual). Timed on the iterate of a converged solve (surface 1, alpha 1,
n = 4096: a third of the cells lie below table T1, the rest inside it), so the branches are
those a real solve takes. Divide the times by ``extra_info["cells"]`` for ns per cell; the
``hermite`` case reads T1 through its Hermite data (:meth:`PerssonTheory.separation_table`'s
kernel), for the same-run ratio to the solvers' Horner form.
"""

from __future__ import annotations

import numpy as np
import pytest

import fastline as fl
from bench.conftest import E_STAR, RADIUS, load_for_alpha
from fastline._lib import fftw as _fftw
from fastline.contact.line_newton import _evaluate, _law
from fastline.elastic.line import compiled_tables
from fastline.theory.tables import _separation_and_slope

N = 4096


@pytest.fixture(scope="module")
def scene(psd1, theory1):
    """The converged ln p of a solve, its gap and weights, and the laws' compiled forms."""
    lc = fl.LineContact(psd1, E_STAR, RADIUS, n=N, theory=theory1, warn=False)
    res = lc.solve(load_for_alpha(1.0))
    v = np.log(np.maximum(res.pressure, 1e-300))
    gap = res.x**2 / (2.0 * RADIUS)
    w = np.full(N, res.dx)
    forms = {
        "persson": fl.PerssonLaw(theory1)._compiled_form(),
        "exponential": fl.ExponentialLaw.from_theory(theory1)._compiled_form(),
    }
    return v, gap, w, forms, theory1


@pytest.mark.parametrize("law", ["persson", "exponential", "hermite"])
def test_law_per_cell(benchmark, scene, law):
    benchmark.group = "law-per-cell"
    v, _, _, forms, theory = scene
    u, dudv = np.empty(N), np.empty(N)
    if law == "hermite":
        args = (v, *theory._t1, u, dudv)
        benchmark(_separation_and_slope, *args)
    else:
        args = (forms[law][0], v, *forms[law][1:], u, dudv)
        benchmark(_law, *args)
    benchmark.extra_info["cells"] = N
    assert np.all(dudv < 0.0) and np.all(np.isfinite(u))


@pytest.mark.skipif(not _fftw.AVAILABLE, reason="the compiled Newton needs the FFTW library")
def test_evaluate_per_cell(benchmark, scene):
    """One residual evaluation: exp, the Persson law, one convolution of length 2n."""
    benchmark.group = "law-per-cell"
    v, gap, w, forms, _ = scene
    kspec = compiled_tables(N)[0]
    a, c = _fftw.aligned_buffers(2 * N)
    p, U, dU, gk, r = (np.empty(N) for _ in range(5))
    fft = _fftw.acquire(2 * N)
    try:
        state = (v.copy(), p, U, dU, gk, r)
        args = (state, np.nan, fft, kspec, 1e-10, gap, w, forms["persson"], a, c)
        _, res, _ = benchmark(_evaluate, *args)
    finally:
        _fftw.release(2 * N)
    benchmark.extra_info["cells"] = N
    benchmark.extra_info["convolutions"] = 1
    assert np.isfinite(res)
