"""The Python (GIL-held) time of a warm solve and the 2-thread speed-up: ``python -m bench.gil``.

Threads solving different scenes run in parallel only while a solve is inside a ``nogil``
compiled kernel; the Python around the kernels (checks, result, diagnostics, the kernels'
dispatch) holds the GIL and serialises them. Measured here:

* **GIL-held time** of a warm ``LineContact.solve``: the Newton kernel
  (:func:`fastline.contact.line_newton.newton_line`, as :mod:`fastline.elastic.line` keeps it) is
  replaced by a compiled stub with the same argument types (the same dispatch cost) that
  replays the recorded outputs of the real one, so the stubbed solve takes the Python time
  plus the other kernels' compiled work; that work is timed alone in compiled loops and
  subtracted. CPU time of this thread, best of many calls.
* **2-thread speed-up**: wall time of S solves of different loads in turn, over the wall time
  of the same solves split between 2 threads of one shared model (every other load each, no
  pool: a pool's hand-over of each task costs GIL time of its own); min / median / max over
  ``--runs`` runs (the machine's other load shows as spread). Beside it, in the same runs, the
  same split on 2 forked processes: the machine's own ceiling at that moment.

Options: ``--ns 256 1024``, ``--runs 9``.
"""

from __future__ import annotations

import argparse
import contextlib
import math
import multiprocessing
import statistics
import threading
import time
import warnings

import numba
import numpy as np

import fastline as fl
from fastline.contact import kernels, line_newton
from fastline.contact import line as _line_contact
from fastline.contact import model as _contact
from fastline.reports.paper import E_STAR, RADIUS, load_for_alpha, surfaces

ALPHAS = (1.0, 1e-2)
#: solves per thread run: ~0.1-0.2 s serial at n = 256 / 1024
SOLVES = {256: 400, 1024: 120}


def cpu_best(fn, repeat: int) -> float:
    """Best CPU time of this thread (s) over ``repeat`` calls, after one warm-up."""
    fn()
    best = math.inf
    for _ in range(repeat):
        t = time.thread_time_ns()
        fn()
        best = min(best, time.thread_time_ns() - t)
    return best * 1e-9


def _replay(v_end, u_end, hist_end, scalars):
    """A compiled stand-in for ``newton_line`` that writes the recorded outputs."""
    u1, res, status, steps, cg, kapps, circ, tol_eff = scalars

    @numba.njit(nogil=True)
    def stub(fft, tables, op, scene, law, v, settings, out):
        h, u = out.hist, out.u
        for i in range(v.shape[0]):
            v[i] = v_end[i]
            u[i] = u_end[i]
        for i in range(hist_end.shape[0]):
            for j in range(3):
                h[i, j] = hist_end[i, j]
        return u1, res, status, steps, cg, kapps, circ, tol_eff

    return stub


@contextlib.contextmanager
def newton_replayed(lc: fl.LineContact, load: float):
    """Within: ``lc.solve(load)`` runs everything but the Newton iteration (module docstring).
    Yields the compiled kernels' arguments of one solve (name -> args, first call)."""
    real = line_newton.newton_line
    calls: dict = {}
    spied = []
    for mod, name in (
        (_contact, "cold_start_normalised"),
        (_line_contact, "line_cells"),
        (_line_contact, "line_measures"),
        (kernels, "pressure_into"),
    ):
        fn = getattr(mod, name)
        spied.append((mod, name, fn))

        def spy(*args, _fn=fn, _name=name):
            copied = tuple(a.copy() if isinstance(a, np.ndarray) else a for a in args)
            calls.setdefault(_name, copied)
            return _fn(*args)

        setattr(mod, name, spy)

    def record(*args):
        out = real(*args)
        calls.setdefault(
            "newton_line", (args[5].copy(), args[7].u.copy(), args[7].hist.copy(), out)
        )
        return out

    line_newton.newton_line = record
    try:
        reference = lc.solve(load)
        for mod, name, fn in spied:
            setattr(mod, name, fn)
        line_newton.newton_line = _replay(*calls.pop("newton_line"))
        replayed = lc.solve(load)
        assert np.array_equal(replayed.pressure, reference.pressure)
        yield calls
    finally:
        for mod, name, fn in spied:
            setattr(mod, name, fn)
        line_newton.newton_line = real


@numba.njit(nogil=True)
def _cold_loop(reps, x, profiles, load, w, out):
    for _ in range(reps):
        kernels.cold_start_normalised(x, profiles, load, w, out)


@numba.njit(nogil=True)
def _cells_loop(reps, dx, two_r, x, gap, w):
    for _ in range(reps):
        kernels.line_cells(dx, two_r, x, gap, w)
        x[0] += 0.0  # (keeps the loop from being hoisted)


@numba.njit(nogil=True)
def _pressure_loop(reps, v, p):
    for _ in range(reps):
        kernels.pressure_into(v, p)


@numba.njit(nogil=True)
def _measures_loop(reps, x, p, dx):
    acc = 0.0
    for _ in range(reps):
        acc += kernels.line_measures(x, p, dx)[0]
    return acc


def compiled_work(calls: dict, reps: int = 2000) -> dict:
    """CPU time (s) of each recorded kernel call, timed in a compiled loop (no dispatch)."""
    loops = {
        "cold_start_normalised": _cold_loop,
        "line_cells": _cells_loop,
        "pressure_into": _pressure_loop,
        "line_measures": _measures_loop,
    }
    return {
        name: cpu_best(lambda f=loops[name], a=args: f(reps, *a), repeat=5) / reps
        for name, args in calls.items()
    }


def gil_held(n: int, alpha: float, repeat: int = 2000, warn: bool = False) -> dict:
    """Times (s) of a warm solve of surface 1: ``solve``, ``replayed`` (Newton replaced),
    ``kernels`` (the other kernels' compiled work) and ``gil`` = replayed - kernels. With
    ``warn`` the model assesses each result during the solve (its validity warnings, ignored
    here, are emitted then)."""
    lc = fl.LineContact(surfaces()[0], E_STAR, RADIUS, n=n, warn=warn)
    load = load_for_alpha(alpha)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        solve = cpu_best(lambda: lc.solve(load), max(50, repeat // 4))
        with newton_replayed(lc, load) as calls:
            replayed = cpu_best(lambda: lc.solve(load), repeat)
    work = sum(compiled_work(calls).values())
    return dict(solve=solve, replayed=replayed, kernels=work, gil=replayed - work)


def _on_two_threads(lc: fl.LineContact, loads: np.ndarray) -> float:
    """Wall time (s) of two threads, each solving every other load, started together."""
    start = threading.Barrier(3)

    def run(part):
        start.wait()
        for f in part:
            lc.solve(f)

    workers = [threading.Thread(target=run, args=(loads[k::2],)) for k in (0, 1)]
    for t in workers:
        t.start()
    start.wait()
    t0 = time.perf_counter()
    for t in workers:
        t.join()
    return time.perf_counter() - t0


#: the model the forked worker processes of :func:`parallel_speedups` solve with (set before
#: the pool forks, so each worker inherits it with its compiled kernels and FFT plans)
_MODEL: fl.LineContact | None = None


def _solve_part(loads: np.ndarray) -> None:
    for f in loads:
        _MODEL.solve(f)


def _on_two_processes(pool, loads: np.ndarray) -> float:
    """Wall time (s) of two worker processes, each solving every other load."""
    t0 = time.perf_counter()
    pool.map(_solve_part, [loads[0::2], loads[1::2]], chunksize=1)
    return time.perf_counter() - t0


def parallel_speedups(n: int, runs: int, solves: int | None = None) -> dict[str, list[float]]:
    """Serial wall time over the wall time of the same ``solves`` solves (loads 1e3..1e6 N/m,
    surface 1, one shared model; the loads split in two) on 2 threads and on 2 forked
    processes, interleaved in each run: one figure per run for each. The processes share
    nothing, so their speed-up is what this machine gives any parallel code at that moment
    (two cores that are hyperthreads of one, or busy with other work, give less than 2)."""
    global _MODEL
    lc = _MODEL = fl.LineContact(surfaces()[0], E_STAR, RADIUS, n=n, warn=False)
    loads = np.geomspace(1e3, 1e6, solves or SOLVES.get(n, 120))
    out: dict[str, list[float]] = {"threads": [], "processes": []}
    with multiprocessing.get_context("fork").Pool(2) as pool:
        _on_two_threads(lc, loads[:16])  # both threads and both workers warm (plans, caches)
        _on_two_processes(pool, loads[:16])
        for _ in range(runs):
            t = time.perf_counter()
            for f in loads:
                lc.solve(f)
            serial = time.perf_counter() - t
            out["threads"].append(serial / _on_two_threads(lc, loads))
            out["processes"].append(serial / _on_two_processes(pool, loads))
    return out


def main(argv=None) -> None:  # pragma: no cover - a report
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--ns", type=int, nargs="+", default=[256, 1024])
    ap.add_argument("--runs", type=int, default=9)
    args = ap.parse_args(argv)
    print("| n | alpha | warm solve | GIL-held | share | GIL-held, warn=True |")
    print("|---|---|---|---|---|---|")
    for n in args.ns:
        for alpha in ALPHAS:
            m, w = gil_held(n, alpha), gil_held(n, alpha, warn=True)
            print(
                f"| {n} | {alpha:g} | {m['solve'] * 1e6:.0f} us | {m['gil'] * 1e6:.1f} us | "
                f"{100 * m['gil'] / m['solve']:.0f}% | {w['gil'] * 1e6:.1f} us |"
            )
    print("\n| n | solves | speed-up min / median / max: 2 threads | 2 processes |")
    print("|---|---|---|---|")
    for n in args.ns:
        runs = parallel_speedups(n, args.runs)
        spread = [sorted(runs[k]) for k in ("threads", "processes")]
        cells = [f"{s[0]:.2f} / {statistics.median(s):.2f} / {s[-1]:.2f}" for s in spread]
        print(f"| {n} | {SOLVES.get(n, 120)} | {cells[0]} | {cells[1]} |")


if __name__ == "__main__":  # pragma: no cover
    main()
