"""Where the first line-contact answer's compilation goes: ``python -m bench.compile_profile``.

Runs the first answer of :mod:`bench.coldstart` (one line-contact solve at n = 1024) in a fresh
interpreter with an empty Numba cache (``NUMBA_CACHE_DIR`` a new temporary directory) and
records Numba's events there: every ``numba:compile`` (one per kernel and signature compiled,
nested when a caller's typing compiles its callee) with its wall and CPU seconds, and the
``numba:llvm_lock`` intervals inside it (LLVM: IR passes, optimisation, linking, machine
code). Prints, per compiled kernel, its own seconds (its callees' compilations taken out) split
into LLVM and the rest (Numba's typing and lowering to IR), the total CPU of the whole process
and the load average.

Options: ``--runs 3`` (several fresh processes; the table of the last, the totals of each),
``--script FILE`` (another first answer, run in the child instead).
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tempfile
import time

from bench.coldstart import SCRIPT as FIRST_ANSWER

#: the child's listener: per compile event its kernel, its nesting depth, and its wall, CPU and
#: LLVM seconds (the LLVM lock's intervals that fall inside it)
PROBE = """
import json, time, sys
from numba.core import event as _ev
_t0, _w0 = time.process_time(), time.perf_counter()
_stack, _rows, _llvm = [], [], [0.0, None]
class _Compile(_ev.Listener):
    def on_start(self, e):
        d = e.data["dispatcher"]
        name = d.py_func.__module__ + "." + d.py_func.__qualname__
        _stack.append([name, str(e.data["args"]), time.perf_counter(), time.process_time(),
                       _llvm[0], len(_stack)])
    def on_end(self, e):
        name, args, w, c, l, depth = _stack.pop()
        _rows.append(dict(name=name, args=args, depth=depth, start=w - _w0,
                          wall=time.perf_counter() - w, cpu=time.process_time() - c,
                          llvm=_llvm[0] - l))
class _Llvm(_ev.Listener):
    def on_start(self, e):
        _llvm[1] = time.process_time()
    def on_end(self, e):
        if _llvm[1] is not None:
            _llvm[0] += time.process_time() - _llvm[1]
            _llvm[1] = None
_ev.register("numba:compile", _Compile())
_ev.register("numba:llvm_lock", _Llvm())
"""
TAIL = """
import resource
_kids = resource.getrusage(resource.RUSAGE_CHILDREN)
sys.stdout.flush()
print("PROFILE " + json.dumps(dict(rows=_rows, cpu=time.process_time() - _t0, llvm=_llvm[0],
                                  helper_cpu=_kids.ru_utime + _kids.ru_stime)))
"""


def profile(script: str = FIRST_ANSWER, package: str | None = None) -> dict:
    """One fresh process with an empty cache: ``{rows, cpu, llvm, helper_cpu, wall}`` (module
    docstring); ``package``: the directory holding the fastline to import (default: the
    current directory's)."""
    with tempfile.TemporaryDirectory(prefix="numba-") as cache:
        env = dict(os.environ, NUMBA_CACHE_DIR=cache)
        env.pop("FASTLINE_NUMBA_CACHE", None)
        if package:
            env["PYTHONPATH"] = package
        t = time.perf_counter()
        out = subprocess.run(
            [sys.executable, "-c", PROBE + script + TAIL],
            env=env,
            cwd=package,
            capture_output=True,
            text=True,
            check=True,
        )
        wall = time.perf_counter() - t
    line = next(s for s in out.stdout.splitlines() if s.startswith("PROFILE "))
    result = json.loads(line[len("PROFILE ") :])
    result["wall"] = wall
    return result


def own_seconds(rows: list[dict]) -> list[dict]:
    """Each row with ``self_cpu`` and ``self_llvm``: its seconds minus its direct children's
    (rows are in the order the compilations ended, children before their parent)."""
    out = []
    pending: list[dict] = []  # finished rows whose parent has not ended yet
    for row in rows:
        kids = [r for r in pending if r["depth"] == row["depth"] + 1]
        pending = [r for r in pending if r["depth"] <= row["depth"]] + [row]
        row = dict(row)
        row["self_cpu"] = row["cpu"] - sum(k["cpu"] for k in kids)
        row["self_llvm"] = row["llvm"] - sum(k["llvm"] for k in kids)
        out.append(row)
    return out


def table(result: dict) -> list[str]:
    rows = own_seconds(result["rows"])
    top = sum(r["cpu"] for r in rows if r["depth"] == 0)
    llvm = sum(r["llvm"] for r in rows if r["depth"] == 0)
    L = [
        f"{len(rows)} compilations of {len({r['name'] for r in rows})} kernels: "
        f"{top:.2f} s CPU in compilation ({llvm:.2f} s LLVM, {top - llvm:.2f} s typing and "
        f"lowering); the process {result['cpu']:.2f} s CPU (its second process "
        f"{result['helper_cpu']:.2f} s), {result['wall']:.2f} s wall, "
        f"load {os.getloadavg()[0]:.1f}",
        f"{'kernel (own seconds, callees out)':<58} {'CPU':>6} {'LLVM':>6} {'with callees':>12}",
    ]
    for r in sorted(rows, key=lambda r: -r["self_cpu"]):
        name = r["name"].replace("fastline.", "")
        L.append(
            f"{'  ' * r['depth'] + name:<58} {r['self_cpu']:6.2f} {r['self_llvm']:6.2f} "
            f"{r['cpu']:12.2f}"
        )
    return L


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--runs", type=int, default=1)
    parser.add_argument("--script", help="a Python file run as the first answer instead")
    parser.add_argument("--json", metavar="FILE", help="write the last run's rows to FILE")
    parser.add_argument(
        "--package",
        action="append",
        help="a directory holding another fastline to profile in turn (repeatable; "
        "default: the current directory's)",
    )
    args = parser.parse_args(argv)
    script = FIRST_ANSWER
    if args.script:
        with open(args.script) as f:
            script = f.read()
    print(f"load average at start: {os.getloadavg()[0]:.1f} ({os.cpu_count()} CPUs)")
    result = None
    packages = args.package or [None]
    for k in range(args.runs * len(packages)):
        package = packages[k % len(packages)]
        result = profile(script, package)
        rows = result["rows"]
        top = sum(r["cpu"] for r in rows if r["depth"] == 0)
        llvm = sum(r["llvm"] for r in rows if r["depth"] == 0)
        print(
            f"run {k // len(packages) + 1} ({package or 'here'}): {len(rows)} compilations, "
            f"{top:.2f} s CPU compiling "
            f"({llvm:.2f} LLVM), process {result['cpu']:.2f} s CPU (second process "
            f"{result['helper_cpu']:.2f} s), {result['wall']:.2f} s wall, "
            f"load {os.getloadavg()[0]:.1f}",
            flush=True,
        )
    print("\n".join(table(result)))
    if args.json:
        with open(args.json, "w") as f:
            json.dump(result, f, indent=1)


if __name__ == "__main__":
    main()
