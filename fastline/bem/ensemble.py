"""Ensembles of BEM realisations: the nominal pressure of a rough cylinder or sphere, and the
contact and leakage of a nominally flat interface, with error bars over realisations.

A :class:`Scene` holds everything one realisation needs (spectrum, material, geometry, load,
grid, solver settings).  :func:`run_realization` ``(seed, scene)`` is a plain module-level
function: it draws the surface from ``seed``, solves the contact (and for a flat scene the
Reynolds flow through the gap) and returns a small picklable :class:`Realization`, so an
ensemble runs wherever :func:`fastline.sweep` runs its tasks (:func:`run_ensemble`
``(..., executor=..., workers=...)``: this process, a local process pool, a dask cluster or any
:class:`concurrent.futures.Executor`; :func:`ensemble_executor`).

Statistics (:func:`run_ensemble`):

* cylinder: ``p_bar(x)``, the pressure averaged along the axis y, over bins of ``x`` of width
  ``Scene.bin_width`` and over realisations, with the standard error of the mean over
  realisations in each bin; ``s`` (standard deviation about the centroid, cell-exact) and
  ``p0`` (peak of the even quartic fitted to the central ``|x - x_c| <= 0.75 s`` of the unbinned
  mean profile: the largest bin of a noisy profile is biased upward) and ``w`` (FWHM of the
  binned ``p_bar``);
* sphere: ``p_bar(r)`` averaged over rings of width ``Scene.bin_width`` about the sphere's axis
  and over realisations; ``p0`` from the same central fit over the rings with
  ``r <= 0.75 sqrt(2) s``, ``w = 2 r_half``, and ``s`` the per-axis standard deviation
  ``s^2 = <|r - r_c|^2> / 2`` of the mean pressure map (a Gaussian ``exp(-r^2 / 2 s^2)``
  has standard deviation ``s``);
  Hertz: ``s = a / sqrt(5)``, ``w/s = sqrt(15)``;
* flat: contact-area fraction, mean gap, and the Reynolds conductance and effective gap
  (:mod:`fastline.bem.flow`), means with standard errors.

The error bars of ``p0``, ``s``, ``w`` and ``w/s`` are jackknife standard errors over
realisations (B. Efron, C. Stein, Ann. Stat. 9, 586 (1981)), the right tool for a nonlinear
functional of a mean profile; they need at least two realisations (NaN with one).
"""

from __future__ import annotations

import math
import time
from collections.abc import Iterator
from concurrent.futures import Executor
from contextlib import contextmanager
from dataclasses import dataclass, field, replace
from typing import TYPE_CHECKING

import numpy as np
import scipy.fft

from fastline._lib.executors import close_engine, open_engine
from fastline._lib.validate import finite_scalar, integer, positive
from fastline.bem import _profile
from fastline.bem.contact import (
    DEFAULT_TOL,
    cylinder_gap,
    image_curvature,
    solve_contact,
    sphere_gap,
)
from fastline.bem.flow import reynolds_flow
from fastline.bem.surface import Amplitudes, Grid, random_surface, spectral_grid
from fastline.theory.spectra import PSD

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
    "with_grid",
]

#: u0 / h_rms of the exponential law, used only to size default grids (paper: ~0.4).
_GAMMA_U = 0.4
#: Default cells across the profile's width scale, and the cell's width in width scales.
_CELLS_PER_WIDTH = 64
_IMAGE_SPACING = 4.0  # cylinder: Lx = 4 widths (8 a): Hertz s +2e-5 with the image correction
_PATCH_WIDTHS = 4.0  # sphere (isolated patch): L = 4 widths


@dataclass(frozen=True)
class Scene:
    """One BEM scene: what :func:`run_realization` needs besides the seed.

    Build it with :func:`line_contact_scene`, :func:`point_contact_scene` or
    :func:`flat_contact_scene`, which validate the inputs and size the grid.

    Attributes
    ----------
    geometry : {"cylinder", "sphere", "flat"}
    psd : PSD or None
        Roughness spectrum (None: smooth, for checks against Hertz).
    E_star : float
        Effective modulus [Pa].
    load : float
        Cylinder: load per unit length [N/m]; sphere: force [N]; flat: nominal pressure [Pa].
    radius : float
        Cylinder or sphere radius [m] (NaN for flat).
    grid : Grid
    periodic : bool
        Periodic cell (cylinder, flat) or isolated patch (sphere).
    amplitudes : str
        Surface synthesis (:func:`~fastline.bem.surface.random_surface`).
    tol : float
    max_iter : int
        CCG settings (:func:`~fastline.bem.contact.solve_contact`).
    viscosity : float
        Fluid viscosity for the flat scene's flow [Pa s].
    bin_width : float
        Width of the x bins (cylinder) or rings (sphere) of the reported ``p_bar`` [m], from
        which ``p0`` and ``w`` are read (``s`` uses every cell); 0 means one cell.  The
        nominal pressure is defined on scales above the roughness: the builders default to a
        quarter of the longest wavelength ``2 pi / q0`` (one cell if smooth).
    image_correction : bool
        Cylinder: cancel the leading effect of the periodic images in x
        (:func:`~fastline.bem.contact.image_curvature`).
    """

    geometry: str
    psd: PSD | None
    E_star: float
    load: float
    radius: float
    grid: Grid
    periodic: bool = True
    amplitudes: Amplitudes = "fixed"
    tol: float = DEFAULT_TOL
    max_iter: int = 5000
    viscosity: float = 1e-3
    bin_width: float = 0.0
    image_correction: bool = True

    @property
    def total_load(self) -> float:
        """Load on the grid [N]."""
        if self.geometry == "cylinder":
            return self.load * self.grid.ly
        if self.geometry == "flat":
            return self.load * self.grid.lx * self.grid.ly
        return self.load

    def hertz(self) -> tuple[float, float, float]:
        """Smooth-contact ``(p0, a, delta)`` [Pa, m, m] (NaN for flat): THEORY sections 5, 9."""
        E, R, f = self.E_star, self.radius, self.load
        if self.geometry == "cylinder":
            delta = 4.0 * f / (math.pi * E)
            return math.sqrt(E * f / (math.pi * R)), math.sqrt(R * delta), delta
        if self.geometry == "sphere":
            a = (3.0 * f * R / (4.0 * E)) ** (1.0 / 3.0)
            return 3.0 * f / (2.0 * math.pi * a * a), a, a * a / R
        return math.nan, math.nan, math.nan


def _check_common(psd, E_star, load, unit):
    if psd is not None and not isinstance(psd, PSD):
        raise TypeError(f"psd must be a fastline PSD or None, got {type(psd).__name__}")
    return positive("E_star", E_star, "Pa"), positive("load", load, unit)


def _check_settings(grid, amplitudes, tol, max_iter):
    if grid is not None and not isinstance(grid, Grid):
        raise TypeError(f"grid must be a fastline.bem.Grid or None, got {type(grid).__name__}")
    if amplitudes not in ("fixed", "gaussian"):
        raise ValueError(f"amplitudes must be 'fixed' or 'gaussian', got {amplitudes!r}")
    tol = positive("tol", tol)
    if tol >= 0.1:
        raise ValueError(f"tol must lie in (0, 0.1), got {tol!r}")
    return tol, integer("max_iter", max_iter, 1)


def _width_scale(psd, radius, a_hertz):
    """A length covering the profile: Hertz width 2a, or 4 Gaussian-limit s = sqrt(R u0)."""
    if psd is None:
        return 2.0 * a_hertz
    return max(2.0 * a_hertz, 4.0 * math.sqrt(radius * _GAMMA_U * psd.h_rms))


def _cell_size(psd, width, points_per_wavelength):
    dx = width / _CELLS_PER_WIDTH
    if psd is not None:
        dx = min(dx, 2.0 * math.pi / (psd.q1 * points_per_wavelength))
    return dx


def _fast(n):
    return int(scipy.fft.next_fast_len(max(int(n), 2), real=True))


def line_contact_scene(
    psd: PSD | None,
    E_star: float,
    radius: float,
    load: float,
    *,
    grid: Grid | None = None,
    points_per_wavelength: float = 4.0,
    periods: float = 2.0,
    bin_width: float | None = None,
    image_correction: bool = True,
    amplitudes: Amplitudes = "fixed",
    tol: float = DEFAULT_TOL,
    max_iter: int = 5000,
) -> Scene:
    """A rigid cylinder (axis y) on a rough half-space, periodic along its axis.

    Default grid: ``dx = min(2 pi / (q1 points_per_wavelength), width / 64)`` with ``width =
    max(2 a_Hertz, 4 sqrt(0.4 R h_rms))``; ``Lx = 4 width`` (with ``image_correction`` the
    periodic images in x then move the Hertz ``s`` by 2e-5; without, by
    ``-(pi^2/12)(a/Lx)^2 = -1.3 %``: :func:`~fastline.bem.contact.image_curvature`);
    ``Ly = periods * 2 pi / q0``.  Cell counts are rounded up to FFT-friendly sizes.

    Parameters
    ----------
    psd : PSD or None
        Roughness spectrum (None: smooth cylinder).
    E_star : float
        Effective modulus [Pa], > 0.
    radius : float
        Cylinder radius ``R`` [m], > 0.
    load : float
        Load per unit length ``f_N`` [N/m], > 0.
    grid : Grid, optional
        Override the default grid.
    points_per_wavelength, periods : float
        Default-grid resolution of ``2 pi / q1`` (>= 2) and ``Ly`` in ``2 pi / q0`` (> 0).
    bin_width : float, optional
        Bin width of ``p_bar`` [m], >= 0 (:class:`Scene`; default ``pi / (2 q0)``).
    image_correction : bool
        Cancel the periodic images' curvature (default True; :class:`Scene`).
    amplitudes, tol, max_iter
        Passed to the surface generator and the contact solver.
    """
    E_star, load = _check_common(psd, E_star, load, "N/m")
    radius = positive("radius", radius, "m")
    tol, max_iter = _check_settings(grid, amplitudes, tol, max_iter)
    if grid is None:
        ppw, periods = _grid_options(points_per_wavelength, periods)
        a = math.sqrt(4.0 * radius * load / (math.pi * E_star))
        width = _width_scale(psd, radius, a)
        dx = _cell_size(psd, width, ppw)
        nx = _fast(math.ceil(_IMAGE_SPACING * width / dx))
        ly = 8.0 * dx if psd is None else periods * 2.0 * math.pi / psd.q0
        ny = _fast(math.ceil(ly / dx - 1e-9))
        grid = Grid(nx, ny, dx, ly / ny)
    return Scene(
        "cylinder",
        psd,
        E_star,
        load,
        radius,
        grid,
        True,
        amplitudes,
        tol,
        max_iter,
        bin_width=_bin_width(psd, bin_width),
        image_correction=_flag("image_correction", image_correction),
    )


def point_contact_scene(
    psd: PSD | None,
    E_star: float,
    radius: float,
    load: float,
    *,
    grid: Grid | None = None,
    points_per_wavelength: float = 4.0,
    bin_width: float | None = None,
    amplitudes: Amplitudes = "fixed",
    tol: float = DEFAULT_TOL,
    max_iter: int = 5000,
) -> Scene:
    """A rigid sphere on a rough half-space: an isolated patch (no periodic images).

    Default grid: square cells as for :func:`line_contact_scene` (``width = max(2 a_Hertz,
    4 sqrt(0.4 R h_rms))``), patch ``4 width`` on a side; the rough surface is periodic on the
    patch.  The pressure must vanish well inside the patch (check ``p_bar`` at the rim).

    Parameters
    ----------
    psd : PSD or None
        Roughness spectrum (None: smooth sphere).
    E_star : float
        Effective modulus [Pa], > 0.
    radius : float
        Sphere radius ``R`` [m], > 0.
    load : float
        Normal force ``F_N`` [N], > 0.
    grid, points_per_wavelength, bin_width, amplitudes, tol, max_iter
        As :func:`line_contact_scene` (``bin_width``: ring width).
    """
    E_star, load = _check_common(psd, E_star, load, "N")
    radius = positive("radius", radius, "m")
    tol, max_iter = _check_settings(grid, amplitudes, tol, max_iter)
    if grid is None:
        ppw, _ = _grid_options(points_per_wavelength, 1.0)
        a = (3.0 * load * radius / (4.0 * E_star)) ** (1.0 / 3.0)
        width = _width_scale(psd, radius, a)
        dx = _cell_size(psd, width, ppw)
        n = _fast(math.ceil(_PATCH_WIDTHS * width / dx))
        grid = Grid(n, n, dx, dx)
    return Scene(
        "sphere",
        psd,
        E_star,
        load,
        radius,
        grid,
        False,
        amplitudes,
        tol,
        max_iter,
        bin_width=_bin_width(psd, bin_width),
    )


def flat_contact_scene(
    psd: PSD,
    E_star: float,
    pressure: float,
    *,
    grid: Grid | None = None,
    points_per_wavelength: float = 4.0,
    periods: float = 2.0,
    viscosity: float = 1e-3,
    amplitudes: Amplitudes = "fixed",
    tol: float = DEFAULT_TOL,
    max_iter: int = 5000,
) -> Scene:
    """A nominally flat rigid body on a rough half-space under a uniform nominal pressure,
    periodic in x and y; each realisation also solves the Reynolds flow across x.

    Default grid: :func:`~fastline.bem.surface.spectral_grid` ``(psd, points_per_wavelength,
    periods)``.

    Parameters
    ----------
    psd : PSD
        Roughness spectrum (required).
    E_star : float
        Effective modulus [Pa], > 0.
    pressure : float
        Nominal contact pressure [Pa], > 0.
    viscosity : float
        Fluid viscosity [Pa s], > 0 (the effective gap does not depend on it).
    grid, points_per_wavelength, periods, amplitudes, tol, max_iter
        As :func:`line_contact_scene`.
    """
    if psd is None:
        raise ValueError("psd is required for a flat contact (a smooth flat is trivial)")
    E_star, pressure = _check_common(psd, E_star, pressure, "Pa")
    viscosity = positive("viscosity", viscosity, "Pa s")
    tol, max_iter = _check_settings(grid, amplitudes, tol, max_iter)
    if grid is None:
        ppw, periods = _grid_options(points_per_wavelength, periods)
        grid = spectral_grid(psd, points_per_wavelength=ppw, periods=periods)
    return Scene(
        "flat", psd, E_star, pressure, math.nan, grid, True, amplitudes, tol, max_iter, viscosity
    )


def _flag(name, value):
    if not isinstance(value, (bool, np.bool_)):
        raise TypeError(f"{name} must be a bool, got {type(value).__name__}")
    return bool(value)


def _bin_width(psd, bin_width):
    if bin_width is not None:
        out = finite_scalar("bin_width", bin_width)
        if out < 0.0:
            raise ValueError(f"bin_width must be >= 0 m (allowed range [0, inf)), got {out!r}")
        return out
    return 0.0 if psd is None else 0.5 * math.pi / psd.q0


def _grid_options(points_per_wavelength, periods):
    ppw = positive("points_per_wavelength", points_per_wavelength)
    if ppw < 2.0:
        raise ValueError(f"points_per_wavelength must be >= 2 (Nyquist), got {ppw!r}")
    return ppw, positive("periods", periods)


# ---- one realisation ---------------------------------------------------------------------------
@dataclass(frozen=True)
class Realization:
    """Per-realisation output of :func:`run_realization` (small and picklable).

    Attributes
    ----------
    seed
        The seed it was drawn from.
    profile : ndarray or None
        Cylinder: pressure averaged along y, shape (nx,) [Pa]; sphere: ring-averaged pressure
        [Pa]; flat: None.
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


def _cells_per_bin(scene):
    return max(1, int(round(scene.bin_width / scene.grid.dx)))


def _ring_index(scene):
    """Ring number ``floor(r / width)`` of every cell (width: a whole number of cells), the
    mean radius of each full ring inside the patch's inscribed circle, and their cell counts."""
    grid = scene.grid
    width = _cells_per_bin(scene) * grid.dx
    x, y = grid.x[:, None], grid.y[None, :]
    r = np.sqrt(x * x + y * y)
    nring = max(int(0.5 * min(grid.lx, grid.ly) / width), 1)
    idx = np.minimum((r / width).astype(np.int64), nring)
    count = np.bincount(idx.ravel(), minlength=nring + 1)[:nring]
    rmean = np.bincount(idx.ravel(), weights=r.ravel(), minlength=nring + 1)[:nring] / count
    return idx, rmean, count


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
    grid = scene.grid
    if scene.psd is None:
        heights = np.zeros(grid.shape)
    else:
        heights = random_surface(scene.psd, grid, seed, amplitudes=scene.amplitudes).heights
    res = solve_contact(
        _undeformed_gap(scene, heights),
        grid,
        scene.E_star,
        scene.total_load,
        periodic=scene.periodic,
        tol=scene.tol,
        max_iter=scene.max_iter,
    )
    p = res.pressure
    x, y = grid.x[:, None], grid.y[None, :]
    moments = np.array([p.sum(), (x * p).sum(), (y * p).sum(), ((x * x + y * y) * p).sum()])
    profile = None
    conductance = effective_gap = math.nan
    percolating = False
    if scene.geometry == "cylinder":
        profile = p.mean(axis=1)
    elif scene.geometry == "sphere":
        idx, _, count = _ring_index(scene)
        sums = np.bincount(idx.ravel(), weights=p.ravel(), minlength=count.size + 1)
        profile = sums[: count.size] / count
    else:
        flow = reynolds_flow(res.gap, grid.dx, grid.dy, viscosity=scene.viscosity)
        conductance, effective_gap, percolating = (
            flow.conductance,
            flow.effective_gap,
            flow.percolating,
        )
    return Realization(
        seed=seed,
        profile=profile,
        moments=moments,
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


def _line_bins(scene):
    """Bin of every cell (bins of ``m`` cells centred on x = 0) and the bin centres [m].

    ``m`` has the parity of ``nx`` (or is 1) so that the bins are symmetric about the axis."""
    grid = scene.grid
    m = _cells_per_bin(scene)
    if m > 1 and m % 2 != grid.nx % 2:
        m += 1
    if m == 1:
        return np.arange(grid.nx), np.ones(grid.nx, dtype=np.int64), grid.x
    offset = np.arange(grid.nx) - 0.5 * (grid.nx - 1)
    k = np.rint(offset / m).astype(np.int64)
    k -= k.min()
    centres = (np.arange(k.max() + 1) + np.rint(offset[0] / m)) * m * grid.dx
    return k, np.bincount(k), centres


def _line_statistic(scene):
    grid = scene.grid
    x = grid.x
    k, count, centres = _line_bins(scene)

    def stat(profile):
        binned = np.bincount(k, weights=profile) / count
        m0 = profile.sum()
        xc = np.dot(x, profile) / m0
        s = math.sqrt(np.dot((x - xc) ** 2, profile) / m0 + grid.dx**2 / 12.0)
        p0 = _profile.central_peak(x - xc, profile, s)
        left, right = _profile.half_crossings(centres, binned, 0.5 * p0)
        return p0, s, right - left, (right - left) / s

    return stat, lambda profiles: np.stack([np.bincount(k, weights=p) / count for p in profiles])


def _sphere_statistic(r, count, dx, dy):
    nring = r.size

    def stat(sample):
        profile, m = sample[:nring], sample[nring:]
        var = 0.5 * (m[3] / m[0] - (m[1] ** 2 + m[2] ** 2) / m[0] ** 2) + (dx * dx + dy * dy) / 24
        s = math.sqrt(var)
        # radial window 0.75 sqrt(2) s: the same fraction of the profile as on a line
        p0 = _profile.central_peak(r / math.sqrt(2.0), profile, s, weights=count)
        _, r_half = _profile.half_crossings(r, profile, 0.5 * p0)
        return p0, s, 2.0 * r_half, 2.0 * r_half / s

    return stat


def _profile_ensemble(scene, runs):
    grid = scene.grid
    profiles = np.array([r.profile for r in runs])
    if scene.geometry == "cylinder":
        stat, binner = _line_statistic(scene)
        samples = profiles
        coord = _line_bins(scene)[2]
        profiles = binner(profiles)
    else:
        _, coord, count = _ring_index(scene)
        samples = np.concatenate([profiles, np.array([r.moments for r in runs])], axis=1)
        stat = _sphere_statistic(coord, count.astype(np.float64), grid.dx, grid.dy)
    (p0, s, w, ws), (p0_e, s_e, w_e, ws_e) = _profile.jackknife(samples, stat)
    n = len(runs)
    err = profiles.std(axis=0, ddof=1) / math.sqrt(n) if n > 1 else np.full(coord.size, np.nan)
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


def _map(executor, scene, seeds) -> list:
    """``run_realization`` over the seeds, results in seed order (``submit``, not ``map``: a
    dask executor's ``map`` needs sized iterables and batches differently)."""
    if executor is None:
        return [run_realization(s, scene) for s in seeds]
    futures = [executor.submit(run_realization, s, scene) for s in seeds]
    try:
        return [f.result() for f in futures]
    finally:
        for f in futures:
            f.cancel()


def run_ensemble(
    scene: Scene,
    realizations: int = 8,
    seed: int | np.random.SeedSequence = 0,
    *,
    executor: ExecutorLike = None,
    workers: int | None = None,
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
    with ensemble_executor(executor, workers, n) as ex:
        runs = _map(ex, scene, seeds)
    if scene.geometry == "flat":
        return _flat_ensemble(scene, runs)
    return _profile_ensemble(scene, runs)


def with_grid(scene: Scene, grid: Grid) -> Scene:
    """The same scene on another grid (for convergence and domain-size studies)."""
    if not isinstance(grid, Grid):
        raise TypeError(f"grid must be a fastline.bem.Grid, got {type(grid).__name__}")
    return replace(scene, grid=grid)
