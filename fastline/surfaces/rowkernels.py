"""Compiled passes over long profiles: the line fit, the detrended copy, the Hann window, the
periodogram's power (private).

A profile of 10^7 heights goes through each of these once, without work arrays of its size:
NumPy would spend a temporary array (and a pass over memory) on each elementary operation.
Heights in m, indices j = 0 .. n-1 along the profile.
"""

from __future__ import annotations

import math

import numba
import numpy as np

from fastline._lib.jit import JIT

__all__ = ["line_sums", "detrend_into", "hann_in_place", "add_power"]

#: the Hann window's cosine is advanced by a rotation and taken afresh every this many points
#: (the rotation's rounding grows ~1e-16 a step: below 1e-13 between fresh values)
_RESYNC = 512


@numba.njit(**JIT)
def line_sums(row: np.ndarray) -> tuple[float, float]:
    """(sum h_j, sum (j - c) h_j) with ``c = (n - 1) / 2``: the mean and the centred first
    moment of a profile, in one pass (pairs of partial sums keep the rounding small)."""
    n = row.shape[0]
    c = 0.5 * (n - 1)
    s0 = 0.0
    s1 = 0.0
    for start in range(0, n, 4096):
        p0 = 0.0
        p1 = 0.0
        for j in range(start, min(start + 4096, n)):
            p0 += row[j]
            p1 += (j - c) * row[j]
        s0 += p0
        s1 += p1
    return s0, s1


@numba.njit(**JIT)
def detrend_into(
    row: np.ndarray, mean: float, slope: float, out: np.ndarray
) -> tuple[float, float]:
    """``out_j = h_j - mean - slope (j - c)`` (``c = (n - 1) / 2``); returns the sum of the
    squares of out and of its differences ``out_{j+1} - out_j`` (h_rms and the rms slope)."""
    n = row.shape[0]
    c = 0.5 * (n - 1)
    squares = 0.0
    steps = 0.0
    previous = 0.0
    for start in range(0, n, 4096):
        p_sq = 0.0
        p_st = 0.0
        for j in range(start, min(start + 4096, n)):
            v = row[j] - mean - slope * (j - c)
            out[j] = v
            p_sq += v * v
            if j > 0:
                d = v - previous
                p_st += d * d
            previous = v
        squares += p_sq
        steps += p_st
    return squares, steps


@numba.njit(**JIT)
def hann_in_place(row: np.ndarray, scale: float) -> None:
    """``h_j *= scale (1 - cos(2 pi j / n)) / 2`` (the periodic Hann window): the cosine
    advanced by a rotation of ``2 pi / n`` and taken afresh every ``_RESYNC`` points."""
    n = row.shape[0]
    step = 2.0 * math.pi / n
    cs = math.cos(step)
    sn = math.sin(step)
    for start in range(0, n, _RESYNC):
        c = math.cos(step * start)
        s = math.sin(step * start)
        for j in range(start, min(start + _RESYNC, n)):
            row[j] *= 0.5 * scale * (1.0 - c)
            c, s = c * cs - s * sn, s * cs + c * sn


@numba.njit(**JIT)
def add_power(F: np.ndarray, out: np.ndarray) -> None:
    """``out_m += |F_m|^2`` (a periodogram's power, summed over profiles)."""
    for m in range(F.shape[0]):
        out[m] += F[m].real * F[m].real + F[m].imag * F[m].imag
