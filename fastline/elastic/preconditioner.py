"""The two-level preconditioner of the line contact's Newton systems (:mod:`fastline.elastic.pcg`).

A block smoother on the loaded core (Strang circulant of K plus D, solved by FFT, with Jacobi
outside it) and a coarse correction on aggregates of the wide block, placed by width and by the
variation of ``ln(D + K00)``; the measurements that chose the constants below are in the
docstring of :mod:`fastline.elastic.pcg`.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numba
import numpy as np

from fastline._lib.jit import JIT, JIT_SUMS
from fastline.elastic.convolution import convolve, segment_sum

#: core block of the smoother: cells with D < CORE_THETA K00
CORE_THETA = 10.0

__all__ = ["TwoLevel", "CORE_THETA", "WIDE_THETA", "EDGE_SHARE", "FROZEN_THETA"]


_CORE_MIN_CELLS = 8


#: wide block of the coarse correction: cells with D < WIDE_THETA K00
WIDE_THETA = 100.0


#: share of the coarse aggregates placed by the variation of ln(D + K00) across the wide block
#: (the rest by width; :func:`_aggregate_edges`)
EDGE_SHARE = 0.7


#: decoupled cells, left out of CG: D > FROZEN_THETA K00
FROZEN_THETA = 1e10


#: entries of ``span``, the preconditioner's integers: the live span [f0, f1), the core
#: [i0, i1), the number of aggregates
_F0, _F1, _I0, _I1, _NC = 0, 1, 2, 3, 4


class TwoLevel(NamedTuple):
    """The two-level preconditioner of one Newton system as set up by :func:`_smoother` and
    :func:`_coarse_level` (module docstring), what :func:`_precondition` applies."""

    #: the system's diagonal ``|du_law/dp|`` (n values, m/Pa)
    D: np.ndarray
    #: dx / E* (m/Pa)
    scale: float
    #: ``(minv, S, cinv, Tc)``: Jacobi ``1/(D + K00)`` (Pa/m, 0 on frozen cells), the core's
    #: scales S (dimensionless), the inverse Strang spectrum (Pa/m, the FFT's 1/(2n)
    #: included), the centred prefix sums Tc of khat (dimensionless, 2n values)
    pre: tuple
    #: Cholesky factor of the coarse matrix ``P^T H P`` (nc_max x nc_max, leading nc x nc, m/Pa)
    L: np.ndarray
    #: the aggregates' edges (cells, int64, nc_max + 1)
    e: np.ndarray
    #: ``(f0, f1, i0, i1, nc)``: the live span, the core, the number of aggregates (int64)
    span: np.ndarray
    #: work array of 2 nc_max + 2 elements
    g: np.ndarray


@numba.njit(**JIT_SUMS)
def _edge_correlations(x, Tc, e, nc, g, lo, hi):
    """``g[j] = sum_{lo <= i < hi} x_i Tc[n - e_j + i]`` for the edges ``j = 0..nc`` (n the
    length of x): ``(H P)^T x`` before differencing, x zero outside ``[lo, hi)``
    (:func:`_precondition`). Four edges per pass (one load of x for four windows), each sum
    vectorised by LLVM (``JIT_SUMS``: 0.064-0.073 ns per cell and edge at n = 512-16384,
    against 0.17-0.21 for four scalar chains per edge without reassociation)."""
    n = x.shape[0]
    xs = x[lo:hi]
    m = hi - lo
    j = 0
    while j + 4 <= nc + 1:
        t0 = Tc[n - e[j] + lo : n - e[j] + hi]
        t1 = Tc[n - e[j + 1] + lo : n - e[j + 1] + hi]
        t2 = Tc[n - e[j + 2] + lo : n - e[j + 2] + hi]
        t3 = Tc[n - e[j + 3] + lo : n - e[j + 3] + hi]
        s0 = s1 = s2 = s3 = 0.0
        for i in range(m):
            xi = xs[i]
            s0 += xi * t0[i]
            s1 += xi * t1[i]
            s2 += xi * t2[i]
            s3 += xi * t3[i]
        g[j] = s0
        g[j + 1] = s1
        g[j + 2] = s2
        g[j + 3] = s3
        j += 4
    for k in range(j, nc + 1):
        t = Tc[n - e[k] + lo : n - e[k] + hi]
        s = 0.0
        for i in range(m):
            s += xs[i] * t[i]
        g[k] = s


@numba.njit(**JIT)
def _subtract_edge_combination(r, Tc, e, nc, c, lo, hi):
    """``r_i -= sum_j c_j Tc[n - e_j + i]`` over the edges ``j = 0..nc``, for ``lo <= i < hi``
    (n the length of r): ``H P`` times a coarse vector where it is needed
    (:func:`_precondition`). Four edges per pass (vectorised: one store per cell for four
    windows instead of four)."""
    n = r.shape[0]
    rs = r[lo:hi]
    m = hi - lo
    j = 0
    while j + 4 <= nc + 1:
        c0, c1, c2, c3 = c[j], c[j + 1], c[j + 2], c[j + 3]
        t0 = Tc[n - e[j] + lo : n - e[j] + hi]
        t1 = Tc[n - e[j + 1] + lo : n - e[j + 1] + hi]
        t2 = Tc[n - e[j + 2] + lo : n - e[j + 2] + hi]
        t3 = Tc[n - e[j + 3] + lo : n - e[j + 3] + hi]
        for i in range(m):
            rs[i] -= (c0 * t0[i] + c1 * t1[i]) + (c2 * t2[i] + c3 * t3[i])
        j += 4
    for k in range(j, nc + 1):
        ck = c[k]
        t = Tc[n - e[k] + lo : n - e[k] + hi]
        for i in range(m):
            rs[i] -= ck * t[i]


# ----------------------------------------------------------------------------------------------
# preconditioner set-up
# ----------------------------------------------------------------------------------------------
@numba.njit(**JIT)
def _first_last(D, limit):
    """First and one-past-last cell with ``D < limit`` (0, 0 if none)."""
    i0 = -1
    i1 = 0
    for i in range(D.shape[0]):
        if D[i] < limit:
            if i0 < 0:
                i0 = i
            i1 = i + 1
    if i0 < 0:
        return 0, 0
    return i0, i1


@numba.njit(**JIT)
def _live_span(minv):
    """First and one-past-last cell that is not frozen (``minv > 0``; 0, 0 if none)."""
    n = minv.shape[0]
    f0 = 0
    while f0 < n and not minv[f0] > 0.0:
        f0 += 1
    f1 = n
    while f1 > f0 and not minv[f1 - 1] > 0.0:
        f1 -= 1
    return (f0, f1) if f0 < f1 else (0, 0)


@numba.njit(**JIT)
def _chol_solve(L, nc, b):
    """``b <- (L L^T)^-1 b`` for the leading nc x nc block, in place. Forward by rows, each
    dot product in four chains; backward by columns (independent updates): 0.29 against
    0.36 us at nc = 16 for the two solves as serial dot products."""
    for i in range(nc):
        Li = L[i]
        i4 = i - i % 4
        s0 = s1 = s2 = s3 = 0.0
        for j in range(0, i4, 4):
            s0 += Li[j] * b[j]
            s1 += Li[j + 1] * b[j + 1]
            s2 += Li[j + 2] * b[j + 2]
            s3 += Li[j + 3] * b[j + 3]
        for j in range(i4, i):
            s0 += Li[j] * b[j]
        b[i] = (b[i] - ((s0 + s1) + (s2 + s3))) / L[i, i]
    for i in range(nc - 1, -1, -1):
        bi = b[i] / L[i, i]
        b[i] = bi
        Li = L[i]
        for j in range(i):
            b[j] -= Li[j] * bi


@numba.njit(**JIT)
def _aggregate_edges(D, K00, j0, j1, nc, e, steps):
    """Edges ``e[0] = j0 < e[1] < ... < e[nc] = j1`` of the coarse aggregates: equal shares of
    the density ``(1 - EDGE_SHARE) / (j1 - j0) + EDGE_SHARE |d ln(D + K00)| / total`` per cell,
    i.e. by width in the core (where D << K00 and ln(D + K00) is flat) and by decades of D
    across the contact edge. Over the 160 count scenes (5 hard surfaces, alpha 1e-4..1e3,
    n 256..16384, with ``fastline.contact.core.ETA_RES_SCALE``): 4446 convolutions with equal
    widths, 3898 with a share of 0.5, 3713 with 0.7 (mirror-symmetric); the worst scene (alpha 1e-2,
    n 16384) 109 -> 99.

    Mirror-symmetric: the left half of the edges counts the share from ``j0``, the right half
    from ``j1``, an even ``nc`` puts the middle edge at the centre, so a symmetric D gives a
    symmetric preconditioner (and p(x) = p(-x) to round-off). Needs ``j1 - j0 >= 4 nc``.
    ``steps``: work array of ``j1 - j0`` elements or more (``|d ln(D + K00)|`` between cells: one
    logarithm per cell, where the three passes took two or three per cell)."""
    width = j1 - j0
    Db = D[j0:j1]
    for i in range(width):
        steps[i] = math.log(Db[i] + K00)
    for i in range(width - 1):  # in place: the step of ln(D + K00) from cell j0 + i to the next
        steps[i] = abs(steps[i + 1] - steps[i])
    total = 0.0
    for i in range(width - 1):
        total += steps[i]
    flat = (1.0 - EDGE_SHARE) / width if total > 0.0 else 1.0 / width
    steep = EDGE_SHARE / total if total > 0.0 else 0.0
    half = nc // 2
    e[0] = j0
    e[nc] = j1
    if 2 * half == nc:
        e[half] = (j0 + j1) // 2
    k = 1  # edge b opens when the share of the cells left of b reaches k / nc (1e-9: ties)
    acc = flat
    for b in range(j0 + 1, j1):
        if k >= (nc + 1) // 2:
            break
        if acc * nc >= k - 1e-9:
            e[k] = b
            k += 1
        acc += flat + steep * steps[b - j0 - 1]
    k = 1  # the same from the right: edge b with the share right of b reaching k / nc
    acc = flat
    for b in range(j1 - 1, j0, -1):
        if k >= (nc + 1) // 2:
            break
        if acc * nc >= k - 1e-9:
            e[nc - k] = b
            k += 1
        acc += flat + steep * steps[b - j0 - 1]
    for m in range(nc - 1, 0, -1):  # at least one cell each
        e[m] = min(e[m], e[m + 1] - 1)
    for m in range(1, nc):
        e[m] = max(e[m], e[m - 1] + 1)


@numba.njit(**JIT)
def _coarse_matrices(D, scale, prefix, j0, j1, nc, e, Tc, U, L):
    """For the aggregates with edges ``e`` (:func:`_aggregate_edges`): the centred prefix
    sums ``Tc = T - T[n]`` (for ``H P`` products, :func:`_precondition`) and the Cholesky
    factor ``L`` of ``P^T H P`` with its constant mode penalised.

    ``(P^T K P)_km = sum_{i in k} sum_{j in m} khat_|i-j|`` is four values of ``U``, the prefix
    sums of ``Tc`` over the window ``[n - (j1 - j0), n + (j1 - j0)]`` that the aggregates span:
    O(n + nc^2) instead of O(n nc). (Centring keeps ``U`` of the size of the sums it yields.)
    """
    n = D.shape[0]
    t_mid = prefix[n]
    for j in range(2 * n):
        Tc[j] = prefix[j] - t_mid
    width = j1 - j0
    lo = n - width
    U[0] = 0.0
    for j in range(2 * width):
        U[j + 1] = U[j] + Tc[lo + j]
    for k in range(nc):
        for m in range(nc):
            s = (U[e[k + 1] - e[m] + width] - U[e[k] - e[m] + width]) - (
                U[e[k + 1] - e[m + 1] + width] - U[e[k] - e[m + 1] + width]
            )
            L[k, m] = scale * s
    for k in range(nc):
        dsum = 0.0
        for i in range(e[k], e[k + 1]):
            dsum += D[i]
        L[k, k] += dsum
    sizes = 0.0
    energy = 0.0
    diag_max = 0.0
    for k in range(nc):
        sizes += (e[k + 1] - e[k]) ** 2
        diag_max = max(diag_max, abs(L[k, k]))
        for m in range(k):
            L[k, m] = L[m, k] = 0.5 * (L[k, m] + L[m, k])
    for k in range(nc):
        for m in range(nc):
            energy += L[k, m] * (e[k + 1] - e[k]) * (e[m + 1] - e[m])
    big = (2.0 * abs(energy) / sizes + nc * diag_max) / sizes
    for k in range(nc):
        for m in range(nc):
            L[k, m] += big * (e[k + 1] - e[k]) * (e[m + 1] - e[m])
    # in-place lower Cholesky factor
    for j in range(nc):
        acc = L[j, j]
        for k in range(j):
            acc -= L[j, k] * L[j, k]
        L[j, j] = math.sqrt(acc)
        for i in range(j + 1, nc):
            acc = L[i, j]
            for k in range(j):
                acc -= L[i, k] * L[j, k]
            L[i, j] = acc / L[j, j]


@numba.njit(**JIT, inline="always")
def _smoother(D, K00, scale, strang, minv, S, cinv, span):
    """Set up the smoother (module docstring): ``minv = 1/(D + K00)``, 0 on frozen cells; on
    the loaded core ``[i0, i1)`` the scales ``S`` and ``cinv``, the spectrum of the inverse
    Strang circulant of ``K + d I`` (d the geometric mean of D there; the FFT's 1/(2n)
    included). Writes the live span ``f0, f1`` (:func:`_live_span`) and the core ``i0, i1``
    (0, 0: none) into ``span``."""
    n = D.shape[0]
    for i in range(n):
        minv[i] = 0.0 if D[i] > FROZEN_THETA * K00 else 1.0 / (D[i] + K00)
    f0, f1 = _live_span(minv)
    i0, i1 = _first_last(D, CORE_THETA * K00)
    if i1 - i0 < _CORE_MIN_CELLS:
        i0 = i1 = 0
    else:
        Dc = D[i0:i1]
        logsum = 0.0
        for i in range(i1 - i0):
            logsum += math.log(Dc[i])
        shift = math.exp(logsum / (i1 - i0))  # geometric mean of D on the core
        for i in range(i1 - i0):
            S[i] = math.sqrt((K00 + shift) / (K00 + Dc[i]))
        for k in range(n + 1):
            cinv[k] = 1.0 / ((scale * strang[k] + shift) * (2 * n))
    span[_F0] = f0
    span[_F1] = f1
    span[_I0] = i0
    span[_I1] = i1


@numba.njit(**JIT, inline="always")
def _coarse_level(D, K00, scale, prefix, nc_max, coarse, steps, span):
    """Set up the coarse level on the wide block (cells with ``D < WIDE_THETA K00``): at most
    ``nc_max`` aggregates, a quarter of its cells, none below two (:func:`_aggregate_edges`,
    :func:`_coarse_matrices`). ``coarse = (e, Tc, U, L)``, written: the aggregates' edges
    (cells, int64, nc_max + 1), the centred prefix sums of khat (dimensionless, 2n), work for
    their sums (2n + 1) and the Cholesky factor of ``P^T H P`` (nc_max x nc_max, m/Pa). Writes
    the number of aggregates into ``span``; ``steps``: work array of n elements."""
    e, Tc, U, L = coarse
    j0, j1 = _first_last(D, WIDE_THETA * K00)
    nc = min(nc_max, (j1 - j0) // 4)
    if nc < 2:
        nc = 0
    else:
        _aggregate_edges(D, K00, j0, j1, nc, e, steps)
        _coarse_matrices(D, scale, prefix, j0, j1, nc, e, Tc, U, L)
    span[_NC] = nc


@numba.njit(**JIT)
def _precondition(y, shift, out, prec, fft, bufs, circulant):
    """``out = R B R (y - shift)`` (two-level, module docstring; R zeroes the frozen cells);
    returns the number of FFT convolutions. ``circulant`` False: Jacobi on the core too (no
    FFT; the direction of the zero-load projection, :func:`_pcg_start`). ``prec``: the
    preconditioner (:class:`TwoLevel`: ``D, scale, pre = (minv, S, cinv, Tc), L, e, span, g``)
    as set up by :func:`_smoother` and :func:`_coarse_level`; the coarse products run over the
    live span ``[f0, f1)`` only (a third of the grid is frozen in the scenes of the count
    test). ``fft``: the plans (:func:`fastline._lib.fftw.acquire`); ``bufs = (a, c, work)``:
    the FFT buffers and a work array of 3n + _STRIP elements, ``work[2n:3n]`` holding ones."""
    D, scale, pre, L, e, span, g = prec
    minv, S, cinv, Tc = pre
    fr2c, fc2r, pf, pb = fft
    a, c, work = bufs
    f0, f1, i0, i1, nc = span[_F0], span[_F1], span[_I0], span[_I1], span[_NC]
    n = y.shape[0]
    tmp, r1, ones = work[:n], work[n : 2 * n], work[2 * n : 3 * n]
    g1, g2 = g[: nc + 1], g[nc + 1 :]
    for i in range(n):  # R y, and the coarse right-hand side P^T R y
        r1[i] = y[i] - shift if minv[i] > 0.0 else 0.0
    for k in range(nc):
        g1[k] = segment_sum(r1, ones, e[k], e[k + 1])
    if nc > 0:  # r1 = R y - H P c1: the edge windows of Tc, then the diagonal
        _chol_solve(L, nc, g1)
        prev = 0.0
        for j in range(nc + 1):  # jumps of scale * c1 across the edges
            cj = g1[j] if j < nc else 0.0
            g2[j] = scale * (cj - prev)
            prev = cj
        _subtract_edge_combination(r1, Tc, e, nc, g2, f0, f1)  # (R drops the rest)
        for k in range(nc):
            for i in range(e[k], e[k + 1]):
                r1[i] -= D[i] * g1[k]
    for i in range(n):  # smoother: Jacobi, and the scaled circulant on the core
        out[i] = minv[i] * r1[i]
    ffts = 0
    m = i1 - i0 if circulant else 0
    if m > 0:
        for i in range(m):
            tmp[i] = S[i] * r1[i0 + i] if minv[i0 + i] > 0.0 else 0.0
        convolve(tmp, m, cinv, fr2c, fc2r, pf, pb, a, c, tmp)
        for i in range(m):
            if minv[i0 + i] > 0.0:
                out[i0 + i] = S[i] * tmp[i]
        ffts = 1
    if nc > 0:  # c2 = (P^T H P)^-1 (H P)^T z1, out = z1 + P (c1 - c2)
        _edge_correlations(out, Tc, e, nc, g2, f0, f1)  # g2 = (H P)^T z1, then the diagonal
        for k in range(nc):
            g2[k] = scale * (g2[k] - g2[k + 1]) + segment_sum(D, out, e[k], e[k + 1])
        _chol_solve(L, nc, g2)
        for k in range(nc):
            d = g1[k] - g2[k]
            for i in range(e[k], e[k + 1]):
                if minv[i] > 0.0:
                    out[i] += d
    return ffts
