"""Fresh-process time to a first answer: cold (empty Numba cache) and warm (cache filled)."""

from __future__ import annotations

import os
import subprocess
import sys
import tempfile
import time
from typing import NamedTuple

SCRIPT = (
    "import fastline as fl\n"
    "from fastline.contact.line import solve_line_contact\n"
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


def _timed(args, env):
    """``(seconds to the first line the child prints, seconds to its exit, that line)`` for a
    fresh interpreter started now (unbuffered, so the line arrives when it is printed). The
    exit holds Numba's and LLVM's teardown (~0.3 s here), which comes after the answer."""
    t = time.perf_counter()
    proc = subprocess.Popen(
        [sys.executable, "-u", *args],
        env=env,
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )
    line = proc.stdout.readline()
    t_answer = time.perf_counter() - t
    _, err = proc.communicate()
    t_exit = time.perf_counter() - t
    if proc.returncode:
        raise subprocess.CalledProcessError(proc.returncode, args, line, err)
    return t_answer, t_exit, line.strip()


def first_answer(cache_dir):
    """``(seconds to the printed p0 ratio, seconds to exit, p0 ratio)`` of a fresh interpreter
    that imports fastline and solves one scene."""
    t_answer, t_exit, line = _timed(["-c", SCRIPT], _environment(cache_dir))
    return t_answer, t_exit, float(line)


#: the same first answer, with a clock read after each stage of start-up
STAGED = (
    "import time\n"
    "t = [time.perf_counter()]\n"
    "import numpy\n"
    "t.append(time.perf_counter())\n"
    "import numba\n"
    "t.append(time.perf_counter())\n"
    "import fastline as fl\n"
    "from fastline.contact.line import solve_line_contact\n"
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
    """``(seconds to its printed answer, seconds to exit)``, medians over ``runs`` fresh
    interpreters running :data:`TRIVIAL` with its cache filled: what any Numba program pays on
    this machine before its own work."""
    script = os.path.join(cache_dir, "trivial_numba.py")
    with open(script, "w") as f:
        f.write(TRIVIAL)
    env = _environment(cache_dir)
    _timed([script], env)
    times = sorted(_timed([script], env)[:2] for _ in range(runs))
    return times[len(times) // 2]


class Startup(NamedTuple):
    """Fresh-process start-up (s): to the printed answer, and to the process's exit."""

    cold: float
    warm: float
    cold_exit: float
    warm_exit: float
    p_cold: float
    p_warm: float
    staged: list | None
    floor: tuple[float, float] | None


def cold_and_warm(warm_runs=5, details=True) -> Startup:
    """Cold first answer (one run, empty cache), warm first answer (median of ``warm_runs``
    fresh interpreters on the filled cache, by time to the answer), both p0 ratios, and with
    ``details`` :func:`stages` and :func:`trivial_numba` (else None, None)."""
    with tempfile.TemporaryDirectory(prefix="fastline-numba-") as d:
        cold, cold_exit, p_cold = first_answer(d)
        runs = sorted(first_answer(d) for _ in range(warm_runs))
        warm, warm_exit, p_warm = runs[len(runs) // 2]
        staged = stages(d) if details else None
        floor = trivial_numba(d) if details else None
    return Startup(cold, warm, cold_exit, warm_exit, p_cold, p_warm, staged, floor)


def test_first_answer(benchmark):
    benchmark.group = "startup"
    s = benchmark.pedantic(
        cold_and_warm, kwargs=dict(warm_runs=1, details=False), rounds=1, iterations=1
    )
    benchmark.extra_info.update(
        cold_seconds=s.cold, warm_seconds=s.warm, warm_exit_seconds=s.warm_exit, p0_ratio=s.p_warm
    )
    assert s.p_cold == s.p_warm and 0.0 < s.p_warm < 2.0
    assert s.warm <= s.warm_exit
