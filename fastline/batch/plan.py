"""The plan of a sweep: scenes grouped by model, cut into pieces (one continuation sweep
each) and packed into tasks (what an executor receives); see :mod:`fastline.batch`.

The plan depends on the table and ``chunksize`` only, never on the executor.
"""

from __future__ import annotations

import hashlib
import math
import pickle
from collections.abc import Mapping
from dataclasses import dataclass, field

import numpy as np

from fastline.batch.laws import LawKeys
from fastline.batch.scenes import SPECTRUM_PARAMS

__all__ = ["default_chunksize", "pool_pays", "DEFAULT_TASKS", "MIN_CHUNK", "MAX_CHUNK"]

#: default plan: about this many tasks per table, each of ``[MIN, MAX]`` scenes. Measured with
#: 2 workers on paper-like scenes at n = 256 (0.4-0.6 ms of CPU per scene; docs/throughput.md):
#: the engine costs 0.5-1.3 ms per task in a local pool and 4-13 ms on dask; with 157 scenes
#: per task (10,000 scenes) the workers were 89-94% busy, with 8 per task 80-90% (pool).
DEFAULT_TASKS, MIN_CHUNK, MAX_CHUNK = 64, 8, 256
#: when the default local pool pays for its start: each spawned worker imports fastline and
#: loads the compiled kernels before its first scene (10.6 s for 2 workers on a loaded 2-core
#: machine, ``python -m bench.batch_pool``), while a cylinder scene at n = 1024 costs ~2 ms in
#: a continuation sweep (6.6 ms in another run, where a sphere took 10 ms at n = 128 and 30 ms
#: at n = 256) and each distinct spectrum ~80 ms of theory tables. The table's work in
#: cylinder scenes at n = 1024: per scene ``w (n / n_ref)^k`` with ``(w, n_ref, k)`` of
#: ``POOL_WORK`` by geometry, plus ``POOL_THEORY_WORK`` per distinct model; the pool starts
#: from ``POOL_MIN_WORK`` (about twice the start-up in serial work; docs/sweeps.md).
POOL_MIN_WORK = 10_000.0
POOL_THEORY_WORK = 40.0
POOL_WORK = {"cylinder": (1.0, 1024, 1), "sphere": (20.0, 512, 2)}


def pool_pays(tasks: list[tuple[Piece, ...]]) -> bool:
    """Whether the tasks hold enough work for the default pool to pay for starting its
    workers (``POOL_MIN_WORK``; a smaller table runs faster in this process)."""
    work, models = 0.0, set()
    for task in tasks:
        for piece in task:
            weight, n_ref, power = POOL_WORK.get(piece.spec.geometry, (1.0, 1024, 1))
            work += len(piece.rows) * weight * (piece.spec.n / n_ref) ** power
            models.add(piece.spec)
    return work + POOL_THEORY_WORK * len(models) >= POOL_MIN_WORK


# ----------------------------------------------------------------------------------------------
# the plan: groups of scenes sharing a model, pieces, tasks
# ----------------------------------------------------------------------------------------------
@dataclass(frozen=True)
class ModelSpec:
    """Everything about a scene but its load: what a worker needs to build (or find) a model.

    ``spectrum`` is a hashable key: ``("self-affine", h_rms, H, q0, qr, q1)``, ``("file",
    path)``, ``("object", digest of the pickled PSD)`` or ``("none",)``; ``psd`` carries the
    object for the ``"object"`` kind (not part of equality). ``law`` is the key of the law
    column (:class:`~fastline.batch.laws.LawKeys`): ``("none",)``, ``("file", path, checksum
    or None)`` or ``("data", checksum)``, with ``law_data`` the law's arrays for the last."""

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
    law: tuple = ("none",)
    psd: object = field(default=None, compare=False, hash=False, repr=False)
    law_data: object = field(default=None, compare=False, hash=False, repr=False)


@dataclass(frozen=True)
class Piece:
    """Scenes of one model, ordered by load: solved by one ``sweep`` call."""

    spec: ModelSpec
    rows: tuple[int, ...]
    loads: tuple[float, ...]


class _SpectrumKeys:
    """Spectrum keys of the table's cells; PSD objects digested once per object."""

    def __init__(self):
        self._digests: dict[int, str] = {}

    def column(self, cols: Mapping) -> list[tuple]:
        if "psd" not in cols:
            params = zip(*(cols[k] for k in SPECTRUM_PARAMS), strict=True)
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


#: the columns that, with the spectrum, make a model (in :class:`ModelSpec`'s order)
_MODEL_COLUMNS = (
    "geometry", "E_star", "radius", "model", "method", "n", "gamma", "variant", "tol"
)  # fmt: skip


def _groups(cols: Mapping) -> dict[ModelSpec, list[int]]:
    """Rows of each model, in order of first appearance (keyed by plain tuples: fast)."""
    max_iter = [m or None for m in cols["max_iter"]]
    hardness = [None if math.isnan(h) else h for h in cols["hardness"]]
    spectra = _SpectrumKeys().column(cols)
    laws = LawKeys().column(cols)
    law_keys = [key for key, _ in laws]
    rows: dict[tuple, list[int]] = {}
    keys = zip(
        spectra, *(cols[k] for k in _MODEL_COLUMNS), max_iter, hardness, law_keys, strict=True
    )
    for i, key in enumerate(keys):
        rows.setdefault(key, []).append(i)
    return {_spec(key, cols, laws, r[0]): r for key, r in rows.items()}


def _spec(key: tuple, cols: Mapping, laws: list, first: int) -> ModelSpec:
    """The model of a group; ``laws[first]``'s data (one object per distinct law, so a task
    that holds several pieces with one law pickles its arrays once)."""
    spectrum, geometry, *rest = key
    psd = cols["psd"][first] if spectrum[0] == "object" else None
    return ModelSpec(geometry, spectrum, *rest, psd=psd, law_data=laws[first][1])


def default_chunksize(scenes: int) -> int:
    """Scenes per task when none is given: about :data:`DEFAULT_TASKS` tasks, each of
    :data:`MIN_CHUNK` to :data:`MAX_CHUNK` scenes (a function of the table size only)."""
    return min(MAX_CHUNK, max(MIN_CHUNK, math.ceil(scenes / DEFAULT_TASKS)))


def plan_tasks(cols: Mapping, chunksize: int) -> list[tuple[Piece, ...]]:
    """Tasks (tuples of pieces) for the table; see :mod:`fastline.batch`."""
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
            current.append(Piece(spec, tuple(part.tolist()), tuple(loads[part].tolist())))
            size += part.size
    tasks.append(tuple(current))
    return tasks
