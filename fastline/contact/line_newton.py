"""The line contact's Newton iteration as one compiled call (the laws fastline ships).

:func:`fastline.contact.core.newton` is the readable reference: a Python loop that any geometry and
any pressure law can use. For the line contact with a law whose p(u) tables are compiled (Persson,
exponential, tabulated) the same iteration runs here, without returning to Python between the
steps: no interpreter work between FFTs, and the GIL is released for the whole solve, so
threads solving different scenes run in parallel. The steps, constants and safeguards are
those of :mod:`fastline.contact.core` (module docstring there); tests hold the two paths together.

Laws enter as a kind code and arrays (one compiled signature for all):

* ``0`` Persson, table T1 in its solver form: ``prm``, ``A = Cf``
  (:func:`fastline.theory.tables._solver_form`, :func:`fastline.theory.tables.solver_law`);
* ``1`` exponential: ``prm = (u0, ln(beta E*))``;
* ``2`` tabulated: ``A, B, C = V, U, S`` (:func:`fastline.theory.laws._tabulated_u`).

Returns a status: 0 converged, 1 ``max_iter`` reached, 2 the line search failed.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numba
import numpy as np

from fastline._lib import fftw
from fastline._lib.fftw import ALIGN_PAD, aligned_size, aligned_views
from fastline._lib.jit import JIT
from fastline._lib.native import compile_meanwhile
from fastline.contact.core import (
    DV_MAX,
    ETA_FLOOR,
    ETA_MAX,
    ETA_RES_SCALE,
    ETA_RETRY_MIN,
    FLOOR_STALL,
    LINE_SEARCH_HALVINGS,
    MAX_CG,
    ROUNDOFF_FACTOR,
)
from fastline.contact.kernels import (
    LN_FLOOR,
    LN_TINY,
    largest,
    largest_abs,
    line_measures,
    normalise_pressure_into,
    pressure_into,
)
from fastline.elastic.convolution import convolve, segment_sum
from fastline.elastic.line import (
    LogKernelOperator,
    coarse_aggregates,
    compiled_tables,
    compiled_workspace,
)
from fastline.elastic.pcg import CGSettings, call_system, system_address
from fastline.elastic.pcg import workspace_size as _system_workspace
from fastline.theory.laws import hermite
from fastline.theory.tables import solver_law

_EPS = float(np.finfo(np.float64).eps)
#: n-sized work arrays of :func:`newton_line` itself (iterate and trial: v, p, U, dU, gk, r each;
#: D and dp)
_HEAD_ARRAYS = 14
#: the arrays of an iterate (``state`` and ``trial`` of :func:`newton_line`): ln p, p, the law's
#: u and du/dv, g + K p, the residual
_V, _P, _U, _DU, _GK, _R = 0, 1, 2, 3, 4, 5


class Scene(NamedTuple):
    """The line contact's discrete scene (n cells)."""

    #: the gap before contact, ``x^2 / 2R`` at the cell centres (m)
    gap: np.ndarray
    #: the cells' weights in the load, ``load = sum w p`` (their widths, m)
    w: np.ndarray
    #: the load per unit length (N/m)
    load: float


class Law(NamedTuple):
    """The pressure law as :func:`newton_line` evaluates it."""

    #: ``(kind, prm, A, B, C, E)``, the law's compiled form (module docstring)
    form: tuple
    #: the separation that sets the residual's scale (m)
    u_ref: float


class NewtonSettings(NamedTuple):
    """When :func:`newton_line` stops, the size of its preconditioner's coarse level, and the
    Newton systems' solver it calls."""

    #: tolerance on the largest residual, in units of ``u_ref`` (dimensionless)
    tol: float
    #: most Newton steps
    max_iter: int
    #: most coarse aggregates (:func:`fastline.elastic.line.coarse_aggregates`)
    nc: int
    #: address of the compiled Newton-system solver (:func:`fastline.elastic.pcg.system_address`)
    system: int


class NewtonOutputs(NamedTuple):
    """Where :func:`newton_line` writes, besides ln p."""

    #: (max_iter x 3): per step the residual (in units of u_ref), CG iterations, step length
    hist: np.ndarray
    #: the law's separation at the final iterate (n values, m)
    u: np.ndarray
    #: float64 work space of :func:`workspace_size` ``(n)`` elements, its contents irrelevant
    ws: np.ndarray


def workspace_size(n: int) -> int:
    """float64 elements of the work space :func:`newton_line` takes for n cells (its own
    arrays, then the Newton system's)."""
    return aligned_size(2 * n) + _HEAD_ARRAYS * n + _system_workspace(n)


@numba.njit(**JIT)
def _law(kind, v, prm, A, B, C, E, u, dU):
    """u and du/d(ln p) at v = ln p for the law of ``kind`` (module docstring)."""
    n = v.shape[0]
    if kind == 0:
        solver_law(v, prm, A, u, dU)
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
                u[i], dU[i] = hermite(x, A, B, C, k)


@numba.njit(**JIT)
def _evaluate(state, u1_in, fft, kspec, scale, gap, w, law, a, c):
    """Pressure, law, g + K p and the residual at the iterate ``state = (v, p, U, dU, gk, r)``
    (v = ln p given; one FFT convolution). ``u1_in`` NaN: the load-weighted least-squares
    rigid approach. Returns ``(u1, ||r||_2, size)``, size the largest term the residual
    subtracts (for the round-off floor)."""
    v, p = state[_V], state[_P]
    n = v.shape[0]
    floor = max(largest(v, -math.inf) - LN_FLOOR, LN_TINY)  # see fastline.contact.kernels.LN_FLOOR
    for i in range(n):
        p[i] = math.exp(v[i]) if v[i] > floor else 0.0
    return _residual(state, u1_in, fft, kspec, scale, gap, w, law, a, c)


@numba.njit(**JIT, inline="always")
def _residual(state, u1_in, fft, kspec, scale, gap, w, law, a, c):
    """:func:`_evaluate` with the pressure ``p`` of v given (inlined there: one compiled
    kernel fewer)."""
    v, p, U, dU, gk, r = state
    kind, prm, A, B, C, E = law
    fr2c, fc2r, pf, pb = fft
    n = v.shape[0]
    _law(kind, v, prm, A, B, C, E, U, dU)
    convolve(p, n, kspec, fr2c, fc2r, pf, pb, a, c, gk)
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
    # ||r||^2 in four chains; lo = n - n, not 0: a constant would be typed as a literal and
    # compile a second segment_sum
    phi2 = segment_sum(r, r, n - n, n)
    return u1, math.sqrt(phi2), largest_abs(gk, abs(u1))


@numba.njit(**JIT, inline="always")
def _newton_views(ws, n):
    """The views of :func:`newton_line` into its work space ``ws``: the FFT buffers ``a, c``,
    the iterate and the line search's trial (:func:`_iterate_views`), ``D``, ``dp``, and the
    tail left to the Newton system."""
    a, c = aligned_views(ws, 2 * n)
    o = 4 * n + ALIGN_PAD  # aligned_size(2 n)
    state = _iterate_views(ws, o, n)
    trial = _iterate_views(ws, o + 6 * n, n)
    D = ws[o + 12 * n : o + 13 * n]
    dp = ws[o + 13 * n : o + 14 * n]
    return a, c, state, trial, D, dp, ws[o + _HEAD_ARRAYS * n :]


@numba.njit(**JIT, inline="always")
def _stop(res, tol, size, u_ref, out_of_steps, eta_cap):
    """``(status, tol_effective)``: status 0 converged, 1 out of steps, 2 stalled (the forcing
    capped below ``ETA_RETRY_MIN``), -1 go on. The tolerance is raised to the round-off of the
    law's separations (``size``, m, against u_ref), and a stalled solve within
    ``FLOOR_STALL`` of that raised tolerance counts as converged (its noise level)."""
    tol_eff = max(tol, ROUNDOFF_FACTOR * _EPS * size / u_ref)
    stalled = eta_cap < ETA_RETRY_MIN
    if stalled and tol_eff > tol and res < FLOOR_STALL * tol_eff:
        tol_eff *= FLOOR_STALL
    if res < tol_eff or out_of_steps or stalled:
        return (0 if res < tol_eff else (2 if stalled else 1)), tol_eff
    return -1, tol_eff


@numba.njit(**JIT, inline="always")
def _record(hist, steps, res, its, t):
    """Row ``steps - 1`` of the Newton history: residual, CG iterations, step taken (0 when the
    line search failed); steps beyond the history's rows are not recorded."""
    if steps <= hist.shape[0]:
        hist[steps - 1, 0] = res
        hist[steps - 1, 1] = its
        hist[steps - 1, 2] = t


@numba.njit(**JIT)
def newton_line(fft, tables, op, scene, pressure_law, v_io, settings, out):
    """Newton-Krylov on v = ln p (in place, ``v_io``) for the line contact.

    ``fft``: FFT plans of length 2n (:func:`fastline._lib.fftw.acquire`); ``tables``, ``op``:
    the log kernel's :class:`~fastline.elastic.convolution.KernelTables` and
    :class:`~fastline.elastic.convolution.KernelScale` (m/Pa); ``scene``: :class:`Scene` (m, m,
    N/m); ``pressure_law``: :class:`Law` ``(law, u_ref)`` (module docstring; m);
    ``settings``: :class:`NewtonSettings`; ``out``: :class:`NewtonOutputs` ``(hist, u_out,
    ws)``: per step (residual, CG iterations, step), the law's separation at the end (m), work
    space of :func:`workspace_size` ``(n)`` elements. Returns ``(u1, residual, status, steps,
    cg_iterations, k_applications, circulant_solves, tol_effective)``. Each step: the Newton
    system (:func:`fastline.elastic.pcg.solve_newton_system`, called at the address
    ``settings.system``: compiled on its own) to the forcing of :func:`_forcing`, a step guard
    on ln p (:func:`_step_guard`), Armijo backtracking on ||r|| (:func:`_line_search`), the
    last two inlined (``inline="always"``: less cold compile time)."""
    kspec, strang, prefix = tables
    scale, K00 = op
    gap, w, load = scene
    law, u_ref = pressure_law
    tol, max_iter, nc, system = settings
    hist, u_out, ws = out
    n = v_io.shape[0]
    a, c, state, trial, D, dp, tail = _newton_views(ws, n)  # trial: the line search's
    conv = (fft, kspec, scale, a, c)
    for i in range(n):
        state[_V][i] = v_io[i]
    u1, phi, size = _evaluate(state, math.nan, fft, kspec, scale, gap, w, law, a, c)
    kapps = 1
    steps = cg_total = circ = 0
    res_prev = eta = math.nan
    eta_cap = ETA_MAX
    while True:
        res = largest_abs(state[_R], 0.0) / u_ref
        status, tol_eff = _stop(res, tol, size, u_ref, steps >= max_iter, eta_cap)
        if status >= 0:
            for i in range(n):  # loops, not v_io[:] = v: no broadcasting error path to compile
                v_io[i] = state[_V][i]
                u_out[i] = state[_U][i]
            return u1, res, status, steps, cg_total, kapps, circ, tol_eff
        steps += 1
        _newton_diagonal(state[_P], state[_DU], u_ref, D)
        eta = min(_forcing(res, res_prev, eta, tol_eff), eta_cap)
        res_prev = res
        sys_args = (fft, tables, op, D, w, state[_R], CGSettings(eta, MAX_CG, nc), dp, tail)
        du1, its, ka, ci = call_system(system, sys_args)
        cg_total += its
        kapps += ka
        circ += ci
        t = _step_guard(state[_P], state[_DU], u_ref, dp)
        accepted, t, trials, u1n, phin, sizen = _line_search(
            state, trial, dp, t, u1, du1, phi, scene, law, conv
        )
        kapps += trials
        _record(hist, steps, res, its, t if accepted else 0.0)
        if accepted:
            state, trial = trial, state
            u1, phi, size = u1n, phin, sizen
        else:  # not a descent direction: solve the step more accurately
            eta_cap = eta * 1e-3


@numba.njit(**JIT, inline="always")
def _iterate_views(ws, o, n):
    """The arrays of an iterate, ``(v, p, U, dU, gk, r)`` (ln p, p, the law's u and du/dv,
    g + K p, the residual; indices ``_V`` ... ``_R``): six views of n elements into ``ws`` from
    offset ``o``."""
    return (
        ws[o : o + n],
        ws[o + n : o + 2 * n],
        ws[o + 2 * n : o + 3 * n],
        ws[o + 3 * n : o + 4 * n],
        ws[o + 4 * n : o + 5 * n],
        ws[o + 5 * n : o + 6 * n],
    )


@numba.njit(**JIT, inline="always")
def _newton_diagonal(p, dU, u_ref, D):
    """``D = |du/dp| = -(du/dv) / p``, kept within [1e-300 u_ref / p, 1e300]."""
    for i in range(p.shape[0]):
        D[i] = min(max(-dU[i], 1e-300 * u_ref) / max(p[i], 1e-300), 1e300)


@numba.njit(**JIT, inline="always")
def _step_guard(p, dU, u_ref, dp):
    """Turn the Newton step ``dp`` into ``dv = dp / p`` (in place) and return the step length
    that moves ln p by at most ``DV_MAX`` where it matters (cells carrying load or in the
    law's steep range)."""
    pmax = largest(p, 0.0)
    gmax = 0.0
    for i in range(p.shape[0]):
        dp[i] /= max(p[i], 1e-300)  # dp -> dv
        if p[i] > 1e-6 * pmax or dU[i] > -0.5 * u_ref:
            gmax = max(gmax, abs(dp[i]))
    return min(1.0, DV_MAX / max(1e-300, gmax))


@numba.njit(**JIT, inline="always")
def _line_search(state, trial, dv, t, u1, du1, phi, scene, law, conv):
    """Armijo backtracking on ||r|| from step length ``t``: ``trial`` holds the iterate
    ``v + t dv`` (its pressure renormalised to the load) of the last trial. ``scene = (gap,
    w, load)`` (m, m, N/m) and ``law`` as in :func:`newton_line`; ``conv = (fft, kspec, scale,
    a, c)``: what a K product takes (the FFT plans, the kernel spectrum / 2n, dx / E* in m/Pa,
    the two FFT buffers). Returns ``(accepted, t, trials, u1, ||r||, size)`` of that trial (one
    FFT convolution each)."""
    gap, w, load = scene
    fft, kspec, scale, a, c = conv
    v, v2, p2 = state[_V], trial[_V], trial[_P]
    n = v.shape[0]
    u1n = phin = sizen = math.nan
    for k in range(LINE_SEARCH_HALVINGS + 1):
        for i in range(n):
            v2[i] = v[i] + t * dv[i]
        normalise_pressure_into(v2, load, w, p2)
        u1n, phin, sizen = _residual(trial, u1 + t * du1, fft, kspec, scale, gap, w, law, a, c)
        if phin < (1.0 - 1e-4 * t) * phi:
            return True, t, k + 1, u1n, phin, sizen
        t *= 0.5
    return False, t, LINE_SEARCH_HALVINGS + 1, u1n, phin, sizen


@numba.njit(**JIT)
def _forcing(res, res_prev, eta_prev, tol):
    """Eisenstat-Walker choice 2, floored at ``ETA_RES_SCALE * res``
    (:func:`fastline.contact.core._forcing`)."""
    if res_prev != res_prev:  # the first step: the floors below alone
        eta = 0.0
    else:
        eta = 0.9 * (res / res_prev) ** 2
        if 0.9 * eta_prev * eta_prev > 0.1:
            eta = max(eta, 0.9 * eta_prev * eta_prev)
    # two-argument max only: one compiled version of it
    return min(ETA_MAX, max(max(max(eta, ETA_RES_SCALE * res), ETA_FLOOR), 0.5 * tol / res))


def solve_compiled(
    op: LogKernelOperator,
    gap: np.ndarray,
    w: np.ndarray,
    load: float,
    law_form: tuple,
    u_ref: float,
    v: np.ndarray,
    tol: float,
    max_iter: int,
) -> tuple[float, float, int, int, int, float, np.ndarray, np.ndarray] | None:
    """The whole Newton iteration on the operator ``op`` in one compiled call (:func:`newton_line`)
    for a law with a compiled form; ``v`` (ln p, normalised) is updated in place. Returns
    ``(u1, residual, status, steps, cg_iterations, tol_effective, history, u)`` (status 0
    converged, 1 max_iter, 2 line search failed) and counts the FFT convolutions on ``op``; None
    if the compiled FFT path is not available."""
    if not fftw.AVAILABLE:
        return None
    hist = np.zeros((max_iter, 3))
    u = np.empty(op.n)
    N = 2 * op.n
    fft = fftw.acquire(N)
    tables = compiled_tables(op.n)
    try:
        args = [
            fft,
            tables,
            op.kernel_scale,
            Scene(gap, w, float(load)),
            Law(law_form, float(u_ref)),
            v,
            NewtonSettings(float(tol), int(max_iter), coarse_aggregates(op.n), 0),
            NewtonOutputs(hist, u, compiled_workspace(workspace_size(op.n))),
        ]
        compile_meanwhile(newton_line, args)  # while the system's solver compiles elsewhere,
        compile_meanwhile(pressure_into, (u, u))  # and what makes the answer of its result
        compile_meanwhile(line_measures, (u, u, 1.0))
        args[6] = args[6]._replace(system=system_address(fft, tables, op.kernel_scale, w))
        u1, res, status, steps, cg, kapps, circ, tol_eff = newton_line(*args)
    finally:
        fftw.release(N)
    op.convolutions += kapps + circ
    op.circulant_solves += circ
    return u1, res, status, steps, cg, tol_eff, hist[:steps], u
