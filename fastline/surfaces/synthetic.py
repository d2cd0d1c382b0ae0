"""Synthetic surfaces: periodic Gaussian random height maps with a given isotropic spectrum.

Heights and spacings in m, wavenumbers in 1/m, C(q) in m^4 (Persson's convention).
"""

from __future__ import annotations

import math

import numpy as np

from fastline._lib.validate import integer, positive
from fastline.theory.spectra import PSD

#: most points of a synthetic surface, n * ny (4096 x 4096: ~1 GB of FFT work arrays)
SYNTHETIC_MAX_POINTS = 4096 * 4096
_SYNTHETIC_WHY = " (n * ny at most 4096 x 4096 points: the FFTs need ~64 bytes a point)"


def synthetic_surface(
    psd: PSD,
    n: int,
    dx: float,
    *,
    ny: int | None = None,
    seed: int | np.random.Generator | None = None,
) -> np.ndarray:
    """A periodic Gaussian random surface with the isotropic spectrum psd, shape (ny, n).

    Unit white noise, Fourier transformed, shaped by ``sqrt((2 pi)^2 A C(|q|) / ((dx dy)^2 N))``
    and transformed back: random phases and Gaussian amplitudes, ``E[h_rms^2]`` the sum of
    ``C(|q|) (2 pi)^2 / A`` over the grid's wavenumbers (the spectrum's h_rms^2 up to the
    discreteness of the grid and its Nyquist limit ``pi / dx``).

    Parameters
    ----------
    psd : PSD
        Isotropic spectrum (Persson's convention).
    n, ny : int
        Points along x and y (ny defaults to n), >= 2; ``n * ny`` at most
        ``SYNTHETIC_MAX_POINTS`` (4096 x 4096).
    dx : float
        Spacing in m (both directions).
    seed : int or numpy Generator, optional

    Raises
    ------
    ValueError
        Bad sizes or spacing, or a grid none of whose wavenumbers (2 pi / L up to the Nyquist
        corner) lies where the spectrum is nonzero: the surface would be flat.
    """
    if not isinstance(psd, PSD):
        raise TypeError(f"psd must be a fastline PSD, got {type(psd).__name__}")
    if ny is None:  # a square map
        n = ny = integer("n", n, 2, math.isqrt(SYNTHETIC_MAX_POINTS), _SYNTHETIC_WHY)
    else:
        n = integer("n", n, 2, SYNTHETIC_MAX_POINTS // 2, _SYNTHETIC_WHY)
        ny = integer("ny", ny, 2, SYNTHETIC_MAX_POINTS // n, _SYNTHETIC_WHY)
    dx = positive("dx", dx, "m")
    qx = 2.0 * math.pi * np.fft.fftfreq(n, dx)
    qy = 2.0 * math.pi * np.fft.fftfreq(ny, dx)
    q = np.hypot(qy[:, None], qx[None, :])
    C = psd(q)
    if not np.any(C > 0.0):
        raise ValueError(
            f"the grid's wavenumbers {2.0 * math.pi / (max(n, ny) * dx):.4g}-{q.max():.4g} 1/m "
            f"(2 pi / L to the Nyquist corner) miss the spectrum, which is 0 outside "
            f"{float(psd.q0):.4g}-{float(psd.q1):.4g} 1/m: the surface would be flat (is dx in m?)"
        )
    rng = np.random.default_rng(seed)
    noise = np.fft.fft2(rng.standard_normal((ny, n)))
    area = n * ny * dx * dx
    amplitude = np.sqrt((2.0 * math.pi) ** 2 * area * C / (dx**4 * n * ny))
    return np.fft.ifft2(noise * amplitude).real
