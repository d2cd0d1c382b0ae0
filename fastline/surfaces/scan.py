"""From a measurement file to the spectrum a contact solve uses, in one call.

:func:`analyse_scan` is the pipeline behind ``fastline psd`` and ``--scan``: read a line scan,
parallel line scans or a height map (:func:`fastline.surfaces.topography.read_topography`),
take its spectrum over the usable range
(:func:`~fastline.surfaces.topography.psd_from_profile` and the exact inverse Abel transform
:func:`~fastline.surfaces.topography.isotropic_from_1d`, or
:func:`~fastline.surfaces.topography.psd_from_map`), fit the self-affine model
(:func:`~fastline.surfaces.topography.fit_self_affine`: to C1D for line scans, to C(q) for
maps) and, on request, cut the table at q1 or continue it to q1 by the fitted power law
(:func:`~fastline.surfaces.topography.extend_psd`; the fitted model ``fit.psd`` spans the same
range). Every number is the one those functions return; this module only chains them and
records what was done.

Conventions and SI units as :mod:`fastline.surfaces.topography`: heights and spacings in m,
wavenumbers in 1/m, C1D in m^3, C(q) in m^4 with ``h_rms^2 = 2 pi int q C dq``. The analysis
warns (:class:`~fastline.errors.TopographyWarning`) when h_rms or the slopes suggest a unit slip
and when noise in C1D makes the inverse transform smooth it (its falling envelope).
"""

from __future__ import annotations

import math
import os
import warnings
from dataclasses import dataclass
from typing import Literal, NamedTuple

import numpy as np

from fastline._lib.validate import positive
from fastline.surfaces import topography as tp
from fastline.surfaces.files import file_path, unit_advice
from fastline.surfaces.heights import heights_refused
from fastline.surfaces.maps import map_spectrum
from fastline.surfaces.profiles import spectrum_and_periodogram
from fastline.surfaces.ranges import range_rules
from fastline.surfaces.read import read_spectrum
from fastline.theory.spectra import TabulatedPSD

__all__ = ["ScanSpectrum", "analyse_scan", "LIMIT_RULES"]

#: what each end of the usable range was set by (``ScanSpectrum.limits``), in words
LIMIT_RULES = {
    "scan length": f"scan length (Fourier mode {tp.LOW_MODE}: {tp.LOW_MODE} x 2 pi / L)",
    "sampling": f"sampling ({tp.POINTS_PER_WAVELENGTH} points per wavelength: "
    f"2 pi / ({tp.POINTS_PER_WAVELENGTH} dx))",
    "tip radius": f"stylus tip (it cannot follow curvatures beyond {tp.TIP_SAFETY:g} / R_tip)",
    "noise floor": f"noise floor (C below {tp.NOISE_MARGIN:g} x the white-noise level)",
    "noise floor found": "noise floor found in the data (a white plateau; the fitted power law "
    f"falls below {tp.NOISE_MARGIN:g} x it)",
    "tip radius or noise floor": "stylus tip or noise floor",
    "given": "given",
    "all": "all measured wavenumbers",
}
#: a two-column file is taken for a spectrum (q, C) rather than a profile (x, h) when its first
#: column spans at least this ratio and its second column falls over this many decades
_SPECTRUM_SPAN, _SPECTRUM_DECADES = 10.0, 3.0
#: ... and only when it has at most this many rows (a spectrum table is short; a scan of more
#: points is not read a second time to check)
_SPECTRUM_ROWS = 100_000


@dataclass(frozen=True)
class ScanSpectrum:
    """A measured surface's spectrum: what was read, the range used and why, the fit, the table.

    Attributes
    ----------
    path : str
        The file read.
    kind : {"profile", "profiles", "map"}
        One line scan, parallel line scans (the rows of a 2D file, averaged), or a height map.
    shape : tuple of int
        Shape of the heights read (profiles: ``(P, N)`` or ``(N,)``; maps ``(Ny, Nx)``).
    dx, dy : float
        Spacings in m (dy of a map only, else None).
    spectrum : ProfileSpectrum or None
        The 1D spectrum over the usable range (profiles); it holds the data's h_rms and slope.
    raw : tuple of ndarray
        For figures: ``(k, C1D)`` at every Fourier mode (profiles) or ``(q, C)`` ring averages
        over all full rings (maps), before the range was cut.
    measured : TabulatedPSD
        The isotropic C(q) over the usable range.
    q_range : tuple of float
        The usable range in 1/m; ``limits`` the rule that set each end (keys of LIMIT_RULES).
    fit : SelfAffineFit
        The self-affine model fitted over the usable range: to the 1D spectrum ``spectrum``
        (line scans) or to ``measured`` (maps). ``fit.psd`` spans the same range as ``psd``:
        the usable range, cut at q1, or continued to q1 (with ``extend``) by the model itself.
    psd : TabulatedPSD
        The table to use: ``measured``, cut at q1, or continued to q1 above ``extended_from``.
    extended_from : float or None
        The wavenumber (1/m) above which ``psd`` is the fitted power law, not the measurement.
    window, detrend : str
        As used.
    """

    path: str
    kind: str
    shape: tuple
    dx: float
    dy: float | None
    spectrum: tp.ProfileSpectrum | None
    raw: tuple
    measured: TabulatedPSD
    q_range: tuple
    limits: dict
    fit: tp.SelfAffineFit
    psd: TabulatedPSD
    extended_from: float | None
    window: str
    detrend: str

    @property
    def n_profiles(self) -> int:
        """Profiles averaged (1 for a map)."""
        return self.spectrum.n_profiles if self.spectrum is not None else 1

    def describe(self) -> str:
        """The whole analysis, as ``fastline psd`` and ``--scan`` print it: the same text as
        :meth:`summary` with its C(q) table line (:meth:`one_line`: what was read, in one line)."""
        return self.summary(table=True)

    def one_line(self) -> str:
        """One line: what was read and how it was analysed (the first line of :meth:`summary`,
        without the path)."""
        if self.kind == "map":
            ny, nx = self.shape
            what = (
                f"height map {ny} x {nx} points, dx {self.dx:.4g} m, dy {self.dy:.4g} m "
                f"({nx * self.dx:.4g} m x {ny * self.dy:.4g} m); ring-averaged 2D spectrum"
            )
        else:
            n = self.shape[-1]
            many = "one profile" if self.n_profiles == 1 else f"{self.n_profiles} parallel profiles"
            what = (
                f"{many} of {n} points, dx {self.dx:.4g} m (L = {n * self.dx:.4g} m); "
                "1D spectrum, exact inverse Abel transform to C(q)"
            )
        return f"{what}; {self.window} window, {self.detrend} detrend"

    def cut(self) -> str | None:
        """What the usable range left out at its top and why, in words (None: nothing)."""
        if self.spectrum is None:
            return None
        top, hi = math.pi / self.dx, self.q_range[1]
        if hi >= top * (1.0 - 1e-9):
            return None
        s = self.spectrum
        text = (
            f"{hi:.4g}-{top:.4g} 1/m, the {math.log10(top / hi):.2g} decades up to the Nyquist "
            "wavenumber pi / dx (the high end's rule)"
        )
        if s.noise_floor > 0.0:
            sigma = math.sqrt(s.noise_floor * 2.0 * math.pi / self.dx)
            text += (
                f"; white-noise level C1D {s.noise_floor:.3g} m^3 (rms noise {sigma:.3g} m, "
                f"{sigma / s.h_rms:.2%} of h_rms), taken off C1D by the fit"
            )
        return text

    def summary(self, table: bool = True) -> str:
        """The full summary ``fastline psd`` prints: what was read, the data, the usable range
        and the rule of each end, what was cut above it, the fit, the table (``table``)."""
        return "\n".join(summary_lines(self, table))

    def __str__(self) -> str:
        return self.summary()

    def metadata(self) -> dict:
        """``key: value`` entries for a file header: the source, range, rules, fit, extension."""
        f = self.fit
        meta = {
            "scan": self.path,
            "analysis": self.one_line(),
        }
        if self.spectrum is not None:
            meta["h_rms_data_m"] = self.spectrum.h_rms
            meta["rms_slope_data"] = self.spectrum.rms_slope
            if self.spectrum.noise_floor > 0.0:
                meta["noise_floor_C1D_m3"] = self.spectrum.noise_floor
        meta.update(
            q_range_low_1_per_m=self.q_range[0],
            q_range_high_1_per_m=self.q_range[1],
            q_range_low_rule=self.limits["low"],
            q_range_high_rule=self.limits["high"],
            fit_h_rms_m=f.h_rms,
            fit_h_rms_err_m=f.h_rms_err,
            fit_hurst=f.hurst,
            fit_hurst_err=f.hurst_err,
            fit_qr_1_per_m=f.qr,
            fit_qr_err_1_per_m=f.qr_err,
            fit_qr_low_1_per_m=f.qr_interval[0],
            fit_qr_high_1_per_m=f.qr_interval[1],
            fit_rms_residual=f.rms_residual,
        )
        if self.extended_from is not None:
            meta["extended_above_1_per_m"] = self.extended_from
            meta["extension"] = f"power law C ~ q^-2(1+H), H = {f.hurst:.6g} (the fit)"
        return meta


def _fit_line(f: tp.SelfAffineFit) -> str:
    """The fit in one line: H, q_r and h_rms with their errors, or why one is not measured."""
    hurst = f"H {f.hurst:.3f} ± {f.hurst_err:.2g}"
    if f.hurst_at_bound:  # held there: no error bar
        steeper = "faster" if f.hurst >= 1.0 else "slower"
        hurst = f"H {f.hurst:g} (held at its bound: C falls {steeper} than self-affine can)"
    lo, hi = f.qr_interval
    qr = f"q_r {f.qr:.4g} ± {f.qr_err:.2g} 1/m ({lo:.3g}-{hi:.3g} at two standard errors"
    qr += ": uncertain)" if f.qr_uncertain else ")"
    if f.qr_at_bound:
        qr = f"q_r {f.qr:.4g} 1/m not resolved (the roll-off may lie anywhere below {hi:.3g})"
    return (
        f"fit              {hurst}, {qr}, h_rms {f.h_rms:.4g} ± {f.h_rms_err:.2g} m "
        f"(self-affine with roll-off fitted to {f.fitted_to} over {f.q_range[0]:.4g}-"
        f"{f.q_range[1]:.4g} 1/m; scatter of ln {f.fitted_to.split('(')[0]} "
        f"{f.rms_residual:.2g} rms, {f.n_points} points)"
    )


def summary_lines(scan: ScanSpectrum, table: bool) -> list[str]:
    """The lines of :meth:`ScanSpectrum.summary`."""
    lines = [f"scan             {scan.path}: {scan.one_line()}"]
    if scan.spectrum is not None:
        s = scan.spectrum
        lines.append(
            f"data             h_rms {s.h_rms:.4g} m, rms slope {s.rms_slope:.4g} (detrended "
            "heights; slope from differences at dx)"
        )
    lo, hi = scan.q_range
    lines.append(
        f"q range used     {lo:.4g}-{hi:.4g} 1/m; low end: {LIMIT_RULES[scan.limits['low']]}; "
        f"high end: {LIMIT_RULES[scan.limits['high']]}"
    )
    cut = scan.cut()
    if cut is not None:
        lines.append(f"left out         {cut}")
    lines.append(_fit_line(scan.fit))
    if table:
        t = scan.psd
        lines.append(
            f"C(q) table       {t.q.size} points, q {t.q0:.4g}-{t.q1:.4g} 1/m: h_rms "
            f"{t.h_rms:.4g} m, rms slope {t.rms_slope:.4g}"
        )
    if scan.extended_from is not None:
        lines.append(
            f"continued        above {scan.extended_from:.4g} 1/m to q1 = {scan.psd.q1:.4g} 1/m "
            f"as C ~ q^-{2.0 * (1.0 + scan.fit.hurst):.3g} (the fitted H): an assumption, not a "
            "measurement"
        )
    return lines


# ----------------------------------------------------------------------------------------------
# stages
# ----------------------------------------------------------------------------------------------
def _looks_like_spectrum(path: str) -> bool:
    """Whether a file reads as a spectrum table (q > 0 increasing over a decade or more, C > 0
    falling over decades): the mistake of passing a spectrum where a scan belongs."""
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            table = read_spectrum(path)
    except (ValueError, OSError):
        return False
    q, C = table.q, table.C
    live = C > 0.0
    if q[-1] / q[0] < _SPECTRUM_SPAN or live.sum() < 3:
        return False
    logC = np.log10(C[live])
    return bool(logC[0] - logC[-1] >= _SPECTRUM_DECADES)


def _refuse_spectrum(path: str) -> None:
    if _looks_like_spectrum(path):
        raise ValueError(
            f"{path}: this looks like a spectrum (q [1/m], C [m^4]), not a height profile: "
            "pass it as a spectrum (--psd, fastline.io.read_spectrum), not as a scan"
        )


class _Scan(NamedTuple):
    """What a file holds: its kind (a key of ScanSpectrum.kind), heights (m), dx and dy (m; dy
    of a map only, else None)."""

    kind: str
    h: np.ndarray
    dx: float
    dy: float | None


def _read(path: str, dx, dy, as_map: bool, unit: str, x_unit) -> _Scan:
    """The scan a file holds; refuses a spectrum table passed as a scan."""
    if os.path.isdir(path):
        raise ValueError(f"{path} is a directory, not a file")
    try:
        return _Scan(*_read_file(path, dx, dy, as_map, unit, x_unit))
    except ValueError as e:
        if dx is None and ("needs dx" in str(e) or "dx (m) is required" in str(e)):
            what = "a height map" if as_map else "heights only (no x column)"
            raise ValueError(f"{path} holds {what}: their spacing dx (m) is required") from None
        raise


def _read_file(path: str, dx, dy, as_map: bool, unit: str, x_unit):
    if as_map:
        m = tp.read_map(path, dx=dx, dy=dy, unit=unit)
        return "map", m.heights, m.dx, m.dy
    if dy is not None:
        raise ValueError("dy is the row spacing of a map: it needs as_map=True (--map)")
    try:
        data = tp.read_topography(path, dx=dx, unit=unit, x_unit=x_unit)
    except ValueError as e:
        if "not uniformly spaced" in str(e):
            _refuse_spectrum(path)
        raise
    if isinstance(data, tp.Map):
        h = data.heights
        return ("profile" if h.shape[0] == 1 else "profiles"), h, data.dx, None
    h = data.heights
    if h.size <= _SPECTRUM_ROWS and np.all(h > 0.0):  # a (q, C) table on a uniform q grid
        _refuse_spectrum(path)
    return "profile", h, data.dx, None


class _Spectra(NamedTuple):
    """A scan's spectra: the ProfileSpectrum (line scans) or None (a map), the raw spectrum for
    figures, C(q) over the usable range (m^4), the range (1/m) and the rule of each end."""

    spectrum: tp.ProfileSpectrum | None
    raw: tuple
    measured: TabulatedPSD
    q_range: tuple
    limits: dict


def _profile_stage(h, dx, options) -> _Spectra:
    """The ProfileSpectrum over the usable range, the raw periodogram, C(q) over the range."""
    rules = {key: options[key] for key in ("q_range", "tip_radius", "noise")}
    rest = {key: options[key] for key in ("window", "detrend", "nan", "bins_per_decade")}
    spectrum, raw = spectrum_and_periodogram(h, dx, **rules, **rest)
    measured = spectrum.isotropic()
    return _Spectra(spectrum, raw, measured, spectrum.q_range, dict(spectrum.limits))


def _map_limits(psd: TabulatedPSD, dx, dy, q_range, tip, noise) -> dict:
    """Which rule set each end of a map's usable range (:func:`psd_from_map` applies them; the
    ends it returns are matched to the rule values)."""
    if q_range is None:
        return {"low": "all", "high": "all"}
    lo, hi = (None, None) if isinstance(q_range, str) else q_range
    sampling = 2.0 * math.pi / (tp.POINTS_PER_WAVELENGTH * max(dx, dy))
    if hi is not None:
        high = "given"
    elif math.isclose(psd.q1, sampling, rel_tol=1e-9) or (tip is None and noise is None):
        high = "sampling"
    elif tip is not None and noise is not None:
        high = "tip radius or noise floor"
    else:
        high = "tip radius" if tip is not None else "noise floor"
    return {"low": "given" if lo is not None else "scan length", "high": high}


def _map_stage(h, dx, dy, options) -> _Spectra:
    """The ring averages over all full rings, C(q) over the usable range, the range's rules."""
    rules = range_rules(options["q_range"], options["tip_radius"], options["noise"])
    rest = (options[key] for key in ("window", "detrend", "nan", "bins_per_decade"))
    measured, raw = map_spectrum(h, dx, dy, *rest, rules, raw=True)
    limits = _map_limits(
        measured, dx, dy, options["q_range"], options["tip_radius"], options["noise"]
    )
    q_rng = (float(measured.q0), float(measured.q1))
    return _Spectra(None, (raw.q, raw.C), measured, q_rng, limits)


def _check_q1(measured: TabulatedPSD, q1, extend: bool) -> None:
    """q1 above the usable range needs extend (before the fit)."""
    top = float(measured.q1)
    if q1 is not None and q1 > top and not extend:
        raise ValueError(
            f"q1 = {q1:.4g} 1/m lies above the usable range, which ends at {top:.4g} 1/m: "
            "continuing the spectrum there is an assumption, not a measurement; ask for it "
            "with extend=True (--extend on the command line), which continues the power law "
            "of the fitted H"
        )


def _fit(spectrum, measured: TabulatedPSD, q1) -> tp.SelfAffineFit:
    """The self-affine model fitted to C1D (line scans: :func:`fit_self_affine` of the
    ProfileSpectrum, not of the noisier inverse transform) or to C(q) (maps), spanning the
    table's range: from the usable range's low end to q1 when given."""
    return tp.fit_self_affine(measured if spectrum is None else spectrum, q0=measured.q0, q1=q1)


def _table(measured: TabulatedPSD, fit, q1, extend: bool):
    """(the table to use, the wavenumber above which it is extrapolated or None)."""
    if q1 is None:
        return measured, None
    _check_q1(measured, q1, extend)
    top = float(measured.q1)
    if q1 <= top:
        return tp.extend_psd(measured, q1), None
    return tp.extend_psd(measured, q1, hurst=fit.hurst), top


def _spectra(path: str, scan: _Scan, options: dict, unit) -> _Spectra:
    """The spectra of a map (:func:`_map_stage`) or of line scans (:func:`_profile_stage`);
    heights of an implausible h_rms refused naming the unit they were read in (``unit``)."""
    with heights_refused(path, lambda: unit_advice(path, unit)):
        if scan.kind == "map":
            return _map_stage(scan.h, scan.dx, scan.dy, options)
        return _profile_stage(scan.h, scan.dx, options)


def _scan_spectrum(path: str, scan: _Scan, spectra: _Spectra, fit, table, options) -> ScanSpectrum:
    """The ScanSpectrum of a file's scan, its spectra, fit, ``table`` (the table to use and the
    wavenumber above which it is extrapolated, or None) and the spectrum ``options``."""
    psd, extended_from = table
    window = options["window"]
    return ScanSpectrum(
        path=path,
        kind=scan.kind,
        shape=tuple(scan.h.shape),
        dx=float(scan.dx),
        dy=None if scan.dy is None else float(scan.dy),
        spectrum=spectra.spectrum,
        raw=spectra.raw,
        measured=spectra.measured,
        q_range=spectra.q_range,
        limits=spectra.limits,
        fit=fit,
        psd=psd,
        extended_from=extended_from,
        window="none" if window is None else str(window),
        detrend=options["detrend"],
    )


def _checked_options(as_map: bool, detrend, q1, extend: bool):
    """The detrending (the default of a map or of line scans) and q1 (1/m), checked with
    extend before any work."""
    if extend and q1 is None:
        raise ValueError("extend=True needs q1, the wavenumber (1/m) to continue C(q) to")
    allowed = ("plane", "mean") if as_map else ("linear", "mean", "parabola", "circle")
    detrend = allowed[0] if detrend is None else detrend
    if detrend not in allowed:
        what = "a map" if as_map else "line scans"
        hint = " ('plane' is for a height map: as_map=True (--map))" if detrend == "plane" else ""
        raise ValueError(
            f"detrend for {what} must be one of {', '.join(allowed)}, got {detrend!r}{hint}"
        )
    return detrend, None if q1 is None else positive("q1", q1, "1/m")


def _spectrum_options(window, detrend, nan, bins_per_decade, q_range, tip_radius, noise) -> dict:
    """The keyword arguments of :func:`~fastline.surfaces.topography.psd_from_profile` (or
    ``psd_from_map``) that the analysis passes on."""
    return dict(
        window=window,
        detrend=detrend,
        nan=nan,
        bins_per_decade=bins_per_decade,
        q_range=q_range,
        tip_radius=tip_radius,
        noise=noise,
    )


def analyse_scan(
    path: str | os.PathLike,
    *,
    dx: float | None = None,
    dy: float | None = None,
    as_map: bool = False,
    unit: str | None = None,
    x_unit: str | None = None,
    window: str | None = "hann",
    detrend: Literal["linear", "plane", "mean", "parabola", "circle"] | None = None,
    nan: Literal["raise", "interpolate"] = "raise",
    bins_per_decade: int = 20,
    q_range: tp.QRange = "auto",
    tip_radius: float | None = None,
    noise: float | None = None,
    q1: float | None = None,
    extend: bool = False,
) -> ScanSpectrum:
    """The isotropic spectrum C(q) of a measured surface, its usable range, fit and table.

    Parameters
    ----------
    path : str or path-like
        A line scan (a column h with ``dx``, or columns x, h), parallel scans (rows of a 2D
        file), a height map or an instrument file (text, ``.npy``, or :func:`read_topography`).
    dx, dy : float, optional
        Spacing in m along the scans and between a map's rows (default: the file's own).
    as_map : bool
        A 2D file as a height map (ring-averaged 2D spectrum), not as parallel line scans.
    unit, x_unit : str, optional
        Units of heights and x of a text or ``.npy`` file (``"m"``, ``"mm"``, ``"um"``,
        ``"nm"``; default: the header's, as :func:`~fastline.surfaces.topography.read_profile`).
    window, nan, bins_per_decade, q_range, tip_radius, noise
        As :func:`fastline.surfaces.topography.psd_from_profile` (maps: ``psd_from_map``).
    detrend : str, optional
        Default ``"linear"`` (profiles; also ``"mean"``, ``"parabola"``, ``"circle"``) or
        ``"plane"`` (maps; also ``"mean"``).
    q1, extend : float, optional; bool
        Cut the table at q1 (1/m); above the usable range, with ``extend``, continue it by the
        fitted ``C ~ q^-2(1+H)`` (:func:`fastline.surfaces.topography.extend_psd`).

    Returns
    -------
    ScanSpectrum

    Raises
    ------
    ValueError
        Bad options (before any work), an unreadable or implausible file, an empty usable
        range, q1 above it without ``extend`` (FileNotFoundError: no such file).
    """
    path = file_path(path)
    detrend, q1 = _checked_options(as_map, detrend, q1, extend)
    options = _spectrum_options(window, detrend, nan, bins_per_decade, q_range, tip_radius, noise)
    scan = _read(path, dx, dy, as_map, unit, x_unit)
    spectra = _spectra(path, scan, options, unit)
    _check_q1(spectra.measured, q1, extend)
    fit = _fit(spectra.spectrum, spectra.measured, q1)
    table = _table(spectra.measured, fit, q1, extend)
    return _scan_spectrum(path, scan, spectra, fit, table, options)
