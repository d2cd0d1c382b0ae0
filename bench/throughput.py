"""Sweep throughput: ``python -m bench.throughput`` writes docs/throughput.md.

10,000 paper-like scenes (the paper's three surfaces, loads for alpha log-spaced over
1e-3..1e3, n = 256, shuffled) through :func:`fastline.sweep`: serially, on 2 local processes
and on a ``dask.distributed.LocalCluster`` with 2 worker processes. Every number on the page is
measured by this script; the page is never edited by hand.

Besides scenes per second it reports what the engine adds over the solves themselves, so the
figure keeps its meaning when solves get faster:

* ``solve time`` is the serial run's time inside tasks (the solves and their bookkeeping);
* efficiency = serial solve time / (workers x wall time): 1 is perfect scaling;
* busy = time inside tasks on the workers / (workers x wall time), and the engine's cost per
  task = (workers x wall - time inside tasks) / tasks (scheduling, pickling, idle tails).

Pools are *warm* unless stated: started, with fastline imported and the three theories built
by a small sweep before the timed one (a long-running service keeps its pool). The *cold*
row includes starting the pool inside :func:`fastline.sweep`.

Options: ``--scenes N`` (10000), ``--n N`` (256), ``--repeat K`` (3, best of), ``--out PATH``.
"""

from __future__ import annotations

import argparse
import concurrent.futures as cf
import datetime
import logging
import multiprocessing
import os
import platform
import sys
import time
import warnings
from pathlib import Path

import numpy as np

import fastline as fl
from fastline.reports.paper import E_STAR, Q0, Q1, QR, RADIUS, SURFACES, load_for_alpha

ROOT = Path(__file__).resolve().parent.parent
WORKERS = 2
TARGET = 2000.0  # scenes/s with 2 processes (the standing target)
CHUNKSIZES = (8, 32)  # besides the default, on the warm pool
LOAD = (0.0, 0.0, 0.0)  # load average when the measurement starts
REPEAT = 3


def paper_scenes(count: int, n: int, seed: int = 0) -> list[dict]:
    """``count`` scenes: the three surfaces in turn, alpha log-spaced over 1e-3..1e3, shuffled."""
    rows = []
    per = [count // 3 + (k < count % 3) for k in range(3)]
    for (_label, h_rms, hurst), m in zip(SURFACES, per, strict=True):
        for alpha in np.geomspace(1e-3, 1e3, m):
            load = float(load_for_alpha(alpha, h_rms))
            rows.append(
                dict(h_rms=h_rms, hurst=hurst, q0=Q0, qr=QR, q1=Q1, E_star=E_STAR, radius=RADIUS,
                     load=load, n=n)
            )  # fmt: skip
    order = np.random.default_rng(seed).permutation(len(rows))
    return [rows[i] for i in order]


def run_once(scenes, executor, **kw) -> fl.SweepTable:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return fl.sweep(scenes, executor, progress=False, **kw)


def warm(executor, n: int) -> None:
    """Import fastline and build the three theories on every worker (many small tasks)."""
    run_once(paper_scenes(96, n, seed=1), executor, chunksize=1)


def row(label: str, res: fl.SweepTable, workers: int, serial: fl.SweepTable) -> dict:
    st, ref = res.stats, serial.stats
    busy = st.compute_seconds / (workers * st.wall_seconds)
    return dict(
        label=label,
        workers=workers,
        tasks=st.tasks,
        chunksize=st.chunksize,
        wall=st.wall_seconds,
        rate=st.scenes_per_second,
        compute=st.compute_seconds,
        cpu=st.compute_cpu_seconds,
        efficiency=ref.compute_seconds / (workers * st.wall_seconds),
        busy=busy,
        cpu_share=st.compute_cpu_seconds / st.compute_seconds,
        projected=workers * busy * st.scenes / ref.compute_cpu_seconds,
        per_task_ms=1e3 * (workers * st.wall_seconds - st.compute_seconds) / st.tasks,
        failed=int(res.failed.sum()),
        unconverged=len(res) - int(res.failed.sum()) - int(res.ok.sum()),
    )


def same_numbers(a: fl.SweepTable, b: fl.SweepTable) -> bool:
    return all(
        np.array_equal(a[k].view(np.int64), b[k].view(np.int64))
        for k in ("p0", "p0_ratio", "s", "fwhm", "residual")
    )


def dask_cluster():
    """A LocalCluster with 2 worker processes (or None without dask)."""
    try:
        from distributed import LocalCluster
    except ImportError:
        return None
    return LocalCluster(
        n_workers=WORKERS,
        processes=True,
        threads_per_worker=1,
        dashboard_address=None,
        silence_logs=logging.ERROR,
    )


def measure(count: int, n: int, repeat: int) -> tuple[list[dict], dict]:
    """Every run ``repeat`` times, interleaved (serial, pools, dask in turn, so that a busy
    spell of the machine does not land on one of them only); the fastest of each is kept."""
    scenes = paper_scenes(count, n)
    t0 = time.perf_counter()
    cold = run_once(scenes, None, workers=WORKERS)
    cold_total = time.perf_counter() - t0
    ctx = multiprocessing.get_context("spawn")
    cluster = dask_cluster()
    with cf.ProcessPoolExecutor(WORKERS, mp_context=ctx) as pool:
        runs = {"serial": ("serial", None), "pool": (pool, None)}
        runs.update({f"pool{c}": (pool, c) for c in CHUNKSIZES})
        client = None
        if cluster is not None:
            from distributed import Client

            client = Client(cluster)
            runs["dask"] = (client, None)
        for executor, _ in runs.values():
            warm(executor, n)
        best: dict[str, fl.SweepTable] = {}
        for _ in range(repeat):
            for name, (executor, chunk) in runs.items():
                res = run_once(scenes, executor, chunksize=chunk)
                if name not in best or res.stats.wall_seconds < best[name].stats.wall_seconds:
                    best[name] = res
        if client is not None:
            client.close()
            cluster.close()
    serial = best["serial"]
    rows = [
        row("serial (in-process)", serial, 1, serial),
        row("2 processes, cold (pool started by sweep)", cold, WORKERS, serial),
        row("2 processes, warm pool", best["pool"], WORKERS, serial),
    ]
    rows += [
        row(f"2 processes, warm pool, chunksize {c}", best[f"pool{c}"], WORKERS, serial)
        for c in CHUNKSIZES
    ]
    checks = {
        "serial_convolutions": int(serial["convolutions"].sum()),
        "cold_pool_total": cold_total,
        "pool_equal": same_numbers(cold, serial) and same_numbers(best["pool"], serial),
    }
    if "dask" in best:
        rows.append(row("dask LocalCluster, 2 worker processes", best["dask"], WORKERS, serial))
        checks["dask_equal"] = same_numbers(best["dask"], serial)
    return rows, checks


def page(rows: list[dict], checks: dict, count: int, n: int, seconds: float) -> str:
    import numba
    import scipy

    pool = next(r for r in rows if r["label"] == "2 processes, warm pool")
    serial = rows[0]
    met = pool["rate"] >= TARGET
    lines = [
        "# Sweep throughput",
        "",
        "_Generated by `python -m bench.throughput`; do not edit by hand._",
        "",
        f"- Date: {datetime.datetime.now(datetime.UTC):%Y-%m-%d %H:%M} UTC",
        f"- Machine: {platform.platform()}, {os.cpu_count()} CPUs, shared with other jobs "
        f"(load average {LOAD[0]:.1f} at the start, {os.getloadavg()[0]:.1f} at the end): "
        "wall times are noisy; *busy* and the CPU times are what carry over",
        f"- Versions: python {platform.python_version()}, numpy {np.__version__}, numba "
        f"{numba.__version__}, scipy {scipy.__version__}, fastline {fl.__version__}",
        f"- Scenes: {count} paper-like scenes: the paper's three surfaces (E* = {E_STAR:g} Pa, "
        f"R = {RADIUS:g} m), loads for alpha log-spaced over 1e-3..1e3, n = {n}, tol 1e-8, "
        "shuffled.",
        f"- Method: every run {REPEAT} times, interleaved (serial, pools and dask in turn), the "
        f"fastest of each kept; pools warm unless stated. Script runtime {seconds:.0f} s.",
        "",
        "## Standing target: scenes per second",
        "",
        "| target | measured | met? | margin |",
        "|---|---|---|---|",
        f"| >= {TARGET:.0f} scenes/s with 2 processes | {pool['rate']:.0f} scenes/s "
        f"(efficiency {pool['efficiency']:.2f}, busy {pool['busy']:.2f}) | "
        f"{'yes' if met else 'no'} | {pool['rate'] / TARGET:.2f}x |",
        "",
        f"A scene costs {1e3 * serial['cpu'] / count:.3f} ms of CPU in the serial run "
        f"({serial['rate']:.0f} scenes/s serial), so 2 processes on two idle cores could at "
        f"best give {2 * count / serial['cpu']:.0f} scenes/s: the target depends on the "
        "per-solve cost, which falls as the solver gets faster. What the engine costs "
        f"is *busy*: the workers spent {100 * pool['busy']:.0f}% of their time solving "
        f"({pool['projected']:.0f} scenes/s projected on two idle cores).",
        "",
        "## Runs",
        "",
        "| run | tasks (scenes each) | wall s | scenes/s | in tasks s (CPU s) | efficiency | "
        "busy | CPU share | engine ms/task | projected scenes/s |",
        "|---|---|---|---|---|---|---|---|---|---|",
    ]
    for r in rows:
        lines.append(
            f"| {r['label']} | {r['tasks']} ({r['chunksize']}) | {r['wall']:.2f} | "
            f"{r['rate']:.0f} | {r['compute']:.2f} ({r['cpu']:.2f}) | {r['efficiency']:.2f} | "
            f"{r['busy']:.2f} | {r['cpu_share']:.2f} | {r['per_task_ms']:.2f} | "
            f"{r['projected']:.0f} |"
        )
    lines += [
        "",
        "- *in tasks*: wall time inside tasks summed over tasks, measured in the workers "
        "(in brackets: the CPU time of the threads running them).",
        "- *efficiency*: serial solve time (the serial run's time in tasks) / (workers x "
        "wall): 1 is perfect scaling.",
        "- *busy*: time in tasks / (workers x wall): the rest is the engine (checking and "
        "planning the table, pickling, scheduling, waiting for the last task, assembling).",
        "- *CPU share*: CPU time / wall time in tasks: below 1 when the workers waited for a "
        "core held by another job (the machine, not the engine).",
        "- *engine ms/task*: (workers x wall - time in tasks) / tasks.",
        "- *projected*: workers x busy x scenes / (the serial run's CPU time in tasks): the "
        "rate on idle cores if each solve cost what it costs serially.",
        "",
        f"Every run solved the same {count} scenes: "
        f"{serial['failed']} failed, {serial['unconverged']} did not converge (serial run); "
        f"{checks['serial_convolutions']} FFT convolutions in all. Numbers bit-identical to "
        f"the serial run: process pool {'yes' if checks['pool_equal'] else 'NO'}"
        + (
            f", dask {'yes' if checks['dask_equal'] else 'NO'}."
            if "dask_equal" in checks
            else " (dask not installed)."
        ),
        f"The cold pool run took {checks['cold_pool_total']:.2f} s end to end (starting two "
        "spawned processes, importing fastline and building the theories in each).",
        "",
        "Reproduce: `python -m bench.throughput` (two to three minutes on 2 cores; "
        "`--scenes 2000 --repeat 1` for a quick look). The smoke benchmark "
        "`bench/test_bench_batch.py` runs in CI.",
        "",
    ]
    return "\n".join(lines)


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--scenes", type=int, default=10_000)
    parser.add_argument("--n", type=int, default=256)
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--out", default=str(ROOT / "docs" / "throughput.md"))
    args = parser.parse_args(argv)
    global LOAD, REPEAT
    LOAD, REPEAT = os.getloadavg(), args.repeat
    t0 = time.perf_counter()
    rows, checks = measure(args.scenes, args.n, args.repeat)
    text = page(rows, checks, args.scenes, args.n, time.perf_counter() - t0)
    Path(args.out).write_text(text, encoding="utf-8")
    print(text)
    return 0


if __name__ == "__main__":
    sys.exit(main())
