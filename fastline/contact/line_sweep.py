"""A line contact's sweep over loads as one compiled call (continuation without Python).

:meth:`fastline.LineContact.sweep` solves a series of loads by continuation: each solve starts
from a prediction made from the solutions already found (:meth:`fastline.contact.model.ContactModel.
_predict` is the readable reference). Between two compiled Newton solves that loop used to spend
~150 us of Python per load (the prediction, the slopes of its Hermite interpolant, the grid): more
than the solve itself at n = 256. Here the whole loop runs in one compiled call, with the GIL
released: for each load, in increasing order,

1. the cells of its grid (:func:`fastline.contact.kernels.line_cells`),
2. the start: the prediction (:func:`predict_into`) normalised to the load; the cold start for
   the first load and after a step in ln load longer than ``PREDICTOR_MAX_STEP``,
3. the compiled Newton solve (:func:`fastline.contact.line_newton.newton_line`); when it fails
   from a predicted start, once more from the cold start (its work counted too),
4. the pressure and its measures (p0, s, FWHM), and what the next predictions need
   (:func:`_remember`): ln load, ln s, the cells in units of s, ln p and its slopes.

The prediction is that of the Python loop, stage for stage, on the same constants
(``SWEEP_PREDICTOR_ORDER``, ``PREDICTOR_MAX_STEP``, ``CORE_DEPTH`` of
:mod:`fastline.contact.model`); one difference: ln p of the solution comes from the Newton iterate
itself, not from the law's inverse at the separation (equal to round-off; no flushed cells to
repair).

Rows of the history arrays are the remembered solutions, oldest first; ``nh`` of them are set.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import NamedTuple

import numba
import numpy as np

from fastline._lib import fftw as _fftw
from fastline._lib.jit import JIT
from fastline._lib.native import compile_meanwhile
from fastline.contact.kernels import (
    cold_start_normalised,
    hermite_accumulate,
    line_cells,
    line_measures,
    normalise_into,
    pressure_into,
)
from fastline.contact.line_newton import (
    Law,
    NewtonOutputs,
    NewtonSettings,
    Scene,
    newton_line,
)
from fastline.contact.line_newton import workspace_size as _newton_workspace
from fastline.contact.model import CORE_DEPTH, PREDICTOR_MAX_STEP, SWEEP_PREDICTOR_ORDER
from fastline.elastic import line as elastic
from fastline.elastic.convolution import KernelScale
from fastline.elastic.pcg import system_address

#: columns of the per-load statistics a sweep returns
STATS = (
    "u1",
    "residual",
    "status",
    "steps",
    "cg_iterations",
    "k_applications",
    "circulant_solves",
    "tol_effective",
    "restarted_cold",
    "p0",
    "s",
    "fwhm",
    "sum_p",
)
#: n-sized work arrays of :func:`sweep_line` itself: x, gap, w, v (ln p), in_domain, in_contact
_OWN_ARRAYS = 6


class Cylinder(NamedTuple):
    """The elastic cylinder of a line contact, as :func:`sweep_line` builds each load's grid."""

    #: ``khat_0``, the log kernel's first influence coefficient (dimensionless)
    khat0: float
    #: the effective plane-strain modulus E* (Pa)
    E_star: float
    #: twice the radius, 2R (m)
    two_r: float


class SweepLoads(NamedTuple):
    """The loads of a sweep and what each one's solve starts from (m loads)."""

    #: the loads, increasing (N/m)
    loads: np.ndarray
    #: each load's domain half-width (m)
    halves: np.ndarray
    #: (m x 7): each load's cold-start profiles ``(a, ln_h, floor, ln_g, 2 s^2, ln_t, k_t)``
    #: (:func:`fastline.contact.kernels.cold_start_into`)
    cold: np.ndarray


class SweepOutputs(NamedTuple):
    """Where :func:`sweep_line` writes, row k for load k."""

    #: (m x n) the law's separation (m)
    U: np.ndarray
    #: (m x n) the pressure (Pa)
    P: np.ndarray
    #: (m x len(STATS)) the columns of ``STATS``
    stats: np.ndarray
    #: (m x max_iter x 3) each solve's Newton history (residual, CG iterations, step)
    hist: np.ndarray
    #: float64 work space of :func:`workspace_size` ``(n)`` elements, its contents irrelevant
    ws: np.ndarray


def workspace_size(n: int) -> int:
    """float64 elements of the work space :func:`sweep_line` takes for n cells."""
    return _OWN_ARRAYS * n + _newton_workspace(n)


def history_arrays(order: int, n: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Empty history of a sweep: ``(scalars (order + 1, 2), cells (3, order + 1, n),
    count (1,))`` (:func:`sweep_line`); kept by the caller between chunks of loads."""
    return np.zeros((order + 1, 2)), np.zeros((3, order + 1, n)), np.zeros(1, np.int64)


@numba.njit(**JIT)
def _slopes(h, y, out):
    """dy/dxi on cells spaced h: second-order central differences, one-sided second order at
    the ends (what ``np.gradient(y, xi, edge_order=2)`` gives on a uniform grid)."""
    n = y.shape[0]
    for i in range(1, n - 1):
        out[i] = (y[i + 1] - y[i - 1]) / (2.0 * h)
    out[0] = (-3.0 * y[0] + 4.0 * y[1] - y[2]) / (2.0 * h)
    out[n - 1] = (3.0 * y[n - 1] - 4.0 * y[n - 2] + y[n - 3]) / (2.0 * h)


@numba.njit(**JIT)
def predict_into(t, order, core_lo, core_hi, scal, cells, nh, x, work, out):
    """ln p at ln load ``t`` on the cells ``x`` (m) from the ``nh`` remembered solutions:
    the Lagrange polynomial in ln load through the last ``order + 1`` of them, in the core at
    the same x / s (s extrapolated too), in the tail at the same place in the domain, blended
    linearly between ``core_lo`` and ``core_hi`` below the peak
    (:meth:`fastline.contact.model.ContactModel._predict`).
    ``scal[k] = (ln load, ln s)``, ``cells[:, k]`` = (x / s, ln p, slope) of solution k;
    ``work``: two n-sized arrays."""
    n = x.shape[0]
    first = max(0, nh - 1 - order)
    in_domain, in_contact = work[:n], work[n : 2 * n]
    for i in range(n):
        in_domain[i] = 0.0
        in_contact[i] = 0.0
    ln_width = 0.0
    weights = np.empty(nh - first)
    for a in range(first, nh):  # Lagrange weights, the width and the domain term
        wa = 1.0
        for b in range(first, nh):
            if b != a:
                wa *= (t - scal[b, 0]) / (scal[a, 0] - scal[b, 0])
        weights[a - first] = wa
        ln_width += wa * scal[a, 1]
        va = cells[1, a]
        for i in range(n):
            in_domain[i] += wa * va[i]
    width = math.exp(ln_width)
    for i in range(n):  # the core term is interpolated at x / s
        out[i] = x[i] / width
    for a in range(first, nh):
        hermite_accumulate(
            out, cells[0, a], cells[1, a], cells[2, a], weights[a - first], in_contact
        )
    top = -math.inf
    for i in range(n):
        top = max(top, in_domain[i])
    for i in range(n):
        tail = min(max((top - in_domain[i] - core_lo) / (core_hi - core_lo), 0.0), 1.0)
        out[i] = tail * in_domain[i] + (1.0 - tail) * in_contact[i]


@numba.njit(**JIT)
def _remember(t, x, v, dx, width, scal, cells, nh):
    """Add the solution ln p = ``v`` at ln load ``t``, of width ``width`` (m: its standard
    deviation s), to the history (the oldest out when it is full; a solution at the newest load
    replaces it); returns the new count."""
    keep = scal.shape[0]
    if nh > 0 and t == scal[nh - 1, 0]:
        nh -= 1  # the same load again: no two rows at one load (Lagrange weights)
    elif nh == keep:
        for k in range(1, keep):
            scal[k - 1, 0] = scal[k, 0]
            scal[k - 1, 1] = scal[k, 1]
            for j in range(3):
                cells[j, k - 1, :] = cells[j, k, :]
        nh -= 1
    scal[nh, 0] = t
    scal[nh, 1] = math.log(width)
    xi, lv, slope = cells[0, nh], cells[1, nh], cells[2, nh]
    for i in range(x.shape[0]):
        xi[i] = x[i] / width
        lv[i] = v[i]
    _slopes(dx / width, lv, slope)
    return nh + 1


@numba.njit(**JIT, inline="always")
def _cold_profiles(cold, k):
    """The cold-start profiles of load k as the tuple :func:`cold_start_normalised` takes."""
    return (cold[k, 0], cold[k, 1], cold[k, 2], cold[k, 3], cold[k, 4], cold[k, 5], cold[k, 6])


@numba.njit(**JIT)
def sweep_line(
    fft, tables, cylinder, series, pressure_law, settings, predictor, history, rows, out
):
    """Solve loads ``k0 <= k < k1`` (``rows``) of a sweep by continuation (module docstring).

    ``fft``, ``tables``, ``pressure_law`` (:class:`~fastline.contact.line_newton.Law`) and
    ``settings`` (:class:`~fastline.contact.line_newton.NewtonSettings`) as in
    :func:`~fastline.contact.line_newton.newton_line`; ``cylinder``: :class:`Cylinder` ``(khat0,
    E_star, two_r)`` (-, Pa, m); ``series``: :class:`SweepLoads` ``(loads, halves, cold)``: the
    increasing loads (N/m), each one's domain half-width (m) and cold-start profiles ``(a, ln_h,
    floor, ln_g, 2 s^2, ln_t, k_t)``; ``predictor = (order, max_step, core_lo, core_hi)``: the
    prediction's degree in ln load, its longest step, the depths below the peak in ln p of its
    blend from core to tail (:func:`predict_into`); ``history = (scal, cells, count)``
    (:func:`history_arrays`), updated in place. ``out``: :class:`SweepOutputs` ``(U, P, stats,
    hist, ws)``, row k: the law's separation (m), the pressure (Pa), the columns of ``STATS``,
    the Newton history; ``ws`` work space of :func:`workspace_size` ``(n)`` elements."""
    khat0, E_star, two_r = cylinder
    loads, halves, cold = series
    scal, cells, count = history
    k0, k1 = rows
    U, P, stats, hist, ws = out
    n = U.shape[1]
    order, max_step, core_lo, core_hi = predictor
    x, gap, w, v = ws[:n], ws[n : 2 * n], ws[2 * n : 3 * n], ws[3 * n : 4 * n]
    work, solver_ws = ws[4 * n : 6 * n], ws[_OWN_ARRAYS * n :]
    nh = count[0]
    for k in range(k0, k1):
        load, u = loads[k], U[k]
        dx = 2.0 * halves[k] / n
        line_cells(dx, two_r, x, gap, w)
        scale = dx / E_star
        op, scene = KernelScale(scale, scale * khat0), Scene(gap, w, load)
        outputs = NewtonOutputs(hist[k], u, solver_ws)
        t = math.log(load)
        restarted = 0.0
        kapps = circ = 0
        predicted = nh > 0 and t - scal[nh - 1, 0] <= max_step
        for attempt in range(2):
            if not predicted or attempt == 1:
                cold_start_normalised(x, _cold_profiles(cold, k), load, w, v)
            else:
                predict_into(t, order, core_lo, core_hi, scal, cells, nh, x, work, v)
                normalise_into(v, load, w)
            u1, res, status, steps, cg, ka, ci, tol_eff = newton_line(
                fft, tables, op, scene, pressure_law, v, settings, outputs
            )
            kapps += ka
            circ += ci
            if status == 0 or not predicted or attempt == 1:
                break
            restarted = 1.0  # the prediction misled Newton: start cold
        pressure_into(v, P[k])
        p0, s, fw, total = line_measures(x, P[k], dx)
        row = stats[k]
        row[0], row[1], row[2], row[3], row[4] = u1, res, status, steps, cg
        row[5], row[6], row[7], row[8] = kapps, circ, tol_eff, restarted
        row[9], row[10], row[11], row[12] = p0, s, fw, total
        nh = _remember(t, x, v, dx, s if s > 0.0 else halves[k], scal, cells, nh)
    count[0] = nh


class SweepArrays(NamedTuple):
    """What :func:`run_sweep` returns, row k for the k-th load in increasing order: ``u`` the
    law's separation (m), ``p`` the pressure (Pa), ``stats`` the columns of ``STATS``, ``hist``
    each solve's Newton history (residual, CG iterations, step)."""

    u: np.ndarray
    p: np.ndarray
    stats: np.ndarray
    hist: np.ndarray


def run_sweep(
    n: int,
    E_star: float,
    radius: float,
    loads: np.ndarray,
    halves: np.ndarray,
    cold: np.ndarray,
    law_form: tuple,
    u_ref: float,
    tol: float,
    max_iter: int,
    progress: Callable[[], object] | None = None,
    history: tuple[np.ndarray, np.ndarray, np.ndarray] | None = None,
) -> SweepArrays:
    """Solve the increasing ``loads`` (N/m) of a line contact on n cells by continuation in
    compiled calls (module docstring): all at once, or one call per load when ``progress``
    is given (called after each). ``halves`` (m) and ``cold`` as in :func:`sweep_line`;
    ``history``: solutions to continue from (:func:`history_arrays`, updated in place; default
    none). The caller has checked everything."""
    m = loads.shape[0]
    U, P = np.empty((m, n)), np.empty((m, n))
    # every stats column is written; of hist only the rows of the steps taken are read
    stats, hist = np.empty((m, len(STATS))), np.empty((m, max_iter, 3))
    scal, cells, count = history_arrays(SWEEP_PREDICTOR_ORDER, n) if history is None else history
    predictor = (SWEEP_PREDICTOR_ORDER, PREDICTOR_MAX_STEP, CORE_DEPTH[0], CORE_DEPTH[1])
    tables = elastic.compiled_tables(n)
    cylinder = Cylinder(elastic.KHAT0, float(E_star), 2.0 * radius)
    series = SweepLoads(loads, halves, cold)
    pressure_law = Law(law_form, float(u_ref))
    step = m if progress is None else 1
    fft = _fftw.acquire(2 * n)
    try:
        ws = elastic.compiled_workspace(workspace_size(n))
        settings = NewtonSettings(float(tol), int(max_iter), elastic.coarse_aggregates(n), 0)
        args = [fft, tables, cylinder, series, pressure_law, settings, predictor]
        args += [(scal, cells, count), (0, m), SweepOutputs(U, P, stats, hist, ws)]
        compile_meanwhile(sweep_line, args)  # while the system's solver compiles elsewhere
        # the arguments' types count: w is a C-contiguous view into ws in sweep_line
        system = system_address(fft, tables, KernelScale(1.0, 1.0), np.empty(1))
        args[5] = settings._replace(system=system)
        for k0 in range(0, m, step):
            args[8] = (k0, min(m, k0 + step))
            sweep_line(*args)
            if progress is not None:
                progress()
    finally:
        _fftw.release(2 * n)
    return SweepArrays(U, P, stats, hist)
