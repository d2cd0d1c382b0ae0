"""One elastic convolution (zero-padded FFT of the log kernel)."""

from __future__ import annotations

import numpy as np
import pytest

import fastline as fl
from bench.conftest import E_STAR


@pytest.mark.parametrize("n", [512, 2048, 8192])
def test_convolution(benchmark, n):
    benchmark.group = "elastic-convolution"
    op = fl.LogKernelOperator(n, 1e-5, E_STAR)
    p = np.random.default_rng(0).random(n)
    out = np.empty(n)
    op.apply(p, out=out)
    benchmark(op.apply, p, out)
    assert np.all(np.isfinite(out))
