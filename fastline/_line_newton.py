"""The line contact's Newton iteration as one compiled call (the laws fastline ships).

:func:`fastline._core.newton` is the readable reference: a Python loop that any geometry and any
pressure law can use. For the line contact with a law whose p(u) tables are compiled (Persson,
exponential, tabulated) the same iteration runs here, without returning to Python between the
steps: no interpreter work between FFTs, and the GIL is released for the whole solve, so
threads solving different scenes run in parallel. The steps, constants and safeguards are
those of :mod:`fastline._core` (module docstring there); tests hold the two paths together.

Laws enter as a kind code and arrays (one compiled signature for all):

* ``0`` Persson, table T1 in its solver form: ``prm``, ``A = Cf``
  (:func:`fastline.persson._solver_form`, :func:`fastline.persson._solver_law`);
* ``1`` exponential: ``prm = (u0, ln(beta E*))``;
* ``2`` tabulated: ``A, B, C = V, U, S`` (:func:`fastline.laws._tabulated_u`).

Returns a status: 0 converged, 1 ``max_iter`` reached, 2 the line search failed.
"""

from __future__ import annotations

import math

import numba
import numpy as np

from fastline._core import (
    _LN_TINY,
    DV_MAX,
    ETA0_SCALE,
    ETA_FLOOR,
    ETA_MAX,
    ETA_RES_SCALE,
    ETA_RETRY_MIN,
    FLOOR_STALL,
    LINE_SEARCH_HALVINGS,
    LN_FLOOR,
    MAX_CG,
    ROUNDOFF_FACTOR,
)
from fastline._fftw import ALIGN_PAD, aligned_size, aligned_views
from fastline._jit import JIT
from fastline._solve_kernels import largest, largest_abs, normalise_pressure_into
from fastline._toeplitz_pcg import _convolve, _segment_sum, solve_newton_system
from fastline._toeplitz_pcg import workspace_size as _system_workspace
from fastline.laws import _hermite
from fastline.persson import _solver_law

_EPS = float(np.finfo(np.float64).eps)
#: n-sized work arrays of :func:`newton_line` itself (iterate and trial: v, p, U, dU, gk, r each;
#: D and dp)
_HEAD_ARRAYS = 14


def workspace_size(n: int) -> int:
    """float64 elements of the work space :func:`newton_line` takes for n cells (its own
    arrays, then the Newton system's)."""
    return aligned_size(2 * n) + _HEAD_ARRAYS * n + _system_workspace(n)


@numba.njit(**JIT)
def _law(kind, v, prm, A, B, C, E, u, dU):
    """u and du/d(ln p) at v = ln p for the law of ``kind`` (module docstring)."""
    n = v.shape[0]
    if kind == 0:
        _solver_law(v, prm, A, u, dU)
    elif kind == 1:
        for i in range(n):
            u[i] = prm[0] * (prm[1] - v[i])
            dU[i] = -prm[0]
    else:
        m = A.shape[0]
        for i in range(n):
            x = v[i]
            if x <= A[0]:
                dU[i] = C[0]
                u[i] = B[0] + C[0] * (x - A[0])
            elif x >= A[m - 1]:
                dU[i] = C[m - 1]
                u[i] = B[m - 1] + C[m - 1] * (x - A[m - 1])
            else:  # bisection for A[k] <= x < A[k + 1] (np.searchsorted: ~0.3 s more compile)
                k = 0
                hi = m - 1
                while hi - k > 1:
                    mid = (k + hi) // 2
                    if A[mid] <= x:
                        k = mid
                    else:
                        hi = mid
                u[i], dU[i] = _hermite(x, A, B, C, k)


@numba.njit(**JIT)
def _evaluate(v, u1_in, fft, kspec, scale, gap, w, kind, prm, A, B, C, E, a, c, p, U, dU, gk, r):
    """Pressure, law, g + K p and the residual at v (one FFT convolution). ``u1_in`` NaN: the
    load-weighted least-squares rigid approach. Returns ``(u1, ||r||_2, size)``, size the
    largest term the residual subtracts (for the round-off floor)."""
    n = v.shape[0]
    floor = max(largest(v, -math.inf) - LN_FLOOR, _LN_TINY)  # see fastline._core.LN_FLOOR
    for i in range(n):
        p[i] = math.exp(v[i]) if v[i] > floor else 0.0
    return _residual(
        v, u1_in, fft, kspec, scale, gap, w, kind, prm, A, B, C, E, a, c, p, U, dU, gk, r
    )


@numba.njit(**JIT)
def _residual(v, u1_in, fft, kspec, scale, gap, w, kind, prm, A, B, C, E, a, c, p, U, dU, gk, r):
    """:func:`_evaluate` with the pressure ``p`` of v given."""
    fr2c, fc2r, pf, pb = fft
    n = v.shape[0]
    _law(kind, v, prm, A, B, C, E, U, dU)
    _convolve(p, n, kspec, fr2c, fc2r, pf, pb, a, c, gk)
    u1 = u1_in
    if u1 != u1:
        num = 0.0
        den = 0.0
        for i in range(n):
            gk[i] = gap[i] + scale * gk[i]
            num += w[i] * p[i] * (U[i] - gk[i])
            den += w[i] * p[i]
        u1 = num / den
    else:
        for i in range(n):
            gk[i] = gap[i] + scale * gk[i]
    for i in range(n):
        r[i] = U[i] - u1 - gk[i]
    phi2 = _segment_sum(r, r, 0, n)  # ||r||^2 in four chains
    return u1, math.sqrt(phi2), largest_abs(gk, abs(u1))


@numba.njit(**JIT)
def newton_line(
    fft,
    kspec,
    strang,
    prefix,
    scale,
    K00,
    gap,
    w,
    load,
    law,
    u_ref,
    v_io,
    tol,
    max_iter,
    nc,
    hist,
    u_out,
    ws,
):
    """Newton-Krylov on v = ln p (in place) for the line contact; ``law`` is
    ``(kind, prm, A, B, C, E)``, ``hist`` (max_iter x 3) receives (residual, CG iterations,
    step), ``u_out`` the law's separation at the final iterate, ``ws`` is float64 work space of
    :func:`workspace_size` ``(n)`` elements (contents irrelevant: every work array of the solve
    is a view into it, :func:`fastline._toeplitz_pcg.solve_newton_system`). Returns ``(u1,
    residual, status, steps, cg_iterations, k_applications, circulant_solves,
    tol_effective)``."""
    kind, prm, A, B, C, E = law
    fr2c, fc2r, pf, pb = fft
    n = v_io.shape[0]
    a, c = aligned_views(ws, 2 * n)
    o = 4 * n + ALIGN_PAD  # aligned_size(2 n)
    v = ws[o + 0 * n : o + 1 * n]
    p = ws[o + 1 * n : o + 2 * n]
    U = ws[o + 2 * n : o + 3 * n]
    dU = ws[o + 3 * n : o + 4 * n]
    gk = ws[o + 4 * n : o + 5 * n]
    r = ws[o + 5 * n : o + 6 * n]
    v2 = ws[o + 6 * n : o + 7 * n]
    p2 = ws[o + 7 * n : o + 8 * n]
    U2 = ws[o + 8 * n : o + 9 * n]
    dU2 = ws[o + 9 * n : o + 10 * n]
    gk2 = ws[o + 10 * n : o + 11 * n]
    r2 = ws[o + 11 * n : o + 12 * n]
    D = ws[o + 12 * n : o + 13 * n]
    dp = ws[o + 13 * n : o + 14 * n]
    tail = ws[o + _HEAD_ARRAYS * n :]
    for i in range(n):
        v[i] = v_io[i]
    u1, phi, size = _evaluate(
        v, math.nan, fft, kspec, scale, gap, w, kind, prm, A, B, C, E, a, c, p, U, dU, gk, r
    )
    kapps = 1
    steps = cg_total = circ = 0
    res_prev = eta = math.nan
    eta_cap = ETA_MAX
    while True:
        res = largest_abs(r, 0.0) / u_ref
        tol_eff = max(tol, ROUNDOFF_FACTOR * _EPS * size / u_ref)
        stalled = eta_cap < ETA_RETRY_MIN
        if stalled and tol_eff > tol and res < FLOOR_STALL * tol_eff:
            tol_eff *= FLOOR_STALL  # noise level of a raised tolerance: as converged as can be
        if res < tol_eff or steps >= max_iter or stalled:
            status = 0 if res < tol_eff else (2 if stalled else 1)
            for i in range(n):  # loops, not v_io[:] = v: no broadcasting error path to compile
                v_io[i] = v[i]
                u_out[i] = U[i]
            return u1, res, status, steps, cg_total, kapps, circ, tol_eff
        steps += 1
        for i in range(n):
            D[i] = min(max(-dU[i], 1e-300 * u_ref) / max(p[i], 1e-300), 1e300)
        eta = min(_forcing(res, res_prev, eta, tol_eff), eta_cap)
        res_prev = res
        du1, its, ka, ci = solve_newton_system(
            fr2c,
            fc2r,
            pf,
            pb,
            kspec,
            strang,
            prefix,
            scale,
            K00,
            D,
            w,
            r,
            eta,
            MAX_CG,
            nc,
            dp,
            tail,
        )
        cg_total += its
        kapps += ka
        circ += ci
        # step guard on ln p where it matters, then Armijo backtracking on ||r||
        pmax = largest(p, 0.0)
        gmax = 0.0
        for i in range(n):
            dp[i] /= max(p[i], 1e-300)  # dp -> dv
            if p[i] > 1e-6 * pmax or dU[i] > -0.5 * u_ref:
                gmax = max(gmax, abs(dp[i]))
        t = min(1.0, DV_MAX / max(1e-300, gmax))
        accepted = False
        for _ in range(LINE_SEARCH_HALVINGS + 1):
            for i in range(n):
                v2[i] = v[i] + t * dp[i]
            normalise_pressure_into(v2, load, w, p2)
            u1n, phin, sizen = _residual(
                v2,
                u1 + t * du1,
                fft,
                kspec,
                scale,
                gap,
                w,
                kind,
                prm,
                A,
                B,
                C,
                E,
                a,
                c,
                p2,
                U2,
                dU2,
                gk2,
                r2,
            )
            kapps += 1
            if phin < (1.0 - 1e-4 * t) * phi:
                accepted = True
                break
            t *= 0.5
        if steps <= hist.shape[0]:
            hist[steps - 1, 0] = res
            hist[steps - 1, 1] = its
            hist[steps - 1, 2] = t if accepted else 0.0
        if accepted:
            v, v2 = v2, v
            p, p2 = p2, p
            U, U2 = U2, U
            dU, dU2 = dU2, dU
            gk, gk2 = gk2, gk
            r, r2 = r2, r
            u1, phi, size = u1n, phin, sizen
        else:  # not a descent direction: solve the step more accurately
            eta_cap = eta * 1e-3


@numba.njit(**JIT)
def _forcing(res, res_prev, eta_prev, tol):
    """Eisenstat-Walker choice 2, floored at ``ETA_RES_SCALE * res``
    (:func:`fastline._core._forcing`)."""
    if res_prev != res_prev:
        eta = min(ETA_MAX, ETA0_SCALE * res)
    else:
        eta = 0.9 * (res / res_prev) ** 2
        if 0.9 * eta_prev * eta_prev > 0.1:
            eta = max(eta, 0.9 * eta_prev * eta_prev)
    # two-argument max only: one compiled version of it
    return min(ETA_MAX, max(max(max(eta, ETA_RES_SCALE * res), ETA_FLOOR), 0.5 * tol / res))
