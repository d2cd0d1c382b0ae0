"""Tabulated spectra: checking a table, its log-log slope, and its power-law continuation.

Wavenumbers q in 1/m, isotropic spectra C(q) in m^4 (Persson's convention,
``h_rms^2 = 2 pi int q C dq``).
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import ArrayLike

from fastline._lib.validate import WAVENUMBER_RANGE, finite_scalar, positive, real_array
from fastline.theory.spectra import TabulatedPSD


def checked_table(
    name_q: str, q: ArrayLike, name_c: str, C: ArrayLike, *, positive_values: bool
) -> tuple[np.ndarray, np.ndarray]:
    """A spectrum table checked: wavenumbers q (1/m, > 0, strictly increasing, >= 3 points) and
    finite values C of the same length (> 0 with ``positive_values``)."""
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


def loglog_slope(q: np.ndarray, C: np.ndarray, decades: float) -> float:
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
        slope = loglog_slope(q, C, positive("fit_decades", fit_decades))
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
