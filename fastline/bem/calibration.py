"""Calibrate a pressure law on boundary-element ensembles of the user's own spectrum.

:func:`calibrate` draws ``realizations`` periodic random surfaces of the spectrum, presses a
rigid flat on each at every pressure of a range (the same surface carried from pressure to
pressure, each solve warm-started from the last one's pressure field), and measures on every
gap field the mean gap, the contact fraction and the Reynolds effective gap
``(12 eta K)^(1/3)`` for flow along x and along y (:func:`fastline.bem.flow.reynolds_flow`,
its conjugate gradients started from the last pressure's fluid field and stopped on the
conductance's own error, or its direct solve where that is cheaper). The ensemble
means with their standard errors become a :class:`~fastline.theory.calibrated.CalibratedLaw`:
a monotone fit joined to Persson's law outside the simulated range (docs/calibration.md). The
mean gap is averaged over the surfaces at a fixed gap (:func:`fixed_gap_mean`: the pressure a
rigid body needs for a given gap is the surfaces' mean), the other quantities at a fixed
pressure.

One task is one surface through every pressure, so the realisations run wherever
:func:`fastline.sweep` runs its tasks (:func:`~fastline.bem.ensemble.ensemble_executor`: this
process, a local process pool, a dask cluster or any executor).

Resolution: the grid is :func:`~fastline.bem.surface.spectral_grid` (``points_per_wavelength``
cells per shortest wavelength ``2 pi / q1``, ``periods`` longest wavelengths per side); fewer
than ``MIN_CELLS_PER_WAVELENGTH`` cells is refused. ``check="finer"`` (default) repeats a
subset (three pressures, a quarter of the realisations) on a grid twice as fine, ``"larger"``
on a cell twice as long, and reports the change of the mean gap and the hydraulic gap
(``law.settings["check"]``); a change beyond ``CHECK_TOLERANCE`` warns
(:class:`~fastline.errors.CalibrationWarning`).
"""

from __future__ import annotations

import concurrent.futures as cf
import contextlib
import math
import time
import warnings
from collections.abc import Callable
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike

from fastline._lib.validate import integer, positive, positive_array
from fastline._lib.version import __version__
from fastline.bem.contact import DEFAULT_TOL, solve_contact
from fastline.bem.ensemble import ensemble_executor, progress_bar
from fastline.bem.flow import CONDUCTANCE_TOL, reynolds_flow
from fastline.bem.surface import Grid, random_surface, spectral_grid
from fastline.errors import CalibrationWarning
from fastline.theory.calibrated import CalibratedLaw, CalibrationPoints
from fastline.theory.limits import hertz_line_contact, hertz_point_contact
from fastline.theory.spectra import PSD

if TYPE_CHECKING:
    from fastline.bem.ensemble import ExecutorLike

__all__ = ["calibrate", "pressure_range", "MIN_CELLS_PER_WAVELENGTH"]

#: the grid must hold at least this many cells per shortest wavelength 2 pi / q1
MIN_CELLS_PER_WAVELENGTH = 4.0
#: pressures of a calibration by default
DEFAULT_PRESSURES = 15
#: the companion check warns when the mean gap or hydraulic gap moves by more than this
#: (relative) and by more than 3 combined standard errors
CHECK_TOLERANCE = 0.05
#: pressure range from the scenes: this fraction of the smallest peak pressure ...
RANGE_LOW = 0.01
#: ... up to this multiple of the largest (Hertz's peak bounds the rough one from above)
RANGE_HIGH = 1.5
CHECKS = ("finer", "larger", None)
#: most cells of a calibration grid, the check's companion included (4096 x 4096: a surface's
#: arrays and the solver's work space take about a gigabyte there)
MAX_CELLS = 4096 * 4096
#: most realisations of one calibration
MAX_REALIZATIONS = 10_000


@dataclass(frozen=True)
class _Task:
    """What one realisation needs besides its seed (picklable)."""

    psd: PSD
    E_star: float
    grid: Grid
    pressures: np.ndarray
    tol: float
    max_iter: int
    viscosity: float


def _one_surface(seed, task: _Task) -> dict:
    """One surface through every pressure (increasing, warm starts): per pressure the mean
    gap [m], contact fraction, effective gaps along x and y [m], iterations and convergence."""
    start = time.perf_counter()
    grid = task.grid
    g0 = -random_surface(task.psd, grid, seed).heights
    n = task.pressures.size
    keys = ("u", "area", "gx", "gy", "iterations", "flow_iterations", "flow_direct")
    out = {k: np.zeros(n) for k in keys}
    out["converged"] = np.zeros(n, dtype=bool)
    warm = sx = sy = None
    for i, p in enumerate(task.pressures):
        res = solve_contact(
            g0, grid, task.E_star, float(p) * grid.lx * grid.ly, tol=task.tol,
            max_iter=task.max_iter, p_init=warm,
        )  # fmt: skip
        if i + 1 < n:  # the next start: this field scaled to the next load
            warm = np.maximum(res.pressure, 0.0) * (task.pressures[i + 1] / p)
        flow = dict(viscosity=task.viscosity, conductance_tol=CONDUCTANCE_TOL)
        sx = reynolds_flow(res.gap, grid.dx, grid.dy, start=sx, **flow)
        sy = reynolds_flow(res.gap.T, grid.dy, grid.dx, start=sy, **flow)
        out["gx"][i], out["gy"][i] = sx.conductance, sy.conductance
        out["flow_iterations"][i] = sx.iterations + sy.iterations
        out["flow_direct"][i] = (sx.solver == "direct") + (sy.solver == "direct")
        out["u"][i] = res.gap.mean()
        out["area"][i] = res.contact_fraction
        out["iterations"][i] = res.iterations
        out["converged"][i] = res.converged
    out["seconds"] = time.perf_counter() - start
    return out


def pressure_range(
    psd: PSD, E_star: float, radius: float, loads: ArrayLike, geometry: str = "line"
) -> tuple[float, float]:
    """The nominal pressures a calibration should cover for the scenes the user will solve.

    From ``RANGE_LOW`` times the smallest Hertz peak pressure to ``RANGE_HIGH`` times the
    largest (a rough contact's peak lies below Hertz's; its tails below the range are Persson's
    law, scaled: docs/calibration.md).

    Parameters
    ----------
    psd : PSD
    E_star : float
        Effective modulus [Pa], > 0.
    radius : float
        Cylinder or sphere radius [m], > 0.
    loads : float or array_like
        Loads per length [N/m] (line) or forces [N] (point), > 0.
    geometry : {"line", "point"}

    Returns
    -------
    (p_lo, p_hi) : tuple of float
        [Pa].
    """
    if not isinstance(psd, PSD):
        raise TypeError(f"psd must be a fastline PSD, got {type(psd).__name__}")
    E_star = positive("E_star", E_star, "Pa")
    radius = positive("radius", radius, "m")
    loads = np.atleast_1d(positive_array("loads", loads)).ravel()
    if loads.size == 0:
        raise ValueError("loads must hold at least one load (N/m for a line, N for a point)")
    if geometry not in ("line", "point"):
        raise ValueError(f"geometry must be 'line' or 'point', got {geometry!r}")
    hertz = hertz_line_contact if geometry == "line" else hertz_point_contact
    p0 = [hertz(E_star, radius, float(f)).p0 for f in (loads.min(), loads.max())]
    return RANGE_LOW * p0[0], RANGE_HIGH * p0[1]


def _pressures(pressures, psd, E_star, radius, loads, geometry, n_pressures) -> np.ndarray:
    """The calibration pressures [Pa], increasing: given, or spread over the scenes' range
    (``geometry`` and ``n_pressures`` checked either way)."""
    if geometry not in ("line", "point"):
        raise ValueError(f"geometry must be 'line' or 'point', got {geometry!r}")
    n = integer("n_pressures", n_pressures, 3, 200)
    if pressures is not None:
        if radius is not None or loads is not None:
            raise ValueError("give either pressures or radius and loads, not both")
        p = np.unique(np.atleast_1d(positive_array("pressures", pressures)).ravel())
        if p.size < 3:
            raise ValueError(f"pressures must hold at least 3 distinct values, got {p.size}")
        return p
    if radius is None or loads is None:
        raise ValueError(
            "give pressures [Pa], or radius [m] and loads (N/m for a line contact, N for a "
            "point contact) of the scenes to be solved, from which the range is chosen"
        )
    lo, hi = pressure_range(psd, E_star, radius, loads, geometry)
    return np.geomspace(lo, hi, n)


def _grid(psd, grid, points_per_wavelength, periods) -> Grid:
    """The calibration grid, refused when it does not resolve the spectrum."""
    if grid is None:
        ppw = positive("points_per_wavelength", points_per_wavelength)
        if ppw < MIN_CELLS_PER_WAVELENGTH:
            raise ValueError(
                f"points_per_wavelength must be >= {MIN_CELLS_PER_WAVELENGTH:g} (cells per "
                f"shortest wavelength 2 pi/q1: the contact spots are not resolved below), "
                f"got {ppw!r}"
            )
        return _sized(spectral_grid(psd, points_per_wavelength=ppw, periods=periods))
    if not isinstance(grid, Grid):
        raise TypeError(f"grid must be a fastline.bem.Grid or None, got {type(grid).__name__}")
    cells = 2.0 * math.pi / psd.q1 / max(grid.dx, grid.dy)
    if cells < MIN_CELLS_PER_WAVELENGTH:
        raise ValueError(
            f"grid must hold >= {MIN_CELLS_PER_WAVELENGTH:g} cells per shortest wavelength "
            f"2 pi/q1 = {2 * math.pi / psd.q1:.4g} m, got {cells:.3g} (cell {grid.dx:.4g} m)"
        )
    return _sized(grid)


def _sized(grid: Grid, what: str = "the calibration grid") -> Grid:
    """``grid`` if it has at most :data:`MAX_CELLS` cells; a ValueError saying what sets its
    size otherwise (before any surface is drawn: its arrays alone would not fit)."""
    if grid.nx * grid.ny > MAX_CELLS:
        raise ValueError(
            f"{what} would have {grid.nx} x {grid.ny} cells, more than {MAX_CELLS:,} "
            "(~1 GB per surface): lower points_per_wavelength or periods, give a grid of your "
            "own, or narrow the spectrum's q1/q0"
        )
    return grid


def _warn_width(grid, E_star, radius, loads, geometry) -> None:
    """Warn when a cell of the calibration is wider than the narrowest contact asked about."""
    if radius is None or loads is None:
        return
    hertz = hertz_line_contact if geometry == "line" else hertz_point_contact
    a = hertz(E_star, radius, float(np.min(loads))).a
    if max(grid.dx, grid.dy) > a:
        warnings.warn(
            f"fastline.calibrate: a calibration cell ({grid.dx:.3g} m) is wider than the "
            f"smallest contact half-width asked about ({a:.3g} m, Hertz): the law is an average "
            "over scales the contact does not hold",
            CalibrationWarning,
            stacklevel=3,
        )


def _run(executor, task, seeds, progress, done0, total) -> list[dict]:
    """``_one_surface`` over the seeds (results in seed order), reporting progress."""
    if executor is None:
        out = []
        for k, s in enumerate(seeds):
            out.append(_one_surface(s, task))
            if progress is not None:
                progress(done0 + k + 1, total)
        return out
    futures = [executor.submit(_one_surface, s, task) for s in seeds]
    try:
        for k, _ in enumerate(cf.as_completed(futures)):
            if progress is not None:
                progress(done0 + k + 1, total)
        return [f.result() for f in futures]
    finally:
        for f in futures:
            f.cancel()


def _mean_se(x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Mean over realisations (axis 0) and its standard error (NaN with one)."""
    n = x.shape[0]
    se = x.std(axis=0, ddof=1) / math.sqrt(n) if n > 1 else np.full(x.shape[1:], np.nan)
    return x.mean(axis=0), se


def _effective_gap(K, viscosity) -> tuple[np.ndarray, np.ndarray]:
    """Effective gap ``(12 eta <K>)^(1/3)`` [m] of the mean conductance and its error."""
    k, k_se = _mean_se(K)
    g = np.cbrt(12.0 * viscosity * k)
    with np.errstate(divide="ignore", invalid="ignore"):
        g_se = np.where(k > 0.0, g / (3.0 * k) * k_se, np.nan)
    return g, g_se


def _log_pressure_at(u_i: np.ndarray, v: np.ndarray, u: np.ndarray) -> np.ndarray:
    """ln p at which one surface (mean gaps ``u_i`` [m] at ``v = ln p``, decreasing) has the
    mean gaps ``u``: linear in ln p between its pressures, extended with its end slopes."""
    x, y = u_i[::-1], v[::-1]
    out = np.interp(u, x, y)
    for m, a, b in ((u < x[0], 0, 1), (u > x[-1], -1, -2)):
        out[m] = y[a] + (u[m] - x[a]) * (y[b] - y[a]) / (x[b] - x[a])
    return out


def fixed_gap_mean(u: np.ndarray, pressures: np.ndarray) -> np.ndarray:
    """The ensemble's mean gap at each pressure [m], averaged at a fixed gap.

    ``u[i, k]`` is surface i's mean gap at ``pressures[k]``. A rigid body on the rough surface
    sets the gap, not the pressure, and its nominal pressure is the mean over surfaces at a
    fixed gap. So for the mean gaps ``u_k = mean_i u[i, k]`` the law's pressure is
    ``P_k = mean_i p_i(u_k)`` (each surface's own u(p), linear in ln p); the result is the
    curve ``(P_k, u_k)`` read at ``pressures`` (linear in ln p, extended at its ends). On a
    cell that holds many contact spots it equals the mean at a fixed pressure; on a small cell
    at low pressure it is larger (docs/calibration.md). One surface, or surfaces whose u(p) is
    not strictly decreasing: the plain mean.
    """
    um = u.mean(axis=0)
    if u.shape[0] < 2 or np.any(np.diff(u, axis=1) >= 0.0):
        return um
    v = np.log(pressures)
    P = np.mean([np.exp(_log_pressure_at(ui, v, um)) for ui in u], axis=0)
    V = np.log(P)
    if np.any(np.diff(V) <= 0.0):
        return um
    return _gap_at(V, um, v)


def _gap_at(V: np.ndarray, U: np.ndarray, v: np.ndarray) -> np.ndarray:
    """U (decreasing) at nodes V (increasing) read at v: linear, extended with the end slopes."""
    out = np.interp(v, V, U)
    for m, a, b in ((v < V[0], 0, 1), (v > V[-1], -1, -2)):
        out[m] = U[a] + (v[m] - V[a]) * (U[b] - U[a]) / (V[b] - V[a])
    return out


def _points(task, runs) -> CalibrationPoints:
    stack = {k: np.array([r[k] for r in runs]) for k in ("u", "area", "gx", "gy")}
    _, u_se = _mean_se(stack["u"])
    u = fixed_gap_mean(stack["u"], task.pressures)
    a, a_se = _mean_se(stack["area"])
    gx, gx_se = _effective_gap(stack["gx"], task.viscosity)
    gy, gy_se = _effective_gap(stack["gy"], task.viscosity)
    return CalibrationPoints(task.pressures, u, u_se, a, a_se, gx, gx_se, gy, gy_se)


def _grid_record(psd, grid) -> dict:
    return {
        "nx": grid.nx,
        "ny": grid.ny,
        "dx": grid.dx,
        "dy": grid.dy,
        "cells_per_wavelength": 2.0 * math.pi / psd.q1 / max(grid.dx, grid.dy),
        "periods": grid.lx * psd.q0 / (2.0 * math.pi),
    }


def _solve_record(runs, seconds) -> dict:
    it = np.array([r["iterations"] for r in runs])
    conv = np.array([r["converged"] for r in runs])
    return {
        "solves": int(it.size),
        "iterations": int(it.sum()),
        "iterations_max": int(it.max()),
        "flow_iterations": int(sum(r["flow_iterations"].sum() for r in runs)),
        "flow_direct_solves": int(sum(r["flow_direct"].sum() for r in runs)),
        "unconverged": int((~conv).sum()),
        "converged": bool(conv.all()),
        "seconds": seconds,
        "seconds_per_realization": [float(r["seconds"]) for r in runs],
    }


def _companion(task, check) -> _Task | None:
    """The check's task: three pressures (ends and middle) on a grid twice as fine or a cell
    twice as long (None without a check)."""
    if check is None:
        return None
    p = task.pressures
    sub = p[[0, p.size // 2, p.size - 1]]
    g = task.grid
    if check == "finer":
        grid = Grid(2 * g.nx, 2 * g.ny, 0.5 * g.dx, 0.5 * g.dy)
    else:
        grid = Grid(2 * g.nx, 2 * g.ny, g.dx, g.dy)
    grid = _sized(grid, f"the companion grid of check={check!r} (check=None: no check)")
    return _Task(task.psd, task.E_star, grid, sub, task.tol, task.max_iter, task.viscosity)


def _compare(main: CalibrationPoints, comp: CalibrationPoints, check, grid, seconds) -> dict:
    """The companion's change of u and of the hydraulic gap at its pressures (relative and in
    combined standard errors); warns beyond ``CHECK_TOLERANCE``."""
    idx = np.searchsorted(main.p, comp.p)
    out = {"kind": check, "p": comp.p.tolist(), "grid": [grid.nx, grid.ny, grid.dx, grid.dy]}
    worst = 0.0
    for name, a, ae, b, be in (
        ("u", main.u[idx], main.u_error[idx], comp.u, comp.u_error),
        ("gap_x", main.gap_x[idx], main.gap_x_error[idx], comp.gap_x, comp.gap_x_error),
    ):
        with np.errstate(divide="ignore", invalid="ignore"):
            rel = np.where(a > 0.0, b / a - 1.0, np.nan)
            z = (b - a) / np.hypot(ae, be)
        out[f"{name}_change"] = np.nan_to_num(rel, nan=0.0).tolist()
        out[f"{name}_z"] = np.nan_to_num(z, nan=0.0).tolist()
        bad = (np.abs(rel) > CHECK_TOLERANCE) & (np.abs(z) > 3.0)
        if np.any(bad):
            worst = max(worst, float(np.nanmax(np.abs(rel[bad]))))
    out["seconds"] = seconds
    out["passed"] = worst == 0.0
    if worst > 0.0:
        warnings.warn(
            f"fastline.calibrate: the {check} companion grid moves the mean or hydraulic gap by "
            f"{100 * worst:.1f} % (beyond {100 * CHECK_TOLERANCE:g} % and 3 standard errors): "
            "the calibration is not converged in its grid; raise "
            + ("points_per_wavelength" if check == "finer" else "periods"),
            CalibrationWarning,
            stacklevel=3,
        )
    return out


def _warn_unconverged(record) -> None:
    if record["unconverged"]:
        warnings.warn(
            f"fastline.calibrate: {record['unconverged']} of {record['solves']} contact solves "
            "did not converge within max_iter (law.settings['solves']); raise max_iter or "
            "tol",
            CalibrationWarning,
            stacklevel=3,
        )


def calibrate(
    psd: PSD, E_star: float, pressures: ArrayLike | None = None, *,
    radius: float | None = None, loads: ArrayLike | None = None, geometry: str = "line",
    n_pressures: int = DEFAULT_PRESSURES, realizations: int = 8, seed: int = 0,
    points_per_wavelength: float = 4.0, periods: float = 4.0, grid: Grid | None = None,
    check: str | None = "finer", tol: float = DEFAULT_TOL, max_iter: int = 5000,
    viscosity: float = 1e-3, executor: ExecutorLike = None, workers: int | None = None,
    progress: bool | Callable[[int, int], None] | None = None,
) -> CalibratedLaw:  # fmt: skip
    """A pressure law and hydraulic gap calibrated on flat-contact BEM ensembles of ``psd``
    (module docstring; docs/calibration.md).

    Parameters
    ----------
    psd, E_star : PSD, float
        The roughness spectrum and the effective modulus [Pa], > 0.
    pressures : array_like, optional
        Nominal pressures [Pa] to simulate (>= 3 distinct, > 0). Or give ``radius`` and
        ``loads`` of the scenes to be solved: ``n_pressures`` pressures log-spaced over
        :func:`pressure_range`.
    radius, loads, geometry
        Cylinder (``"line"``, loads in N/m) or sphere (``"point"``, forces in N) [m].
    n_pressures, realizations, seed : int
        Pressures chosen from the scenes (in [3, 200]); surfaces (>= 1, >= 2 for error bars),
        each run through every pressure; the root seed (surface k:
        ``SeedSequence(seed).spawn(realizations)[k]``).
    points_per_wavelength, periods : float
        Grid: cells per shortest wavelength ``2 pi / q1`` (>= 4) and cell length in longest
        wavelengths ``2 pi / q0`` (defaults 4 and 4: 512 x 512 cells at q1/q0 = 32).
    grid : Grid, optional
        A grid of your own instead (>= 4 cells per ``2 pi / q1``).
    check : {"finer", "larger", None}
        The companion grid of the convergence check (module docstring).
    tol, max_iter, viscosity
        CCG settings (:func:`~fastline.bem.contact.solve_contact`); the flow's viscosity [Pa s].
    executor, workers, progress
        Where the realisations run, as for :func:`fastline.sweep`; ``progress``: True (a bar on
        stderr), a callable ``progress(done, total)`` called after each realisation, or None.

    Returns
    -------
    CalibratedLaw
        ``law.settings`` holds the grid, the solves (iterations, convergence, s), the check.

    Raises
    ------
    ValueError
        A grid of < 4 cells per ``2 pi / q1``, a u(p) not monotone within its errors, an input
        out of range.
    """
    if not isinstance(psd, PSD):
        raise TypeError(f"psd must be a fastline PSD, got {type(psd).__name__}")
    E_star = positive("E_star", E_star, "Pa")
    p = _pressures(pressures, psd, E_star, radius, loads, geometry, n_pressures)
    g = _grid(psd, grid, points_per_wavelength, periods)
    n = integer("realizations", realizations, 1, MAX_REALIZATIONS)
    task = _Task(psd, E_star, g, p, positive("tol", tol), integer("max_iter", max_iter, 1),
                 positive("viscosity", viscosity, "Pa s"))  # fmt: skip
    _warn_width(g, E_star, radius, None if loads is None else np.atleast_1d(loads), geometry)
    return _calibration(task, n, integer("seed", seed, 0), check, (executor, workers), progress)


def _calibration(task, n, seed, check, engine, progress) -> CalibratedLaw:
    """The ensembles of a checked calibration (and of its companion), and the law."""
    if check not in CHECKS:
        raise ValueError(f"check must be one of {CHECKS}, got {check!r}")
    if not (progress is None or isinstance(progress, (bool, np.bool_)) or callable(progress)):
        raise TypeError(f"progress must be True, False, None or a callable, got {progress!r}")
    comp = _companion(task, check)
    n_comp = 0 if comp is None else max(2, n // 4) if n > 1 else 1
    seeds = np.random.SeedSequence(seed).spawn(n + n_comp)
    bar = None
    if isinstance(progress, (bool, np.bool_)):
        bar = progress_bar(bool(progress), n + n_comp, "calibration")
        progress = None if not progress else lambda done, total: bar.update(1)
    with (
        ensemble_executor(engine[0], engine[1], n) as ex,
        bar if bar is not None else contextlib.nullcontext(),
    ):
        t0 = time.perf_counter()
        runs = _run(ex, task, seeds[:n], progress, 0, n + n_comp)
        t1 = time.perf_counter()
        comp_runs = [] if comp is None else _run(ex, comp, seeds[n:], progress, n, n + n_comp)
        t2 = time.perf_counter()
    points = _points(task, runs)
    settings = {"grid": _grid_record(task.psd, task.grid), "realizations": n, "seed": seed,
                "tol": task.tol, "max_iter": task.max_iter, "viscosity": task.viscosity,
                "solves": _solve_record(runs, t1 - t0), "psd": repr(task.psd),
                "fastline": __version__}  # fmt: skip
    _warn_unconverged(settings["solves"])
    if comp is not None:
        settings["check"] = _compare(points, _points(comp, comp_runs), check, comp.grid, t2 - t1)
    return CalibratedLaw(points, task.psd, task.E_star, settings=settings)
