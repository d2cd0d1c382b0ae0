"""Line contact: the nominal pressure p(x) under a cylinder on a rough half-space.

Equations (paper eqs. 3-4; docs/theory.md, "Line contact"): unknown pressure ``p(x) > 0`` and
rigid approach ``u1`` with

    u(x) = u1 + x^2/(2R) + (K p)(x),     u(x) = u_law(p(x)),     int p dx = f_N,

``K`` the plane-strain log kernel (:mod:`fastline.elastic.line`), ``u_law`` the pressure law
(:mod:`fastline.theory.laws`). What is cylinder-specific lives here: the grid and its sizing, the
gap ``x^2/2R``, the Hertz reference, alpha, the initial guess and the profile measures (p0, s,
FWHM). The Newton-Krylov core that solves the discrete equations is shared with other geometries
(:mod:`fastline.contact.core`), and so are the settings, the law, the solve and sweep loop, the cold
start and the peak and FWHM measures (:mod:`fastline.contact.model`).

:class:`LineContact` is the reusable model (theory tables, law and settings built once, many
loads solved); :func:`solve_line_contact` is a one-call wrapper around it.
"""

from __future__ import annotations

import copy
import math
import os
from collections.abc import Callable, Iterable
from dataclasses import KW_ONLY, dataclass, field
from typing import Any, ClassVar, NamedTuple

import numpy as np
from numpy.typing import ArrayLike

from fastline._lib import fftw as _fftw
from fastline._lib.validate import real_array
from fastline.contact import core as _core
from fastline.contact import line_sweep, resolution
from fastline.contact.core import ConvergenceWarning, Discretisation
from fastline.contact.kernels import line_cells, line_measures
from fastline.contact.line_newton import solve_compiled
from fastline.contact.model import (  # noqa: F401 (METHODS ... shared_theory: importable here as before)
    MAX_NEWTON,
    METHODS,
    MODELS,
    PREDICTOR_MAX_STEP,
    SWEEP_PREDICTOR_ORDER,
    ContactModel,
    DeferredFields,
    deferrable,
    fwhm,
    log_pressure,
    peak,
    shared_theory,
    std,
)
from fastline.contact.result import ContactResult
from fastline.elastic.line import (
    LogKernelOperator,
    compile_system_elsewhere,
    log_reference_shift_unchecked,
)
from fastline.theory.laws import PressureLaw
from fastline.theory.limits import (
    HertzLineContact,
    gaussian_line_contact,
    gaussian_line_unchecked,
    hertz_line_unchecked,
)
from fastline.theory.persson import PerssonTheory
from fastline.theory.spectra import PSD

__all__ = [
    "ConvergenceWarning",
    "LineContact",
    "LineContactResult",
    "solve_line_contact",
    "profile",
    "w_over_s",
    "p0_ratio",
]

DEFAULT_N = 1024
#: the cold start's tail outside the Hertz contact starts at the Hertz pressure this fraction of
#: the edge layer inside the edge (the layer: the depth at which Hertz's gap outside reaches u0).
#: Convolutions of the 160 count scenes of bench/core.py (5 surfaces, alpha 1e-4..1e3, n 256..
#: 16384): 3297 without the tail, 2976 with it (worst per n 29/39/51/65 -> 25/33/47/61); at
#: n = 1024, alpha <= 1: 650 without, 547 at 0.3, 553 at 0.1, 571 at 1.0
COLD_TAIL_DEPTH = 0.3
#: ... and no higher than the law's pressure at separation ``COLD_TAIL_CAP u0``: outside the
#: contact the law is exponential. Without the cap, a campaign scene whose centre reaches full
#: contact (tests/test_solver.py, alpha 0.13) started with an edge 40x the solution's and Newton
#: stalled at n = 4096 (residual 5 after 100 steps); with it 35/104/51 convolutions at n = 1024/
#: 4096/8192 (37/103/55 without the tail). Count scenes (no k_t gate): 2938 at 0.5, 2963 at 1,
#: 3043 at 2
COLD_TAIL_CAP = 1.0
#: ... and only in a Hertz-like contact, ``k_t = a^2 / (2 R u0) = delta / (2 u0)`` at least this
#: (the Hertz contact wider than the Gaussian, ``a >= sqrt(2 R u0)``; alpha below about 1 at
#: gamma_u = 0.4): above, the tail (about ``e^-4`` of the Gaussian at alpha = 100) saved 13 of
#: 666 convolutions of the 80 count scenes at alpha >= 1 and cost 20-30 ns a cell
COLD_TAIL_MIN_K = 1.0
#: nested iteration: a cold solve (Newton, a pressure law) on ``NESTED_MIN_N`` cells or more
#: starts from the solution of the same load on ``n // NESTED_FACTOR`` cells of the same domain
#: (interpolated in ln p), which settles the contact's shape for a few 8x cheaper FFTs. Surface
#: 1, alpha 1e-4..10, same run (CPU ms, cold -> nested; convolutions of length 2n cold ->
#: nested + those on n/8 cells): n = 4096: 13.4 -> 11.0 ms summed over the six alphas, alpha 1e-2
#: 3.8 -> 2.7 ms (37 -> 25 + 27), alpha 1e-4 2.1 -> 2.4 (the one loss); n = 16384: 85.7 -> 57.8
#: ms, alpha 1e-2 26.6 -> 15.7 (47 -> 27 + 41), alpha 0.1 10.9 -> 5.6. A chain n/64 -> n/8 -> n
#: was no better. The solutions agree to the solver tolerance (p0 within 1e-9). Over the 40 hard
#: scenes per n (``python -m bench.count_grid --nested``): 0.85 / 0.76 / 0.71 of the cold time
#: at n = 4096 / 8192 / 16384.
NESTED_MIN_N = 4096
NESTED_FACTOR = 8
#: largest grid (about 2 GB of working arrays)
MAX_N = 2**22
#: loads per unit length accepted, in units of E* R
LOAD_RANGE = (1e-12, 1e4)

#: what a solve accepts as its spectrum: a PSD, a spectrum file's path, or None (hertz)
Spectrum = PSD | str | os.PathLike | None


@dataclass(repr=False)  # the short repr of ContactResult, not every array
class LineContactResult(ContactResult):
    """The solution of one line-contact scene and what follows from it.

    Arrays are on the solver grid (cell centres). Units: m, Pa, N/m. ``real_area`` and
    ``diagnostics`` of a solve are computed when first read (for ``diagnostics``, unless the
    model warns); the values are the same (:class:`fastline.contact.model.DeferredFields`).

    Attributes
    ----------
    x : ndarray
        Grid coordinates in m (symmetric about 0).
    pressure : ndarray
        Nominal contact pressure p(x) in Pa.
    separation : ndarray
        Mean interfacial separation u(x) in m (the gap for ``model="hertz"``).
    real_area : ndarray or None
        Real contact area fraction P(q1, p(x)) from the Persson theory (1 inside and 0 outside
        the contact for ``model="hertz"``; None for a law that does not know it).
    p0 : float
        Peak pressure in Pa.
    s : float
        Standard deviation of p(x) about its centroid in m.
    fwhm : float
        Full width at half maximum in m.
    w_over_s, p0_ratio : float
        ``fwhm / s`` and ``p0 / p0_Hertz``.
    alpha, delta : float
        ``alpha = h_rms / delta`` and the Hertz penetration ``delta = 4 f_N / (pi E*)`` in m.
    u1 : float
        Rigid approach in m, with the logarithm's reference length R (a constant offset).
    converged : bool
        Whether the residual fell below ``tol``.
    iterations, convolutions : int
        Outer iterations (Newton steps, sweeps; hertz: active-set steps) and FFT convolutions
        of length 2n: applications of K plus the preconditioner's circulant solves
        (``diagnostics`` splits the two as ``k_applications`` and ``circulant_solves``).
    residual : float
        Final residual: max |u_law(p) - u1 - x^2/2R - K p| / u0 (for hertz: the
        complementarity error relative to delta, or the relative load error if larger).
    message : str
        What happened.
    model, method : str
        The law's name (``"persson"``, ``"exponential"``, ``"tabulated"``, a user law's
        ``name``, or ``"hertz"``) and the method.
    load, radius, E_star, dx : float
        The scene (N/m, m, Pa) and the cell width (m).
    force_error : float
        ``|sum p dx - f_N| / f_N``.
    edge_pressure : float
        Pressure at the domain edge relative to p0.
    diagnostics : dict
        Solver counts and the validity checks of :func:`fastline.contact.diagnostics.assess`.
    theory : PerssonTheory or None
        The theory the scene was solved with (None for hertz and for user laws), for
        post-processing such as leak rates.
    error_estimate : ErrorEstimate or None
        Estimated relative errors of p0, s, FWHM and w/s (:mod:`fastline.contact.resolution`): set
        when the model has ``accuracy=`` or by :meth:`LineContact.estimate_error`, else None.
    """

    _: KW_ONLY
    x: np.ndarray
    dx: float
    error_estimate: resolution.ErrorEstimate | None = field(default=None, repr=False, compare=False)


# ----------------------------------------------------------------------------------------------
# profile measures (peak and FWHM are shared with the other geometries: fastline.contact.model)
# ----------------------------------------------------------------------------------------------
def _measures(x: np.ndarray, p: np.ndarray, dx: float) -> tuple[float, float, float, float]:
    """``(p0, s, fwhm, sum p)``: :func:`peak`, :func:`std`, :func:`fwhm` and ``p.sum()`` in one
    compiled pass that releases the GIL (equal to them to round-off)."""
    p = np.ascontiguousarray(p, dtype=np.float64)
    p0, s, w, total = line_measures(x, p, dx)
    return float(p0), float(s), float(w), float(total)


# ----------------------------------------------------------------------------------------------
# the grid of one load
# ----------------------------------------------------------------------------------------------
class _LineGrid(NamedTuple):
    """Cells of one solve: coordinates, width, the Hertz reference and the discretisation
    (a tuple: built once per solve, ~1 us less than a frozen dataclass)."""

    x: np.ndarray
    dx: float
    half_width: float
    hertz: HertzLineContact
    disc: Discretisation


def _build_grid(n: int, half_width: float, radius: float, E_star: float, hz) -> _LineGrid:
    """Cells ``x = (i - (n-1)/2) dx``, gap ``x^2/2R`` and weights ``dx`` (one compiled pass);
    the model checked n, R and E* once, so the operator skips its checks."""
    dx = 2.0 * half_width / n
    x, gap, w = np.empty(n), np.empty(n), np.empty(n)
    line_cells(dx, 2.0 * radius, x, gap, w)
    op = LogKernelOperator._unchecked(n, dx, E_star)  # fresh counters per solve (per thread)
    return _LineGrid(x, dx, half_width, hz, Discretisation(gap, w, op, hz.load, solve_compiled))


def _rescaled_start(grid: _LineGrid, initial: LineContactResult) -> np.ndarray:
    """ln p of a neighbouring solution at the same relative position in the domain (the default
    domain scales with the contact), interpolated onto this grid; the load is restored later."""
    xi = initial.x / (0.5 * initial.x.size * initial.dx)
    return np.interp(grid.x / grid.half_width, xi, log_pressure(initial))


class LineContact(ContactModel):
    """A reusable line-contact model: one spectrum, material, cylinder and law, many loads.

    It owns what every solve reuses: the Persson theory and its tables, the pressure law, the
    grid policy and the solver settings. FFT plans and kernel spectra are shared per grid size
    by all models (:mod:`fastline.elastic.line`). An instance is safe to share between threads
    (``solve`` changes no state of the model) and pickles (the theory's tables travel with it).

    Parameters
    ----------
    psd : PSD, str, path-like or None
        Combined roughness spectrum (m^4 vs 1/m), or the path of a spectrum file (read by
        ``fastline.io.read_spectrum``, as :func:`fastline.sweep` reads one; read the file once
        yourself for many models). None only with ``model="hertz"`` or a user law (then alpha
        is not defined and reported as NaN).
    E_star : float
        Effective modulus in Pa (paper eq. 1), in [1, 1e13].
    radius : float
        Cylinder radius R in m, in [1e-9, 1e3].
    model : {"persson", "exponential", "hertz"} or PressureLaw
        p(u) relation: full Persson theory (default), the exponential law (paper eq. 5, u0 and
        beta from the theory unless given), hard contact of smooth surfaces, or a pressure law
        object (:mod:`fastline.theory.laws`: :class:`~fastline.theory.laws.TabulatedLaw`, your own).
    method : {"newton", "picard"}
        Newton-Krylov (default) or the plain damped fixed point (for comparison).
    gamma : float, optional
        Parameter gamma of the theory's correction S(P), in [0.05, 1] (default: the variant's
        own, 0.45; 5/9 for ``"wang-mueser"``).
    variant : str, optional
        Variant of the theory's u(p) (:mod:`fastline.theory.variants`, docs/theory.md):
        ``"yang-persson-energy"`` (None, the default), ``"yang-persson-printed"`` or
        ``"wang-mueser"``. Ignored for ``model="hertz"`` and for laws without a theory;
        with ``theory=`` it must name the theory's own variant (or be None).
    n : int, optional
        Grid points, in [16, 2^22] (default 1024; with ``accuracy``, the first grid tried).
    half_width : float, optional
        Half-width of the domain in m, the same for every load, at most 1e3 R and at least the
        Hertz half-width ``a`` of each load solved; default per load ``1.25 a + 8 sqrt(R u0)``.
    tol : float
        Residual tolerance (separation mismatch in units of u0; hertz: gap mismatch in the
        contact in units of delta, :mod:`fastline.contact.hard`), in (0, 1e-2].
    max_iter : int, optional
        Newton steps / fixed-point sweeps allowed (defaults 100 / 5000; the fixed point also
        stops when it stagnates, see :func:`fastline.contact.core.picard`); hertz: active-set steps
        (at most 30, typically 1-2).
    u0, beta : float, optional
        Exponential-law parameters for ``model="exponential"`` (m, dimensionless); refused
        with another model, which would ignore them.
    theory : PerssonTheory, optional
        A prebuilt theory for ``psd`` and ``E_star`` (its gamma and variant are used).
    hardness : float, optional
        Indentation hardness of the softer solid in Pa, for the plasticity diagnostic.
    warn : bool
        Emit a ``ConvergenceWarning`` when a solve does not converge and the diagnostics'
        ``ValidityWarning`` s.
    accuracy : float, optional
        Relative error wanted in p0, s and w/s, in [1e-8, 0.1] (not for ``model="hertz"``):
        each load is solved on grids refined until the estimated error is below it, and every
        result carries ``error_estimate`` (:mod:`fastline.contact.resolution`, docs/accuracy.md).
        None (default): one solve on the grid of ``n`` and ``half_width``, no estimate.

    Examples
    --------
    >>> import fastline as fl
    >>> psd = fl.SelfAffinePSD(10e-6, 0.8, 1e3, 1e4, 1e9)
    >>> lc = fl.LineContact(psd, E_star=1.33e9, radius=0.01)
    >>> res = lc.solve(1e4)
    >>> res2 = lc.solve(1.2e4, initial=res)  # warm start
    >>> results = lc.sweep([1e3, 1e4, 1e5])  # continuation along the loads
    """

    #: the class of this model's results
    result_type: ClassVar[type] = LineContactResult

    def __init__(
        self,
        psd: Spectrum,
        E_star: float,
        radius: float,
        *,
        model: str | PressureLaw = "persson",
        method: str = "newton",
        gamma: float | None = None,
        variant: str | None = None,
        n: int | None = None,
        half_width: float | None = None,
        tol: float = 1e-8,
        max_iter: int | None = None,
        u0: float | None = None,
        beta: float | None = None,
        theory: PerssonTheory | None = None,
        hardness: float | None = None,
        warn: bool = True,
        accuracy: float | None = None,
    ) -> None:
        self._check_settings(E_star, radius, method, DEFAULT_N if n is None else n)
        if method == "newton" and not (isinstance(model, str) and model == "hertz"):
            compile_system_elsewhere()  # only when nothing has it yet: a fresh installation
        self._n_given = None if n is None else self.n  # with accuracy=, the first grid tried
        self.accuracy = resolution.check_accuracy(accuracy)
        self.half_width = self._check_extent("half_width", half_width)
        self._check_rest(
            psd, model, gamma, variant, tol, max_iter, u0, beta, theory, hardness, warn
        )
        if self.accuracy is not None and self._law is None:
            raise ValueError("accuracy needs a pressure law (model='hertz' converges at order ~1)")

    # -- what the shared machinery (fastline.contact.model.ContactModel) needs --------------------
    RESULT = LineContactResult
    LOAD_UNIT = "N/m"
    LOAD_RANGE = LOAD_RANGE
    LOAD_SCALE_TEXT = "E* R"
    MAX_N = MAX_N
    N_NOTE = " (a solve needs about 500 bytes per cell)"
    HERTZ_EXTENT_TEXT = "Hertz half-width"

    def __repr__(self):
        return (
            f"LineContact({self.psd!r}, E_star={self.E_star!r}, radius={self.radius!r}, "
            f"model={self.model!r}, method={self.method!r}, n={self.n})"
        )

    # -- solving ------------------------------------------------------------------------------
    def solve(self, load: float, initial: LineContactResult | None = None) -> LineContactResult:
        """Solve one load (N/m); ``initial`` is a neighbouring solution to start from.

        Stages: check the load, size the grid, make the initial guess, run the core method,
        measure the profile, run the diagnostics. Without ``initial``, a grid of
        ``NESTED_MIN_N`` cells or more starts from the solution on an eighth of them (nested
        iteration; its work in ``diagnostics["nested_start"]``). With ``accuracy``: grids
        chosen by the error estimate (:func:`fastline.contact.resolution.solve_to_accuracy`).
        """
        if self.accuracy is not None:
            if initial is not None and not isinstance(initial, LineContactResult):
                raise TypeError(
                    f"initial must be a LineContactResult or None, got {type(initial).__name__}"
                )
            return resolution.solve_to_accuracy(self, self._check_load("load", load), initial)
        return self._solve(load, initial)

    def sweep(
        self, loads: Iterable[float], progress: Callable[[], object] | None = None
    ) -> list[LineContactResult]:
        """Solve a series of loads (N/m) by continuation; results in the order given.

        The loads are solved in increasing order. Each solve starts from a prediction made
        from the solutions already found: ln p extrapolated in ln f_N by a polynomial through
        the last ``SWEEP_PREDICTOR_ORDER + 1`` of them, in the core of the contact at the same
        x / s, in the tail at the same place in the domain (a cold start after a step longer
        than ``PREDICTOR_MAX_STEP``, and again after a failed predicted start;
        :mod:`fastline.contact.model`). With Newton and a shipped law the whole loop is one
        compiled call that releases the GIL (:mod:`fastline.contact.line_sweep`; with ``progress``,
        one call per load). Over the paper's 50-load sweeps this costs fewer FFT convolutions
        than independent solves, and less time (docs/performance.md gives the figures); each
        result is the converged solution at its load, equal to an independent solve to the
        solver tolerance. Warnings are emitted once per cause for the whole sweep, naming the
        loads concerned (:func:`fastline.contact.diagnostics.warn_once`). ``progress``, if given, is
        called with no argument after each solve (e.g. a tqdm bar's ``update``).
        """
        progress = self._check_progress(progress)
        if self.accuracy is not None:  # each load on its own grids: no continuation
            return resolution.sweep_to_accuracy(self, self._check_loads(loads), progress)
        return self._sweep(loads, progress)

    def _sweep(
        self, loads: Iterable[float], progress: Callable[[], object] | None
    ) -> list[LineContactResult]:
        """Continuation along the loads in compiled calls (:mod:`fastline.contact.line_sweep`) when
        the solve itself is compiled (Newton, a shipped law, FFTW found); else the Python loop
        of :meth:`fastline.contact.model.ContactModel._sweep` (the same predictor)."""
        form = self._law_form() if self.method == "newton" else None
        if form is None or not _fftw.AVAILABLE:
            return super()._sweep(loads, progress)
        loads = self._check_loads(loads)
        order = np.argsort(loads, kind="stable")
        hzs = [hertz_line_unchecked(self.E_star, self.radius, f) for f in loads[order].tolist()]
        halves = [self._extent("half_width", self.half_width, hz, hz.load) for hz in hzs]
        cold = np.array([self._cold_profiles(hz) for hz in hzs])
        arrays = line_sweep.run_sweep(
            self.n,
            self.E_star,
            self.radius,
            loads[order],
            np.array(halves),
            cold,
            form,
            self._law.u0,
            self.tol,
            self.max_iter or MAX_NEWTON,
            progress,
        )
        out: list = [None] * loads.size
        for k, i in enumerate(order.tolist()):
            grid = _build_grid(self.n, halves[k], self.radius, self.E_star, hzs[k])
            out[i] = self._swept_result(grid, arrays, k)
        if self.warn:
            self._warn_sweep(out)
        return out

    def _swept_result(self, grid: _LineGrid, arrays, k: int) -> LineContactResult:
        """The result of load k of a compiled sweep (:func:`fastline.contact.line_sweep.run_sweep`);
        its arrays are copies (a result does not keep the sweep's alive)."""
        u1, res, status, steps, cg, kapps, circ, tol_eff, restarted, *measures = arrays.stats[
            k
        ].tolist()
        hist, p, u = arrays.hist[k, : int(steps)], arrays.p[k].copy(), arrays.u[k].copy()
        outcome = _core.compiled_outcome(
            None, u1, res, status, steps, cg, self.tol, tol_eff, hist, p, u
        )
        op = grid.disc.op
        op.convolutions, op.circulant_solves = int(kapps + circ), int(circ)
        result = self._result(grid, outcome, tuple(measures))
        if restarted:
            result.diagnostics["restarted_cold"] = True
        self._defer_diagnostics(result)
        return result

    def estimate_error(self, result: LineContactResult) -> resolution.ErrorEstimate:
        """Relative errors of a result of this model from one companion solve on the same
        domain (:func:`fastline.contact.resolution.estimate_error`); also stored as
        ``result.error_estimate``."""
        resolution.check_result(self, result)
        if self._law is None:
            raise ValueError("estimate_error needs a pressure law (not model='hertz')")
        return resolution.estimate_error(self, result)

    def _coarse_start(self, grid: _LineGrid, load: float) -> tuple[np.ndarray | None, dict | None]:
        """Nested iteration: a cold solve on ``NESTED_MIN_N`` cells or more starts from the
        same load's solution on ``n // NESTED_FACTOR`` cells, interpolated in ln p (none if it
        did not converge); its work goes to ``diagnostics["nested_start"]`` (its FFT
        convolutions are of length n / 4, not counted in ``convolutions``)."""
        if not self._nests():
            return None, None
        coarse_model = self._nested_model()
        coarse = coarse_model._solve(load, None)
        start = _rescaled_start(grid, coarse) if coarse.converged else None
        work = dict(n=coarse_model.n, convolutions=coarse.convolutions, used=start is not None)
        return start, {"nested_start": work}

    def _nests(self) -> bool:
        """Whether a cold solve starts from a coarser grid's solution (:data:`NESTED_MIN_N`):
        Newton with a pressure law (the hard contact's active set needs no start)."""
        return self.n >= NESTED_MIN_N and self._law is not None and self.method == "newton"

    def _nested_model(self) -> LineContact:
        """This model on ``n // NESTED_FACTOR`` cells of the same domain, silent; made once
        (sharing theory, law and settings). A race between threads makes two equal copies."""
        other = self.__dict__.get("_nested")
        if other is None:
            other = copy.copy(self)
            other.__dict__.pop("_nested", None)
            other.n = other._n_given = self.n // NESTED_FACTOR
            other.accuracy, other.warn = None, False
            self._nested = other
        return other

    def _with_grid(self, n: int, half_width: float) -> LineContact:
        """This model on ``n`` cells over ``[-half_width, half_width]`` (m), one solve per
        load, silent: a grid of the accuracy loop. Shares theory, law and settings."""
        other = copy.copy(self)
        other.__dict__.pop("_nested", None)
        other.n, other._n_given, other.half_width = n, n, half_width
        other.accuracy, other.warn = None, False
        return other

    # -- solve stages -------------------------------------------------------------------------
    def _grid(self, load: float) -> _LineGrid:
        hz = hertz_line_unchecked(self.E_star, self.radius, load)  # checked by the caller
        half = self._extent("half_width", self.half_width, hz, load)
        return _build_grid(self.n, half, self.radius, self.E_star, hz)

    def _gaussian(self, load: float):
        u0 = self._u0()
        if type(u0) is float and 0.0 < u0 < math.inf:  # what the checks would pass unchanged
            return gaussian_line_unchecked(u0, self.radius, load)
        return gaussian_line_contact(u0, self.radius, load)

    def _cold_tail(self, hz, ln_h: float, ln_g: float) -> tuple[float, float]:
        """The cold start outside the Hertz contact: ``ln p = ln_t - k_t G(|x|/a)``, the
        exponential law ``p ~ exp(-u/u0)`` (paper eq. 5) at Hertz's gap ``(a^2/2R) G``
        (:func:`fastline.contact.kernels.hertz_line_gap`), so ``k_t = a^2 / (2 R u0)``. It starts
        at ``ln_t``, the (weighted) Hertz pressure ``COLD_TAIL_DEPTH`` edge layers inside the
        edge, the layer being the depth ``e a`` at which the gap outside, ``(a^2/2R) (4 sqrt(2)
        / 3) e^(3/2)``, reaches u0, capped at the law's pressure at ``COLD_TAIL_CAP u0``.
        Without it the Gaussian alone is the tail, 1e2-1e4 u0 off below alpha = 0.01 (the
        first Newton residual). None (``ln_t = -inf``) unless the contact is Hertz-like,
        ``k_t >= COLD_TAIL_MIN_K``: ``ln_g`` (the Gaussian's) is not used."""
        u0 = self._u0()
        k_t = hz.a * hz.a / (2.0 * self.radius * u0)
        if k_t < COLD_TAIL_MIN_K:
            return -math.inf, 0.0
        layer = (3.0 / (4.0 * math.sqrt(2.0) * k_t)) ** (2.0 / 3.0)
        ln_t = ln_h + 0.5 * math.log(2.0 * COLD_TAIL_DEPTH * min(layer, 0.5))
        return min(ln_t, self._tail_cap()), k_t

    def _tail_cap(self) -> float:
        """ln of the law's pressure at ``COLD_TAIL_CAP u0`` (the cold start's tail starts no
        higher), made once per model: the law does not change (asked per solve, it cost ~8 us
        of a ~25 us Python budget)."""
        cap = self.__dict__.get("_cap")
        if cap is None:
            u = np.array([COLD_TAIL_CAP * self._u0()])
            cap = self._cap = float(np.asarray(_core._log_pressure(self._law, u))[0])
        return cap

    def _rescaled_start(self, grid: _LineGrid, initial: LineContactResult) -> np.ndarray:
        return _rescaled_start(grid, initial)

    def _result(
        self,
        grid: _LineGrid,
        out: _core.Outcome,
        measures: tuple[float, float, float, float] | None = None,
    ) -> LineContactResult:
        """The result of ``out`` on ``grid``; ``measures``: ``(p0, s, fwhm, sum p)`` of the
        profile if the caller has them (:func:`_measures`)."""
        x, dx, hz = grid.x, grid.dx, grid.hertz
        p = out.pressure
        separation, real = self._separation_and_area(out)
        p0, s, w, total = _measures(x, p, dx) if measures is None else measures
        op = grid.disc.op
        alpha = self._alpha(hz.delta)
        return LineContactResult(
            x=x,
            pressure=p,
            separation=separation,
            real_area=real,
            p0=p0,
            s=s,
            fwhm=w,
            w_over_s=w / s,
            p0_ratio=p0 / hz.p0,
            alpha=alpha,
            delta=hz.delta,
            u1=out.u1 + log_reference_shift_unchecked(hz.load, dx, self.E_star, self.radius),
            converged=bool(out.converged),
            iterations=int(out.iterations),
            convolutions=int(op.convolutions),
            residual=float(out.residual),
            message=self._message(out, alpha),
            model=self.model,
            method=self.method,
            load=hz.load,
            radius=self.radius,
            E_star=self.E_star,
            dx=dx,
            force_error=abs(total * dx - hz.load) / hz.load,
            edge_pressure=float(max(p[0], p[-1]) / p0),
            diagnostics={
                "n": self.n,
                "domain_half_width": grid.half_width,
                "k_applications": op.convolutions - op.circulant_solves,
                "circulant_solves": op.circulant_solves,
                **out.info,
            },
            theory=self._theory,
        )


# ----------------------------------------------------------------------------------------------
# one-call functions
# ----------------------------------------------------------------------------------------------
def solve_line_contact(
    psd: Spectrum, E_star: float, radius: float, load: float, **options: Any
) -> LineContactResult:
    """Solve for the nominal pressure under a rigid cylinder on a rough elastic half-space.

    ``solve_line_contact(psd, E_star, radius, load, **options)`` is
    ``LineContact(psd, E_star, radius, **options).solve(load)``; the theory of a spectrum is
    built once and shared between calls while the spectrum object lives. For many loads of one
    scene, keep a :class:`LineContact` (and use its ``sweep``).

    Parameters
    ----------
    psd : PSD, str, path-like or None
        Combined roughness spectrum or a spectrum file's path (:class:`LineContact`); None only
        with ``model="hertz"``.
    E_star : float
        Effective modulus in Pa (paper eq. 1).
    radius : float
        Cylinder radius R in m.
    load : float
        Normal load per unit length f_N in N/m.
    **options
        Keyword options of :class:`LineContact` (model, method, gamma, variant, n, half_width,
        tol, max_iter, u0, beta, theory, hardness, warn).

    Returns
    -------
    LineContactResult
    """
    return LineContact(psd, E_star, radius, **options).solve(load)


def profile(
    psd: Spectrum, E_star: float, radius: float, load: float, **options: Any
) -> tuple[np.ndarray, np.ndarray]:
    """Pressure profile ``(x [m], p [Pa])`` of one scene (see :func:`solve_line_contact`)."""
    res = solve_line_contact(psd, E_star, radius, load, **options)
    return res.x, res.pressure


def _per_load(
    attr: str, psd: Spectrum, E_star: float, radius: float, load: ArrayLike, options: dict
) -> float | np.ndarray:
    loads = real_array("load", load)  # bools and strings refused, as solve refuses them
    lc = LineContact(psd, E_star, radius, **options)
    if loads.ndim == 0:
        return float(getattr(lc.solve(float(loads)), attr))
    results = lc.sweep(loads.ravel())
    return np.array([getattr(r, attr) for r in results]).reshape(loads.shape)


def w_over_s(
    psd: Spectrum, E_star: float, radius: float, load: ArrayLike, **options: Any
) -> float | np.ndarray:
    """FWHM-to-standard-deviation ratio w/s; a float, or an array for an array of loads."""
    return _per_load("w_over_s", psd, E_star, radius, load, options)


def p0_ratio(
    psd: Spectrum, E_star: float, radius: float, load: ArrayLike, **options: Any
) -> float | np.ndarray:
    """Peak-pressure ratio p0(rough)/p0(Hertz); a float, or an array for an array of loads."""
    return _per_load("p0_ratio", psd, E_star, radius, load, options)
