"""The sweep itself, :func:`sweep`: check the table, plan it, run the tasks on an executor and
assemble the :class:`~fastline.batch.table.SweepTable` (see :mod:`fastline.batch`)."""

from __future__ import annotations

import concurrent.futures as cf
import sys
import time
from collections.abc import Iterable, Mapping
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import ArrayLike
from tqdm import tqdm

from fastline._lib.executors import close_engine, open_engine
from fastline._lib.validate import boolean, integer
from fastline.batch.plan import Piece, default_chunksize, plan_tasks, pool_pays
from fastline.batch.scenes import normalise
from fastline.batch.table import (
    SweepStats,
    SweepTable,
    emit_warnings,
    empty_table,
    fill_table,
    summarise,
)
from fastline.batch.worker import TaskOutcome, task_outcomes

if TYPE_CHECKING:  # annotations only: pandas and dask are optional
    import pandas as pd
    from distributed import Client

    #: a table of scenes: rows (dicts), columns (a dict of sequences), a NumPy structured array
    #: or a pandas DataFrame
    Scenes = Iterable[Mapping[str, Any]] | Mapping[str, ArrayLike] | np.ndarray | pd.DataFrame

__all__ = ["sweep"]


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
        One scene per row, with the columns of :mod:`fastline.batch.scenes`: ``E_star`` [Pa],
        ``radius`` [m], ``load`` (N/m for a cylinder, N for a sphere), the spectrum and optional
        settings. Each scene is solved as ``LineContact(psd, E_star, radius, ...).solve(load)``
        would (``PointContact`` for a sphere); a bad value fails that scene only.
    executor : None, "serial", str, concurrent.futures.Executor or dask Client
        None (default): a pool of ``workers`` spawned processes, made and shut down here (this
        process for one task, ``workers=1`` or too little work). ``"serial"``: in this process,
        in order. A dask scheduler address (``"tcp://host:8786"``; the ``dask`` extra), an
        executor or a ``distributed.Client``: used as given and left running. Workers must
        import fastline and read the spectrum files named in the table.
    workers : int, optional
        Processes of the default pool (default: the CPUs this process may use, for a table
        whose work pays for them: :func:`fastline.batch.plan.pool_pays`).
    chunksize : int, optional
        Scenes per task at most (default :func:`default_chunksize`: ~64 tasks); the results
        depend on it within the solver tolerance, and not at all on the executor.
    progress : bool or None
        A tqdm progress bar on stderr (None: only when stderr is a terminal).
    warn : bool
        Emit, once each for the sweep, a :class:`~fastline.errors.SceneFailureWarning`, a
        ``ConvergenceWarning`` and a ``ValidityWarning`` per cause (kept in ``.warnings``).

    Returns
    -------
    SweepTable
        One row per scene, in the order given (``.table``, ``.to_csv``, ``.to_pandas``).

    Raises
    ------
    ValueError, TypeError, ImportError, OSError
        Before any work: unknown or missing columns, a cell of the wrong type, an unknown
        geometry, model, method or variant, a bad ``chunksize``, ``workers`` or ``executor``; a
        scheduler address without dask installed (ImportError) or out of reach (OSError).
    """
    t0 = time.perf_counter()
    progress, warn = _flags(progress, warn)
    cols = normalise(scenes)
    size = len(cols["load"])
    chunk = default_chunksize(size) if chunksize is None else integer("chunksize", chunksize, 1)
    tasks = plan_tasks(cols, chunk)
    outcomes, description = _run_tasks(tasks, executor, workers, size, progress)
    table, summary = _assemble(cols, outcomes)
    stats = _stats(outcomes, size, len(tasks), chunk, t0, description)
    if warn:
        emit_warnings(summary)
    return SweepTable(table, summary, stats)


def _flags(progress, warn) -> tuple[bool | None, bool]:
    """``progress`` (None kept) and ``warn`` as bools; a TypeError naming either otherwise."""
    return (None if progress is None else boolean("progress", progress)), boolean("warn", warn)


def _run_tasks(
    tasks: list[tuple[Piece, ...]],
    executor: str | cf.Executor | Client | None,
    workers: int | None,
    scenes: int,
    progress: bool | None,
) -> tuple[list[TaskOutcome], str]:
    """Every task's outcome, in the order completed, and what ran them; the engine (a pool made
    here, a dask client connected here) is closed whatever happens."""
    if executor is None and workers is None and not pool_pays(tasks):
        executor = "serial"  # too little work to pay for starting a pool: faster here
    engine = open_engine(executor, workers, len(tasks))
    outcomes = []
    try:
        disable = None if progress is None else not progress
        with tqdm(
            total=scenes, desc="sweep", unit="scene", file=sys.stderr, disable=disable
        ) as bar:
            for outcome in task_outcomes(tasks, engine):
                outcomes.append(outcome)
                bar.update(len(outcome.rows))
    finally:
        close_engine(engine)
    return outcomes, engine.description


def _assemble(
    cols: dict[str, list], outcomes: list[TaskOutcome]
) -> tuple[np.ndarray, list[tuple[str, str]]]:
    """The result table (the scene columns, then the workers' rows) and its warnings, once per
    cause."""
    table = empty_table(cols)
    return table, summarise(table, fill_table(table, outcomes))


def _stats(
    outcomes: list[TaskOutcome], scenes: int, tasks: int, chunksize: int, t0: float, executor: str
) -> SweepStats:
    """How the sweep ran; its wall time from ``t0`` (a ``time.perf_counter()``) to now."""
    wall = time.perf_counter() - t0
    return SweepStats(
        scenes=scenes,
        tasks=tasks,
        chunksize=chunksize,
        workers=len({o.worker for o in outcomes if o.worker != "?"}),
        theory_builds=sum(o.theories for o in outcomes),
        model_builds=sum(o.models for o in outcomes),
        compute_seconds=sum(o.seconds for o in outcomes),
        compute_cpu_seconds=sum(o.cpu_seconds for o in outcomes),
        wall_seconds=wall,
        executor=executor,
    )
