"""Compile every kernel a user can reach, ahead of time, into Numba's on-disk cache.

:func:`compile_kernels` (the command ``fastline compile``) runs a few small scenes in fresh
interpreters, one group of independent kernels per process (:data:`GROUPS`), several at once
when the machine has more than one core. Each process fills Numba's cache (beside the sources,
or under ``NUMBA_CACHE_DIR``), so that a later process loads the machine code instead of
compiling it. The scenes are scripts run by the child interpreters: this module imports no
other part of fastline.

Where the cache does not apply (another CPU, another Numba or Python, an edited source),
fastline compiles at first use as before, and says so once (:mod:`fastline._lib.jit`).
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
import time
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass

__all__ = ["GROUPS", "GroupReport", "compile_kernels", "COUNTER"]

#: prepended to each group's script: counts the fastline kernels the child compiles (Numba's
#: ``numba:compile`` event starts only on a cache miss) and their CPU seconds
COUNTER = """
import json, time, warnings
from numba.core import event as _ev
_count = {"compiled": 0, "kernels": set()}
class _Count(_ev.Listener):
    def on_start(self, e):
        f = e.data["dispatcher"].py_func
        if f.__module__.startswith("fastline."):
            _count["compiled"] += 1
            _count["kernels"].add(f.__module__ + "." + f.__qualname__)
    def on_end(self, e):
        pass
_ev.register("numba:compile", _Count())
_t0 = time.process_time()
warnings.simplefilter("ignore")
import fastline as fl
psd = fl.SelfAffinePSD(10e-6, 0.8, 1e3, 1e4, 1e9)
"""
#: appended: one JSON line with the counts
REPORT = """
print(json.dumps({"compiled": _count["compiled"], "kernels": sorted(_count["kernels"]),
                  "cpu_seconds": time.process_time() - _t0}))
"""

#: the groups of kernels, each reached by a few small scenes through the public API; a group's
#: kernels are compiled in one process, independent groups in parallel (the line contact's
#: Newton solve, the largest, first). A group named in :data:`AFTER` starts when the group it
#: names is done, and loads that group's kernels from the cache instead of compiling them too.
GROUPS = {
    "line contact": """
fl.solve_line_contact(psd, 1.33e9, 0.01, 1.0e4)
fl.solve_line_contact(psd, 1.33e9, 0.01, 3.0e5, n=256)
fl.solve_line_contact(psd, 1.33e9, 0.01, 1.0e4, model="exponential", n=256)
fl.solve_line_contact(psd, 1.33e9, 0.01, 1.0e4, n=4096)
""",
    "line sweeps and leakage": """
lc = fl.LineContact(psd, 1.33e9, 0.01, n=256)
rs = lc.sweep([1.0e4, 1.1e4, 1.2e4, 1.3e4, 4.0e4])
fl.leak_rate(rs[0], 1e4, 1e-3, 1e-2)
fl.w_over_s(psd, 1.33e9, 0.01, [1e3, 1e4])
fl.sweep([dict(psd=psd, E_star=1.33e9, radius=0.01, load=1e4, n=128)], "serial",
         progress=False)
""",
    "point contact": """
r = fl.solve_point_contact(psd, 1.33e9, 0.01, 1.0, n=64)
fl.PointContact(psd, 1.33e9, 0.01, n=64).sweep([0.5, 1.0])
fl.leak_rate(r, 1e4, 1e-3, inner_radius=r.r[len(r.r) // 4])
fl.seal_leak(r, [1e3], 1e-3, inner_radius=r.r[len(r.r) // 4])
""",
    "theory tables": """
t = fl.PerssonTheory(psd, 1.33e9)
t.pressure(t.separation(1e6))
t.contact_area(1e6)
t.critical_gap(1e6)
fl.PerssonTheory(psd, 1.33e9, variant="wang-mueser").separation(1e6)
""",
    "measured surfaces": """
import numpy as np
from fastline import topography as topo
_rng = np.random.default_rng(0)
topo.psd_from_profile(np.cumsum(_rng.standard_normal(4096)) * 1e-9, 1e-6).isotropic()
topo.psd_from_map(np.cumsum(_rng.standard_normal((64, 64)), axis=0) * 1e-9, 1e-6)
""",
}


#: group -> the group whose kernels it calls (the sweep's compiled loop calls the Newton solve)
AFTER = {"line sweeps and leakage": "line contact"}


@dataclass(frozen=True)
class GroupReport:
    """One group's compilation: kernels compiled (0 when the cache already held them all),
    CPU seconds of its process, wall seconds, and the error text if the process failed."""

    name: str
    compiled: int
    cpu_seconds: float
    seconds: float
    error: str = ""


#: the directory that holds this fastline package: put first on the child interpreters' path, so
#: that they compile the installation that asked (``python -c`` would otherwise import a
#: ``fastline`` directory in the working directory first, e.g. a source checkout)
PACKAGE_ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))


def child_script(body: str) -> str:
    """The script a child interpreter runs: this installation first on ``sys.path``, then
    ``body``."""
    return f"import sys\nsys.path.insert(0, {PACKAGE_ROOT!r})\n" + body


def _run_group(name: str, env: dict) -> GroupReport:
    t = time.perf_counter()
    proc = subprocess.run(
        [sys.executable, "-c", child_script(COUNTER + GROUPS[name] + REPORT)],
        capture_output=True,
        text=True,
        env=env,
    )
    seconds = time.perf_counter() - t
    if proc.returncode:
        tail = (proc.stderr.strip().splitlines() or [f"exit status {proc.returncode}"])[-1]
        return GroupReport(name, 0, 0.0, seconds, tail)
    out = json.loads(proc.stdout.strip().splitlines()[-1])
    return GroupReport(name, out["compiled"], out["cpu_seconds"], seconds)


def compile_kernels(jobs: int | None = None, groups: list[str] | None = None) -> list[GroupReport]:
    """Compile every kernel a user can reach into Numba's on-disk cache (``fastline compile``).

    Parameters
    ----------
    jobs : int, optional
        Processes at once; default: the usable CPUs, at most the number of groups.
    groups : list of str, optional
        Names of :data:`GROUPS` to compile; default all.

    Returns
    -------
    list of GroupReport
        One per group, in the order of :data:`GROUPS`: kernels compiled (0 when the cache
        already held them), CPU and wall seconds, an error text when a group failed.

    Notes
    -----
    Run it where the package is installed, as the user (or with the ``NUMBA_CACHE_DIR``) that
    will run fastline, after ``pip install`` (docs/performance.md, cold start). Raises
    ``ValueError`` for an unknown group or ``jobs < 1``.
    """
    names = list(GROUPS) if groups is None else list(groups)
    unknown = [g for g in names if g not in GROUPS]
    if unknown:
        raise ValueError(f"groups must be names of {list(GROUPS)}; got {unknown}")
    cpus = len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else os.cpu_count()
    jobs = min(cpus or 1, len(names)) if jobs is None else jobs
    if not isinstance(jobs, int) or jobs < 1:
        raise ValueError(f"jobs must be an integer >= 1; got {jobs!r}")
    env = dict(os.environ)
    env.pop("FASTLINE_NUMBA_CACHE", None)  # the point is the cache
    with ThreadPoolExecutor(max_workers=max(1, min(jobs, len(names)))) as pool:
        lanes = {g: [g] for g in names if AFTER.get(g) not in names}
        for g in names:
            if AFTER.get(g) in names:
                next(lane for lane in lanes.values() if AFTER[g] in lane).append(g)
        done = pool.map(lambda lane: [_run_group(g, env) for g in lane], lanes.values())
        reports = {r.name: r for lane in done for r in lane}
    return [reports[g] for g in names]
