"""Where a table of tasks runs: in this process, on a local process pool, or on dask.

Shared by :func:`fastline.sweep` and the boundary-element ensembles: :func:`open_engine` turns
the user's ``executor`` and ``workers`` into an :class:`Engine`, :func:`close_engine` shuts down
what it started.
"""

from __future__ import annotations

import concurrent.futures as cf
import os
from dataclasses import dataclass

from fastline._lib.validate import integer

__all__ = [
    "Engine",
    "open_engine",
    "close_engine",
    "available_cpus",
    "SCHEDULER_SCHEMES",
]

#: schemes of dask scheduler addresses accepted as ``executor``
SCHEDULER_SCHEMES = ("tcp://", "tls://", "ucx://", "ws://", "wss://", "inproc://")


def available_cpus() -> int:
    try:
        return len(os.sched_getaffinity(0))
    except AttributeError:  # pragma: no cover - not on Linux
        return os.cpu_count() or 1


def isdask_client(obj) -> bool:
    return type(obj).__module__.split(".")[0] == "distributed" and hasattr(obj, "get_executor")


def dask_client(address: str):
    try:
        from distributed import Client
    except ImportError:
        raise ImportError(
            f"executor={address!r} needs dask.distributed: "
            'pip install "fastline-contact[dask]" (the dask extra)'
        ) from None
    return Client(address)


@dataclass
class Engine:
    """Where tasks run: ``executor`` None means in this process, in order."""

    executor: cf.Executor | None
    description: str
    close: object = None  # what to shut down afterwards (an owned pool or client)


def open_engine(executor, workers: int | None, tasks: int) -> Engine:
    if workers is not None:
        if executor is not None:
            raise ValueError("workers applies only to the default local pool (executor=None)")
        workers = integer("workers", workers, 1)
    if executor is None:
        workers = workers or available_cpus()
        if workers == 1 or tasks == 1:
            return Engine(None, "serial (in this process)")
        import multiprocessing

        pool = cf.ProcessPoolExecutor(workers, mp_context=multiprocessing.get_context("spawn"))
        return Engine(pool, f"local process pool ({workers} workers)", pool)
    if isinstance(executor, str):
        if executor == "serial":
            return Engine(None, "serial (in this process)")
        if executor.startswith(SCHEDULER_SCHEMES):
            client = dask_client(executor)
            return Engine(client.get_executor(pure=False), f"dask scheduler {executor}", client)
        schemes = ", ".join(SCHEDULER_SCHEMES)
        raise ValueError(
            f'executor must be None, "serial", a dask scheduler address ({schemes}...), a '
            f"concurrent.futures.Executor or a dask Client, got {executor!r}"
        )
    if isdask_client(executor):
        return Engine(executor.get_executor(pure=False), f"dask client {executor!r}")
    if isinstance(executor, cf.Executor):
        return Engine(executor, f"{type(executor).__name__}")
    raise TypeError(
        'executor must be None, "serial", a dask scheduler address, a '
        f"concurrent.futures.Executor or a dask Client, got {type(executor).__name__}"
    )


def close_engine(engine: Engine) -> None:
    """Shut down what :func:`open_engine` started (a pool: pending tasks cancelled)."""
    owned = engine.close
    if owned is None:
        return
    if isdask_client(owned):
        owned.close()
    else:
        owned.shutdown(wait=True, cancel_futures=True)
