"""Line scans: the 1D spectrum of profiles and the isotropic spectrum it implies.

Conventions as :mod:`fastline.surfaces.topography` (docs/theory.md section 2): the two-sided 1D
spectrum ``h_rms^2 = 2 int_0^inf C1D(k) dk`` (m^3), the isotropic spectrum
``h_rms^2 = 2 pi int q C dq`` (m^4); heights and lengths in m, wavenumbers in 1/m. The
periodogram of a profile of N points (window w, ``sum w_j^2 = N``) is
``C1D(k_m) = dx^2 / (2 pi L) |sum_j w_j h_j exp(-i k_m x_j)|^2``, ``k_m = 2 pi m / L``; with the
rectangular window ``sum_m C1D(k_m) 2 pi / L`` over all m equals the mean square of the
detrended heights exactly (Parseval). Heights with h_rms > 1 mm or an rms slope outside
[1e-6, 5] suggest a unit slip and warn (:class:`~fastline.errors.TopographyWarning`).
"""

from __future__ import annotations

import math
from collections.abc import Iterator
from dataclasses import dataclass, field
from typing import Any, Literal, NamedTuple

import numpy as np
from numpy.typing import ArrayLike

from fastline._lib.validate import BINS_PER_DECADE_RANGE, finite_scalar, integer, positive
from fastline.surfaces.abel import inverse_abel
from fastline.surfaces.floor import find_floor, load_scipy
from fastline.surfaces.heights import (
    MIN_POINTS,
    apply_window,
    check_plausible,
    checked_heights,
    checked_spacing,
    choice,
    detrend_rows,
    fill_dropouts,
    refuse_flat,
    topography_warning,
    window_factor,
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
from fastline.surfaces.rowkernels import add_power, detrend_into, line_sums
from fastline.surfaces.tables import checked_table, extend_psd, loglog_slope
from fastline.theory.spectra import TabulatedPSD


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
    noise_floor : float
        The instrument's white-noise level of C1D in m^3 (``noise^2 dx / (2 pi)``), found in
        the data (:mod:`~fastline.surfaces.floor`) or from ``noise``; 0 when there is none.
        C1D includes it; :func:`fit_self_affine` takes it off.
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
    noise_floor: float = 0.0

    def __iter__(self) -> Iterator[np.ndarray]:
        return iter((self.k, self.C1D))

    def isotropic(self, **options: Any) -> TabulatedPSD:
        """The isotropic 2D spectrum, ``isotropic_from_1d(k, C1D, **options)``."""
        return isotropic_from_1d(self.k, self.C1D, **options)


_DETRENDS = ("mean", "linear", "parabola", "circle")


def _profile_rows(h, dx) -> tuple[np.ndarray, float]:
    """The heights as rows of at least MIN_POINTS each, and the spacing dx (m), checked."""
    rows = np.atleast_2d(checked_heights(h, (1, 2)))
    dx = checked_spacing("dx", dx)
    if rows.shape[-1] < MIN_POINTS:
        raise ValueError(
            f"h must hold at least {MIN_POINTS} points per profile, got {rows.shape[-1]}"
        )
    return rows, dx


class _Detrended(NamedTuple):
    """Profiles without their form (m), the form's radius (m) or None, their h_rms (m) and rms
    slope."""

    rows: np.ndarray
    radius: float | None
    h_rms: float
    slope: float


def _line_detrended(raw: np.ndarray, how: str) -> tuple[np.ndarray, float, float]:
    """Rows less their mean or least-squares line (a new array; compiled passes, no work
    arrays), with the sums of the squares of the residual and of its differences."""
    n = raw.shape[-1]
    tt = n * (n * n - 1.0) / 12.0  # sum of (j - centre)^2
    out = np.empty(raw.shape, dtype=np.float64)
    squares = steps = 0.0
    for r in range(raw.shape[0]):
        row = np.ascontiguousarray(raw[r], dtype=np.float64)
        total, moment = line_sums(row)
        slope = moment / tt if how == "linear" else 0.0
        sq, st = detrend_into(row, total / n, slope, out[r])
        squares, steps = squares + sq, steps + st
    return out, squares, steps


def _detrended(rows: np.ndarray, dx: float, detrend: str, nan: str) -> _Detrended:
    """The rows with dropouts bridged (or refused) and their form removed (a new array); a
    flat profile is refused."""
    raw = fill_dropouts(rows, nan)
    if detrend in ("parabola", "circle"):  # before a form fit divides by 0
        refuse_flat(float(np.std(raw)), raw, "profile", "mean")
        rows, radius = detrend_rows(raw, dx, detrend)
        squares, steps = float(np.vdot(rows, rows)), 0.0
        for row in rows:
            d = np.diff(row)
            steps += float(np.dot(d, d))
    else:
        (rows, squares, steps), radius = _line_detrended(raw, detrend), None
    h_rms = math.sqrt(squares / rows.size)
    refuse_flat(h_rms, raw, "profile", detrend)
    slope = math.sqrt(steps / (rows.shape[0] * (rows.shape[1] - 1))) / dx
    return _Detrended(rows, radius, h_rms, slope)


def _periodogram(h: np.ndarray, dx: float, window):
    """``k_m, C1D(k_m)`` for m = 1 .. N//2, averaged over the rows (module docstring). The
    rows are windowed in place (they are the detrended copy)."""
    n = h.shape[-1]
    L = n * dx
    C = np.zeros(n // 2 + 1)
    for row in h:
        apply_window(row, window)
        F = np.fft.rfft(row)
        add_power(F, C)
        del F
    C *= dx * dx / (2.0 * math.pi * L * h.shape[0])
    k = np.arange(C.size, dtype=np.float64)
    k *= 2.0 * math.pi / L
    return k[1:], C[1:]


def _profile_range(k, C, rows, dx, rules: RangeRules, independent: float, k_tip: float):
    """The usable range of a periodogram (k, C) of rows at spacing dx, the rule of each end,
    and the white-noise level of C1D (m^3; given by ``noise`` or found in the data)."""
    given, _, noise = rules
    measured = (float(k[0]), float(k[-1]))
    if given == "all":
        return measured, {"low": "all", "high": "all"}, 0.0
    k_low = LOW_MODE * 2.0 * math.pi / (rows.shape[-1] * dx)
    k_noise, noise_rule = math.inf, "noise floor"
    if noise is not None:
        level = noise * noise * dx / (2.0 * math.pi)
        kb, Cb, _ = log_bins(k, C, 20, k[0], k[-1])
        k_noise = noise_cutoff(kb, Cb, level)
    else:
        level, k_noise, _, _ = find_floor(k, C, independent, k_low)
        noise_rule = "noise floor found"
    usable = usable_range(
        k_low,
        2.0 * math.pi / (POINTS_PER_WAVELENGTH * dx),
        k_tip,
        k_noise,
        given,
        measured,
    )
    if usable[1]["high"] == "noise floor":
        usable[1]["high"] = noise_rule
    return usable[0], usable[1], level


def _profile_points(k, C, q_rng, bins_per_decade):
    """The periodogram cut to q_rng, raw or binned with its end points; and the counts."""
    if bins_per_decade is None:
        keep = (k >= q_rng[0] * (1 - 1e-12)) & (k <= q_rng[1] * (1 + 1e-12))
        k, C, counts = k[keep], C[keep], np.ones(int(keep.sum()), dtype=int)
    else:
        kb, C, counts = log_bins(k, C, bins_per_decade, *q_rng)
        k, C = span_bins(kb, C, *q_rng)
        counts = np.concatenate([[0] * int(k[0] < kb[0]), counts, [0] * int(k[-1] > kb[-1])])
    if k.size < 2:
        raise ValueError(f"the usable range {q_rng} 1/m holds fewer than 2 spectrum points")
    return k, C, counts


def _spectrum(points, usable, form: _Detrended, dx, factor, window, detrend) -> ProfileSpectrum:
    """The ProfileSpectrum of the points ``(k, C1D, counts)`` over the usable range
    ``(q_range, limits, noise level)``, with the data and the analysis they came from."""
    k, C, counts = points
    q_rng, limits, level = usable
    return ProfileSpectrum(
        k=k,
        C1D=C,
        counts=counts,
        q_range=q_rng,
        limits=limits,
        h_rms=form.h_rms,
        rms_slope=form.slope,
        n_profiles=form.rows.shape[0],
        dx=dx,
        length=form.rows.shape[-1] * dx,
        window="none" if window is None else str(window),
        detrend=detrend,
        form_radius=form.radius,
        window_factor=factor,
        noise_floor=float(level),
    )


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
    """The 1D spectrum C1D (m^3) of a height profile, or the average over parallel profiles
    (the periodogram of the module docstring, binned and cut to its usable range).

    Parameters
    ----------
    h : array_like
        Heights in m: one profile (N,) or parallel profiles (P, N), at least MIN_POINTS each.
    dx : float
        Spacing in m (> 0).
    window : str or None
        ``"hann"`` (default), ``"none"``, or a name :func:`scipy.signal.get_window` knows,
        normalised to ``sum w^2 = N`` (it keeps the jump between a profile's ends from leaking
        power ~k^-2 into steeper spectra).
    detrend : {"linear", "mean", "parabola", "circle"}
        Removed from each profile before the window; ``"parabola"`` and ``"circle"`` take out
        a cylinder's form (its radius is reported as ``form_radius``).
    nan : {"raise", "interpolate"}
        NaN heights (dropouts) are refused, or bridged by straight lines (at most 20 % of the
        points; a little high-k power goes in proportion).
    bins_per_decade : int or None
        Average the periodogram over bins equally spaced in log k (default 20, at least
        MIN_PER_BIN values each; :mod:`fastline.surfaces.ranges`), or None: the raw one.
    q_range : "auto", None or (lo, hi)
        The usable range: ``"auto"`` by the rules of :mod:`fastline.surfaces.ranges` (from
        mode LOW_MODE to the lowest of the sampling, tip and noise limits), None the whole
        periodogram, a pair overrides either end (None keeps the rule).
    tip_radius, noise : float, optional
        Stylus tip radius and rms instrument noise, in m (their limits of ``"auto"``). Without
        ``noise`` the white-noise plateau is sought in the data
        (:func:`~fastline.surfaces.floor.find_floor`): when found, the range ends where the
        fitted power law falls to ``NOISE_MARGIN`` times it, and ``noise_floor`` holds its
        level, which :func:`fit_self_affine` takes off.

    Returns
    -------
    ProfileSpectrum
        Unpacks as ``k, C1D``; also the range used, the counts per point and the data's h_rms.
    """
    options = dict(window=window, detrend=detrend, nan=nan, bins_per_decade=bins_per_decade)
    return spectrum_and_periodogram(h, dx, q_range, tip_radius, noise, **options)[0]


def spectrum_and_periodogram(h, dx, q_range, tip_radius, noise, *, window, detrend, nan,
                             bins_per_decade) -> tuple[ProfileSpectrum, tuple]:  # fmt: skip
    """:func:`psd_from_profile` and the raw periodogram ``(k, C1D)`` at every Fourier mode it
    was cut and binned from (for figures), from one pass over the heights."""
    rows, dx = _profile_rows(h, dx)
    detrend = choice("detrend", detrend, _DETRENDS)
    nan = choice("nan", nan, ("raise", "interpolate"))
    if bins_per_decade is not None:
        bins_per_decade = integer("bins_per_decade", bins_per_decade, *BINS_PER_DECADE_RANGE)
    rules = range_rules(q_range, tip_radius, noise)
    factor = window_factor(window, rows.shape[-1])  # checks the name before any work
    load_scipy()
    form = _detrended(rows, dx, detrend, nan)
    check_plausible(form.h_rms, form.slope, "psd_from_profile")
    k_tip = math.inf if rules.tip is None else tip_cutoff(form.rows, dx, rules.tip)
    k, C = _periodogram(form.rows, dx, window)  # windows form.rows in place
    form = form._replace(rows=rows)  # the windowed copy is no longer needed: free it
    usable = _profile_range(k, C, rows, dx, rules, rows.shape[0] / factor, k_tip)
    points = _profile_points(k, C, usable[0], bins_per_decade)
    return _spectrum(points, usable, form, dx, factor, window, detrend), (k, C)


# ----------------------------------------------------------------------------------------------
# 1D -> isotropic 2D
# ----------------------------------------------------------------------------------------------
def non_increasing(C1D: np.ndarray) -> np.ndarray:
    """The non-increasing sequence closest to C1D in least squares of ``ln C1D`` (the
    pool-adjacent-violators algorithm: rising runs are pooled into their mean).

    ``C1D(k) = 2 int_0^inf C(sqrt(k^2 + s^2)) ds`` falls with k wherever C(q) falls with q, and
    with ``C1D' <= 0`` the inverse transform ``-(1/pi) int C1D' / sqrt(k^2 - q^2) dk`` is
    positive: the noise of a periodogram, not the surface, makes a measured C1D rise."""
    values, sizes = [], []
    for v in np.log(C1D):
        values.append(float(v))
        sizes.append(1)
        while len(values) > 1 and values[-2] < values[-1]:
            v2, n2 = values.pop(), sizes.pop()
            values[-1] = (values[-1] * sizes[-1] + v2 * n2) / (sizes[-1] + n2)
            sizes[-1] += n2
    return np.exp(np.repeat(values, sizes))


def _tail_slope(k: np.ndarray, C1D: np.ndarray, tail, tail_decades) -> float | None:
    """The exponent of C1D beyond the last point (< -1), or None for no tail: the ``tail`` of
    :func:`isotropic_from_1d`."""
    if not isinstance(tail, str):
        slope = finite_scalar("tail", tail)
        if slope >= -1.0:
            raise ValueError(f"tail must be an exponent < -1 (or 'fit', 'zero'), got {slope!r}")
        return slope
    choice("tail", tail, ("fit", "zero"))
    if tail == "zero":
        return None
    decades = positive("tail_decades", tail_decades)
    slope = loglog_slope(k, C1D, decades)
    if slope >= -1.0:
        raise ValueError(
            f"the top of C1D does not fall off (fitted exponent {slope:.3g} >= -1 over "
            f"the top {decades:g} decades): it is noise or instrument floor. Cut the "
            "spectrum below it (q_range) or pass tail='zero' or an exponent < -1"
        )
    return slope


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
        (:func:`extend_psd`).

    Returns
    -------
    TabulatedPSD
        C(q) in Persson's convention (m^4), ``h_rms^2 = 2 pi int q C dq``, on the points k.

    Warns
    -----
    TopographyWarning
        When noise makes C(q) <= 0 somewhere: C1D is then replaced by its closest
        non-increasing sequence (:func:`non_increasing`), and the table keeps every point.
    """
    k, C1D = checked_table("k", k, "C1D", C1D, positive_values=True)
    slope = _tail_slope(k, C1D, tail, tail_decades)
    C = inverse_abel(k, C1D, slope)
    good = C > 0.0
    if not good.all():  # noise: C1D rises somewhere; its falling envelope keeps C > 0
        pooled = non_increasing(C1D)
        topography_warning(
            f"isotropic_from_1d: noise in C1D made C(q) <= 0 at {int((~good).sum())} of "
            f"{k.size} points; C1D was replaced by its closest non-increasing sequence (least "
            f"squares in ln C1D; {int(np.sum(pooled != C1D))} points changed), whose inverse "
            "transform is positive. Fewer bins per decade or more profiles help.",
        )
        C = inverse_abel(k, pooled, slope)
        good = C > 0.0
    if good.sum() < 2:
        raise ValueError("the inverse transform left fewer than 2 positive values of C(q)")
    psd = TabulatedPSD(k[good], C[good])
    return psd if q1 is None else extend_psd(psd, q1)
