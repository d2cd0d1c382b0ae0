"""Periodic random height maps with a given isotropic power spectrum, and their spectrum.

Convention (Persson's, as :mod:`fastline.theory.spectra`): ``h_rms^2 = 2 pi int q C(q) dq``
and, for a height map of ``nx x ny`` cells of size ``dx x dy`` (area ``A = nx dx ny dy``) with the
unnormalised DFT ``H = FFT2(h)``,

    C(q_k) = (dx dy)^2 / ((2 pi)^2 A) * E|H_k|^2,        q_k = 2 pi (kx / Lx, ky / Ly).

A surface is synthesised by giving every lattice mode ``k`` the modulus
``|H_k| = 2 pi sqrt(A c_k) / (dx dy)`` and a random phase (Hermitian symmetric, so ``h`` is
real), where ``c_k`` is the mean of ``C(|q|)`` over the mode's lattice cell (the rectangle
``dqx x dqy`` about ``q_k``, ``dqx dqy = (2 pi)^2 / A``; ``C = 0`` outside ``[q0, q1]``) times
one normalising factor (below).  With ``amplitudes="fixed"`` (the default; the "random-phase"
surfaces of e.g. Persson, J. Phys.: Condens. Matter 17, R1 (2005), and of the contact-mechanics
challenge, Muser et al., Tribol. Lett. 65, 118 (2017)) the moduli are exactly these, so every
realisation has exactly (Parseval) the discrete moments

    h_rms^2 = sum_k c_k dqx dqy,       h'^2 = sum_k |q_k|^2 c_k dqx dqy;

with ``amplitudes="gaussian"`` the modes are complex Gaussian (Rayleigh moduli), which the same
sums give in expectation.

Why cell means and not ``C(|q_k|)``: the cells tile the wavevector plane, so the sum of the
cell integrals ``c_k dqx dqy`` is the integral of ``C`` over the annulus ``q0 <= |q| <= q1``,
i.e. the spectrum's ``m0 = h_rms^2``, whatever the cell size.  The point values ``C(|q_k|)``
instead weigh a whole cell by its centre: near ``q0``, where ``C`` is steep and cells straddle
the annulus's inner edge, that overestimates ``m0`` at the default cell (two longest
wavelengths ``2 pi / q0``, lowest ring ``|k| = 2``) by 11 % (``h_rms`` +5.5 %) on the validation
page's cylinder grid and by 25 % (``h_rms`` +11.6 %) on its 256 x 256 flat grid.  The cell
means are computed by a midpoint rule on sub-cells of width at most ``q0 / 32`` in the cells
where ``C`` varies on the cell's scale (within 16 cell widths of the origin, and on the circles
``q0`` and ``q1``), by ``C(|q_k|)`` elsewhere (relative error there
``(1 + H)^2 (dq / q)^2 / 6 < 0.3 %`` for a power law ``C ~ q^(-2(1 + H))``).  The remaining
quadrature error (at most 0.3 % of ``m0`` on the grids of docs/validation.md) is removed by one
deterministic factor, the same for every mode: ``sum_k c_k dqx dqy`` equals
``psd.h_rms^2`` to round-off whenever the lattice resolves ``q1`` (``dx, dy <= pi / q1``; on
coarser grids the modes beyond the Nyquist wavenumber are missing, no factor is applied and the
discrete moments fall short of the spectrum's).  The rms slope, dominated by the large ``q``
where the cells are fine, stays within 2 % of ``psd.rms_slope`` (measured for q1/q0 = 4-32:
+0.2-0.6 % at two longest wavelengths, +0.6-1.7 % at one);
:attr:`RoughSurface.expected_rms_slope` and :func:`lattice_moments` report it.  A cell straddling
``q0`` may belong to a mode just below ``q0`` (e.g. ``|k| = (1, 1)`` at two periods): it carries
the power of its part of the annulus.

Modes on the Nyquist lines (``kx = nx/2`` or ``ky = ny/2``) are not used: they are
self-conjugate and cannot carry a random phase.  With the default sampling (4 points per
shortest wavelength ``2 pi / q1``) they lie outside the spectrum anyway.

Random numbers are drawn with a seeded :class:`numpy.random.Generator` outside any compiled code
(the phases are those of the DFT of real white noise), so a seed reproduces a surface exactly.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Literal, get_args

import numpy as np
import scipy.fft
from numpy.typing import ArrayLike

from fastline._lib.validate import finite_array, integer, positive
from fastline.theory.spectra import PSD

__all__ = [
    "Grid",
    "RoughSurface",
    "spectral_grid",
    "lattice_moments",
    "random_surface",
    "isotropic_spectrum",
]

#: the values of ``amplitudes`` (:func:`random_surface`)
Amplitudes = Literal["fixed", "gaussian"]
_AMPLITUDES = get_args(Amplitudes)
#: what :func:`numpy.random.default_rng` accepts as a seed here
Seed = int | np.random.SeedSequence | np.random.Generator | None


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


#: relative slack of the cell count before rounding up: spectra typed with rounded wavenumbers
#: (q1/q0 = 32.00000004 for 32) keep the grid they were meant for (512, not 540 cells)
_SIZE_SLACK = 1e-6


def _fast_size(length, dx_max):
    cells = length / dx_max * (1.0 - _SIZE_SLACK)
    return int(scipy.fft.next_fast_len(max(2, math.ceil(cells)), real=True))


def spectral_grid(
    psd: PSD,
    *,
    points_per_wavelength: float = 4.0,
    periods: float = 2.0,
    lx: float | None = None,
    ly: float | None = None,
) -> Grid:
    """A square-cell grid sized from the spectrum (resolve ``q1``, hold ``q0``).

    ``dx <= 2 pi / (q1 * points_per_wavelength)`` (to 1e-6 relative); the lengths default to
    ``periods`` times the longest wavelength ``2 pi / q0``; the cell counts are rounded up to
    FFT-friendly sizes (``scipy.fft.next_fast_len``) and ``dx = dy`` shrunk to fit the lengths
    exactly.

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


#: cells within this many cell widths of q = 0 get sub-cell quadrature (module docstring)
_NEAR_CELLS = 16
#: sub-cell width at most q0 / _SUB_PER_Q0 in the refined cells
_SUB_PER_Q0 = 32
#: most sub-cells per side of a lattice cell (reached only by a period far shorter than 2 pi/q0)
_SUB_MAX = 256


def _subcell_means(psd: PSD, qx, qy, dqx: float, dqy: float) -> np.ndarray:
    """Mean of ``C(|q|)`` over the cells ``[qx +- dqx/2] x [qy +- dqy/2]`` (1-D arrays of the
    centres) by the midpoint rule on sub-cells of width at most ``q0 / _SUB_PER_Q0``."""
    mx = min(_SUB_MAX, max(2, math.ceil(_SUB_PER_Q0 * dqx / psd.q0)))
    my = min(_SUB_MAX, max(2, math.ceil(_SUB_PER_Q0 * dqy / psd.q0)))
    tx = ((np.arange(mx) + 0.5) / mx - 0.5) * dqx
    ty = ((np.arange(my) + 0.5) / my - 0.5) * dqy
    out = np.empty(qx.size)
    step = max(1, 2**22 // (mx * my))  # bound the temporary arrays to ~32 MB
    for i in range(0, qx.size, step):
        sx = qx[i : i + step, None, None] + tx[None, :, None]
        sy = qy[i : i + step, None, None] + ty[None, None, :]
        out[i : i + step] = psd(np.sqrt(sx * sx + sy * sy)).mean(axis=(1, 2))
    return out


def _mode_spectrum(psd: PSD, grid: Grid) -> tuple[np.ndarray, np.ndarray]:
    """The cell means ``c_k`` [m^4] on the full FFT2 lattice with the unused modes zeroed,
    normalised to ``sum c_k dqx dqy = psd.h_rms^2`` if the lattice resolves ``q1``, and
    ``|q_k|^2`` (module docstring)."""
    qx, qy = grid.wavevectors()
    dqx, dqy = 2.0 * math.pi / grid.lx, 2.0 * math.pi / grid.ly
    q2 = qx * qx + qy * qy
    q = np.sqrt(q2)
    half = 0.5 * math.hypot(dqx, dqy)  # cells with |q_k - r| > half do not meet the circle r
    c = np.array(np.broadcast_to(psd(q), q.shape))
    near = max(psd.q0, _NEAR_CELLS * max(dqx, dqy))
    refine = (q - half <= near) | (np.abs(q - psd.q0) <= half) | (np.abs(q - psd.q1) <= half)
    refine &= (q + half >= psd.q0) & (q - half <= psd.q1)
    refine[0, 0] = False  # the mean carries no roughness
    i, j = np.nonzero(refine)
    c[i, j] = _subcell_means(psd, qx[i, 0], qy[0, j], dqx, dqy)
    c[0, 0] = 0.0
    if grid.nx % 2 == 0:
        c[grid.nx // 2, :] = 0.0
    if grid.ny % 2 == 0:
        c[:, grid.ny // 2] = 0.0
    m0 = c.sum() * dqx * dqy
    if m0 > 0.0 and max(grid.dx, grid.dy) <= math.pi / psd.q1:
        c *= psd.h_rms**2 / m0
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
        The discrete moments of the spectrum on this lattice (module docstring;
        :func:`lattice_moments`) [m], [-]: exact for every realisation with fixed amplitudes,
        expectations with Gaussian ones; ``expected_h_rms == psd.h_rms`` to round-off when the
        lattice resolves ``q1``.
    continuum_h_rms, continuum_rms_slope : float
        The spectrum's integrals ``psd.h_rms``, ``psd.rms_slope`` for comparison.
    modes : int
        Number of lattice modes carrying roughness (both signs of q).
    """

    heights: np.ndarray = field(repr=False)
    grid: Grid
    amplitudes: Amplitudes
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


def _moments(c, q2, grid) -> tuple[float, float]:
    dq2 = (2.0 * math.pi) ** 2 / (grid.lx * grid.ly)
    return math.sqrt(c.sum() * dq2), math.sqrt((c * q2).sum() * dq2)


def lattice_moments(psd: PSD, grid: Grid) -> tuple[float, float]:
    """The rms height [m] and rms slope [-] of the surfaces :func:`random_surface` draws on
    ``grid`` (exactly with fixed amplitudes, in expectation with Gaussian ones): the discrete
    moments of the module docstring, without drawing a surface.

    Compare them with ``psd.h_rms`` (equal to round-off when ``dx, dy <= pi / q1``) and
    ``psd.rms_slope`` (within 2 %: module docstring).
    """
    if not isinstance(psd, PSD):
        raise TypeError(f"psd must be a fastline PSD, got {type(psd).__name__}")
    if not isinstance(grid, Grid):
        raise TypeError(f"grid must be a fastline.bem.Grid, got {type(grid).__name__}")
    return _moments(*_mode_spectrum(psd, grid), grid)


def _checked_seed(seed: Seed) -> Seed:
    """``seed`` if NumPy can seed a generator with it (None, an int >= 0, a SeedSequence or a
    Generator); a TypeError or ValueError naming it otherwise."""
    if seed is None or isinstance(seed, (np.random.SeedSequence, np.random.Generator)):
        return seed
    if isinstance(seed, bool) or not isinstance(seed, (int, np.integer)):
        raise TypeError(
            "seed must be None, an int >= 0, a numpy SeedSequence or Generator, "
            f"got {type(seed).__name__}"
        )
    if seed < 0:
        raise ValueError(f"seed must be >= 0, got {seed}")
    return int(seed)


def random_surface(
    psd: PSD, grid: Grid, seed: Seed = None, *, amplitudes: Amplitudes = "fixed"
) -> RoughSurface:
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
        Mode moduli exactly ``sqrt(c_k)`` (random phases only) or Rayleigh-distributed.

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
    rng = np.random.default_rng(_checked_seed(seed))
    noise = rng.standard_normal(grid.shape)
    w = np.fft.fft2(noise)
    n_cells = grid.nx * grid.ny
    if amplitudes == "fixed":
        w *= math.sqrt(n_cells) / np.maximum(np.abs(w), 1e-300)
    hk = w * (2.0 * math.pi * np.sqrt(c / grid.cell_area))
    heights = np.ascontiguousarray(np.fft.ifft2(hk).real)
    h_rms, rms_slope = _moments(c, q2, grid)
    return RoughSurface(
        heights=heights,
        grid=grid,
        amplitudes=amplitudes,
        expected_h_rms=h_rms,
        expected_rms_slope=rms_slope,
        continuum_h_rms=psd.h_rms,
        continuum_rms_slope=psd.rms_slope,
        modes=modes,
    )


def isotropic_spectrum(
    heights: ArrayLike, dx: float, dy: float | None = None, *, bins: ArrayLike | None = None
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
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
