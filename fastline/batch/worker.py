"""What a worker does: build (or find in its cache) the model of each piece of a task, solve
the piece and send back its rows; and the loop over an executor's tasks
(:func:`task_outcomes`).

A failing scene is reported in its row, never raised: bad values and exceptions inside a
worker become the row's ``error`` text.
"""

from __future__ import annotations

import concurrent.futures as cf
import os
import socket
import threading
import time
from collections import OrderedDict
from dataclasses import dataclass, replace

from fastline._lib.executors import Engine
from fastline.batch.plan import ModelSpec, Piece
from fastline.batch.scenes import GEOMETRIES, NEEDS_THEORY
from fastline.errors import CalibrationFileError
from fastline.io import read_spectrum
from fastline.theory.lawdata import check_law_scene, read_law_file, restore_law
from fastline.theory.persson import PerssonTheory
from fastline.theory.spectra import SelfAffinePSD

__all__ = ["CACHE_SIZES"]

#: bounds of each worker's cache: spectra, Persson theories (about 150 kB each), models, laws
#: (a calibrated law: about 10 kB)
CACHE_SIZES = {"spectra": 64, "theories": 32, "models": 64, "laws": 32}


# ----------------------------------------------------------------------------------------------
# what a worker does
# ----------------------------------------------------------------------------------------------
def _lru(store: OrderedDict, key, build, size: int):
    """``store[key]``, built on a miss; keeps the ``size`` most recently used entries."""
    if key in store:
        store.move_to_end(key)
        return store[key]
    value = build()
    store[key] = value
    while len(store) > size:
        store.popitem(last=False)
    return value


class _ModelCache:
    """Spectra, theories, laws and models of one process, bounded by :data:`CACHE_SIZES`.

    Thread-safe (a dask worker may run several tasks at once): one lock around look-ups and
    builds, so a theory is built once per process even when two threads want it."""

    def __init__(self):
        self._lock = threading.Lock()
        self._spectra: OrderedDict = OrderedDict()
        self._theories: OrderedDict = OrderedDict()
        self._models: OrderedDict = OrderedDict()
        self._laws: OrderedDict = OrderedDict()

    def model(self, spec: ModelSpec, counts: dict):
        build = lambda: self._build(spec, counts)  # noqa: E731
        with self._lock:
            return _lru(self._models, spec, build, CACHE_SIZES["models"])

    def _build(self, spec: ModelSpec, counts: dict):
        builder = GEOMETRIES[spec.geometry]
        theory, law = None, None
        if spec.law[0] != "none":  # the law's theory: diagnostics only (fastline profile --law)
            law, data = _lru(self._laws, spec.law, lambda: _law(spec), CACHE_SIZES["laws"])
            check_law_scene(data, self._spectrum(spec), spec.E_star, _law_name(spec))
        if spec.model in NEEDS_THEORY or (law is not None and self._spectrum(spec) is not None):
            key = (spec.spectrum, spec.E_star, spec.gamma, spec.variant)
            theory = _lru(
                self._theories,
                key,
                lambda: self._theory(spec, counts),
                CACHE_SIZES["theories"],
            )
        psd = theory.psd if theory is not None else self._spectrum(spec)
        model = builder(spec if law is None else replace(spec, model=law), psd, theory)
        counts["models"] += 1
        return model

    def _theory(self, spec: ModelSpec, counts: dict):
        psd = self._spectrum(spec)
        if psd is None:
            raise ValueError(f"psd must be a PSD for model={spec.model!r} (None only for 'hertz')")
        theory = PerssonTheory(psd, spec.E_star, gamma=spec.gamma, variant=spec.variant)
        counts["theories"] += 1
        return theory

    def _spectrum(self, spec: ModelSpec):
        return _lru(
            self._spectra,
            spec.spectrum,
            lambda: _make_spectrum(spec.spectrum, spec.psd),
            CACHE_SIZES["spectra"],
        )


def _make_spectrum(key: tuple, obj):
    kind = key[0]
    if kind == "self-affine":
        return SelfAffinePSD(*key[1:])
    if kind == "file":
        return read_spectrum(key[1])
    return obj  # "object" (the PSD itself) or "none"


def _law_name(spec: ModelSpec) -> str:
    return f"law file {spec.law[1]}" if spec.law[0] == "file" else "the law of the law column"


def _law(spec: ModelSpec) -> tuple:
    """(law, its data) of a model: rebuilt from the data sent with the task, or read from
    the file (its checksum checked against the one the caller read, when it read one)."""
    if spec.law[0] == "data":
        return restore_law(spec.law_data), spec.law_data
    _, path, want = spec.law
    where = f"on {socket.gethostname()}"
    try:
        data = read_law_file(path)
    except FileNotFoundError:
        raise FileNotFoundError(
            f"law file {path}: no such file {where} (a worker reads a law file at the path in "
            "the table: put it where every worker sees it, or give the law object, which "
            "travels with the tasks)"
        ) from None
    except OSError as e:
        raise OSError(f"cannot read law file {path} {where}: {e.strerror or e}") from None
    if want is not None and data.checksum != want:
        raise CalibrationFileError(
            f"law file {path} {where} is not the law of the table: its checksum is "
            f"{data.checksum[:16]}..., the table's {want[:16]}... (the file changed, or the "
            "workers see another file at this path)"
        )
    return restore_law(data), data


_CACHE = _ModelCache()  # the cache of this process (used by _run_task in workers)


@dataclass
class TaskOutcome:
    """What a task sends back: one entry per scene, and the worker's counts.

    ``rows`` holds ``(row, numbers, warning messages or None, error text)``; ``numbers`` are
    the values of the first ten :data:`RESULT_COLUMNS`."""

    rows: list
    worker: str
    theories: int = 0
    models: int = 0
    seconds: float = 0.0
    cpu_seconds: float = 0.0


def _error_text(e: BaseException) -> str:
    return " ".join(f"{type(e).__name__}: {e}".split())


def _row(i: int, r) -> tuple:
    numbers = (
        r.p0,
        r.p0_ratio,
        r.s,
        r.fwhm,
        r.w_over_s,
        r.alpha,
        r.converged,
        r.iterations,
        r.convolutions,
        r.residual,
    )
    return i, numbers, r.diagnostics.get("warning_messages") or None, ""


def _failed(i: int, e: BaseException) -> tuple:
    return i, None, None, _error_text(e)


def _solve_one(model, i: int, load: float) -> tuple:
    try:
        return _row(i, model.solve(load))
    except Exception as e:  # a failing scene is reported in its row, never raised
        return _failed(i, e)


def _solve_piece(piece: Piece, cache: _ModelCache, counts: dict) -> list[tuple]:
    """The scenes of one piece: one sweep; if it raises (a bad load, say), load by load so
    that only the failing scenes are lost."""
    try:
        model = cache.model(piece.spec, counts)
    except Exception as e:  # bad spectrum, modulus, radius, n ...: every scene of the piece
        return [_failed(i, e) for i in piece.rows]
    try:
        results = model.sweep(piece.loads)
    except Exception:
        return [_solve_one(model, i, f) for i, f in zip(piece.rows, piece.loads, strict=True)]
    return [_row(i, r) for i, r in zip(piece.rows, results, strict=True)]


def _run_on(task: tuple[Piece, ...], cache: _ModelCache) -> TaskOutcome:
    t0, c0 = time.perf_counter(), time.thread_time()
    counts = {"theories": 0, "models": 0}
    rows = [row for piece in task for row in _solve_piece(piece, cache, counts)]
    worker = f"{socket.gethostname()}:{os.getpid()}"
    seconds, cpu = time.perf_counter() - t0, time.thread_time() - c0
    return TaskOutcome(rows, worker, counts["theories"], counts["models"], seconds, cpu)


def _run_task(task: tuple[Piece, ...]) -> TaskOutcome:
    """The function executors run: one task, with this process's cache."""
    return _run_on(task, _CACHE)


# ----------------------------------------------------------------------------------------------
# executors
# ----------------------------------------------------------------------------------------------
def _failed_task(task, e: BaseException) -> TaskOutcome:
    text = f"task failed: {_error_text(e)}"
    rows = [(i, None, None, text) for piece in task for i in piece.rows]
    return TaskOutcome(rows, worker="?")


def task_outcomes(tasks: list, engine: Engine):
    """Yield each task's outcome as it completes (in order when serial)."""
    if engine.executor is None:
        cache = _ModelCache()  # a serial sweep keeps nothing once it is done
        for task in tasks:
            try:
                yield _run_on(task, cache)
            except Exception as e:  # pragma: no cover - _run_on catches per scene
                yield _failed_task(task, e)
        return
    futures = {}
    try:
        for k, task in enumerate(tasks):
            try:
                futures[engine.executor.submit(_run_task, task)] = k
            except Exception as e:  # e.g. a scene that does not pickle (dask pickles here)
                yield _failed_task(task, e)
        for fut in cf.as_completed(futures):
            try:
                yield fut.result()
            except Exception as e:  # a worker that died, a pickling error, ...
                yield _failed_task(tasks[futures[fut]], e)
    finally:
        for fut in futures:
            fut.cancel()
