"""Fresh-process time to a first answer: cold (empty Numba cache) and warm (cache filled)."""

from __future__ import annotations

import os
import subprocess
import sys
import tempfile
import time

SCRIPT = (
    "import fastline as fl\n"
    "from fastline.line_contact import solve_line_contact\n"
    "psd = fl.SelfAffinePSD(10e-6, 0.8, 1e3, 1e4, 1e9)\n"
    "r = solve_line_contact(psd, 1.33e9, 0.01, 1.0e4)\n"
    "print(r.p0_ratio)\n"
)


def first_answer(cache_dir):
    """Seconds for a fresh interpreter to import fastline and print one p0 ratio."""
    env = dict(os.environ, NUMBA_CACHE_DIR=cache_dir)
    t = time.perf_counter()
    out = subprocess.run(
        [sys.executable, "-c", SCRIPT], env=env, capture_output=True, text=True, check=True
    )
    dt = time.perf_counter() - t
    return dt, float(out.stdout.strip().splitlines()[-1])


def cold_and_warm():
    with tempfile.TemporaryDirectory(prefix="fastline-numba-") as d:
        cold, p_cold = first_answer(d)
        warm, p_warm = first_answer(d)
    return cold, warm, p_cold, p_warm


def test_first_answer(benchmark):
    benchmark.group = "startup"
    cold, warm, p_cold, p_warm = benchmark.pedantic(cold_and_warm, rounds=1, iterations=1)
    benchmark.extra_info.update(cold_seconds=cold, warm_seconds=warm, p0_ratio=p_warm)
    assert p_cold == p_warm and 0.0 < p_warm < 2.0
