"""The self-affine model with roll-off fitted to a measured spectrum, with standard errors.

Model (docs/theory.md section 2): ``C = C0`` below qr, ``C0 (q/qr)^-2(1+H)`` above; fitted to
the 1D spectrum of line scans (Whittle likelihood) or to an isotropic table (least squares in
``ln C``). Wavenumbers in 1/m, C in m^4, C1D in m^3, heights in m.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import NamedTuple

import numpy as np
from numpy.typing import ArrayLike

from fastline._lib.validate import boolean, positive
from fastline.surfaces.heights import topography_warning
from fastline.surfaces.profiles import ProfileSpectrum
from fastline.surfaces.ranges import range_argument
from fastline.surfaces.tables import checked_table
from fastline.theory.spectra import PSD, SelfAffinePSD, TabulatedPSD

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
#: the interval of q_r (``qr_interval``) holds the roll-offs whose profile likelihood (twice
#: its log, over the dispersion) lies within this of the best: two standard errors
QR_INTERVAL_LEVEL = 4.0
#: a resolved q_r whose interval reaches beyond this factor of it on either side is uncertain
#: (a TopographyWarning says so): one profile places a roll-off only a dozen Fourier modes above
#: its lowest to within about 1.3x (docs/topography.md, "How far a roll-off can be measured")
QR_TOLERANCE = 1.25


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
    qr_interval : tuple of float
        The roll-offs (1/m) the data allow at two standard errors: where twice the profile
        log-likelihood lies within ``QR_INTERVAL_LEVEL`` of its best (fitted to C1D; it may be
        lopsided), or ``qr exp(+-2 se)`` (fitted to C(q)). Its lower end is the lowest fitted
        wavenumber when the data allow no roll-off at all. NaN without roll-off.
    qr_uncertain : bool
        The interval reaches beyond ``QR_TOLERANCE`` (25 %) of q_r on either side (a warning
        says so), or q_r is not resolved.
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
    qr_interval: tuple[float, float] = (math.nan, math.nan)
    qr_uncertain: bool = False


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
        q_all, C_all = checked_table("q", q_all, "C", C_all, positive_values=False)
    lo, hi = (None, None) if q_range is None else range_argument(q_range)
    keep = (C_all > 0.0) & (q_all >= (lo or 0.0)) & (q_all <= (hi or np.inf))
    if keep.sum() < 4:
        raise ValueError(f"need at least 4 points with C > 0 in the fitted range, got {keep.sum()}")
    live = q_all[C_all > 0.0]
    return q_all[keep], C_all[keep], (float(live[0]), float(live[-1]))


def _best_rolloff(x, y, wts) -> float:
    """ln qr minimising the profile least squares: a scan of 200 values, then Brent."""
    from scipy.optimize import minimize_scalar  # here: scipy.optimize takes ~1 s to import

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
    from scipy.special import beta, betainc  # here: SciPy's import costs ~0.2 s

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
    by Nelder-Mead within the bounds."""
    from scipy.optimize import minimize  # here: scipy.optimize takes ~1 s to import

    x = np.log(k)
    Hs = np.linspace(*_HURST_BOUNDS, 100)
    xrs = np.linspace(x[0], x[-3], 60) if rolloff else np.array([x[0]])
    _, obj = _whittle(C, n, _c1d_shape(k, Hs[:, None, None], xrs[None, :, None]))
    i, j = np.unravel_index(int(np.argmin(obj)), obj.shape)
    if rolloff:
        res = minimize(
            lambda p: float(_whittle(C, n, _c1d_shape(k, p[0], p[1]))[1]),
            [Hs[i], xrs[j]],
            method="Nelder-Mead",
            bounds=[_HURST_BOUNDS, (x[0], x[-3])],
            options={"xatol": 1e-5, "fatol": 1e-9},
        )
        H, xr = (float(v) for v in res.x)
    else:
        res = minimize(
            lambda p: float(_whittle(C, n, _c1d_shape(k, p[0], x[0]))[1]),
            [Hs[i]],
            method="Nelder-Mead",
            bounds=[_HURST_BOUNDS],
            options={"xatol": 1e-5, "fatol": 1e-9},
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
    return cov, float(np.sqrt(np.mean(np.log(np.maximum(ratio, 1e-3)) ** 2))), dispersion


def _profile_fit_points(spectrum, q_range):
    """(k, C1D, n) of the measured points (the two end points continue the bins: left out)
    inside q_range, less the instrument's white-noise level (``noise_floor``: the mean of a
    bin less a constant keeps the Whittle score unbiased); n the equivalent number of
    independent periodogram values of each."""
    lo, hi = (None, None) if q_range is None else range_argument(q_range)
    k, C = spectrum.k, spectrum.C1D
    keep = (spectrum.counts > 0) & (C > 0.0) & (k >= (lo or 0.0)) & (k <= (hi or np.inf))
    if keep.sum() < 4:
        raise ValueError(
            f"need at least 4 points with C1D > 0 in the fitted range, got {keep.sum()}"
        )
    n = spectrum.counts[keep] * spectrum.n_profiles / spectrum.window_factor
    return k[keep], C[keep] - spectrum.noise_floor, n.astype(np.float64)


class _Fitted(NamedTuple):
    """A fit's ln C0, H, ln qr, their covariance, the rms residual of ``ln C``, the fitted
    wavenumbers (1/m), the roll-off's gain over a pure power law and the interval of ln qr."""

    a: float
    H: float
    xr: float
    cov: np.ndarray
    rms: float
    q: np.ndarray
    gain: float
    interval: tuple[float, float] = (math.nan, math.nan)


def _whittle_at(k, C, n, xr: float) -> float:
    """The Whittle objective with ln qr held at xr, minimised over H (and C0, in closed
    form): a grid over H refined by Brent's method."""
    from scipy.optimize import minimize_scalar  # here: scipy.optimize takes ~1 s to import

    Hs = np.linspace(*_HURST_BOUNDS, 100)
    obj = _whittle(C, n, _c1d_shape(k, Hs[:, None], xr))[1]
    j = int(np.argmin(obj))
    res = minimize_scalar(
        lambda H: float(_whittle(C, n, _c1d_shape(k, H, xr))[1]),
        bounds=(Hs[max(j - 1, 0)], Hs[min(j + 1, Hs.size - 1)]),
        method="bounded",
        options={"xatol": 1e-6},
    )
    return min(float(res.fun), float(obj[j]))


def _profile_interval(k, C, n, xr: float, best: float, dispersion: float):
    """(lo, hi) of ln qr where twice the profile log-likelihood over the dispersion lies within
    QR_INTERVAL_LEVEL of its best (``best``, at xr): each end found by stepping out from xr
    to the ends of the fitted roll-offs (ln k[0], ln k[-3]) and Brent's root between steps;
    an end that is never crossed is that limit."""
    from scipy.optimize import brentq  # here: scipy.optimize takes ~1 s to import

    def excess(g):
        return 2.0 * (_whittle_at(k, C, n, g) - best) / dispersion - QR_INTERVAL_LEVEL

    ends = []
    for limit in (math.log(k[0]), math.log(k[-3])):
        steps = np.linspace(xr, limit, 17)[1:]
        inner, end = xr, limit
        for g in steps:
            if excess(g) > 0.0:
                end = brentq(excess, inner, g, xtol=1e-4) if g != inner else g
                break
            inner = g
        ends.append(float(end))
    return ends[0], ends[1]


def _fit_profile(spectrum, q_range, rolloff):
    """The model's C1D fitted to a ProfileSpectrum by the Whittle likelihood (:class:`_Fitted`;
    the interval of ln qr from the profile likelihood)."""
    k, C, n = _profile_fit_points(spectrum, q_range)
    a, H, xr, objective = _whittle_optimum(k, C, n, rolloff)
    at_bound = H in _HURST_BOUNDS
    free = [c for c in (0, 1, 2) if not (c == 1 and at_bound) and not (c == 2 and not rolloff)]
    cov, rms, dispersion = _whittle_covariance(k, C, n, np.array([a, H, xr]), free)
    if not rolloff:
        return _Fitted(a, H, xr, cov, rms, k, 0.0)
    # the likelihood ratio against a pure power law, in units of the dispersion
    gain = 2.0 * (_whittle_optimum(k, C, n, False)[3] - objective) / dispersion
    interval = _profile_interval(k, C, n, xr, objective, dispersion)
    return _Fitted(a, H, xr, cov, rms, k, gain, interval)


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
    se = math.sqrt(cov[2, 2])
    interval = (max(xr - 2.0 * se, float(x[0])), xr + 2.0 * se) if rolloff else (math.nan,) * 2
    return _Fitted(a, H, xr, cov, math.sqrt(sse / np.sum(wts)), q, gain, interval)


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


def _warn_uncertain(qr: float, interval, lowest: float, length: float | None) -> None:
    lo, hi = interval
    where = f"{qr / lowest:.3g} times the lowest fitted wavenumber {lowest:.3g} 1/m"
    advice = "a larger map or more maps narrow it"
    if length is not None:
        where = f"{qr * length / (2.0 * math.pi):.3g} Fourier modes of the scan up ({where})"
        advice = (
            "one profile places a roll-off within 25 % only from about 32 (H near 1) to 128 "
            "(H = 0.3) modes up: more profiles, a longer scan or a map narrow it"
        )
    topography_warning(
        f"fit_self_affine: q_r = {qr:.3g} 1/m is uncertain: the data allow {lo:.3g}-{hi:.3g} "
        f"1/m (two standard errors; qr_interval), more than {QR_TOLERANCE - 1.0:.0%} either "
        f"way. The roll-off lies {where}; {advice}",
    )


def _warn_unresolved(qr: float, lowest: float, gain: float, upper: float) -> None:
    if qr < lowest * ROLLOFF_MARGIN:
        why = f"lies within a factor {ROLLOFF_MARGIN:.3g} of the lowest fitted wavenumber"
    else:
        why = (
            f"improves on a pure power law by {gain:.3g} < {ROLLOFF_SIGNIFICANCE:g} (likelihood "
            "ratio or F statistic): noise could make it, from the range starting at"
        )
    topography_warning(
        f"fit_self_affine: the roll-off is not resolved: q_r = {qr:.3g} 1/m {why} {lowest:.3g} "
        f"1/m. The roll-off may lie anywhere below {upper:.3g} 1/m (two standard errors); q_r, "
        "its error and the model's h_rms are not measurements (a longer scan, more profiles or "
        "a map resolve them)",
    )


def _fit_result(f: _Fitted, m0: float, m1: float, flags, fitted_to: str) -> SelfAffineFit:
    """The fitted model on ``[m0, m1]`` (1/m) with its parameters and their standard errors
    (that of h_rms from its derivatives, by central differences, and the covariance)."""
    hurst_at_bound = f.H in _HURST_BOUNDS
    qr_at_bound, qr_uncertain = flags
    a, H, xr = f.a, f.H, max(f.xr, math.log(m0))
    p = np.array([a, H, xr])
    grad = np.array(
        [
            (_model_h_rms(*(p + d), m0, m1) - _model_h_rms(*(p - d), m0, m1)) / 2e-6
            for d in np.eye(3) * 1e-6
        ]
    )
    h_rms = _model_h_rms(a, H, xr, m0, m1)
    model = SelfAffinePSD(h_rms, H, m0, min(max(math.exp(xr), m0), m1 * (1 - 1e-12)), m1)
    cov, q = f.cov, f.q
    return SelfAffineFit(
        psd=model,
        h_rms=h_rms,
        hurst=float(H),
        qr=model.qr,
        C0=model.C0,
        h_rms_err=float(math.sqrt(max(grad @ cov @ grad, 0.0))),
        hurst_err=float(math.sqrt(cov[1, 1])),
        qr_err=math.nan if qr_at_bound else float(model.qr * math.sqrt(cov[2, 2])),
        rms_residual=float(f.rms),
        n_points=int(q.size),
        q_range=(float(q[0]), float(q[-1])),
        at_bound=bool(hurst_at_bound or qr_at_bound),
        fitted_to=fitted_to,
        hurst_at_bound=bool(hurst_at_bound),
        qr_at_bound=bool(qr_at_bound),
        rolloff_gain=float(f.gain),
        qr_interval=(float(math.exp(f.interval[0])), float(math.exp(f.interval[1]))),
        qr_uncertain=bool(qr_uncertain),
    )


def _qr_flags(fitted: _Fitted, length: float | None) -> tuple[bool, bool]:
    """(q_r not resolved, q_r uncertain) of a fit with roll-off, each said by a warning;
    ``length``: the profile's (m), None for a table."""
    qr, lowest, gain = math.exp(fitted.xr), float(fitted.q[0]), fitted.gain
    qr_at_bound = qr < lowest * ROLLOFF_MARGIN or gain < ROLLOFF_SIGNIFICANCE
    lo, hi = (math.exp(v) for v in fitted.interval)
    wide = not (qr / QR_TOLERANCE <= lo and hi <= qr * QR_TOLERANCE)
    if qr_at_bound:
        _warn_unresolved(qr, lowest, gain, hi)
    elif wide:
        _warn_uncertain(qr, (lo, hi), lowest, length)
    return qr_at_bound, qr_at_bound or wide


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
    rolloff = boolean("rolloff", rolloff)
    profile = isinstance(psd, ProfileSpectrum)
    m0, m1 = _model_range(psd, q0, q1)
    fitted = (_fit_profile if profile else _fit_table)(psd, q_range, rolloff)
    flags = _qr_flags(fitted, psd.length if profile else None) if rolloff else (False, False)
    return _fit_result(fitted, m0, m1, flags, "C1D(k)" if profile else "C(q)")
