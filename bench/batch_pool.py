"""When a local process pool pays for itself: ``python -m bench.batch_pool``.

Times :func:`fastline.sweep` on tables of 3 to N rows (the seal study of ``fastline batch``:
paper-like scenes, 3 surfaces, n = 1024, loads alpha 1e-2..1e2), once in this process and once
on a fresh pool of spawned workers (each must import fastline and load the compiled kernels
before its first scene). Prints rows, the serial and pool wall times and their ratio; the
break-even is where the ratio crosses 1. The pool's start-up is measured alone too (a
one-scene task per worker), and a table whose scenes each have their own spectrum (a theory
build per scene). Kernels are compiled before the first timing. The rule it sizes:
``fastline.batch.plan.pool_pays``.
"""

from __future__ import annotations

import sys
import time
import warnings

import fastline as fl

SURFACES = ((1e-6, 0.8), (10e-6, 0.8), (10e-6, 0.5))
SIZES = (3, 12, 48, 192, 768)


def table(rows: int, n: int = 1024) -> list[dict]:
    """``rows`` scenes over 3 surfaces and 4 models' loads (alpha 1e-2..1e2)."""
    out = []
    for i in range(rows):
        h, H = SURFACES[i % 3]
        alpha = 10.0 ** (-2 + 4 * ((i * 7919) % 97) / 96)
        load = float(fl.paper.load_for_alpha(alpha, h))
        out.append(dict(h_rms=h, hurst=H, q0=1e3, qr=1e4, q1=1e9, E_star=1.33e9,
                        radius=0.01, load=load, n=n))  # fmt: skip
    return out


def timed(scenes, **kw) -> float:
    t0 = time.perf_counter()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        fl.sweep(scenes, progress=False, **kw)
    return time.perf_counter() - t0


def main(workers: int = 2, sizes=SIZES) -> None:
    timed(table(3), executor="serial")  # compile / load the kernels here
    start = timed(table(workers), workers=workers, chunksize=1)
    print(f"pool of {workers} spawned workers, one scene each: {start:.2f} s")
    print(f"{'rows':>6}{'serial s':>10}{'pool s':>10}{'pool/serial':>13}")
    for rows in sizes:
        scenes = table(rows)
        serial = timed(scenes, executor="serial")
        pool = timed(scenes, workers=workers)
        print(f"{rows:>6}{serial:>10.2f}{pool:>10.2f}{pool / serial:>13.2f}", flush=True)
    for rows in (12, 48):
        serial = timed(distinct(rows), executor="serial")
        print(f"{rows} scenes of {rows} spectra (a theory each), serial: {serial:.2f} s")


if __name__ == "__main__":
    main(*(int(a) for a in sys.argv[1:2]))


def distinct(rows: int, n: int = 1024) -> list[dict]:
    """``rows`` scenes, each of its own spectrum (a theory build each)."""
    return [dict(h_rms=1e-6 * (1 + i / rows), hurst=0.8, q0=1e3, qr=1e4, q1=1e9, E_star=1.33e9,
                 radius=0.01, load=1e4, n=n) for i in range(rows)]  # fmt: skip
