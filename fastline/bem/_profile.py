"""Peak, width and spread of a sampled nominal-pressure profile, and jackknife error bars."""

from __future__ import annotations

import math

import numpy as np

#: Half-width of the central window of the peak fit, in units of the profile's s.
PEAK_WINDOW = 0.75


def central_peak(u, p, s, weights=None):
    """Peak ``a`` of the least-squares fit ``p = a + b u^2 + c u^4`` over ``|u| <= 0.75 s``.

    ``u`` is the distance from the centre (signed or radial).  Averaging over the central
    window keeps the noise of a rough-contact profile out of the peak (the largest sample of a
    noisy profile is biased upward); the fit's own bias is ~2e-4 relative for Hertz and
    ~5e-4 for a Gaussian (their u^6 terms).  Falls back to the largest sample if the window
    holds fewer than 5 samples.
    """
    inside = np.abs(u) <= PEAK_WINDOW * s
    if np.count_nonzero(inside) < 5:
        return float(np.max(p))
    t = u[inside] / s
    A = np.stack([np.ones(t.size), t * t, t**4], axis=1)
    b = p[inside]
    if weights is not None:
        w = np.sqrt(weights[inside])
        A, b = A * w[:, None], b * w
    return float(np.linalg.lstsq(A, b, rcond=None)[0][0])


def half_crossings(x, p, level):
    """Outermost positions where ``p`` crosses ``level`` (linear interpolation); NaN if the
    profile is still above ``level`` at an end of the sampled range."""
    above = np.nonzero(p >= level)[0]
    if above.size == 0:
        return math.nan, math.nan
    i, j = above[0], above[-1]
    left = math.nan
    if i > 0:
        left = x[i - 1] + (level - p[i - 1]) * (x[i] - x[i - 1]) / (p[i] - p[i - 1])
    right = math.nan
    if j < p.size - 1:
        right = x[j] + (level - p[j]) * (x[j + 1] - x[j]) / (p[j + 1] - p[j])
    return float(left), float(right)


def jackknife(samples, statistic):
    """Statistic of the mean of ``samples`` (axis 0) and its jackknife standard error.

    ``statistic`` maps a mean sample to a tuple of floats.  With one sample the errors are NaN.
    """
    samples = np.asarray(samples, dtype=np.float64)
    n = samples.shape[0]
    full = np.array(statistic(samples.mean(axis=0)), dtype=np.float64)
    if n < 2:
        return full, np.full_like(full, np.nan)
    total = samples.sum(axis=0)
    loo = np.array([statistic((total - samples[k]) / (n - 1)) for k in range(n)])
    err = np.sqrt((n - 1) / n * np.sum((loo - loo.mean(axis=0)) ** 2, axis=0))
    return full, err
