"""What every contact geometry shares: settings, the law, solving along a sweep, profile measures.

A geometry module (:mod:`fastline.contact.line`, :mod:`fastline.contact.point`) subclasses
:class:`ContactModel` and supplies what depends on the shape of the contact:

* ``_grid(load)`` - the cells of one solve: an object with ``x`` (cell centres, m; the radius
  r for a sphere), ``half_width`` (the extent of the domain, m), ``hertz`` (the smooth
  reference at this load: ``p0``, ``a``, ``delta``, ``load``) and ``disc`` (the
  :class:`fastline.contact.core.Discretisation`);
* ``_gaussian(load)`` - the Gaussian (large-alpha) reference at this load (``p0``, ``s``);
* ``_result(grid, outcome)`` - the geometry's result object;
* ``_rescaled_start(grid, initial)`` - ln p of a neighbouring result on this grid;
* class attributes ``RESULT`` (the result type), ``LOAD_UNIT`` (``"N/m"`` or ``"N"``),
  ``LOAD_RANGE`` (loads accepted, in units of ``_load_scale()``), ``LOAD_SCALE_TEXT``,
  ``MAX_N`` and ``N_NOTE`` (why n is capped).

The Hertz and Gaussian references have the same shapes for both geometries,
``p0 sqrt(1 - (x/a)^2)`` and ``p0 exp(-x^2 / 2 s^2)``, so the cold start is shared too.

SI units throughout: m, Pa, N/m (line) or N (point).
"""

from __future__ import annotations

import math
import os
import threading
import warnings
from collections.abc import Callable, Iterable
from functools import partial
from typing import NamedTuple

import numpy as np

from fastline._lib.stack import outside_stacklevel
from fastline._lib.validate import (
    MAX_ITER_RANGE,
    RADIUS_RANGE,
    boolean,
    finite_scalar,
    in_span,
    integer,
    positive,
    real_array,
)
from fastline.contact import core as _core
from fastline.contact import kernels as _kernels
from fastline.contact.core import ConvergenceWarning, dot, normalise
from fastline.contact.diagnostics import assess, warn_once
from fastline.contact.hard import hard_contact
from fastline.contact.kernels import cold_start_into, cold_start_normalised, hermite_accumulate
from fastline.theory.files import read_spectrum
from fastline.theory.laws import ExponentialLaw, PerssonLaw, PressureLaw, TabulatedLaw, check_law
from fastline.theory.persson import PerssonTheory
from fastline.theory.spectra import PSD, check_modulus, modulus_slip
from fastline.theory.variants import DEFAULT_VARIANT, VARIANTS, get_variant

MODELS = ("persson", "exponential", "hertz")
METHODS = ("newton", "picard")
MAX_NEWTON = 100
MAX_PICARD_SWEEPS = 5000
#: the ConvergenceWarning of a single solve: the same text for every scene, so that a loop of
#: solves shows it once under Python's default warning filter (which prints a text once per
#: place); each result's residual, steps and reason are in ``result.message``
NOT_CONVERGED = (
    "fastline: a solve did not converge (result.converged is False; its residual, steps and "
    "reason: result.message)"
)
#: degree of the polynomial (in ln load) that predicts each solve of a sweep from the previous
#: ones. Over the paper's three 50-load line-contact sweeps (n = 1024, the predictor below) the
#: total convolutions were 4337 independent, 2747 / 2596 / 2620 with degree 2 / 3 / 4 (an
#: earlier solver). With the cold start's tail, 32 / 64 coarse aggregates and the compiled
#: sweep, over four line-contact cases (the 50-load sweeps, 20 and 35 loads over the same range,
#: and 64 loads alpha 1e3..1e-3 at n = 256; 3 surfaces each): 6411 convolutions with degree 3
#: and CORE_DEPTH (3, 10), 6191 with degree 4, 6014 with degree 4 and (5, 10), 5909 with
#: degree 5 and (5, 10), which lost on surface 3's shorter sweeps (471 against 408 at 20 loads).
SWEEP_PREDICTOR_ORDER = 4
#: largest step in ln f_N over which the polynomial extrapolates; a longer step starts cold. An
#: O-ring sweep of 6-12 loads over 10..1e4 N/m (steps of ln 2-ln 4) failed to converge from cubic
#: predictions. The previous solution rescaled (degree 0), the remedy before, cost up to 5x the
#: convolutions of a cold start below alpha ~0.05 (surface 1, n = 256, 32 loads alpha 1e3..1e-3,
#: steps of ln 1.55: 714 convolutions against 512 independent; 137 against 23 at alpha 1.3e-3)
#: and saved at most 4 per solve near alpha 0.1-1.
PREDICTOR_MAX_STEP = math.log(1.5)
#: where a sweep's prediction follows the contact and where the domain: cells whose predicted
#: ln p lies less than ``CORE_DEPTH[0]`` below the peak take the prediction in x / s (the core
#: of the contact widens with the load), cells more than ``CORE_DEPTH[1]`` below it the
#: prediction at the same place in the domain (the tail, set by the gap), linear in between.
#: Either alone leaves an error of ~0.01-0.5 in ln p where the other is exact (at the edge of a
#: Hertz-like contact, in a tail 100-300 below the peak); blended, the paper's 50-load sweeps
#: cost 43 / 43 / 36 % fewer convolutions than independent solves (domain alone: 36 / 36 / 17
#: %, with cold starts below alpha 5e-3); with the core interpolated by cubic Hermite
#: (:func:`hermite_slopes`) instead of linearly, 46 / 47 / 40 %, and with the first Newton
#: step's forcing scaled to the start's residual (``fastline.contact.core.ETA_RES_SCALE``) 49 / 47 /
#: 42 %. With degree 4 (``SWEEP_PREDICTOR_ORDER``) a deeper core, (5, 10), did better than (3, 10):
#: 495 / 516 / 714 against 506 / 513 / 732 convolutions on the 50-load sweeps.
CORE_DEPTH = (5.0, 10.0)
#: below this alpha a law's solve that did not converge is told to use ``model="hertz"``. There
#: the roughness is invisible: the rough p0 is within 1e-4 of Hertz's at alpha = 1e-8 (n = 32 to
#: 4096), and Newton on ln p stalls on some grids (line search failed, residual 1e5-1e13 u0)
#: while no solve above it failed: probed over three spectra, both shipped laws and
#: alpha = 1e-6..1e-14, the failures were at alpha <= 1e-9 (line, n = 256), <= 1e-11 (line,
#: n = 4096) and <= 3e-9 (sphere, n = 128).
HERTZ_HINT_ALPHA = 1e-8


# ----------------------------------------------------------------------------------------------
# theories shared by the one-call functions: seal codes call them thousands of times with the
# same spectrum. The spectrum object keeps them (a private attribute), so they live exactly as
# long as it does; one lock guards the look-up.
# ----------------------------------------------------------------------------------------------
_shared_lock = threading.Lock()


def shared_theory(
    psd: PSD, E_star: float, gamma: float | None = None, variant: str | None = None
) -> PerssonTheory:
    """The :class:`PerssonTheory` of ``(psd, E_star, gamma, variant)``, built once per spectrum
    object. ``variant`` None is the default variant, ``gamma`` None the variant's own gamma
    (:mod:`fastline.theory.variants`); both are checked (ValueError naming them).

    Thread-safe. The theories are kept on the spectrum (dropped with it, left out of pickles).
    """
    var = get_variant(DEFAULT_VARIANT if variant is None else variant)
    gamma = var.default_gamma if gamma is None else finite_scalar("gamma", gamma)
    key = (float(E_star), gamma, var.name)
    with _shared_lock:
        hit = psd._theories.get(key)
    if hit is not None:
        return hit
    theory = PerssonTheory(psd, E_star, gamma=gamma, variant=var)  # outside the lock (ms)
    with _shared_lock:
        return psd._theories.setdefault(key, theory)


def _check_variant(variant) -> str | None:
    """None (the default variant, or the given theory's) or the name of a known variant;
    ValueError naming ``variant`` and the allowed names otherwise."""
    if variant is None:
        return None
    if not isinstance(variant, str) or variant not in VARIANTS:
        raise ValueError(f"variant must be one of {tuple(VARIANTS)} or None, got {variant!r}")
    return variant


# ----------------------------------------------------------------------------------------------
# profile measures along a line (a cylinder's x, a sphere's diameter)
# ----------------------------------------------------------------------------------------------
def peak(p: np.ndarray) -> float:
    """Peak value by a parabola through the three points around the discrete maximum."""
    return float(_kernels.peak(np.ascontiguousarray(p, dtype=float)))


def std(x: np.ndarray, p: np.ndarray, dx: float) -> float:
    """Standard deviation of piecewise-constant p about its centroid (cell-exact), in m."""
    m0 = p.sum()
    xc = dot(x, p) / m0
    var = dot((x - xc) ** 2, p) / m0 + dx * dx / 12.0
    return math.sqrt(var)


def fwhm(x: np.ndarray, p: np.ndarray, p0: float) -> float:
    """Width between the outermost half-maximum crossings (linear interpolation); NaN when p
    does not fall below p0/2 at both ends of the grid."""
    x, p = np.ascontiguousarray(x, dtype=float), np.ascontiguousarray(p, dtype=float)
    return float(_kernels.fwhm(x, p, float(p0)))


def log_pressure(result) -> np.ndarray:
    """ln p of a result (p in Pa), with 0 mapped to ln 1e-300."""
    return np.log(np.maximum(result.pressure, 1e-300))


def hermite_slopes(x: np.ndarray, y: np.ndarray) -> np.ndarray:
    """Slopes dy/dx of the sweep predictor's cubic Hermite interpolant
    (:func:`fastline.contact.kernels.hermite_accumulate`): second-order finite differences,
    one-sided at the ends (``np.gradient``, exact for quadratics). Cubic instead of linear
    interpolation of ln p onto the moved cells saves Newton steps (the paper's surface-3 sweep:
    1159 convolutions with linear, 1089 with cubic interpolation)."""
    return np.gradient(y, x, edge_order=2)


# ----------------------------------------------------------------------------------------------
# result fields computed on first access
# ----------------------------------------------------------------------------------------------
class Deferred(NamedTuple):
    """A field value still to compute: ``compute(result)`` gives it (:class:`DeferredFields`)."""

    compute: Callable[[object], object]


#: one lock for every deferred computation: rare (once per field and result), and a thread
#: reading a field another thread is computing waits for that value instead of making its own
_deferred_lock = threading.RLock()


class _DeferredField:
    """The class attribute of a deferrable field: a non-data descriptor, so that an instance
    that holds the value answers from its ``__dict__`` at full speed and only a pending field
    reaches :meth:`__get__` (what :func:`functools.cached_property` does; here with one lock
    for all and the computation kept on the instance)."""

    def __init__(self, name: str) -> None:
        self.name = name

    def __get__(self, result, owner=None):
        if result is None:
            return self
        with _deferred_lock:
            d = result.__dict__
            if self.name in d:  # computed by another thread meanwhile
                return d[self.name]
            pending = d.get("_deferred")
            if not pending or self.name not in pending:
                raise AttributeError(f"{type(result).__name__!r} has no {self.name!r} (never set)")
            value = d[self.name] = pending[self.name](result)
            del pending[self.name]
            if not pending:
                del d["_deferred"]
            return value


def deferrable(*names: str):
    """Class decorator (above ``@dataclass``) of a :class:`DeferredFields` result: the fields
    ``names`` may be given as :class:`Deferred`."""

    def install(cls):
        cls._DEFERRABLE = frozenset(names)
        for name in names:  # after @dataclass: the fields keep no default
            setattr(cls, name, _DeferredField(name))
        return cls

    return install


class DeferredFields:
    """Mixin of the result dataclasses: fields that are costly and rarely read (the real-area
    profile, the validity diagnostics) can be given as :class:`Deferred` and are computed on
    their first access, once, then kept like any attribute (the fields are named by
    :func:`deferrable`).

    A solve builds them with the GIL held (~10 us of a 50 us Python budget per solve), so two
    threads solving different scenes serialise on them; deferred, that work is done only when
    someone reads the field. Reading, comparing, copying and pickling a result see the same
    values as an eager construction: the first read computes a pending field, and pickling
    computes every pending field first (the pending computations, which may hold a law, never
    travel). ``vars(result)`` lists a pending field only once it has been read. Thread-safe:
    one lock, held while a field is computed.
    """

    #: the fields that may be deferred (set by :func:`deferrable`)
    _DEFERRABLE: frozenset = frozenset()

    def __post_init__(self):
        d = self.__dict__
        pending = {k: d.pop(k).compute for k in self._DEFERRABLE if type(d.get(k)) is Deferred}
        if pending:
            d["_deferred"] = pending

    def _defer(self, name: str, compute: Callable[[object], object]) -> None:
        """Make field ``name`` pending: ``compute(result)`` gives it on first access."""
        with _deferred_lock:
            d = self.__dict__
            d.pop(name, None)
            d.setdefault("_deferred", {})[name] = compute

    def __getstate__(self) -> dict:
        for name in tuple(self.__dict__.get("_deferred", ())):
            getattr(self, name)
        state = dict(self.__dict__)
        state.pop("_deferred", None)
        return state


class _Solved(NamedTuple):
    """A solution as a sweep's predictor uses it: ln load, ln of the contact width s (m), the
    cells in units of s, ln p on the cells (p in Pa) and its slopes in those units."""

    ln_load: float
    ln_width: float
    xi: np.ndarray
    v: np.ndarray
    slope: np.ndarray


def _assessed(counts: dict, result, theory, hardness) -> dict:
    """A result's ``diagnostics``: its solver ``counts`` and
    :func:`fastline.contact.diagnostics.assess` (no warnings: a model that warns assesses at
    once)."""
    counts.update(assess(result, theory, hardness, warn=False))
    return counts


def _real_area(area: Callable, p: np.ndarray, result) -> np.ndarray | None:
    """A result's ``real_area``: ``area(p)`` (a law's ``real_area`` at the solved pressures)."""
    return area(p)


#: load types whose in-range values :meth:`ContactModel._check_load` passes without
#: :func:`fastline._lib.validate.in_span` (which returns them as they are, as floats)
_FLOATS = (float, np.float64)

#: laws whose real area is a pure function of p, computed on first access of a result's
#: ``real_area`` (a user's law is asked during the solve, as its errors should surface there)
_SHIPPED_LAWS = (PerssonLaw, ExponentialLaw, TabulatedLaw)


# ----------------------------------------------------------------------------------------------
# the model base class
# ----------------------------------------------------------------------------------------------
def _hertz_start(r: np.ndarray, a: float) -> np.ndarray:
    """ln p of Hertz's profile ``sqrt(1 - r^2/a^2)`` (up to a constant) at distances ``r`` (m)
    from the centre, -inf outside ``a``; the innermost cells when ``a`` is below a cell."""
    inside = r < a
    if not inside.any():
        inside = r == r.min()
    with np.errstate(divide="ignore"):
        return np.where(inside, 0.5 * np.log(np.maximum(1.0 - (r / a) ** 2, 1e-300)), -np.inf)


class ContactModel:
    """Settings, law and solve loop shared by the contact geometries (module docstring).

    Not used directly: :class:`~fastline.LineContact` and :class:`~fastline.PointContact`
    document the parameters.
    """

    RESULT: type = object
    LOAD_UNIT = "N/m"
    LOAD_RANGE = (1e-12, 1e4)
    LOAD_SCALE_TEXT = "E* R"
    MAX_N = 2**22
    N_NOTE = ""
    HERTZ_EXTENT_TEXT = "Hertz half-width"
    #: floor of ``1 - (x/a)^2`` in the Hertz part of the cold start (0: none, the Hertz part
    #: vanishes outside the contact)
    COLD_FLOOR = 0.0
    #: a sweep's prediction: the largest step in ln load for the polynomial (else degree 0;
    #: a module constant, measured on the line contact)
    PREDICTOR_MAX_STEP = PREDICTOR_MAX_STEP

    # -- construction stages ----------------------------------------------------------------
    def _check_settings(self, E_star, radius, method, n) -> None:
        """E_star, radius, method and n (the first checks of every geometry's __init__)."""
        self.E_star = check_modulus(E_star, stacklevel=outside_stacklevel())
        self.radius = in_span("radius", radius, RADIUS_RANGE, "m")
        if method not in METHODS:
            raise ValueError(f"method must be one of {METHODS}, got {method!r}")
        self.method = method
        self.n = integer("n", n, 16, self.MAX_N, self.N_NOTE)

    def _check_extent(self, name: str, value) -> float | None:
        """An optional fixed domain extent (m), at most 1e3 R."""
        if value is None:
            return None
        return in_span(name, value, (0.0, 1e3 * self.radius), "m")

    def _check_rest(
        self, psd, model, gamma, variant, tol, max_iter, u0, beta, theory, hardness, warn
    ):
        """tol, max_iter, hardness, warn, the spectrum and the model (the last checks)."""
        self.tol = finite_scalar("tol", tol)
        if not 0.0 < self.tol <= 1e-2:
            raise ValueError(f"tol must lie in (0, 1e-2], got {tol!r}")
        if max_iter is not None:
            max_iter = integer("max_iter", max_iter, *MAX_ITER_RANGE)
        self.max_iter = max_iter
        self.hardness = None if hardness is None else positive("hardness", hardness, "Pa")
        self.warn = boolean("warn", warn)
        if isinstance(psd, str | os.PathLike):  # a spectrum file, read as fastline.sweep does
            psd = read_spectrum(psd)
        if psd is not None and not isinstance(psd, PSD):
            raise TypeError(
                f"psd must be a fastline PSD, a spectrum file's path or None, got "
                f"{type(psd).__name__}"
            )
        if theory is not None and not isinstance(theory, PerssonTheory):
            raise TypeError(f"theory must be a PerssonTheory or None, got {type(theory).__name__}")
        self.psd = psd
        variant = _check_variant(variant)
        self._theory, self._law = self._resolve_model(model, psd, theory, gamma, variant, u0, beta)
        self.model = "hertz" if self._law is None else getattr(self._law, "name", "custom")
        if variant is not None and self._theory is not None and self._theory.variant != variant:
            raise ValueError(
                f"variant={variant!r} differs from the variant of the given theory "
                f"({self._theory.variant!r}): pass variant=None (the theory's) or a theory "
                "built with that variant"
            )

    def _resolve_model(self, model, psd, theory, gamma, variant, u0, beta):
        """(theory or None, law or None for hertz) from the ``model`` argument."""
        exponential = isinstance(model, str) and model == "exponential"
        if (u0 is not None or beta is not None) and not exponential:
            raise ValueError(
                "u0 and beta set the exponential law p = beta E* exp(-u/u0): they apply only "
                f"with model='exponential' (model={model if isinstance(model, str) else 'a law'}"
                " would ignore them)"
            )
        if isinstance(model, str):
            if model not in MODELS:
                raise ValueError(f"model must be one of {MODELS} or a pressure law, got {model!r}")
            if model == "hertz":
                return None, None
            if psd is None:
                raise ValueError(f"psd must be a PSD for model={model!r} (None only for 'hertz')")
            if theory is None:
                theory = shared_theory(psd, self.E_star, gamma, variant)
            elif theory.psd is not psd or theory.E_star != self.E_star:
                raise ValueError("theory must be built for the same psd and E_star")
            if model == "persson":
                return theory, PerssonLaw(theory)
            return theory, ExponentialLaw.from_theory(theory, u0, beta)
        law = check_law(model)
        if theory is None and isinstance(law, PerssonLaw | ExponentialLaw):
            theory = law.theory
        return theory, law

    # -- public attributes --------------------------------------------------------------------
    @property
    def theory(self) -> PerssonTheory | None:
        """The Persson theory (None for ``model="hertz"`` and user laws without one)."""
        return self._theory

    @property
    def law(self) -> PressureLaw | None:
        """The pressure law the solver uses (None for ``model="hertz"``)."""
        return self._law

    # -- solving (each geometry's public ``solve`` and ``sweep`` call these) -------------------
    def _solve(self, load, initial):
        """Solve one load from a neighbouring solution ``initial`` (or cold).

        Stages: check the load, size the grid, make the initial guess, run the core method,
        measure the profile, run the diagnostics. Warnings point at the caller of ``solve``.
        """
        load = self._check_load("load", load)
        if initial is not None and not isinstance(initial, self.RESULT):
            raise TypeError(
                f"initial must be a {self.RESULT.__name__} or None, got {type(initial).__name__}"
            )
        grid = self._grid(load)
        if initial is not None:
            return self._solve_on(grid, self._rescaled_start(grid, initial), self.warn)
        start, counts = self._coarse_start(grid, load)
        return self._solve_on(grid, start, self.warn, counts)

    def _coarse_start(self, grid, load: float) -> tuple[np.ndarray | None, dict | None]:
        """A cold solve's start from a coarser grid (ln p on ``grid``, and the work it took
        for the result's ``diagnostics``), or ``(None, None)``: the cold start of
        :meth:`_run`. None here; a geometry may nest (:class:`fastline.LineContact`)."""
        return None, None

    def _solve_on(self, grid, start: np.ndarray | None, warn: bool, counts: dict | None = None):
        """Run the core from ``start`` (ln p; None: cold) and finish the result (``counts``:
        more entries of its solver counts in ``diagnostics``). The validity diagnostics are
        made now when they may warn, else on first access to the result's ``diagnostics``
        (:class:`DeferredFields`)."""
        outcome = self._run(grid, start)
        result = self._result(grid, outcome)
        if counts:
            result.diagnostics.update(counts)
        if warn:  # the warnings point at the user's line that led here
            level = outside_stacklevel()
            if not result.converged:
                warnings.warn(NOT_CONVERGED, ConvergenceWarning, stacklevel=level)
            found = assess(result, self._theory, self.hardness, warn=True, stacklevel=level)
            result.diagnostics.update(found)
        else:
            self._defer_diagnostics(result)
        return result

    def _defer_diagnostics(self, result) -> None:
        """Make a result's validity diagnostics pending: made on first access
        (:class:`DeferredFields`), added to its solver counts."""
        counts = result.diagnostics
        theory, hardness = self._theory, self.hardness
        result._defer("diagnostics", lambda r: _assessed(counts, r, theory, hardness))

    def _sweep(self, loads: Iterable[float], progress: Callable[[], object] | None) -> list:
        """Continuation along the loads (see the geometry's ``sweep``): increasing order, each
        solve started from a polynomial prediction in ln load (:meth:`_predict`) and restarted
        cold if that start fails, warnings once per cause."""
        loads = self._check_loads(loads)
        out: list = [None] * loads.size
        history: list[_Solved] = []
        for i in np.argsort(loads, kind="stable"):
            grid = self._grid(float(loads[i]))
            result = self._solve_on(grid, self._predict(grid, history), warn=False)
            if not result.converged and history:  # the prediction misled Newton: start cold
                cold = self._solve_on(grid, None, warn=False)
                cold.convolutions += result.convolutions  # count all the work done
                cold.diagnostics["restarted_cold"] = True
                result = cold
            solved = self._solved(grid, result)
            if history and history[-1].ln_load == solved.ln_load:  # a repeated load: no two
                history.pop()  # solutions at one load (the Lagrange weights divide by the gap)
            history = (history + [solved])[-(SWEEP_PREDICTOR_ORDER + 1) :]
            out[i] = result
            if progress is not None:
                progress()
        if self.warn:
            self._warn_sweep(out)
        return out

    def _message(self, out: _core.Outcome, alpha: float) -> str:
        """The outcome's message; for a law's solve that did not converge at alpha below
        ``HERTZ_HINT_ALPHA``, with the advice to solve the smooth contact instead."""
        if out.converged or self._law is None or not alpha < HERTZ_HINT_ALPHA:
            return out.message
        return (
            f"{out.message}; alpha = {alpha:.3g} < {HERTZ_HINT_ALPHA:g} is the smooth-contact "
            "limit, where the roughness no longer changes the pressure (p0 within 1e-4 of "
            f"Hertz's) and the rough solve can stall: use model='hertz' ("
            f"{type(self).__name__}(None, E_star, radius, model='hertz'))"
        )

    def _warn_sweep(self, results: list) -> None:
        """One ConvergenceWarning for the loads that did not converge, one ValidityWarning per
        cause (the caller of the geometry's ``sweep`` sees them)."""
        failed = [r.load for r in results if not r.converged]
        if failed:
            loads = ", ".join(f"{f:.4g}" for f in failed)
            warnings.warn(
                f"fastline: {len(failed)} of {len(results)} solves did not converge "
                f"(loads {loads} {self.LOAD_UNIT}); see each result's message",
                ConvergenceWarning,
                stacklevel=outside_stacklevel(),
            )
        warn_once(results, stacklevel=outside_stacklevel())

    def _load_scale(self) -> float:
        """The unit of ``LOAD_RANGE`` in N/m or N (``E* R`` for a line contact)."""
        return self.E_star * self.radius

    def _check_load(self, name: str, load) -> float:
        """A load inside ``LOAD_RANGE`` (in units of ``_load_scale()``): the Hertz contact
        stays between ~1e-6 R and ~100 R, where every quantity of the solve is representable."""
        lo, hi = self.LOAD_RANGE
        scale = self._load_scale()
        if type(load) in _FLOATS and lo * scale <= load <= hi * scale:  # in_span's answer, faster
            return float(load)
        unit = f"{self.LOAD_UNIT} ([{lo:g}, {hi:g}] {self.LOAD_SCALE_TEXT})"
        slip = modulus_slip(self.E_star)
        if slip is None:
            return in_span(name, load, (lo * scale, hi * scale), unit)
        try:  # the load range scales with E*: an implausible E* is the likelier culprit
            return in_span(name, load, (lo * scale, hi * scale), unit)
        except ValueError as e:
            raise ValueError(
                f"E_star = {self.E_star:g} Pa looks like a unit slip (E* is in Pa; the "
                f"UnitWarning names the likely unit), and with it {e}"
            ) from None

    @staticmethod
    def _check_progress(progress) -> Callable[[], object] | None:
        """``progress`` if it is None or callable; a TypeError naming it otherwise."""
        if progress is not None and not callable(progress):
            raise TypeError(
                "progress must be None or a callable, called with no argument after each "
                f"load (e.g. a tqdm bar's update), got {type(progress).__name__}"
            )
        return progress

    def _check_loads(self, loads) -> np.ndarray:
        if isinstance(loads, Iterable) and not isinstance(
            loads, np.ndarray | list | tuple | str | bytes
        ):
            loads = list(loads)  # a generator, a range...
        arr = real_array("loads", loads)  # bools and strings refused, as solve refuses them
        if arr.ndim != 1 or arr.size == 0:
            raise ValueError(f"loads must be a non-empty 1-D sequence of loads in {self.LOAD_UNIT}")
        for f in arr:
            self._check_load("loads", f)
        return arr

    # -- solve stages -------------------------------------------------------------------------
    def _u0(self) -> float:
        return 0.0 if self._law is None else self._law.u0

    def _extent(self, name: str, given: float | None, hertz, load: float) -> float:
        """The domain extent: ``given`` (checked against the Hertz contact) or the default
        ``1.25 a + 8 sqrt(R u0)`` (the Hertz contact plus eight Gaussian widths)."""
        if given is None:
            return 1.25 * hertz.a + 8.0 * math.sqrt(self.radius * self._u0())
        if given < hertz.a:
            raise ValueError(
                f"{name} = {given:.6g} m cuts the contact: at load {load:.6g} {self.LOAD_UNIT} "
                f"the {self.HERTZ_EXTENT_TEXT} alone is a = {hertz.a:.6g} m; give {name} >= a (the "
                f"default, None, sizes the domain as 1.25 a + 8 sqrt(R u0))"
            )
        return given

    def _alpha(self, delta: float) -> float:
        """h_rms / delta; 0 for smooth surfaces (hertz without a spectrum), NaN when unknown."""
        if self.psd is None:
            return 0.0 if self._law is None else float("nan")
        return self.psd.h_rms / delta

    def _cold_start(self, grid) -> np.ndarray:
        """ln p to start from without a neighbour: Hertz and Gaussian profiles blended (up to
        a constant: :meth:`_run` normalises every start to the load)."""
        x = grid.x
        if self._law is None:  # hard contact: Hertz's profile, sqrt(1 - x^2/a^2)
            return _hertz_start(np.abs(x), grid.hertz.a)
        v = np.empty_like(x)
        cold_start_into(x, *self._cold_profiles(grid.hertz), v)  # compiled, nogil
        return v  # normalised to the load by _run, as every start is

    def _cold_profiles(self, hz) -> tuple[float, float, float, float, float, float, float]:
        """``(a, ln_h, floor, ln_g, 2 s^2, ln_t, k_t)`` of
        :func:`fastline.contact.kernels.cold_start_into`: the Hertz and Gaussian profiles of the
        cold start and their weights, and the tail outside the Hertz contact
        (:meth:`_cold_tail`)."""
        alpha = self._alpha(hz.delta)
        if not math.isfinite(alpha):
            alpha = 2.0 * self._u0() / hz.delta
        gs = self._gaussian(hz.load)
        # weights alpha/(alpha + 0.3) and 0.3/(alpha + 0.3), in logarithms (no 1 - 1 at huge alpha)
        ln_wh = math.log(0.3) - math.log(alpha + 0.3)
        ln_wg = math.log(alpha) - math.log(alpha + 0.3)
        ln_h, ln_g = ln_wh + math.log(hz.p0), ln_wg + math.log(gs.p0)
        return (hz.a, ln_h, self.COLD_FLOOR, ln_g, 2.0 * gs.s**2, *self._cold_tail(hz, ln_h, ln_g))

    def _cold_tail(self, hz, ln_h: float, ln_g: float) -> tuple[float, float]:
        """``(ln_t, k_t)`` of the cold start's tail outside the Hertz contact; none here
        (``ln_t = -inf``): a geometry that knows its Hertz gap overrides this."""
        return -math.inf, 0.0

    def _solved(self, grid, result) -> _Solved:
        """What a sweep keeps of a solution for the next predictions. ln p comes from the
        law's inverse at the solution's separation: exact also in the far tail, where the
        result's pressure is flushed to 0 (``fastline.contact.kernels.LN_FLOOR``)."""
        v = log_pressure(result)
        flushed = result.pressure == 0.0
        if self._law is not None and flushed.any():
            with np.errstate(all="ignore"):
                exact = np.asarray(_core._log_pressure(self._law, result.separation[flushed]))
            v[flushed] = np.where(np.isfinite(exact), exact, v[flushed])
        width = result.s if result.s > 0.0 else grid.half_width
        xi = grid.x / width
        return _Solved(math.log(grid.hertz.load), math.log(width), xi, v, hermite_slopes(xi, v))

    def _predict(self, grid, history: list[_Solved]) -> np.ndarray | None:
        """ln p at this load extrapolated from earlier solutions of this model (same n) by
        the Lagrange polynomial in ln load through the last ones: in the core of the contact at
        the same x / s (s, the standard deviation of p, extrapolated too), in the tail at the
        same place in the domain, blended by depth below the peak (``CORE_DEPTH``). None (a
        cold start) without history and after a step longer than ``PREDICTOR_MAX_STEP``."""
        if not history:
            return None
        t = math.log(grid.hertz.load)
        if t - history[-1].ln_load > self.PREDICTOR_MAX_STEP:
            return None
        pts = history[-(SWEEP_PREDICTOR_ORDER + 1) :]
        weights = [
            math.prod((t - b.ln_load) / (a.ln_load - b.ln_load) for b in pts if b is not a)
            for a in pts
        ]
        terms = list(zip(weights, pts, strict=True))
        width = math.exp(sum(w * a.ln_width for w, a in terms))
        in_domain = sum(w * a.v for w, a in terms)
        in_contact = np.zeros(grid.x.size)
        xq = grid.x / width
        for w, a in terms:
            hermite_accumulate(xq, a.xi, a.v, a.slope, float(w), in_contact)  # one signature
        depth = np.max(in_domain) - in_domain
        tail = np.clip((depth - CORE_DEPTH[0]) / (CORE_DEPTH[1] - CORE_DEPTH[0]), 0.0, 1.0)
        return tail * in_domain + (1.0 - tail) * in_contact

    def _separation_and_area(self, out: _core.Outcome) -> tuple[np.ndarray, np.ndarray | Deferred]:
        """Separation u (m) and real contact-area fraction of a solve's outcome: the law's at
        the solved pressures, or, for a hard (Hertz) contact, the gap and 1 where p > 0. The
        area of a shipped law is :class:`Deferred` (computed when the result's ``real_area``
        is first read); a user's law is asked now."""
        p = out.pressure
        if self._law is None:
            return out.separation, (p > 0.0).astype(float)
        separation = out.separation
        if separation is None:
            separation = self._law.separation_and_slope(out.v)[0]
        if type(self._law) in _SHIPPED_LAWS:
            return separation, Deferred(partial(_real_area, self._law.real_area, p))
        area = getattr(self._law, "real_area", None)  # optional in the protocol
        return separation, None if area is None else area(p)

    def _run(self, grid, start: np.ndarray | None) -> _core.Outcome:
        disc, load = grid.disc, grid.hertz.load
        if self._law is None:
            v = self._cold_start(grid) if start is None else start
            max_iter = self.max_iter or 10 * self.n
            p = _core.pressure_of(v)  # exactly 0 off the predicted contact
            return hard_contact(disc, p, grid.hertz.delta, self.tol, max_iter)
        if start is None:  # the cold start, normalised to the load, in one compiled call
            v = np.empty_like(grid.x)
            profiles = self._cold_profiles(grid.hertz)
            cold_start_normalised(grid.x, profiles, float(load), disc.weights, v)
        else:
            v = normalise(start, load, disc.weights)
        if self.method == "newton":
            max_iter = self.max_iter or MAX_NEWTON
            return _core.newton(disc, self._law, v, self.tol, max_iter, self._law_form())
        return _core.picard(disc, self._law, v, self.tol, self.max_iter or MAX_PICARD_SWEEPS)

    def _law_form(self) -> tuple | None:
        """The law's ``_compiled_form()`` (None if it has none), made once per model: the law
        of a model does not change."""
        form = self.__dict__.get("_form")
        if form is None:
            make = getattr(self._law, "_compiled_form", None)
            form = self._form = () if make is None else make()
        return form or None

    # -- supplied by each geometry --------------------------------------------------------------
    def _grid(self, load: float):  # pragma: no cover - abstract
        raise NotImplementedError

    def _gaussian(self, load: float):  # pragma: no cover - abstract
        raise NotImplementedError

    def _result(self, grid, outcome: _core.Outcome):  # pragma: no cover - abstract
        raise NotImplementedError

    def _rescaled_start(self, grid, initial) -> np.ndarray:  # pragma: no cover - abstract
        raise NotImplementedError
