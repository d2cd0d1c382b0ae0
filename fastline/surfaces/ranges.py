"""The usable wavenumber range of a measured spectrum, and its binning in log q.

The rules (applied by :func:`~fastline.surfaces.profiles.psd_from_profile` and
:func:`~fastline.surfaces.maps.psd_from_map`): the range starts at Fourier mode ``LOW_MODE``
(``4 x 2 pi / L``) and ends at the lowest of the sampling limit ``2 pi / (4 dx)``, the
stylus-tip limit (:func:`tip_cutoff`) and the noise limit (:func:`noise_cutoff`). Wavenumbers in
1/m, lengths in m.
"""

from __future__ import annotations

import math
from typing import Literal, NamedTuple

import numpy as np

from fastline._lib.validate import positive

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

#: log_bins works through long spectra in pieces of this many values
_CHUNK = 1 << 19

#: a usable range: "auto" (the rules), None (everything), or (lo, hi) in 1/m with None for a rule
QRange = Literal["auto"] | tuple[float | None, float | None] | None


def log_bins(x: np.ndarray, y: np.ndarray, per_decade: int, lo: float, hi: float, weights=None):
    """Averages of y over bins of x equally spaced in log between lo and hi.

    Neighbouring bins are merged (from the low end) until each holds at least MIN_PER_BIN
    values: at the low end of a periodogram a bin of a twentieth of a decade holds one or no
    wavenumber, and the inverse Abel transform amplifies the scatter of single values.
    Each bin's value is the mean of its members; it is placed at ``x_eff = <x^s>^(1/s)``, where
    a power law of the local slope s (from the neighbouring bins) equals its mean, so that
    binning a power law is exact (the plain mean of x would bias C by ~0.5 % at 20 bins per
    decade for C ~ k^-2.6). ``weights`` (optional, integers): each value stands for that many
    (a map's half plane of modes, the other half their mirror images). Returns ``x_eff, mean y,
    members`` of the bins.
    """
    nb = max(1, math.ceil(per_decade * math.log10(hi / lo) - 1e-9))
    edges = np.geomspace(lo, hi, nb + 1)
    edges[-1] = hi * (1.0 + 1e-12)
    if x.size > 1 and x[0] <= x[1] and bool(np.all(x[1:] >= x[:-1])):  # sorted: views
        cut = slice(*np.searchsorted(x, [lo, edges[-1]], side="left"))
        x, y = x[cut], y[cut]
        weights = None if weights is None else weights[cut]
    idx = np.searchsorted(edges, x, side="right")
    idx -= 1
    inside = (idx >= 0) & (idx < nb)
    if not inside.all():
        x, y, idx = x[inside], y[inside], idx[inside]
        weights = None if weights is None else weights[inside]
    del inside
    group = _merge_groups(np.rint(np.bincount(idx, weights, minlength=nb)).astype(int), MIN_PER_BIN)
    idx = group[idx]
    ng = int(group[-1]) + 1
    counts = np.rint(np.bincount(idx, weights, minlength=ng)).astype(int)
    wy = y if weights is None else y * weights
    ybar = np.bincount(idx, weights=wy, minlength=ng) / counts
    del wy
    wx = x if weights is None else x * weights
    xbar = np.bincount(idx, weights=wx, minlength=ng) / counts
    del wx
    if ybar.size < 3 or np.any(ybar <= 0.0):
        return xbar, ybar, counts
    s = np.clip(np.gradient(np.log(ybar), np.log(xbar)), -8.0, 8.0)  # noise: no wild slopes
    flat = np.abs(s) < 1e-4  # there <x^s>^(1/s) -> the geometric mean exp<ln x>
    mean = np.zeros(ng)
    for start in range(0, x.size, _CHUNK):  # in pieces: no work arrays of the spectrum's size
        part = slice(start, start + _CHUNK)
        j = idx[part]
        power = x[part] / xbar[j]  # the ratio, then its power in place
        member = flat[j]
        power[member] = np.log(power[member])
        power[~member] **= s[j[~member]]
        if weights is not None:
            power *= weights[part]
        mean += np.bincount(j, weights=power, minlength=ng)
    mean /= counts
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


def span_bins(x: np.ndarray, y: np.ndarray, lo: float, hi: float):
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


def range_argument(q_range, name="q_range"):
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


class RangeRules(NamedTuple):
    """The arguments of the range rules, checked: the given ends (:func:`range_argument`), the
    stylus tip radius and the rms instrument noise (m; None where that rule is not applied)."""

    given: tuple[float | None, float | None] | str
    tip: float | None
    noise: float | None


def range_rules(q_range, tip_radius, noise) -> RangeRules:
    """``q_range``, ``tip_radius`` (m) and ``noise`` (m) checked, in this order."""
    given = range_argument(q_range)
    tip = None if tip_radius is None else positive("tip_radius", tip_radius, "m")
    noise = None if noise is None else positive("noise", noise, "m")
    return RangeRules(given, tip, noise)


def tip_cutoff(h: np.ndarray, dx: float, tip_radius: float) -> float:
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


def noise_cutoff(k: np.ndarray, C: np.ndarray, floor: float) -> float:
    """The first k at which the (binned) spectrum falls below NOISE_MARGIN x the floor."""
    below = np.flatnonzero(C < NOISE_MARGIN * floor)
    return math.inf if below.size == 0 else float(k[below[0]])


def usable_range(k_low: float, k_sampling: float, k_tip: float, k_noise: float, given, measured):
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
