"""fl.sweep throughput on a small paper-like table (the full 10,000-scene measurement is
``python -m bench.throughput``, which writes docs/throughput.md)."""

from __future__ import annotations

import concurrent.futures as cf
import multiprocessing
import warnings

import pytest

import fastline as fl
from bench.throughput import paper_scenes

SCENES, N = 300, 128


@pytest.fixture(scope="module")
def scenes():
    return paper_scenes(SCENES, N)


@pytest.fixture(scope="module")
def pool():
    with cf.ProcessPoolExecutor(2, mp_context=multiprocessing.get_context("spawn")) as ex:
        fl.sweep(paper_scenes(24, N, seed=1), ex, chunksize=1, progress=False, warn=False)
        yield ex


def _run(scenes, executor):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return fl.sweep(scenes, executor, progress=False, warn=False)


@pytest.mark.parametrize("where", ["serial", "pool"])
def test_sweep_throughput(benchmark, scenes, pool, where):
    benchmark.group = "batch-sweep"
    executor = "serial" if where == "serial" else pool
    res = benchmark(_run, scenes, executor)
    st = res.stats
    benchmark.extra_info.update(
        scenes=st.scenes,
        tasks=st.tasks,
        workers=st.workers,
        compute_seconds=st.compute_seconds,
        scenes_per_second=st.scenes_per_second,
    )
    assert len(res) == SCENES and not res.failed.any()
