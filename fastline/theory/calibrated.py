"""A pressure law calibrated on boundary-element ensembles of the user's own spectrum.

Persson's u(p) is a mean-field approximation: on a narrow band it puts the mean gap 8-30 %
too high at low pressure, and its critical-junction gap is 1.2-1.5x the Reynolds effective gap
of an exact gap field (docs/validation.md). :func:`fastline.calibrate` replaces both by the
boundary-element method's own numbers for the user's spectrum, measured once; this module holds
what it measures and the law made of it.

The fit (:class:`CalibratedLaw`)
--------------------------------
The calibration points are ensemble means at pressures ``p_k``: the mean gap ``u_k`` with its
standard error ``e_k``, the contact fraction and the hydraulic gaps ``g_x``, ``g_y`` (the
Reynolds effective gap ``(12 eta K)^(1/3)`` of the gap fields for flow along x and along y).

1. Monotone step: weighted isotonic regression of u on ``v = ln p`` (pool-adjacent-violators,
   weights ``1 / e_k^2``; R. E. Barlow et al., *Statistical Inference under Order
   Restrictions*, Wiley (1972)). Points that violate ``u`` decreasing are pooled into their
   weighted mean; a violation larger than ``MONOTONE_SIGMAS`` combined standard errors is not
   noise and is refused (``ValueError``).
2. Smooth curve: the pooled nodes joined by the monotone piecewise cubic Hermite of
   :class:`~fastline.theory.laws.TabulatedLaw` (u in ln p, Fritsch-Butland slopes): C1, no
   overshoot, so u(p) is strictly decreasing.
3. Join: outside the simulated range ``[p_lo, p_hi]`` the law is Persson's, raised to a power
   and scaled to meet the fit in value and slope:
   ``u(p) = u_fit(p_end) (u_P(p) / u_P(p_end))^m`` with ``p_end`` the nearer end and ``m`` the
   fit's secant in ``ln u`` against ``ln p`` over its end cell divided by Persson's over the
   same cell (``m = 1``, Persson's shape scaled, when the fit has Persson's shape there). It is
   sampled at ``JOIN_PER_DECADE`` nodes per decade over ``JOIN_DECADES`` decades below ``p_lo``
   and up to near full contact above ``p_hi``; the same Hermite runs through every node, so
   the law is continuous and C1 across the joins, and the slopes of the cells on either side
   of a join agree. (A BEM ensemble's u(p) flattens at low pressure, where a finite cell holds
   few contact spots: on the narrow band of docs/validation.md its log-slope at the bottom of
   the range is 0.4-0.6 times Persson's; scaling Persson's u by value alone put a slope up to
   2.5 times too steep below the range and widened a cylinder whose flanks lie there by 2 %.)
   Beyond the outermost nodes it continues exponentially (as every :class:`TabulatedLaw`).

The hydraulic gap follows the same rule in ln g against ln p (isotonic, then piecewise linear
in log-log; joined to Persson's critical gap ``u_c(p)`` scaled at the ends). A pressure at
which no realisation percolates, or where Persson's interface seals, seals the law above it.

A calibrated law *is* a :class:`TabulatedLaw`: every solver takes it (``model=law``) and a
calibrated solve costs what a tabulated one costs.

File format
-----------
``law.save(path)`` writes a NumPy ``.npz`` archive of plain float arrays and one JSON string
(``metadata``: format, fastline version, E*, the settings of the calibration, a SHA-256
checksum of every array and of the metadata). ``CalibratedLaw.load(path)`` reads it with
``allow_pickle=False`` (a crafted file cannot run code) and refuses, with one
:class:`~fastline.errors.CalibrationFileError`, a file that is not such an archive, of
another format version, whose checksum does not match, or (given ``psd`` or ``E_star``) made
for another spectrum or modulus.
"""

from __future__ import annotations

import hashlib
import json
import math
import os
import warnings
import zipfile
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from fastline._lib.validate import E_STAR_RANGE, finite_array, in_span
from fastline._lib.version import __version__
from fastline.errors import CalibrationFileError, CalibrationWarning
from fastline.theory.laws import TabulatedLaw, _monotone_slopes
from fastline.theory.persson import PerssonTheory
from fastline.theory.spectra import PSD, TabulatedPSD

__all__ = ["CalibrationPoints", "CalibratedLaw", "FORMAT", "isotonic_decreasing"]

#: the format tag of a law file (a file with another tag is refused)
FORMAT = "fastline-calibrated-law/1"
#: a rise of u with p larger than this many combined standard errors is refused
MONOTONE_SIGMAS = 3.0
#: Persson nodes per decade of p in the joins, and the decades sampled below the range
JOIN_PER_DECADE = 8
JOIN_DECADES = 6.0
#: the upper join stops where u has fallen below this fraction of u at the top of the range
JOIN_FLOOR = 1e-6
#: relative tolerance of the spectrum and modulus checks of :meth:`CalibratedLaw.load`
MATCH_RTOL = 1e-6
#: the spectrum is recorded at its breakpoints and at this many log-spaced wavenumbers
SPECTRUM_SAMPLES = 65
#: the point arrays of :class:`CalibrationPoints`, in order
_POINT_FIELDS = (
    "p",
    "u",
    "u_error",
    "contact_fraction",
    "contact_fraction_error",
    "gap_x",
    "gap_x_error",
    "gap_y",
    "gap_y_error",
)


@dataclass(frozen=True)
class CalibrationPoints:
    """Ensemble means of a calibration, one per pressure (SI units; errors are standard errors
    of the mean over realisations, NaN with one realisation).

    Attributes
    ----------
    p : ndarray
        Nominal pressures [Pa], increasing.
    u, u_error : ndarray
        Mean gap [m].
    contact_fraction, contact_fraction_error : ndarray
        Real contact area fraction A/A0.
    gap_x, gap_x_error, gap_y, gap_y_error : ndarray
        Reynolds effective gap ``(12 eta K)^(1/3)`` [m] for flow along x and along y (0 where
        no realisation percolates).
    """

    p: np.ndarray
    u: np.ndarray
    u_error: np.ndarray
    contact_fraction: np.ndarray
    contact_fraction_error: np.ndarray
    gap_x: np.ndarray
    gap_x_error: np.ndarray
    gap_y: np.ndarray
    gap_y_error: np.ndarray

    def __post_init__(self):
        n = None
        for name in _POINT_FIELDS:
            a = np.array(getattr(self, name), dtype=np.float64).ravel()
            if n is None:
                n = a.size
            if a.size != n:
                raise ValueError(f"{name} must hold one value per pressure ({n}), got {a.size}")
            object.__setattr__(self, name, a)
        if n < 3:
            raise ValueError(f"p must hold at least 3 pressures, got {n}")
        for name in ("p", "u", "contact_fraction", "gap_x", "gap_y"):
            finite_array(name, getattr(self, name))
        if np.any(self.p <= 0.0) or np.any(np.diff(self.p) <= 0.0):
            raise ValueError("p must be > 0 Pa and strictly increasing")
        if np.any(self.u <= 0.0):
            raise ValueError("u must be > 0 m at every pressure (a mean gap)")

    @property
    def gap(self) -> np.ndarray:
        """Hydraulic gap [m] of an isotropic interface: the cube root of the mean of the x and y
        conductances (``g^3`` averaged)."""
        return np.cbrt(0.5 * (self.gap_x**3 + self.gap_y**3))


def isotonic_decreasing(y: ArrayLike, w: ArrayLike) -> tuple[np.ndarray, np.ndarray]:
    """Weighted least-squares non-increasing fit (pool adjacent violators).

    Parameters
    ----------
    y, w : array_like
        Values in order and their weights (> 0).

    Returns
    -------
    fit : ndarray
        The fitted values, one per point (non-increasing; equal within a pooled block).
    block : ndarray of int
        The block of each point (points pooled together share a block).
    """
    y = np.asarray(y, dtype=np.float64)
    w = np.asarray(w, dtype=np.float64)
    vals, wts, size = [], [], []
    for yi, wi in zip(y, w, strict=True):
        vals.append(yi)
        wts.append(wi)
        size.append(1)
        while len(vals) > 1 and vals[-2] <= vals[-1]:  # pool: equal values too (strictness)
            ws = wts[-2] + wts[-1]
            vals[-2] = (wts[-2] * vals[-2] + wts[-1] * vals[-1]) / ws
            wts[-2] = ws
            size[-2] += size[-1]
            del vals[-1], wts[-1], size[-1]
    block = np.repeat(np.arange(len(vals)), size)
    return np.asarray(vals)[block], block


def _weights(values, errors):
    """``1 / e^2`` with the errors floored at 1e-6 of the value (and 1 where all are unknown)."""
    e = np.where(np.isfinite(errors), errors, np.nan)
    if not np.any(np.isfinite(e)):
        return np.ones_like(values)
    floor = 1e-6 * np.abs(values)
    e = np.where(np.isfinite(e), np.maximum(e, floor), np.nanmax(e))
    return 1.0 / np.maximum(e, 1e-300) ** 2


def _check_monotone(p, u, err, what) -> None:
    """Refuse a rise of ``u`` with ``p`` beyond ``MONOTONE_SIGMAS`` combined errors."""
    e = np.where(np.isfinite(err), err, 0.0)
    rise = np.diff(u)
    bound = MONOTONE_SIGMAS * np.hypot(e[:-1], e[1:])
    bad = np.flatnonzero(rise > bound)
    if bad.size:
        k = int(bad[0])
        raise ValueError(
            f"the calibration's {what} is not monotone within its errors: it rises from "
            f"{u[k]:.6g} m at p = {p[k]:.6g} Pa to {u[k + 1]:.6g} m at p = {p[k + 1]:.6g} Pa "
            f"(more than {MONOTONE_SIGMAS:g} standard errors); the ensemble is too small or "
            "did not converge"
        )


def _pooled_nodes(p, y, err):
    """(ln p, y) at the blocks of the isotonic fit: the weighted mean ln p of each block."""
    w = _weights(y, err)
    fit, block = isotonic_decreasing(y, w)
    v = np.log(p)
    nb = int(block[-1]) + 1
    vb = np.bincount(block, weights=w * v, minlength=nb) / np.bincount(block, w, minlength=nb)
    yb = fit[np.searchsorted(block, np.arange(nb))]
    return vb, yb


def _join_pressures(p_lo, p_hi, E_star):
    """Persson nodes below ``p_lo`` and above ``p_hi`` [Pa] (at least 1/JOIN_PER_DECADE
    decade from the ends)."""
    step = 1.0 / JOIN_PER_DECADE
    lo = 10.0 ** (math.log10(p_lo) - np.arange(JOIN_DECADES * JOIN_PER_DECADE, 0, -1) * step)
    top = max(10.0 * E_star, 10.0 * p_hi)
    n_hi = int(math.ceil(math.log10(top / p_hi) / step))
    hi = p_hi * 10.0 ** (np.arange(1, n_hi + 1) * step)
    return lo, hi


def _strictly_decreasing_prefix(y, floor):
    """How many leading entries of ``y`` decrease strictly and stay above ``floor``."""
    ok = (y > floor) & np.isfinite(y)
    ok[1:] &= np.diff(y) < 0.0
    return int(np.argmin(ok)) if not ok.all() else y.size


def _spectrum_record(psd: PSD) -> tuple[np.ndarray, np.ndarray]:
    """(q, C(q)) at the spectrum's breakpoints and ``SPECTRUM_SAMPLES`` log-spaced points."""
    q = np.geomspace(psd.q0, psd.q1, SPECTRUM_SAMPLES)
    bp = np.asarray(psd.breakpoints(), dtype=np.float64)
    q = np.unique(np.concatenate([q, bp[(bp >= psd.q0) & (bp <= psd.q1)]]))
    return q, np.asarray(psd(q), dtype=np.float64)


@dataclass
class _GapLaw:
    """The hydraulic gap of one flow direction: ln g at nodes of ln p (piecewise linear in
    log-log, linear extension beyond the ends) and the ln p above which the law is sealed."""

    V: np.ndarray
    G: np.ndarray
    seal: float = math.inf

    def log_gap(self, v: np.ndarray) -> np.ndarray:
        V, G = self.V, self.G
        out = np.interp(v, V, G)
        lo, hi = v < V[0], v > V[-1]
        out[lo] = G[0] + (v[lo] - V[0]) * (G[1] - G[0]) / (V[1] - V[0])
        out[hi] = G[-1] + (v[hi] - V[-1]) * (G[-1] - G[-2]) / (V[-1] - V[-2])
        return out


def _gap_law(p, g, err, theory, threshold, direction) -> _GapLaw:
    """The hydraulic-gap law of one direction: the BEM points where they percolate, Persson's
    critical gap scaled to meet them outside (module docstring)."""
    open_ = g > 0.0
    seal = math.inf
    if not open_.all():
        first = int(np.argmin(open_))
        seal = math.log(p[first])
        open_[first:] = False
    if np.count_nonzero(open_) < 2:
        warnings.warn(
            f"fastline.calibrate: fewer than 2 calibration pressures percolate for flow along "
            f"{direction}; the hydraulic gap there is Persson's critical gap, uncalibrated",
            CalibrationWarning,
            stacklevel=4,
        )
        pc = np.geomspace(p[0] * 1e-6, p[-1] * 1e2, 65)
        gc = theory.critical_gap(pc, threshold)
        k = _strictly_decreasing_prefix(gc.u_c, 0.0)
        return _GapLaw(np.log(pc[:k]), np.log(gc.u_c[:k]), min(seal, math.log(pc[k - 1])))
    ps, gs, es = p[open_], g[open_], err[open_]
    _check_monotone(ps, gs, es, f"hydraulic gap along {direction}")
    vb, gb = _pooled_nodes(ps, gs, es)
    lo, hi = _join_pressures(math.exp(vb[0]), math.exp(vb[-1]), theory.E_star)
    ends = theory.critical_gap(np.exp(vb[[0, -1]]), threshold).u_c
    c_lo = theory.critical_gap(lo, threshold).u_c * gb[0] / ends[0]
    V, G = [np.log(lo), vb], [np.log(c_lo), np.log(gb)]
    if math.isinf(seal) and ends[1] > 0.0:
        c_hi = theory.critical_gap(hi, threshold).u_c * gb[-1] / ends[1]
        k = _strictly_decreasing_prefix(c_hi, JOIN_FLOOR * gb[-1])
        V.append(np.log(hi[:k]))
        G.append(np.log(c_hi[:k]))
        if k < hi.size:
            seal = math.log(hi[k])
    elif math.isinf(seal):
        seal = math.log(hi[0])
    return _GapLaw(np.concatenate(V), np.concatenate(G), seal)


class CalibratedLaw(TabulatedLaw):
    """A pressure law u(p) and hydraulic gap g(p) calibrated on boundary-element ensembles
    (module docstring: the fit, the join to Persson's law, the file format).

    Made by :func:`fastline.calibrate`; or from points of your own (e.g. another code's BEM).

    Parameters
    ----------
    points : CalibrationPoints
        The ensemble means (at least 3 pressures).
    psd : PSD
        The spectrum the points belong to.
    E_star : float
        Effective modulus [Pa], in [1, 1e13].
    settings : dict, optional
        How the points were computed (grid, realisations, tolerances, ...): plain JSON values,
        saved with the law.
    threshold : float
        Percolation threshold of Persson's critical gap in the joins (default 0.42).

    Attributes
    ----------
    points : CalibrationPoints
    psd : PSD
    E_star : float
    settings : dict
    p_range : tuple of float
        The simulated range ``(p_lo, p_hi)`` [Pa]; outside it the law is Persson's, scaled.
    version : str
        The fastline version that made the law.
    """

    name = "calibrated"

    def __init__(
        self,
        points: CalibrationPoints,
        psd: PSD,
        E_star: float,
        *,
        settings: dict | None = None,
        threshold: float = 0.42,
    ) -> None:
        if not isinstance(points, CalibrationPoints):
            raise TypeError(f"points must be CalibrationPoints, got {type(points).__name__}")
        if not isinstance(psd, PSD):
            raise TypeError(f"psd must be a fastline PSD, got {type(psd).__name__}")
        E_star = in_span("E_star", E_star, E_STAR_RANGE, "Pa")
        theory = PerssonTheory(psd, E_star)
        pt = points
        _check_monotone(pt.p, pt.u, pt.u_error, "mean gap u(p)")
        vb, ub = _pooled_nodes(pt.p, pt.u, pt.u_error)
        V, U = _joined_nodes(theory, vb, ub)
        area = _joined_area(theory, pt, V, vb)
        TabulatedLaw.__init__(self, U, np.exp(V), real_area=area)
        gaps = {
            "x": _gap_law(pt.p, pt.gap_x, pt.gap_x_error, theory, threshold, "x"),
            "y": _gap_law(pt.p, pt.gap_y, pt.gap_y_error, theory, threshold, "y"),
            "mean": _gap_law(pt.p, pt.gap, _mean_gap_error(pt), theory, threshold, "x and y"),
        }
        meta = {"E_star": E_star, "threshold": float(threshold), "version": __version__}
        self._setup(pt, psd, theory, dict(settings or {}), meta, gaps)
        self._p_range = (float(math.exp(vb[0])), float(math.exp(vb[-1])))

    def _setup(self, points, psd, theory, settings, meta, gaps) -> None:
        self.points, self.psd, self._theory = points, psd, theory
        self.E_star = float(meta["E_star"])
        self.threshold = float(meta["threshold"])
        self.version = str(meta["version"])
        self.settings = json.loads(json.dumps(settings))  # plain JSON values only
        self._gaps = gaps

    def __repr__(self):
        lo, hi = self.p_range
        return (
            f"CalibratedLaw(<{self.points.p.size} pressures from {lo:.3g} to {hi:.3g} Pa, "
            f"E*={self.E_star:.4g} Pa>)"
        )

    @property
    def p_range(self) -> tuple[float, float]:
        """The simulated range of nominal pressure [Pa] (the law is Persson's, scaled, outside)."""
        return self._p_range

    @property
    def theory(self) -> PerssonTheory:
        """The Persson theory of the spectrum (the joins, and the leak rate's checks)."""
        if self._theory is None:
            self._theory = PerssonTheory(self.psd, self.E_star)
        return self._theory

    def log_hydraulic_gap(
        self, p: ArrayLike, direction: str = "mean"
    ) -> tuple[np.ndarray, np.ndarray]:
        """``(ln g, sealed)`` at nominal pressures p [Pa]: the calibrated Reynolds effective gap
        (g in m; +inf where p = 0, and ``sealed`` True where no channel percolates).

        Parameters
        ----------
        p : array_like
            Nominal pressure [Pa], >= 0.
        direction : {"mean", "x", "y"}
            Flow along x, along y, or the conductance averaged over both (an isotropic
            interface: the default).
        """
        if direction not in self._gaps:
            raise ValueError(f"direction must be one of {tuple(self._gaps)}, got {direction!r}")
        p = finite_array("p", p)
        if np.any(p < 0.0):
            raise ValueError("p must be >= 0 Pa everywhere (allowed range [0, inf))")
        law = self._gaps[direction]
        with np.errstate(divide="ignore"):
            v = np.log(p)
        out = np.full(p.shape, math.inf)
        live = p > 0.0
        out[live] = law.log_gap(v[live])
        sealed = v >= law.seal
        out[sealed] = -math.inf
        return out, sealed

    def hydraulic_gap(self, p: ArrayLike, direction: str = "mean") -> np.ndarray:
        """The calibrated Reynolds effective gap g(p) [m] (0 where sealed; see
        :meth:`log_hydraulic_gap`)."""
        log_g, _ = self.log_hydraulic_gap(p, direction)
        return np.exp(log_g)

    def save(self, path: str | os.PathLike) -> None:
        """Write the law to ``path`` (a ``.npz`` archive of plain arrays and JSON metadata with
        a checksum; module docstring, "File format")."""
        arrays, meta = _state_arrays(self), _state_meta(self)
        meta["checksum"] = _checksum(arrays, meta)
        with open(os.fspath(path), "wb") as f:
            np.savez_compressed(f, metadata=np.array(json.dumps(meta)), **arrays)

    @classmethod
    def load(
        cls, path: str | os.PathLike, *, psd: PSD | None = None, E_star: float | None = None
    ) -> CalibratedLaw:
        """Read a law written by :meth:`save`.

        Parameters
        ----------
        path : str or path-like
        psd : PSD, optional
            The spectrum of the scenes to be solved: refused if the file was made for another
            (C(q) differs by more than 1e-6 relative at the recorded wavenumbers). Default:
            the recorded spectrum (interpolated log-log between its samples).
        E_star : float, optional
            The modulus of the scenes [Pa]: refused if it differs from the file's.

        Raises
        ------
        CalibrationFileError
            The file is not a calibrated-law archive, is of another format version, fails its
            checksum, or was made for another spectrum or modulus.
        """
        arrays, meta = _read(os.fspath(path))
        return _restore(cls, arrays, meta, psd, E_star, os.fspath(path))


def _join_power(theory, vb, ub, end: int) -> float:
    """The exponent m of the join at one end (``end`` 0: low, -1: high): the fit's secant in
    ln u against ln p over its end cell over Persson's over the same cell (1 with one node)."""
    if vb.size < 2:
        return 1.0
    k = [0, 1] if end == 0 else [-2, -1]
    u_p = theory.separation(np.exp(vb[k]))
    m = math.log(ub[k[1]] / ub[k[0]]) / math.log(u_p[1] / u_p[0])
    return m if math.isfinite(m) and m > 0.0 else 1.0


def _joined_nodes(theory, vb, ub) -> tuple[np.ndarray, np.ndarray]:
    """(ln p, u) nodes of the law: Persson's u_P below and above the pooled nodes ``(vb, ub)``,
    ``u = u_end (u_P / u_P(p_end))^m`` with m matching the fit's end cell (module docstring)."""
    lo, hi = _join_pressures(math.exp(vb[0]), math.exp(vb[-1]), theory.E_star)
    u_p = theory.separation(np.concatenate([lo, np.exp(vb[[0, -1]]), hi]))
    u_lo, u_end, u_hi = u_p[: lo.size], u_p[lo.size : lo.size + 2], u_p[lo.size + 2 :]
    u_lo = ub[0] * (u_lo / u_end[0]) ** _join_power(theory, vb, ub, 0)
    with np.errstate(divide="ignore", under="ignore"):
        u_hi = ub[-1] * (np.maximum(u_hi, 0.0) / u_end[1]) ** _join_power(theory, vb, ub, -1)
    k = _strictly_decreasing_prefix(np.concatenate([[ub[-1]], u_hi]), JOIN_FLOOR * ub[-1])
    V = np.concatenate([np.log(lo), vb, np.log(hi[: k - 1])])
    return V, np.concatenate([u_lo, ub, u_hi[: k - 1]])


def _mean_gap_error(pt: CalibrationPoints) -> np.ndarray:
    """Standard error of ``CalibrationPoints.gap`` from the two directions' errors."""
    g = pt.gap
    with np.errstate(divide="ignore", invalid="ignore"):
        e3 = 0.5 * np.hypot(3 * pt.gap_x**2 * pt.gap_x_error, 3 * pt.gap_y**2 * pt.gap_y_error)
        return np.where(g > 0.0, e3 / (3.0 * g**2), np.nan)


def _joined_area(theory, pt, V, vb) -> np.ndarray:
    """Contact fraction at the nodes: the points inside the range (interpolated onto the
    pooled nodes), Persson's area scaled to meet them outside, within [0, 1]."""
    v = np.log(pt.p)
    inside = np.interp(vb, v, pt.contact_fraction)
    a_p = theory.contact_area(np.exp(V))
    ends = theory.contact_area(np.exp(vb[[0, -1]]))
    scale = np.where(ends > 0.0, np.array([inside[0], inside[-1]]) / np.maximum(ends, 1e-300), 1)
    out = np.where(V < vb[0], a_p * scale[0], a_p * scale[1])
    n_lo = int(np.searchsorted(V, vb[0]))
    out[n_lo : n_lo + vb.size] = inside
    return np.clip(out, 0.0, 1.0)


# ---- the file ----------------------------------------------------------------------------------
def _state_arrays(law: CalibratedLaw) -> dict[str, np.ndarray]:
    """Every array of a law's state, by name (float64)."""
    q, C = _spectrum_record(law.psd)
    out = {"V": law._V, "U": law._U, "area": law._area, "spectrum_q": q, "spectrum_C": C}
    for name in _POINT_FIELDS:
        out[f"point_{name}"] = getattr(law.points, name)
    for k, g in law._gaps.items():
        out[f"gap_{k}_V"], out[f"gap_{k}_G"] = g.V, g.G
    return {k: np.ascontiguousarray(v, dtype=np.float64) for k, v in out.items()}


def _state_meta(law: CalibratedLaw) -> dict:
    """A law's metadata as its file holds it (without the checksum)."""
    return {
        "format": FORMAT,
        "version": law.version,
        "E_star": law.E_star,
        "threshold": law.threshold,
        "p_range": list(law.p_range),
        "seal": {k: g.seal for k, g in law._gaps.items()},
        "settings": law.settings,
    }


def _checksum(arrays: dict, meta: dict) -> str:
    h = hashlib.sha256()
    for name in sorted(arrays):
        a = arrays[name]
        h.update(f"{name}:{a.dtype.str}:{a.shape}".encode())
        h.update(a.tobytes())
    body = {k: v for k, v in meta.items() if k != "checksum"}
    h.update(json.dumps(body, sort_keys=True).encode())
    return h.hexdigest()


def _read(path: str) -> tuple[dict, dict]:
    """The arrays and metadata of a law file, checked (format and checksum)."""
    bad = f"{path} is not a fastline calibrated-law file ({FORMAT})"
    if os.path.isfile(path) and not zipfile.is_zipfile(path):
        raise CalibrationFileError(
            f"{bad}: not a .npz archive (`fastline calibrate --out FILE` writes one)"
        )
    try:
        with np.load(path, allow_pickle=False) as f:
            arrays = {k: f[k] for k in f.files}
        meta = json.loads(str(arrays.pop("metadata")[()]))
        arrays = {k: np.asarray(v, dtype=np.float64) for k, v in arrays.items()}
    except FileNotFoundError:
        raise
    except (OSError, ValueError, KeyError, EOFError, zipfile.BadZipFile, TypeError) as e:
        why = str(e)
        if "pickle" in why:  # NumPy's own text would invite an unsafe load
            why = "it holds Python objects, which a law file never does (not loaded)"
        raise CalibrationFileError(f"{bad}: {why}") from None
    if not isinstance(meta, dict) or meta.get("format") != FORMAT:
        got = meta.get("format") if isinstance(meta, dict) else None
        raise CalibrationFileError(f"{bad}: its format is {got!r}; remake it with this version")
    want = meta.get("checksum")
    if want != _checksum(arrays, meta):
        raise CalibrationFileError(f"{path} is corrupt: its checksum does not match its content")
    return arrays, meta


def _check_match(arrays, meta, psd, E_star, path) -> PSD:
    """The spectrum of the law (the user's, checked against the record, or the record's)."""
    if E_star is not None:
        E_star = in_span("E_star", E_star, E_STAR_RANGE, "Pa")
        if not math.isclose(E_star, meta["E_star"], rel_tol=MATCH_RTOL):
            raise CalibrationFileError(
                f"{path} was calibrated for E* = {meta['E_star']:.6g} Pa, not {E_star:.6g} Pa: "
                "calibrate again for this modulus"
            )
    q, C = arrays["spectrum_q"], arrays["spectrum_C"]
    if psd is None:
        return TabulatedPSD(q, C)
    if not isinstance(psd, PSD):
        raise TypeError(f"psd must be a fastline PSD or None, got {type(psd).__name__}")
    mine = np.asarray(psd(q), dtype=np.float64)
    if not np.allclose(mine, C, rtol=MATCH_RTOL, atol=0.0):
        k = int(np.argmax(np.abs(mine - C) - MATCH_RTOL * np.abs(C)))
        raise CalibrationFileError(
            f"{path} was calibrated for another spectrum: C(q = {q[k]:.6g} 1/m) is "
            f"{C[k]:.6g} m^4 there and {mine[k]:.6g} m^4 in the psd given; calibrate again "
            "for this spectrum"
        )
    return psd


def _restore(cls, arrays, meta, psd, E_star, path) -> CalibratedLaw:
    try:
        psd = _check_match(arrays, meta, psd, E_star, path)
        law = cls.__new__(cls)
        law._V, law._U, law._area = arrays["V"], arrays["U"], arrays["area"]
        law._S = np.ascontiguousarray(_monotone_slopes(law._V, law._U))
        law.u0 = float(-law._S[0])
        points = CalibrationPoints(**{n: arrays[f"point_{n}"] for n in _POINT_FIELDS})
        gaps = {
            k: _GapLaw(arrays[f"gap_{k}_V"], arrays[f"gap_{k}_G"], float(s))
            for k, s in meta["seal"].items()
        }
        law._setup(points, psd, None, meta["settings"], meta, gaps)
        law._p_range = (float(meta["p_range"][0]), float(meta["p_range"][1]))
    except KeyError as e:
        raise CalibrationFileError(
            f"{path} lacks {e} (not a complete calibrated-law file)"
        ) from None
    return law
