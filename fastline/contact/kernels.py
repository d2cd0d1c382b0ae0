"""Compiled array stages of a solve that run around the Newton kernel, without the GIL.

A warm line-contact solve at n = 1024 spends ~0.6 ms in the compiled Newton iteration
(:mod:`fastline.contact.line_newton`, which releases the GIL) and, before this module, ~0.2 ms in
Python and NumPy around it: the cold start, the load normalisation, the flushed pressure and the
profile measures, each a handful of NumPy passes over the grid that hold the GIL. Threads sharing
one model then serialise on that part (Amdahl: ~22 % held caps two threads at ~1.6x). Here each
of those stages is one loop in a ``nogil`` kernel; the Python wrappers that call them
(:func:`fastline.contact.core.normalise`, :func:`fastline.contact.core.pressure_of`, the cold start
of :class:`fastline.contact.model.ContactModel`, :func:`fastline.contact.line._measures`) keep
their signatures. Results equal the NumPy expressions they replace to round-off (sums in a
different order, FMA contraction).
"""

from __future__ import annotations

import math

import numba

from fastline._lib.jit import JIT

_LN2 = math.log(2.0)
#: :func:`_logaddexp` drops a term this far below the other (e^-40 = 4.2e-18)
_LOGADDEXP_CUT = 40.0

#: pressures more than e^460 (1e200) below the peak are flushed to 0: they carry no load and
#: no displacement float64 can register, and their products with cell widths, coordinates or
#: separations would be subnormal numbers, 10-100x slower in every operation (at n = 16384 the
#: profile measures took 28 ms and each normalisation 11 ms before this floor)
LN_FLOOR = 460.0
#: and absolutely below 1e-290 Pa
LN_TINY = math.log(1e-290)


# A maximum as the loop ``m = max(m, x_i)`` is one chain of compares at their latency (~3
# cycles a cell; the JIT options let LLVM reorder nothing). Max is exact, so four interleaved
# chains give the same value, bit for bit (NaN skipped as there: Numba's ``max(m, nan)`` is m).
@numba.njit(**JIT)
def largest(x, start):
    """``max(start, x_0, x_1, ...)``, NaN skipped (``start`` not NaN), in four chains."""
    n = x.shape[0]
    n4 = n - n % 4
    m0 = m1 = m2 = m3 = start
    for i in range(0, n4, 4):
        m0 = max(m0, x[i])
        m1 = max(m1, x[i + 1])
        m2 = max(m2, x[i + 2])
        m3 = max(m3, x[i + 3])
    for i in range(n4, n):
        m0 = max(m0, x[i])
    return max(max(m0, m1), max(m2, m3))


@numba.njit(**JIT)
def largest_abs(x, start):
    """``max(start, |x_0|, |x_1|, ...)``, NaN skipped (``start`` not NaN), in four chains."""
    n = x.shape[0]
    n4 = n - n % 4
    m0 = m1 = m2 = m3 = start
    for i in range(0, n4, 4):
        m0 = max(m0, abs(x[i]))
        m1 = max(m1, abs(x[i + 1]))
        m2 = max(m2, abs(x[i + 2]))
        m3 = max(m3, abs(x[i + 3]))
    for i in range(n4, n):
        m0 = max(m0, abs(x[i]))
    return max(max(m0, m1), max(m2, m3))


@numba.njit(**JIT)
def normalise_into(v, load, w):
    """Shift v in place so that ``sum(w exp(v)) = load`` (log-sum-exp, terms below e^-460 of
    the largest left out: see :func:`fastline.contact.core.normalise`)."""
    vmax = largest(v, -math.inf)
    acc = 0.0
    for i in range(v.shape[0]):
        acc += w[i] * math.exp(max(v[i] - vmax, -LN_FLOOR))
    shift = math.log(load) - (vmax + math.log(acc))
    for i in range(v.shape[0]):
        v[i] += shift


@numba.njit(**JIT)
def normalise_pressure_into(v, load, w, p):
    """:func:`normalise_into`, and ``p = exp(v)`` of the shifted v with the flush of
    :func:`pressure_into`, from the same exponentials: ``exp(v_i + shift) = exp(v_i - max v)
    exp(max v + shift)``, one ``exp`` per cell instead of two (the exponentials are most of
    both passes: ~5 ns a cell, a convolution costs 5-7). p equals :func:`pressure_into`'s to
    a few ulp (a NaN in v makes v NaN and p 0, as the two stages do)."""
    n = v.shape[0]
    vmax = largest(v, -math.inf)
    acc = 0.0
    for i in range(n):
        p[i] = math.exp(max(v[i] - vmax, -LN_FLOOR))
        acc += w[i] * p[i]
    shift = math.log(load) - (vmax + math.log(acc))
    top = vmax + shift  # = max(v + shift): rounding is monotone
    floor = max(top - LN_FLOOR, LN_TINY)
    peak = math.exp(top)
    for i in range(n):
        v[i] += shift
        p[i] = p[i] * peak if v[i] > floor else 0.0


@numba.njit(**JIT)
def pressure_into(v, p):
    """``p = exp(v)``, 0 below ``max(v) - LN_FLOOR`` and below 1e-290 Pa (all 0 if v has a
    NaN, as the NumPy form gives)."""
    vmax = -math.inf
    for i in range(v.shape[0]):
        if v[i] != v[i]:
            vmax = math.nan
            break
        vmax = max(vmax, v[i])
    floor = max(vmax - LN_FLOOR, LN_TINY) if vmax == vmax else math.nan
    for i in range(v.shape[0]):
        p[i] = math.exp(v[i]) if v[i] > floor else 0.0


@numba.njit(**JIT)
def _logaddexp(a, b):
    """``ln(e^a + e^b)`` as ``numpy.logaddexp`` computes it (equal infinities, NaN), except
    that a term more than ``_LOGADDEXP_CUT`` below the other is dropped (it would add less
    than 4.3e-18: nothing to a log-pressure of magnitude above 1e-2), which saves the exp and
    the log1p on the cells where one profile alone counts (most of a cold start's cells)."""
    if a == b:
        return a + _LN2
    d = a - b
    if d > _LOGADDEXP_CUT:
        return a
    if d < -_LOGADDEXP_CUT:
        return b
    if d > 0.0:
        return a + math.log1p(math.exp(-d))
    if d <= 0.0:
        return b + math.log1p(math.exp(d))
    return d  # NaN


@numba.njit(**JIT)
def hertz_line_gap(xi):
    """The gap outside a smooth (Hertz) line contact in units of ``a^2 / (2R)``, at
    ``xi = |x| / a >= 1``: ``xi sqrt(xi^2 - 1) - arccosh(xi)`` (the surface displacement of
    the elliptic pressure, K. L. Johnson, Contact Mechanics, Cambridge University Press 1985,
    section 5.6, taken from the parabola; ``(4 sqrt(2) / 3) (xi - 1)^(3/2)`` near the edge)."""
    s = math.sqrt(xi * xi - 1.0)
    return xi * s - math.log(xi + s)


@numba.njit(**JIT)
def cold_start_into(x, a, ln_h, floor, ln_g, two_s2, ln_t, k_t, out):
    """ln of the blend of a Hertz and a Gaussian profile on the cells ``x`` (m):
    ``logaddexp(ln_h + ln(max(1 - (x/a)^2, floor)) / 2, ln_g - x^2 / (2 s^2))``, with
    ``ln_h``, ``ln_g`` the logarithms of the weighted peaks and ``two_s2 = 2 s^2`` (m^2);
    outside the Hertz half-width a, the exponential law's tail ``ln_t - k_t G(|x|/a)`` is
    added in (G, :func:`hertz_line_gap`; ``k_t = a^2 / (2 R u0)``; ``ln_t = -inf``: none)."""
    for i in range(x.shape[0]):
        t = x[i] / a
        q = max(1.0 - t * t, floor)
        lh = ln_h + 0.5 * math.log(q) if q > 0.0 else -math.inf
        lg = ln_g - x[i] * x[i] / two_s2
        v = _logaddexp(lh, lg)
        if ln_t > -math.inf and abs(t) >= 1.0:
            v = _logaddexp(v, ln_t - k_t * hertz_line_gap(abs(t)))
        out[i] = v


@numba.njit(**JIT)
def line_cells(dx, two_r, x, gap, w):
    """Cell centres ``x = (i - (n-1)/2) dx``, the gap ``x^2 / 2R`` and the weights ``dx``."""
    c = 0.5 * (x.shape[0] - 1)
    for i in range(x.shape[0]):
        xi = (i - c) * dx
        x[i] = xi
        gap[i] = xi * xi / two_r
        w[i] = dx


@numba.njit(**JIT)
def line_measures(x, p, dx):
    """``(p0, s, fwhm, sum p)`` of piecewise-constant p on the cells x (see
    :func:`fastline.contact.model.peak`, :func:`fastline.contact.model.fwhm` and
    :func:`fastline.contact.model.std`, which this equals to round-off)."""
    n = p.shape[0]
    m0 = 0.0
    m1 = 0.0
    for i in range(n):
        m0 += p[i]
        m1 += x[i] * p[i]
    p0 = peak(p)
    xc = m1 / m0
    m2 = 0.0
    for i in range(n):
        m2 += (x[i] - xc) * (x[i] - xc) * p[i]
    s = math.sqrt(m2 / m0 + dx * dx / 12.0)
    return p0, s, fwhm(x, p, p0), m0


@numba.njit(**JIT)
def peak(p):
    """Peak value of p by a parabola through the three points around the discrete maximum
    (the first maximum; the maximum itself at an end of the grid)."""
    n = p.shape[0]
    k = 0
    for i in range(n):
        if p[i] > p[k]:
            k = i
    p0 = p[k]
    if 0 < k < n - 1:
        a, b, c = p[k - 1], p[k], p[k + 1]
        den = a - 2.0 * b + c
        if den < 0.0:
            p0 = b - 0.25 * (a - c) * (0.5 * (a - c) / den)
    return p0


@numba.njit(**JIT)
def fwhm(x, p, p0):
    """Width between the outermost crossings of p0/2 by p on the cells x (linear
    interpolation between cells); NaN when the profile does not fall below p0/2 at both ends."""
    n = p.shape[0]
    half = 0.5 * p0
    i = 0
    while i < n and not p[i] >= half:
        i += 1
    j = n - 1
    while j >= 0 and not p[j] >= half:
        j -= 1
    if i == 0 or j == n - 1 or i >= n:
        return math.nan
    xl = x[i - 1] + (half - p[i - 1]) * (x[i] - x[i - 1]) / (p[i] - p[i - 1])
    xr = x[j] + (half - p[j]) * (x[j + 1] - x[j]) / (p[j + 1] - p[j])
    return xr - xl


@numba.njit(**JIT)
def hermite_accumulate(xq, x, y, m, weight, out):
    """``out += weight * H(xq)``, H the cubic Hermite interpolant through (x, y) with slopes m
    (x increasing), constant beyond the ends: the sweep predictor's core term (see
    :func:`fastline.contact.model.hermite_slopes`). The query points are visited in increasing
    order when they are sorted, so the interval search moves forward."""
    n = x.shape[0]
    j = 0
    for k in range(xq.shape[0]):
        q = xq[k]
        if q <= x[0]:
            out[k] += weight * y[0]
            continue
        if q >= x[n - 1]:
            out[k] += weight * y[n - 1]
            continue
        if q < x[j]:
            j = 0
        while x[j + 1] < q:
            j += 1
        h = x[j + 1] - x[j]
        t = (q - x[j]) / h
        s = 1.0 - t
        out[k] += weight * (
            (1.0 + 2.0 * t) * s * s * y[j]
            + t * s * s * h * m[j]
            + t * t * (3.0 - 2.0 * t) * y[j + 1]
            - t * t * s * h * m[j + 1]
        )


@numba.njit(**JIT)
def cold_start_normalised(x, profiles, load, w, out):
    """:func:`cold_start_into` then :func:`normalise_into` to ``load`` (N/m) with the weights w
    (m): the start of a cold solve in one call (one hand-over of the GIL instead of two, and no
    copy). ``profiles = (a, ln_h, floor, ln_g, two_s2, ln_t, k_t)``, the arguments of
    :func:`cold_start_into` (a in m, ln_h and ln_g logarithms of pressures in Pa, floor
    dimensionless, two_s2 in m^2, ln_t as ln_h, k_t dimensionless)."""
    a, ln_h, floor, ln_g, two_s2, ln_t, k_t = profiles
    cold_start_into(x, a, ln_h, floor, ln_g, two_s2, ln_t, k_t, out)
    normalise_into(out, load, w)
