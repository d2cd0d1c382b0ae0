"""Compiled solver of the line contact's Newton system (the hot loop of every solve).

Each Newton step of :func:`fastline._core.newton` solves

    (D + K) dp + du1 = r,        sum_i w_i dp_i = 0,

K the Toeplitz log-kernel compliance (:mod:`fastline.elastic`), D = |du_law/dp| > 0 diagonal.
This module does it in one compiled call, FFTs included (:mod:`fastline._fftw`):
projected conjugate gradients in the inner product ``<a, b> = sum w a b`` with the
M-orthogonal projection onto zero-load increments (du1 is the multiplier), preconditioned by
a two-level method:

* smoother: Jacobi ``1/(D + K00)``, except on the loaded core (cells from the first to the last
  with ``D < CORE_THETA K00``) where a Strang circulant of ``K + median(D) I`` is inverted by
  FFT, scaled by ``S_i = sqrt((K00 + median)/(K00 + D_i))`` so that cells whose D departs from
  the median keep their own diagonal (one FFT convolution per application);
* coarse correction on the smooth modes of the wide block (cells with ``D < WIDE_THETA K00``:
  the core plus the contact edge, where D spans five decades and neither Jacobi nor a circulant
  fits), ``NC`` piecewise-constant aggregates, applied multiplicatively:
  ``B = C + (I - C H) S (I - H C)``, ``C = P (P^T H P)^-1 P^T``. ``H P`` comes from prefix sums
  of the Toeplitz coefficients (no FFT): ``sum_{j in [a, b)} khat_|i-j| = T[i-a+n] - T[i-b+n]``.
  The coarse matrix penalises its constant mode (the projection handles constants; the log
  kernel's constant mode is strongly negative).

Dense analysis at n = 1024 (tests/scratch measurements in docs/performance.md): the condition
number of the preconditioned system on zero-load increments falls from 5-32 (the circulant
alone) to 1.3-4 (two-level); the limit at small alpha is the contact edge.

CG stops when the Jacobi-weighted norm of the projected residual fell by ``rtol``: this is
known before the next preconditioner application, which is then saved.
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
#: piecewise-constant aggregates of the coarse space (at most one per 4 cells)
NC = 16
#: cells with D > FROZEN_THETA K00 are decoupled: CG leaves them out (their vectors would hold
#: subnormal numbers, ~r/D with D up to 1e300, which slowed FFTs and dot products 10-100x) and
#: they get the Jacobi update dp = (res - du1)/D from the final residual
FROZEN_THETA = 1e10


# ----------------------------------------------------------------------------------------------
# FFT convolutions
# ----------------------------------------------------------------------------------------------
@numba.njit(**JIT)
def _convolve(x, m, spec, fft, a, c, out):
    """``out[:m] = (IFFT(spec * FFT([x[:m], 0...])))[:m]``: a linear convolution with the
    kernel whose real spectrum (normalisation included) is ``spec``; one FFT convolution."""
    r2c, c2r, pf, pb = fft
    for i in range(m):
        a[i] = x[i]
    for i in range(m, a.shape[0]):
        a[i] = 0.0
    execute(r2c, pf, a.ctypes.data, c.ctypes.data)
    for k in range(c.shape[0]):
        c[k] = c[k] * spec[k]
    execute(c2r, pb, c.ctypes.data, a.ctypes.data)
    for i in range(m):
        out[i] = a[i]


@numba.njit(**JIT)
def apply_kernel(x, kspec, scale, fft, out):
    """``out = K x`` with ``K = scale * toeplitz(khat)`` (``kspec``: spectrum of the zero-padded
    circulant embedding of khat, divided by 2n)."""
    a, c = aligned_buffers(2 * x.shape[0])
    _convolve(x, x.shape[0], kspec, fft, a, c, out)
    for i in range(out.shape[0]):
        out[i] *= scale


# ----------------------------------------------------------------------------------------------
# preconditioner set-up
# ----------------------------------------------------------------------------------------------
@numba.njit(**JIT)
def _block(D, limit):
    """First and one-past-last cell with ``D < limit`` (0, 0 if none)."""
    i0, i1 = -1, 0
    for i in range(D.shape[0]):
        if D[i] < limit:
            if i0 < 0:
                i0 = i
            i1 = i + 1
    return (0, 0) if i0 < 0 else (i0, i1)


@numba.njit(**JIT)
def _smoother(D, K00, scale, strang):
    """Jacobi factors, core block, its diagonal scaling and inverse circulant spectrum."""
    n = D.shape[0]
    minv = 1.0 / (D + K00)
    for i in range(n):
        if D[i] > FROZEN_THETA * K00:
            minv[i] = 0.0
    i0, i1 = _block(D, CORE_THETA * K00)
    if i1 - i0 < _CORE_MIN_CELLS:
        return minv, 0, 0, np.empty(0), np.empty(0)
    shift = np.median(D[i0:i1])
    S = np.sqrt((K00 + shift) / (K00 + D[i0:i1]))
    cinv = 1.0 / ((scale * strang + shift) * (2 * n))
    return minv, i0, i1, S, cinv


@numba.njit(**JIT)
def _coarse(D, K00, scale, prefix, nc_max):
    """Aggregate edges, ``H P`` (n x nc) and the Cholesky factor of the penalised P^T H P."""
    n = D.shape[0]
    j0, j1 = _block(D, WIDE_THETA * K00)
    nc = min(nc_max, (j1 - j0) // 4)
    if nc < 2:
        return np.zeros(1, np.int64), np.empty((n, 0)), np.empty((0, 0))
    e = np.empty(nc + 1, np.int64)
    for k in range(nc + 1):
        e[k] = j0 + int(round(k * (j1 - j0) / nc))
    HP = np.empty((n, nc))
    for k in range(nc):
        a, b = e[k], e[k + 1]
        for i in range(n):
            HP[i, k] = scale * (prefix[i - a + n] - prefix[i - b + n])
        for i in range(a, b):
            HP[i, k] += D[i]
    Hc = np.zeros((nc, nc))
    for k in range(nc):
        for i in range(e[k], e[k + 1]):
            for m in range(nc):
                Hc[k, m] += HP[i, m]
    s = np.empty(nc)
    for k in range(nc):
        s[k] = e[k + 1] - e[k]
    s /= math.sqrt(np.dot(s, s))
    Hc = 0.5 * (Hc + Hc.T)
    big = 2.0 * abs(np.dot(s, Hc @ s)) + nc * np.max(np.abs(np.diag(Hc)))
    Hc += big * np.outer(s, s)
    return e, HP, np.linalg.cholesky(Hc)


# ----------------------------------------------------------------------------------------------
# preconditioner application
# ----------------------------------------------------------------------------------------------
@numba.njit(**JIT)
def _chol_solve(L, b):
    """``(L L^T)^-1 b`` by forward and back substitution."""
    nc = b.shape[0]
    y = np.empty(nc)
    for i in range(nc):
        acc = b[i]
        for j in range(i):
            acc -= L[i, j] * y[j]
        y[i] = acc / L[i, i]
    for i in range(nc - 1, -1, -1):
        acc = y[i]
        for j in range(i + 1, nc):
            acc -= L[j, i] * y[j]
        y[i] = acc / L[i, i]
    return y


@numba.njit(**JIT)
def _smooth(y, out, minv, i0, i1, S, cinv, fft, a, c, tmp):
    """``out = S(y)``: Jacobi (0 on frozen cells, minv = 0), and the scaled circulant on the
    core; returns the FFT count."""
    for i in range(y.shape[0]):
        out[i] = minv[i] * y[i]
    m = i1 - i0
    if m == 0:
        return 0
    for i in range(m):
        tmp[i] = S[i] * y[i0 + i]
    _convolve(tmp, m, cinv, fft, a, c, tmp)
    for i in range(m):
        out[i0 + i] = S[i] * tmp[i]
    return 1


@numba.njit(**JIT)
def _precondition(y_in, out, sm, co, fft, a, c, tmp, r1):
    """``out = R B R y`` (two-level, module docstring; R zeroes the frozen cells, so CG never
    moves them and no subnormal number enters its vectors); returns the FFT count."""
    minv, i0, i1, S, cinv = sm
    e, HP, L = co
    nc = HP.shape[1]
    y = np.where(minv > 0.0, y_in, 0.0)
    if nc == 0:
        ffts = _smooth(y, out, minv, i0, i1, S, cinv, fft, a, c, tmp)
        _restrict(out, minv)
        return ffts
    g = np.zeros(nc)
    for k in range(nc):
        for i in range(e[k], e[k + 1]):
            g[k] += y[i]
    c1 = _chol_solve(L, g)
    for i in range(y.shape[0]):
        acc = y[i]
        for k in range(nc):
            acc -= HP[i, k] * c1[k]
        r1[i] = acc
    ffts = _smooth(r1, out, minv, i0, i1, S, cinv, fft, a, c, tmp)
    g[:] = 0.0
    for i in range(y.shape[0]):
        for k in range(nc):
            g[k] += HP[i, k] * out[i]
    c2 = _chol_solve(L, g)
    for k in range(nc):
        d = c1[k] - c2[k]
        for i in range(e[k], e[k + 1]):
            out[i] += d
    _restrict(out, minv)
    return ffts


@numba.njit(**JIT)
def _restrict(x, minv):
    """Zero the frozen cells (``minv == 0``)."""
    for i in range(x.shape[0]):
        if minv[i] == 0.0:
            x[i] = 0.0


# ----------------------------------------------------------------------------------------------
# projected preconditioned conjugate gradients
# ----------------------------------------------------------------------------------------------
@numba.njit(**JIT)
def solve_newton_system(fft, kspec, strang, prefix, scale, K00, D, w, rhs, rtol, maxit, nc, dp):
    """Solve ``(D + K) dp + du1 = rhs``, ``sum(w dp) = 0`` (module docstring) into ``dp``.

    Returns ``(du1, iterations, k_applications, circulant_solves)``.
    """
    n = D.shape[0]
    a, c = aligned_buffers(2 * n)
    tmp = np.empty(n)
    r1 = np.empty(n)
    sm = _smoother(D, K00, scale, strang)
    co = _coarse(D, K00, scale, prefix, nc)
    circ = 0
    m1 = np.empty(n)
    circ += _precondition(np.ones(n), m1, sm, co, fft, a, c, tmp, r1)
    s_m1 = np.dot(w, m1)
    jac = w * sm[0]  # 0 on frozen cells: their residual is theirs alone
    s_jac = jac.sum()
    res = rhs.copy()
    z = np.empty(n)
    circ += _precondition(res, z, sm, co, fft, a, c, tmp, r1)
    lam = np.dot(w, z) / s_m1
    z -= lam * m1
    rz = np.dot(w * res, z)
    r0 = _jacobi_norm(res, jac, s_jac)
    d = z.copy()
    Hd = np.empty(n)
    dp[:] = 0.0
    its = kapps = 0
    # the best iterate so far (by Jacobi residual) is what is returned: if round-off breaks CG
    # down at a tight tolerance (the log kernel's constant mode has a large negative energy, so
    # a tiny leak off zero load makes <d, H d> negative), nothing worse than it comes back
    best_dp, best_res, best, best_its = dp.copy(), res.copy(), r0, 0
    while its < maxit and rz > 0.0:
        _convolve(d, n, kspec, fft, a, c, Hd)
        kapps += 1
        for i in range(n):
            Hd[i] = D[i] * d[i] + scale * Hd[i]
        dHd = np.dot(w * d, Hd)
        if not dHd > 0.0:
            break
        alpha = rz / dHd
        dp += alpha * d
        res -= alpha * Hd
        its += 1
        rn = _jacobi_norm(res, jac, s_jac)
        if rn < best:
            best, best_its = rn, its
            best_dp[:] = dp
            best_res[:] = res
        # stop when reduced by rtol, at maxit, or stagnant (round-off) for 20 iterations
        if rn <= rtol * r0 or its - best_its >= 20:
            break
        circ += _precondition(res, z, sm, co, fft, a, c, tmp, r1)
        lam = np.dot(w, z) / s_m1
        z -= lam * m1
        rz_new = np.dot(w * res, z)
        d = z + (rz_new / rz) * d
        rz = rz_new
    dp[:] = best_dp
    lam = np.dot(jac, best_res) / s_jac  # the multiplier: Jacobi-weighted mean residual
    dp -= (np.dot(w, dp) / s_m1) * m1  # back onto zero load (round-off drift)
    for i in range(n):  # frozen cells: the Jacobi update from the final residual
        if sm[0][i] == 0.0:
            dp[i] = (best_res[i] - lam) / D[i]
    return lam, its, kapps, circ


@numba.njit(**JIT)
def _jacobi_norm(res, jac, s_jac):
    """Jacobi-weighted norm of ``res`` with its Jacobi-weighted mean removed (the part the
    projection onto zero-load increments sees, as cheap as a dot product)."""
    mean = np.dot(jac, res) / s_jac
    acc = 0.0
    for i in range(res.shape[0]):
        r = res[i] - mean
        acc += jac[i] * r * r
    return math.sqrt(acc)


def prefix_sums(khat: np.ndarray) -> np.ndarray:
    """``T`` with ``T[0] = 0`` and ``T[j+1] = sum_{l <= j} khat_|l - (n-1)|`` (length 2n)."""
    two_sided = np.concatenate([khat[:0:-1], khat])
    return np.concatenate([[0.0], np.cumsum(two_sided)])
