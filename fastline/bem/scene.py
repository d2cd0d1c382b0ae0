"""BEM scenes: a rough cylinder, sphere or nominally flat contact (:class:`Scene`), built and
checked by :func:`line_contact_scene`, :func:`point_contact_scene` and
:func:`flat_contact_scene`, which also size the default grid; the bins (cylinder) and rings
(sphere) of a scene's reported nominal pressure (:func:`cells_per_bin`, :func:`ring_index`)
and whether its contact is too narrow to compare widths (:func:`narrow_contact`).

The bins follow the contact's own width ``W`` (the Hertz width 2a in units of the profile's
standard deviation s: ``W = 4 s`` for a cylinder, ``2 sqrt(5) s`` for a sphere, exact for
Hertz): at least :data:`BINS_ACROSS` bins across ``W``, no wider than a quarter of the longest
roughness wavelength ``2 pi / q0`` (the nominal pressure is a mean over the roughness), and
never narrower than one cell of the grid, the finest scale the BEM resolves.  The FWHM is read
by linear interpolation between bin centres ``b`` apart, which moves it by up to
``b^2 |p''| / (8 |p'|)`` at the half-maximum: for Hertz at ``b = W / 20 = a / 10`` up to 0.7 %.

Units: m, Pa; a cylinder's load in N/m, a sphere's in N, a flat contact's nominal pressure in
Pa.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np
import scipy.fft

from fastline._lib.validate import MAX_ITER_RANGE, finite_scalar, integer, positive
from fastline.bem.contact import DEFAULT_TOL
from fastline.bem.surface import Amplitudes, Grid, spectral_grid
from fastline.theory.spectra import PSD

__all__ = [
    "Scene",
    "line_contact_scene",
    "point_contact_scene",
    "flat_contact_scene",
    "with_grid",
    "cells_per_bin",
    "contact_width",
    "narrow_contact",
    "ring_index",
    "BINS_ACROSS",
    "MIN_CELLS_ACROSS",
]

_GAMMA_U = 0.4
#: Default cells across the profile's width scale, and the cell's width in width scales.
_CELLS_PER_WIDTH = 64
_IMAGE_SPACING = 4.0  # cylinder: Lx = 4 widths (8 a): Hertz s +2e-5 with the image correction
_PATCH_WIDTHS = 4.0  # sphere (isolated patch): L = 4 widths
#: Bins (cylinder) or ring widths (sphere) across the contact's width ``W``, at least, when
#: the bins follow the contact (``Scene.bin_width`` None).
BINS_ACROSS = 20
#: Fewer cells than this across ``W``: the grid does not resolve the contact's width.
MIN_CELLS_ACROSS = 10
#: The contact's width ``W`` in units of the profile's s: the Hertz width 2a (cylinder
#: s = a/2, sphere s = a/sqrt(5)); a Gaussian profile carries 95 % of the load within 4 s.
_WIDTH_PER_S = {"cylinder": 4.0, "sphere": 2.0 * math.sqrt(5.0)}


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
    bin_width : float or None
        Width of the x bins (cylinder) or rings (sphere) of the reported ``p_bar`` [m], from
        which ``w`` is read (``p0`` and ``s`` use every cell); 0 means one cell.  None (the
        default): from the contact's own width, measured on the ensemble (module docstring,
        :func:`cells_per_bin`).
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
    bin_width: float | None = None
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
    return tol, integer("max_iter", max_iter, *MAX_ITER_RANGE)


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
        Bin width of ``p_bar`` [m], >= 0 (:class:`Scene`; default None: from the contact's
        width, :func:`cells_per_bin`).
    image_correction : bool
        Cancel the periodic images' curvature (default True; :class:`Scene`).
    amplitudes, tol, max_iter
        Passed to the surface generator and the contact solver.
    """
    E_star, load = _check_common(psd, E_star, load, "N/m")
    radius = positive("radius", radius, "m")
    tol, max_iter = _check_settings(grid, amplitudes, tol, max_iter)
    if grid is None:
        grid = _line_grid(psd, E_star, radius, load, points_per_wavelength, periods)
    kw = {"bin_width": _bin_width(bin_width)}
    kw["image_correction"] = _flag("image_correction", image_correction)
    return Scene("cylinder", psd, E_star, load, radius, grid, True, amplitudes, tol, max_iter, **kw)


def _line_grid(psd, E_star, radius, load, points_per_wavelength, periods) -> Grid:
    """The default grid of :func:`line_contact_scene` (its docstring)."""
    ppw, periods = _grid_options(points_per_wavelength, periods)
    a = math.sqrt(4.0 * radius * load / (math.pi * E_star))
    width = _width_scale(psd, radius, a)
    dx = _cell_size(psd, width, ppw)
    nx = _fast(math.ceil(_IMAGE_SPACING * width / dx))
    ly = 8.0 * dx if psd is None else periods * 2.0 * math.pi / psd.q0
    ny = _fast(math.ceil(ly / dx - 1e-9))
    return Grid(nx, ny, dx, ly / ny)


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
        bin_width=_bin_width(bin_width),
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


def _bin_width(bin_width):
    if bin_width is None:
        return None
    out = finite_scalar("bin_width", bin_width)
    if out < 0.0:
        raise ValueError(f"bin_width must be >= 0 m (allowed range [0, inf)), got {out!r}")
    return out


def _grid_options(points_per_wavelength, periods):
    ppw = positive("points_per_wavelength", points_per_wavelength)
    if ppw < 2.0:
        raise ValueError(f"points_per_wavelength must be >= 2 (Nyquist), got {ppw!r}")
    return ppw, positive("periods", periods)


def contact_width(scene: Scene, s: float) -> float:
    """The contact's width ``W`` [m] of a profile of standard deviation ``s`` [m]: ``4 s``
    (cylinder) or ``2 sqrt(5) s`` (sphere), the Hertz width 2a."""
    return _WIDTH_PER_S[scene.geometry] * s


def cells_per_bin(scene: Scene, s: float | None = None) -> int:
    """Cells of the grid in one bin (cylinder) or ring width (sphere) of ``p_bar``, >= 1.

    ``Scene.bin_width`` if given; else (with the profile's s [m]) the width
    ``min(W / BINS_ACROSS, pi / (2 q0))`` with ``W = contact_width(scene, s)``, rounded to
    whole cells (one cell for a smooth scene, or without ``s``)."""
    dx = scene.grid.dx
    if scene.bin_width is not None:
        return max(1, int(round(scene.bin_width / dx)))
    if scene.psd is None or s is None or not s > 0.0:
        return 1
    width = min(contact_width(scene, s) / BINS_ACROSS, 0.5 * math.pi / scene.psd.q0)
    return max(1, int(width / dx + 1e-9))


def narrow_contact(scene: Scene, s: float) -> str:
    """Why the contact of profile standard deviation ``s`` [m] is too narrow to compare
    widths, or ``""``: ``W`` (:func:`contact_width`) spans fewer than
    :data:`MIN_CELLS_ACROSS` cells, or is narrower than the longest roughness wavelength
    ``2 pi / q0`` (the theory's mean field assumes the nominal pressure varies slowly on that
    scale, and each realisation's width is set by a few asperities)."""
    width = contact_width(scene, s)
    what = "4 s" if scene.geometry == "cylinder" else "2 sqrt(5) s"
    why = []
    cells = width / scene.grid.dx
    if cells < MIN_CELLS_ACROSS:
        why.append(
            f"it spans {cells:.3g} cells of the BEM grid (at least {MIN_CELLS_ACROSS} resolve "
            "its width; raise points_per_wavelength)"
        )
    if scene.psd is not None:
        lam = 2.0 * math.pi / float(scene.psd.q0)
        if width < lam:
            why.append(
                f"it is narrower than the longest roughness wavelength 2 pi/q0 = {lam:.3g} m "
                "(a few asperities set each realisation's width; the theory's mean field "
                "assumes the pressure varies slowly on that scale)"
            )
    if not why:
        return ""
    return (
        f"the BEM contact (width {width:.3g} m = {what}) is too narrow to compare widths: "
        + "; ".join(why)
    )


def ring_index(scene: Scene, cells: int | None = None) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The rings of a sphere scene's ``p_bar``, of width ``cells`` cells (default
    :func:`cells_per_bin` without the profile: ``Scene.bin_width``, else one cell).

    Returns
    -------
    idx : ndarray of int, shape (nx, ny)
        Ring number ``floor(r / width)`` of every cell, capped at ``count.size`` (the cells
        outside the patch's inscribed circle).
    rmean : ndarray
        Mean radius of each full ring inside the inscribed circle [m].
    count : ndarray of int
        Cells in each of those rings.
    """
    grid = scene.grid
    width = (cells_per_bin(scene) if cells is None else cells) * grid.dx
    x, y = grid.x[:, None], grid.y[None, :]
    r = np.sqrt(x * x + y * y)
    nring = max(int(0.5 * min(grid.lx, grid.ly) / width), 1)
    idx = np.minimum((r / width).astype(np.int64), nring)
    count = np.bincount(idx.ravel(), minlength=nring + 1)[:nring]
    rmean = np.bincount(idx.ravel(), weights=r.ravel(), minlength=nring + 1)[:nring] / count
    return idx, rmean, count


def with_grid(scene: Scene, grid: Grid) -> Scene:
    """The same scene on another grid (for convergence and domain-size studies)."""
    if not isinstance(grid, Grid):
        raise TypeError(f"grid must be a fastline.bem.Grid, got {type(grid).__name__}")
    return replace(scene, grid=grid)
