"""Write examples/scan_example.txt: four parallel stylus traces of a synthetic surface.

A made-up "measurement" for the docs and the command line (``fastline psd``, ``--scan``): four
parallel traces, 2048 heights each at 1 µm spacing (2.048 mm), heights in µm rounded to 0.1 nm,
one trace per line. The surface is a Gaussian random surface of the self-affine spectrum with
roll-off h_rms 0.5 µm, H = 0.8, q0 = 1e3, qr = 3e4, q1 = 1e9 1/m (Persson's convention).

Each trace is a window of 2048 points cut from a periodic realisation 8 times longer, so the
traces are not periodic (as real ones are not) and hold wavelengths longer than themselves.
Traces far apart on an isotropic surface are independent realisations of a profile whose
two-sided 1D spectrum is the Abel transform of C(q) (docs/topography.md):

    C1D(k) = 2 int_k^q1 C(q) q / sqrt(q^2 - k^2) dq,

evaluated here by quadrature after ``q = k cosh t`` (no singularity). The Fourier coefficients
F_m = sum_j h_j exp(-i k_m x_j) of the periodic realisation (length L) are complex Gaussian with
``E|F_m|^2 = 2 pi L C1D(k_m) / dx^2``, the convention of ``fastline.surfaces.topography``. Run from
the repository root:

    python examples/make_scan_example.py
"""

import math
import os

import numpy as np
from scipy.integrate import quad

import fastline as fl

HERE = os.path.dirname(os.path.abspath(__file__))
TRUTH = fl.SelfAffinePSD(0.5e-6, 0.8, 1e3, 3e4, 1e9)
DX = 1e-6  # m
POINTS, TRACES, LONGER = 2048, 4, 8
SEED = 20260611


def c1d(k: float) -> float:
    """The two-sided 1D spectrum of TRUTH at k > 0 (m^3), by quadrature over t."""
    top = math.acosh(max(TRUTH.q1 / k, 1.0))
    kinks = [math.acosh(q / k) for q in (TRUTH.q0, TRUTH.qr) if q > k]

    def integrand(t):
        q = k * math.cosh(t)
        return TRUTH(q) * q

    return 2.0 * quad(integrand, 0.0, top, points=kinks or None, limit=200, epsrel=1e-10)[0]


def traces() -> np.ndarray:
    """TRACES windows of POINTS heights (m), each from its own periodic realisation."""
    n = POINTS * LONGER
    length = n * DX
    k = 2.0 * math.pi * np.arange(1, n // 2 + 1) / length
    amplitude = np.sqrt(np.array([c1d(kk) for kk in k]) * math.pi * length) / DX
    rng = np.random.default_rng(SEED)
    out = []
    for _ in range(TRACES):
        F = amplitude * (rng.standard_normal(k.size) + 1j * rng.standard_normal(k.size))
        F[-1] = F[-1].real * math.sqrt(2.0)  # the Nyquist coefficient is real
        h = np.fft.irfft(np.concatenate([[0.0], F]), n)
        start = int(rng.integers(0, n - POINTS))
        out.append(h[start : start + POINTS])
    return np.array(out)


def main() -> None:
    h_um = traces() * 1e6
    lines = [
        "# synthetic stylus traces (examples/make_scan_example.py): 4 parallel traces, one per",
        "# line, 2048 heights each in micrometres at dx = 1 um; surface: self-affine with",
        "# roll-off, h_rms 0.5 um, H 0.8, q0 1e3, qr 3e4, q1 1e9 1/m",
        "# fastline psd examples/scan_example.txt --dx 1e-6 --units um",
    ]
    lines += [" ".join(f"{v:.4f}" for v in row) for row in h_um]
    with open(os.path.join(HERE, "scan_example.txt"), "w", encoding="utf-8") as fh:
        fh.write("\n".join(lines) + "\n")


if __name__ == "__main__":
    main()
