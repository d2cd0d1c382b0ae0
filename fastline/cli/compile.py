"""Compile fastline's kernels ahead of time: ``fastline compile``.

Fills Numba's on-disk cache with every kernel a user can reach (line and point contacts,
sweeps, Persson tables, leakage), one group of kernels per process and several processes at
once on a machine with more than one core (:func:`fastline.compile_kernels`). After it, a new
process loads the machine code instead of compiling it: a first answer in about a second
instead of tens of seconds. Run it once after ``pip install``, when building a container
image and on each kind of worker machine of a cluster (docs/performance.md, cold start).
"""

from __future__ import annotations

import argparse
import os
import sys
import time

import fastline as fl

__all__ = ["compile_parser", "cmd_compile"]


def compile_parser(sub: argparse._SubParsersAction, fmt: type[argparse.HelpFormatter]) -> None:
    """The ``compile`` command: build Numba's cache of every kernel, ahead of time."""
    p = sub.add_parser(
        "compile",
        help="compile every kernel for this machine now (Numba's on-disk cache), not at first use",
        formatter_class=fmt,
        description="Compile every kernel a user can reach (line and point contacts, sweeps, "
        "Persson tables, leakage) into Numba's on-disk cache, beside the installed sources or "
        "under NUMBA_CACHE_DIR; later processes load them (a first answer in about a second). "
        "Groups of kernels compile in parallel processes. Run it after pip install, in a "
        "container image's build and on each kind of worker machine. Exit status 0 done, "
        "1 a group failed, 2 bad usage.",
    )
    p.add_argument(
        "--jobs",
        type=int,
        default=None,
        metavar="N",
        help="processes at once (default: the usable CPUs, at most the number of groups)",
    )


def cmd_compile(args: argparse.Namespace) -> int:
    """Compile the groups, print one line per group and the total; 1 if a group failed."""
    if args.jobs is not None and args.jobs < 1:
        raise ValueError(f"--jobs must be an integer >= 1; got {args.jobs}")
    where = os.path.dirname(fl.__file__)
    print(f"fastline compile: compiling the kernels of {where} for this machine...", flush=True)
    t = time.perf_counter()
    reports = fl.compile_kernels(jobs=args.jobs)
    for r in reports:
        state = f"failed: {r.error}" if r.error else f"{r.compiled} kernels compiled"
        print(f"  {r.name:<26}{state} ({r.cpu_seconds:.1f} s CPU, {r.seconds:.1f} s)")
    failed = [r.name for r in reports if r.error]
    print(f"done in {time.perf_counter() - t:.1f} s" + (f"; failed: {failed}" if failed else ""))
    if failed:
        print(f"fastline: error: compiling {', '.join(failed)} failed", file=sys.stderr)
    return 1 if failed else 0
