"""The log kernel's compliance applied by FFT: zero-padded circulant convolutions of length 2n.

``K = scale * toeplitz(khat)`` (:mod:`fastline.elastic.line`) with ``scale = dx / E*``; its
tables (:class:`KernelTables`) are the spectrum of the circulant embedding, the Strang
circulant's spectrum and the prefix sums of khat, kept per n by
:func:`fastline.elastic.line.compiled_tables`. FFT plans and aligned buffers come from
:mod:`fastline._lib.fftw`.
"""

from __future__ import annotations

from typing import NamedTuple

import numba
import numpy as np

from fastline._lib.fftw import aligned_buffers, execute
from fastline._lib.jit import JIT

__all__ = ["KernelTables", "KernelScale", "convolve", "apply_kernel", "segment_sum", "prefix_sums"]


class KernelTables(NamedTuple):
    """The log kernel's tables for n cells, dimensionless (K = scale * toeplitz(khat);
    :func:`fastline.elastic.line.compiled_tables` keeps them per n)."""

    #: spectrum of the zero-padded circulant embedding of khat, divided by 2n (n + 1 values)
    kspec: np.ndarray
    #: spectrum of khat's Strang circulant (n + 1 values)
    strang: np.ndarray
    #: prefix sums of the two-sided khat (2n values, :func:`prefix_sums`)
    prefix: np.ndarray


class KernelScale(NamedTuple):
    """The scale of the log kernel's compliance ``K = scale * toeplitz(khat)`` on a grid."""

    #: dx / E* (m/Pa)
    scale: float
    #: ``K00 = scale * khat_0``, the compliance's diagonal (m/Pa)
    diagonal: float


# ----------------------------------------------------------------------------------------------
# FFT convolutions
# ----------------------------------------------------------------------------------------------
@numba.njit(**JIT)
def convolve(
    x: np.ndarray,
    m: int,
    spec: np.ndarray,
    fr2c: object,
    fc2r: object,
    pf: np.ndarray,
    pb: np.ndarray,
    a: np.ndarray,
    c: np.ndarray,
    out: np.ndarray,
) -> None:
    """``out[:m] = (IFFT(spec * FFT([x[:m], 0...])))[:m]``: a linear convolution with the
    kernel whose real spectrum (normalisation included) is ``spec``; one FFT convolution."""
    for i in range(m):
        a[i] = x[i]
    for i in range(m, a.shape[0]):
        a[i] = 0.0
    execute(fr2c, pf, a.ctypes.data, c.ctypes.data)
    for k in range(spec.shape[0]):  # c holds (re, im) pairs; spec is real
        c[2 * k] *= spec[k]
        c[2 * k + 1] *= spec[k]
    execute(fc2r, pb, c.ctypes.data, a.ctypes.data)
    for i in range(m):
        out[i] = a[i]


@numba.njit(**JIT)
def apply_kernel(
    x: np.ndarray,
    kspec: np.ndarray,
    scale: float,
    fr2c: object,
    fc2r: object,
    pf: np.ndarray,
    pb: np.ndarray,
    out: np.ndarray,
) -> None:
    """``out = K x`` with ``K = scale * toeplitz(khat)`` (``kspec``: spectrum of the zero-padded
    circulant embedding of khat, divided by 2n)."""
    n = x.shape[0]
    a, c = aligned_buffers(2 * n)
    convolve(x, n, kspec, fr2c, fc2r, pf, pb, a, c, out)
    for i in range(n):
        out[i] *= scale


# The coarse level's products with ``H P`` (:func:`_precondition`) take one shifted window
# ``Tc[n - e_j : 2n - e_j]`` of the prefix sums per aggregate edge: nc + 1 = 17 passes over n
# cells, as many multiply-adds as 8-17 FFT convolutions of size 2n. Both run four edges per
# pass (one load of x or r for four windows). The correlations are sums that LLVM vectorises
# once it may reassociate them (``JIT_SUMS``); before, four scalar chains per edge in registers
# (0.17-0.21 ns per cell and edge) beat the strip sums of :func:`_wdot` (0.27-0.69).
@numba.njit(**JIT)
def segment_sum(a: np.ndarray, b: np.ndarray, lo: int, hi: int) -> float:
    """``sum_{lo <= i < hi} a_i b_i`` in four chains (aggregate sums, a few to n cells)."""
    sa, sb = a[lo:hi], b[lo:hi]
    m = hi - lo
    m4 = m - m % 4
    s0 = s1 = s2 = s3 = 0.0
    for i in range(0, m4, 4):
        s0 += sa[i] * sb[i]
        s1 += sa[i + 1] * sb[i + 1]
        s2 += sa[i + 2] * sb[i + 2]
        s3 += sa[i + 3] * sb[i + 3]
    for i in range(m4, m):
        s0 += sa[i] * sb[i]
    return (s0 + s1) + (s2 + s3)


def prefix_sums(khat: np.ndarray) -> np.ndarray:
    """``T`` with ``T[0] = 0`` and ``T[j+1] = sum_{l <= j} khat_|l - (n-1)|`` (length 2n)."""
    two_sided = np.concatenate([khat[:0:-1], khat])
    return np.concatenate([[0.0], np.cumsum(two_sided)])
