"""Sweeps of many scenes on a process pool or a dask.distributed cluster: :func:`sweep`.

A *scene* is one solve: a roughness spectrum, an effective modulus, a geometry (a cylinder of
radius R, ``geometry="cylinder"``, solved by :class:`~fastline.LineContact`, or a sphere,
``geometry="sphere"``, solved by :class:`~fastline.PointContact`), a load and the solver
settings. :func:`sweep`
takes a table of scenes (a list of dicts, a dict of columns, a NumPy structured array or a
pandas DataFrame; the columns are listed in :data:`SCENE_COLUMNS`), runs it on any
:class:`concurrent.futures.Executor` and returns a :class:`SweepTable`: one row per scene, in
the order given, with the inputs and the results.

How the work is cut (the *plan*):

1. scenes are grouped by *model*: everything but the load (spectrum, E*, geometry and its
   size, model, method, n, gamma, variant, tol, max_iter, hardness);
2. the scenes of a group are ordered by load and cut into *pieces* of at most ``chunksize``
   scenes; a piece is solved by one ``sweep`` of its model (continuation along its loads);
3. pieces are packed, in table order, into *tasks* of at most ``chunksize`` scenes: a task is
   what an executor receives (one pickle, one scheduling step).

The plan depends on the table and ``chunksize`` only, never on the executor, so a process
pool, a dask cluster and ``executor="serial"`` give the same numbers bit for bit. (A different
``chunksize`` changes the continuation starts, hence the results within the solver tolerance.)

Workers keep spectra, Persson theories and models in a per-process cache keyed by their
parameters (least recently used entries dropped beyond :data:`CACHE_SIZES`): scenes sharing a
spectrum and material share one theory per worker process, whichever task brings them, and
whichever geometry they have.

Failures stay in their rows: bad values (a Hurst exponent of 1.5, a load out of range, a
spectrum file that cannot be read) and exceptions inside a worker become the row's ``error``
text; the sweep always completes. The table's shape and types (column names, value types,
geometry/model/method names) are checked before any work and raise.

SI units throughout: m, 1/m, Pa; loads in N/m (per unit length) for a cylinder, in N (the
total load) for a sphere.
"""

from __future__ import annotations

import concurrent.futures as cf
import hashlib
import math
import os
import pickle
import socket
import sys
import threading
import time
import warnings
from collections import OrderedDict
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import ArrayLike

from fastline._lib.executors import Engine, close_engine, open_engine
from fastline.errors import SceneFailureWarning
from fastline.theory.variants import DEFAULT_VARIANT, VARIANTS

if TYPE_CHECKING:  # annotations only: pandas and dask are optional
    import pandas as pd
    from distributed import Client

    #: a table of scenes: rows (dicts), columns (a dict of sequences), a NumPy structured array
    #: or a pandas DataFrame
    Scenes = Iterable[Mapping[str, Any]] | Mapping[str, ArrayLike] | np.ndarray | pd.DataFrame

__all__ = [
    "sweep",
    "SweepTable",
    "SweepStats",
    "SceneFailureWarning",
    "read_scenes",
    "default_chunksize",
    "SCENE_COLUMNS",
    "RESULT_COLUMNS",
    "GEOMETRIES",
    "LOAD_UNITS",
    "CACHE_SIZES",
]


# ----------------------------------------------------------------------------------------------
# the table's columns
# ----------------------------------------------------------------------------------------------
@dataclass(frozen=True)
class _Column:
    """One column: name, kind (float, int, bool, text, psd), unit and default (None: required;
    ``_SPECTRUM``: required unless the spectrum is given by a ``psd`` column)."""

    name: str
    kind: str
    unit: str = ""
    default: object = None

    @property
    def csv_name(self) -> str:
        """Name in CSV files: the unit appended (``load_N_per_m``), as in :mod:`fastline.io`."""
        suffix = self.unit.replace("/", "_per_")
        return f"{self.name}_{suffix}" if self.unit and self.unit != "-" else self.name


_SPECTRUM = object()  # default marker of the self-affine spectrum columns
_BY_GEOMETRY = object()  # default marker of a column whose default depends on the geometry
_SPECTRUM_PARAMS = ("h_rms", "hurst", "q0", "qr", "q1")

#: input columns; ``default`` None means required
_INPUTS = (
    _Column("label", "text", default=""),
    _Column("geometry", "text", default="cylinder"),
    _Column("h_rms", "float", "m", _SPECTRUM),
    _Column("hurst", "float", "-", _SPECTRUM),
    _Column("q0", "float", "1/m", _SPECTRUM),
    _Column("qr", "float", "1/m", _SPECTRUM),
    _Column("q1", "float", "1/m", _SPECTRUM),
    _Column("psd", "psd", default=_SPECTRUM),
    _Column("E_star", "float", "Pa"),
    _Column("radius", "float", "m"),
    _Column("load", "float", "N/m"),  # N for a sphere (_load_csv_name)
    _Column("model", "text", default="persson"),
    _Column("method", "text", default="newton"),
    _Column("n", "int", default=_BY_GEOMETRY),  # the geometry's own (_GEOMETRY_N)
    _Column("gamma", "float", "-", math.nan),  # NaN: the variant's own (_normalise)
    _Column("variant", "text", default=DEFAULT_VARIANT),
    _Column("tol", "float", "-", 1e-8),
    _Column("max_iter", "int", default=0),
    _Column("hardness", "float", "Pa", math.nan),
)
#: result columns added to the inputs
_OUTPUTS = (
    _Column("p0", "float", "Pa"),
    _Column("p0_ratio", "float", "-"),
    _Column("s", "float", "m"),
    _Column("fwhm", "float", "m"),
    _Column("w_over_s", "float", "-"),
    _Column("alpha", "float", "-"),
    _Column("converged", "bool"),
    _Column("iterations", "int"),
    _Column("convolutions", "int"),
    _Column("residual", "float", "-"),
    _Column("warnings", "text"),
    _Column("error", "text"),
)
_BY_NAME = {c.name: c for c in _INPUTS + _OUTPUTS}
#: names of the scene columns (``psd`` or the five self-affine parameters give the spectrum)
SCENE_COLUMNS = tuple(c.name for c in _INPUTS)
#: names of the result columns of a :class:`SweepTable` (after the scene columns)
RESULT_COLUMNS = tuple(c.name for c in _OUTPUTS)
_REQUIRED = tuple(c.name for c in _INPUTS if c.default is None)
_NUMERIC_RESULTS = RESULT_COLUMNS[:10]  # p0 ... residual, in the order workers return them
_MODELS = ("persson", "exponential", "hertz")
_METHODS = ("newton", "picard")
_NEEDS_THEORY = ("persson", "exponential")

#: bounds of each worker's cache: spectra, Persson theories (about 150 kB each), models
CACHE_SIZES = {"spectra": 64, "theories": 32, "models": 64}
#: default plan: about this many tasks per table, each of ``[MIN, MAX]`` scenes. Measured with
#: 2 workers on paper-like scenes at n = 256 (0.4-0.6 ms of CPU per scene; docs/throughput.md):
#: the engine costs 0.5-1.3 ms per task in a local pool and 4-13 ms on dask; with 157 scenes
#: per task (10,000 scenes) the workers were 89-94% busy, with 8 per task 80-90% (pool).
DEFAULT_TASKS, MIN_CHUNK, MAX_CHUNK = 64, 8, 256


# ----------------------------------------------------------------------------------------------
# geometries: how a model of a scene is built
# ----------------------------------------------------------------------------------------------
def _cylinder(spec, psd, theory):
    from fastline.contact.line import LineContact

    return LineContact(
        psd,
        spec.E_star,
        spec.radius,
        model=spec.model,
        method=spec.method,
        gamma=spec.gamma,
        variant=spec.variant,
        n=spec.n,
        tol=spec.tol,
        max_iter=spec.max_iter,
        theory=theory,
        hardness=spec.hardness,
        warn=False,
    )


def _sphere(spec, psd, theory):
    from fastline.contact.point import PointContact

    return PointContact(
        psd,
        spec.E_star,
        spec.radius,
        model=spec.model,
        method=spec.method,
        gamma=spec.gamma,
        variant=spec.variant,
        n=spec.n,
        tol=spec.tol,
        max_iter=spec.max_iter,
        theory=theory,
        hardness=spec.hardness,
        warn=False,
    )


#: ``geometry`` column value -> builder ``(spec, psd, theory) -> model`` of a model with
#: ``solve(load)`` and ``sweep(loads)`` returning results with p0, p0_ratio, s, fwhm, w_over_s,
#: alpha, converged, iterations, convolutions, residual and ``diagnostics``
GEOMETRIES = {"cylinder": _cylinder, "sphere": _sphere}
#: default ``n`` of each geometry: the model's own default (LineContact 1024, PointContact 512)
_GEOMETRY_N = {"cylinder": 1024, "sphere": 512}
#: unit of the ``load`` column for each geometry
LOAD_UNITS = {"cylinder": "N/m", "sphere": "N"}
_CATEGORIES = {"geometry": GEOMETRIES, "model": _MODELS, "method": _METHODS, "variant": VARIANTS}


# ----------------------------------------------------------------------------------------------
# reading and checking the table (before any work)
# ----------------------------------------------------------------------------------------------
def _columns_of(scenes) -> dict[str, list]:
    """Column name -> list of cells, from any of the accepted table forms."""
    if isinstance(scenes, np.ndarray):
        if scenes.dtype.names is None or scenes.ndim != 1:
            raise TypeError("scenes as an array must be a 1-D NumPy structured array")
        return {name: scenes[name].tolist() for name in scenes.dtype.names}
    if hasattr(scenes, "columns") and hasattr(scenes, "to_dict"):  # a pandas DataFrame
        return {name: scenes[name].tolist() for name in scenes.columns}
    if isinstance(scenes, Mapping):
        for name, cells in scenes.items():
            if isinstance(cells, str | bytes) or not isinstance(cells, Iterable):
                raise TypeError(
                    f"scenes: column {name!r} of a dict of columns must be a sequence of cells, "
                    f"one per scene; got {type(cells).__name__} ({cells!r}): repeat a value "
                    "shared by every scene, e.g. [value] * len(loads)"
                )
        cols = {k: list(v) for k, v in scenes.items()}
        if len({len(v) for v in cols.values()}) > 1:
            raise ValueError("scenes: every column of a dict of columns must have the same length")
        return cols
    if isinstance(scenes, Iterable) and not isinstance(scenes, str | bytes):
        return _columns_of_rows(list(scenes))
    raise TypeError(
        "scenes must be a list of dicts, a dict of columns, a NumPy structured array or a "
        f"pandas DataFrame, got {type(scenes).__name__}"
    )


def _columns_of_rows(rows: list) -> dict[str, list]:
    for i, row in enumerate(rows):
        if not isinstance(row, Mapping):
            raise TypeError(f"scenes: row {i} must be a dict, got {type(row).__name__}")
    names = list(dict.fromkeys(k for row in rows for k in row))
    for name in _REQUIRED:
        missing = [i for i, row in enumerate(rows) if name in names and name not in row]
        if missing:
            raise ValueError(f"scenes: column {name!r} is missing in rows {_few(missing)}")
    return {name: [row.get(name) for row in rows] for name in names}


def _few(rows: Sequence[int], k: int = 5) -> str:
    return ", ".join(str(r) for r in rows[:k]) + (" ..." if len(rows) > k else "")


def _check_names(cols: Mapping) -> None:
    """Unknown and missing columns, and exactly one way of giving the spectrum."""
    bad = [k for k in cols if not isinstance(k, str)]
    unknown = [k for k in cols if k not in _BY_NAME or k in RESULT_COLUMNS]
    if bad or unknown:
        raise ValueError(
            f"scenes: unknown columns {sorted(map(str, bad + unknown))}; allowed: "
            f"{', '.join(SCENE_COLUMNS)}"
        )
    if not cols or not len(next(iter(cols.values()))):
        raise ValueError("scenes must hold at least one scene")
    missing = [k for k in _REQUIRED if k not in cols]
    given = [k for k in _SPECTRUM_PARAMS if k in cols]
    if "psd" in cols and given:
        raise ValueError(
            f"scenes: give the spectrum either as a psd column or as {', '.join(_SPECTRUM_PARAMS)}"
            f", not both (got psd and {', '.join(given)})"
        )
    if "psd" not in cols:
        missing += [k for k in _SPECTRUM_PARAMS if k not in cols]
    if missing:
        raise ValueError(
            f"scenes: missing columns {missing}; the spectrum needs a psd column (PSD objects or "
            f"spectrum files) or all of {', '.join(_SPECTRUM_PARAMS)}"
        )


def _is_missing(v) -> bool:
    return v is None or (isinstance(v, float) and math.isnan(v))


def _cell(col: _Column, i: int, v):
    """One cell converted to its column's type; TypeError naming the column and row."""
    optional = col.default is not None and col.default is not _SPECTRUM
    if optional and _is_missing(v):
        return col.default
    if v is None and col.kind != "psd":
        raise ValueError(f"scenes: column {col.name!r} has no value in row {i}")
    if col.kind == "float":
        if isinstance(v, bool | np.bool_) or not isinstance(v, int | float | np.number):
            _type_error(col, i, v, "a real number")
        return float(v)
    if col.kind == "int":
        if isinstance(v, bool | np.bool_) or not isinstance(v, int | float | np.number):
            _type_error(col, i, v, "an integer")
        if not float(v).is_integer():
            _type_error(col, i, v, "an integer")
        return int(v)
    if col.kind == "text":
        if not isinstance(v, str):
            _type_error(col, i, v, "a string")
        return str(v)
    return _psd_cell(col, i, v)


def _psd_cell(col: _Column, i: int, v):
    from fastline.theory.spectra import PSD

    if v is None or isinstance(v, PSD):
        return v
    if isinstance(v, str | os.PathLike):
        return os.path.abspath(os.fspath(v))
    _type_error(col, i, v, "a fastline PSD, the path of a spectrum file, or None")


def _type_error(col: _Column, i: int, v, what: str):
    raise TypeError(
        f"scenes: column {col.name!r} must hold {what}; row {i} holds {v!r} ({type(v).__name__})"
    )


def _check_category(name: str, values: list) -> None:
    allowed = tuple(_CATEGORIES[name])  # GEOMETRIES read now: a geometry may be added later
    for i, v in enumerate(values):
        if v not in allowed:
            raise ValueError(f"scenes: column {name!r} must be one of {allowed}; row {i} is {v!r}")


_PLAIN_NUMBERS = {float, int, np.float64, np.float32, np.int64, np.int32}


def _fast_column(col: _Column, values: list) -> list | None:
    """The column converted at once when every cell is plainly of its type (the common case,
    ~20x faster than cell by cell); None when some cell needs :func:`_cell`."""
    types = set(map(type, values))
    if col.kind == "text":
        return values if types == {str} else None
    if col.kind not in ("float", "int") or not types <= _PLAIN_NUMBERS:
        return None  # bools, strings, None, other objects: cell by cell
    arr = np.asarray(values)
    if col.kind == "float":
        if arr.dtype.kind == "f" and col.default is not None and np.isnan(arr).any():
            return None  # missing cells of an optional column take its default
        return arr.astype(np.float64).tolist()
    if arr.dtype.kind == "f" and not np.all((np.abs(arr) < 2.0**62) & (arr == np.round(arr))):
        return None  # NaN, huge or fractional cells: cell by cell
    return arr.astype(np.int64).tolist()


def _normalise(scenes) -> dict[str, list]:
    """The table as complete, typed columns (defaults filled in); raises before any work."""
    cols = _columns_of(scenes)
    _check_names(cols)
    size = len(next(iter(cols.values())))
    out = {}
    for col in _INPUTS:
        if col.name in cols:
            values = cols[col.name]
            fast = _fast_column(col, values)
            out[col.name] = (
                fast if fast is not None else [_cell(col, i, v) for i, v in enumerate(values)]
            )
        elif col.default is not _SPECTRUM:
            out[col.name] = [col.default] * size
    for name in _CATEGORIES:
        _check_category(name, out[name])
    out["n"] = [
        _GEOMETRY_N.get(g, 1024) if n is _BY_GEOMETRY else n
        for n, g in zip(out["n"], out["geometry"], strict=True)
    ]
    out["gamma"] = [
        VARIANTS[v].default_gamma if math.isnan(g) else g
        for g, v in zip(out["gamma"], out["variant"], strict=True)
    ]
    return out


# ----------------------------------------------------------------------------------------------
# the plan: groups of scenes sharing a model, pieces, tasks
# ----------------------------------------------------------------------------------------------
@dataclass(frozen=True)
class _ModelSpec:
    """Everything about a scene but its load: what a worker needs to build (or find) a model.

    ``spectrum`` is a hashable key: ``("self-affine", h_rms, H, q0, qr, q1)``, ``("file",
    path)``, ``("object", digest of the pickled PSD)`` or ``("none",)``; ``psd`` carries the
    object for the ``"object"`` kind (not part of equality)."""

    geometry: str
    spectrum: tuple
    E_star: float
    radius: float
    model: str
    method: str
    n: int
    gamma: float
    variant: str
    tol: float
    max_iter: int | None
    hardness: float | None
    psd: object = field(default=None, compare=False, hash=False, repr=False)


@dataclass(frozen=True)
class _Piece:
    """Scenes of one model, ordered by load: solved by one ``sweep`` call."""

    spec: _ModelSpec
    rows: tuple[int, ...]
    loads: tuple[float, ...]


class _SpectrumKeys:
    """Spectrum keys of the table's cells; PSD objects digested once per object."""

    def __init__(self):
        self._digests: dict[int, str] = {}

    def column(self, cols: Mapping) -> list[tuple]:
        if "psd" not in cols:
            params = zip(*(cols[k] for k in _SPECTRUM_PARAMS), strict=True)
            return [("self-affine", *p) for p in params]
        return [self._key(psd) for psd in cols["psd"]]

    def _key(self, psd) -> tuple:
        if psd is None:
            return ("none",)
        if isinstance(psd, str):
            return ("file", psd)
        digest = self._digests.get(id(psd))
        if digest is None:
            digest = hashlib.sha1(pickle.dumps(psd, protocol=4)).hexdigest()
            self._digests[id(psd)] = digest
        return ("object", digest)


#: the columns that, with the spectrum, make a model (in :class:`_ModelSpec`'s order)
_MODEL_COLUMNS = (
    "geometry", "E_star", "radius", "model", "method", "n", "gamma", "variant", "tol"
)  # fmt: skip


def _groups(cols: Mapping) -> dict[_ModelSpec, list[int]]:
    """Rows of each model, in order of first appearance (keyed by plain tuples: fast)."""
    max_iter = [m or None for m in cols["max_iter"]]
    hardness = [None if math.isnan(h) else h for h in cols["hardness"]]
    spectra = _SpectrumKeys().column(cols)
    rows: dict[tuple, list[int]] = {}
    keys = zip(spectra, *(cols[k] for k in _MODEL_COLUMNS), max_iter, hardness, strict=True)
    for i, key in enumerate(keys):
        rows.setdefault(key, []).append(i)
    return {_spec(key, cols, r[0]): r for key, r in rows.items()}


def _spec(key: tuple, cols: Mapping, first: int) -> _ModelSpec:
    spectrum, geometry, *rest = key
    psd = cols["psd"][first] if spectrum[0] == "object" else None
    return _ModelSpec(geometry, spectrum, *rest, psd=psd)


def default_chunksize(scenes: int) -> int:
    """Scenes per task when none is given: about :data:`DEFAULT_TASKS` tasks, each of
    :data:`MIN_CHUNK` to :data:`MAX_CHUNK` scenes (a function of the table size only)."""
    return min(MAX_CHUNK, max(MIN_CHUNK, math.ceil(scenes / DEFAULT_TASKS)))


def _plan(cols: Mapping, chunksize: int) -> list[tuple[_Piece, ...]]:
    """Tasks (tuples of pieces) for the table; see the module docstring."""
    loads = np.asarray(cols["load"], dtype=float)
    tasks, current, size = [], [], 0
    for spec, rows in _groups(cols).items():
        rows = np.asarray(rows)
        rows = rows[np.argsort(loads[rows], kind="stable")]
        for k in range(0, rows.size, chunksize):
            part = rows[k : k + chunksize]
            if size + part.size > chunksize:
                tasks.append(tuple(current))
                current, size = [], 0
            current.append(_Piece(spec, tuple(part.tolist()), tuple(loads[part].tolist())))
            size += part.size
    tasks.append(tuple(current))
    return tasks


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
    """Spectra, theories and models of one process, bounded by :data:`CACHE_SIZES`.

    Thread-safe (a dask worker may run several tasks at once): one lock around look-ups and
    builds, so a theory is built once per process even when two threads want it."""

    def __init__(self):
        self._lock = threading.Lock()
        self._spectra: OrderedDict = OrderedDict()
        self._theories: OrderedDict = OrderedDict()
        self._models: OrderedDict = OrderedDict()

    def model(self, spec: _ModelSpec, counts: dict):
        build = lambda: self._build(spec, counts)  # noqa: E731
        with self._lock:
            return _lru(self._models, spec, build, CACHE_SIZES["models"])

    def _build(self, spec: _ModelSpec, counts: dict):
        builder = GEOMETRIES[spec.geometry]
        theory = None
        if spec.model in _NEEDS_THEORY:
            key = (spec.spectrum, spec.E_star, spec.gamma, spec.variant)
            theory = _lru(
                self._theories,
                key,
                lambda: self._theory(spec, counts),
                CACHE_SIZES["theories"],
            )
        psd = theory.psd if theory is not None else self._spectrum(spec)
        model = builder(spec, psd, theory)
        counts["models"] += 1
        return model

    def _theory(self, spec: _ModelSpec, counts: dict):
        from fastline.theory.persson import PerssonTheory

        psd = self._spectrum(spec)
        if psd is None:
            raise ValueError(f"psd must be a PSD for model={spec.model!r} (None only for 'hertz')")
        theory = PerssonTheory(psd, spec.E_star, gamma=spec.gamma, variant=spec.variant)
        counts["theories"] += 1
        return theory

    def _spectrum(self, spec: _ModelSpec):
        return _lru(
            self._spectra,
            spec.spectrum,
            lambda: _make_spectrum(spec.spectrum, spec.psd),
            CACHE_SIZES["spectra"],
        )


def _make_spectrum(key: tuple, obj):
    kind = key[0]
    if kind == "self-affine":
        from fastline.theory.spectra import SelfAffinePSD

        return SelfAffinePSD(*key[1:])
    if kind == "file":
        from fastline.io import read_spectrum

        return read_spectrum(key[1])
    return obj  # "object" (the PSD itself) or "none"


_CACHE = _ModelCache()  # the cache of this process (used by _run_task in workers)


@dataclass
class _TaskOutcome:
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


def _solve_piece(piece: _Piece, cache: _ModelCache, counts: dict) -> list[tuple]:
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


def _run_on(task: tuple[_Piece, ...], cache: _ModelCache) -> _TaskOutcome:
    t0, c0 = time.perf_counter(), time.thread_time()
    counts = {"theories": 0, "models": 0}
    rows = [row for piece in task for row in _solve_piece(piece, cache, counts)]
    worker = f"{socket.gethostname()}:{os.getpid()}"
    seconds, cpu = time.perf_counter() - t0, time.thread_time() - c0
    return _TaskOutcome(rows, worker, counts["theories"], counts["models"], seconds, cpu)


def _run_task(task: tuple[_Piece, ...]) -> _TaskOutcome:
    """The function executors run: one task, with this process's cache."""
    return _run_on(task, _CACHE)


# ----------------------------------------------------------------------------------------------
# executors
# ----------------------------------------------------------------------------------------------
def _failed_task(task, e: BaseException) -> _TaskOutcome:
    text = f"task failed: {_error_text(e)}"
    rows = [(i, None, None, text) for piece in task for i in piece.rows]
    return _TaskOutcome(rows, worker="?")


def _outcomes(tasks: list, engine: Engine):
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


# ----------------------------------------------------------------------------------------------
# the result table
# ----------------------------------------------------------------------------------------------
_DTYPES = {"float": np.float64, "int": np.int64, "bool": np.bool_, "text": object, "psd": object}


def _dtype(cols: Mapping) -> np.dtype:
    names = [c for c in SCENE_COLUMNS if c in cols] + list(RESULT_COLUMNS)
    return np.dtype([(name, _DTYPES[_BY_NAME[name].kind]) for name in names])


def _empty_table(cols: Mapping) -> np.ndarray:
    size = len(cols["load"])
    table = np.zeros(size, dtype=_dtype(cols))
    for name, values in cols.items():
        if _BY_NAME[name].kind in ("text", "psd"):
            table[name] = np.fromiter(values, dtype=object, count=size)  # cells kept as given
        else:
            table[name] = values
    for name in _NUMERIC_RESULTS:
        if _BY_NAME[name].kind == "float":
            table[name] = np.nan
    table["warnings"] = ""
    table["error"] = ""
    return table


@dataclass
class _Flagged:
    """A solved scene as :func:`fastline.contact.diagnostics.summarise_warnings` reads it (the load's
    symbol and unit those of its geometry's results)."""

    load: float
    diagnostics: dict
    LOAD_SYMBOL: str = "f_N"
    LOAD_UNIT: str = "N/m"


_UNFLAGGED = _Flagged(0.0, {})  # a solved scene without warnings
_LOAD_SYMBOLS = {"cylinder": "f_N", "sphere": "F"}


def _fill(table: np.ndarray, outcomes: list[_TaskOutcome]) -> dict[str, list[_Flagged]]:
    """Write the workers' rows into the table; returns the solved scenes (with their
    warnings) of each geometry."""
    solved, numbers, failed, errors, flagged = [], [], [], [], []
    for outcome in outcomes:
        for i, values, messages, error in outcome.rows:
            if error:
                failed.append(i)
                errors.append(error)
                continue
            solved.append(i)
            numbers.append(values)
            if messages:
                table["warnings"][i] = ";".join(messages)
                diag = {"warning_causes": list(messages), "warning_messages": messages}
                flagged.append((i, diag))
    if failed:
        table["error"][np.asarray(failed)] = np.fromiter(errors, dtype=object, count=len(errors))
    if solved:
        idx = np.asarray(solved)
        block = np.asarray(numbers, dtype=np.float64)
        for k, name in enumerate(_NUMERIC_RESULTS):
            table[name][idx] = block[:, k].astype(table.dtype[name])
    return _by_geometry(table, solved, flagged)


def _by_geometry(table: np.ndarray, solved: list[int], flagged: list) -> dict[str, list]:
    """Geometry -> its solved scenes as :class:`_Flagged` (one shared entry stands for each
    scene without warnings: only the count matters)."""
    geometry, load = table["geometry"], table["load"]
    out: dict[str, list[_Flagged]] = {}
    for i, diag in flagged:
        g = geometry[i]
        symbol, unit = _LOAD_SYMBOLS.get(g, "load"), LOAD_UNITS.get(g, "N/m")
        out.setdefault(g, []).append(_Flagged(float(load[i]), diag, symbol, unit))
    counts: dict[str, int] = {}
    for g in geometry[np.asarray(solved, dtype=np.int64)]:
        counts[g] = counts.get(g, 0) + 1
    for g, k in counts.items():
        scenes = out.setdefault(g, [])
        scenes.extend([_UNFLAGGED] * (k - len(scenes)))
    return out


@dataclass
class SweepStats:
    """How a sweep ran (not part of the results: these vary from run to run).

    Attributes
    ----------
    scenes, tasks, chunksize : int
        Scenes in the table, tasks sent to the executor, scenes per task at most.
    workers : int
        Distinct processes (host:pid) that ran tasks.
    theory_builds, model_builds : int
        Persson theories and models built by the workers in this sweep (a worker's cache may
        already hold some from an earlier sweep).
    compute_seconds : float
        Time spent inside tasks, summed over tasks (s).
    compute_cpu_seconds : float
        CPU time of the threads running the tasks, summed over tasks (s): below
        ``compute_seconds`` when the workers waited for a CPU (other jobs on the machine).
    wall_seconds : float
        Wall time of the whole call: checking the table, planning, solving (including a
        process pool's start-up when :func:`sweep` made the pool) and assembling (s).
    executor : str
        What ran the tasks.
    """

    scenes: int
    tasks: int
    chunksize: int
    workers: int
    theory_builds: int
    model_builds: int
    compute_seconds: float
    compute_cpu_seconds: float
    wall_seconds: float
    executor: str

    @property
    def scenes_per_second(self) -> float:
        return self.scenes / self.wall_seconds if self.wall_seconds > 0 else math.inf


def _text_cell(v) -> str:
    """A text cell for a CSV file: one line, no commas (the files are read by splitting)."""
    text = "none" if v is None else v if isinstance(v, str) else repr(v)
    return " ".join(text.split()).replace(",", ";")


class SweepTable:
    """The results of :func:`sweep`: one row per scene, in the order given.

    Attributes
    ----------
    table : numpy structured array
        The scene columns (defaults filled in; ``psd`` cells as given, paths made absolute)
        followed by :data:`RESULT_COLUMNS`: ``p0`` [Pa], ``p0_ratio``, ``s`` [m], ``fwhm`` [m],
        ``w_over_s``, ``alpha``, ``converged``, ``iterations``, ``convolutions``,
        ``residual``, ``warnings`` (the validity causes found, ``;``-separated) and ``error``
        (empty when the scene was solved). A failed scene has NaN numbers, ``converged``
        False and zero counts. Text columns hold Python strings (object dtype).

        Each result is the attribute of that name of the scene's
        :class:`~fastline.LineContactResult` (cylinder) or
        :class:`~fastline.PointContactResult` (sphere). For a sphere: ``p0_ratio`` is
        against the Hertz *sphere*, ``s`` and ``fwhm`` are measured along a diameter
        (``s^2 = int r^2 p dA / (2F)``), ``alpha = h_rms / delta`` with ``delta = a^2/R``
        (a cylinder's ``delta = 4 f_N / (pi E*)``), ``convolutions`` counts ring-operator
        applications (products with K plus preconditioner solves; a cylinder's, FFT
        convolutions) and ``residual`` is relative to u0 as for a cylinder.
    warnings : list of (str, str)
        ``(cause, message)`` once per cause over the whole sweep: ``"failed"``,
        ``"not_converged"`` and the causes of :data:`fastline.contact.diagnostics.CAUSES`.
    stats : SweepStats
        How the sweep ran (workers, tasks, theory builds, times).

    ``table_obj["p0"]`` is a column, ``len(table_obj)`` the number of scenes.
    """

    def __init__(
        self, table: np.ndarray, warnings: list[tuple[str, str]], stats: SweepStats
    ) -> None:
        self.table = table
        self.warnings = warnings
        self.stats = stats

    @property
    def columns(self) -> tuple[str, ...]:
        return self.table.dtype.names

    @property
    def ok(self) -> np.ndarray:
        """Boolean mask of the scenes solved and converged."""
        return (self.table["error"] == "") & self.table["converged"]

    @property
    def failed(self) -> np.ndarray:
        """Boolean mask of the scenes that failed (their ``error`` text says why)."""
        return self.table["error"] != ""

    def __len__(self) -> int:
        return self.table.size

    def __getitem__(self, key):
        return self.table[key]

    def __repr__(self):
        failed = int(self.failed.sum())
        unconverged = len(self) - failed - int(self.ok.sum())
        return (
            f"SweepTable({len(self)} scenes: {int(self.ok.sum())} converged, {unconverged} not "
            f"converged, {failed} failed; warnings: {[c for c, _ in self.warnings]})"
        )

    def to_csv(self, path: str | os.PathLike, meta: Mapping | None = None) -> None:
        """Write the table as a CSV file (:func:`fastline.io.write_csv`): ``# key: value``
        header lines, then columns named with their units (``load_N_per_m``, ``p0_Pa``...;
        the load is ``load_N`` when every scene is a sphere, ``load`` when the table mixes
        geometries, and the header's ``load_unit`` line says which unit each geometry's has).

        Text cells are written on one line with commas replaced by ``;``; ``psd`` cells as the
        file path or the spectrum's repr. :func:`fastline.io.read_csv` reads the file back,
        :func:`read_scenes` reads its scene columns.
        """
        from fastline import __version__
        from fastline.io import check_output_file, write_csv

        path = check_output_file(path)
        header = {"fastline_version": __version__, "scenes": len(self)}
        header.update(failed=int(self.failed.sum()), not_converged=self._unconverged())
        header.update(chunksize=self.stats.chunksize, **(meta or {}))
        names = self.columns
        header["load_unit"] = "; ".join(
            f"{LOAD_UNITS.get(g, 'N/m')} ({g})" for g in dict.fromkeys(self.table["geometry"])
        )
        text = [_BY_NAME[n].kind in ("text", "psd") for n in names]
        rows = (
            [_text_cell(v) if t else v for v, t in zip(rec, text, strict=True)]
            for rec in self.table.tolist()
        )
        title = "fastline sweep: one row per scene (inputs, then results); SI units"
        csv_names = [self._csv_name(n) for n in names]
        write_csv(path, csv_names, rows, header, title=title)

    def _csv_name(self, name: str) -> str:
        """A column's name in CSV files; the load's unit follows the geometries of the table
        (``load_N_per_m`` for cylinders, ``load_N`` for spheres, ``load`` when mixed)."""
        if name != "load":
            return _BY_NAME[name].csv_name
        units = {LOAD_UNITS.get(g, "N/m") for g in self.table["geometry"]}
        if len(units) > 1:
            return "load"
        return _Column("load", "float", units.pop()).csv_name

    def _unconverged(self) -> int:
        return int(((self.table["error"] == "") & ~self.table["converged"]).sum())

    def to_pandas(self) -> pd.DataFrame:
        """The table as a pandas DataFrame (needs pandas)."""
        try:
            import pandas as pd
        except ImportError:
            raise ImportError("SweepTable.to_pandas needs pandas (not installed)") from None
        return pd.DataFrame({name: self.table[name] for name in self.columns})


# ----------------------------------------------------------------------------------------------
# warnings, once per cause
# ----------------------------------------------------------------------------------------------
def _summary(table: np.ndarray, flagged: dict[str, list[_Flagged]]) -> list[tuple[str, str]]:
    """Failed and unconverged scenes, then the validity causes once each per geometry (the
    loads of a cylinder and of a sphere are in different units)."""
    from fastline.contact.diagnostics import summarise_warnings

    out = []
    failed = np.flatnonzero(table["error"] != "")
    if failed.size:
        first = int(failed[0])
        out.append(
            (
                "failed",
                f"{failed.size} of {table.size} scenes failed (rows {_few(failed.tolist())}); "
                f"row {first}: {table['error'][first]}; see the table's error column",
            )
        )
    bad = np.flatnonzero((table["error"] == "") & ~table["converged"])
    if bad.size:
        out.append(
            (
                "not_converged",
                f"{bad.size} of {table.size} scenes did not converge (rows "
                f"{_few(bad.tolist())}); see the converged and residual columns",
            )
        )
    for solved in flagged.values():
        out += summarise_warnings(solved)
    return out


def _emit(summary: list[tuple[str, str]]) -> None:
    from fastline.contact.diagnostics import ValidityWarning
    from fastline.contact.line import ConvergenceWarning

    classes = {"failed": SceneFailureWarning, "not_converged": ConvergenceWarning}
    for cause, msg in summary:
        warnings.warn(f"fastline: {msg}", classes.get(cause, ValidityWarning), stacklevel=3)


# ----------------------------------------------------------------------------------------------
# the public functions
# ----------------------------------------------------------------------------------------------
def _progress_bar(total: int, progress: bool | None):
    from tqdm import tqdm

    disable = None if progress is None else not progress
    return tqdm(total=total, desc="sweep", unit="scene", file=sys.stderr, disable=disable)


def sweep(
    scenes: Scenes,
    executor: str | cf.Executor | Client | None = None,
    *,
    workers: int | None = None,
    chunksize: int | None = None,
    progress: bool | None = True,
    warn: bool = True,
) -> SweepTable:
    """Solve a table of scenes on a process pool, a dask cluster or any executor.

    Parameters
    ----------
    scenes : list of dict, dict of columns, NumPy structured array or pandas DataFrame
        One scene per row. Required columns: ``E_star`` [Pa], ``radius`` [m], ``load`` (N/m
        for a cylinder, N for a sphere) and the spectrum: either ``h_rms`` [m], ``hurst``,
        ``q0``, ``qr``, ``q1`` [1/m] (a :class:`~fastline.SelfAffinePSD`) or ``psd`` (a PSD
        object, the path of a spectrum file read by :func:`fastline.io.read_spectrum` on the
        worker, or None for ``model="hertz"``). Optional, with defaults: ``label`` (""),
        ``geometry`` ("cylinder", the default, or "sphere": :data:`GEOMETRIES`), ``model``
        ("persson", "exponential", "hertz"), ``method`` ("newton", "picard"), ``n`` (the
        geometry's own: 1024 grid points for a cylinder, 512 cells for a sphere; the table
        shows the value used), ``variant`` of the theory's u(p) ("yang-persson-energy", the
        default, "yang-persson-printed" or "wang-mueser"; :mod:`fastline.theory.variants`),
        ``gamma`` (the variant's own: 0.45, 5/9 for "wang-mueser"; the table shows the value
        used), ``tol`` (1e-8), ``max_iter`` (0: the method's default), ``hardness`` [Pa]
        (NaN: none). A missing cell (None, NaN) in an optional column takes the default.
        Each scene is solved as ``LineContact(psd, E_star, radius, model=...,
        variant=..., ...).solve(load)`` would (``PointContact`` for a sphere), its values
        checked there (a bad value fails that scene only). Scenes of either geometry that
        share a spectrum, E*, gamma and variant share one Persson theory per worker.
    executor : None, "serial", str, concurrent.futures.Executor or dask Client
        None (default): a local pool of ``workers`` processes (spawned; made and shut down
        here; a single task or ``workers=1`` runs in this process). ``"serial"``: in this
        process, in order. A dask scheduler address (``"tcp://host:8786"``): a
        ``dask.distributed`` client is connected for the sweep (needs the ``dask`` extra). An
        executor (``ProcessPoolExecutor``, ``ThreadPoolExecutor``, ``client.get_executor()``)
        or a ``distributed.Client``: used as given and left running. Workers must be able to
        import fastline (and read the spectrum files named in the table).
    workers : int, optional
        Processes of the default pool (default: the CPUs this process may use).
    chunksize : int, optional
        Scenes per task at most (default :func:`default_chunksize`: ~64 tasks). Scenes of one
        model within a task are solved by one continuation sweep; the results depend on
        ``chunksize`` within the solver tolerance, and not at all on the executor.
    progress : bool or None
        Show a tqdm progress bar on stderr (None: only when stderr is a terminal).
    warn : bool
        Emit, once each for the whole sweep: a :class:`SceneFailureWarning` for failed scenes,
        a ``ConvergenceWarning`` for scenes that did not converge and one ``ValidityWarning``
        per validity cause (:func:`fastline.contact.diagnostics.summarise_warnings`). They are in
        ``SweepTable.warnings`` either way.

    Returns
    -------
    SweepTable
        One row per scene, in the order given (``.table``, ``.to_csv``, ``.to_pandas``).

    Raises
    ------
    ValueError, TypeError
        Before any work, for unknown or missing columns, a cell of the wrong type, an unknown
        geometry, model, method or variant, a bad ``chunksize``, ``workers`` or ``executor``.
    ImportError
        For a scheduler address without dask installed.
    OSError
        When the dask scheduler at an address cannot be reached.

    Examples
    --------
    >>> import fastline as fl
    >>> scenes = [dict(h_rms=1e-6, hurst=0.8, q0=1e3, qr=1e4, q1=1e9, E_star=1.33e9,
    ...                radius=0.01, load=f, n=128) for f in (1e3, 1e4, 1e5)]
    >>> res = fl.sweep(scenes, "serial", progress=False)
    >>> res["p0"], res["w_over_s"]  # doctest: +SKIP
    """
    from fastline._lib.validate import integer

    t0 = time.perf_counter()
    cols = _normalise(scenes)
    size = len(cols["load"])
    chunk = default_chunksize(size) if chunksize is None else integer("chunksize", chunksize, 1)
    tasks = _plan(cols, chunk)
    engine = open_engine(executor, workers, len(tasks))
    outcomes = []
    try:
        with _progress_bar(size, progress) as bar:
            for outcome in _outcomes(tasks, engine):
                outcomes.append(outcome)
                bar.update(len(outcome.rows))
    finally:
        close_engine(engine)
    table = _empty_table(cols)
    summary = _summary(table, _fill(table, outcomes))
    wall = time.perf_counter() - t0
    stats = SweepStats(
        scenes=size,
        tasks=len(tasks),
        chunksize=chunk,
        workers=len({o.worker for o in outcomes if o.worker != "?"}),
        theory_builds=sum(o.theories for o in outcomes),
        model_builds=sum(o.models for o in outcomes),
        compute_seconds=sum(o.seconds for o in outcomes),
        compute_cpu_seconds=sum(o.cpu_seconds for o in outcomes),
        wall_seconds=wall,
        executor=engine.description,
    )
    if warn:
        _emit(summary)
    return SweepTable(table, summary, stats)


def read_scenes(path: str | os.PathLike) -> dict[str, list]:
    """Read a scene table from a CSV file, for :func:`sweep` (``fastline batch``).

    The file has a header row of column names (:data:`SCENE_COLUMNS`, or the same names with
    their units as :meth:`SweepTable.to_csv` writes them: ``E_star_Pa``, ``load_N_per_m``...)
    and one row per scene, comma-separated (double quotes allowed around a cell); ``#`` lines
    are comments. An empty cell takes the column's default. Spectrum files in a ``psd`` column
    are relative to the CSV file's directory; ``none`` there means no spectrum (hertz).

    Returns
    -------
    dict
        Column name -> list of cells (numbers as floats, text as str), for :func:`sweep`.

    Raises
    ------
    ValueError
        When the file cannot be read, a row has the wrong number of cells, or a column is
        unknown (each named).
    """
    path = os.fspath(path)
    header, body = _csv_rows(path)
    aliases = {c.csv_name: c.name for c in _INPUTS} | {c.name: c.name for c in _INPUTS}
    aliases["load_N"] = "load"  # the load on a sphere (SweepTable.to_csv names it so)
    unknown = [k for k in header if k not in aliases]
    if unknown:
        raise ValueError(f"{path}: unknown columns {unknown}; allowed: {', '.join(SCENE_COLUMNS)}")
    base = os.path.dirname(os.path.abspath(path))
    cols = {}
    for j, key in enumerate(header):
        col = _BY_NAME[aliases[key]]
        cols[col.name] = [_csv_cell(col, row[j].strip(), base) for _line, row in body]
    return cols


def _csv_rows(path: str) -> tuple[list[str], list[tuple[int, list[str]]]]:
    """Header and (line number, cells) of the data rows of a CSV file."""
    import csv

    try:
        with open(path, encoding="utf-8", newline="") as fh:
            lines = [(k, ln) for k, ln in enumerate(fh, 1) if ln.strip() and ln[0] != "#"]
    except OSError as e:
        raise ValueError(f"cannot read scene table {path}: {e.strerror}") from None
    except UnicodeDecodeError:
        raise ValueError(f"{path}: not a text file") from None
    if len(lines) < 2:
        raise ValueError(f"{path}: need a header row and at least one scene")
    rows = [(k, row) for (k, _), row in zip(lines, csv.reader(ln for _, ln in lines), strict=True)]
    header = [h.strip() for h in rows[0][1]]
    for k, row in rows[1:]:
        if len(row) != len(header):
            raise ValueError(f"{path}:{k}: {len(row)} cells, the header names {len(header)}")
    return header, rows[1:]


def _csv_cell(col: _Column, text: str, base: str):
    if text == "":
        return None
    if col.kind in ("float", "int"):
        try:
            return float(text)
        except ValueError:
            return text  # reported by sweep's type check, with its row
    if col.kind == "psd":
        return None if text == "none" else os.path.join(base, text)
    return text
