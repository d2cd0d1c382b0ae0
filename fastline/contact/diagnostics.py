"""Validity diagnostics of a solved line contact (docs/theory.md sections 6 and 7).

:func:`assess` looks at a :class:`~fastline.contact.line.LineContactResult` (or a
:class:`~fastline.contact.point.PointContactResult`: there "half-width" reads "radius", the
Hertz half-width is the Hertz contact radius and the width is a diameter) and reports which
regime the scene is in (information) and which model assumptions fail (warnings):

* **regime** from ``alpha = h_rms / delta``: ``"Hertz-like"`` for alpha < 0.01,
  ``"Gaussian-like"`` for alpha > 10, ``"transition"`` in between (paper, section 3);
* **exponential-law range**: the range of pressures where ``u = u0 ln(beta E* / p)`` (paper
  eq. 5) is within 5 % of the full Persson ``u(p)``; with ``model="exponential"`` a scene whose
  pressures (``1e-3 p0`` to ``p0``) leave it is warned about (cause ``"exponential_range"``);
  for the full theory ``p0 / (beta E*)`` and whether the peak lies beyond that range are
  reported (information: there the profile is more peaked than a Gaussian and w/s can fall
  below 2.355, docs/theory.md section 6);
* **elastic mean asperity pressure** ``h' E*/2`` (h' the rms slope) and the real contact area
  fraction at the peak, ``P(q1, p0)``; with a hardness given, a warning when ``h' E*/2``
  exceeds it (cause ``"plastic"``);
* **half-space**: a warning when the contact half-width exceeds 10 % of R (``"half_space"``);
* **mean field**: a warning when the contact (the larger of the FWHM and the Hertz width 2a)
  is narrower than the longest roughness wavelength ``2 pi / q0`` (``"narrow_contact"``): the
  theory assumes the nominal pressure varies slowly on that scale;
* **domain**: a warning when the pressure at the edge of the domain exceeds
  :data:`EDGE_LIMIT` of p0 (``"truncated_domain"``): a ``half_width`` (``domain_radius``)
  given too small cuts off part of the contact, and p0, s and w/s are off, converged or not
  (not for a result of ``accuracy=`` that met it: its error estimate counts the truncation);
* **resolution**: a warning when the FWHM spans fewer than :data:`RESOLUTION_CELLS` grid cells,
  or the contact's edge (the fall from p0/2 to :data:`ROLLOFF_LEVEL` p0) fewer than
  :data:`ROLLOFF_CELLS` (``"resolution"``): p0 and w/s are then limited by the grid, converged
  or not.

Warnings reach the user once: :func:`assess` lists them (``warning_causes``,
``warning_messages``) and emits them when ``warn=True``; for many results (a sweep)
:func:`warn_once` emits one :class:`ValidityWarning` per cause naming the loads concerned,
and :func:`summarise_warnings` returns those messages without emitting them.

SI units throughout: Pa, m, N/m (N for a point contact).
"""

from __future__ import annotations

import math
import warnings
from collections.abc import Iterable
from typing import TYPE_CHECKING

import numpy as np

from fastline.errors import ValidityWarning
from fastline.theory.limits import hertz_line_unchecked
from fastline.theory.persson import PerssonTheory

if TYPE_CHECKING:  # annotations only
    from fastline.contact.line import LineContactResult
    from fastline.contact.point import PointContactResult
    from fastline.theory.spectra import PSD

__all__ = [
    "ValidityWarning",
    "assess",
    "regime",
    "summarise_warnings",
    "warn_once",
    "CAUSES",
    "HERTZ_LIKE_ALPHA",
    "GAUSSIAN_LIKE_ALPHA",
    "RESOLUTION_CELLS",
    "ROLLOFF_CELLS",
    "EDGE_LIMIT",
]

#: alpha below which the contact is Hertz-like (paper section 3).
HERTZ_LIKE_ALPHA = 0.01
#: alpha above which the contact is Gaussian-like (paper section 3).
GAUSSIAN_LIKE_ALPHA = 10.0
#: relative mismatch in u allowed between the exponential law and the full theory.
EXPONENTIAL_RTOL = 0.05
#: lowest pressure (relative to p0) considered "met" in the contact.
PRESSURE_FLOOR = 1e-3
#: contact half-width / radius above which the half-space assumption is strained.
HALF_WIDTH_LIMIT = 0.1
#: fewest grid cells across the FWHM for a result not to be resolution-limited. Measured on a
#: fixed domain against n = 16384 (four scenes: the paper's surface 1 at alpha 0.01, 1 and 30,
#: and the needle-peaked scene of docs/accuracy.md): at 7-8 cells p0 is within 0.08 % and w/s within
#: 0.4 % for the paper's scenes; the needle scene has p0 off by 4 % at 2.8 cells, 0.5 % at
#: 5.9 and 0.07 % at 11.9.
RESOLUTION_CELLS = 8.0
#: fewest grid cells across the contact's edge, the fall of p from p0/2 to ROLLOFF_LEVEL p0
#: (outermost crossings, linear interpolation). A Hertz-like contact with a steep edge can
#: have a FWHM of many cells and an edge of one: a sphere whose law is in full contact up to
#: the edge (rms slope 6e-5, the domain sized by u0 23 times the Hertz radius) had, against
#: n = 2048 on its domain, w/s off by 4.0 % at n = 128 (FWHM 9.2 cells, edge 1.4 cells),
#: 0.5 % at 256 (2.2 cells) and 0.08 % at 512 (3.7 cells). The paper's surface 1 (alpha
#: 1e-3..100) has edges of 3.3 cells or more already at n = 32, with w/s within 0.6 %.
ROLLOFF_CELLS = 3.0
#: the level (relative to p0) where the edge ends, for ROLLOFF_CELLS
ROLLOFF_LEVEL = 0.01
#: pressure at the domain edge, relative to p0, above which the domain cuts off the contact.
#: Measured against the default domain (paper surface 1, E* = 1.33 GPa, R = 1 cm, n = 2048,
#: domains a + k sqrt(R u0)): an edge pressure of 1e-3 goes with errors of 0.03-0.4 % in s
#: and w/s and below 0.2 % in p0 (alpha 0.1-100; cylinder and sphere), 1e-2 with 1-4 %,
#: 0.4-0.8 with 20-190 % (and a NaN FWHM when p does not fall to p0/2 inside the domain); the
#: default domain's edge pressure is below 1e-14 over alpha 1e-3..100
EDGE_LIMIT = 1e-3
#: causes whose worst case is the smallest load of a sweep (the narrowest contact)
_WORST_AT_SMALL_LOAD = frozenset({"narrow_contact"})
#: warning causes, in the order they are reported
CAUSES = (
    "half_space",
    "plastic",
    "exponential_range",
    "narrow_contact",
    "truncated_domain",
    "resolution",
)


_REAL = (int, float, np.floating, np.integer)


def regime(alpha: float) -> str:
    """``"Hertz-like"`` (alpha < 0.01), ``"Gaussian-like"`` (alpha > 10) or ``"transition"``."""
    if alpha < HERTZ_LIKE_ALPHA:
        return "Hertz-like"
    if alpha > GAUSSIAN_LIKE_ALPHA:
        return "Gaussian-like"
    return "transition"


def _exponential_validity(theory, fit, p_lo_met: float, p_hi_met: float) -> dict:
    """The law's valid range and a direct check on the pressures the contact meets."""
    pm = np.logspace(math.log10(p_lo_met), math.log10(p_hi_met), 60)
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        um = theory.separation(pm)
        err = np.abs(fit.u0 * np.log(fit.beta * theory.E_star / pm) - um) / um
    err = np.where(np.isnan(err), np.inf, err)  # u = 0 (full contact): the law is off
    return {
        "exponential_valid": bool(np.all(err <= EXPONENTIAL_RTOL)),
        "exponential_valid_range": theory.exponential_valid_range(EXPONENTIAL_RTOL),
        "exponential_max_error": float(err.max()),
        "pressure_range_met": (float(p_lo_met), float(p_hi_met)),
    }


def _hertz_half_width(result) -> float:
    """The result's Hertz half-width (its ``hertz_radius`` if it has one: a point contact)."""
    a = getattr(result, "hertz_radius", None)
    if a is None:  # a line contact: a solver's own checked values
        a = hertz_line_unchecked(result.E_star, result.radius, result.load).a
    return a


def _half_space(out, result, msgs) -> None:
    half = _hertz_half_width(result)
    if math.isfinite(result.fwhm):
        half = max(half, 0.5 * result.fwhm)
    out["half_width"] = float(half)
    out["half_width_over_radius"] = float(half / result.radius)
    out["half_space_ok"] = bool(half <= HALF_WIDTH_LIMIT * result.radius)
    if not out["half_space_ok"]:
        word = getattr(result, "EXTENT_WORD", "half-width")
        body = "the sphere's radius" if word == "radius" else "the radius"
        msgs["half_space"] = (
            f"contact {word} {half:.3g} m is {100 * half / result.radius:.3g}% of {body} "
            f"R = {result.radius:.3g} m (> {100 * HALF_WIDTH_LIMIT:g}%): the elastic half-space "
            "assumption is strained"
        )
    out["contact_width"] = float(2.0 * half)


def _mean_field(out, result, psd, msgs) -> None:
    if psd is None:
        out["longest_wavelength"] = out["mean_field_ok"] = None
        return
    lam = 2.0 * math.pi / float(psd.q0)
    width = out["contact_width"]
    out["longest_wavelength"] = lam
    out["mean_field_ok"] = bool(width >= lam)
    if width < lam:
        wide = "wide, max of FWHM and the Hertz width 2a"
        if getattr(result, "EXTENT_WORD", "half-width") == "radius":
            wide = "across, max of FWHM and the Hertz diameter 2a"
        msgs["narrow_contact"] = (
            f"the contact ({width:.3g} m {wide}) is narrower "
            f"than the longest roughness wavelength 2 pi/q0 = {lam:.3g} m: the theory's "
            "mean-field assumption (pressure varying slowly on that scale) is not met"
        )


def _domain_parameter(result) -> str:
    """The name of the option that sets the domain: a cylinder's ``half_width``, a sphere's
    ``domain_radius``."""
    point = getattr(result, "EXTENT_WORD", "half-width") == "radius"
    return "domain_radius" if point else "half_width"


def _domain_half_width(result) -> float:
    """The extent of the solved domain (m): a cylinder's cells span ``n dx``, a sphere's
    central disc and rings reach ``(n - 1/2) dr``."""
    if hasattr(result, "dr"):
        return float((result.r.size - 0.5) * result.dr)
    return float(0.5 * result.x.size * result.dx)


def _domain(out, result, msgs) -> None:
    edge = float(result.edge_pressure)
    out["domain_ok"] = bool(edge <= EDGE_LIMIT)
    estimate = getattr(result, "error_estimate", None)
    if estimate is not None and estimate.met:  # accuracy= met: the truncation is in its errors
        return
    if not out["domain_ok"]:
        name = _domain_parameter(result)
        msgs["truncated_domain"] = (
            f"the pressure at the edge of the domain is {edge:.3g} of p0 (> {EDGE_LIMIT:g}): "
            f"the domain ({name} = {out['domain_half_width']:.3g} m) cuts off part of the "
            f"contact and p0, s and w/s are off; widen {name} (None, the default, sizes it "
            "for each load)"
        )


def _resolution(out, result, msgs) -> None:
    step = result.dr if hasattr(result, "dr") else result.dx  # a point contact's ring width
    cells = result.fwhm / step if step > 0 else float("nan")
    edge = _edge_cells(result, step)
    out["fwhm_cells"] = float(cells)
    out["edge_cells"] = edge
    wide = not cells < RESOLUTION_CELLS  # NaN: no FWHM inside the domain (the domain check)
    sharp = not edge < ROLLOFF_CELLS
    out["resolution_ok"] = bool(cells >= RESOLUTION_CELLS and sharp)
    fix = f"raise n or narrow {_domain_parameter(result)}"
    if not wide:
        msgs["resolution"] = (
            f"the FWHM spans {cells:.3g} grid cells (< {RESOLUTION_CELLS:g}): p0 and w/s are "
            f"limited by the grid (errors of percents); {fix}"
        )
    elif not sharp:
        msgs["resolution"] = (
            f"the contact's edge (p falling from p0/2 to {ROLLOFF_LEVEL:g} p0) spans {edge:.2g} "
            f"grid cells (< {ROLLOFF_CELLS:g}): p0, s and w/s are limited by the grid (errors "
            f"of percents, though the FWHM spans {cells:.3g} cells); {fix}"
        )


def _edge_cells(result, step: float) -> float:
    """Grid cells between the outermost crossings of p0/2 and ``ROLLOFF_LEVEL`` p0 (linear
    interpolation between cell centres); NaN when p does not fall that far in the domain."""
    x = result.r if hasattr(result, "r") else result.x
    p, p0 = np.asarray(result.pressure), float(result.p0)
    if not (step > 0 and p0 > 0 and math.isfinite(p0)):
        return float("nan")
    ends = []
    for level in (0.5 * p0, ROLLOFF_LEVEL * p0):
        above = np.flatnonzero(p >= level)
        j = int(above[-1]) if above.size else -1
        if j < 0 or j == p.size - 1:
            return float("nan")
        ends.append(x[j] + (p[j] - level) / (p[j] - p[j + 1]) * (x[j + 1] - x[j]))
    return float((ends[1] - ends[0]) / step)


def _asperities(out, result, theory, hardness, msgs) -> None:
    if theory is None:
        out["rms_slope"] = out["asperity_pressure"] = out["real_area_at_peak"] = None
        out["plastic_likely"] = None
        return
    slope = theory.rms_slope
    p_asp = 0.5 * slope * result.E_star
    out["rms_slope"] = slope
    out["asperity_pressure"] = p_asp
    if math.isfinite(result.p0) and result.p0 >= 0.0:  # a solver's own peak: no checks needed
        out["real_area_at_peak"] = float(theory._real_area(np.array([result.p0]))[0])
    else:
        out["real_area_at_peak"] = math.nan
    out["plastic_likely"] = None if hardness is None else bool(p_asp > hardness)
    if out["plastic_likely"]:
        msgs["plastic"] = (
            f"elastic mean asperity pressure h'E*/2 = {p_asp:.3g} Pa exceeds the hardness "
            f"{hardness:.3g} Pa: asperities likely deform plastically (the theory is elastic)"
        )


def _exponential(out, result, theory, msgs) -> None:
    if theory is None or not (math.isfinite(result.p0) and result.p0 > 0.0):
        return
    fit = theory.exponential_fit()
    out["p0_over_beta_E_star"] = float(result.p0 / (fit.beta * result.E_star))
    if result.model == "persson":
        top = theory.exponential_valid_range(EXPONENTIAL_RTOL)[1]
        out["beyond_exponential_law"] = bool(not result.p0 <= top)
    if result.model != "exponential":
        return
    out.update(_exponential_validity(theory, fit, PRESSURE_FLOOR * result.p0, result.p0))
    if not out["exponential_valid"]:
        hi = out["exponential_valid_range"][1]
        msgs["exponential_range"] = (
            f"model='exponential' is used outside its range: over the pressures met "
            f"({PRESSURE_FLOOR * result.p0:.3g}-{result.p0:.3g} Pa) its u(p) is off by up to "
            f"{out['exponential_max_error']:.3g} (relative; within 5% only below {hi:.3g} Pa): "
            "use model='persson'"
        )


def assess(
    result: LineContactResult | PointContactResult,
    theory: PerssonTheory | None = None,
    hardness: float | None = None,
    *,
    psd: PSD | None = None,
    warn: bool = True,
    stacklevel: int = 1,
) -> dict:
    """Regime and validity checks of a solved line or point contact.

    Parameters
    ----------
    result : LineContactResult or PointContactResult
        A solve from :func:`fastline.contact.line.solve_line_contact` or
        :func:`fastline.contact.point.solve_point_contact`.
    theory : PerssonTheory, optional
        The theory the scene was solved with (needed for the rms slope, the real contact area,
        the exponential-law checks and the roughness wavelength). If omitted and ``psd`` is
        given, one is built.
    hardness : float, optional
        Indentation hardness of the softer solid in Pa. When the elastic mean asperity pressure
        ``h' E*/2`` exceeds it a :class:`ValidityWarning` is emitted.
    psd : PSD, optional
        The roughness spectrum, used only when ``theory`` is not given.
    warn : bool
        One :class:`ValidityWarning` per cause found and not yet reported for this result (by
        its solve or an earlier ``assess``); all are listed either way. The regime never warns.
    stacklevel : int
        Where the warnings point: 1 the caller of ``assess``, 2 its caller, and so on.

    Returns
    -------
    dict
        ``regime`` (str), ``alpha`` (-), ``half_width`` (m; max of FWHM/2 and the Hertz a),
        ``contact_width`` (m, twice that), ``half_width_over_radius`` (-), ``half_space_ok``
        (bool), ``longest_wavelength`` (m, ``2 pi/q0``) and ``mean_field_ok`` (contact at least
        that wide), ``domain_half_width`` (m, the solved domain's extent) and ``domain_ok``
        (edge pressure at most :data:`EDGE_LIMIT` of p0), ``fwhm_cells`` (FWHM / grid
        spacing), ``edge_cells`` (cells from p0/2 to ``ROLLOFF_LEVEL`` p0) and
        ``resolution_ok``, ``rms_slope`` (-), ``asperity_pressure`` (Pa, ``h' E*/2``),
        ``real_area_at_peak`` (-, ``P(q1, p0)``), ``plastic_likely`` (bool or None),
        ``p0_over_beta_E_star`` (-); for
        ``model="persson"`` ``beyond_exponential_law`` (the peak lies above the range where
        the exponential law holds); for ``model="exponential"`` ``exponential_valid`` (bool),
        ``exponential_valid_range`` ((p_min, p_max) in Pa where the law is within 5 % in u;
        p_min is 0 since the law is the low-pressure asymptote), ``exponential_max_error``
        (relative, over the pressures met) and ``pressure_range_met`` ((1e-3 p0, p0) in Pa).
        Quantities that cannot be computed (no theory, Hertz model) are None or absent.
        ``warning_causes`` lists the causes found (keys of :data:`CAUSES`, in that order),
        ``warning_messages`` maps each to its message and ``warnings`` lists the messages.
    """
    hardness = _checked_hardness(hardness)
    if theory is None and psd is not None:
        theory = PerssonTheory(psd, result.E_star)
    if psd is None and theory is not None:
        psd = theory.psd
    out, msgs = _checks(result, theory, psd, hardness)
    _list_causes(out, msgs, result, warn, stacklevel + 1)
    return out


def _checked_hardness(hardness) -> float | None:
    """The indentation hardness in Pa as a float (None stays None); a TypeError or ValueError
    naming it otherwise."""
    if hardness is None:
        return None
    if isinstance(hardness, bool) or not isinstance(hardness, _REAL):
        raise TypeError(f"hardness must be a number in Pa, got {type(hardness).__name__}")
    hardness = float(hardness)
    if not math.isfinite(hardness) or hardness <= 0.0:
        raise ValueError(f"hardness must be a finite number > 0 Pa, got {hardness!r}")
    return hardness


def _checks(result, theory, psd, hardness) -> tuple[dict, dict[str, str]]:
    """Every check of :func:`assess`: the quantities found and the message of each cause."""
    out: dict = {"alpha": float(result.alpha), "regime": regime(result.alpha)}
    msgs: dict[str, str] = {}
    _half_space(out, result, msgs)
    _mean_field(out, result, psd, msgs)
    out["domain_half_width"] = _domain_half_width(result)
    _domain(out, result, msgs)
    _resolution(out, result, msgs)
    _asperities(out, result, theory, hardness, msgs)
    _exponential(out, result, theory, msgs)
    return out, msgs


def _list_causes(out: dict, msgs: dict[str, str], result, warn: bool, stacklevel: int) -> None:
    """The causes found, in the order of :data:`CAUSES`, into ``out``; one warning each if
    ``warn`` and the result has not warned of it yet (``stacklevel`` as
    :func:`warnings.warn` counts from here)."""
    causes = [c for c in CAUSES if c in msgs]
    out["warning_causes"] = causes
    out["warning_messages"] = {c: msgs[c] for c in causes}
    out["warnings"] = [msgs[c] for c in causes]
    told = result.__dict__.setdefault("_warned_causes", set())  # by the solve, or before
    for c in [c for c in causes if c not in told] if warn else ():
        told.add(c)
        warnings.warn(
            f"fastline: {_headline(c, result)}", ValidityWarning, stacklevel=stacklevel + 1
        )


def _headline(cause: str, result) -> str:
    """The warning a single solve emits for a cause: the same text for every scene, so that
    Python's warning filter shows it once in a loop of solves (the default action prints a
    text once per place); this scene's numbers are in ``diagnostics["warning_messages"]``."""
    point = getattr(result, "EXTENT_WORD", "half-width") == "radius"
    text = {
        "half_space": (
            f"the contact {'radius' if point else 'half-width'} exceeds "
            f"{100 * HALF_WIDTH_LIMIT:g}% of {'the sphere' if point else 'the cylinder'}'s "
            "radius R: the elastic half-space assumption is strained"
        ),
        "plastic": (
            "the elastic mean asperity pressure h'E*/2 exceeds the hardness: asperities likely "
            "deform plastically (the theory is elastic)"
        ),
        "exponential_range": (
            "model='exponential' is used outside its range: its u(p) is off by more than "
            f"{100 * EXPONENTIAL_RTOL:g}% over the pressures met; use model='persson'"
        ),
        "narrow_contact": (
            "the contact is narrower than the longest roughness wavelength 2 pi/q0: the "
            "theory's mean-field assumption (pressure varying slowly on that scale) is not met"
        ),
        "truncated_domain": (
            f"the pressure at the edge of the domain exceeds {EDGE_LIMIT:g} of p0: the domain "
            f"cuts off part of the contact; widen {_domain_parameter(result)} (None, the "
            "default, sizes it for each load)"
        ),
        "resolution": (
            f"the FWHM spans fewer than {RESOLUTION_CELLS:g} grid cells, or the contact's edge "
            f"fewer than {ROLLOFF_CELLS:g}: p0 and w/s are limited by the grid (errors of "
            f"percents); raise n or narrow {_domain_parameter(result)}"
        ),
    }[cause]
    return f"{text} (this scene's numbers: result.diagnostics['warning_messages'])"


def _loads_text(loads: list[float], total: int, symbol: str = "f_N", unit: str = "N/m") -> str:
    """``"f_N = 1e4 N/m"`` or ``"3 of 30 solves: f_N from 1e5 to 1.5e6 N/m"`` (``F`` and ``N``
    for a point contact)."""
    if total == 1:
        return f"{symbol} = {loads[0]:.4g} {unit}"
    distinct = sorted(set(loads))
    head = f"{len(loads)} of {total} solves: {symbol}"
    if len(distinct) <= 4:
        return f"{head} = {', '.join(f'{f:.4g}' for f in distinct)} {unit}"
    return f"{head} from {distinct[0]:.4g} to {distinct[-1]:.4g} {unit}"


def summarise_warnings(results: Iterable) -> list[tuple[str, str]]:
    """One ``(cause, message)`` per warning cause found in a list of results.

    Parameters
    ----------
    results : iterable of LineContactResult
        Solved scenes (their ``diagnostics`` hold :func:`assess`'s findings).

    Returns
    -------
    list of (str, str)
        In the order of :data:`CAUSES`. Each message is that of the worst result concerned (the
        smallest load for ``"narrow_contact"``, the largest for the others), followed by the
        loads concerned, e.g. ``"... [3 of 30 solves: f_N from 1e5 to 1.5e6 N/m]"``.
    """
    results = list(results)
    found: dict[str, list] = {}
    for r in results:
        d = r.diagnostics if hasattr(r, "diagnostics") else r
        for c in d.get("warning_causes", ()):
            found.setdefault(c, []).append(r)
    out = []
    for c in CAUSES:
        if c not in found:
            continue
        rs = sorted(found[c], key=lambda r: r.load)
        worst = rs[0] if c in _WORST_AT_SMALL_LOAD else rs[-1]
        msg = worst.diagnostics["warning_messages"][c]
        symbol = getattr(worst, "LOAD_SYMBOL", "f_N")
        unit = getattr(worst, "LOAD_UNIT", "N/m")
        loads = _loads_text([r.load for r in rs], len(results), symbol, unit)
        out.append((c, f"{msg} [{loads}]"))
    return out


def warn_once(results: Iterable, *, stacklevel: int = 1) -> list[str]:
    """Emit one :class:`ValidityWarning` per cause found in ``results``; returns the causes.

    Use after a loop of solves made with ``warn=False`` (a sweep over loads) so that each
    problem is reported once, naming the loads concerned, instead of once per solve.

    Parameters
    ----------
    results : iterable of LineContactResult
    stacklevel : int
        Where the warnings point: 1 the caller of ``warn_once``, 2 its caller, and so on.
    """
    summary = summarise_warnings(results)
    for _cause, msg in summary:
        warnings.warn(f"fastline: {msg}", ValidityWarning, stacklevel=stacklevel + 1)
    return [c for c, _ in summary]
