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
    heights_refused,
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

#: what psd_from_map says of heights whose spectrum is implausible
_IN_METRES = (
    "heights are taken in m; heights in other units must be converted first (micrometres "
    "passed as metres give an h_rms 1e6 times too large)"
)


def _detrend_map(h: np.ndarray, how: str) -> np.ndarray:
    """The map less its mean or least-squares plane (a new array). On a full grid the centred
    coordinates are orthogonal to the constant and to each other, so the plane's coefficients
    are the mean and ``sum h x / sum x^2``, ``sum h y / sum y^2``: no design matrix."""
    out = h - h.mean()
    if how == "plane":
        ny, nx = h.shape
        x = np.arange(nx, dtype=np.float64) - 0.5 * (nx - 1)
        y = np.arange(ny, dtype=np.float64) - 0.5 * (ny - 1)
        x *= float(out.mean(axis=0) @ x) / float(x @ x)
        y *= float(out.mean(axis=1) @ y) / float(y @ y)
        out -= x[None, :]
        out -= y[:, None]
    return out


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


def _apply_map_window(m: np.ndarray, window) -> None:
    """Multiply a map in place by the product of two windows, along y and along x, normalised
    to ``sum w^2 = Nx Ny`` (no work array of the map's size)."""
    ny, nx = m.shape
    m *= normalised_window(window, ny)[:, None]
    m *= normalised_window(window, nx)[None, :]


def _detrended(stack: np.ndarray, dx: float, dy: float, detrend: str, nan: str):
    """The maps with dropouts bridged (or refused) and their plane or mean removed, their h_rms
    (m) and the rms slope of the first; a flat surface is refused."""
    maps = [_detrend_map(fill_dropouts(m, nan), detrend) for m in stack]
    h_rms = math.sqrt(sum(float(np.vdot(m, m)) for m in maps) / (len(maps) * maps[0].size))
    refuse_flat(h_rms, stack, "map", detrend)
    h = maps[0]
    along_x = np.diff(h, axis=1).ravel()
    sx = float(np.dot(along_x, along_x)) / along_x.size
    del along_x
    along_y = np.diff(h, axis=0).ravel()
    sy = float(np.dot(along_y, along_y)) / along_y.size
    slope = math.sqrt(sx / (dx * dx) + sy / (dy * dy))
    return maps, h_rms, slope


def _map_modes(maps: list, dx: float, dy: float, window):
    """|q|, C and the weight of every Fourier mode of the half plane, averaged over the maps
    (module docstring; windowed in place, then freed). The real FFT keeps the columns
    ``qx >= 0``; a column with ``-qx`` in the full plane (not qx = 0, nor the Nyquist column
    of an even Nx) stands for two modes of equal power, so its weight is 2: ring means over the
    half plane with these weights equal those over every mode."""
    from scipy import fft  # here: scipy.fft's import costs ~0.1 s

    ny, nx = maps[0].shape
    count = len(maps)
    power = np.zeros((ny, nx // 2 + 1))
    while maps:
        m = maps.pop(0)
        _apply_map_window(m, window)
        F = fft.rfft2(m, workers=-1, overwrite_x=True)
        del m
        power += F.real * F.real
        power += F.imag * F.imag
        del F
    power *= (dx * dy) ** 2 / ((2.0 * math.pi) ** 2 * (nx * dx * ny * dy) * count)
    qx = 2.0 * math.pi * np.fft.rfftfreq(nx, dx)
    qy = 2.0 * math.pi * np.fft.fftfreq(ny, dy)
    q = np.hypot(qy[:, None], qx[None, :]).ravel()
    weight = np.full((ny, qx.size), 2.0)
    weight[:, 0] = 1.0
    if nx % 2 == 0:
        weight[:, -1] = 1.0
    return q, power.ravel(), weight.ravel()


def _map_range(q, C, weight, maps, spacing, rules: RangeRules):
    """The usable range of a map's modes (the profile rule with L = min(Lx, Ly) and
    dx = max(dx, dy); full rings only up to pi / max(dx, dy)); ``spacing`` (dx, dy, the
    stylus-tip limit in 1/m)."""
    given, _, noise = rules
    dx, dy, k_tip = spacing
    ny, nx = maps
    measured = (2.0 * math.pi / max(nx * dx, ny * dy), math.pi / max(dx, dy))
    if given == "all":
        return measured
    k_noise = math.inf
    if noise is not None:
        qb, Cb, _ = log_bins(q, C, 20, *measured, weights=weight)
        k_noise = noise_cutoff(qb, Cb, noise * noise * dx * dy / (2.0 * math.pi) ** 2)
    (lo, hi), _ = usable_range(
        LOW_MODE * 2.0 * math.pi / min(nx * dx, ny * dy),
        2.0 * math.pi / (POINTS_PER_WAVELENGTH * max(dx, dy)),
        k_tip,
        k_noise,
        given,
        measured,
    )
    return lo, hi


def _rings(q, C, weight, usable, bins_per_decade: int) -> TabulatedPSD:
    """The modes (q, C, weight) averaged over rings in the usable range ``(lo, hi)``,
    continued to its ends."""
    lo, hi = usable
    qb, Cb, _ = log_bins(q, C, bins_per_decade, lo, hi, weights=weight)
    qb, Cb = span_bins(qb, Cb, lo, hi)
    if qb.size < 2:
        raise ValueError(f"the usable range ({lo:.3g}, {hi:.3g}) 1/m holds fewer than 2 rings")
    return TabulatedPSD(qb, Cb)


def map_spectrum(h, dx, dy, window, detrend, nan, bins_per_decade, rules, raw: bool = False):
    """(the ring averages over the usable range, those over all full rings or None without
    ``raw``) of :func:`psd_from_map`'s arguments (``rules`` from :func:`range_rules`), from one
    Fourier transform of each map."""
    stack, dx, dy = _map_stack(h, dx, dy)
    detrend = choice("detrend", detrend, ("plane", "mean"))
    nan = choice("nan", nan, ("raise", "interpolate"))
    bins_per_decade = integer("bins_per_decade", bins_per_decade, *BINS_PER_DECADE_RANGE)
    normalised_window(window, MIN_POINTS)  # checks the name before any work
    maps, h_rms, slope = _detrended(stack, dx, dy, detrend, nan)
    check_plausible(h_rms, slope, "psd_from_map")
    tip = rules.tip
    k_tip = math.inf if tip is None else tip_cutoff(np.concatenate(maps), dx, tip)
    shape = maps[0].shape
    q, C, weight = _map_modes(maps, dx, dy, window)  # empties maps
    usable = _map_range(q, C, weight, shape, (dx, dy, k_tip), rules)
    psd = _rings(q, C, weight, usable, bins_per_decade)
    if not raw:
        return psd, None
    everything = _map_range(q, C, weight, shape, (dx, dy, k_tip), rules._replace(given="all"))
    return psd, _rings(q, C, weight, everything, bins_per_decade)


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
    rules = range_rules(q_range, tip_radius, noise)
    with heights_refused("psd_from_map", lambda: _IN_METRES):
        psd, _ = map_spectrum(h, dx, dy, window, detrend, nan, bins_per_decade, rules)
    return psd if q1 is None else extend_psd(psd, q1)
