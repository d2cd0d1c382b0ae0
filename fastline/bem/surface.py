"""Periodic random height maps with a given isotropic power spectrum, and their spectrum.

Convention (Persson's, as :mod:`fastline.spectra`): ``h_rms^2 = 2 pi int q C(q) dq`` and, for a
height map of ``nx x ny`` cells of size ``dx x dy`` (area ``A = nx dx ny dy``) with the
unnormalised DFT ``H = FFT2(h)``,

    C(q_k) = (dx dy)^2 / ((2 pi)^2 A) * E|H_k|^2,        q_k = 2 pi (kx / Lx, ky / Ly).

A surface is synthesised by giving every lattice mode with ``q0 <= |q_k| <= q1`` the modulus
``|H_k| = 2 pi sqrt(A C(|q_k|)) / (dx dy)`` and a random phase (Hermitian symmetric, so ``h`` is
real), all other modes zero.  With ``amplitudes="fixed"`` (the default; the "random-phase"
surfaces of e.g. Persson, J. Phys.: Condens. Matter 17, R1 (2005), and of the contact-mechanics
challenge, Muser et al., Tribol. Lett. 65, 118 (2017)) the moduli are exactly these, so every
realisation has exactly (Parseval) the discrete moments

    h_rms^2 = sum_k C(|q_k|) dqx dqy,       h'^2 = sum_k |q_k|^2 C(|q_k|) dqx dqy,

``dqx dqy = (2 pi)^2 / A``, the sums over the modes kept.  With ``amplitudes="gaussian"``
the modes are complex Gaussian (Rayleigh moduli), which the same sums give in expectation.  The
discrete sums approach the continuum integrals of the spectrum as ``q0 Lx``, ``q0 Ly`` grow; at
``L = 2 pi / q0`` the lowest ring holds only the four modes ``|k| = 1``.

Modes on the Nyquist lines (``kx = nx/2`` or ``ky = ny/2``) are not used: they are
self-conjugate and cannot carry a random phase.  With the default sampling (4 points per
shortest wavelength ``2 pi / q1``) they lie outside the spectrum anyway.

Random numbers are drawn with a seeded :class:`numpy.random.Generator` outside any compiled code
(the phases are those of the DFT of real white noise), so a seed reproduces a surface exactly.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
import scipy.fft

from fastline._validate import finite_array, integer, positive
from fastline.spectra import PSD

__all__ = ["Grid", "RoughSurface", "spectral_grid", "random_surface", "isotropic_spectrum"]

_AMPLITUDES = ("fixed", "gaussian")


@dataclass(frozen=True)
class Grid:
    """A uniform grid of ``nx x ny`` cells of size ``dx x dy`` [m], centred on the origin.

    Cell centres are ``x_i = (i - (nx - 1)/2) dx`` and ``y_j = (j - (ny - 1)/2) dy``.
    """

    nx: int
    ny: int
    dx: float
    dy: float

    def __post_init__(self):
        object.__setattr__(self, "nx", integer("nx", self.nx, 2))
        object.__setattr__(self, "ny", integer("ny", self.ny, 2))
        object.__setattr__(self, "dx", positive("dx", self.dx, "m"))
        object.__setattr__(self, "dy", positive("dy", self.dy, "m"))

    @property
    def shape(self) -> tuple[int, int]:
        return (self.nx, self.ny)

    @property
    def lx(self) -> float:
        """Period / patch length along x [m]."""
        return self.nx * self.dx

    @property
    def ly(self) -> float:
        """Period / patch length along y [m]."""
        return self.ny * self.dy

    @property
    def cell_area(self) -> float:
        return self.dx * self.dy

    @property
    def x(self) -> np.ndarray:
        """Cell-centre x coordinates [m], shape (nx,)."""
        return (np.arange(self.nx) - 0.5 * (self.nx - 1)) * self.dx

    @property
    def y(self) -> np.ndarray:
        """Cell-centre y coordinates [m], shape (ny,)."""
        return (np.arange(self.ny) - 0.5 * (self.ny - 1)) * self.dy

    def wavevectors(self) -> tuple[np.ndarray, np.ndarray]:
        """``(qx, qy)`` of the full FFT2 lattice [1/m], shapes (nx, 1) and (1, ny)."""
        qx = 2.0 * np.pi * np.fft.fftfreq(self.nx, self.dx)
        qy = 2.0 * np.pi * np.fft.fftfreq(self.ny, self.dy)
        return qx[:, None], qy[None, :]


def _fast_size(length, dx_max):
    return int(scipy.fft.next_fast_len(max(2, math.ceil(length / dx_max - 1e-9)), real=True))


def spectral_grid(psd: PSD, *, points_per_wavelength=4.0, periods=2.0, lx=None, ly=None) -> Grid:
    """A square-cell grid sized from the spectrum (issue 15: resolve ``q1``, hold ``q0``).

    ``dx <= 2 pi / (q1 * points_per_wavelength)``; the lengths default to ``periods`` times the
    longest wavelength ``2 pi / q0``; the cell counts are rounded up to FFT-friendly sizes
    (``scipy.fft.next_fast_len``) and ``dx = dy`` shrunk to fit the lengths exactly.

    Parameters
    ----------
    psd : PSD
        The spectrum (its ``q0`` and ``q1`` [1/m] are used).
    points_per_wavelength : float
        Cells per shortest wavelength ``2 pi / q1``, >= 2 (default 4).
    periods : float
        Default lengths in units of ``2 pi / q0``, > 0 (default 2).
    lx, ly : float, optional
        Override the lengths [m], > 0.

    Returns
    -------
    Grid
    """
    if not isinstance(psd, PSD):
        raise TypeError(f"psd must be a fastline PSD, got {type(psd).__name__}")
    ppw = positive("points_per_wavelength", points_per_wavelength)
    if ppw < 2.0:
        raise ValueError(f"points_per_wavelength must be >= 2 (Nyquist), got {ppw!r}")
    periods = positive("periods", periods)
    lam0 = 2.0 * math.pi / psd.q0
    lx = periods * lam0 if lx is None else positive("lx", lx, "m")
    ly = periods * lam0 if ly is None else positive("ly", ly, "m")
    dx_max = 2.0 * math.pi / (psd.q1 * ppw)
    n = max(_fast_size(lx, dx_max), 2)
    dx = lx / n
    m = max(int(round(ly / dx)), 2)
    m = int(scipy.fft.next_fast_len(m, real=True))
    return Grid(n, m, dx, ly / m)


def _mode_spectrum(psd: PSD, grid: Grid) -> tuple[np.ndarray, np.ndarray]:
    """``C(|q_k|)`` on the full FFT2 lattice with the unused modes zeroed, and ``|q_k|^2``."""
    qx, qy = grid.wavevectors()
    q2 = qx * qx + qy * qy
    q = np.sqrt(q2)
    c = np.where((q >= psd.q0) & (q <= psd.q1), psd(q), 0.0)
    if grid.nx % 2 == 0:
        c[grid.nx // 2, :] = 0.0
    if grid.ny % 2 == 0:
        c[:, grid.ny // 2] = 0.0
    return c, q2


@dataclass(frozen=True)
class RoughSurface:
    """One periodic random height map and the statistics it was built to have.

    Attributes
    ----------
    heights : ndarray, shape (nx, ny)
        Heights ``h`` [m], mean zero.
    grid : Grid
        The cells.
    amplitudes : str
        ``"fixed"`` or ``"gaussian"`` (module docstring).
    expected_h_rms, expected_rms_slope : float
        The discrete moments of the spectrum on this lattice (module docstring) [m], [-]:
        exact for every realisation with fixed amplitudes, expectations with Gaussian ones.
    continuum_h_rms, continuum_rms_slope : float
        The spectrum's integrals ``psd.h_rms``, ``psd.rms_slope`` for comparison.
    modes : int
        Number of lattice modes carrying roughness (both signs of q).
    """

    heights: np.ndarray = field(repr=False)
    grid: Grid
    amplitudes: str
    expected_h_rms: float
    expected_rms_slope: float
    continuum_h_rms: float
    continuum_rms_slope: float
    modes: int

    @property
    def h_rms(self) -> float:
        """Measured rms height [m]."""
        return float(np.sqrt(np.mean(self.heights**2)))

    @property
    def rms_slope(self) -> float:
        """Measured rms slope (spectral derivative of the trigonometric interpolant) [-]."""
        qx, qy = self.grid.wavevectors()
        hk = np.fft.fft2(self.heights)
        power = np.abs(hk) ** 2 * (qx * qx + qy * qy)
        return float(np.sqrt(power.sum()) / (self.grid.nx * self.grid.ny))


def random_surface(psd: PSD, grid: Grid, seed=None, *, amplitudes="fixed") -> RoughSurface:
    """A periodic random surface with the isotropic spectrum ``psd`` (module docstring).

    Parameters
    ----------
    psd : PSD
        Isotropic power spectrum ``C(q)`` [m^4], Persson's convention.
    grid : Grid
        Cells; the periods are ``grid.lx``, ``grid.ly``.
    seed : None, int, numpy.random.SeedSequence or numpy.random.Generator
        Source of randomness (``numpy.random.default_rng(seed)``).
    amplitudes : {"fixed", "gaussian"}
        Mode moduli exactly ``sqrt(C)`` (random phases only) or Rayleigh-distributed.

    Returns
    -------
    RoughSurface

    Raises
    ------
    ValueError
        If no lattice mode falls inside ``[q0, q1]`` (grid too coarse or too small).
    """
    if not isinstance(psd, PSD):
        raise TypeError(f"psd must be a fastline PSD, got {type(psd).__name__}")
    if not isinstance(grid, Grid):
        raise TypeError(f"grid must be a fastline.bem.Grid, got {type(grid).__name__}")
    if amplitudes not in _AMPLITUDES:
        raise ValueError(f"amplitudes must be one of {_AMPLITUDES}, got {amplitudes!r}")
    c, q2 = _mode_spectrum(psd, grid)
    modes = int(np.count_nonzero(c))
    if modes == 0:
        raise ValueError(
            f"no lattice mode of the grid lies in [q0, q1] = [{psd.q0:g}, {psd.q1:g}] 1/m: "
            f"make grid.lx, grid.ly >= 2 pi/q0 = {2 * math.pi / psd.q0:g} m and "
            f"dx, dy <= pi/q1 = {math.pi / psd.q1:g} m"
        )
    rng = np.random.default_rng(seed)
    noise = rng.standard_normal(grid.shape)
    w = np.fft.fft2(noise)
    n_cells = grid.nx * grid.ny
    if amplitudes == "fixed":
        w *= math.sqrt(n_cells) / np.maximum(np.abs(w), 1e-300)
    hk = w * (2.0 * math.pi * np.sqrt(c / grid.cell_area))
    heights = np.ascontiguousarray(np.fft.ifft2(hk).real)
    dq2 = (2.0 * math.pi) ** 2 / (grid.lx * grid.ly)
    return RoughSurface(
        heights=heights,
        grid=grid,
        amplitudes=amplitudes,
        expected_h_rms=math.sqrt(c.sum() * dq2),
        expected_rms_slope=math.sqrt((c * q2).sum() * dq2),
        continuum_h_rms=psd.h_rms,
        continuum_rms_slope=psd.rms_slope,
        modes=modes,
    )


def isotropic_spectrum(heights, dx, dy=None, *, bins=None):
    """Ring-averaged isotropic power spectrum of a periodic height map (Persson's convention).

    ``C(q) = (dx dy)^2 / ((2 pi)^2 A) |FFT2(h)|^2`` averaged over the modes of each ring of
    ``|q|`` (no window: the map is assumed periodic).

    Parameters
    ----------
    heights : array_like, shape (nx, ny)
        Heights [m], finite, nx, ny >= 2.
    dx, dy : float
        Cell size [m], > 0 (``dy`` defaults to ``dx``).
    bins : array_like, optional
        Ring edges [1/m], increasing; default: width ``2 pi / max(Lx, Ly)`` from 0 to the
        largest ``|q|``.

    Returns
    -------
    q : ndarray
        Mean ``|q|`` of the modes in each non-empty ring [1/m].
    C : ndarray
        Ring-averaged spectrum [m^4].
    count : ndarray of int
        Number of lattice modes in each ring (the statistical weight).
    """
    h = finite_array("heights", heights, ndim=2)
    if min(h.shape) < 2:
        raise ValueError(f"heights must be at least 2 x 2, got shape {h.shape}")
    dx = positive("dx", dx, "m")
    dy = dx if dy is None else positive("dy", dy, "m")
    grid = Grid(h.shape[0], h.shape[1], dx, dy)
    qx, qy = grid.wavevectors()
    q = np.sqrt(qx * qx + qy * qy).ravel()
    area = grid.lx * grid.ly
    c = (dx * dy) ** 2 / ((2.0 * math.pi) ** 2 * area) * np.abs(np.fft.fft2(h)).ravel() ** 2
    if bins is None:
        step = 2.0 * math.pi / max(grid.lx, grid.ly)
        bins = np.arange(0.5 * step, q.max() + step, step)
    else:
        bins = finite_array("bins", bins, ndim=1)
        if bins.size < 2 or np.any(np.diff(bins) <= 0.0):
            raise ValueError("bins must be strictly increasing with at least 2 edges")
    idx = np.digitize(q, bins) - 1
    ok = (idx >= 0) & (idx < bins.size - 1)
    count = np.bincount(idx[ok], minlength=bins.size - 1)
    csum = np.bincount(idx[ok], weights=c[ok], minlength=bins.size - 1)
    qsum = np.bincount(idx[ok], weights=q[ok], minlength=bins.size - 1)
    keep = count > 0
    return qsum[keep] / count[keep], csum[keep] / count[keep], count[keep]
