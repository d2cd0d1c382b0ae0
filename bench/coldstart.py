"""Cold, fallback and warm start of a fresh process, as a user meets them.

``python -m bench.coldstart [--runs 5]`` copies the package's sources (no cache) to a temporary
installation and measures, each as whole processes started from the shell (time to the printed
answer of one line-contact solve, min and median of ``--runs``):

* fallback: an empty Numba cache (``NUMBA_CACHE_DIR`` a new empty directory per run): every
  kernel the solve reaches is compiled at first use;
* ``fastline compile``: its wall time and its groups' CPU seconds, once, on the copy;
* after compile: a new process of the compiled copy (the kernels loaded from the cache);
* after a copy: the compiled installation copied to another path (new files, new times);
* warm: the same copy, again (the figure the two above must match).

Each run also reports the kernels it compiled (Numba's ``numba:compile`` event), so a cache
that did not serve shows as a count, not only as seconds. The machine's load is printed: on a
shared machine, compare the figures of one run with each other.
"""

from __future__ import annotations

import argparse
import json
import os
import resource
import shutil
import statistics
import subprocess
import sys
import tempfile
import time

import fastline

#: the first answer: one line-contact solve, with the count of kernels compiled
SCRIPT = (
    "import time\n"
    "from numba.core import event\n"
    "n = [0]\n"
    "class C(event.Listener):\n"
    "    def on_start(self, e): n[0] += 1\n"
    "    def on_end(self, e): pass\n"
    "event.register('numba:compile', C())\n"
    "import fastline as fl\n"
    "psd = fl.SelfAffinePSD(10e-6, 0.8, 1e3, 1e4, 1e9)\n"
    "r = fl.solve_line_contact(psd, 1.33e9, 0.01, 1.0e4, warn=False)\n"
    "print(r.p0_ratio, n[0], fl.__file__)\n"
)


def _env(cache_dir=None, parent=None):
    env = dict(os.environ)
    for name in ("NUMBA_CACHE_DIR", "FASTLINE_NUMBA_CACHE", "PYTHONDONTWRITEBYTECODE"):
        env.pop(name, None)
    if cache_dir:
        env["NUMBA_CACHE_DIR"] = cache_dir
    if parent:
        env["PYTHONPATH"] = parent
    return env


def _children_cpu():
    r = resource.getrusage(resource.RUSAGE_CHILDREN)
    return r.ru_utime + r.ru_stime


def first_answer(parent, cache_dir=None):
    """``(seconds to the printed answer, kernels compiled, CPU seconds of the whole process)``
    of a fresh interpreter importing the fastline under ``parent``."""
    cpu = _children_cpu()
    t = time.perf_counter()
    proc = subprocess.Popen(
        [sys.executable, "-u", "-c", SCRIPT],
        env=_env(cache_dir, parent),
        cwd=parent,
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )
    line = proc.stdout.readline()
    seconds = time.perf_counter() - t
    _, err = proc.communicate()
    if proc.returncode:
        raise RuntimeError(err)
    _, compiled, where = line.split()
    assert where.startswith(parent), where  # the copy, not the checkout
    return seconds, int(compiled), _children_cpu() - cpu


def series(label, runs, call):
    """Run ``call`` ``runs`` times; print and return min, median and the compile counts."""
    results = [call() for _ in range(runs)]
    secs = [s for s, _, _ in results]
    counts = sorted({c for _, c, _ in results})
    cpu = statistics.median(c for _, _, c in results)
    row = dict(label=label, min=min(secs), median=statistics.median(secs), compiled=counts)
    row.update(cpu=cpu, load=os.getloadavg()[0])
    print(
        f"{label:<40} min {row['min']:6.2f} s  median {row['median']:6.2f} s  "
        f"CPU (median) {cpu:6.2f} s  kernels compiled per run {counts}  load {row['load']:.1f}",
        flush=True,
    )
    return row


def _copy_sources(dest):
    src = os.path.dirname(fastline.__file__)
    shutil.copytree(
        src, os.path.join(dest, "fastline"), ignore=shutil.ignore_patterns("__pycache__")
    )


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--runs", type=int, default=5)
    parser.add_argument("--skip-fallback", action="store_true", help="no empty-cache runs")
    parser.add_argument("--json", metavar="FILE", help="write the rows to FILE")
    args = parser.parse_args(argv)
    print(f"load average at start: {os.getloadavg()[0]:.1f} ({os.cpu_count()} CPUs)")
    rows = []
    with tempfile.TemporaryDirectory(prefix="fastline-coldstart-") as tmp:
        a, b = os.path.join(tmp, "a"), os.path.join(tmp, "b")
        _copy_sources(a)
        if not args.skip_fallback:

            def cold():
                with tempfile.TemporaryDirectory(prefix="numba-") as cache:
                    return first_answer(a, cache)

            rows.append(series("fallback: empty cache", args.runs, cold))
        t, cpu = time.perf_counter(), _children_cpu()
        out = subprocess.run(
            [sys.executable, "-m", "fastline", "compile"],
            env=_env(None, a),
            cwd=a,
            capture_output=True,
            text=True,
            check=True,
        )
        wall, cpu = time.perf_counter() - t, _children_cpu() - cpu
        print(f"fastline compile: {wall:.1f} s wall, {cpu:.1f} s CPU\n{out.stdout}", flush=True)
        rows.append(dict(label="fastline compile", seconds=wall, cpu=cpu, output=out.stdout))
        rows.append(series("after fastline compile", args.runs, lambda: first_answer(a)))
        shutil.copytree(a, b, copy_function=shutil.copy)  # new files, new times
        rows.append(series("after copying to another path", args.runs, lambda: first_answer(b)))
        rows.append(series("warm (the first copy, again)", args.runs, lambda: first_answer(a)))
    print(f"load average at end: {os.getloadavg()[0]:.1f}")
    if args.json:
        with open(args.json, "w") as f:
            json.dump(rows, f, indent=1)
    return rows


#: the section's text before the measured table (docs/performance.md)
PROSE = """## Cold, fallback and warm start

fastline's kernels are compiled by Numba for the CPU that runs them and kept in Numba's on-disk
cache: beside the installed sources (`__pycache__/*.nbi`, `*.nbc`), or under `NUMBA_CACHE_DIR`
when that is set. A new process starts in one of three ways:

- **warm**: the cache holds every kernel it calls, which load in a fraction of a second;
- **after `fastline compile`**: the same, for a fresh installation. `fastline compile` (or
  `python -m fastline compile`, or `fl.compile_kernels()` in Python) compiles every kernel a
  user can reach (the line contact with its laws and nested start, sweeps, the point contact,
  the Persson tables, leakage), one group of kernels per process, several at once on a machine
  with more than one core;
- **fallback**: the cache holds nothing for this machine (an installation not compiled, another
  CPU, another Numba or Python, an edited module, or `FASTLINE_NUMBA_CACHE=0`). The kernels a
  call needs compile at its first use, and the process says so once, on stderr, before it waits:

```text
fastline: compiling the solver for this machine, once: ~15 s (`fastline compile` ...)
```

  On a machine with more than one core, the line contact's largest kernel, the solver of its
  Newton systems (`elastic/pcg.py`), then compiles in a second Python process meanwhile, into
  the cache, from which the first process loads it: the Newton kernel calls it through its
  machine-code address, so neither waits for the other to be compiled, and its code is compiled
  once instead of once more inside the Newton kernel. `FASTLINE_PARALLEL_COMPILE=0` keeps the
  compilation in the one process (the second process needs the cache on, and is started with
  the same Python and environment).

In Python the notice is a message of level WARNING on the logger `"fastline"` (printed on stderr
when logging is not configured). A program that embeds fastline silences it with
`logging.getLogger("fastline").setLevel(logging.ERROR)`.

Numba keys each cached kernel by a hash of its source file, the CPU's name and features and the
Numba and Python versions; fastline adds a hash of the contents of every module of the package
(a kernel holds the kernels it calls, compiled in, from other files, so any edit recompiles all).
Nothing in the key depends on where the package lies or on its files' times: a compiled
installation copied elsewhere (a container image layer, an install with pip's `--target`, a shared
network install) keeps its kernels.

Recipes:

```bash
# a virtual environment (the README's set-up does this):
.venv/bin/pip install ".[plot]" && .venv/bin/fastline compile
# a container image (in its build, as the user who will run it; the cache lands beside the
# installed sources), from the checkout:  RUN pip install ".[plot]" && fastline compile
# a read-only installation: a cache directory the running user can write, the same path
# at build and at run time:  NUMBA_CACHE_DIR=/var/cache/fastline-numba fastline compile
```

The workers of a dask cluster each compile for their own machine: bake `fastline compile` into
the workers' image as above, or once per cluster, from the client,
`client.run(fl.compile_kernels)` (each worker compiles in its own installation; workers of one
machine share the cache, which Numba writes atomically). `pip install` itself does not compile:
a build step would run in pip's isolated build environment, which would need its own Numba,
NumPy, SciPy and pyFFTW, possibly of other versions than those installed, so `fastline compile`
after the install costs the same compilation once with the installed versions.

The measurements below: `python -m bench.coldstart` (whole processes started from the shell,
the time to the printed p0 ratio of one line-contact solve at n = 1024, min and median of 5 each,
one run of the script; a copy of the package's sources serves as the installation, compiled by
`fastline compile` and then copied to another path). Beside the times, the kernels each start
compiled (Numba's `numba:compile` event), the CPU seconds of the whole process and the
machine's load average (1 min) after each series: on a shared machine the wall times grow with
the load, the CPU times and counts much less.
"""


def markdown(rows) -> list[str]:
    """The cold-start section of docs/performance.md from :func:`main`'s rows."""
    by = {r["label"]: r for r in rows}
    L = [PROSE]
    L.append("| start | min | median | CPU of the process (median) | kernels compiled | load |")
    L.append("|---|---|---|---|---|---|")
    for label, row in by.items():
        if "min" in row:
            counts = ", ".join(str(c) for c in row["compiled"])
            L.append(
                f"| {label} | {row['min']:.2f} s | {row['median']:.2f} s | {row['cpu']:.2f} s "
                f"| {counts} | {row['load']:.1f} |"
            )
    if "fastline compile" in by:
        c = by["fastline compile"]
        L.append(
            f"\n`fastline compile` itself: {c['seconds']:.1f} s wall, {c['cpu']:.1f} s CPU in "
            "all its processes:\n"
        )
        L.append("```text\n" + c["output"].rstrip() + "\n```\n")
    return L


if __name__ == "__main__":
    main()
