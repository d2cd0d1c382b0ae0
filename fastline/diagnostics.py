"""Validity diagnostics of a solved line contact (THEORY.md sections 5 and 7).

:func:`assess` looks at a :class:`~fastline.line_contact.LineContactResult` and tells the user which
regime the scene is in and whether the model assumptions hold:

* **regime** from ``alpha = h_rms / delta``: ``"Hertz-like"`` for alpha < 0.01,
  ``"Gaussian-like"`` for alpha > 10, ``"transition"`` in between (paper, section 3);
* for ``model="exponential"``: whether the nominal pressures met in the contact (from the peak
  ``p0`` down to ``1e-3 p0``) stay inside the range where the exponential law
  ``u = u0 ln(beta E* / p)`` (paper eq. 5) matches the full Persson ``u(p)`` to within 5 %;
* **elastic mean asperity pressure** ``h' E*/2`` (h' the rms slope, dimensionless; result in Pa)
  and the real contact area fraction at the peak pressure, ``P(q1, p0)``;
* a :class:`ValidityWarning` when a hardness is given and ``h' E*/2`` exceeds it (asperities
  likely flow plastically; the theory is purely elastic), and when the contact half-width
  exceeds 10 % of the cylinder radius (the half-space/small-strain assumption is strained).

SI units throughout: Pa, m, N/m.
"""

from __future__ import annotations

import functools
import math
import warnings

import numpy as np

__all__ = ["ValidityWarning", "assess", "regime", "HERTZ_LIKE_ALPHA", "GAUSSIAN_LIKE_ALPHA"]

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


class ValidityWarning(UserWarning):
    """A scene is outside the assumptions of the model (elasticity, half-space)."""


def regime(alpha: float) -> str:
    """``"Hertz-like"`` (alpha < 0.01), ``"Gaussian-like"`` (alpha > 10) or ``"transition"``."""
    if alpha < HERTZ_LIKE_ALPHA:
        return "Hertz-like"
    if alpha > GAUSSIAN_LIKE_ALPHA:
        return "Gaussian-like"
    return "transition"


@functools.lru_cache(maxsize=32)
def _law_valid_range(theory) -> tuple[float, float]:
    """(0, p_top) in Pa: where u0 ln(beta E*/p) is within 5 % of the full u(p).

    Depends on the theory only, so it is computed once per theory (400 direct evaluations over
    the table range; below it the law holds by construction, above it u -> 0 and it fails).
    """
    fit = theory.exponential_fit()
    lo, hi = theory.p_range
    p = np.logspace(math.log10(lo), math.log10(hi), 400)
    u_full = theory.separation(p)
    ok = np.abs(fit.u0 * np.log(fit.beta * theory.E_star / p) - u_full) <= (
        EXPONENTIAL_RTOL * u_full
    )
    # the law is the small-p asymptote: the valid range starts at the bottom of the grid and
    # ends at the first pressure where the mismatch exceeds the tolerance
    if not ok[0]:
        return (float("nan"), float("nan"))
    bad = np.nonzero(~ok)[0]
    return (0.0, float(p[bad[0] - 1] if bad.size else p[-1]))


def _exponential_validity(theory, fit, p_lo_met: float, p_hi_met: float) -> dict:
    """The law's valid range and a direct check on the pressures the contact meets."""
    pm = np.logspace(math.log10(p_lo_met), math.log10(p_hi_met), 60)
    um = theory.separation(pm)
    err = np.abs(fit.u0 * np.log(fit.beta * theory.E_star / pm) - um) / um
    return {
        "exponential_valid": bool(np.all(err <= EXPONENTIAL_RTOL)),
        "exponential_valid_range": _law_valid_range(theory),
        "exponential_max_error": float(err.max()),
        "pressure_range_met": (float(p_lo_met), float(p_hi_met)),
    }


def assess(result, theory=None, hardness=None, *, psd=None, warn=True) -> dict:
    """Regime and validity checks of a solved line contact.

    Parameters
    ----------
    result : LineContactResult
        A solve from :func:`fastline.line_contact.solve_line_contact`.
    theory : PerssonTheory, optional
        The theory the scene was solved with (needed for the rms slope, the real contact area
        and the exponential-law check). If omitted and ``psd`` is given, one is built.
    hardness : float, optional
        Indentation hardness of the softer solid in Pa. When the elastic mean asperity pressure
        ``h' E*/2`` exceeds it a :class:`ValidityWarning` is emitted.
    psd : PSD, optional
        The roughness spectrum, used only when ``theory`` is not given.
    warn : bool
        Emit the :class:`ValidityWarning` s (they are listed in the result either way).

    Returns
    -------
    dict
        ``regime`` (str), ``alpha`` (-), ``half_width`` (m; max of FWHM/2 and the Hertz a),
        ``half_width_over_radius`` (-), ``rms_slope`` (-), ``asperity_pressure`` (Pa,
        ``h' E*/2``), ``real_area_at_peak`` (-, ``P(q1, p0)``), ``plastic_likely`` (bool or
        None), ``half_space_ok`` (bool), and for ``model="exponential"``
        ``exponential_valid`` (bool), ``exponential_valid_range`` ((p_min, p_max) in Pa where the
        law is within 5 % in u; p_min is 0 since the law is the low-pressure asymptote),
        ``exponential_max_error`` (relative, over the pressures met) and ``pressure_range_met``
        ((1e-3 p0, p0) in Pa). Quantities that cannot be computed (no theory, Hertz model) are
        None. ``warnings`` lists the warning messages issued.
    """
    from fastline.limits import hertz_line_contact

    if hardness is not None:
        hardness = float(hardness)
        if not math.isfinite(hardness) or hardness <= 0.0:
            raise ValueError(f"hardness must be a finite number > 0 Pa, got {hardness!r}")
    if theory is None and psd is not None:
        from fastline.persson import PerssonTheory

        theory = PerssonTheory(psd, result.E_star)

    out: dict = {"alpha": float(result.alpha), "regime": regime(result.alpha)}
    msgs: list[str] = []

    a_hertz = hertz_line_contact(result.E_star, result.radius, result.load).a
    half = a_hertz
    if math.isfinite(result.fwhm):
        half = max(half, 0.5 * result.fwhm)
    out["half_width"] = float(half)
    out["half_width_over_radius"] = float(half / result.radius)
    out["half_space_ok"] = bool(half <= HALF_WIDTH_LIMIT * result.radius)
    if not out["half_space_ok"]:
        msgs.append(
            f"contact half-width {half:.3g} m is {100 * half / result.radius:.3g}% of the radius "
            f"R = {result.radius:.3g} m (> {100 * HALF_WIDTH_LIMIT:g}%): the elastic half-space "
            "assumption is strained"
        )

    if theory is not None:
        slope = float(theory.psd.rms_slope)
        p_asp = 0.5 * slope * result.E_star
        out["rms_slope"] = slope
        out["asperity_pressure"] = p_asp
        out["real_area_at_peak"] = float(np.ravel(theory.contact_area([result.p0]))[0])
        if hardness is not None:
            out["plastic_likely"] = bool(p_asp > hardness)
            if p_asp > hardness:
                msgs.append(
                    f"elastic mean asperity pressure h'E*/2 = {p_asp:.3g} Pa exceeds the hardness "
                    f"{hardness:.3g} Pa: asperities likely deform plastically (the theory is "
                    "elastic)"
                )
        else:
            out["plastic_likely"] = None
    else:
        out["rms_slope"] = out["asperity_pressure"] = out["real_area_at_peak"] = None
        out["plastic_likely"] = None

    if result.model == "exponential" and theory is not None:
        out.update(
            _exponential_validity(
                theory, theory.exponential_fit(), PRESSURE_FLOOR * result.p0, result.p0
            )
        )

    for m in msgs if warn else ():
        warnings.warn(f"fastline: {m}", ValidityWarning, stacklevel=3)
    out["warnings"] = msgs
    return out
