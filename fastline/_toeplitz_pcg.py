"""Compiled solver of the line contact's Newton system (the hot loop of every solve).

Each Newton step of :func:`fastline._core.newton` solves

    (D + K) dp + du1 = r,        sum_i w_i dp_i = 0,

K the Toeplitz log-kernel compliance (:mod:`fastline.elastic`), D = |du_law/dp| > 0 diagonal.
This module does it in one compiled call, FFTs included (:mod:`fastline._fftw`):
projected conjugate gradients in the inner product ``<a, b> = sum w a b`` with the
M-orthogonal projection onto zero-load increments (du1 is the multiplier), preconditioned by
a two-level method:

* smoother: Jacobi ``1/(D + K00)``, except on the loaded core (cells from the first to the last
  with ``D < CORE_THETA K00``) where a Strang circulant of ``K + d I`` (d the geometric mean of
  D there) is inverted by FFT, scaled by ``S_i = sqrt((K00 + d)/(K00 + D_i))`` so that cells
  whose D departs from d keep their own diagonal (one FFT convolution per application);
* coarse correction on the smooth modes of the wide block (cells with ``D < WIDE_THETA K00``:
  the core plus the contact edge, where D spans five decades and neither Jacobi nor a circulant
  fits), ``nc`` piecewise-constant aggregates, applied multiplicatively:
  ``B = C + (I - C H) S (I - H C)``, ``C = P (P^T H P)^-1 P^T``. The aggregates are denser
  where ln(D + K00) changes fast (``EDGE_SHARE``, :func:`_aggregate_edges`): the slowest modes
  of the preconditioned system sit at the rim of the core, where the smoother switches from
  the circulant to Jacobi, and that rim widens in cells with n. ``H P`` comes from prefix sums
  of the Toeplitz coefficients (no FFT): ``sum_{j in [a, b)} khat_|i-j| = T[i-a+n] - T[i-b+n]``.
  The coarse matrix penalises its constant mode (the projection handles constants; the log
  kernel's constant mode is strongly negative).
* cells with ``D > FROZEN_THETA K00`` are decoupled: CG leaves them out (``R B R``, R zeroing
  them; their vectors would hold subnormal numbers ~r/D, D up to 1e300, which slowed FFTs and
  dot products 10-100x) and they get the Jacobi update from the final residual.

Dense analysis at n = 1024: the condition number of the preconditioned system on zero-load
increments falls from 5-32 (the circulant alone) to 1.3-4 (two-level, 32 aggregates). CG stops
when the Jacobi-weighted norm of the projected residual fell by ``rtol`` (known before the next
preconditioner application, which is then saved), and returns the best iterate it saw.

Written in plain loops over arrays passed one by one (no tuples, no NumPy linear algebra, no
sorting): Numba compiles that in a fraction of the time, and first-call compilation is a real
cost to users (the first version, with ``np.linalg.cholesky``, ``np.median`` and tuples of
arrays, took 18 s to compile cold).
"""

from __future__ import annotations

import math

import numba
import numpy as np

from fastline._fftw import aligned_buffers, execute
from fastline._jit import JIT

#: core block of the smoother: cells with D < CORE_THETA K00
CORE_THETA = 10.0
_CORE_MIN_CELLS = 8
#: wide block of the coarse correction: cells with D < WIDE_THETA K00
WIDE_THETA = 100.0
#: share of the coarse aggregates placed by the variation of ln(D + K00) across the wide block
#: (the rest by width; :func:`_aggregate_edges`)
EDGE_SHARE = 0.7
#: decoupled cells, left out of CG: D > FROZEN_THETA K00
FROZEN_THETA = 1e10
#: CG stops when its residual has not improved for this many iterations (round-off)
_STAGNATION = 20


# ----------------------------------------------------------------------------------------------
# FFT convolutions
# ----------------------------------------------------------------------------------------------
@numba.njit(**JIT)
def _convolve(x, m, spec, fr2c, fc2r, pf, pb, a, c, out):
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
def apply_kernel(x, kspec, scale, fr2c, fc2r, pf, pb, out):
    """``out = K x`` with ``K = scale * toeplitz(khat)`` (``kspec``: spectrum of the zero-padded
    circulant embedding of khat, divided by 2n)."""
    n = x.shape[0]
    a, c = aligned_buffers(2 * n)
    _convolve(x, n, kspec, fr2c, fc2r, pf, pb, a, c, out)
    for i in range(n):
        out[i] *= scale


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
def _chol_solve(L, nc, b):
    """``b <- (L L^T)^-1 b`` for the leading nc x nc block, in place."""
    for i in range(nc):
        acc = b[i]
        for j in range(i):
            acc -= L[i, j] * b[j]
        b[i] = acc / L[i, i]
    for i in range(nc - 1, -1, -1):
        acc = b[i]
        for j in range(i + 1, nc):
            acc -= L[j, i] * b[j]
        b[i] = acc / L[i, i]


# ----------------------------------------------------------------------------------------------
# preconditioner application
# ----------------------------------------------------------------------------------------------
@numba.njit(**JIT)
def _precondition(
    y, out, minv, i0, i1, S, cinv, nc, e, HP, L, fr2c, fc2r, pf, pb, a, c, tmp, r1, g1, g2
):
    """``out = R B R y`` (two-level, module docstring; R zeroes the frozen cells); returns the
    number of FFT convolutions. ``a, c, tmp, r1, g1, g2``: work arrays."""
    n = y.shape[0]
    for i in range(n):  # R y, and the coarse right-hand side P^T R y
        r1[i] = y[i] if minv[i] > 0.0 else 0.0
    for k in range(nc):
        acc = 0.0
        for i in range(e[k], e[k + 1]):
            acc += r1[i]
        g1[k] = acc
    _chol_solve(L, nc, g1)
    for i in range(n):  # r1 = R y - H P c1
        acc = r1[i]
        for k in range(nc):
            acc -= HP[i, k] * g1[k]
        r1[i] = acc
    for i in range(n):  # smoother: Jacobi, and the scaled circulant on the core
        out[i] = minv[i] * r1[i]
    ffts = 0
    m = i1 - i0
    if m > 0:
        for i in range(m):
            tmp[i] = S[i] * r1[i0 + i] if minv[i0 + i] > 0.0 else 0.0
        _convolve(tmp, m, cinv, fr2c, fc2r, pf, pb, a, c, tmp)
        for i in range(m):
            if minv[i0 + i] > 0.0:
                out[i0 + i] = S[i] * tmp[i]
        ffts = 1
    for k in range(nc):  # c2 = (P^T H P)^-1 (H P)^T z1, out = z1 + P (c1 - c2)
        g2[k] = 0.0
    for i in range(n):
        for k in range(nc):
            g2[k] += HP[i, k] * out[i]
    _chol_solve(L, nc, g2)
    for k in range(nc):
        d = g1[k] - g2[k]
        for i in range(e[k], e[k + 1]):
            if minv[i] > 0.0:
                out[i] += d
    return ffts


# ----------------------------------------------------------------------------------------------
# projected preconditioned conjugate gradients
# ----------------------------------------------------------------------------------------------
@numba.njit(**JIT)
def solve_newton_system(
    fr2c, fc2r, pf, pb, kspec, strang, prefix, scale, K00, D, w, rhs, rtol, maxit, nc_max, dp
):
    """Solve ``(D + K) dp + du1 = rhs``, ``sum(w dp) = 0`` (module docstring) into ``dp``.

    Stages: set up the smoother and the coarse level, then projected PCG. Returns
    ``(du1, iterations, k_applications, circulant_solves)``. (One function with plain loops:
    every separate compiled function and NumPy convenience costs compile time.)
    """
    n = D.shape[0]
    a, c = aligned_buffers(2 * n)
    tmp, r1, g1, g2 = np.empty(n), np.empty(n), np.empty(nc_max), np.empty(nc_max)
    # -- smoother: Jacobi (0 on frozen cells), scaled circulant on the core -------------------
    minv, S, cinv = np.empty(n), np.empty(n), np.empty(n + 1)
    for i in range(n):
        minv[i] = 0.0 if D[i] > FROZEN_THETA * K00 else 1.0 / (D[i] + K00)
    i0, i1 = _first_last(D, CORE_THETA * K00)
    if i1 - i0 < _CORE_MIN_CELLS:
        i0 = i1 = 0
    else:
        logsum = 0.0
        for i in range(i0, i1):
            logsum += math.log(D[i])
        shift = math.exp(logsum / (i1 - i0))  # geometric mean of D on the core
        for i in range(i0, i1):
            S[i - i0] = math.sqrt((K00 + shift) / (K00 + D[i]))
        for k in range(n + 1):
            cinv[k] = 1.0 / ((scale * strang[k] + shift) * (2 * n))
    # -- coarse level: aggregates of the wide block, H P, Cholesky of penalised P^T H P -------
    e = np.empty(nc_max + 1, np.int64)
    HP, L = np.empty((n, nc_max)), np.empty((nc_max, nc_max))
    j0, j1 = _first_last(D, WIDE_THETA * K00)
    nc = min(nc_max, (j1 - j0) // 4)
    if nc < 2:
        nc = 0
    else:
        _aggregate_edges(D, K00, j0, j1, nc, e)
        _coarse_matrices(D, scale, prefix, nc, e, HP, L)
    # -- projected PCG ----------------------------------------------------------------------
    m1, z, d, Hd, jac = np.empty(n), np.empty(n), np.empty(n), np.empty(n), np.empty(n)
    res, best_dp, best_res = np.empty(n), np.empty(n), np.empty(n)
    for i in range(n):
        tmp[i] = 1.0
    circ = _precondition(
        tmp, m1, minv, i0, i1, S, cinv, nc, e, HP, L, fr2c, fc2r, pf, pb, a, c, tmp, r1, g1, g2
    )
    s_m1 = 0.0
    s_jac = 0.0
    for i in range(n):
        s_m1 += w[i] * m1[i]
        jac[i] = w[i] * minv[i]  # 0 on frozen cells: their residual is theirs alone
        s_jac += jac[i]
        res[i] = rhs[i]
    circ += _precondition(
        res, z, minv, i0, i1, S, cinv, nc, e, HP, L, fr2c, fc2r, pf, pb, a, c, tmp, r1, g1, g2
    )
    lam = 0.0
    for i in range(n):
        lam += w[i] * z[i]
    lam /= s_m1
    rz = 0.0
    for i in range(n):
        z[i] -= lam * m1[i]
        d[i] = z[i]
        dp[i] = 0.0
        best_dp[i] = 0.0
        best_res[i] = res[i]
        rz += w[i] * res[i] * z[i]
    r0 = _jacobi_norm(res, jac, s_jac)
    # the best iterate so far (by Jacobi residual) is what is returned: if round-off breaks CG
    # down at a tight tolerance (the log kernel's constant mode has a large negative energy, so
    # a tiny leak off zero load makes <d, H d> negative), nothing worse than it comes back
    best, best_its, its, kapps = r0, 0, 0, 0
    while its < maxit and rz > 0.0:
        _convolve(d, n, kspec, fr2c, fc2r, pf, pb, a, c, Hd)
        kapps += 1
        dHd = 0.0
        for i in range(n):
            Hd[i] = D[i] * d[i] + scale * Hd[i]
            dHd += w[i] * d[i] * Hd[i]
        if not dHd > 0.0:
            break
        alpha = rz / dHd
        for i in range(n):
            dp[i] += alpha * d[i]
            res[i] -= alpha * Hd[i]
        its += 1
        rn = _jacobi_norm(res, jac, s_jac)
        if rn < best:
            best, best_its = rn, its
            for i in range(n):
                best_dp[i] = dp[i]
                best_res[i] = res[i]
        if rn <= rtol * r0 or its - best_its >= _STAGNATION:
            break
        circ += _precondition(
            res, z, minv, i0, i1, S, cinv, nc, e, HP, L, fr2c, fc2r, pf, pb, a, c, tmp, r1, g1, g2
        )
        lam = 0.0
        for i in range(n):
            lam += w[i] * z[i]
        lam /= s_m1
        rz_new = 0.0
        for i in range(n):
            z[i] -= lam * m1[i]
            rz_new += w[i] * res[i] * z[i]
        beta = rz_new / rz
        for i in range(n):
            d[i] = z[i] + beta * d[i]
        rz = rz_new
    # -- finish: the best iterate, back onto zero load, the frozen cells' Jacobi update ------
    lam = 0.0
    drift = 0.0
    for i in range(n):
        lam += jac[i] * best_res[i]
        drift += w[i] * best_dp[i]
    lam /= s_jac
    drift /= s_m1
    for i in range(n):
        dp[i] = best_dp[i] - drift * m1[i]
        if minv[i] == 0.0:
            dp[i] = (best_res[i] - lam) / D[i]
    return lam, its, kapps, circ


@numba.njit(**JIT)
def _aggregate_edges(D, K00, j0, j1, nc, e):
    """Edges ``e[0] = j0 < e[1] < ... < e[nc] = j1`` of the coarse aggregates: equal shares of
    the density ``(1 - EDGE_SHARE) / (j1 - j0) + EDGE_SHARE |d ln(D + K00)| / total`` per cell,
    i.e. by width in the core (where D << K00 and ln(D + K00) is flat) and by decades of D
    across the contact edge. Over the 160 count scenes (5 hard surfaces, alpha 1e-4..1e3,
    n 256..16384, with ``fastline._core.ETA_RES_SCALE``): 4446 convolutions with equal widths,
    3898 with a share of 0.5, 3713 with 0.7 (mirror-symmetric); the worst scene (alpha 1e-2,
    n 16384) 109 -> 99.

    Mirror-symmetric: the left half of the edges counts the share from ``j0``, the right half
    from ``j1``, an even ``nc`` puts the middle edge at the centre, so a symmetric D gives a
    symmetric preconditioner (and p(x) = p(-x) to round-off). Needs ``j1 - j0 >= 4 nc``."""
    total = 0.0
    for i in range(j0 + 1, j1):
        total += abs(math.log((D[i] + K00) / (D[i - 1] + K00)))
    flat = (1.0 - EDGE_SHARE) / (j1 - j0) if total > 0.0 else 1.0 / (j1 - j0)
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
        acc += flat + steep * abs(math.log((D[b] + K00) / (D[b - 1] + K00)))
    k = 1  # the same from the right: edge b with the share right of b reaching k / nc
    acc = flat
    for b in range(j1 - 1, j0, -1):
        if k >= (nc + 1) // 2:
            break
        if acc * nc >= k - 1e-9:
            e[nc - k] = b
            k += 1
        acc += flat + steep * abs(math.log((D[b - 1] + K00) / (D[b] + K00)))
    for m in range(nc - 1, 0, -1):  # at least one cell each
        e[m] = min(e[m], e[m + 1] - 1)
    for m in range(1, nc):
        e[m] = max(e[m], e[m - 1] + 1)


@numba.njit(**JIT)
def _coarse_matrices(D, scale, prefix, nc, e, HP, L):
    """``H P`` (n x nc) for the aggregates with edges ``e`` and the Cholesky factor ``L`` of
    ``P^T H P`` with its constant mode penalised."""
    n = D.shape[0]
    for i in range(n):
        for k in range(nc):
            HP[i, k] = scale * (prefix[i - e[k] + n] - prefix[i - e[k + 1] + n])
    for k in range(nc):
        for i in range(e[k], e[k + 1]):
            HP[i, k] += D[i]
    for k in range(nc):
        for m in range(nc):
            L[k, m] = 0.0
    for k in range(nc):
        for i in range(e[k], e[k + 1]):
            for m in range(nc):
                L[k, m] += HP[i, m]
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


@numba.njit(**JIT)
def _jacobi_norm(res, jac, s_jac):
    """Jacobi-weighted norm of ``res`` with its Jacobi-weighted mean removed (the part the
    projection onto zero-load increments sees, as cheap as a dot product)."""
    mean = 0.0
    for i in range(res.shape[0]):
        mean += jac[i] * res[i]
    mean /= s_jac
    acc = 0.0
    for i in range(res.shape[0]):
        r = res[i] - mean
        acc += jac[i] * r * r
    return math.sqrt(acc)


def prefix_sums(khat: np.ndarray) -> np.ndarray:
    """``T`` with ``T[0] = 0`` and ``T[j+1] = sum_{l <= j} khat_|l - (n-1)|`` (length 2n)."""
    two_sided = np.concatenate([khat[:0:-1], khat])
    return np.concatenate([[0.0], np.cumsum(two_sided)])
