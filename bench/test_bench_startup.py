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


def _environment(cache_dir):
    """The child's environment: the given Numba cache, and Python's bytecode cache on (as after
    ``pip install``, which byte-compiles the package; a ``PYTHONDONTWRITEBYTECODE`` set on this
    machine would add ~0.15 s of compiling fastline's sources to every start)."""
    env = dict(os.environ, NUMBA_CACHE_DIR=cache_dir)
    env.pop("PYTHONDONTWRITEBYTECODE", None)
    return env


def first_answer(cache_dir):
    """Seconds for a fresh interpreter to import fastline and print one p0 ratio."""
    env = _environment(cache_dir)
    t = time.perf_counter()
    out = subprocess.run(
        [sys.executable, "-c", SCRIPT], env=env, capture_output=True, text=True, check=True
    )
    dt = time.perf_counter() - t
    return dt, float(out.stdout.strip().splitlines()[-1])


#: the same first answer, with a clock read after each stage of start-up
STAGED = (
    "import time\n"
    "t = [time.perf_counter()]\n"
    "import numpy\n"
    "t.append(time.perf_counter())\n"
    "import numba\n"
    "t.append(time.perf_counter())\n"
    "import fastline as fl\n"
    "from fastline.line_contact import solve_line_contact\n"
    "t.append(time.perf_counter())\n"
    "from numba.core.registry import cpu_target\n"
    "cpu_target.target_context.refresh()\n"
    "t.append(time.perf_counter())\n"
    "psd = fl.SelfAffinePSD(10e-6, 0.8, 1e3, 1e4, 1e9)\n"
    "r = solve_line_contact(psd, 1.33e9, 0.01, 1.0e4)\n"
    "t.append(time.perf_counter())\n"
    "print(' '.join(str(b - a) for a, b in zip(t, t[1:])))\n"
)
#: what each interval of STAGED measures
STAGES = (
    "import numpy",
    "import numba",
    "import fastline and its line-contact modules",
    "Numba's first-use set-up (typing and lowering registries; loads scipy.linalg)",
    "theory tables, loading the cached kernels, the solve",
)


def stages(cache_dir, repeat=5):
    """Seconds of each start-up stage (:data:`STAGES`) of a warm first answer, the median over
    ``repeat`` fresh interpreters (the cache in ``cache_dir`` must be filled already)."""
    env = _environment(cache_dir)
    runs = []
    for _ in range(repeat):
        out = subprocess.run(
            [sys.executable, "-W", "ignore", "-c", STAGED],
            env=env,
            capture_output=True,
            text=True,
            check=True,
        )
        runs.append([float(v) for v in out.stdout.split()])
    runs.sort(key=sum)
    return runs[len(runs) // 2]


#: the floor: a fresh interpreter that imports NumPy and Numba and calls one trivial cached
#: kernel (numba's own first-use set-up and teardown included)
TRIVIAL = (
    "import numba\n"
    "import numpy as np\n"
    "@numba.njit(cache=True)\n"
    "def total(x):\n"
    "    return x.sum()\n"
    "print(total(np.ones(3)))\n"
)


def trivial_numba(cache_dir, runs=5):
    """Median seconds of a fresh interpreter running :data:`TRIVIAL` with its cache filled:
    what any Numba program pays on this machine before its own work."""
    script = os.path.join(cache_dir, "trivial_numba.py")
    with open(script, "w") as f:
        f.write(TRIVIAL)
    env = _environment(cache_dir)
    subprocess.run([sys.executable, script], env=env, capture_output=True, check=True)
    times = []
    for _ in range(runs):
        t = time.perf_counter()
        subprocess.run([sys.executable, script], env=env, capture_output=True, check=True)
        times.append(time.perf_counter() - t)
    return sorted(times)[len(times) // 2]


def cold_and_warm(warm_runs=5, details=True):
    """Cold first answer (one run, empty cache), warm first answer (median of ``warm_runs``
    fresh interpreters on the filled cache), both p0 ratios, and with ``details``
    :func:`stages` and :func:`trivial_numba` (else None, None)."""
    with tempfile.TemporaryDirectory(prefix="fastline-numba-") as d:
        cold, p_cold = first_answer(d)
        runs = sorted(first_answer(d) for _ in range(warm_runs))
        warm, p_warm = runs[len(runs) // 2]
        staged = stages(d) if details else None
        floor = trivial_numba(d) if details else None
    return cold, warm, p_cold, p_warm, staged, floor


def test_first_answer(benchmark):
    benchmark.group = "startup"
    cold, warm, p_cold, p_warm, _, _ = benchmark.pedantic(
        cold_and_warm, kwargs=dict(warm_runs=1, details=False), rounds=1, iterations=1
    )
    benchmark.extra_info.update(cold_seconds=cold, warm_seconds=warm, p0_ratio=p_warm)
    assert p_cold == p_warm and 0.0 < p_warm < 2.0
