"""Theory against the BEM ensemble, in units of the BEM's error bar.

:func:`compare_line_contact` takes a line-contact solution of the theory (anything with the
attributes ``x``, ``pressure``, ``p0``, ``s``, ``fwhm`` and ``load`` of
:class:`fastline.LineContactResult`) and a cylinder :class:`~fastline.bem.ProfileEnsemble`
of the same scene, and returns for ``p0``, ``s``, ``w`` (FWHM) and ``w/s`` the difference
theory - BEM, relative and in BEM standard errors (``z``), and for the profile the theory's
pressure averaged over the BEM's bins against ``p_bar(x)`` in the core of the contact.
:func:`compare_point_contact` does the same for a sphere (a
:class:`fastline.PointContactResult`, attributes ``r`` instead of ``x``) against the BEM's
ring-averaged ``p_bar(r)``: the theory's p(r) is sampled at the BEM's cell centres and
averaged over the same rings.
``|z| <= 2`` is agreement within the BEM's error bars at about 95 % (the error bars are
standard errors over realisations; the theory's own numerical error, ~1e-6, is neglected).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from fastline._lib.validate import finite_array, positive
from fastline.bem.ensemble import ProfileEnsemble
from fastline.bem.scene import ring_index

__all__ = [
    "Difference",
    "ProfileComparison",
    "LineComparison",
    "PointComparison",
    "compare_line_contact",
    "compare_point_contact",
]

_SUBSAMPLES = 16  # midpoint rule per bin for the theory's bin averages
#: Bins with p_bar below this fraction of the BEM's p0 get no z: there a few contact spots in a
#: few realisations carry the pressure and the standard error is itself unreliable (measured:
#: |z| up to 64 in bins where one realisation of eight touched).
CORE_FRACTION = 0.1


@dataclass(frozen=True)
class Difference:
    """One scalar, theory against BEM.

    Attributes
    ----------
    theory, bem, bem_error : float
        The two values and the BEM's standard error (same unit).
    difference : float
        ``theory - bem``.
    relative : float
        ``theory / bem - 1``.
    z : float
        ``difference / bem_error`` (NaN without an error bar).
    """

    theory: float
    bem: float
    bem_error: float
    difference: float
    relative: float
    z: float


def _difference(theory, bem, error):
    diff = theory - bem
    z = diff / error if error > 0.0 and math.isfinite(error) else math.nan
    return Difference(float(theory), float(bem), float(error), diff, theory / bem - 1.0, z)


@dataclass(frozen=True)
class ProfileComparison:
    """Theory vs BEM for a cylinder or a sphere (:class:`LineComparison`,
    :class:`PointComparison`).

    Attributes
    ----------
    p0, s, fwhm, w_over_s : Difference
    coordinate : ndarray
        BEM bin centres x [m] (cylinder) or mean ring radii r [m] (sphere).
    theory_pressure : ndarray
        The theory's pressure averaged over each BEM bin or ring [Pa].
    bem_pressure, bem_pressure_error : ndarray
        ``p_bar`` and its standard error [Pa].
    z_profile : ndarray
        ``(theory - bem) / error`` per bin of the core, ``p_bar >= CORE_FRACTION * p0`` (NaN
        outside it and where the error is 0).
    chi2_per_bin : float
        Mean of ``z_profile^2`` over the core bins.
    max_abs_z : float
        Largest ``|z_profile|``.
    alpha : float
        The scene's ``h_rms / delta``.
    realizations : int
    """

    p0: Difference
    s: Difference
    fwhm: Difference
    w_over_s: Difference
    coordinate: np.ndarray = field(repr=False)
    theory_pressure: np.ndarray = field(repr=False)
    bem_pressure: np.ndarray = field(repr=False)
    bem_pressure_error: np.ndarray = field(repr=False)
    z_profile: np.ndarray = field(repr=False)
    chi2_per_bin: float
    max_abs_z: float
    alpha: float
    realizations: int

    def table(self) -> str:
        """A plain-text table of the four scalars (what ``fastline validate`` prints)."""
        rows = [f"{'':>6} {'theory':>12} {'BEM':>12} {'+-':>10} {'rel.':>8} {'z':>6}"]
        for name in ("p0", "s", "fwhm", "w_over_s"):
            d = getattr(self, name)
            rows.append(
                f"{name:>6} {d.theory:12.5g} {d.bem:12.5g} {d.bem_error:10.2g} "
                f"{100 * d.relative:+7.2f}% {d.z:+6.2f}"
            )
        rows.append(f"profile: chi2/bin {self.chi2_per_bin:.2f}, max |z| {self.max_abs_z:.2f}")
        return "\n".join(rows)


@dataclass(frozen=True)
class LineComparison(ProfileComparison):
    """Theory vs BEM for a cylinder (:func:`compare_line_contact`); ``coordinate`` is x."""

    @property
    def x(self) -> np.ndarray:
        """BEM bin centres [m]."""
        return self.coordinate


@dataclass(frozen=True)
class PointComparison(ProfileComparison):
    """Theory vs BEM for a sphere (:func:`compare_point_contact`); ``coordinate`` is r."""

    @property
    def r(self) -> np.ndarray:
        """Mean radius of each BEM ring [m]."""
        return self.coordinate


def _bin_average(x, p, centres, width):
    """Mean of the linear interpolant of ``p(x)`` (0 outside) over each bin."""
    offsets = ((np.arange(_SUBSAMPLES) + 0.5) / _SUBSAMPLES - 0.5) * width
    points = centres[:, None] + offsets[None, :]
    return np.interp(points, x, p, left=0.0, right=0.0).mean(axis=1)


def _ring_average(r, p, ensemble):
    """The BEM's ring average applied to the theory's p(r) (linear interpolation, 0 outside)
    sampled at the BEM's cell centres."""
    scene = ensemble.scene
    grid = scene.grid
    idx, _, count = ring_index(scene, max(1, int(round(ensemble.bin_width / grid.dx))))
    radius = np.hypot(grid.x[:, None], grid.y[None, :])
    sampled = np.interp(radius.ravel(), r, p, right=0.0)
    sums = np.bincount(idx.ravel(), weights=sampled, minlength=count.size + 1)
    return sums[: count.size] / count


def _checked_theory(theory, ensemble, geometry, coordinate, unit):
    """(coordinate, pressure, load) of a theory result, checked against the ensemble."""
    if not isinstance(ensemble, ProfileEnsemble) or ensemble.geometry != geometry:
        raise TypeError(
            f"ensemble must be a {geometry} ProfileEnsemble (fastline.bem.run_ensemble)"
        )
    names = (coordinate, "pressure", "p0", "s", "fwhm", "load")
    missing = [a for a in names if not hasattr(theory, a)]
    if missing:
        kind = "LineContactResult" if geometry == "cylinder" else "PointContactResult"
        raise TypeError(f"theory must be a {kind}-like object; missing {missing}")
    x = finite_array(f"theory.{coordinate}", getattr(theory, coordinate), ndim=1)
    p = finite_array("theory.pressure", theory.pressure, ndim=1)
    if x.shape != p.shape or x.size < 2 or np.any(np.diff(x) <= 0.0):
        raise ValueError(
            f"theory.{coordinate} must be increasing and match theory.pressure in length"
        )
    load = positive("theory.load", theory.load, unit)
    if abs(load / ensemble.scene.load - 1.0) > 1e-9:
        raise ValueError(
            f"theory.load = {load!r} {unit} differs from the ensemble's "
            f"{ensemble.scene.load!r} {unit}"
        )
    return x, p


def _compare(cls, theory, ensemble, p_th):
    """The scalars and the profile's z in the core of the contact."""
    err = ensemble.pressure_error
    core = ensemble.pressure >= CORE_FRACTION * ensemble.p0
    has_error = core & np.isfinite(err) & (err > 0.0)
    z = np.full(p_th.size, np.nan)
    z[has_error] = (p_th[has_error] - ensemble.pressure[has_error]) / err[has_error]
    zz = z[has_error]
    p0, s, w = float(theory.p0), float(theory.s), float(theory.fwhm)
    return cls(
        p0=_difference(p0, ensemble.p0, ensemble.p0_error),
        s=_difference(s, ensemble.s, ensemble.s_error),
        fwhm=_difference(w, ensemble.fwhm, ensemble.fwhm_error),
        w_over_s=_difference(w / s, ensemble.w_over_s, ensemble.w_over_s_error),
        coordinate=ensemble.coordinate,
        theory_pressure=p_th,
        bem_pressure=ensemble.pressure,
        bem_pressure_error=err,
        z_profile=z,
        chi2_per_bin=float(np.mean(zz * zz)) if zz.size else math.nan,
        max_abs_z=float(np.max(np.abs(zz))) if zz.size else math.nan,
        alpha=ensemble.alpha,
        realizations=ensemble.realizations,
    )


def compare_line_contact(theory: Any, ensemble: ProfileEnsemble) -> LineComparison:
    """Compare a theory line-contact solution with a cylinder BEM ensemble.

    Parameters
    ----------
    theory : LineContactResult or compatible
        Needs ``x`` [m] (increasing), ``pressure`` [Pa], ``p0`` [Pa], ``s`` [m], ``fwhm`` [m]
        and ``load`` [N/m]; its load must equal the ensemble's (relative 1e-9).
    ensemble : ProfileEnsemble
        A cylinder ensemble (:func:`~fastline.bem.run_ensemble`), >= 2 realisations for
        error bars.

    Returns
    -------
    LineComparison
    """
    x, p = _checked_theory(theory, ensemble, "cylinder", "x", "N/m")
    centres = ensemble.coordinate
    return _compare(
        LineComparison, theory, ensemble, _bin_average(x, p, centres, ensemble.bin_width)
    )


def compare_point_contact(theory: Any, ensemble: ProfileEnsemble) -> PointComparison:
    """Compare a theory point-contact solution with a sphere BEM ensemble.

    Parameters
    ----------
    theory : PointContactResult or compatible
        Needs ``r`` [m] (increasing from the axis), ``pressure`` [Pa], ``p0`` [Pa], ``s`` [m]
        (``s^2 = int r^2 p dA / 2F``), ``fwhm`` [m] (along a diameter) and ``load`` [N]; its
        load must equal the ensemble's (relative 1e-9).
    ensemble : ProfileEnsemble
        A sphere ensemble (:func:`~fastline.bem.run_ensemble` of
        :func:`~fastline.bem.point_contact_scene`), >= 2 realisations for error bars.

    Returns
    -------
    PointComparison
        ``theory_pressure`` is the theory's p(r) averaged over the BEM's rings.
    """
    r, p = _checked_theory(theory, ensemble, "sphere", "r", "N")
    return _compare(PointComparison, theory, ensemble, _ring_average(r, p, ensemble))
