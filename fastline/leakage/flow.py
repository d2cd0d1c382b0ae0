"""Seal leakage from the nominal contact pressure: Persson's critical-junction theory.

The leak rate of a seal is the flow through the critical junctions of the interface
(:mod:`fastline.theory.interface`: the gap ``u_c`` of the junction at the percolation threshold
for each nominal pressure), strips of the contact in series along the leak path
(docs/leakage.md section 4; B.N.J. Persson, C. Yang, J. Phys.: Condens. Matter 20, 315011
(2008), doi:10.1088/0953-8984/20/31/315011; B. Lorenz, B.N.J. Persson, EPL 86, 44006 (2009),
doi:10.1209/0295-5075/86/44006).

Each strip of a pressure profile is a uniform-pressure seal of local conductance
``sigma = u_c(p)^3 / (12 eta)``, and the strips are in series across the contact:

    Q / L_y = dP / int dx (1 / sigma(x)),

which for a constant pressure over a width L_x is Persson's rectangle formula
``Q = (L_y / L_x) dP u_c^3 / (12 eta)``. Around a point contact the profile is axisymmetric,
p(r), and the fluid enters at ``r = inner_radius`` (the orifice of a seat) and flows outwards
through rings in series (each ring of width dr is a rectangle of length 2 pi r):

    Q = dP / int_{inner_radius} dr / (2 pi r sigma(r)).

A law calibrated on boundary-element ensembles (``law=``, :func:`fastline.calibrate`) puts
its Reynolds effective gap g(p) in place of u_c(p), strips in series as before
(docs/calibration.md). Otherwise u_c comes from a table of the critical gap built once per
theory and threshold (relative error below the theory's rtol;
:func:`fastline.theory.interface.gap_table`). A sealed strip (``P(q1, p) >= threshold``) on the
flow path seals the contact.
"""

from __future__ import annotations

import math
import warnings
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Literal

import numpy as np
from numpy.typing import ArrayLike

from fastline._lib.validate import boolean, finite_array, finite_scalar, positive
from fastline.errors import LeakageWarning
from fastline.leakage.medium import _MediumTable, medium_table
from fastline.theory.interface import (
    THRESHOLD_BRUGGEMAN,
    THRESHOLD_PERSSON,
    check_threshold,
    gap_table,
    interface_cache,
    sealing_argument,
)

if TYPE_CHECKING:  # annotations only
    from fastline.contact.line import LineContactResult
    from fastline.contact.point import PointContactResult
    from fastline.theory.calibrated import CalibratedLaw
    from fastline.theory.persson import PerssonTheory

__all__ = ["LeakResult", "LeakageWarning", "leak_rate", "leak_rate_profile"]

# ----------------------------------------------------------------------------------------------
# leak rate of a pressure profile: strips in series (docs/leakage.md §4)
# ----------------------------------------------------------------------------------------------
METHODS = ("critical-junction", "effective-medium")
#: warn when fewer roll-off wavelengths 2 pi/qr than this fit across the region holding 90 % of
#: the flow resistance (the theory averages over many junctions in series)
MIN_JUNCTIONS = 5.0
#: warn when the Knudsen number (mean free path / u_c at the strip of highest resistance)
#: exceeds this: the flow is no longer viscous (slip flow starts near 0.01-0.1)
MAX_KNUDSEN = 0.1
#: warn when the fluid pressure drop exceeds this fraction of the peak contact pressure
MAX_FLUID_PRESSURE_RATIO = 0.1
#: default molecular floor of the gap (m): a strip whose gap is below it is sealed (docs/leakage.md,
#: "A floor for sealing"): a few molecular diameters (water 0.28 nm), below which a continuum
#: Poiseuille flow is not defined
GAP_FLOOR = 1e-9
#: radial flow (point contacts): an orifice wider than this share of the pressure's half width at
#: half maximum changes the contact pressure, which is taken from the solid (unperforated) contact
MAX_ORIFICE_SHARE = 0.1


#: the warning of a leak rate computed from a solve that did not converge (one text for every
#: scene, so that a loop shows it once)
UNCONVERGED = (
    "fastline.leak_rate: the contact's solve did not converge (result.converged is False): "
    "the leak rate is that of an unconverged pressure profile (LeakResult.converged says so)"
)


@dataclass
class LeakResult:
    """The leak rate of a seal and where along the contact it is decided.

    Arrays are per strip (cell) of the pressure profile: strips across a line contact
    (``inner_radius`` None), or rings around a point contact's axis (radial flow from
    ``inner_radius`` outwards). Units: m, Pa, s.

    Attributes
    ----------
    Q : float
        Volume flow across the contact in m^3/s: along x for the seal length given,
        ``Q = conductance * length * pressure_drop``; radially outwards through the whole ring,
        ``Q = conductance * pressure_drop``. 0 when sealed.
    conductance : float
        Conductance per unit seal length ``1 / int dx (12 eta / u_c^3)`` in m^2/(Pa s); radial
        flow: of the whole contact, ``1 / int_{r_in} dr 12 eta / (2 pi r u_c^3)`` in
        m^3/(Pa s).
    sealed : bool
        Some strip the flow crosses is sealed: its real contact area ``P(q1, p) >= threshold``
        (no channel percolates), or its gap is below ``gap_floor`` (``sealed_by`` says which).
    x, pressure : ndarray
        Strip centres in m (radii of the ring cells for radial flow) and the nominal pressure
        in Pa.
    u_c : ndarray
        Critical gap ``u_c(p(x))`` in m (the effective-medium gap ``u_eff`` with that method;
        with a calibrated ``law``, its hydraulic gap ``g(p(x))``): 0 where the real contact
        area percolates, below ``gap_floor`` (the theory's sub-molecular gap, kept to show how
        far below the floor it is; it may underflow to 0) where the floor seals, +inf where
        p = 0.
    sigma : ndarray
        Local conductance ``u_c^3 / (12 eta)`` in m^3/(Pa s) (not 0 in the strips the floor
        seals: ``sealed_strips`` says which strips carry no flow).
    sealed_strips : ndarray of bool
        The sealed strips, by either criterion (radial flow: only those the flow crosses,
        outside ``inner_radius``).
    floor_strips : ndarray of bool
        The sealed strips that the gap floor alone seals (no percolation there, the gap below
        ``gap_floor``); ``sealed_strips & ~floor_strips`` are those where the real contact
        area percolates, ``P(q1, p) >= threshold``.
    resistance_share, cumulative_share : ndarray
        Each strip's share of the flow resistance ``int dx / sigma`` and its running sum from
        ``x[0]`` (when sealed, the sealed strips share it equally; 0 inside ``inner_radius``).
    share_in_fwhm : float
        Share of the resistance in the strips where ``p >= max(p) / 2``.
    resistance_width : float
        Width in m of the region holding the central 90 % of the resistance (between 5 % and 95 %
        of ``cumulative_share``): where the leak is decided.
    pressure_drop, viscosity, length, threshold : float
        The inputs (Pa, Pa s, m, -); ``length`` is None for radial flow.
    method : str
    converged : bool
        Whether the pressure profile it post-processes converged (True for a given profile).
    diagnostics : dict
        ``n_strips``, ``n_sealed``, ``peak_pressure`` (Pa), ``fluid_pressure_ratio``
        (``pressure_drop / peak_pressure``), ``rolloff_wavelength`` (m, ``2 pi/qr``),
        ``junctions_across`` (``resistance_width / rolloff_wavelength``), ``min_gap`` (m, u_c
        at the strip of highest resistance), ``knudsen`` (or None), ``gap_table`` (z range and
        step of the table), ``warnings`` (the messages behind the :class:`LeakageWarning` s);
        radial flow adds ``orifice_share`` (``inner_radius`` over the half width at half
        maximum of p).
    inner_radius : float or None
        Radial flow: the radius in m where the fluid enters (the orifice of a seat); None for
        flow across a line contact.
    sealed_by : str or None
        Why the seal is sealed: ``"percolation"`` (some strip has ``P(q1, p) >= threshold``;
        it wins when both criteria hold), ``"gap floor"`` (no strip percolates, but the gap
        of some strip is below ``gap_floor``), None when it leaks.
    gap_floor : float
        The molecular floor of the gap in m (0: none).
    """

    Q: float
    conductance: float
    sealed: bool
    x: np.ndarray
    pressure: np.ndarray
    u_c: np.ndarray
    sigma: np.ndarray
    sealed_strips: np.ndarray
    resistance_share: np.ndarray
    cumulative_share: np.ndarray
    share_in_fwhm: float
    resistance_width: float
    pressure_drop: float
    viscosity: float
    length: float | None
    threshold: float
    method: str
    converged: bool
    diagnostics: dict
    inner_radius: float | None = None
    sealed_by: str | None = None
    gap_floor: float = 0.0
    floor_strips: np.ndarray = field(default_factory=lambda: np.zeros(0, dtype=bool))

    def __repr__(self):
        radial = "" if self.inner_radius is None else f", inner_radius={self.inner_radius:.4g} m"
        return (
            f"LeakResult(Q={self.Q:.4g} m^3/s{radial}, sealed={self.sealed}"
            f"{'' if self.sealed_by is None else f' ({self.sealed_by})'}, "
            f"share_in_fwhm={self.share_in_fwhm:.3g}, resistance_width={self.resistance_width:.4g}"
            f" m, converged={self.converged})"
        )


#: points per decade of q where a spectrum without a known roll-off is searched for it
_ROLLOFF_SEARCH_PER_DECADE = 64


def _rolloff_wavenumber(psd) -> float:
    """The roll-off wavenumber qr (1/m): where ``q^2 C(q)``, the height variance per unit
    ln q, peaks. That is qr itself for a self-affine spectrum (C flat below qr, falling as
    ``q^(-2 - 2H)`` above), the smallest over the parts of a sum; for any other spectrum
    (a measured table) the peak is searched on its nodes or on a log grid. A spectrum that
    rises to its lowest wavenumber has it at q0: the roll-off is then not resolved, and
    ``2 pi / q0`` (the longest wavelength the spectrum holds) is a lower bound of the roll-off
    wavelength."""
    parts = getattr(psd, "parts", None)
    if parts is not None:
        return min(_rolloff_wavenumber(part) for part in parts)
    qr = getattr(psd, "qr", None)
    if qr is not None:
        return float(qr)
    q = getattr(psd, "q", None)
    if q is None or np.ndim(q) != 1:
        decades = math.log10(psd.q1 / psd.q0)
        q = np.geomspace(psd.q0, psd.q1, max(2, int(decades * _ROLLOFF_SEARCH_PER_DECADE) + 1))
    q = np.asarray(q, dtype=float)
    q = q[(q >= psd.q0) & (q <= psd.q1)]
    return float(q[int(np.argmax(q * q * np.asarray(psd(q), dtype=float)))])


def _cell_edges(x: np.ndarray, inner_radius: float | None) -> tuple[np.ndarray, np.ndarray]:
    """Lower and upper edges (m) of the cells centred at x: halfway between centres, the end
    cells symmetric (width dx on a uniform grid). Radial flow: the edges are radii, clipped at
    0 (the axis cell of a point contact is a disc) and at ``inner_radius`` (the flow starts
    there; cells inside it have zero width)."""
    mid = 0.5 * (x[1:] + x[:-1])
    edges = np.concatenate([[2.0 * x[0] - mid[0]], mid, [2.0 * x[-1] - mid[-1]]])
    if inner_radius is not None:
        edges = np.maximum(edges, inner_radius)
    return edges[:-1], edges[1:]


def _log_geometry(lo: np.ndarray, hi: np.ndarray, radial: bool) -> np.ndarray:
    """ln of each cell's geometric factor of resistance: its width (strips, per unit seal
    length: ``R = width 12 eta / u_c^3``) or ``ln(hi / lo) / (2 pi)`` (a ring crossed
    radially: ``R = int dr 12 eta / (2 pi r u_c^3)``); -inf for the cells the flow does not
    cross."""
    with np.errstate(divide="ignore"):
        if not radial:
            return np.log(hi - lo)
        return np.log(np.log(hi / lo)) - math.log(2.0 * math.pi)


def _scalars(pressure_drop, viscosity, length, threshold, method, mean_free_path):
    pressure_drop = positive("pressure_drop", pressure_drop, "Pa")
    viscosity = positive("viscosity", viscosity, "Pa s")
    length = None if length is None else positive("length", length, "m")
    method = _method(method)
    if threshold is None:  # each method's own threshold
        threshold = THRESHOLD_BRUGGEMAN if method == "effective-medium" else THRESHOLD_PERSSON
    threshold = check_threshold(threshold)
    if mean_free_path is not None:
        mean_free_path = positive("mean_free_path", mean_free_path, "m")
    return pressure_drop, viscosity, length, threshold, mean_free_path


def _method(method) -> str:
    """The method's name (``_`` read as ``-``), checked."""
    name = method.replace("_", "-") if isinstance(method, str) else method
    if name not in METHODS:
        raise ValueError(f"method must be one of {METHODS}, got {method!r}")
    return name


def _gap_floor(gap_floor) -> float:
    out = finite_scalar("gap_floor", gap_floor)
    if out < 0.0:
        raise ValueError(f"gap_floor must be >= 0 m (allowed range [0, inf)), got {out!r}")
    return out


def _profile(x, p, inner_radius=None):
    x = finite_array("x", x, ndim=1)
    p = finite_array("p", p, ndim=1)
    if x.size < 2:
        raise ValueError(f"x must hold at least 2 strip centres, got {x.size}")
    if p.shape != x.shape:
        raise ValueError(f"p must have the same length as x ({x.size}), got {p.size}")
    if np.any(np.diff(x) <= 0.0):
        raise ValueError("x must be strictly increasing (strip centres in m)")
    if np.any(p < 0.0):
        raise ValueError("p must be >= 0 Pa everywhere (allowed range [0, inf))")
    if not np.any(p > 0.0):
        raise ValueError("p must be > 0 somewhere (an unloaded profile has no contact)")
    if inner_radius is None:
        return x, p, None
    if x[0] < 0.0:
        raise ValueError(f"x must be radii >= 0 m for radial flow, got x[0] = {x[0]:.6g}")
    inner_radius = positive("inner_radius", inner_radius, "m")
    outer = float(_cell_edges(x, None)[1][-1])
    if inner_radius >= outer:
        raise ValueError(
            f"inner_radius must be below the outer edge of the profile, {outer:.6g} m "
            f"(allowed range (0, {outer:.6g}) m), got {inner_radius:.6g}"
        )
    return x, p, inner_radius


def _resistance(log_geometry, log_gap, sealed, viscosity):
    """ln of the total resistance (the cells' geometric factors times 12 eta / u_c^3, summed)
    and each cell's share of it."""
    if sealed.any():
        share = sealed / float(sealed.sum())
        return math.inf, share
    with np.errstate(over="ignore", invalid="ignore"):
        log_r = log_geometry + math.log(12.0 * viscosity) - 3.0 * log_gap
    log_r[np.isneginf(log_geometry)] = -math.inf  # not crossed (also where the gap is +inf)
    top = float(np.max(log_r))
    log_total = top + math.log(float(np.sum(np.exp(log_r - top))))
    return log_total, np.exp(log_r - log_total)


def _where(lo, hi, p, share):
    """Cumulative share, the share inside the FWHM and the width holding the central 90 %."""
    cum = np.cumsum(share)
    cum /= cum[-1]
    in_fwhm = float(np.sum(share[p >= 0.5 * p.max()]))
    edges = np.concatenate([lo[:1], hi])
    c_edges = np.concatenate([[0.0], cum])
    lo, hi = np.interp([0.05, 0.95], c_edges, edges)
    return cum, in_fwhm, float(hi - lo)


def _half_width(hi: np.ndarray, p: np.ndarray) -> float:
    """Half width at half maximum (m) of a radial pressure profile: the outer edge of the
    outermost cell with ``p >= max(p) / 2``."""
    return float(hi[np.nonzero(p >= 0.5 * p.max())[0][-1]])


def _orifice(hi, p, inner_radius) -> tuple[dict, list[str]]:
    """Radial flow: the orifice's size against the contact it perforates (``hi``: the cells'
    outer edges in m, clipped at the orifice: a half width inside it gives a share of 1)."""
    share = inner_radius / _half_width(hi, p)
    msgs = []
    if share > MAX_ORIFICE_SHARE:
        msgs.append(
            "the orifice (inner_radius) is wider than 0.1 of the pressure's half width at half "
            "maximum (diagnostics['orifice_share']): the contact pressure is that of the solid "
            "contact, which an orifice of that size changes"
        )
    return {"orifice_share": share}, msgs


def _validity(theory, p, pressure_drop, width90, min_gap, sealed, mean_free_path):
    """Out-of-range checks (docs/leakage.md, "When the model is out of its range"): numbers for
    the diagnostics, messages for warnings."""
    lam_r = 2.0 * math.pi / _rolloff_wavenumber(theory.psd)
    p_max = float(p.max())
    out = {
        "peak_pressure": p_max,
        "fluid_pressure_ratio": pressure_drop / p_max,
        "rolloff_wavelength": lam_r,
        "junctions_across": None if sealed else width90 / lam_r,
        "min_gap": min_gap,
        "knudsen": None,
    }
    msgs = []
    if out["fluid_pressure_ratio"] > MAX_FLUID_PRESSURE_RATIO:
        msgs.append(
            "the fluid pressure drop exceeds 10% of the peak contact pressure "
            "(diagnostics['fluid_pressure_ratio']): the theory neglects the fluid pressure on "
            "the walls, which lowers the contact pressure and can open the seal"
        )
    if not sealed and out["junctions_across"] < MIN_JUNCTIONS:
        msgs.append(
            "fewer than 5 roll-off wavelengths 2 pi/qr fit across the region holding 90% of the "
            "flow resistance (diagnostics['junctions_across']): the critical-junction theory "
            "averages over many junctions and is only an estimate for so narrow a contact"
        )
    if mean_free_path is not None and not sealed and min_gap > 0.0:
        out["knudsen"] = mean_free_path / min_gap
        if out["knudsen"] > MAX_KNUDSEN:
            msgs.append(
                "the mean free path exceeds 0.1 of the critical gap (diagnostics['knudsen']): "
                "gas rarefaction (slip or Knudsen flow) is not in the viscous flow model"
            )
    return out, msgs


def leak_rate_profile(
    x: ArrayLike,
    p: ArrayLike,
    theory: PerssonTheory,
    pressure_drop: float,
    viscosity: float,
    length: float | None = None,
    *,
    inner_radius: float | None = None,
    threshold: float | None = None,
    method: Literal["critical-junction", "effective-medium"] = "critical-junction",
    mean_free_path: float | None = None,
    gap_floor: float = GAP_FLOOR,
    warn: bool = True,
) -> LeakResult:
    """Leak rate of a seal with a nominal pressure profile p(x): strips (or rings) in series,
    each of conductance ``u_c(p)^3 / (12 eta)`` (module docstring; docs/leakage.md §3-5).

    Parameters
    ----------
    x, p : array_like
        Strip (cell) centres in m, strictly increasing, at least 2, edges halfway between
        (radial flow: radii >= 0 of rings), and the nominal pressure there in Pa (>= 0).
    theory : PerssonTheory
        The theory of the interface (spectrum, E*, gamma).
    pressure_drop, viscosity : float
        Pressure difference across the seal in Pa and dynamic viscosity in Pa s (> 0).
    length : float, optional
        Seal length L_y in m (> 0) across the flow (an O-ring's circumference); default 1 m;
        not for radial flow.
    inner_radius : float, optional
        Radial flow (a point contact): the radius in m where the fluid enters, in (0, outer
        edge of the profile); warns above ``MAX_ORIFICE_SHARE`` of p's half width.
    threshold : float, optional
        Percolation threshold of the real contact area, in (0, 1) (see :func:`critical_gap`);
        default the method's: 0.42 for the critical junction, 0.5 (Bruggeman) for the
        effective medium.
    method : {"critical-junction", "effective-medium"}
        The local gap: the critical junction's ``u_c`` or the effective-medium gap
        ``(12 eta s_eff)^(1/3)`` (docs/leakage.md; ``_`` may stand for ``-``).
    mean_free_path : float, optional
        Mean free path of a gas in m (70e-9 for air at 1 bar): warns if not viscous flow.
    gap_floor : float
        Molecular floor of the gap in m, >= 0 (default :data:`GAP_FLOOR`, 1 nm; 0 switches it
        off): a strip whose gap is below it is sealed (``sealed_by = "gap floor"``).
    warn : bool
        Emit the :class:`LeakageWarning` s (listed in ``diagnostics['warnings']`` either way).

    Returns
    -------
    LeakResult
    """
    flow = _flow(
        pressure_drop, viscosity, length, inner_radius, threshold, method, mean_free_path,
        gap_floor,
    )  # fmt: skip
    interface_cache(theory)
    x, p, inner_radius = _profile(x, p, inner_radius)
    return _leak(x, p, theory, flow, boolean("warn", warn), converged=True)


def _length(length, inner_radius) -> float | None:
    """The seal length: 1 m by default across a line contact; none for radial flow."""
    if inner_radius is None:
        return 1.0 if length is None else length
    if length is not None:
        raise ValueError(
            "length is for flow across a line contact; radial flow (inner_radius given) goes "
            "round the whole ring: leave length at None"
        )
    return None


@dataclass(frozen=True)
class _Flow:
    """The fluid and flow path of a leak-rate call (validated)."""

    pressure_drop: float
    viscosity: float
    length: float | None
    inner_radius: float | None
    threshold: float
    method: str
    mean_free_path: float | None
    gap_floor: float = GAP_FLOOR


def _flow(
    pressure_drop, viscosity, length, inner_radius, threshold, method, mean_free_path, gap_floor
) -> _Flow:
    """The validated fluid and flow path of a call (``inner_radius`` is checked against the
    profile by :func:`_profile`)."""
    length = _length(length, inner_radius)
    pressure_drop, viscosity, length, threshold, mean_free_path = _scalars(
        pressure_drop, viscosity, length, threshold, method, mean_free_path
    )
    return _Flow(
        pressure_drop, viscosity, length,
        None if inner_radius is None else positive("inner_radius", inner_radius, "m"),
        threshold, _method(method), mean_free_path, _gap_floor(gap_floor),
    )  # fmt: skip


def _law(law, method):
    """A calibrated law for the gap (duck-typed: it has ``log_hydraulic_gap``), or None."""
    if law is not None and not callable(getattr(law, "log_hydraulic_gap", None)):
        raise TypeError(
            "law must be a calibrated law with log_hydraulic_gap(p) (fastline.CalibratedLaw, "
            f"from fastline.calibrate), got {type(law).__name__}"
        )
    if law is not None and method != "critical-junction":
        raise ValueError(
            f"law gives the gap of every strip itself; method={method!r} cannot be used with it "
            "(leave method at 'critical-junction')"
        )
    return law


def _gaps(theory, p, flow: _Flow, law):
    """(ln gap, sealed strips, table diagnostics): the local gap of the flow's method from its
    table, or a calibrated law's hydraulic gap g(p) in its place."""
    if law is not None:
        log_gap, sealed = law.log_hydraulic_gap(p)
        return log_gap, sealed, {"law": getattr(law, "name", "calibrated")}
    table = _gap_table(theory, flow)
    log_gap, sealed = table.log_gap(sealing_argument(theory, p))
    return log_gap, sealed, _summary(table)


def _leak(x, p, theory, flow: _Flow, warn: bool, converged: bool, law=None) -> LeakResult:
    radial = flow.inner_radius is not None
    log_gap, sealed_strips, table = _gaps(theory, p, flow, law)
    lo, hi = _cell_edges(x, flow.inner_radius)
    log_geometry = _log_geometry(lo, hi, radial)
    crossed = ~np.isneginf(log_geometry)  # only the cells the flow crosses
    sealed_strips &= crossed
    below = crossed & ~sealed_strips & _below_floor(log_gap, flow.gap_floor)
    sealed_by = "percolation" if sealed_strips.any() else ("gap floor" if below.any() else None)
    sealed_strips |= below
    sealed = sealed_by is not None
    log_total, share = _resistance(log_geometry, log_gap, sealed_strips, flow.viscosity)
    conductance = 0.0 if sealed else math.exp(-log_total)
    cum, in_fwhm, width90 = _where(lo, hi, p, share)
    with np.errstate(over="ignore"):
        gap = np.exp(log_gap)
        sigma = gap**3 / (12.0 * flow.viscosity)
    min_gap = 0.0 if sealed else float(gap[int(np.argmax(share))])
    diag, msgs = _validity(
        theory, p, flow.pressure_drop, width90, min_gap, sealed, flow.mean_free_path
    )
    if radial:
        more, more_msgs = _orifice(hi, p, flow.inner_radius)
        diag.update(more)
        msgs += more_msgs
    diag.update(n_strips=int(x.size), n_sealed=int(sealed_strips.sum()))
    diag.update(n_below_floor=int(below.sum()), gap_table=table, warnings=msgs)
    for msg in msgs if warn else ():
        warnings.warn(f"fastline.leak_rate: {msg}", LeakageWarning, stacklevel=3)
    if warn and not converged:  # not in diagnostics: the solve's own diagnostics say it
        warnings.warn(UNCONVERGED, LeakageWarning, stacklevel=3)
    return LeakResult(
        Q=conductance * (1.0 if radial else flow.length) * flow.pressure_drop,
        conductance=conductance,
        sealed=sealed,
        x=x,
        pressure=p,
        u_c=gap,
        sigma=sigma,
        sealed_strips=sealed_strips,
        resistance_share=share,
        cumulative_share=cum,
        share_in_fwhm=in_fwhm,
        resistance_width=width90,
        pressure_drop=flow.pressure_drop,
        viscosity=flow.viscosity,
        length=flow.length,
        threshold=flow.threshold,
        method=flow.method,
        converged=converged,
        diagnostics=diag,
        inner_radius=flow.inner_radius,
        sealed_by=sealed_by,
        gap_floor=flow.gap_floor,
        floor_strips=below,
    )


def _flow_table(theory, leak: LeakResult):
    """The local-gap table a leak rate used (for the coupled seal)."""
    return _gap_table(theory, _Flow(leak.pressure_drop, leak.viscosity, leak.length, None,
                                    leak.threshold, leak.method, None, leak.gap_floor))  # fmt: skip


def _summary(table) -> dict:
    """z range and step of the gap table (``diagnostics['gap_table']``)."""
    if isinstance(table, _MediumTable):
        return table.summary()
    return {"z0": table.z0, "h": table.h, "cells": int(table.cf.shape[0])}


def _below_floor(log_gap: np.ndarray, gap_floor: float) -> np.ndarray:
    """The strips whose gap is below the molecular floor (none for a floor of 0)."""
    if gap_floor <= 0.0:
        return np.zeros(log_gap.shape, dtype=bool)
    return log_gap < math.log(gap_floor)


def _gap_table(theory, flow: _Flow):
    """The table of the local gap of the flow's method: ``log_gap(x1) -> (ln gap, sealed)``."""
    if flow.method == "effective-medium":
        return medium_table(theory, flow.threshold)
    return gap_table(theory, flow.threshold)


def leak_rate(
    result: LineContactResult | PointContactResult,
    pressure_drop: float,
    viscosity: float,
    length: float | None = None,
    *,
    inner_radius: float | None = None,
    theory: PerssonTheory | None = None,
    threshold: float | None = None,
    method: Literal["critical-junction", "effective-medium"] = "critical-junction",
    mean_free_path: float | None = None,
    gap_floor: float = GAP_FLOOR,
    warn: bool = True,
    law: CalibratedLaw | None = None,
) -> LeakResult:
    """Leak rate of a solved contact: across a line contact (along x), or radially out of the
    orifice of a point contact.

    The nominal pressure of a contact result (any model with a roughness spectrum) and the
    theory of its interface give it by :func:`leak_rate_profile` (docs/leakage.md §4-5).

    Parameters
    ----------
    result : LineContactResult or PointContactResult
        A solved contact (``model="persson"`` or ``"exponential"``).
    pressure_drop, viscosity, threshold, method, mean_free_path, gap_floor, warn
        As in :func:`leak_rate_profile` (Pa, Pa s, -, str, m, m, bool); with ``warn`` an
        unconverged result warns too (one text: a loop shows it once).
    length : float, optional
        Line contact: the seal length in m (default 1 m). Not for a point contact.
    inner_radius : float, optional
        Point contact (required there): the radius in m where the fluid enters, e.g. the
        orifice of a valve seat closed by a ball; the fluid flows outwards through the contact.
        Not for a line contact.
    theory : PerssonTheory, optional
        The theory the contact was solved with; default ``result.theory`` (or ``law.theory``).
    law : CalibratedLaw, optional
        Its Reynolds effective gap g(p) in place of u_c(p) (:func:`fastline.calibrate`).

    Returns
    -------
    LeakResult

    Raises
    ------
    TypeError
        For anything but a line- or point-contact result.
    ValueError
        For a Hertz result, no theory, a theory of another interface (E*, spectrum, gamma,
        variant), ``inner_radius`` missing for a point contact or given for a line contact,
        or an input outside its range.
    """
    coords = _coordinates(result, inner_radius)
    flow = _flow(
        pressure_drop, viscosity, length, inner_radius, threshold, method, mean_free_path,
        gap_floor,
    )  # fmt: skip
    theory = _result_theory(result, theory, _law(law, flow.method))
    x, p, _ = _profile(coords, result.pressure, inner_radius)
    return _leak(x, p, theory, flow, boolean("warn", warn), bool(result.converged), law)


def _coordinates(result, inner_radius) -> np.ndarray:
    """The cell centres of a contact result (x of a line contact, r of a point contact), with
    the check that ``inner_radius`` comes with the point contact only."""
    line = hasattr(result, "x") and hasattr(result, "pressure")
    point = hasattr(result, "r") and hasattr(result, "pressure")
    if not (line or point):
        raise TypeError(
            "result must be a LineContactResult or a PointContactResult (from "
            f"solve_line_contact / solve_point_contact), got {type(result).__name__}; for a "
            "pressure profile of your own use leak_rate_profile"
        )
    if point and inner_radius is None:
        raise ValueError(
            "inner_radius is required for a point contact: the radius in m where the fluid "
            "enters (e.g. the orifice of a seat); the leak is the radial flow from there "
            "outwards"
        )
    if line and inner_radius is not None:
        raise ValueError(
            "inner_radius is for a point contact (radial flow); a line contact leaks across x"
        )
    return result.r if point else result.x


def _result_theory(result, theory, law=None):
    """The PerssonTheory of a result's interface (or of a calibrated ``law``), checked against
    its E*."""
    if getattr(result, "model", None) == "hertz":
        raise ValueError(
            "leak_rate needs a roughness spectrum: a model='hertz' result is for smooth surfaces "
            "(solve with model='persson' or 'exponential')"
        )
    if theory is None:
        theory = getattr(result, "theory", None)
    if theory is None and law is not None:
        theory = law.theory
    if theory is None:
        raise ValueError(
            "leak_rate needs the PerssonTheory of the interface: pass theory=... (the one the "
            "contact was solved with)"
        )
    interface_cache(theory)
    if not math.isclose(theory.E_star, result.E_star, rel_tol=1e-12):
        raise ValueError(
            f"theory.E_star = {theory.E_star:g} Pa differs from the result's E* = "
            f"{result.E_star:g} Pa"
        )
    _check_same_interface(result, theory)
    return theory


def _check_same_interface(result, theory) -> None:
    """The theory must describe the surface the result was solved for: its h_rms (which the
    result carries as ``alpha * delta``) and, when the result holds a theory, its gamma and
    variant. A theory of another spectrum would give a leak rate decades off, silently."""
    h_rms = result.alpha * result.delta  # NaN for a law of your own without a spectrum
    if math.isfinite(h_rms) and not math.isclose(theory.psd.h_rms, h_rms, rel_tol=1e-9):
        raise ValueError(
            f"theory is of another spectrum: its h_rms = {theory.psd.h_rms:.6g} m, the result's "
            f"{h_rms:.6g} m (alpha * delta); pass the theory the contact was solved with"
        )
    own = getattr(result, "theory", None)
    if own is not None and (own.gamma, own.variant) != (theory.gamma, theory.variant):
        raise ValueError(
            f"theory has gamma = {theory.gamma:g}, variant {theory.variant!r}; the result was "
            f"solved with gamma = {own.gamma:g}, variant {own.variant!r}: pass the theory the "
            "contact was solved with"
        )
