"""Height maps: the isotropic spectrum C(q) from the 2D Fourier transform, averaged over rings.

``C(q) = (dx dy)^2 / ((2 pi)^2 A) |FFT2(w h)|^2`` for an ``Ny x Nx`` map of area ``A``
(Persson's convention, ``h_rms^2 = 2 pi int q C dq``, m^4). Heights and spacings in m,
wavenumbers in 1/m.
"""

from __future__ import annotations

import math
from typing import Literal

import numpy as np
from numpy.typing import ArrayLike

from fastline._lib.validate import BINS_PER_DECADE_RANGE, integer
from fastline.surfaces.heights import (
    MIN_POINTS,
    check_plausible,
    checked_heights,
    checked_spacing,
    choice,
    fill_dropouts,
    normalised_window,
    refuse_flat,
)
from fastline.surfaces.ranges import (
    LOW_MODE,
    POINTS_PER_WAVELENGTH,
    QRange,
    RangeRules,
    log_bins,
    noise_cutoff,
    range_rules,
    span_bins,
    tip_cutoff,
    usable_range,
)
from fastline.surfaces.tables import extend_psd
from fastline.theory.spectra import TabulatedPSD


def _detrend_map(h: np.ndarray, how: str) -> np.ndarray:
    if how == "mean":
        return h - h.mean()
    ny, nx = h.shape
    y, x = np.mgrid[0:ny, 0:nx]
    V = np.column_stack([np.ones(h.size), (x.ravel() - 0.5 * nx) / nx, (y.ravel() - 0.5 * ny) / ny])
    coef, *_ = np.linalg.lstsq(V, h.ravel(), rcond=None)
    return h - (V @ coef).reshape(h.shape)


def _map_stack(h, dx, dy) -> tuple[np.ndarray, float, float]:
    """The maps as a stack (M, Ny, Nx) of at least MIN_POINTS each way, and the spacings dx,
    dy (m), checked."""
    h = checked_heights(h, (2, 3))
    stack = h if h.ndim == 3 else h[None]
    dx = checked_spacing("dx", dx)
    dy = dx if dy is None else checked_spacing("dy", dy)
    if min(stack.shape[1:]) < MIN_POINTS:
        raise ValueError(
            f"h must hold at least {MIN_POINTS} points in each direction, got shape {h.shape}"
            + (" (a single row is a profile: use psd_from_profile)" if 1 in h.shape[-2:] else "")
        )
    return stack, dx, dy


def _map_window(window, ny: int, nx: int) -> np.ndarray:
    """The product of two windows, along y and along x, normalised to ``sum w^2 = Nx Ny``."""
    return normalised_window(window, ny)[:, None] * normalised_window(window, nx)[None, :]


def _detrended(stack: np.ndarray, dx: float, dy: float, detrend: str, nan: str):
    """The maps with dropouts bridged (or refused) and their plane or mean removed, their h_rms
    (m) and the rms slope of the first; a flat surface is refused."""
    maps = [_detrend_map(fill_dropouts(m, nan), detrend) for m in stack]
    h_rms = float(np.sqrt(np.mean([np.mean(m**2) for m in maps])))
    refuse_flat(h_rms, stack, "map", detrend)
    h = maps[0]
    slope = float(
        np.sqrt(np.mean((np.diff(h, axis=1) / dx) ** 2) + np.mean((np.diff(h, axis=0) / dy) ** 2))
    )
    return maps, h_rms, slope


def _map_modes(maps, dx: float, dy: float, w: np.ndarray):
    """|q| and C of every Fourier mode, averaged over the maps (module docstring)."""
    ny, nx = maps[0].shape
    power = np.mean([np.abs(np.fft.fft2(m * w)) ** 2 for m in maps], axis=0)
    C = (dx * dy) ** 2 / ((2.0 * math.pi) ** 2 * (nx * dx * ny * dy)) * power
    qx = 2.0 * math.pi * np.fft.fftfreq(nx, dx)
    qy = 2.0 * math.pi * np.fft.fftfreq(ny, dy)
    return np.hypot(qy[:, None], qx[None, :]).ravel(), C.ravel()


def _map_range(q, C, maps, dx, dy, rules: RangeRules):
    """The usable range of a map's modes (the profile rule with L = min(Lx, Ly) and
    dx = max(dx, dy); full rings only up to pi / max(dx, dy))."""
    given, tip, noise = rules
    ny, nx = maps[0].shape
    measured = (2.0 * math.pi / max(nx * dx, ny * dy), math.pi / max(dx, dy))
    if given == "all":
        return measured
    k_noise = math.inf
    if noise is not None:
        qb, Cb, _ = log_bins(q, C, 20, *measured)
        k_noise = noise_cutoff(qb, Cb, noise * noise * dx * dy / (2.0 * math.pi) ** 2)
    (lo, hi), _ = usable_range(
        LOW_MODE * 2.0 * math.pi / min(nx * dx, ny * dy),
        2.0 * math.pi / (POINTS_PER_WAVELENGTH * max(dx, dy)),
        math.inf if tip is None else tip_cutoff(np.concatenate(maps), dx, tip),
        k_noise,
        given,
        measured,
    )
    return lo, hi


def _rings(q, C, usable, bins_per_decade: int) -> TabulatedPSD:
    """The modes (q, C) averaged over rings in the usable range ``(lo, hi)``, continued to its
    ends."""
    lo, hi = usable
    qb, Cb, _ = log_bins(q, C, bins_per_decade, lo, hi)
    qb, Cb = span_bins(qb, Cb, lo, hi)
    if qb.size < 2:
        raise ValueError(f"the usable range ({lo:.3g}, {hi:.3g}) 1/m holds fewer than 2 rings")
    return TabulatedPSD(qb, Cb)


def psd_from_map(
    h: ArrayLike,
    dx: float,
    dy: float | None = None,
    *,
    window: str | None = "hann",
    detrend: Literal["plane", "mean"] = "plane",
    nan: Literal["raise", "interpolate"] = "raise",
    bins_per_decade: int = 20,
    q_range: QRange = "auto",
    q1: float | None = None,
    tip_radius: float | None = None,
    noise: float | None = None,
) -> TabulatedPSD:
    """The isotropic spectrum C(q) of a height map, averaged over rings of ``|q|``.

    ``C(q) = (dx dy)^2 / ((2 pi)^2 A) |FFT2(w h)|^2`` (Persson's convention,
    ``h_rms^2 = 2 pi int q C dq``; docs/theory.md section 2), no Abel step needed.

    Parameters
    ----------
    h : array_like
        Heights in m, shape (Ny, Nx): rows along x; or (M, Ny, Nx), M maps of one surface whose
        spectra are averaged. At least 32 points each way (a single row is a profile:
        :func:`psd_from_profile`).
    dx, dy : float
        Spacings in m along x (columns) and y (rows); dy defaults to dx.
    window : str or None
        ``"hann"`` (default; the product of two Hann windows), ``"none"`` or a scipy window;
        normalised to ``sum w^2 = Nx Ny``.
    detrend : {"plane", "mean"}
    nan : {"raise", "interpolate"}
        NaN (dropouts) refused, or bridged linearly along x (at most 20 %).
    bins_per_decade : int
        Rings per decade of q (default 20), placed as in :func:`psd_from_profile`.
    q_range : "auto", None or (lo, hi)
        As :func:`psd_from_profile`, with ``L = min(Lx, Ly)`` and ``dx = max(dx, dy)``; the
        noise floor of white noise of rms ``noise`` is ``noise^2 dx dy / (2 pi)^2``; the tip
        rule looks along x. None: all full rings, ``2 pi / max(Lx, Ly) .. pi / max(dx, dy)``.
    q1 : float, optional
        Cut at, or extend by a fitted power law to, q1 (:func:`extend_psd`).
    tip_radius, noise : float, optional
        Stylus tip radius and rms instrument noise, in m.

    Returns
    -------
    TabulatedPSD
        Its ``q0``, ``q1`` are the usable range (or the extension).
    """
    stack, dx, dy = _map_stack(h, dx, dy)
    detrend = choice("detrend", detrend, ("plane", "mean"))
    nan = choice("nan", nan, ("raise", "interpolate"))
    bins_per_decade = integer("bins_per_decade", bins_per_decade, *BINS_PER_DECADE_RANGE)
    rules = range_rules(q_range, tip_radius, noise)
    w = _map_window(window, *stack.shape[1:])
    maps, h_rms, slope = _detrended(stack, dx, dy, detrend, nan)
    check_plausible(h_rms, slope, "psd_from_map")
    q, C = _map_modes(maps, dx, dy, w)
    psd = _rings(q, C, _map_range(q, C, maps, dx, dy, rules), bins_per_decade)
    return psd if q1 is None else extend_psd(psd, q1)
