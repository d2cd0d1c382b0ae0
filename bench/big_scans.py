"""Big scans through :func:`fastline.surfaces.analyse_scan`: time and peak memory.

Three files, written once in a temporary folder: a line scan of 10^7 heights as ``.npy``, the
same kind of scan as a ~90 MB two-column text file (x and h in micrometres, a header line), and
a 4096 x 4096 height map as ``.npy``. Each is analysed at the defaults after a warm-up call on
a small scan (the compiled kernels loaded); the peak is what ``tracemalloc`` sees NumPy
allocate during a second call, against the size of the file's own float64 array (traced apart:
tracing slows NumPy's text reader many times). Beside the wall time: the CPU time of the process
(all its threads) and the load average of the machine at the end (a shared machine's wall time
follows its load; the CPU time much less).

Run: ``python -m bench.big_scans`` (``--skip-map`` to leave the map out).
"""

from __future__ import annotations

import argparse
import os
import tempfile
import time
import tracemalloc
import warnings

import numpy as np

import fastline as fl
from fastline.surfaces import analyse_scan


def _profile(n: int, seed: int) -> np.ndarray:
    """A rough profile in um: a random walk (H = 1/2) with 1 % white noise."""
    rng = np.random.default_rng(seed)
    h = np.cumsum(rng.standard_normal(n)) * 1e-3
    return h + 0.01 * float(np.std(h)) * rng.standard_normal(n)


def _reference(n: int) -> float:
    """Seconds of one real FFT of n points plus the sum of their squares: the load of the
    machine at the time, to read the analysis times as ratios."""
    x = np.random.default_rng(0).standard_normal(n)
    start = time.perf_counter()
    np.fft.rfft(x)
    float(np.dot(x, x))
    return time.perf_counter() - start


def _measure(label: str, path: str, points: int, **options) -> None:
    reference = _reference(points)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", fl.topography.TopographyWarning)
        start, cpu = time.perf_counter(), time.process_time()
        scan = analyse_scan(path, **options)
        seconds, cpu = time.perf_counter() - start, time.process_time() - cpu
        tracemalloc.start()  # a second call: tracing slows NumPy's text reader many times
        analyse_scan(path, **options)
        peak = tracemalloc.get_traced_memory()[1]
        tracemalloc.stop()
    size = 8 * points
    print(
        f"{label:<34} {seconds:6.1f} s, CPU {cpu:5.1f} s ({seconds / reference:4.0f} FFTs of "
        f"its size; load {os.getloadavg()[0]:.1f})   peak "
        f"{peak / 2**20:7.0f} MiB = {peak / size:4.2f} x "
        f"the array ({size / 2**20:.0f} MiB); H {scan.fit.hurst:.3f}, range ends "
        f"{scan.q_range[1]:.3g} 1/m ({scan.limits['high']})"
    )


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--skip-map", action="store_true")
    args = parser.parse_args(argv)
    folder = tempfile.mkdtemp()
    small = os.path.join(folder, "small.npy")
    np.save(small, _profile(4096, 0))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", fl.topography.TopographyWarning)
        analyse_scan(small, dx=1e-7, unit="um")  # warm: the compiled kernels loaded
    n = 10**7
    big = os.path.join(folder, "profile_1e7.npy")
    np.save(big, _profile(n, 1))
    _measure("10^7-point profile, .npy", big, n, dx=1e-7, unit="um")
    text = os.path.join(folder, "profile_text.txt")
    m = 3_800_000
    h = _profile(m, 2)
    np.savetxt(text, np.column_stack([np.arange(m) * 0.1, h]), fmt="%.4f %.9f",
               header="x [um] h [um]")  # fmt: skip
    del h
    size = os.path.getsize(text) / 1e6
    _measure(f"{size:.0f} MB text (x, h), {m:.2g} points", text, 2 * m)
    if not args.skip_map:
        maps = os.path.join(folder, "map_4096.npy")
        rng = np.random.default_rng(3)
        np.save(maps, np.cumsum(np.cumsum(rng.standard_normal((4096, 4096)), 0), 1) * 1e-6)
        _measure("4096 x 4096 map, .npy", maps, 4096 * 4096, dx=1e-6, as_map=True, unit="um")


if __name__ == "__main__":
    main()
