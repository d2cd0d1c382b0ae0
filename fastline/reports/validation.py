"""The theory against a boundary-element simulation of the user's own surface.

:func:`validate_line_contact` runs the BEM ensemble of a cylinder on a random surface of the given
spectrum (:func:`fastline.bem.run_ensemble`) and solves the same scene with each pressure law
asked for (the variants of :mod:`fastline.theory.variants`, the Greenwood-Williamson law of
:mod:`fastline.theory.asperity`); :func:`fastline.bem.compare_line_contact` gives each law's p0,
s, w and w/s and its profile against the BEM in units of the BEM's error bar.

:func:`validate_point_contact` does the same for a sphere: the BEM's ring-averaged nominal
pressure p_bar(r) against the theory's p(r) (:class:`fastline.PointContact`,
:func:`fastline.bem.compare_point_contact`), with the same statistics (p0, s with
``s^2 = int r^2 p dA / 2F``, the FWHM along a diameter and w/s).

:func:`validate_flat_contact` does the same for a nominally flat interface under uniform
pressures (the building block of a seal): the BEM contact fraction, mean gap and Reynolds
effective gap (:mod:`fastline.bem.flow`) against the theory's real contact area ``P(q1, p)``,
mean separation ``u(p)`` and critical-junction gap ``u_c`` (:mod:`fastline.leakage.flow`).

The BEM realisations are independent: ``executor=`` and ``workers=`` run them where
:func:`fastline.sweep` runs its tasks (a local process pool, a dask scheduler address or Client,
any :class:`concurrent.futures.Executor`; :func:`fastline.bem.run_ensemble`). ``fastline
validate`` is the command line of both.

Each function also takes a pressure law object (``law=``, e.g. a :class:`fastline.CalibratedLaw`
of the same spectrum and E*), compared beside the named models under its ``name``; the tables
end with the law closest to the BEM (:meth:`ProfileValidation.closeness`: the mean |z| of p0, s
and w/s; :meth:`FlatValidation.leak_closeness`: the leak-rate ratio of the hydraulic gaps).
"""

from __future__ import annotations

import math
import time
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, cast

import numpy as np
from numpy.typing import ArrayLike

from fastline import bem
from fastline._lib.validate import integer, positive, positive_array
from fastline.bem.compare import Difference, compare_line_contact, compare_point_contact
from fastline.contact.line import LineContact
from fastline.contact.point import PointContact
from fastline.theory.asperity import GreenwoodWilliamsonLaw
from fastline.theory.calibrated import CalibratedLaw
from fastline.theory.laws import PerssonLaw, PressureLaw
from fastline.theory.persson import PerssonTheory
from fastline.theory.spectra import PSD
from fastline.theory.variants import DEFAULT_VARIANT, VARIANTS

if TYPE_CHECKING:
    from fastline.bem.ensemble import ExecutorLike
    from fastline.theory.variants import VariantName

__all__ = [
    "MODELS",
    "ProfileValidation",
    "LineValidation",
    "PointValidation",
    "FlatValidation",
    "validate_line_contact",
    "validate_point_contact",
    "validate_flat_contact",
    "law_of",
]

GW = "greenwood-williamson"
#: fewest BEM realisations: every difference is in units of their standard error (one has none)
MIN_REALIZATIONS = 2
#: fewest realisations for the table's profile chi2/bin: below, the mean of z^2 over the bins
#: does not exist (each z is Student-t with n - 1 <= 2 degrees of freedom; 2 realisations gave
#: chi2/bin 8.5-320 where the profiles agree within their band)
MIN_CHI2_REALIZATIONS = 4
#: the laws a validation can compare: the variants of the Persson theory and the GW law
MODELS = (*VARIANTS, GW)
#: the critical-junction thresholds compared in a flat validation (Persson; Bruggeman)
THRESHOLDS = (0.42, 0.5)


def _check_models(models) -> tuple[str, ...]:
    if isinstance(models, str):
        models = (models,)
    models = tuple(models)
    if not models:
        raise ValueError(f"models must name at least one of {MODELS}")
    for m in models:
        if m not in MODELS:
            raise ValueError(f"models must be among {MODELS}, got {m!r}")
    return models


def law_of(
    model: str, psd: PSD, E_star: float, gamma: float | None = None
) -> PerssonLaw | GreenwoodWilliamsonLaw:
    """The pressure law called ``model`` (an entry of :data:`MODELS`) for a spectrum and E*;
    gamma (None: the variant's own) applies to the Persson variants."""
    _check_models(model)
    if model == GW:
        return GreenwoodWilliamsonLaw.from_psd(psd, E_star)
    variant = cast("VariantName", model)  # checked above: one of VARIANTS
    return PerssonLaw(PerssonTheory(psd, E_star, gamma=gamma, variant=variant))


def _difference(theory, bem_value, error) -> Difference:
    diff = theory - bem_value
    z = diff / error if error > 0.0 and math.isfinite(error) else math.nan
    rel = theory / bem_value - 1.0 if bem_value != 0.0 else math.nan
    return Difference(float(theory), float(bem_value), float(error), diff, rel, z)


# ----------------------------------------------------------------------------------------------
# cylinder and sphere
# ----------------------------------------------------------------------------------------------
@dataclass(frozen=True)
class ProfileValidation:
    """Theory against BEM for one cylinder or sphere scene (:class:`LineValidation`,
    :class:`PointValidation`).

    Attributes
    ----------
    ensemble : fastline.bem.ProfileEnsemble
        The BEM ensemble (p_bar with error bars, p0, s, w, w/s).
    results : dict
        Model name -> the theory's :class:`fastline.LineContactResult` (cylinder) or
        :class:`fastline.PointContactResult` (sphere).
    comparisons : dict
        Model name -> :class:`fastline.bem.LineComparison` or
        :class:`fastline.bem.PointComparison`.
    seconds_bem, seconds_theory : float
        Wall times [s].
    """

    ensemble: bem.ProfileEnsemble = field(repr=False)
    results: dict = field(repr=False)
    comparisons: dict = field(repr=False)
    seconds_bem: float
    seconds_theory: float

    @property
    def alpha(self) -> float:
        """``h_rms / delta`` of the scene."""
        return self.ensemble.alpha

    @property
    def geometry(self) -> str:
        """``"cylinder"`` or ``"sphere"``."""
        return self.ensemble.geometry

    def closeness(self) -> dict[str, float]:
        """Law name -> mean |z| of p0, s and w/s against the BEM (the z that are finite; NaN
        when none is)."""
        out = {}
        for name, c in self.comparisons.items():
            z = np.abs([c.p0.z, c.s.z, c.w_over_s.z])
            out[name] = float(np.mean(z[np.isfinite(z)])) if np.isfinite(z).any() else math.nan
        return out

    @property
    def closest(self) -> str | None:
        """The law with the smallest mean |z| (:meth:`closeness`); None when no z is finite."""
        return _closest(self.closeness())

    def table(self) -> str:
        """Plain text: BEM values with standard errors, then each law's values and their
        difference from the BEM (relative, and z in BEM standard errors); columns at least two
        spaces apart whatever the widths of the values; the profile's chi2/bin (``n/a`` below
        :data:`MIN_CHI2_REALIZATIONS` realisations; with the theory right it averages
        (n - 1)/(n - 3), 1.4 for 8) and the mean |z| of p0, s and w/s; with two laws or more a
        line ``closest to the BEM: ...`` (:attr:`closest`); a last line ``warning: ...`` when
        the contact is too narrow to compare widths (``ensemble.narrow``)."""
        e = self.ensemble
        head = ["", "p0/p0_Hertz", "s [m]", "w/s", "profile chi2/bin", "mean |z|"]
        closeness = self.closeness()
        rows = [
            [
                "BEM",
                _pm(e.p0_ratio, e.p0_ratio_error),
                _pm(e.s, e.s_error),
                _pm(e.w_over_s, e.w_over_s_error),
                "",
                "",
            ]
        ]
        for name, c in self.comparisons.items():
            rows.append(
                [
                    name,
                    _vz(self.results[name].p0_ratio, c.p0),
                    _vz(c.s.theory, c.s),
                    _vz(c.w_over_s.theory, c.w_over_s),
                    _chi2_cell(c.chi2_per_bin, e.realizations),
                    f"{closeness[name]:.2g}",
                ]
            )
        table = _columns([head, *rows])
        if len(closeness) > 1 and self.closest is not None:
            table += "\n" + _closest_line(closeness, "mean |z| of p0, s, w/s")
        if e.narrow:
            table += f"\nwarning: {e.narrow}"
        return table


@dataclass(frozen=True)
class LineValidation(ProfileValidation):
    """Theory against BEM for a cylinder (:func:`validate_line_contact`): p_bar(x) averaged
    along the axis; attributes as :class:`ProfileValidation`."""


@dataclass(frozen=True)
class PointValidation(ProfileValidation):
    """Theory against BEM for a sphere (:func:`validate_point_contact`): p_bar(r) averaged
    over rings about the axis; attributes as :class:`ProfileValidation`."""


def _columns(rows: list[list[str]], gap: int = 2) -> str:
    """Rows of cells as text: the first column left-aligned, the others right-aligned, each
    as wide as its widest cell, columns ``gap`` spaces apart."""
    widths = [max(len(r[k]) for r in rows) for k in range(len(rows[0]))]
    lines = []
    for r in rows:
        cells = [r[0].ljust(widths[0])] + [
            c.rjust(w) for c, w in zip(r[1:], widths[1:], strict=True)
        ]
        lines.append((" " * gap).join(cells).rstrip())
    return "\n".join(lines)


def _closest(measure: dict[str, float]) -> str | None:
    """The name of the smallest finite value of ``measure`` (None when there is none)."""
    finite = {k: v for k, v in measure.items() if math.isfinite(v)}
    return min(finite, key=finite.__getitem__) if finite else None


def _closest_line(measure: dict[str, float], what: str, head: str = "closest to the BEM") -> str:
    """``HEAD: NAME (WHAT V; then NAME2 V2, ...)``, by increasing value."""
    ranked = sorted((v, k) for k, v in measure.items() if math.isfinite(v))
    rest = "; then " + ", ".join(f"{k} {v:.3g}" for v, k in ranked[1:]) if ranked[1:] else ""
    return f"{head}: {ranked[0][1]} ({what} {ranked[0][0]:.3g}{rest})"


def _chi2_cell(chi2: float, realizations: int) -> str:
    """The profile's chi2/bin, or ``n/a`` below :data:`MIN_CHI2_REALIZATIONS` (with n
    realisations each bin's z is Student-t with n - 1 degrees of freedom, whose z^2 has the
    mean (n - 1)/(n - 3) for n > 3 and none for n <= 3)."""
    return f"{chi2:.3g}" if realizations >= MIN_CHI2_REALIZATIONS else "n/a"


def _pm(value: float, error: float) -> str:
    return f"{value:.4g} +- {error:.2g}"


def _vz(value: float, d: Difference) -> str:
    """Value, relative difference and z."""
    return f"{value:.4g} ({100 * d.relative:+.1f}%, z {d.z:+.1f})"


def validate_line_contact(
    psd: PSD,
    E_star: float,
    radius: float,
    load: float,
    *,
    models: Sequence[str] = (DEFAULT_VARIANT,),
    gamma: float | None = None,
    law: PressureLaw | None = None,
    realizations: int = 8,
    seed: int = 0,
    executor: ExecutorLike = None,
    workers: int | None = None,
    points_per_wavelength: float = 4.0,
    periods: float = 2.0,
    n: int = 1024,
    scene: bem.Scene | None = None,
    progress: bool | None = None,
) -> LineValidation:
    """BEM ensemble of a rough cylinder against the theory's p(x) for each model.

    Parameters
    ----------
    psd, E_star, radius, load
        Spectrum (m^4 vs 1/m), effective modulus [Pa], radius [m], load per length [N/m].
    models, gamma, law
        Laws to compare, from :data:`MODELS` (default the default variant), the gamma of the
        Persson variants (default: each variant's own), and a law object of the same spectrum
        and E* (e.g. :class:`fastline.CalibratedLaw`), compared under its ``name``.
    realizations, seed : int
        BEM surfaces (>= 2: the error bars) and root seed (:func:`fastline.bem.run_ensemble`).
    executor, workers, progress
        Where the realisations run (as for :func:`fastline.sweep`: a dask scheduler address or
        Client, any executor; default this process; ``workers``: a local pool of that many
        processes) and a progress bar on stderr (None: on a terminal only), as for
        :func:`fastline.bem.run_ensemble`.
    points_per_wavelength, periods, n, scene
        BEM grid (:func:`fastline.bem.line_contact_scene`); theory grid points; a prebuilt BEM
        scene (then the grid options are ignored).

    Returns
    -------
    LineValidation

    Warns
    -----
    fastline.NarrowContactWarning
        When the BEM contact is too narrow to compare widths (``ensemble.narrow``).
    """
    models = _check_inputs(psd, models, realizations, seed, law, E_star)
    if scene is None:
        grid = {"points_per_wavelength": points_per_wavelength, "periods": periods}
        scene = bem.line_contact_scene(psd, E_star, radius, load, **grid)
    elif not isinstance(scene, bem.Scene) or scene.geometry != "cylinder":
        raise ValueError("scene must be a cylinder scene (fastline.bem.line_contact_scene)")
    laws = _laws(models, psd, E_star, gamma, law)
    results, seconds_theory = _theory_results(LineContact, psd, E_star, radius, load, laws, n)
    ensemble, seconds_bem = _bem_ensemble(scene, realizations, seed, executor, workers, progress)
    comparisons = {m: compare_line_contact(r, ensemble) for m, r in results.items()}
    return LineValidation(ensemble, results, comparisons, seconds_bem, seconds_theory)


def validate_point_contact(
    psd: PSD,
    E_star: float,
    radius: float,
    load: float,
    *,
    models: Sequence[str] = (DEFAULT_VARIANT,),
    gamma: float | None = None,
    law: PressureLaw | None = None,
    realizations: int = 8,
    seed: int = 0,
    executor: ExecutorLike = None,
    workers: int | None = None,
    points_per_wavelength: float = 4.0,
    n: int = 512,
    scene: bem.Scene | None = None,
    progress: bool | None = None,
) -> PointValidation:
    """BEM ensemble of a rough sphere against the theory's p(r) for each model.

    The BEM's nominal pressure ``p_bar(r)`` is the pressure averaged over rings about the
    sphere's axis (``Scene.bin_width``, default from the contact's width:
    :func:`fastline.bem.run_ensemble`) and over
    realisations; p0, s (``s^2 = int r^2 p dA / 2F``), the FWHM along a diameter and w/s as
    for the theory (docs/sphere.md; :func:`fastline.bem.run_ensemble`).

    Parameters
    ----------
    psd : PSD
        Roughness spectrum (m^4 vs 1/m).
    E_star, radius, load : float
        Effective modulus [Pa], sphere radius [m], normal force on the sphere [N].
    models, gamma, law, realizations, seed, executor, workers, progress
        As :func:`validate_line_contact` (which also names the warning).
    points_per_wavelength : float
        BEM cells per shortest wavelength ``2 pi / q1`` (>= 2;
        :func:`fastline.bem.point_contact_scene`: an isolated square patch four contact widths
        on a side).
    n : int
        Theory cells from the axis (:class:`fastline.PointContact`, default 512).
    scene : fastline.bem.Scene, optional
        A prebuilt sphere scene (then ``points_per_wavelength`` is ignored).

    Returns
    -------
    PointValidation
    """
    models = _check_inputs(psd, models, realizations, seed, law, E_star)
    if scene is None:
        scene = bem.point_contact_scene(
            psd, E_star, radius, load, points_per_wavelength=points_per_wavelength
        )
    elif not isinstance(scene, bem.Scene) or scene.geometry != "sphere":
        raise ValueError("scene must be a sphere scene (fastline.bem.point_contact_scene)")
    laws = _laws(models, psd, E_star, gamma, law)
    results, seconds_theory = _theory_results(PointContact, psd, E_star, radius, load, laws, n)
    ensemble, seconds_bem = _bem_ensemble(scene, realizations, seed, executor, workers, progress)
    comparisons = {m: compare_point_contact(r, ensemble) for m, r in results.items()}
    return PointValidation(ensemble, results, comparisons, seconds_bem, seconds_theory)


def _check_inputs(psd, models, realizations, seed, law=None, E_star=None) -> tuple[str, ...]:
    """The checks shared by the cylinder, the sphere and the flat contact, before any work;
    the models."""
    if not isinstance(psd, PSD):
        raise TypeError(f"psd must be a fastline PSD, got {type(psd).__name__}")
    _check_ensemble(realizations, seed)
    models = _check_models(models)
    _check_law(law, models, E_star)
    return models


def _check_law(law, models, E_star) -> None:
    """``law``: None or a pressure law whose name is not among ``models``; a calibrated law
    made for the scene's E* (its spectrum is the caller's to match: ``CalibratedLaw.load``)."""
    if law is None:
        return
    if not isinstance(law, PressureLaw):
        raise TypeError(f"law must be a fastline PressureLaw, got {type(law).__name__}")
    if law.name in models:
        raise ValueError(f"law is named {law.name!r}, as one of models: give it another name")
    if isinstance(law, CalibratedLaw) and E_star is not None:
        E = positive("E_star", E_star, "Pa")
        if not math.isclose(law.E_star, E, rel_tol=1e-6):
            raise ValueError(
                f"law was calibrated for E* = {law.E_star:.6g} Pa, the scene has {E:.6g} Pa"
            )


def _laws(models, psd, E_star, gamma, law) -> dict:
    """Name -> pressure law: each model's, then ``law`` (if any) under its name."""
    laws = {m: law_of(m, psd, E_star, gamma) for m in models}
    if law is not None:
        laws[law.name] = law
    return laws


def _check_ensemble(realizations, seed) -> None:
    """At least ``MIN_REALIZATIONS`` BEM realisations and a seed."""
    integer("realizations", realizations, MIN_REALIZATIONS, why=" (the error bars need them)")
    if not isinstance(seed, np.random.SeedSequence):
        integer("seed", seed, 0)


def _theory_results(contact, psd, E_star, radius, load, laws, n):
    """({name: result}, seconds): the scene solved by ``contact`` (LineContact or
    PointContact) with each law of ``laws`` (name -> law)."""
    t0 = time.perf_counter()
    results = {}
    for name, law in laws.items():
        results[name] = contact(psd, E_star, radius, model=law, n=n, warn=False).solve(load)
    return results, time.perf_counter() - t0


def _bem_ensemble(scene, realizations, seed, executor, workers, progress):
    """(ProfileEnsemble, seconds) of ``realizations`` surfaces."""
    t0 = time.perf_counter()
    ensemble = cast(
        bem.ProfileEnsemble,
        bem.run_ensemble(
            scene, realizations, seed, executor=executor, workers=workers, progress=progress
        ),
    )
    return ensemble, time.perf_counter() - t0


# ----------------------------------------------------------------------------------------------
# flat contact (the seal's building block)
# ----------------------------------------------------------------------------------------------
@dataclass(frozen=True)
class FlatValidation:
    """Theory against BEM for a nominally flat contact (:func:`validate_flat_contact`).

    Attributes
    ----------
    pressures : ndarray
        Nominal pressures [Pa].
    ensembles : list of fastline.bem.FlatEnsemble
        One per pressure.
    area, separation : dict
        Model name -> list (per pressure) of :class:`fastline.bem.Difference`: the real contact
        area fraction against the BEM contact fraction, u(p) [m] against the BEM mean gap.
    critical_gap : dict
        Threshold -> list of Difference: ``u_c`` of the first Persson variant in ``models`` [m]
        against the BEM effective (Reynolds) gap; 0 where the theory says sealed.
    model : str
        The Persson variant of ``critical_gap``.
    laws : dict
        Model name -> pressure law (for curves between the pressures); a law given as
        ``law=`` under its name, last.
    seconds_bem : float
    hydraulic_gap : list
        Differences of the hydraulic gap ``g(p)`` of a calibrated ``law=`` [m] against the
        BEM effective gap, one per pressure (empty without a calibrated law).
    """

    pressures: np.ndarray
    ensembles: list = field(repr=False)
    area: dict = field(repr=False)
    separation: dict = field(repr=False)
    critical_gap: dict = field(repr=False)
    model: str
    laws: dict = field(repr=False)
    seconds_bem: float
    hydraulic_gap: list = field(default_factory=list, repr=False)

    def closeness(self) -> dict[str, float]:
        """Law name -> mean |z| of u(p) against the BEM mean gap over the pressures."""
        out = {}
        for name, diffs in self.separation.items():
            z = np.abs([d.z for d in diffs])
            out[name] = float(np.mean(z[np.isfinite(z)])) if np.isfinite(z).any() else math.nan
        return out

    def leak_closeness(self) -> dict[str, float]:
        """Leak gap -> its typical leak-rate factor against the BEM: ``exp(mean |3 ln(g /
        g_BEM)|)`` over the pressures where both gaps are open (1: the BEM's leak rate; 1.3:
        30 % off either way). The gaps: ``u_c`` of each threshold (named ``u_c (MODEL,
        threshold T)``) and the hydraulic gap of a calibrated law (named as the law)."""
        gaps = {f"u_c ({self.model}, threshold {t:g})": d for t, d in self.critical_gap.items()}
        if self.hydraulic_gap:
            gaps[list(self.laws)[-1]] = self.hydraulic_gap
        out = {}
        for name, diffs in gaps.items():
            r = np.array([d.theory / d.bem if d.bem > 0.0 else math.nan for d in diffs])
            ok = np.isfinite(r) & (r > 0.0)
            out[name] = (
                float(np.exp(np.mean(np.abs(3.0 * np.log(r[ok]))))) if ok.any() else math.nan
            )
        return out

    def table(self) -> str:
        """Plain text, one block per pressure; with two laws or more the one closest to the
        BEM in u(p) (:meth:`closeness`), and the leak gap closest in leak rate
        (:meth:`leak_closeness`)."""
        out = []
        for i, (p, e) in enumerate(zip(self.pressures, self.ensembles, strict=True)):
            out.append(
                f"p = {p:.4g} Pa: BEM contact {e.contact_fraction:.4g} +- "
                f"{e.contact_fraction_error:.2g}, mean gap {e.mean_gap:.4g} +- "
                f"{e.mean_gap_error:.2g} m, effective gap {e.effective_gap:.4g} +- "
                f"{e.effective_gap_error:.2g} m (percolating in "
                f"{100 * e.percolating_fraction:.0f}% of {e.realizations})"
            )
            for name in self.area:
                a, s = self.area[name][i], self.separation[name][i]
                out.append(
                    f"  {name:<22} area {a.theory:.4g} ({100 * a.relative:+.1f}%, z {a.z:+.1f})"
                    f"  u {s.theory:.4g} m ({100 * s.relative:+.1f}%, z {s.z:+.1f})"
                )
            for t, diffs in self.critical_gap.items():
                d = diffs[i]
                out.append(
                    f"  u_c ({self.model}, threshold {t:g}) {d.theory:.4g} m "
                    f"({100 * d.relative:+.1f}%, z {d.z:+.1f}) vs effective gap"
                )
            if self.hydraulic_gap:
                d = self.hydraulic_gap[i]
                out.append(
                    f"  g ({list(self.laws)[-1]}) {d.theory:.4g} m ({100 * d.relative:+.1f}%, "
                    f"z {d.z:+.1f}) vs effective gap"
                )
        if len(self.laws) > 1 and _closest(self.closeness()) is not None:
            out.append(_closest_line(self.closeness(), "mean |z| of u(p)"))
        leak = self.leak_closeness()
        if len(leak) > 1 and _closest(leak) is not None:
            out.append(_closest_line(leak, "leak-rate factor", "closest leak rate to the BEM"))
        return "\n".join(out)


def validate_flat_contact(
    psd: PSD,
    E_star: float,
    pressures: ArrayLike,
    *,
    models: Sequence[str] = (DEFAULT_VARIANT,),
    gamma: float | None = None,
    law: PressureLaw | None = None,
    realizations: int = 8,
    seed: int = 0,
    executor: ExecutorLike = None,
    workers: int | None = None,
    points_per_wavelength: float = 4.0,
    periods: float = 2.0,
    thresholds: Sequence[float] = THRESHOLDS,
    progress: bool | None = None,
) -> FlatValidation:
    """BEM ensembles of a nominally flat contact against the theory, one per pressure.

    Parameters
    ----------
    psd : PSD
    E_star : float
        Effective modulus [Pa].
    pressures : float or array_like
        Nominal contact pressures [Pa], > 0.
    models, gamma, law, realizations, seed, executor, workers, points_per_wavelength, periods
        As :func:`validate_line_contact` (one pool or client serves every pressure); the
        critical gap uses the first Yang-Persson variant in ``models`` (the leak-rate theory
        needs the contact area erf(x)); a calibrated ``law`` also gives its hydraulic gap.
    thresholds : sequence of float
        Percolation thresholds of the critical junction (default 0.42 and 0.5).
    progress : bool or None
        A progress bar over each pressure's realisations on stderr (None: only when stderr
        is a terminal).

    Returns
    -------
    FlatValidation
    """
    models = _check_inputs(psd, models, realizations, seed, law, E_star)
    E_star = positive("E_star", E_star, "Pa")
    p = np.atleast_1d(positive_array("pressures", pressures)).ravel()
    laws = _laws(models, psd, E_star, gamma, law)
    leak_model, leak_theory = _leak_theory(models, laws, psd, E_star)
    grid = {"points_per_wavelength": points_per_wavelength, "periods": periods}
    scenes = [bem.flat_contact_scene(psd, E_star, float(pi), **grid) for pi in p]
    t0 = time.perf_counter()
    ensembles = _flat_ensembles(scenes, realizations, seed, executor, workers, progress)
    seconds = time.perf_counter() - t0
    area, separation = _area_and_separation(laws, p, ensembles)
    gaps = _critical_gaps(leak_theory, p, ensembles, thresholds)
    g = [] if not isinstance(law, CalibratedLaw) else _hydraulic_gaps(law, p, ensembles)
    return FlatValidation(p, ensembles, area, separation, gaps, leak_model, laws, seconds, g)


def _flat_ensembles(scenes, realizations, seed, executor, workers, progress) -> list:
    """One :class:`fastline.bem.FlatEnsemble` per scene (seeds ``seed + i``), all on one pool or
    client, each with its progress bar."""
    with bem.ensemble_executor(executor, workers, realizations) as ex:
        return [
            bem.run_ensemble(
                scene,
                realizations,
                seed + i,
                executor=ex,
                progress=progress,
                desc=f"BEM p = {scene.load:.4g} Pa",
            )
            for i, scene in enumerate(scenes)
        ]


def _leak_theory(models, laws, psd, E_star) -> tuple[str, PerssonTheory]:
    """The model of the critical gap (the first Yang-Persson variant in ``models``, else the
    default variant) and its Persson theory."""
    persson = [m for m in models if m != GW and not VARIANTS[m].area_correction]
    leak_model = persson[0] if persson else DEFAULT_VARIANT
    leak_law = laws.get(leak_model)
    leak_theory = (
        leak_law.theory if isinstance(leak_law, PerssonLaw) else PerssonTheory(psd, E_star)
    )
    return leak_model, leak_theory


def _hydraulic_gaps(law, p, ensembles) -> list:
    """Differences of a calibrated law's hydraulic gap g(p) [m] against the BEM effective gap,
    one per pressure."""
    g = np.atleast_1d(law.hydraulic_gap(p))
    return [
        _difference(gi, e.effective_gap, e.effective_gap_error)
        for gi, e in zip(g, ensembles, strict=True)
    ]


def _area_and_separation(laws, p, ensembles) -> tuple[dict, dict]:
    """Model -> Differences of the real contact area against the BEM contact fraction (NaN for
    a law without one), and of u(p) [m] against the BEM mean gap, one per pressure."""
    area, separation = {}, {}
    for m, law in laws.items():
        u, _ = law.separation_and_slope(np.log(p))
        A = law.real_area(p)
        A = np.full(p.size, np.nan) if A is None else np.atleast_1d(A)
        area[m] = [
            _difference(a, e.contact_fraction, e.contact_fraction_error)
            for a, e in zip(A, ensembles, strict=True)
        ]
        separation[m] = [
            _difference(ui, e.mean_gap, e.mean_gap_error)
            for ui, e in zip(u, ensembles, strict=True)
        ]
    return area, separation


def _critical_gaps(leak_theory, p, ensembles, thresholds) -> dict:
    """Threshold -> Differences of ``u_c`` [m] against the BEM effective gap, one per
    pressure."""
    gaps = {}
    for t in thresholds:
        uc = leak_theory.critical_gap(p, threshold=t).u_c
        gaps[float(t)] = [
            _difference(g, e.effective_gap, e.effective_gap_error)
            for g, e in zip(np.atleast_1d(uc), ensembles, strict=True)
        ]
    return gaps
