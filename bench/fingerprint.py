"""A fingerprint of the line solver's arithmetic: ``python -m bench.fingerprint``.

Solves the count test's five hard surfaces at 8 alphas (1e-4..1e3) and n = 256, 1024, 4096,
sweeps 3 loads on each, and solves one smooth (``model="hertz"``) contact; prints the total
FFT convolutions and a SHA-256 of every pressure array. A refactoring that keeps the
arithmetic (same operations, same order) prints the same line on the same machine; any change
of round-off changes the hash. (Not comparable across machines: FFTW's plans and the CPU's
vector width may differ.) ~10 s warm.
"""

from __future__ import annotations

import hashlib

import numpy as np

import fastline as fl
from bench.conftest import E_STAR, RADIUS, load_for_alpha
from bench.core import ALPHAS, HARD

NS = (256, 1024, 4096)
SWEEP_ALPHAS = (1e2, 1.0, 1e-2)


def fingerprint() -> tuple[int, str]:
    """(total FFT convolutions, the first 16 hex digits of the pressures' SHA-256)."""
    digest, total = hashlib.sha256(), 0
    results = []
    for n in NS:
        for psd in HARD.values():
            lc = fl.LineContact(psd, E_STAR, RADIUS, n=n, warn=False)
            results += [lc.solve(load_for_alpha(a, psd.h_rms)) for a in ALPHAS]
            results += lc.sweep([load_for_alpha(a, psd.h_rms) for a in SWEEP_ALPHAS])
    smooth = fl.LineContact(HARD["surface 1"], E_STAR, RADIUS, n=1024, model="hertz", warn=False)
    results.append(smooth.solve(1e4))
    for r in results:
        digest.update(np.ascontiguousarray(r.pressure).tobytes())
        total += r.convolutions
    return total, digest.hexdigest()[:16]


if __name__ == "__main__":
    total, digest = fingerprint()
    print(f"{total} convolutions, pressures {digest}")
