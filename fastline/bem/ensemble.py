"""Ensembles of BEM realisations: the nominal pressure of a rough cylinder or sphere, and the
contact and leakage of a nominally flat interface, with error bars over realisations.

A :class:`~fastline.bem.scene.Scene` (:mod:`fastline.bem.scene`, whose names this module
re-exports) holds everything one realisation needs (spectrum, material, geometry, load, grid,
solver settings).  :func:`run_realization` ``(seed, scene)`` is a plain module-level
function: it draws the surface from ``seed``, solves the contact (and for a flat scene the
Reynolds flow through the gap) and returns a small picklable :class:`Realization`, so an
ensemble runs wherever :func:`fastline.sweep` runs its tasks (:func:`run_ensemble`
``(..., executor=..., workers=...)``: this process, a local process pool, a dask cluster or any
:class:`concurrent.futures.Executor`; :func:`ensemble_executor`).

Statistics (:func:`run_ensemble`):

* cylinder: ``p_bar(x)``, the pressure averaged along the axis y, over bins of ``x`` and over
  realisations, with the standard error of the mean over realisations in each bin; ``s``
  (standard deviation about the centroid, cell-exact) and ``p0`` (peak of the even quartic
  fitted to the central ``|x - x_c| <= 0.75 s`` of the unbinned mean profile: the largest bin
  of a noisy profile is biased upward) and ``w`` (FWHM of the binned ``p_bar``);
* sphere: ``p_bar(r)`` averaged over rings about the sphere's axis and over realisations;
  ``p0`` from the same central fit over the rings with
  ``r <= 0.75 sqrt(2) s``, ``w = 2 r_half``, and ``s`` the per-axis standard deviation
  ``s^2 = <|r - r_c|^2> / 2`` of the mean pressure map (a Gaussian ``exp(-r^2 / 2 s^2)``
  has standard deviation ``s``);
  Hertz: ``s = a / sqrt(5)``, ``w/s = sqrt(15)``;
* flat: contact-area fraction, mean gap, and the Reynolds conductance and effective gap
  (:mod:`fastline.bem.flow`), means with standard errors.

The bins (rings) follow the contact's own width, measured on the ensemble's mean profile
(:func:`~fastline.bem.scene.cells_per_bin`: at least 20 across it, at most a quarter of the
longest roughness wavelength, at least one cell) unless ``Scene.bin_width`` fixes them; a
contact too narrow to compare widths (:func:`~fastline.bem.scene.narrow_contact`) is named in
``ProfileEnsemble.narrow`` and warned about once (:class:`~fastline.errors.NarrowContactWarning`).

The error bars of ``p0``, ``s``, ``w`` and ``w/s`` are jackknife standard errors over
realisations (B. Efron, C. Stein, Ann. Stat. 9, 586 (1981)), the right tool for a nonlinear
functional of a mean profile; they need at least two realisations (NaN with one).
"""

from __future__ import annotations

import math
import sys
import time
import warnings
from collections.abc import Iterator
from concurrent.futures import Executor, Future, as_completed
from contextlib import contextmanager
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

import numpy as np
from tqdm import tqdm

from fastline._lib.executors import close_engine, open_engine
from fastline._lib.validate import integer
from fastline.bem import _profile
from fastline.bem.contact import (
    ContactResult,
    cylinder_gap,
    image_curvature,
    solve_contact,
    sphere_gap,
)
from fastline.bem.flow import CONDUCTANCE_TOL, reynolds_flow
from fastline.bem.scene import (
    Scene,
    cells_per_bin,
    contact_width,
    flat_contact_scene,
    line_contact_scene,
    narrow_contact,
    point_contact_scene,
    ring_index,
    with_grid,
)
from fastline.bem.surface import random_surface
from fastline.errors import NarrowContactWarning

if TYPE_CHECKING:  # annotations only: dask is optional
    from distributed import Client

    #: where realisations run (:func:`ensemble_executor`)
    ExecutorLike = str | Executor | Client | None

__all__ = [
    "Scene",
    "Realization",
    "ProfileEnsemble",
    "FlatEnsemble",
    "line_contact_scene",
    "point_contact_scene",
    "flat_contact_scene",
    "run_realization",
    "run_ensemble",
    "ensemble_executor",
    "progress_bar",
    "with_grid",
]


# ---- one realisation ---------------------------------------------------------------------------
@dataclass(frozen=True)
class Realization:
    """Per-realisation output of :func:`run_realization` (small and picklable).

    Attributes
    ----------
    seed
        The seed it was drawn from.
    profile : ndarray or None
        Cylinder: pressure averaged along y, shape (nx,) [Pa]; sphere: pressure averaged over
        rings one cell wide (``ring_index(scene, 1)``) [Pa]; flat: None.
    moments : ndarray
        ``(sum p, sum x p, sum y p, sum (x^2 + y^2) p)`` over the cells [Pa, Pa m, Pa m, Pa m^2].
    contact_fraction : float
        Fraction of cells in contact.
    mean_gap : float
        Mean gap over the cell [m].
    conductance, effective_gap : float
        Flat scene: Reynolds flow results (:class:`~fastline.bem.flow.FlowResult`); else NaN.
    percolating : bool
        Flat scene: whether the gap percolates across x.
    h_rms : float
        The realisation's rms height [m] (0 if smooth).
    converged : bool
    iterations : int
    residual, max_penetration : float
        From :class:`~fastline.bem.contact.ContactResult`.
    seconds : float
        Wall time of the realisation [s].
    """

    seed: object
    profile: np.ndarray | None = field(repr=False)
    moments: np.ndarray = field(repr=False)
    contact_fraction: float
    mean_gap: float
    conductance: float
    effective_gap: float
    percolating: bool
    h_rms: float
    converged: bool
    iterations: int
    residual: float
    max_penetration: float
    seconds: float


def _image_curvature(scene):
    if scene.geometry != "cylinder":
        return math.nan
    return image_curvature(scene.E_star, scene.load, scene.radius, scene.grid.lx)


def _undeformed_gap(scene, heights):
    if scene.geometry == "cylinder":
        kappa = _image_curvature(scene) if scene.image_correction else 0.0
        shape = cylinder_gap(scene.grid, scene.radius, kappa)
    elif scene.geometry == "sphere":
        shape = sphere_gap(scene.grid, scene.radius)
    else:
        shape = np.zeros(scene.grid.shape)
    return shape - heights


def run_realization(seed: int | np.random.SeedSequence | None, scene: Scene) -> Realization:
    """Draw one surface from ``seed``, solve the contact (and the flow for a flat scene).

    Parameters
    ----------
    seed : int, numpy.random.SeedSequence or None
        Seed of the surface (:func:`~fastline.bem.surface.random_surface`).
    scene : Scene

    Returns
    -------
    Realization
    """
    if not isinstance(scene, Scene):
        raise TypeError(f"scene must be a fastline.bem.Scene, got {type(scene).__name__}")
    start = time.perf_counter()
    heights = _heights(scene, seed)
    res = solve_contact(
        _undeformed_gap(scene, heights),
        scene.grid,
        scene.E_star,
        scene.total_load,
        periodic=scene.periodic,
        tol=scene.tol,
        max_iter=scene.max_iter,
    )
    profile, (conductance, effective_gap, percolating) = _profile_and_flow(scene, res)
    return Realization(
        seed=seed,
        profile=profile,
        moments=_moments(scene, res.pressure),
        contact_fraction=res.contact_fraction,
        mean_gap=float(res.gap.mean()),
        conductance=conductance,
        effective_gap=effective_gap,
        percolating=percolating,
        h_rms=float(np.sqrt(np.mean(heights**2))),
        converged=res.converged,
        iterations=res.iterations,
        residual=res.residual,
        max_penetration=res.max_penetration,
        seconds=time.perf_counter() - start,
    )


def _heights(scene: Scene, seed: int | np.random.SeedSequence | None) -> np.ndarray:
    """The realisation's surface heights [m] (zero for a smooth scene)."""
    if scene.psd is None:
        return np.zeros(scene.grid.shape)
    return random_surface(scene.psd, scene.grid, seed, amplitudes=scene.amplitudes).heights


def _moments(scene: Scene, p: np.ndarray) -> np.ndarray:
    """``(sum p, sum x p, sum y p, sum (x^2 + y^2) p)`` over the cells [Pa, Pa m, Pa m, Pa m^2]."""
    x, y = scene.grid.x[:, None], scene.grid.y[None, :]
    return np.array([p.sum(), (x * p).sum(), (y * p).sum(), ((x * x + y * y) * p).sum()])


def _profile_and_flow(
    scene: Scene, res: ContactResult
) -> tuple[np.ndarray | None, tuple[float, float, bool]]:
    """The realisation's profile (cylinder: pressure averaged along y; sphere: over rings;
    flat: None) [Pa] and ``(conductance, effective_gap, percolating)`` of the Reynolds flow
    through the gap (flat only; else NaN, NaN, False)."""
    p = res.pressure
    if scene.geometry == "cylinder":
        return p.mean(axis=1), (math.nan, math.nan, False)
    if scene.geometry == "sphere":
        idx, _, count = ring_index(scene, 1)
        sums = np.bincount(idx.ravel(), weights=p.ravel(), minlength=count.size + 1)
        return sums[: count.size] / count, (math.nan, math.nan, False)
    flow = reynolds_flow(
        res.gap, scene.grid.dx, scene.grid.dy, viscosity=scene.viscosity,
        conductance_tol=CONDUCTANCE_TOL,
    )  # fmt: skip
    return None, (flow.conductance, flow.effective_gap, flow.percolating)


# ---- ensembles ---------------------------------------------------------------------------------
@dataclass(frozen=True)
class ProfileEnsemble:
    """Ensemble nominal pressure of a rough cylinder (``coordinate`` = x) or sphere (= r).

    Every ``*_error`` is a standard error over realisations (module docstring). Units: m, Pa.

    Attributes
    ----------
    geometry : str
    coordinate : ndarray
        Cell-centre x [m] (cylinder) or mean ring radius r [m] (sphere).
    pressure, pressure_error : ndarray
        ``p_bar`` and its standard error [Pa].
    p0, s, fwhm, w_over_s : float
        Of ``p_bar`` [Pa, m, m, -].
    p0_error, s_error, fwhm_error, w_over_s_error : float
    p0_hertz, a_hertz, delta : float
        Smooth-contact references [Pa, m, m].
    alpha : float
        ``h_rms / delta`` (``psd.h_rms``; 0 if smooth).
    bin_width : float
        Width of the bins (cylinder) or rings (sphere) of ``pressure`` [m] (module docstring).
    contact_width : float
        The contact's width ``W`` [m] the bins follow (:func:`~fastline.bem.scene.contact_width`:
        4 s for a cylinder, 2 sqrt(5) s for a sphere; Hertz 2a).
    narrow : str
        Why the contact is too narrow to compare widths
        (:func:`~fastline.bem.scene.narrow_contact`), or ``""``.
    image_curvature : float
        Cylinder: ``kappa`` of :func:`~fastline.bem.contact.image_curvature` (the relative
        shift of ``s`` by the periodic images is ``-kappa/2`` uncorrected, ``O(kappa^2)`` with
        ``Scene.image_correction``); NaN for the sphere.
    p0_ratio, p0_ratio_error : float
        ``p0 / p0_hertz``.
    realizations : int
    converged : bool
        All realisations converged.
    iterations : ndarray of int
        CCG iterations per realisation.
    seconds : ndarray
        Wall time per realisation [s].
    scene : Scene
    """

    geometry: str
    coordinate: np.ndarray = field(repr=False)
    pressure: np.ndarray = field(repr=False)
    pressure_error: np.ndarray = field(repr=False)
    p0: float
    p0_error: float
    s: float
    s_error: float
    fwhm: float
    fwhm_error: float
    w_over_s: float
    w_over_s_error: float
    p0_hertz: float
    a_hertz: float
    delta: float
    alpha: float
    bin_width: float
    contact_width: float
    narrow: str
    image_curvature: float
    p0_ratio: float
    p0_ratio_error: float
    realizations: int
    converged: bool
    iterations: np.ndarray = field(repr=False)
    seconds: np.ndarray = field(repr=False)
    scene: Scene = field(repr=False)


@dataclass(frozen=True)
class FlatEnsemble:
    """Ensemble contact and leakage of a nominally flat interface (means and standard errors).

    Attributes
    ----------
    contact_fraction, contact_fraction_error : float
        Fraction of the nominal area in contact.
    mean_gap, mean_gap_error : float
        Mean gap [m].
    conductance, conductance_error : float
        Reynolds conductance ``Q Lx / (Ly dP)`` [m^3/(Pa s)] (:mod:`fastline.bem.flow`).
    effective_gap, effective_gap_error : float
        ``(12 eta conductance)^(1/3)`` of the mean conductance [m], comparable with Persson's
        critical-junction gap ``u_c`` (THEORY 8.3); error by the delta method.
    percolating_fraction : float
        Fraction of realisations with an open path across x.
    realizations, converged, iterations, seconds, scene
        As :class:`ProfileEnsemble`.
    """

    contact_fraction: float
    contact_fraction_error: float
    mean_gap: float
    mean_gap_error: float
    conductance: float
    conductance_error: float
    effective_gap: float
    effective_gap_error: float
    percolating_fraction: float
    realizations: int
    converged: bool
    iterations: np.ndarray = field(repr=False)
    seconds: np.ndarray = field(repr=False)
    scene: Scene = field(repr=False)


def _mean_se(values):
    v = np.asarray(values, dtype=np.float64)
    if v.size < 2:
        return float(v.mean()), math.nan
    return float(v.mean()), float(v.std(ddof=1) / math.sqrt(v.size))


def _line_bins(scene, m):
    """Bin of every cell (bins of ``m`` cells centred on x = 0), the cells in each bin, the
    bin centres [m] and the bins' cells.

    ``m`` is lowered to the parity of ``nx`` (or is 1) so that the bins are symmetric about
    the axis."""
    grid = scene.grid
    if m > 1 and m % 2 != grid.nx % 2:
        m -= 1
    if m == 1:
        return np.arange(grid.nx), np.ones(grid.nx, dtype=np.int64), grid.x, 1
    offset = np.arange(grid.nx) - 0.5 * (grid.nx - 1)
    k = np.rint(offset / m).astype(np.int64)
    k -= k.min()
    centres = (np.arange(k.max() + 1) + np.rint(offset[0] / m)) * m * grid.dx
    return k, np.bincount(k), centres, m


def _line_s(x, profile, dx):
    """Standard deviation [m] of a profile about its centroid (cell-exact)."""
    m0 = profile.sum()
    xc = np.dot(x, profile) / m0
    return math.sqrt(np.dot((x - xc) ** 2, profile) / m0 + dx**2 / 12.0)


def _line_statistic(scene, k, count, centres):
    """``profile -> (p0, s, w, w/s)`` on the bins ``k`` (:func:`_line_bins`)."""
    grid = scene.grid
    x = grid.x

    def stat(profile):
        binned = np.bincount(k, weights=profile) / count
        s = _line_s(x, profile, grid.dx)
        xc = np.dot(x, profile) / profile.sum()
        p0 = _profile.central_peak(x - xc, profile, s)
        left, right = _profile.half_crossings(centres, binned, 0.5 * p0)
        return p0, s, right - left, (right - left) / s

    return stat


def _sphere_s(m, dx, dy):
    """Per-axis standard deviation [m] from the moments of a pressure map."""
    var = 0.5 * (m[3] / m[0] - (m[1] ** 2 + m[2] ** 2) / m[0] ** 2) + (dx * dx + dy * dy) / 24
    return math.sqrt(var)


def _sphere_statistic(r, count, dx, dy):
    nring = r.size

    def stat(sample):
        profile, m = sample[:nring], sample[nring:]
        s = _sphere_s(m, dx, dy)
        # radial window 0.75 sqrt(2) s: the same fraction of the profile as on a line
        p0 = _profile.central_peak(r / math.sqrt(2.0), profile, s, weights=count)
        _, r_half = _profile.half_crossings(r, profile, 0.5 * p0)
        return p0, s, 2.0 * r_half, 2.0 * r_half / s

    return stat


def _merge_rings(scene, profiles, cells):
    """One-cell ring averages (each row of ``profiles``) merged into rings of ``cells`` cells:
    (merged profiles, mean radii, cell counts) as :func:`ring_index` ``(scene, cells)``."""
    _, rmean, count = ring_index(scene, cells)
    _, _, count1 = ring_index(scene, 1)
    ring = np.arange(count1.size) // cells
    keep = ring < count.size
    sums = np.stack([np.bincount(ring[keep], weights=(p * count1)[keep]) for p in profiles])
    return sums[:, : count.size] / count, rmean, count


def _binned(scene, runs):
    """(samples of the jackknife, statistic, bin centres, binned profiles, bin width, s) with
    the bins of the contact's width (:func:`~fastline.bem.scene.cells_per_bin`)."""
    grid = scene.grid
    profiles = np.array([r.profile for r in runs])
    if scene.geometry == "cylinder":
        s = _line_s(grid.x, profiles.mean(axis=0), grid.dx)
        k, count, centres, cells = _line_bins(scene, cells_per_bin(scene, s))
        stat = _line_statistic(scene, k, count, centres)
        binned = np.stack([np.bincount(k, weights=p) / count for p in profiles])
        return profiles, stat, centres, binned, cells * grid.dx, s
    moments = np.array([r.moments for r in runs])
    s = _sphere_s(moments.mean(axis=0), grid.dx, grid.dy)
    cells = cells_per_bin(scene, s)
    binned, coord, count = _merge_rings(scene, profiles, cells)
    samples = np.concatenate([binned, moments], axis=1)
    stat = _sphere_statistic(coord, count.astype(np.float64), grid.dx, grid.dy)
    return samples, stat, coord, binned, cells * grid.dx, s


def _profile_ensemble(scene, runs):
    samples, stat, coord, profiles, bin_width, s_mean = _binned(scene, runs)
    (p0, s, w, ws), (p0_e, s_e, w_e, ws_e) = _profile.jackknife(samples, stat)
    n = len(runs)
    err = profiles.std(axis=0, ddof=1) / math.sqrt(n) if n > 1 else np.full(coord.size, np.nan)
    narrow = narrow_contact(scene, s_mean)
    if narrow:
        warnings.warn(narrow, NarrowContactWarning, stacklevel=3)
    p0_h, a_h, delta = scene.hertz()
    h_rms = 0.0 if scene.psd is None else scene.psd.h_rms
    return ProfileEnsemble(
        geometry=scene.geometry,
        coordinate=coord,
        pressure=profiles.mean(axis=0),
        pressure_error=err,
        p0=float(p0),
        p0_error=float(p0_e),
        s=float(s),
        s_error=float(s_e),
        fwhm=float(w),
        fwhm_error=float(w_e),
        w_over_s=float(ws),
        w_over_s_error=float(ws_e),
        p0_hertz=p0_h,
        a_hertz=a_h,
        delta=delta,
        alpha=h_rms / delta,
        bin_width=bin_width,
        contact_width=contact_width(scene, s_mean),
        narrow=narrow,
        image_curvature=_image_curvature(scene),
        p0_ratio=float(p0 / p0_h),
        p0_ratio_error=float(p0_e / p0_h),
        realizations=n,
        converged=all(r.converged for r in runs),
        iterations=np.array([r.iterations for r in runs]),
        seconds=np.array([r.seconds for r in runs]),
        scene=scene,
    )


def _flat_ensemble(scene, runs):
    cf, cf_e = _mean_se([r.contact_fraction for r in runs])
    gap, gap_e = _mean_se([r.mean_gap for r in runs])
    sig, sig_e = _mean_se([r.conductance for r in runs])
    eta = scene.viscosity
    u_eff = (12.0 * eta * sig) ** (1.0 / 3.0)
    u_eff_e = u_eff / (3.0 * sig) * sig_e if sig > 0.0 else math.nan
    return FlatEnsemble(
        contact_fraction=cf,
        contact_fraction_error=cf_e,
        mean_gap=gap,
        mean_gap_error=gap_e,
        conductance=sig,
        conductance_error=sig_e,
        effective_gap=u_eff,
        effective_gap_error=u_eff_e,
        percolating_fraction=float(np.mean([r.percolating for r in runs])),
        realizations=len(runs),
        converged=all(r.converged for r in runs),
        iterations=np.array([r.iterations for r in runs]),
        seconds=np.array([r.seconds for r in runs]),
        scene=scene,
    )


@contextmanager
def ensemble_executor(
    executor: ExecutorLike = None, workers: int | None = None, tasks: int = 2
) -> Iterator[Executor | None]:
    """Where the realisations run, chosen as :func:`fastline.sweep` chooses (a context
    manager: what it starts, it shuts down on exit).

    Parameters
    ----------
    executor : None, "serial", str, concurrent.futures.Executor or dask Client
        None: a local pool of ``workers`` processes (spawned) if ``workers`` > 1, else this
        process. ``"serial"``: this process, in order. A dask scheduler address
        (``"tcp://host:8786"``): a ``dask.distributed`` client is connected for the duration
        (needs the ``dask`` extra). An executor (``ProcessPoolExecutor``,
        ``ThreadPoolExecutor``, ``client.get_executor()``) or a ``distributed.Client``: used as
        given and left running.
    workers : int, optional
        Processes of the local pool (only with ``executor=None``; default: this process,
        unlike :func:`fastline.sweep`, whose default pool has one process per CPU).
    tasks : int
        Realisations to run (one task: no pool is started).

    Yields
    ------
    concurrent.futures.Executor or None
        None means in this process; pass it on as ``run_ensemble(..., executor=...)``.
    """

    if executor is None and workers is None:
        executor = "serial"
    engine = open_engine(executor, workers, tasks)
    try:
        yield engine.executor
    finally:
        close_engine(engine)


def _map(executor, scene, seeds, bar) -> list:
    """``run_realization`` over the seeds, results in seed order (``submit``, not ``map``: a
    dask executor's ``map`` needs sized iterables and batches differently); ``bar`` advances
    as each realisation completes."""
    if executor is None:
        out = []
        for s in seeds:
            out.append(run_realization(s, scene))
            bar.update(1)
        return out
    futures = [executor.submit(run_realization, s, scene) for s in seeds]
    try:
        if all(isinstance(f, Future) for f in futures):
            for _ in as_completed(futures):
                bar.update(1)
        return [f.result() for f in futures]
    finally:
        for f in futures:
            f.cancel()


def progress_bar(progress: bool | None, total: int, desc: str) -> tqdm:
    """A tqdm bar over realisations on stderr (None: only when stderr is a terminal)."""
    if progress is not None and not isinstance(progress, (bool, np.bool_)):
        raise TypeError(f"progress must be True, False or None, got {type(progress).__name__}")
    disable = None if progress is None else not progress
    return tqdm(
        total=total, desc=desc, unit="realisation", file=sys.stderr, disable=disable, leave=False
    )


def run_ensemble(
    scene: Scene,
    realizations: int = 8,
    seed: int | np.random.SeedSequence = 0,
    *,
    executor: ExecutorLike = None,
    workers: int | None = None,
    progress: bool | None = None,
    desc: str = "BEM",
) -> ProfileEnsemble | FlatEnsemble:
    """Run ``realizations`` independent realisations of ``scene`` and average them.

    Parameters
    ----------
    scene : Scene
    realizations : int
        Number of surfaces, >= 1 (>= 2 for error bars); 1 for a smooth scene is enough.
    seed : int or numpy.random.SeedSequence
        Root seed; realisation k uses ``SeedSequence(seed).spawn(realizations)[k]``, so results
        do not depend on the executor or the order of execution.
    executor : None, "serial", str, concurrent.futures.Executor or dask Client
        Where the realisations run, as for :func:`fastline.sweep`
        (:func:`ensemble_executor`): default this process; a local process pool with
        ``workers``; a dask scheduler address or Client; any executor (a process pool or a
        dask cluster needs the scene to pickle: the package's spectra do).
    workers : int, optional
        Processes of a local pool made and shut down here (``executor=None`` only).
    progress : bool or None
        A tqdm progress bar over the realisations on stderr, advanced as each completes
        (None, the default: only when stderr is a terminal).
    desc : str
        The bar's label.

    Returns
    -------
    ProfileEnsemble or FlatEnsemble
        Cylinder and sphere: :class:`ProfileEnsemble`; flat: :class:`FlatEnsemble`.

    Raises
    ------
    ValueError, TypeError
        Before any work, for a bad scene, count, seed, ``workers`` or ``executor``.
    """
    if not isinstance(scene, Scene):
        raise TypeError(f"scene must be a fastline.bem.Scene, got {type(scene).__name__}")
    n = integer("realizations", realizations, 1)
    if isinstance(seed, np.random.SeedSequence):
        root = seed
    else:
        root = np.random.SeedSequence(integer("seed", seed, 0))
    seeds = root.spawn(n)
    with progress_bar(progress, n, desc) as bar, ensemble_executor(executor, workers, n) as ex:
        runs = _map(ex, scene, seeds, bar)
    if scene.geometry == "flat":
        return _flat_ensemble(scene, runs)
    return _profile_ensemble(scene, runs)
