"""Measured surfaces in: from a line scan or a height map to the isotropic spectrum C(q).

Conventions (docs/topography.md, docs/theory.md section 2). SI units: heights and lengths in
m, wavenumbers in 1/m (``k = 2 pi / wavelength``).

* **1D spectrum of a profile**, two-sided: ``h_rms^2 = 2 int_0^inf C1D(k) dk`` (m^3). From N
  heights ``h_j`` at spacing dx (length ``L = N dx``) and a window ``w_j`` normalised to
  ``sum w_j^2 = N``::

      C1D(k_m) = dx^2 / (2 pi L) |sum_j w_j h_j exp(-i k_m x_j)|^2,    k_m = 2 pi m / L,

  so that ``sum_m C1D(k_m) 2 pi / L`` over all m (both signs) is ``mean((w h)^2)``: Parseval,
  exact for the rectangular window.
* **Isotropic 2D spectrum** (Persson): ``h_rms^2 = 2 pi int q C(q) dq`` (m^4). From an
  ``Ny x Nx`` map of area ``A``: ``C(q) = (dx dy)^2 / ((2 pi)^2 A) |FFT2(w h)|^2``, averaged over
  rings of ``|q|``.
* **1D to 2D** for an isotropic surface, the Abel pair
  ``C1D(k) = 2 int_k^inf C q / sqrt(q^2 - k^2) dq`` and
  ``C(q) = -(1/pi) int_q^inf C1D'(k) / sqrt(k^2 - q^2) dk`` (:func:`isotropic_from_1d`). For a
  power law the pair reduces to ``C = Gamma(1+H) / (sqrt(pi) Gamma(H+1/2)) C1D / q``; the
  shortcut ``C = C1D / (2 q)`` is exact only at H = 1/2 (14.6 % low at H = 0.8, 21.5 % low at
  H = 1: the exact C is 17 % and 27 % higher).

Other codes' conventions: :func:`convert_psd`. The usable wavenumber range of a measurement
and the rules that set it: :func:`psd_from_profile`. Files: :func:`read_topography`.
"""

from __future__ import annotations

import contextlib
import contextvars
import math
import os
import warnings
from collections.abc import Iterator
from dataclasses import dataclass, field
from typing import Any, Literal, NamedTuple, TypeVar

import numpy as np
from numpy.typing import ArrayLike

from fastline._lib.validate import WAVENUMBER_RANGE, finite_scalar, integer, positive, real_array
from fastline.errors import TopographyWarning
from fastline.surfaces.abel import inverse_abel
from fastline.surfaces.read import read_table
from fastline.theory.spectra import PSD, SelfAffinePSD, TabulatedPSD

__all__ = [
    "TopographyWarning",
    "ProfileSpectrum",
    "psd_from_profile",
    "isotropic_from_1d",
    "extend_psd",
    "psd_from_map",
    "SelfAffineFit",
    "fit_self_affine",
    "ROLLOFF_MARGIN",
    "ROLLOFF_SIGNIFICANCE",
    "CONVENTIONS",
    "Convention",
    "QRange",
    "convert_psd",
    "synthetic_surface",
    "Profile",
    "Map",
    "read_profile",
    "read_map",
    "read_topography",
]

#: fewest points per profile (and per map direction): a usable range of at least a factor 2
MIN_POINTS = 32
#: the usable range starts at this Fourier mode (k = 4 x 2 pi / L): the first modes carry the
#: detrending's and the window's distortion (a Hann window couples each mode to its neighbours)
LOW_MODE = 4
#: sampling rule: at least this many points per wavelength at the top (k <= 2 pi / (4 dx))
POINTS_PER_WAVELENGTH = 4
#: noise rule: the spectrum is used while it stays this many times above the white-noise floor
NOISE_MARGIN = 10.0
#: tip rule (Sanner et al. 2022): unreliable where the scale-dependent curvature < -0.5 / R_tip
TIP_SAFETY = 0.5
#: fewest periodogram values (or ring modes) averaged into one point of a binned spectrum
MIN_PER_BIN = 5
#: most dropouts (NaN) ``nan="interpolate"`` bridges
MAX_DROPOUT_FRACTION = 0.2
#: plausibility of a measured surface (a unit slip by 1e3 or 1e6 falls outside)
PLAUSIBLE_H_RMS = 1e-3  # m
PLAUSIBLE_SLOPE = (1e-6, 5.0)
#: a surface is flat when its detrended h_rms is below this fraction of its largest height
#: (float64 roundoff of the detrending is ~1e-16 of it)
FLAT_TOLERANCE = 1e-12

#: a usable range: "auto" (the rules), None (everything), or (lo, hi) in 1/m with None for a rule
QRange = Literal["auto"] | tuple[float | None, float | None] | None

_T = TypeVar("_T")

_INSTALL = 'pip install "fastline-contact[topography]" (the optional SurfaceTopography)'


# ----------------------------------------------------------------------------------------------
# shared stages: heights, dropouts, detrending, windows, binning, plausibility
# ----------------------------------------------------------------------------------------------
def _heights(h, ndim_allowed: tuple[int, ...]) -> np.ndarray:
    try:
        arr = np.array(h, dtype=np.float64)
    except (TypeError, ValueError):
        raise ValueError("h must be an array of real numbers (heights in m)") from None
    if arr.ndim not in ndim_allowed:
        dims = " or ".join(f"{d}-dimensional" for d in ndim_allowed)
        raise ValueError(f"h must be {dims}, got shape {arr.shape}")
    if np.any(np.isinf(arr)):
        raise ValueError("h must not contain inf")
    return arr


#: set while a caller recomputes what it has already analysed (and warned about) once
_QUIET: contextvars.ContextVar[bool] = contextvars.ContextVar("fastline_topography_quiet")


@contextlib.contextmanager
def _quiet():
    """Drop this module's TopographyWarnings inside the block. Unlike
    ``warnings.catch_warnings``, it leaves the warning filters alone: changing them (entering
    or leaving that context manager) clears the record of warnings already shown, so each call
    of a function using it would show the same warning again."""
    token = _QUIET.set(True)
    try:
        yield
    finally:
        _QUIET.reset(token)


def _warn(text: str, stacklevel: int) -> None:
    """A TopographyWarning, ``stacklevel`` counted from the caller of this function."""
    if not _QUIET.get(False):
        warnings.warn(text, TopographyWarning, stacklevel=stacklevel + 1)


def _fill_dropouts(h: np.ndarray, nan: str) -> np.ndarray:
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
    if frac > MAX_DROPOUT_FRACTION or bad.all(axis=-1).any():
        raise ValueError(
            f"h has {frac:.1%} NaN values (or a row without data): too many dropouts to bridge "
            f"(at most {MAX_DROPOUT_FRACTION:.0%})"
        )
    out = h.copy()
    j = np.arange(h.shape[-1])
    for row, miss in zip(out, bad, strict=True):
        if miss.any():
            row[miss] = np.interp(j[miss], j[~miss], row[~miss])
    return out


def _detrend_rows(h: np.ndarray, dx: float, how: str):
    """Rows minus their mean, line, parabola or circle; and the form's radius (m) or None."""
    n = h.shape[-1]
    t = (np.arange(n) - 0.5 * (n - 1)) / (0.5 * n)  # in [-1, 1]
    degree = {"mean": 0, "linear": 1, "parabola": 2, "circle": 2}[how]
    V = np.vander(t, degree + 1)
    coef, *_ = np.linalg.lstsq(V, h.T, rcond=None)
    residual = h - (V @ coef).T
    if how in ("mean", "linear"):
        return residual, None
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
    from scipy.optimize import least_squares

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


def _window(window, n: int) -> np.ndarray:
    """A window of n points normalised to ``sum w^2 = n`` (power-preserving)."""
    if window is None or (isinstance(window, str) and window.lower() in _RECTANGULAR):
        return np.ones(n)
    from scipy.signal import get_window

    try:
        w = np.asarray(get_window(window, n, fftbins=True), dtype=np.float64)
    except (ValueError, TypeError) as e:
        raise ValueError(
            f"window must be 'hann', 'none' or a scipy.signal window, got {window!r}: {e}"
        ) from None
    return w * math.sqrt(n / float(np.sum(w * w)))


_RECTANGULAR = ("none", "rect", "rectangular", "boxcar")


def _log_bins(x: np.ndarray, y: np.ndarray, per_decade: int, lo: float, hi: float):
    """Averages of y over bins of x equally spaced in log between lo and hi.

    Neighbouring bins are merged (from the low end) until each holds at least MIN_PER_BIN
    values: at the low end of a periodogram a bin of a twentieth of a decade holds one or no
    wavenumber, and the inverse Abel transform amplifies the scatter of single values.
    Each bin's value is the mean of its members; it is placed at ``x_eff = <x^s>^(1/s)``, where
    a power law of the local slope s (from the neighbouring bins) equals its mean, so that
    binning a power law is exact (the plain mean of x would bias C by ~0.5 % at 20 bins per
    decade for C ~ k^-2.6). Returns ``x_eff, mean y, members`` of the bins.
    """
    nb = max(1, math.ceil(per_decade * math.log10(hi / lo) - 1e-9))
    edges = np.geomspace(lo, hi, nb + 1)
    edges[-1] = hi * (1.0 + 1e-12)
    idx = np.searchsorted(edges, x, side="right") - 1
    inside = (idx >= 0) & (idx < nb)
    x, y = x[inside], y[inside]
    group = _merge_groups(np.bincount(idx[inside], minlength=nb), MIN_PER_BIN)
    idx = group[idx[inside]]
    ng = int(group[-1]) + 1
    counts = np.bincount(idx, minlength=ng)
    ybar = np.bincount(idx, weights=y, minlength=ng) / counts
    xbar = np.bincount(idx, weights=x, minlength=ng) / counts
    if ybar.size < 3 or np.any(ybar <= 0.0):
        return xbar, ybar, counts
    s = np.clip(np.gradient(np.log(ybar), np.log(xbar)), -8.0, 8.0)  # noise: no wild slopes
    ratio = x / xbar[idx]
    flat = np.abs(s) < 1e-4  # there <x^s>^(1/s) -> the geometric mean exp<ln x>
    power = np.where(flat[idx], np.log(ratio), ratio ** np.where(flat, 1.0, s)[idx])
    mean = np.bincount(idx, weights=power, minlength=ng) / counts
    x_eff = np.exp(mean)
    x_eff[~flat] = mean[~flat] ** (1.0 / s[~flat])
    return xbar * x_eff, ybar, counts


def _merge_groups(counts: np.ndarray, minimum: int) -> np.ndarray:
    """Group index of each bin: consecutive bins joined until a group holds >= minimum values
    (empty bins join their neighbours; a short last group joins the one before)."""
    group = np.empty(counts.size, dtype=np.intp)
    g, held = 0, 0
    for b, c in enumerate(counts):
        if held >= minimum:
            g, held = g + 1, 0
        group[b] = g
        held += c
    if held < minimum and g > 0:
        group[group == g] = g - 1
    return group


def _span(x: np.ndarray, y: np.ndarray, lo: float, hi: float):
    """Binned points continued to the ends of the range they represent, along the power law of
    the first and last pair of points (half a bin at most): the table then covers [lo, hi]."""
    if x.size < 2 or np.any(y <= 0.0):
        return x, y
    s0 = math.log(y[1] / y[0]) / math.log(x[1] / x[0])
    s1 = math.log(y[-1] / y[-2]) / math.log(x[-1] / x[-2])
    xs, ys = [x], [y]
    if lo < x[0]:
        xs.insert(0, [lo])
        ys.insert(0, [y[0] * (lo / x[0]) ** s0])
    if hi > x[-1]:
        xs.append([hi])
        ys.append([y[-1] * (hi / x[-1]) ** s1])
    return np.concatenate(xs), np.concatenate(ys)


def _refuse_flat(h_rms: float, h: np.ndarray, what: str, detrend: str) -> None:
    """A ValueError when the detrended heights are zero to roundoff (a constant or a plane
    surface has no roughness spectrum), before the plausibility check blames the units."""
    scale = float(np.nanmax(np.abs(h))) if np.any(np.isfinite(h)) else 0.0
    if h_rms <= FLAT_TOLERANCE * scale or h_rms == 0.0:
        form = "mean" if detrend == "mean" else f"{detrend} form"
        raise ValueError(
            f"the {what} is flat: after removing its {form} the heights vary by h_rms = "
            f"{h_rms:.3g} m, roundoff of heights up to {scale:.3g} m; a flat surface has no "
            "roughness spectrum (does the file hold the heights?)"
        )


def _check_plausible(h_rms: float, slope: float, what: str) -> None:
    """One TopographyWarning when h_rms or the rms slope says the units are off."""
    notes = []
    if h_rms > PLAUSIBLE_H_RMS:
        notes.append(f"h_rms = {h_rms:.3g} m is more than {PLAUSIBLE_H_RMS:g} m")
    if not PLAUSIBLE_SLOPE[0] <= slope <= PLAUSIBLE_SLOPE[1]:
        notes.append(
            f"the rms slope {slope:.3g} is outside [{PLAUSIBLE_SLOPE[0]:g}, {PLAUSIBLE_SLOPE[1]:g}]"
        )
    if notes:
        _warn(
            f"{what}: {' and '.join(notes)}: are the heights or the spacing in the wrong unit "
            "(e.g. micrometres read as metres)? Heights and spacings are in m.",
            stacklevel=3,
        )


def _range_argument(q_range, name="q_range"):
    """'auto' -> (None, None); None -> 'all'; (lo, hi) with None for automatic ends."""
    if isinstance(q_range, str):
        if q_range != "auto":
            raise ValueError(f"{name} must be 'auto', None or (lo, hi) in 1/m, got {q_range!r}")
        return None, None
    if q_range is None:
        return "all"
    try:
        lo, hi = q_range
    except (TypeError, ValueError):
        raise ValueError(
            f"{name} must be 'auto', None or (lo, hi) in 1/m, got {q_range!r}"
        ) from None
    lo = None if lo is None else positive(f"{name}[0]", lo, "1/m")
    hi = None if hi is None else positive(f"{name}[1]", hi, "1/m")
    if lo is not None and hi is not None and hi <= lo:
        raise ValueError(f"{name} must have lo < hi, got ({lo:g}, {hi:g})")
    return lo, hi


# ----------------------------------------------------------------------------------------------
# the usable wavenumber range
# ----------------------------------------------------------------------------------------------
def _tip_cutoff(h: np.ndarray, dx: float, tip_radius: float) -> float:
    """Wavenumber above which a stylus tip of this radius cannot follow the rows of h (1/m).

    Sanner, Nöhring, Schaeffer, Pastewka et al., Appl. Surf. Sci. Adv. 7, 100190 (2022),
    doi:10.1016/j.apsadv.2021.100190: a tip of radius R cannot enter valleys sharper than
    itself, so below the length ``lambda_c`` at which the most negative scale-dependent
    curvature ``(h(x + l) - 2 h(x) + h(x - l)) / l^2`` reaches ``-0.5 / R`` the data show the
    tip, not the surface. Here ``l`` runs over integer multiples of dx and ``lambda_c`` is the
    smallest one from which on the criterion holds; returns ``2 pi / lambda_c`` (inf if it
    holds at ``l = dx``).
    """
    n = h.shape[-1]
    steps = np.unique(np.geomspace(1, max(1, n // 8), 40).astype(int))
    limit = -TIP_SAFETY / tip_radius
    ok = np.array(
        [
            float(np.min(h[:, 2 * m :] - 2.0 * h[:, m:-m] + h[:, : -2 * m])) / (m * dx) ** 2
            >= limit
            for m in steps
        ]
    )
    if ok.all():
        return math.inf
    bad = int(np.flatnonzero(~ok)[-1])
    if bad == steps.size - 1:
        return 2.0 * math.pi / (steps[-1] * dx)
    return 2.0 * math.pi / (steps[bad + 1] * dx)


def _noise_cutoff(k: np.ndarray, C: np.ndarray, floor: float) -> float:
    """The first k at which the (binned) spectrum falls below NOISE_MARGIN x the floor."""
    below = np.flatnonzero(C < NOISE_MARGIN * floor)
    return math.inf if below.size == 0 else float(k[below[0]])


def _usable(k_low: float, k_sampling: float, k_tip: float, k_noise: float, given, measured):
    """The range rule: (lo, hi) and which rule set each end; ``given`` ends override the rule
    but must lie inside the ``measured`` wavenumbers (2 pi / L .. pi / dx)."""
    lo_given, hi_given = given
    for end in (lo_given, hi_given):
        if end is not None and not measured[0] <= end <= measured[1] * (1 + 1e-12):
            raise ValueError(
                f"q_range end {end:g} 1/m lies outside the measured wavenumbers "
                f"[{measured[0]:.4g}, {measured[1]:.4g}] 1/m (2 pi / L to pi / dx)"
            )
    lo, lo_why = (lo_given, "given") if lo_given is not None else (k_low, "scan length")
    if hi_given is not None:
        hi, hi_why = hi_given, "given"
    else:
        hi, hi_why = min((k_sampling, "sampling"), (k_tip, "tip radius"), (k_noise, "noise floor"))
    if hi <= lo:
        raise ValueError(
            f"no usable wavenumbers: the range [{lo:.3g}, {hi:.3g}] 1/m is empty ({lo_why} / "
            f"{hi_why}); a longer scan, a finer sampling or an explicit q_range is needed"
        )
    return (float(lo), float(hi)), {"low": lo_why, "high": hi_why}


# ----------------------------------------------------------------------------------------------
# profiles
# ----------------------------------------------------------------------------------------------
@dataclass(frozen=True)
class ProfileSpectrum:
    """The 1D spectrum of one or more parallel profiles; unpacks as ``k, C1D = ...``.

    Attributes
    ----------
    k : ndarray
        Wavenumbers in 1/m (bin locations, or the Fourier wavenumbers ``2 pi m / L``).
    C1D : ndarray
        Two-sided 1D spectrum in m^3, ``h_rms^2 = 2 int_0^inf C1D dk``.
    counts : ndarray
        Periodogram values averaged into each point, per profile (1 unbinned; 0 for the two
        end points, which continue the first and last bins to the ends of ``q_range``).
    q_range : tuple of float
        The usable range (1/m) the spectrum was cut to, and ``limits`` the rule that set each
        end (``"scan length"``, ``"sampling"``, ``"tip radius"``, ``"noise floor"``, ``"given"``).
    h_rms, rms_slope : float
        Of the detrended heights (m, dimensionless), all profiles together.
    n_profiles, dx, length : int, float, float
        Profiles averaged, spacing (m) and length ``N dx`` (m).
    window, detrend : str
        As used; ``form_radius`` (m) is the fitted radius for ``detrend="parabola"/"circle"``.
    window_factor : float
        ``N sum w^4 / (sum w^2)^2`` of the window: neighbouring periodogram values of a
        windowed profile are correlated, and a mean of n of them scatters like a mean of
        ``n / window_factor`` independent ones (1 without a window, 35/18 for Hann).
    """

    k: np.ndarray
    C1D: np.ndarray
    counts: np.ndarray
    q_range: tuple[float, float]
    limits: dict = field(repr=False)
    h_rms: float
    rms_slope: float
    n_profiles: int
    dx: float
    length: float
    window: str
    detrend: str
    form_radius: float | None = None
    window_factor: float = 1.0

    def __iter__(self) -> Iterator[np.ndarray]:
        return iter((self.k, self.C1D))

    def isotropic(self, **options: Any) -> TabulatedPSD:
        """The isotropic 2D spectrum, ``isotropic_from_1d(k, C1D, **options)``."""
        return isotropic_from_1d(self.k, self.C1D, **options)


_DETRENDS = ("mean", "linear", "parabola", "circle")


def _choice(name: str, value: _T, allowed: tuple[str, ...]) -> _T:
    if value not in allowed:
        raise ValueError(f"{name} must be one of {', '.join(map(repr, allowed))}, got {value!r}")
    return value


def _periodogram(h: np.ndarray, dx: float, w: np.ndarray):
    """``k_m, C1D(k_m)`` for m = 1 .. N//2, averaged over the rows (module docstring)."""
    n = h.shape[-1]
    L = n * dx
    F = np.fft.rfft(h * w, axis=-1)
    C = (dx * dx / (2.0 * math.pi * L)) * np.mean(np.abs(F) ** 2, axis=0)
    k = 2.0 * math.pi * np.arange(F.shape[-1]) / L
    return k[1:], C[1:]


def _profile_range(k, C, rows, dx, given, tip, noise):
    """The usable range of a periodogram (k, C) of rows at spacing dx, and its reasons."""
    measured = (float(k[0]), float(k[-1]))
    if given == "all":
        return measured, {"low": "all", "high": "all"}
    k_noise = math.inf
    if noise is not None:
        kb, Cb, _ = _log_bins(k, C, 20, k[0], k[-1])
        k_noise = _noise_cutoff(kb, Cb, noise * noise * dx / (2.0 * math.pi))
    return _usable(
        LOW_MODE * 2.0 * math.pi / (rows.shape[-1] * dx),
        2.0 * math.pi / (POINTS_PER_WAVELENGTH * dx),
        math.inf if tip is None else _tip_cutoff(rows, dx, tip),
        k_noise,
        given,
        measured,
    )


def _profile_points(k, C, q_rng, bins_per_decade):
    """The periodogram cut to q_rng, raw or binned with its end points; and the counts."""
    if bins_per_decade is None:
        keep = (k >= q_rng[0] * (1 - 1e-12)) & (k <= q_rng[1] * (1 + 1e-12))
        k, C, counts = k[keep], C[keep], np.ones(int(keep.sum()), dtype=int)
    else:
        kb, C, counts = _log_bins(k, C, bins_per_decade, *q_rng)
        k, C = _span(kb, C, *q_rng)
        counts = np.concatenate([[0] * int(k[0] < kb[0]), counts, [0] * int(k[-1] > kb[-1])])
    if k.size < 2:
        raise ValueError(f"the usable range {q_rng} 1/m holds fewer than 2 spectrum points")
    return k, C, counts


def psd_from_profile(
    h: ArrayLike,
    dx: float,
    *,
    window: str | None = "hann",
    detrend: Literal["linear", "mean", "parabola", "circle"] = "linear",
    nan: Literal["raise", "interpolate"] = "raise",
    bins_per_decade: int | None = 20,
    q_range: QRange = "auto",
    tip_radius: float | None = None,
    noise: float | None = None,
) -> ProfileSpectrum:
    """The 1D spectrum of a height profile, or the average over parallel profiles.

    ``C1D(k_m) = dx^2 / (2 pi L) |sum_j w_j h_j exp(-i k_m x_j)|^2`` with ``k_m = 2 pi m / L``
    and ``sum w_j^2 = N``: two-sided, ``h_rms^2 = 2 int_0^inf C1D dk`` (docs/theory.md
    section 2). With the rectangular window, ``sum_m C1D(k_m) 2 pi / L`` over all m equals the
    mean square of the detrended heights exactly (Parseval).

    Parameters
    ----------
    h : array_like
        Heights in m: one profile (N,) or parallel profiles (P, N), averaged. At least
        MIN_POINTS = 32 points per profile.
    dx : float
        Spacing in m (> 0).
    window : str or None
        ``"hann"`` (default), ``"none"``, or a name :func:`scipy.signal.get_window` knows;
        normalised to ``sum w^2 = N``. A window keeps the jump between the two ends of a
        non-periodic profile from leaking power ~k^-2 into steeper spectra.
    detrend : {"linear", "mean", "parabola", "circle"}
        Removed from each profile before the window. ``"parabola"`` and ``"circle"`` take out a
        cylinder's own form (its radius is reported as ``form_radius``).
    nan : {"raise", "interpolate"}
        NaN heights (instrument dropouts) are refused, or bridged by straight lines (at most
        20 % of the points; this removes a little high-k power in proportion to the bridged
        fraction).
    bins_per_decade : int or None
        Average the periodogram over bins equally spaced in log k (default 20; each value is
        placed where a power law equals the bin mean; bins are merged to hold at least
        MIN_PER_BIN = 5 values; two end points continue the first and last bins to the ends of
        the range), or None for the raw periodogram.
    q_range : "auto", None or (lo, hi)
        The usable range the spectrum is cut to. ``"auto"``: from ``LOW_MODE x 2 pi / L``
        (the first modes carry the detrending's and the window's distortion) to the lowest of
        the sampling limit ``2 pi / (4 dx)`` (four points per wavelength), the stylus-tip
        limit (``tip_radius`` given; Sanner et al. 2022) and the noise limit (``noise`` given:
        where C1D falls below 10 times the white-noise floor ``noise^2 dx / (2 pi)``). None:
        the whole periodogram ``2 pi / L .. pi / dx``. A pair overrides either end (None keeps
        the rule).
    tip_radius : float, optional
        Stylus tip radius in m.
    noise : float, optional
        rms instrument noise in m.

    Returns
    -------
    ProfileSpectrum
        Unpacks as ``k, C1D``; also the range used, the counts per point and the data's h_rms.

    Warns
    -----
    TopographyWarning
        When h_rms > 1 mm or the rms slope is outside [1e-6, 5]: a unit slip.
    """
    h = _heights(h, (1, 2))
    rows = np.atleast_2d(h)
    dx = positive("dx", dx, "m")
    if rows.shape[-1] < MIN_POINTS:
        raise ValueError(
            f"h must hold at least {MIN_POINTS} points per profile, got {rows.shape[-1]}"
        )
    detrend = _choice("detrend", detrend, _DETRENDS)
    nan = _choice("nan", nan, ("raise", "interpolate"))
    if bins_per_decade is not None:
        bins_per_decade = integer("bins_per_decade", bins_per_decade, 2)
    given = _range_argument(q_range)
    tip = None if tip_radius is None else positive("tip_radius", tip_radius, "m")
    noise = None if noise is None else positive("noise", noise, "m")
    w = _window(window, rows.shape[-1])  # checks the name before any work

    raw = _fill_dropouts(rows, nan)
    _refuse_flat(float(np.std(raw)), raw, "profile", "mean")  # before a form fit divides by 0
    rows, radius = _detrend_rows(raw, dx, detrend)
    h_rms = float(np.sqrt(np.mean(rows**2)))
    _refuse_flat(h_rms, raw, "profile", detrend)
    slope = float(np.sqrt(np.mean((np.diff(rows, axis=-1) / dx) ** 2)))
    _check_plausible(h_rms, slope, "psd_from_profile")
    k, C = _periodogram(rows, dx, w)
    L = rows.shape[-1] * dx
    q_rng, limits = _profile_range(k, C, rows, dx, given, tip, noise)
    k, C, counts = _profile_points(k, C, q_rng, bins_per_decade)
    return ProfileSpectrum(
        k=k,
        C1D=C,
        counts=counts,
        q_range=q_rng,
        limits=limits,
        h_rms=h_rms,
        rms_slope=slope,
        n_profiles=rows.shape[0],
        dx=dx,
        length=L,
        window="none" if window is None else str(window),
        detrend=detrend,
        form_radius=radius,
        window_factor=float(w.size * np.sum(w**4) / np.sum(w * w) ** 2),
    )


# ----------------------------------------------------------------------------------------------
# 1D -> isotropic 2D, and power-law extensions
# ----------------------------------------------------------------------------------------------
def _table(
    name_q: str, q: ArrayLike, name_c: str, C: ArrayLike, *, positive_values: bool
) -> tuple[np.ndarray, np.ndarray]:
    q = real_array(name_q, q)
    C = real_array(name_c, C)
    if q.ndim != 1 or C.shape != q.shape:
        raise ValueError(f"{name_q} and {name_c} must be 1-dimensional and of equal length")
    if q.size < 3:
        raise ValueError(f"{name_q} must hold at least 3 points, got {q.size}")
    if not (np.all(np.isfinite(q)) and np.all(np.isfinite(C))):
        raise ValueError(f"{name_q} and {name_c} must be finite (no NaN or inf)")
    if q[0] <= 0.0 or np.any(np.diff(q) <= 0.0):
        raise ValueError(f"{name_q} must be > 0 and strictly increasing (1/m)")
    if positive_values and np.any(C <= 0.0):
        raise ValueError(
            f"{name_c} must be > 0 everywhere (it is interpolated on a log scale): cut the "
            "spectrum to where it is positive"
        )
    return q, C


def _loglog_slope(q: np.ndarray, C: np.ndarray, decades: float) -> float:
    """Least-squares slope of ln C against ln q over the top ``decades`` (>= 3 points),
    each point weighted by the log-q interval it covers."""
    top = q >= q[-1] / 10.0**decades
    if top.sum() < 3:
        top = np.arange(q.size) >= q.size - 3
    x, y = np.log(q[top]), np.log(C[top])
    wts = np.gradient(x) if x.size > 1 else np.ones_like(x)
    xm = np.average(x, weights=wts)
    ym = np.average(y, weights=wts)
    return float(np.sum(wts * (x - xm) * (y - ym)) / np.sum(wts * (x - xm) ** 2))


def isotropic_from_1d(
    k: ArrayLike,
    C1D: ArrayLike,
    *,
    tail: Literal["fit", "zero"] | float = "fit",
    tail_decades: float = 0.5,
    q1: float | None = None,
) -> TabulatedPSD:
    """The isotropic 2D spectrum C(q) of the surface a 1D spectrum was measured on.

    The exact inverse Abel transform (docs/theory.md section 2)
    ``C(q) = -(1/pi) int_q^inf C1D'(k) / sqrt(k^2 - q^2) dk`` at every point ``q = k_i``: between
    the points ``ln C1D`` is a monotone cubic in ``ln k`` (no overshoot, continuous slope), and
    ``k = q cosh(theta)`` removes the inverse-square-root singularity exactly
    (:mod:`fastline.surfaces.abel`). Not the shortcut ``C = C1D / (2q)``, which is exact only for a
    power law with H = 1/2 (14.6 % low at H = 0.8, 21.5 % low at H = 1).

    Parameters
    ----------
    k, C1D : array_like
        Wavenumbers (1/m, > 0, increasing, >= 3 points) and the two-sided 1D spectrum
        (m^3, > 0) as :func:`psd_from_profile` returns them (``*spectrum`` works).
    tail : "fit", "zero" or float
        C1D beyond the last point: the power law fitted to the top ``tail_decades`` (default;
        its exponent must be < -1), zero (a band-limited surface), or a given exponent < -1.
        C(q) near the top depends on it; the measured range is what the tail continues.
    q1 : float, optional
        Cut the result at q1, or extend it to q1 by the power law fitted to its top half decade
        (:func:`extend_psd`), as for a spectrum measured to 1e6 1/m used to q1 = 1e9 1/m.

    Returns
    -------
    TabulatedPSD
        C(q) in Persson's convention (m^4), ``h_rms^2 = 2 pi int q C dq``, on the points k.

    Warns
    -----
    TopographyWarning
        When noise makes C(q) <= 0 at some points; they are left out.
    """
    k, C1D = _table("k", k, "C1D", C1D, positive_values=True)
    if isinstance(tail, str):
        _choice("tail", tail, ("fit", "zero"))
        if tail == "zero":
            slope = None
        else:
            decades = positive("tail_decades", tail_decades)
            slope = _loglog_slope(k, C1D, decades)
            if slope >= -1.0:
                raise ValueError(
                    f"the top of C1D does not fall off (fitted exponent {slope:.3g} >= -1 over "
                    f"the top {decades:g} decades): it is noise or instrument floor. Cut the "
                    "spectrum below it (q_range) or pass tail='zero' or an exponent < -1"
                )
    else:
        slope = finite_scalar("tail", tail)
        if slope >= -1.0:
            raise ValueError(f"tail must be an exponent < -1 (or 'fit', 'zero'), got {slope!r}")
    C = inverse_abel(k, C1D, slope)
    good = C > 0.0
    if not good.all():
        _warn(
            f"isotropic_from_1d: C(q) <= 0 at {int((~good).sum())} of {k.size} points (noise "
            "in C1D); they are left out. Fewer bins per decade or more profiles help.",
            stacklevel=2,
        )
    if good.sum() < 2:
        raise ValueError("the inverse transform left fewer than 2 positive values of C(q)")
    psd = TabulatedPSD(k[good], C[good])
    return psd if q1 is None else extend_psd(psd, q1)


def extend_psd(
    psd: TabulatedPSD, q1: float, *, fit_decades: float = 0.5, hurst: float | None = None
) -> TabulatedPSD:
    """The table cut at q1, or continued to q1 by a power law (20 points per decade).

    The exponent is the least-squares slope of ln C against ln q over the top
    ``fit_decades`` of the table, or ``-2(1 + hurst)`` if hurst is given; it must describe a
    self-affine spectrum (H > 0, i.e. C falling faster than q^-2).

    Parameters
    ----------
    psd : TabulatedPSD
        Measured isotropic spectrum.
    q1 : float
        New upper cut-off in 1/m.
    fit_decades : float
        Range of the fit (default the top half decade).
    hurst : float, optional
        Hurst exponent in (0, 1] of the continuation instead of the fit.
    """
    if not isinstance(psd, TabulatedPSD):
        raise TypeError(f"psd must be a TabulatedPSD, got {type(psd).__name__}")
    q1 = positive("q1", q1, "1/m")
    if not WAVENUMBER_RANGE[0] <= q1 <= WAVENUMBER_RANGE[1] or q1 <= psd.q0:
        raise ValueError(f"q1 must lie in ({psd.q0:g}, {WAVENUMBER_RANGE[1]:g}] 1/m, got {q1!r}")
    live = psd.C > 0.0
    q, C = psd.q[live], psd.C[live]
    if q1 <= q[-1]:
        keep = q < q1
        return TabulatedPSD(np.append(q[keep], q1), np.append(C[keep], psd(q1)))
    if hurst is None:
        slope = _loglog_slope(q, C, positive("fit_decades", fit_decades))
        if slope >= -2.0:
            raise ValueError(
                f"the top of the spectrum falls like q^{slope:.3g} (H = {-slope / 2 - 1:.3g} "
                "<= 0): a continuation to q1 would not converge; pass hurst= or a lower q1"
            )
    else:
        H = finite_scalar("hurst", hurst)
        if not 0.0 < H <= 1.0:
            raise ValueError(f"hurst must lie in (0, 1], got {H!r}")
        slope = -2.0 * (1.0 + H)
    n = max(2, math.ceil(20.0 * math.log10(q1 / q[-1])))
    q_new = np.geomspace(q[-1], q1, n + 1)[1:]
    return TabulatedPSD(
        np.concatenate([q, q_new]), np.concatenate([C, C[-1] * (q_new / q[-1]) ** slope])
    )


# ----------------------------------------------------------------------------------------------
# maps
# ----------------------------------------------------------------------------------------------
def _detrend_map(h: np.ndarray, how: str) -> np.ndarray:
    if how == "mean":
        return h - h.mean()
    ny, nx = h.shape
    y, x = np.mgrid[0:ny, 0:nx]
    V = np.column_stack([np.ones(h.size), (x.ravel() - 0.5 * nx) / nx, (y.ravel() - 0.5 * ny) / ny])
    coef, *_ = np.linalg.lstsq(V, h.ravel(), rcond=None)
    return h - (V @ coef).reshape(h.shape)


def _map_modes(maps, dx: float, dy: float, w: np.ndarray):
    """|q| and C of every Fourier mode, averaged over the maps (module docstring)."""
    ny, nx = maps[0].shape
    power = np.mean([np.abs(np.fft.fft2(m * w)) ** 2 for m in maps], axis=0)
    C = (dx * dy) ** 2 / ((2.0 * math.pi) ** 2 * (nx * dx * ny * dy)) * power
    qx = 2.0 * math.pi * np.fft.fftfreq(nx, dx)
    qy = 2.0 * math.pi * np.fft.fftfreq(ny, dy)
    return np.hypot(qy[:, None], qx[None, :]).ravel(), C.ravel()


def _map_range(q, C, maps, dx, dy, given, tip, noise):
    """The usable range of a map's modes (the profile rule with L = min(Lx, Ly) and
    dx = max(dx, dy); full rings only up to pi / max(dx, dy))."""
    ny, nx = maps[0].shape
    measured = (2.0 * math.pi / max(nx * dx, ny * dy), math.pi / max(dx, dy))
    if given == "all":
        return measured
    k_noise = math.inf
    if noise is not None:
        qb, Cb, _ = _log_bins(q, C, 20, *measured)
        k_noise = _noise_cutoff(qb, Cb, noise * noise * dx * dy / (2.0 * math.pi) ** 2)
    (lo, hi), _ = _usable(
        LOW_MODE * 2.0 * math.pi / min(nx * dx, ny * dy),
        2.0 * math.pi / (POINTS_PER_WAVELENGTH * max(dx, dy)),
        math.inf if tip is None else _tip_cutoff(np.concatenate(maps), dx, tip),
        k_noise,
        given,
        measured,
    )
    return lo, hi


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
    h = _heights(h, (2, 3))
    stack = h if h.ndim == 3 else h[None]
    dx = positive("dx", dx, "m")
    dy = dx if dy is None else positive("dy", dy, "m")
    if min(stack.shape[1:]) < MIN_POINTS:
        raise ValueError(
            f"h must hold at least {MIN_POINTS} points in each direction, got shape {h.shape}"
            + (" (a single row is a profile: use psd_from_profile)" if 1 in h.shape[-2:] else "")
        )
    detrend = _choice("detrend", detrend, ("plane", "mean"))
    nan = _choice("nan", nan, ("raise", "interpolate"))
    bins_per_decade = integer("bins_per_decade", bins_per_decade, 2)
    given = _range_argument(q_range)
    tip = None if tip_radius is None else positive("tip_radius", tip_radius, "m")
    noise = None if noise is None else positive("noise", noise, "m")
    ny, nx = stack.shape[1:]
    w = _window(window, ny)[:, None] * _window(window, nx)[None, :]

    maps = [_detrend_map(_fill_dropouts(m, nan), detrend) for m in stack]
    h_rms = float(np.sqrt(np.mean([np.mean(m**2) for m in maps])))
    _refuse_flat(h_rms, stack, "map", detrend)
    h = maps[0]
    slope = float(
        np.sqrt(np.mean((np.diff(h, axis=1) / dx) ** 2) + np.mean((np.diff(h, axis=0) / dy) ** 2))
    )
    _check_plausible(h_rms, slope, "psd_from_map")
    q, C = _map_modes(maps, dx, dy, w)
    lo, hi = _map_range(q, C, maps, dx, dy, given, tip, noise)
    qb, Cb, _ = _log_bins(q, C, bins_per_decade, lo, hi)
    qb, Cb = _span(qb, Cb, lo, hi)
    if qb.size < 2:
        raise ValueError(f"the usable range ({lo:.3g}, {hi:.3g}) 1/m holds fewer than 2 rings")
    psd = TabulatedPSD(qb, Cb)
    return psd if q1 is None else extend_psd(psd, q1)


# ----------------------------------------------------------------------------------------------
# the self-affine model fitted to a measured spectrum
# ----------------------------------------------------------------------------------------------
_HURST_BOUNDS = (0.01, 1.0)
#: a roll-off counts as measured only when it lies at least this factor (a fifth of a decade)
#: above the lowest fitted wavenumber. Below that its flat part would rest on the lowest one or
#: two points, which average the fewest values (bins merged to MIN_PER_BIN: at the default
#: LOW_MODE the first one spans modes 4-8, a factor 2) and scatter most: there a power law
#: whose roll-off lies below the range is fitted with a kink at those points (the 2026-11-22
#: audit: a map with q_r = 3e4 1/m gave 5.2e4 1/m, 6 % above the range's low end, as measured).
ROLLOFF_MARGIN = 10.0**0.2
#: ... and only when it improves the fit over a pure power law by more than this: the likelihood
#: ratio (a ProfileSpectrum) or F statistic (a table) of the roll-off, against the 99 % point of
#: chi-squared with one degree of freedom. A roll-off the data do not ask for is not measured:
#: one profile of 2048 points from a surface whose q_r lies below the range gave a likelihood
#: ratio above 4.2 in 1 % of 256 cases, one whose q_r lies 3x above the range's low end a
#: median of 3-4 (such a profile barely shows it), 8x above it a median of 50.
ROLLOFF_SIGNIFICANCE = 6.63


@dataclass(frozen=True)
class SelfAffineFit:
    """A :class:`~fastline.SelfAffinePSD` fitted to a spectrum, with standard errors.

    Attributes
    ----------
    psd : SelfAffinePSD
        The model, on the measured range ``[q0, q1]`` unless others were given.
    h_rms, hurst, qr, C0 : float
        Its parameters (m, -, 1/m, m^4); ``*_err`` their standard errors (same units; ``qr_err``
        is NaN when q_r is not resolved).
    rms_residual : float
        rms of ``ln(C / C_model)`` over the fitted points (0.1 = 10 % scatter).
    n_points : int
        Points fitted; ``q_range`` their range (1/m).
    at_bound : bool
        A parameter was not measured: ``hurst_at_bound`` or ``qr_at_bound``.
    fitted_to : {"C(q)", "C1D(k)"}
        What the model was fitted to: an isotropic spectrum (a table, a map), or the 1D spectrum
        of line scans (a :class:`ProfileSpectrum`).
    hurst_at_bound : bool
        H hit its bound (0.01 or 1): the spectrum is steeper or flatter than self-affine.
    qr_at_bound : bool
        The roll-off is not resolved (it may lie anywhere below the data), so q_r and h_rms are
        not measurements: q_r lies within ``ROLLOFF_MARGIN`` of the lowest fitted wavenumber,
        or the roll-off improves the fit by less than ``ROLLOFF_SIGNIFICANCE``.
    rolloff_gain : float
        That improvement: the likelihood ratio (``2 ln`` of it, over the dispersion) of the
        model against a pure power law (fitted to C1D), or the F statistic of its sum of
        squares (fitted to C(q)); 0 without roll-off.
    """

    psd: SelfAffinePSD
    h_rms: float
    hurst: float
    qr: float
    C0: float
    h_rms_err: float
    hurst_err: float
    qr_err: float
    rms_residual: float
    n_points: int
    q_range: tuple[float, float]
    at_bound: bool
    fitted_to: str = "C(q)"
    hurst_at_bound: bool = False
    qr_at_bound: bool = False
    rolloff_gain: float = 0.0


def _fit_at(x, y, wts, xr):
    """Weighted least squares of ``y = a + b max(x - xr, 0)`` with ``b = -2(1+H)`` and H in its
    bounds; returns a, H, sum of weighted squared residuals."""
    r = np.maximum(x - xr, 0.0)
    X = np.column_stack([np.ones_like(x), r])
    a, b = np.linalg.lstsq(X * np.sqrt(wts)[:, None], y * np.sqrt(wts), rcond=None)[0]
    H = -0.5 * b - 1.0
    if not _HURST_BOUNDS[0] <= H <= _HURST_BOUNDS[1]:
        H = min(max(H, _HURST_BOUNDS[0]), _HURST_BOUNDS[1])
        b = -2.0 * (1.0 + H)
        a = float(np.average(y - b * r, weights=wts))
    res = y - a - b * r
    return a, H, float(np.sum(wts * res * res))


def _model_h_rms(lnC0, H, lnqr, q0, q1) -> float:
    qr = math.exp(lnqr)
    tail = -math.expm1(-2.0 * H * math.log(q1 / qr)) / (2.0 * H)
    return math.sqrt(2.0 * math.pi * math.exp(lnC0) * (0.5 * (qr * qr - q0 * q0) + qr * qr * tail))


def _fit_points(psd, q_range):
    """(q, C) of a measured spectrum with C > 0 inside q_range, and its whole q range."""
    if isinstance(psd, TabulatedPSD):
        q_all, C_all = psd.q, psd.C
    elif isinstance(psd, PSD):
        raise TypeError(
            "psd must be a TabulatedPSD or a (q, C) pair, or a ProfileSpectrum "
            "(a measured spectrum)"
        )
    else:
        try:
            q_all, C_all = psd
        except (TypeError, ValueError):
            raise TypeError(
                "psd must be a TabulatedPSD or a (q, C) pair, or a ProfileSpectrum"
            ) from None
        q_all, C_all = _table("q", q_all, "C", C_all, positive_values=False)
    lo, hi = (None, None) if q_range is None else _range_argument(q_range)
    keep = (C_all > 0.0) & (q_all >= (lo or 0.0)) & (q_all <= (hi or np.inf))
    if keep.sum() < 4:
        raise ValueError(f"need at least 4 points with C > 0 in the fitted range, got {keep.sum()}")
    live = q_all[C_all > 0.0]
    return q_all[keep], C_all[keep], (float(live[0]), float(live[-1]))


def _best_rolloff(x, y, wts) -> float:
    """ln qr minimising the profile least squares: a scan of 200 values, then Brent."""
    from scipy.optimize import minimize_scalar

    grid = np.linspace(x[0], x[-3], 200)
    sse = np.array([_fit_at(x, y, wts, g)[2] for g in grid])
    j = int(np.argmin(sse))
    a, b = grid[max(j - 1, 0)], grid[min(j + 1, grid.size - 1)]
    if b <= a:
        return float(grid[j])
    res = minimize_scalar(
        lambda g: _fit_at(x, y, wts, g)[2], bounds=(a, b), method="bounded", options={"xatol": 1e-6}
    )
    return float(res.x)


def _covariance(x, wts, H, xr, sse, free) -> np.ndarray:
    """Covariance of (ln C0, H, ln qr) from the Jacobian of the model (``free`` columns)."""
    J = np.column_stack(
        [np.ones_like(x), -2.0 * np.maximum(x - xr, 0.0), 2.0 * (1.0 + H) * (x > xr)]
    )[:, free]
    cov = np.zeros((3, 3))
    s2 = sse / max(x.size - len(free), 1)
    cov[np.ix_(free, free)] = s2 * np.linalg.pinv(J.T @ (wts[:, None] * J))
    return cov


# the 1D route: the model's C1D fitted to the periodogram of line scans
def _c1d_shape(k, H, lnqr):
    """C1D(k) / C0 of the self-affine model with roll-off (continued as a power law above the
    data), the forward Abel transform ``C1D = 2 int_k^inf C q / sqrt(q^2 - k^2) dq`` in closed
    form. With ``kappa = k / qr``, ``B = B(H + 1/2, 1/2)`` and ``I_x`` the regularised
    incomplete beta function::

        kappa >= 1:  qr B kappa^-(1+2H)
        kappa <  1:  qr [2 sqrt(1 - kappa^2) + B kappa^-(1+2H) I_kappa^2(H + 1/2, 1/2)]

    (substitute ``u = (k/q)^2`` in the power-law part). H and lnqr broadcast against k.
    """
    from scipy.special import beta, betainc

    qr = np.exp(lnqr)
    kappa = k / qr
    s = np.minimum(kappa * kappa, 1.0)
    power = beta(H + 0.5, 0.5) * kappa ** (-1.0 - 2.0 * H) * betainc(H + 0.5, 0.5, s)
    return qr * (2.0 * np.sqrt(1.0 - s) + power)


def _whittle(C, n, g):
    """(ln C0, objective) of the spectrum ``S = C0 g`` for bin means C of n periodogram values:
    the Whittle (gamma) log-likelihood ``-sum n (ln S + C / S)`` maximised over C0 in closed
    form, ``C0 = sum(n C / g) / sum(n)``. g may carry leading grid axes."""
    C0 = np.sum(n * C / g, axis=-1) / np.sum(n)
    return np.log(C0), np.sum(n * np.log(g), axis=-1) + np.sum(n) * np.log(C0)


def _whittle_optimum(k, C, n, rolloff: bool) -> tuple[float, float, float, float]:
    """(ln C0, H, ln qr, objective) of the best model: a grid over H (and ln qr between the
    lowest and the third-highest point, or ln qr at the lowest point without roll-off), refined
    by L-BFGS-B."""
    from scipy.optimize import minimize

    x = np.log(k)
    Hs = np.linspace(*_HURST_BOUNDS, 100)
    xrs = np.linspace(x[0], x[-3], 60) if rolloff else np.array([x[0]])
    _, obj = _whittle(C, n, _c1d_shape(k, Hs[:, None, None], xrs[None, :, None]))
    i, j = np.unravel_index(int(np.argmin(obj)), obj.shape)
    if rolloff:
        res = minimize(
            lambda p: float(_whittle(C, n, _c1d_shape(k, p[0], p[1]))[1]),
            [Hs[i], xrs[j]],
            method="L-BFGS-B",
            bounds=[_HURST_BOUNDS, (x[0], x[-3])],
        )
        H, xr = (float(v) for v in res.x)
    else:
        res = minimize(
            lambda p: float(_whittle(C, n, _c1d_shape(k, p[0], x[0]))[1]),
            [Hs[i]],
            method="L-BFGS-B",
            bounds=[_HURST_BOUNDS],
        )
        H, xr = float(res.x[0]), float(x[0])
    a, objective = _whittle(C, n, _c1d_shape(k, H, xr))
    return float(a), H, xr, float(objective)


def _whittle_covariance(k, C, n, p, free) -> tuple[np.ndarray, float, float]:
    """Covariance of (ln C0, H, ln qr) (``free`` ones), the rms of ``ln(C / S)``, dispersion.

    The inverse Fisher information of the Whittle likelihood, ``(J^T diag(n) J)^-1`` with J the
    derivatives of ln S (central differences), times the dispersion: the larger of 1 (a
    Gaussian surface, n counting independent values) and the observed
    ``sum n (C/S - 1)^2 / (points - parameters)`` (a spectrum that the model does not follow)."""

    def ln_s(q):
        return q[0] + np.log(_c1d_shape(k, q[1], q[2]))

    step = 1e-5
    J = np.column_stack([(ln_s(p + d) - ln_s(p - d)) / (2.0 * step) for d in np.eye(3) * step])
    J = J[:, free]
    ratio = C / np.exp(ln_s(p))
    dispersion = max(1.0, float(np.sum(n * (ratio - 1.0) ** 2)) / max(k.size - len(free), 1))
    cov = np.zeros((3, 3))
    cov[np.ix_(free, free)] = dispersion * np.linalg.pinv(J.T @ (n[:, None] * J))
    return cov, float(np.sqrt(np.mean(np.log(ratio) ** 2))), dispersion


def _profile_fit_points(spectrum, q_range):
    """(k, C1D, n) of the measured points (the two end points continue the bins: left out)
    inside q_range; n the equivalent number of independent periodogram values of each."""
    lo, hi = (None, None) if q_range is None else _range_argument(q_range)
    k, C = spectrum.k, spectrum.C1D
    keep = (spectrum.counts > 0) & (C > 0.0) & (k >= (lo or 0.0)) & (k <= (hi or np.inf))
    if keep.sum() < 4:
        raise ValueError(
            f"need at least 4 points with C1D > 0 in the fitted range, got {keep.sum()}"
        )
    n = spectrum.counts[keep] * spectrum.n_profiles / spectrum.window_factor
    return k[keep], C[keep], n.astype(np.float64)


def _fit_profile(spectrum, q_range, rolloff):
    """(ln C0, H, ln qr, covariance, rms residual, fitted k) of the model's C1D fitted to a
    ProfileSpectrum by the Whittle likelihood."""
    k, C, n = _profile_fit_points(spectrum, q_range)
    a, H, xr, objective = _whittle_optimum(k, C, n, rolloff)
    at_bound = H in _HURST_BOUNDS
    free = [c for c in (0, 1, 2) if not (c == 1 and at_bound) and not (c == 2 and not rolloff)]
    cov, rms, dispersion = _whittle_covariance(k, C, n, np.array([a, H, xr]), free)
    gain = 0.0
    if rolloff:  # the likelihood ratio against a pure power law, in units of the dispersion
        gain = 2.0 * (_whittle_optimum(k, C, n, False)[3] - objective) / dispersion
    return a, H, xr, cov, rms, k, gain


def _fit_table(psd, q_range, rolloff):
    """(ln C0, H, ln qr, covariance, rms residual, fitted q) of the model fitted to ln C by
    least squares, each point weighted by the interval of ln q it covers."""
    q, C, _ = _fit_points(psd, q_range)
    x, y = np.log(q), np.log(C)
    wts = np.gradient(x)
    wts = wts / wts.mean()
    xr = _best_rolloff(x, y, wts) if rolloff else float(x[0])
    a, H, sse = _fit_at(x, y, wts, xr)
    at_bound = H in _HURST_BOUNDS
    free = [c for c in (0, 1, 2) if not (c == 1 and at_bound) and not (c == 2 and not rolloff)]
    cov = _covariance(x, wts, H, xr, sse, free)
    gain = 0.0
    if rolloff:  # the F statistic of the roll-off against a pure power law
        sse0 = _fit_at(x, y, wts, float(x[0]))[2]
        gain = (sse0 - sse) / max(sse / max(x.size - 3, 1), 1e-300)
    return a, H, xr, cov, math.sqrt(sse / np.sum(wts)), q, gain


def _model_range(psd, q0, q1) -> tuple[float, float]:
    if isinstance(psd, ProfileSpectrum):
        lo, hi = psd.q_range
    else:
        lo, hi = _fit_points(psd, None)[2]
    m0 = lo if q0 is None else positive("q0", q0, "1/m")
    m1 = hi if q1 is None else positive("q1", q1, "1/m")
    if m1 <= m0:
        raise ValueError(f"q1 must be > q0 = {m0:g} 1/m, got {m1:g}")
    return m0, m1


def _warn_unresolved(qr: float, lowest: float, gain: float) -> None:
    if qr < lowest * ROLLOFF_MARGIN:
        why = f"lies within a factor {ROLLOFF_MARGIN:.3g} of the lowest fitted wavenumber"
    else:
        why = (
            f"improves on a pure power law by {gain:.3g} < {ROLLOFF_SIGNIFICANCE:g} (likelihood "
            "ratio or F statistic): noise could make it, from the range starting at"
        )
    _warn(
        f"fit_self_affine: the roll-off is not resolved: q_r = {qr:.3g} 1/m {why} {lowest:.3g} "
        "1/m. The roll-off may lie anywhere below; q_r, its error and the model's h_rms are not "
        "measurements (a longer scan, more profiles or a map resolve them)",
        stacklevel=3,
    )


def fit_self_affine(
    psd: ProfileSpectrum | TabulatedPSD | tuple[ArrayLike, ArrayLike],
    *,
    q_range: tuple[float | None, float | None] | None = None,
    rolloff: bool = True,
    q0: float | None = None,
    q1: float | None = None,
) -> SelfAffineFit:
    """Fit the self-affine spectrum with roll-off to a measured one.

    Model: ``C = C0`` below qr, ``C0 (q/qr)^-2(1+H)`` above (docs/theory.md section 2), H held
    in [0.01, 1]. How it is fitted depends on what is given:

    * a :class:`ProfileSpectrum` (line scans; the right input for them): the model's own 1D
      spectrum, its forward Abel transform in closed form (``C1D ~ k^-(1+2H)`` above qr), is
      fitted to C1D by the Whittle likelihood of the periodogram (P. Whittle, Bull. Int. Stat.
      Inst. 39, 105 (1962)): each point is the mean of ``n = counts x n_profiles /
      window_factor`` independent, exponentially distributed values, so its log-likelihood is
      ``-n (ln S + C1D / S)``. Unlike least squares in ``ln C1D`` it has no bias from the log of
      few values, and its standard errors follow from the Fisher information. Fitting the
      inverse Abel transform instead (one profile) gave H 0.05 low (H = 0.8: 0.748 mean of 26
      profiles of 8192 points) with error bars a quarter too small: the transform amplifies the
      scatter and correlates neighbouring points.
    * a :class:`TabulatedPSD` or ``(q, C)`` (a map's ring averages, a table): least squares
      in ``ln C``, each point weighted by the interval of ``ln q`` it covers (so that dense parts
      of a table do not dominate); qr by a scan of the profile least squares, refined by
      Brent's method; standard errors from the scatter about the fit (points treated as
      independent: indicative).

    A roll-off within ``ROLLOFF_MARGIN`` (a fifth of a decade) of the lowest fitted point, or
    one that improves the fit over a pure power law by less than ``ROLLOFF_SIGNIFICANCE``
    (``rolloff_gain``), is not resolved: ``qr_at_bound`` and ``at_bound`` are set, ``qr_err``
    is NaN and a :class:`TopographyWarning` says so.

    Parameters
    ----------
    psd : ProfileSpectrum, TabulatedPSD or (q, C)
        The 1D spectrum of line scans (:func:`psd_from_profile`), or an isotropic spectrum in
        Persson's convention.
    q_range : (lo, hi), optional
        Fit only there (1/m); default the whole spectrum.
    rolloff : bool
        False fits a pure power law (qr = lower end of the fitted range).
    q0, q1 : float, optional
        Range of the returned model (1/m); default the spectrum's.

    Returns
    -------
    SelfAffineFit
    """
    profile = isinstance(psd, ProfileSpectrum)
    m0, m1 = _model_range(psd, q0, q1)
    fit = _fit_profile if profile else _fit_table
    a, H, xr, cov, rms, q, gain = fit(psd, q_range, rolloff)
    hurst_at_bound = H in _HURST_BOUNDS
    qr_at_bound = rolloff and (math.exp(xr) < q[0] * ROLLOFF_MARGIN or gain < ROLLOFF_SIGNIFICANCE)
    if qr_at_bound:
        _warn_unresolved(math.exp(xr), float(q[0]), gain)
    xr = max(xr, math.log(m0))
    p = np.array([a, H, xr])
    grad = np.array(
        [
            (_model_h_rms(*(p + d), m0, m1) - _model_h_rms(*(p - d), m0, m1)) / 2e-6
            for d in np.eye(3) * 1e-6
        ]
    )
    h_rms = _model_h_rms(a, H, xr, m0, m1)
    model = SelfAffinePSD(h_rms, H, m0, min(max(math.exp(xr), m0), m1 * (1 - 1e-12)), m1)
    return SelfAffineFit(
        psd=model,
        h_rms=h_rms,
        hurst=float(H),
        qr=model.qr,
        C0=model.C0,
        h_rms_err=float(math.sqrt(max(grad @ cov @ grad, 0.0))),
        hurst_err=float(math.sqrt(cov[1, 1])),
        qr_err=math.nan if qr_at_bound else float(model.qr * math.sqrt(cov[2, 2])),
        rms_residual=float(rms),
        n_points=int(q.size),
        q_range=(float(q[0]), float(q[-1])),
        at_bound=bool(hurst_at_bound or qr_at_bound),
        fitted_to="C1D(k)" if profile else "C(q)",
        hurst_at_bound=bool(hurst_at_bound),
        qr_at_bound=bool(qr_at_bound),
        rolloff_gain=float(gain),
    )


# ----------------------------------------------------------------------------------------------
# other codes' conventions
# ----------------------------------------------------------------------------------------------
#: name -> (dimension, factor): a spectrum in that convention is ``factor`` times fastline's
#: (Persson's) spectrum of the same dimension at the same wavenumber q = 2 pi / wavelength.
CONVENTIONS = {
    # isotropic 2D, h_rms^2 = 2 pi int q C dq
    "persson": (2, 1.0),
    # SurfaceTopography / contact.engineering: C_iso = |h~(q)|^2 / A with
    # h~ = dx dy sum h exp(-i q.x), h_rms^2 = (1/2 pi) int q C_iso dq
    "surfacetopography": (2, (2.0 * math.pi) ** 2),
    "contact.engineering": (2, (2.0 * math.pi) ** 2),
    # 1D, two-sided: h_rms^2 = 2 int_0^inf C1D dk
    "persson-1d": (1, 1.0),
    # SurfaceTopography / contact.engineering: C1D = |h~(q)|^2 / L, h_rms^2 = (1/pi) int_0^inf
    "surfacetopography-1d": (1, 2.0 * math.pi),
    "contact.engineering-1d": (1, 2.0 * math.pi),
    # one-sided PSD per unit wavenumber k: h_rms^2 = int_0^inf G dk
    "one-sided-1d": (1, 2.0),
    # one-sided PSD per unit spatial frequency f = k / (2 pi) (cycles/m): h_rms^2 = int G_f df
    "one-sided-1d-frequency": (1, 4.0 * math.pi),
}
#: the names of :data:`CONVENTIONS` (``from_`` and ``to`` of :func:`convert_psd`)
Convention = Literal[
    "persson",
    "surfacetopography",
    "contact.engineering",
    "persson-1d",
    "surfacetopography-1d",
    "contact.engineering-1d",
    "one-sided-1d",
    "one-sided-1d-frequency",
]


def convert_psd(
    C: ArrayLike,
    q: ArrayLike,
    from_: Convention = "surfacetopography",
    to: Convention = "persson",
) -> np.ndarray:
    """A spectrum in another code's normalisation (same dimension, same q).

    Conventions (``CONVENTIONS``; q always the wavenumber ``2 pi / wavelength`` in 1/m):

    ==========================  ====  ========================================  =============
    name                        dim   normalisation                             x fastline's
    ==========================  ====  ========================================  =============
    ``persson``                 2D    ``h_rms^2 = 2 pi int q C dq``             1
    ``surfacetopography``       2D    ``h_rms^2 = (1/2 pi) int q C dq``         (2 pi)^2
    ``persson-1d``              1D    ``h_rms^2 = 2 int_0^inf C dk``            1
    ``surfacetopography-1d``    1D    ``h_rms^2 = (1/pi) int_0^inf C dk``       2 pi
    ``one-sided-1d``            1D    ``h_rms^2 = int_0^inf G dk``              2
    ``one-sided-1d-frequency``  1D    ``h_rms^2 = int_0^inf G_f df``, f=k/2pi   4 pi
    ==========================  ====  ========================================  =============

    ``contact.engineering`` and ``contact.engineering-1d`` are the SurfaceTopography ones
    (T. D. B. Jacobs, T. Junge, L. Pastewka, Surf. Topogr.: Metrol. Prop. 5, 013001 (2017),
    doi:10.1088/2051-672X/aa51f8; the docstrings of SurfaceTopography's
    ``power_spectrum_from_profile`` and ``power_spectrum_from_area``, version 1.27,
    https://contactengineering.github.io/SurfaceTopography/; the tests hold both estimators,
    converted, equal to fastline's). For ``one-sided-1d-frequency`` tabulated against
    f, pass ``q = 2 pi f``.

    A 1D and a 2D spectrum are not related point by point: the 2D spectrum of a line scan is
    :func:`isotropic_from_1d` (the factor 2 people lose is this, not a normalisation).

    Parameters
    ----------
    C : array_like
        Spectrum values (>= 0, finite).
    q : array_like
        Wavenumbers in 1/m (> 0), same shape.
    from_, to : str
        Names in ``CONVENTIONS``.
    """
    names = ", ".join(repr(n) for n in CONVENTIONS)
    for arg, name in (("from_", from_), ("to", to)):
        if name not in CONVENTIONS:
            raise ValueError(f"{arg} must be one of {names}, got {name!r}")
    (d_from, f_from), (d_to, f_to) = CONVENTIONS[from_], CONVENTIONS[to]
    if d_from != d_to:
        raise ValueError(
            f"{from_!r} is a {d_from}D and {to!r} a {d_to}D spectrum: they are not related point "
            "by point; use isotropic_from_1d (the inverse Abel transform) for 1D -> 2D"
        )
    C = real_array("C", C)
    q = real_array("q", q)
    if C.shape != q.shape:
        raise ValueError(f"C and q must have the same shape, got {C.shape} and {q.shape}")
    if not (np.all(np.isfinite(C)) and np.all(C >= 0.0)):
        raise ValueError("C must be finite and >= 0")
    if not (np.all(np.isfinite(q)) and np.all(q > 0.0)):
        raise ValueError("q must be finite and > 0 (1/m)")
    return C * (f_to / f_from)


# ----------------------------------------------------------------------------------------------
# synthetic surfaces
# ----------------------------------------------------------------------------------------------
#: most points of a synthetic surface, n * ny (4096 x 4096: ~1 GB of FFT work arrays)
SYNTHETIC_MAX_POINTS = 4096 * 4096
_SYNTHETIC_WHY = " (n * ny at most 4096 x 4096 points: the FFTs need ~64 bytes a point)"


def synthetic_surface(
    psd: PSD,
    n: int,
    dx: float,
    *,
    ny: int | None = None,
    seed: int | np.random.Generator | None = None,
) -> np.ndarray:
    """A periodic Gaussian random surface with the isotropic spectrum psd, shape (ny, n).

    Unit white noise, Fourier transformed, shaped by ``sqrt((2 pi)^2 A C(|q|) / ((dx dy)^2 N))``
    and transformed back: random phases and Gaussian amplitudes, ``E[h_rms^2]`` the sum of
    ``C(|q|) (2 pi)^2 / A`` over the grid's wavenumbers (the spectrum's h_rms^2 up to the
    discreteness of the grid and its Nyquist limit ``pi / dx``).

    Parameters
    ----------
    psd : PSD
        Isotropic spectrum (Persson's convention).
    n, ny : int
        Points along x and y (ny defaults to n), >= 2; ``n * ny`` at most
        ``SYNTHETIC_MAX_POINTS`` (4096 x 4096).
    dx : float
        Spacing in m (both directions).
    seed : int or numpy Generator, optional

    Raises
    ------
    ValueError
        Bad sizes or spacing, or a grid none of whose wavenumbers (2 pi / L up to the Nyquist
        corner) lies where the spectrum is nonzero: the surface would be flat.
    """
    if not isinstance(psd, PSD):
        raise TypeError(f"psd must be a fastline PSD, got {type(psd).__name__}")
    if ny is None:  # a square map
        n = ny = integer("n", n, 2, math.isqrt(SYNTHETIC_MAX_POINTS), _SYNTHETIC_WHY)
    else:
        n = integer("n", n, 2, SYNTHETIC_MAX_POINTS // 2, _SYNTHETIC_WHY)
        ny = integer("ny", ny, 2, SYNTHETIC_MAX_POINTS // n, _SYNTHETIC_WHY)
    dx = positive("dx", dx, "m")
    qx = 2.0 * math.pi * np.fft.fftfreq(n, dx)
    qy = 2.0 * math.pi * np.fft.fftfreq(ny, dx)
    q = np.hypot(qy[:, None], qx[None, :])
    C = psd(q)
    if not np.any(C > 0.0):
        raise ValueError(
            f"the grid's wavenumbers {2.0 * math.pi / (max(n, ny) * dx):.4g}-{q.max():.4g} 1/m "
            f"(2 pi / L to the Nyquist corner) miss the spectrum, which is 0 outside "
            f"{float(psd.q0):.4g}-{float(psd.q1):.4g} 1/m: the surface would be flat (is dx in m?)"
        )
    rng = np.random.default_rng(seed)
    noise = np.fft.fft2(rng.standard_normal((ny, n)))
    area = n * ny * dx * dx
    amplitude = np.sqrt((2.0 * math.pi) ** 2 * area * C / (dx**4 * n * ny))
    return np.fft.ifft2(noise * amplitude).real


# ----------------------------------------------------------------------------------------------
# files
# ----------------------------------------------------------------------------------------------
class Profile(NamedTuple):
    """A line scan: heights (N,) in m and their spacing dx in m."""

    heights: np.ndarray
    dx: float


class Map(NamedTuple):
    """A height map: heights (Ny, Nx) in m (rows along x) and the spacings dx, dy in m."""

    heights: np.ndarray
    dx: float
    dy: float


#: length units fastline converts (factor to m)
UNITS = {
    "m": 1.0,
    "mm": 1e-3,
    "um": 1e-6,
    "µm": 1e-6,
    "μm": 1e-6,
    "micron": 1e-6,
    "nm": 1e-9,
    "A": 1e-10,
    "Å": 1e-10,
    "pm": 1e-12,
}
_TEXT = (".txt", ".csv", ".dat", ".tsv", ".prn")
_NUMPY = (".npy",)


def _unit(name: str, unit) -> float:
    if unit not in UNITS:
        raise ValueError(f"{name} must be one of {', '.join(UNITS)}, got {unit!r}")
    return UNITS[unit]


def _uniform_spacing(x: np.ndarray, path: str) -> float:
    """dx of positions x that must lie on a uniform grid (to 1 % of dx)."""
    j = np.arange(x.size)
    slope, offset = np.polyfit(j, x, 1)
    if slope == 0.0:
        raise ValueError(f"{path}: the x column is constant")
    worst = float(np.max(np.abs(x - (offset + slope * j)))) / abs(slope)
    if worst > 0.01:
        raise ValueError(
            f"{path}: x is not uniformly spaced (a point lies {worst:.2g} spacings off the "
            "uniform grid): resample the profile onto a uniform grid first"
        )
    return abs(float(slope))


def _surfacetopography(path: str):
    """(dimension, heights in m, spacings in m) of an instrument file, via SurfaceTopography."""
    try:
        import SurfaceTopography
    except ImportError:
        raise ImportError(
            f"reading {os.path.splitext(path)[1] or 'these'} files needs {_INSTALL}"
        ) from None
    topo = SurfaceTopography.read_topography(path)
    if not getattr(topo, "is_uniform", True):
        raise ValueError(f"{path}: a non-uniform line scan; resample it onto a uniform grid")
    unit = topo.unit
    if unit in UNITS:
        factor = UNITS[unit]
    else:
        from SurfaceTopography.Support.UnitConversion import get_unit_conversion_factor

        factor = get_unit_conversion_factor(unit, "m")
    heights = np.ma.filled(np.ma.asarray(topo.heights(), dtype=np.float64), np.nan) * factor
    sizes = np.atleast_1d(topo.physical_sizes) * factor
    points = np.atleast_1d(topo.nb_grid_pts)
    if topo.dim == 1:
        return 1, heights, (float(sizes[0] / points[0]),)
    return 2, heights.T, (float(sizes[0] / points[0]), float(sizes[1] / points[1]))


def _refuse_columns(path: str, columns: int, traces: bool) -> None:
    """Refuse a table of more than two columns read as a line scan, unless it can be one trace
    per line (``traces``, :func:`read_topography`) with at least MIN_POINTS heights each."""
    if traces and columns >= MIN_POINTS:
        return
    other = (
        f"; one trace per line needs at least {MIN_POINTS} heights per line"
        if traces
        else "; a height map: read_map"
    )
    raise ValueError(
        f"{path}: expected 1 column (heights, with dx) or 2 columns (x, height), got {columns}"
        + other
    )


def _load(path, *, dx, unit, x_unit, kind):
    """(dimension, heights, spacings) from a text, .npy or instrument file (kind: profile,
    map or None for either)."""
    path = os.fspath(path)
    ext = os.path.splitext(path)[1].lower()
    if not os.path.exists(path):
        raise FileNotFoundError(f"no such file: {path}")
    if ext not in _TEXT + _NUMPY:
        return _surfacetopography(path)
    scale = _unit("unit", unit)
    scale_x = _unit("x_unit", unit if x_unit is None else x_unit)
    data = np.load(path, allow_pickle=False) if ext in _NUMPY else read_table(path)[0]
    data = np.asarray(data, dtype=np.float64)
    columns = 1 if data.ndim == 1 else data.shape[1]
    if kind != "map" and data.ndim == 2 and columns > 2:
        _refuse_columns(path, columns, traces=kind is None)
    if kind == "map" or (kind is None and data.ndim == 2 and columns > 2):
        if data.ndim != 2 or min(data.shape) < 2:
            raise ValueError(f"{path}: a map needs a 2D array of heights, got shape {data.shape}")
        if dx is None:
            raise ValueError(f"{path}: a height map from a text or .npy file needs dx (m)")
        return 2, data * scale, (dx, None)
    if columns == 1:
        if dx is None:
            raise ValueError(f"{path}: one column of heights: dx (m) is required")
        return 1, data.ravel() * scale, (dx,)
    x, h = data[:, 0] * scale_x, data[:, 1] * scale
    if np.any(np.isnan(x)):
        raise ValueError(f"{path}: the x column has missing values")
    if x[-1] < x[0]:
        x, h = x[::-1], h[::-1]
    spacing = _uniform_spacing(x, path)
    if dx is not None and not math.isclose(dx, spacing, rel_tol=0.01):
        raise ValueError(f"{path}: dx = {dx:g} m disagrees with the file's spacing {spacing:g} m")
    return 1, h, (spacing,)


def read_profile(
    path: str | os.PathLike,
    *,
    dx: float | None = None,
    unit: str = "m",
    x_unit: str | None = None,
) -> Profile:
    """Read a line scan (heights converted to m).

    Text (``.txt``, ``.csv``, ``.dat``, ``.tsv``, ``.prn``: header lines skipped; comma,
    semicolon, tab or blank separated): two columns x, h (x must be uniform to 1 % of its
    spacing) or one column h with ``dx``. ``.npy``: an (N,) array of heights with ``dx`` or an
    (N, 2) array x, h. Any other extension: an instrument file read by SurfaceTopography
    (X3P, SDF, Dektak OPDx, Mitutoyo, Keyence VK, Zygo, Sensofar PLU, ...; units from the file),
    which needs ``pip install "fastline-contact[topography]"``.

    Parameters
    ----------
    path : str or path-like
    dx : float, optional
        Spacing in m (required for a single column of heights).
    unit, x_unit : str
        Units of the file's height and x columns (``"m"``, ``"mm"``, ``"um"``, ``"nm"``, ...;
        x_unit defaults to unit). Ignored for instrument files.

    Returns
    -------
    Profile
        ``heights`` (m, NaN where the file has none) and ``dx`` (m).
    """
    dx = None if dx is None else positive("dx", dx, "m")
    dim, h, spacing = _load(path, dx=dx, unit=unit, x_unit=x_unit, kind="profile")
    if dim != 1:
        raise ValueError(f"{os.fspath(path)}: holds a map of shape {h.shape}; use read_map")
    return Profile(h, spacing[0])


def read_map(
    path: str | os.PathLike, *, dx: float | None = None, dy: float | None = None, unit: str = "m"
) -> Map:
    """Read a height map (heights converted to m), rows along x.

    Text (one row of heights per line) or ``.npy`` (2D array) with ``dx`` (and ``dy``, default
    dx) in m; any other extension via SurfaceTopography as :func:`read_profile`.

    Returns
    -------
    Map
        ``heights`` (Ny, Nx) in m, ``dx``, ``dy`` in m.
    """
    dx = None if dx is None else positive("dx", dx, "m")
    dim, h, spacing = _load(path, dx=dx, unit=unit, x_unit=None, kind="map")
    if dim != 2:
        raise ValueError(f"{os.fspath(path)}: holds a line scan; use read_profile")
    sx = spacing[0]
    sy = spacing[1] if spacing[1] is not None else (sx if dy is None else positive("dy", dy, "m"))
    return Map(h, sx, sy)


def read_topography(
    path: str | os.PathLike,
    *,
    dx: float | None = None,
    unit: str = "m",
    x_unit: str | None = None,
) -> Profile | Map:
    """A :class:`Profile` or a :class:`Map`, whichever the file holds (text or ``.npy`` with
    one or two columns is a profile, more columns a map; see :func:`read_profile`)."""
    dx = None if dx is None else positive("dx", dx, "m")
    dim, h, spacing = _load(path, dx=dx, unit=unit, x_unit=x_unit, kind=None)
    if dim == 1:
        return Profile(h, spacing[0])
    return Map(h, spacing[0], spacing[1] if spacing[1] is not None else spacing[0])
