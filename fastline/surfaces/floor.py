"""The instrument's white-noise floor of a measured 1D spectrum, found from the data.

Every scan carries instrument noise. White noise of rms sigma adds the flat
``C1D = sigma^2 dx / (2 pi)`` (m^3) to the spectrum of a profile (the periodogram's convention
of :mod:`~fastline.surfaces.profiles`); where the surface's own spectrum, falling as a power
law, sinks towards that plateau the measurement shows the instrument, not the surface.

:func:`find_floor` fits the top ``FLOOR_DECADES`` of the periodogram (log-binned, up to the
Nyquist wavenumber ``pi / dx``) twice by the Whittle likelihood of the periodogram (P. Whittle,
Bull. Int. Stat. Inst. 39, 105 (1962)): as a power law ``A k^-s``, and as a power law plus a
plateau ``A k^-s + N``. The plateau is taken as found when it improves the likelihood by more
than ``FLOOR_SIGNIFICANCE`` (twice the log-likelihood ratio, scaled by the dispersion of the
periodogram about the fit; the 99 % point of chi-squared with one degree of freedom, as for
the roll-off of :mod:`~fastline.surfaces.fit`).
The usable range then ends where the fitted power law falls to ``NOISE_MARGIN`` times the
plateau (:mod:`~fastline.surfaces.ranges`), and the self-affine fit
(:func:`~fastline.surfaces.fit.fit_self_affine`) takes the plateau off the spectrum it fits.
Wavenumbers in 1/m, C1D in m^3.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from fastline.surfaces.ranges import NOISE_MARGIN, log_bins

__all__ = ["FLOOR_DECADES", "FLOOR_SIGNIFICANCE", "Floor", "find_floor", "load_scipy"]

#: the plateau is sought in the top decades of the periodogram (below Nyquist)
FLOOR_DECADES = 1.5
#: twice the log-likelihood gain (over the dispersion) a plateau must bring to count as found
FLOOR_SIGNIFICANCE = 6.63
#: bins per decade of the periodogram the plateau is fitted to
_BINS = 20
#: the power law's exponent is held in this range (C1D ~ k^-(1+2H): H from -0.25 to 3.5)
_SLOPES = (0.5, 8.0)


class Floor(NamedTuple):
    """The plateau found: its level (C1D in m^3; 0 when none), the wavenumber (1/m) where the
    power law falls to NOISE_MARGIN x the level (inf when none), the likelihood gain of the
    plateau, and the fitted power law's exponent s (``C1D ~ k^-s``)."""

    level: float
    cutoff: float
    gain: float
    exponent: float


def _profile(s, t, x, C, n):
    """Minus the Whittle log-likelihood of ``S = A (exp(-s x) + exp(t - s x_top))``, maximised
    over A in closed form (``A = sum(n C / g) / sum(n)``); s and t broadcast. Returns
    (objective, ln A)."""
    g = np.exp(-s[..., None] * x) + np.exp(t[..., None] - s[..., None] * x[-1])
    A = np.sum(n * C / g, axis=-1) / np.sum(n)
    return np.sum(n * np.log(g), axis=-1) + np.sum(n) * (np.log(A) + 1.0), np.log(A)


def _power_law(x, C, n) -> tuple[float, float, float]:
    """(ln A, s, objective) of the best pure power law ``A exp(-s x)`` (A in closed form)."""
    from scipy.optimize import minimize_scalar  # here: scipy.optimize takes ~1 s to import

    def objective(s):
        g = np.exp(-s * x)
        A = np.sum(n * C / g) / np.sum(n)
        return float(np.sum(n * np.log(A * g)) + np.sum(n)), math.log(A)

    res = minimize_scalar(lambda s: objective(s)[0], bounds=_SLOPES, method="bounded")
    value, lnA = objective(float(res.x))
    return lnA, float(res.x), value


def _with_plateau(x, C, n) -> tuple[float, float, float, float]:
    """(ln A, s, ln N, objective) of the best power law plus plateau: a grid over the exponent
    s and the plateau's level relative to the power law's top value, refined by Nelder-Mead."""
    from scipy.optimize import minimize  # here: scipy.optimize takes ~1 s to import

    S, T = np.meshgrid(np.linspace(*_SLOPES, 76), np.linspace(-12.0, 4.0, 65), indexing="ij")
    obj, _ = _profile(S, T, x, C, n)
    i, j = np.unravel_index(int(np.argmin(obj)), obj.shape)

    def objective(p):
        return float(_profile(np.array(p[0]), np.array(p[1]), x, C, n)[0])

    res = minimize(objective, [S[i, j], T[i, j]], method="Nelder-Mead", options={"xatol": 1e-4})
    s, t = float(np.clip(res.x[0], *_SLOPES)), float(res.x[1])
    value, lnA = _profile(np.array(s), np.array(t), x, C, n)
    return float(lnA), s, float(lnA + t - s * x[-1]), float(value)


def load_scipy() -> None:
    """Import the SciPy modules the floor and the fit use, before any warning is shown: a first
    import of SciPy changes the warning filters, which makes Python show a warning already
    shown once again (the analysis of a scan in a loop would repeat its warnings)."""
    import scipy.optimize  # noqa: F401
    import scipy.special  # noqa: F401


def find_floor(k: np.ndarray, C: np.ndarray, independent: float, k_low: float) -> Floor:
    """The white-noise plateau of a raw periodogram ``(k, C)`` (module docstring).

    ``independent``: the number of independent values one periodogram value is worth (profiles
    averaged / the window's factor); ``k_low``: the usable range's low end (1/m), below which
    nothing is fitted."""
    lo = max(k_low, k[-1] / 10.0**FLOOR_DECADES)
    if k[-1] <= lo * 1.5:
        return Floor(0.0, math.inf, 0.0, math.nan)
    kb, Cb, counts = log_bins(k, C, _BINS, lo, float(k[-1]))
    if kb.size < 6 or np.any(Cb <= 0.0):
        return Floor(0.0, math.inf, 0.0, math.nan)
    ref = math.sqrt(kb[0] * kb[-1])
    x, n = np.log(kb / ref), counts * independent
    plain = _power_law(x, Cb, n)
    *p, value = _with_plateau(x, Cb, n)
    S = np.exp(p[0] - p[1] * x) + np.exp(p[2])
    dispersion = max(1.0, float(np.sum(n * (Cb / S - 1.0) ** 2)) / max(kb.size - 3, 1))
    gain = 2.0 * (plain[2] - value) / dispersion
    if gain < FLOOR_SIGNIFICANCE:
        return Floor(0.0, math.inf, gain, plain[1])
    level = math.exp(p[2])
    cutoff = ref * math.exp((p[0] - math.log(NOISE_MARGIN * level)) / p[1])
    return Floor(level, cutoff, gain, float(p[1]))
