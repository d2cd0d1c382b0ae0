"""accuracy=1e-4 against the default grid (n = 1024), warm, surface 1 (docs/accuracy.md).

Run with ``--benchmark-enable``; each group holds the two ways of solving one alpha. The
extra info records the machine-independent cost: convolutions and FFT work (cells x
convolutions summed over every solve).
"""

from __future__ import annotations

import pytest

import fastline as fl
from bench.conftest import E_STAR, RADIUS, load_for_alpha


@pytest.mark.parametrize("how", ["n=1024", "accuracy=1e-4"])
@pytest.mark.parametrize("alpha", [1e-3, 1e-2, 1.0, 100.0])
def test_accuracy_vs_default(benchmark, psd1, theory1, alpha, how):
    benchmark.group = f"accuracy-alpha-{alpha:g}"
    options = {"accuracy": 1e-4} if how.startswith("accuracy") else {}
    model = fl.LineContact(psd1, E_STAR, RADIUS, theory=theory1, warn=False, **options)
    load = load_for_alpha(alpha)
    res = benchmark(model.solve, load)
    est = res.error_estimate
    benchmark.extra_info.update(
        alpha=alpha,
        convolutions=res.convolutions,
        fft_work=est.fft_work if est else model.n * res.convolutions,
        n=est.n if est else model.n,
    )
    assert res.converged
