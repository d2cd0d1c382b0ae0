"""Peak, width and spread of a sampled nominal-pressure profile, and jackknife error bars."""

from __future__ import annotations

import math

import numpy as np


def peak(x, p):
    """Maximum of ``p`` refined by the parabola through the largest sample and its neighbours."""
    i = int(np.argmax(p))
    if 0 < i < p.size - 1:
        a, b, c = p[i - 1], p[i], p[i + 1]
        den = a - 2.0 * b + c
        if den < 0.0:
            t = 0.5 * (a - c) / den
            return float(b - 0.25 * (a - c) * t)
    return float(p[i])


def radial_peak(r, p, rings=3):
    """``p(0)`` from the least-squares fit ``p = a + b r^2`` to the innermost ``rings`` rings."""
    k = min(rings, r.size)
    A = np.stack([np.ones(k), r[:k] ** 2], axis=1)
    return float(np.linalg.lstsq(A, p[:k], rcond=None)[0][0])


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


def line_stats(x, p, dx):
    """(p0, s, fwhm) of a line profile on cell centres ``x`` (``s`` cell-exact about the
    centroid: the ``dx^2/12`` of a uniform cell included)."""
    m0 = p.sum()
    xc = np.dot(x, p) / m0
    s = math.sqrt(np.dot((x - xc) ** 2, p) / m0 + dx * dx / 12.0)
    p0 = peak(x, p)
    left, right = half_crossings(x, p, 0.5 * p0)
    return p0, s, right - left


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
