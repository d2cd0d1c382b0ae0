"""Measured heights on their way to a spectrum: checks, dropouts, detrending, windows.

The stages shared by the spectra of profiles (:mod:`~fastline.surfaces.profiles`) and of maps
(:mod:`~fastline.surfaces.maps`), and the plausibility checks that catch a unit slip. Heights
and lengths in m. Their warnings are :class:`~fastline.errors.TopographyWarning`s
(:func:`topography_warning`), which :func:`quiet` holds back while a caller recomputes what it
has already warned about.
"""

from __future__ import annotations

import contextlib
import contextvars
import math
import warnings
from collections.abc import Callable
from typing import TypeVar

import numpy as np

from fastline._lib.stack import outside_stacklevel
from fastline._lib.validate import in_span, real_array
from fastline.errors import ImplausibleSpectrumError, TopographyWarning
from fastline.surfaces.rowkernels import hann_in_place

#: fewest points per profile (and per map direction): a usable range of at least a factor 2
MIN_POINTS = 32
#: most dropouts (NaN) ``nan="interpolate"`` bridges
MAX_DROPOUT_FRACTION = 0.2
#: plausibility of a measured surface (a unit slip by 1e3 or 1e6 falls outside)
PLAUSIBLE_H_RMS = 1e-3  # m
PLAUSIBLE_SLOPE = (1e-6, 5.0)
#: heights (m) a measurement can hold: their largest magnitude lies in this span (a femtometre
#: is far below any instrument's resolution, a kilometre far above any scan's form)
HEIGHT_SPAN = (1e-15, 1e3)
#: spacings dx, dy (m) of a measurement: from a picometre to ten metres
SPACING_SPAN = (1e-12, 10.0)
#: a surface is flat when its detrended h_rms is below this fraction of its largest height
#: (float64 roundoff of the detrending is ~1e-16 of it)
FLAT_TOLERANCE = 1e-12

_T = TypeVar("_T")


def checked_heights(h, ndim_allowed: tuple[int, ...]) -> np.ndarray:
    """Heights (m) as a float64 array of one of the allowed dimensions, real numbers (not
    strings, bools or complex values), without inf, their largest magnitude inside
    HEIGHT_SPAN (NaN, a dropout, is left to :func:`fill_dropouts`); a ValueError naming h."""
    try:
        arr = real_array("h", h)
    except TypeError as e:
        raise ValueError(f"{e} (heights in m)") from None
    if arr.ndim not in ndim_allowed:
        dims = " or ".join(f"{d}-dimensional" for d in ndim_allowed)
        raise ValueError(f"h must be {dims}, got shape {arr.shape}")
    flat = arr.ravel()  # fmax/fmin skip NaN (all NaN: NaN, left to fill_dropouts) silently
    top = (
        max(abs(float(np.fmax.reduce(flat))), abs(float(np.fmin.reduce(flat)))) if arr.size else 0.0
    )
    if math.isinf(top):
        raise ValueError("h must not contain inf")
    if math.isfinite(top) and top != 0.0 and not HEIGHT_SPAN[0] <= top <= HEIGHT_SPAN[1]:
        raise ValueError(
            f"h: the heights reach {top:.3g} m, outside [{HEIGHT_SPAN[0]:g}, "
            f"{HEIGHT_SPAN[1]:g}] m: are they in m (unit='um', 'nm', ...)?"
        )
    return arr


@contextlib.contextmanager
def heights_refused(what: str, advice: Callable[[], str]):
    """Inside the block, a spectrum table's refusal of its h_rms
    (:class:`~fastline.errors.ImplausibleSpectrumError`) said of the heights it was computed
    from: ``what`` names them (a function, a file), ``advice()`` the unit they were taken in
    and what to do."""
    try:
        yield
    except ImplausibleSpectrumError as e:
        lo, hi = e.span
        raise ImplausibleSpectrumError(
            f"{what}: the heights give h_rms = {e.h_rms:.3g} m over the usable range, outside "
            f"[{lo:g}, {hi:g}] m, the span of a measured surface: {advice()}",
            e.h_rms,
            e.span,
        ) from None


def checked_spacing(name: str, value) -> float:
    """A spacing (m) inside SPACING_SPAN."""
    return in_span(name, value, SPACING_SPAN, "m")


#: set while a caller recomputes what it has already analysed (and warned about) once
_QUIET: contextvars.ContextVar[bool] = contextvars.ContextVar("fastline_topography_quiet")


@contextlib.contextmanager
def quiet():
    """Drop the TopographyWarnings of :func:`topography_warning` inside the block. Unlike
    ``warnings.catch_warnings``, it leaves the warning filters alone: changing them (entering
    or leaving that context manager) clears the record of warnings already shown, so each call
    of a function using it would show the same warning again."""
    token = _QUIET.set(True)
    try:
        yield
    finally:
        _QUIET.reset(token)


def topography_warning(text: str) -> None:
    """A TopographyWarning attributed to the first frame outside fastline: the line of the
    user's code that called a public function (``analyse_scan``, a reader, the fit), however
    deep inside fastline the warning was raised. (Python 3.12's ``skip_file_prefixes`` of
    ``warnings.warn`` does this; fastline supports 3.10.)"""
    if not _QUIET.get(False):
        warnings.warn(text, TopographyWarning, stacklevel=outside_stacklevel())


def fill_dropouts(h: np.ndarray, nan: str) -> np.ndarray:
    """Rows of h with their NaN (dropouts) refused or bridged linearly along the row."""
    bad = np.isnan(h)
    if not bad.any():
        return h
    n, frac = int(bad.sum()), float(bad.mean())
    if nan == "raise":
        raise ValueError(
            f"h contains {n} NaN values (dropouts, {frac:.1%} of the points): pass "
            "nan='interpolate' to bridge them linearly, or clean the data"
        )
    empty = np.flatnonzero(bad.reshape(-1, h.shape[-1]).all(axis=-1))
    if empty.size:
        raise ValueError(
            f"h: row {int(empty[0])} holds no data (all {h.shape[-1]} values NaN): a row "
            "without data cannot be bridged along itself; drop it (or crop the scan)"
        )
    if frac > MAX_DROPOUT_FRACTION:
        raise ValueError(
            f"h has {frac:.1%} NaN values: too many dropouts to bridge "
            f"(at most {MAX_DROPOUT_FRACTION:.0%})"
        )
    out = h.copy()
    j = np.arange(h.shape[-1])
    for row, miss in zip(out, bad, strict=True):
        if miss.any():
            row[miss] = np.interp(j[miss], j[~miss], row[~miss])
    return out


def _line_residual(h: np.ndarray, how: str) -> np.ndarray:
    """Rows minus their mean or least-squares line, in closed form (``t`` centred, so the two
    coefficients are independent): one work array of a row's size, no design matrix."""
    n = h.shape[-1]
    centre = 0.5 * (n - 1)
    tt = n * (n * n - 1.0) / 12.0  # sum of (j - centre)^2
    out = []
    for row in h:
        mean = float(np.mean(row))
        res = np.arange(n, dtype=np.float64)  # j, then the residual in place
        slope = (float(np.dot(row, res)) - centre * mean * n) / tt if how == "linear" else 0.0
        res *= -slope
        res += slope * centre - mean
        res += row
        out.append(res)
    return out[0][None, :] if len(out) == 1 else np.array(out)


def detrend_rows(h: np.ndarray, dx: float, how: str):
    """Rows minus their mean, line, parabola or circle; and the form's radius (m) or None."""
    if how in ("mean", "linear"):
        return _line_residual(h, how), None
    n = h.shape[-1]
    t = (np.arange(n) - 0.5 * (n - 1)) / (0.5 * n)  # in [-1, 1]
    degree = {"mean": 0, "linear": 1, "parabola": 2, "circle": 2}[how]
    V = np.vander(t, degree + 1)
    coef, *_ = np.linalg.lstsq(V, h.T, rcond=None)
    residual = h - (V @ coef).T
    curvature = 2.0 * coef[0] / (0.5 * n * dx) ** 2  # h'' of each row's parabola, 1/m
    radius = float(1.0 / np.mean(np.abs(curvature)))
    if how == "parabola":
        return residual, radius
    return _circle_residual(h, dx, coef, t)


def _circle_residual(h: np.ndarray, dx: float, coef: np.ndarray, t: np.ndarray):
    """Rows minus their least-squares circle arc (a cylinder's own form), and its mean radius.

    The arc ``yc - sigma sqrt(R^2 - (x - xc)^2)`` (sigma the sign of the curvature: -1 for a
    convex cap, whose centre lies below) is fitted to the heights by Gauss-Newton (scipy
    ``least_squares``), started from the parabola's vertex and radius.
    """
    from scipy.optimize import least_squares  # here: scipy.optimize takes ~1 s to import

    n = h.shape[-1]
    half = 0.5 * n * dx
    x = t * half
    out = np.empty_like(h)
    radii = []
    for r, (row, c) in enumerate(zip(h, coef.T, strict=True)):
        a2 = c[0] / half**2  # h = a2 x^2 + a1 x + a0
        a1 = c[1] / half
        if abs(c[0]) <= FLAT_TOLERANCE * np.max(np.abs(row)):  # a sag of roundoff: a line
            raise ValueError("detrend='circle': a profile has no curvature (use 'linear')")
        R0 = 1.0 / abs(2.0 * a2)
        if R0 <= half:
            raise ValueError(
                f"detrend='circle': profile {r} is not an arc of a circle larger than the scan "
                f"(curvature radius {R0:.3g} m <= half length {half:.3g} m)"
            )
        sigma = -1.0 if a2 < 0.0 else 1.0
        xc0 = -a1 / (2.0 * a2)
        yc0 = (c[2] - a1**2 / (4.0 * a2)) + sigma * R0  # the centre: vertex height + sigma R

        def arc(p, sigma=sigma):
            xc, yc, R = p
            return yc - sigma * np.sqrt(np.maximum(R * R - (x - xc) ** 2, 0.0))

        fit = least_squares(lambda p, row=row, arc=arc: arc(p) - row, [xc0, yc0, R0], x_scale="jac")
        out[r] = row - arc(fit.x)
        radii.append(abs(fit.x[2]))
    return out, float(np.mean(radii))


def normalised_window(window, n: int) -> np.ndarray:
    """A window of n points normalised to ``sum w^2 = n`` (power-preserving)."""
    if window is None or (isinstance(window, str) and window.lower() in _RECTANGULAR):
        return np.ones(n)
    if isinstance(window, str) and window.lower() in ("hann", "hanning"):
        w = np.arange(n, dtype=np.float64)  # the periodic Hann window, 1 - cos: sum w^2 = 3n/8
        w *= 2.0 * math.pi / n
        np.cos(w, out=w)
        w *= -0.5
        w += 0.5
        w *= math.sqrt(8.0 / 3.0)
        return w
    from scipy.signal import get_window  # here: scipy.signal takes ~1 s to import

    try:
        w = np.asarray(get_window(window, n, fftbins=True), dtype=np.float64)
    except (ValueError, TypeError) as e:
        raise ValueError(
            f"window must be 'hann', 'none' or a scipy.signal window, got {window!r}: {e}"
        ) from None
    return w * math.sqrt(n / float(np.sum(w * w)))


_RECTANGULAR = ("none", "rect", "rectangular", "boxcar")
_HANN = ("hann", "hanning")


def is_hann(window) -> bool:
    """Whether ``window`` names the Hann window (computed here, in pieces, without SciPy)."""
    return isinstance(window, str) and window.lower() in _HANN


def apply_window(row: np.ndarray, window) -> None:
    """Multiply one row (contiguous) in place by the window of :func:`normalised_window`; the
    Hann window in one compiled pass (no work array of the row's size)."""
    if not is_hann(window):
        row *= normalised_window(window, row.size)
        return
    hann_in_place(row, math.sqrt(8.0 / 3.0))


def window_factor(window, n: int) -> float:
    """``N sum w^4 / (sum w^2)^2`` of the window: 1 without one, 35/18 for the periodic Hann
    window of n >= 5 points (exact), else from the weights."""
    if window is None or (isinstance(window, str) and window.lower() in _RECTANGULAR):
        return 1.0
    if is_hann(window) and n >= 5:
        return 35.0 / 18.0
    w2 = normalised_window(window, n) ** 2
    return float(n * np.dot(w2, w2) / np.sum(w2) ** 2)


def refuse_flat(h_rms: float, h: np.ndarray, what: str, detrend: str) -> None:
    """A ValueError when the detrended heights are zero to roundoff (a constant or a plane
    surface has no roughness spectrum), before the plausibility check blames the units."""
    scale = float(max(abs(np.nanmax(h)), abs(np.nanmin(h)))) if np.any(np.isfinite(h)) else 0.0
    if h_rms <= FLAT_TOLERANCE * scale or h_rms == 0.0:
        form = "mean" if detrend == "mean" else f"{detrend} form"
        raise ValueError(
            f"the {what} is flat: after removing its {form} the heights vary by h_rms = "
            f"{h_rms:.3g} m, roundoff of heights up to {scale:.3g} m; a flat surface has no "
            "roughness spectrum (does the file hold the heights?)"
        )


def check_plausible(h_rms: float, slope: float, what: str) -> None:
    """One TopographyWarning when h_rms or the rms slope says the units are off."""
    notes = []
    if h_rms > PLAUSIBLE_H_RMS:
        notes.append(f"h_rms = {h_rms:.3g} m is more than {PLAUSIBLE_H_RMS:g} m")
    if not PLAUSIBLE_SLOPE[0] <= slope <= PLAUSIBLE_SLOPE[1]:
        notes.append(
            f"the rms slope {slope:.3g} is outside [{PLAUSIBLE_SLOPE[0]:g}, {PLAUSIBLE_SLOPE[1]:g}]"
        )
    if notes:
        topography_warning(
            f"{what}: {' and '.join(notes)}: are the heights or the spacing in the wrong unit "
            "(e.g. micrometres read as metres)? Heights and spacings are in m.",
        )


def choice(name: str, value: _T, allowed: tuple[str, ...]) -> _T:
    """The argument ``name`` if it is one of ``allowed``, else a ValueError naming them."""
    if value not in allowed:
        raise ValueError(f"{name} must be one of {', '.join(map(repr, allowed))}, got {value!r}")
    return value
