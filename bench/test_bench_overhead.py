"""Per-solve overhead of a warm LineContact.solve: the whole solve, and its Python part alone
(the Newton kernel replayed by a compiled stub: :mod:`bench.gil`), which holds the GIL."""

from __future__ import annotations

import pytest

import fastline as fl
from bench.conftest import E_STAR, RADIUS, load_for_alpha
from bench.gil import compiled_work, newton_replayed


@pytest.mark.parametrize("n", [256, 1024])
@pytest.mark.parametrize("alpha", [1.0, 1e-2])
def test_warm_solve(benchmark, psd1, n, alpha):
    benchmark.group = f"warm-solve-n{n}"
    lc = fl.LineContact(psd1, E_STAR, RADIUS, n=n, warn=False)
    load = load_for_alpha(alpha)
    res = benchmark(lc.solve, load)
    benchmark.extra_info.update(alpha=alpha, convolutions=res.convolutions)
    assert res.converged


@pytest.mark.parametrize("n", [256, 1024])
def test_python_part_of_a_warm_solve(benchmark, psd1, n):
    """Everything but the Newton iteration: the GIL-held time plus ~n-linear compiled work
    (``extra_info['kernels_us']``, timed alone)."""
    benchmark.group = "solve-python-part"
    lc = fl.LineContact(psd1, E_STAR, RADIUS, n=n, warn=False)
    load = load_for_alpha(1.0)
    with newton_replayed(lc, load) as calls:
        res = benchmark(lc.solve, load)
    work = compiled_work(calls, reps=20)
    benchmark.extra_info.update(kernels_us={k: v * 1e6 for k, v in work.items()})
    assert res.converged and set(work) == {
        "cold_start_normalised",
        "line_cells",
        "line_measures",
        "pressure_into",
    }
