"""Line contact: the nominal pressure p(x) under a cylinder on a rough half-space.

Equations (paper eqs. 3-4; docs/theory.md, "Line contact"): unknown pressure ``p(x) > 0`` and
rigid approach ``u1`` with

    u(x) = u1 + x^2/(2R) + (K p)(x),     u(x) = u_law(p(x)),     int p dx = f_N,

``K`` the plane-strain log kernel (:mod:`fastline.elastic`), ``u_law`` the pressure law
(:mod:`fastline.laws`). What is cylinder-specific lives here: the grid and its sizing, the gap
``x^2/2R``, the Hertz reference, alpha, the initial guess and the profile measures (p0, s, FWHM).
The Newton-Krylov core that solves the discrete equations is shared with other geometries
(:mod:`fastline._core`).

:class:`LineContact` is the reusable model (theory tables, law and settings built once, many
loads solved); :func:`solve_line_contact` is a one-call wrapper around it.
"""

from __future__ import annotations

import copy
import math
import threading
import warnings
from collections.abc import Callable, Iterable, Sequence
from dataclasses import dataclass, field

import numpy as np

from fastline import _core, resolution
from fastline._core import ConvergenceWarning, Discretisation, normalise
from fastline._validate import (
    E_STAR_RANGE,
    RADIUS_RANGE,
    finite_scalar,
    in_span,
    integer,
    positive,
)
from fastline.diagnostics import assess, warn_once
from fastline.elastic import LogKernelOperator, log_reference_shift
from fastline.laws import ExponentialLaw, PerssonLaw, PressureLaw, check_law
from fastline.limits import HertzLineContact, gaussian_line_contact, hertz_line_contact
from fastline.persson import PerssonTheory
from fastline.spectra import PSD

__all__ = [
    "ConvergenceWarning",
    "LineContact",
    "LineContactResult",
    "solve_line_contact",
    "profile",
    "w_over_s",
    "p0_ratio",
]

MODELS = ("persson", "exponential", "hertz")
METHODS = ("newton", "picard")
DEFAULT_N = 1024
#: largest grid (about 2 GB of working arrays)
MAX_N = 2**22
#: loads per unit length accepted, in units of E* R
LOAD_RANGE = (1e-12, 1e4)
_MAX_NEWTON = 100
_MAX_PICARD_SWEEPS = 5000


@dataclass
class LineContactResult:
    """The solution of one line-contact scene and what follows from it.

    Arrays are on the solver grid (cell centres). Units: m, Pa, N/m.

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
        Outer iterations (Newton steps, sweeps) and FFT convolutions of length 2n: applications
        of K plus the preconditioner's circulant solves (``diagnostics`` splits the two as
        ``k_applications`` and ``circulant_solves``).
    residual : float
        Final residual: max |u_law(p) - u1 - x^2/2R - K p| / u0 (for hertz: the
        complementarity error relative to delta).
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
        Solver counts and the validity checks of :func:`fastline.diagnostics.assess`.
    theory : PerssonTheory or None
        The theory the scene was solved with (None for hertz and for user laws), for
        post-processing such as leak rates.
    error_estimate : ErrorEstimate or None
        Estimated relative errors of p0, s, FWHM and w/s (:mod:`fastline.resolution`): set
        when the model has ``accuracy=`` or by :meth:`LineContact.estimate_error`, else None.
    """

    x: np.ndarray
    pressure: np.ndarray
    separation: np.ndarray
    real_area: np.ndarray | None
    p0: float
    s: float
    fwhm: float
    w_over_s: float
    p0_ratio: float
    alpha: float
    delta: float
    u1: float
    converged: bool
    iterations: int
    convolutions: int
    residual: float
    message: str
    model: str
    method: str
    load: float
    radius: float
    E_star: float
    dx: float
    force_error: float
    edge_pressure: float
    diagnostics: dict = field(default_factory=dict)
    theory: PerssonTheory | None = field(default=None, repr=False, compare=False)
    error_estimate: resolution.ErrorEstimate | None = field(default=None, repr=False, compare=False)

    def __repr__(self):
        return (
            f"LineContactResult(model={self.model!r}, alpha={self.alpha:.4g}, p0={self.p0:.6g} Pa,"
            f" w_over_s={self.w_over_s:.5g}, p0_ratio={self.p0_ratio:.5g}, "
            f"converged={self.converged}, convolutions={self.convolutions})"
        )


# ----------------------------------------------------------------------------------------------
# theories shared by the one-call functions: seal codes call them thousands of times with the
# same spectrum. The spectrum object keeps them (a private attribute), so they live exactly as
# long as it does; one lock guards the look-up.
# ----------------------------------------------------------------------------------------------
_shared_lock = threading.Lock()


def shared_theory(psd: PSD, E_star: float, gamma: float) -> PerssonTheory:
    """The :class:`PerssonTheory` of ``(psd, E_star, gamma)``, built once per spectrum object.

    Thread-safe. The theories are kept on the spectrum (dropped with it, left out of pickles).
    """
    key = (float(E_star), float(gamma))
    with _shared_lock:
        hit = psd._theories.get(key)
    if hit is not None:
        return hit
    theory = PerssonTheory(psd, E_star, gamma=gamma)  # outside the lock (milliseconds)
    with _shared_lock:
        return psd._theories.setdefault(key, theory)


# ----------------------------------------------------------------------------------------------
# profile measures
# ----------------------------------------------------------------------------------------------
def _peak(p: np.ndarray) -> float:
    """Peak value by a parabola through the three points around the discrete maximum."""
    i = int(np.argmax(p))
    if 0 < i < p.size - 1:
        a, b, c = p[i - 1], p[i], p[i + 1]
        den = a - 2.0 * b + c
        if den < 0.0:
            t = 0.5 * (a - c) / den
            return float(b - 0.25 * (a - c) * t)
    return float(p[i])


def _fwhm(x: np.ndarray, p: np.ndarray, p0: float) -> float:
    """Width between the outermost half-maximum crossings (linear interpolation)."""
    half = 0.5 * p0
    above = np.nonzero(p >= half)[0]
    i, j = above[0], above[-1]
    if i == 0 or j == p.size - 1:
        return float("nan")
    xl = x[i - 1] + (half - p[i - 1]) * (x[i] - x[i - 1]) / (p[i] - p[i - 1])
    xr = x[j] + (half - p[j]) * (x[j + 1] - x[j]) / (p[j + 1] - p[j])
    return float(xr - xl)


def _std(x: np.ndarray, p: np.ndarray, dx: float) -> float:
    """Standard deviation of piecewise-constant p about its centroid (cell-exact)."""
    m0 = p.sum()
    xc = np.dot(x, p) / m0
    var = np.dot((x - xc) ** 2, p) / m0 + dx * dx / 12.0
    return math.sqrt(var)


# ----------------------------------------------------------------------------------------------
# the grid of one load
# ----------------------------------------------------------------------------------------------
@dataclass(frozen=True)
class _LineGrid:
    """Cells of one solve: coordinates, width, the Hertz reference and the discretisation."""

    x: np.ndarray
    dx: float
    half_width: float
    hertz: HertzLineContact
    disc: Discretisation


def _build_grid(n: int, half_width: float, radius: float, E_star: float, hz) -> _LineGrid:
    dx = 2.0 * half_width / n
    x = (np.arange(n) - 0.5 * (n - 1)) * dx
    op = LogKernelOperator(n, dx, E_star)  # fresh counters per solve (threads share nothing)
    disc = Discretisation(x * x / (2.0 * radius), np.full(n, dx), op, hz.load)
    return _LineGrid(x, dx, half_width, hz, disc)


#: degree of the polynomial (in ln f_N) that predicts each solve of a sweep from the previous
#: ones. Over the paper's three 50-load sweeps (n = 1024) the total convolutions were
#: 6252 independent, 5018 / 4495 / 4244 with degree 1 / 2 / 3.
SWEEP_PREDICTOR_ORDER = 3
#: largest step in ln f_N over which the polynomial extrapolates; a longer step starts from the
#: previous solution rescaled (degree 0). An O-ring sweep of 6-12 loads over 10..1e4 N/m (steps
#: of ln 2-ln 4) failed to converge from cubic predictions and converged from degree 0.
PREDICTOR_MAX_STEP = math.log(1.5)
#: below this alpha a sweep starts each solve cold (Hertz-Gaussian blend) instead of from the
#: prediction: in the Hertz-like regime the blend's error, though large, is removed by the
#: first Newton step, while the prediction's small error sits at the contact edge and costs
#: more steps (surface 3, n = 1024: 35 cold vs 40 predicted convolutions at alpha 7e-4, 45 vs
#: 43 at 5.6e-3, 37 vs 23 at 0.13).
SWEEP_WARM_ALPHA = 5e-3


def _log_pressure(result: LineContactResult) -> np.ndarray:
    return np.log(np.maximum(result.pressure, 1e-300))


def _warn_sweep(results: list) -> None:
    """One ConvergenceWarning for the loads that did not converge, one ValidityWarning per
    cause (the caller of ``sweep`` sees them)."""
    failed = [r.load for r in results if not r.converged]
    if failed:
        loads = ", ".join(f"{f:.4g}" for f in failed)
        warnings.warn(
            f"fastline: {len(failed)} of {len(results)} solves did not converge "
            f"(loads {loads} N/m); see each result's message",
            ConvergenceWarning,
            stacklevel=3,
        )
    warn_once(results, stacklevel=3)


def _rescaled_start(grid: _LineGrid, initial: LineContactResult) -> np.ndarray:
    """ln p of a neighbouring solution at the same relative position in the domain (the default
    domain scales with the contact), interpolated onto this grid; the load is restored later."""
    xi = initial.x / (0.5 * initial.x.size * initial.dx)
    return np.interp(grid.x / grid.half_width, xi, _log_pressure(initial))


class LineContact:
    """A reusable line-contact model: one spectrum, material, cylinder and law, many loads.

    It owns what every solve reuses: the Persson theory and its tables, the pressure law, the
    grid policy and the solver settings. FFT plans and kernel spectra are shared per grid size
    by all models (:mod:`fastline.elastic`). An instance is safe to share between threads
    (``solve`` changes no state of the model) and pickles (the theory's tables travel with it).

    Parameters
    ----------
    psd : PSD or None
        Combined roughness spectrum (m^4 vs 1/m). None only with ``model="hertz"`` or a user
        law (then alpha is not defined and reported as NaN).
    E_star : float
        Effective modulus in Pa (paper eq. 1), in [1, 1e13].
    radius : float
        Cylinder radius R in m, in [1e-9, 1e3].
    model : {"persson", "exponential", "hertz"} or PressureLaw
        p(u) relation: full Persson theory (default), the exponential law (paper eq. 5, u0 and
        beta from the theory unless given), hard contact of smooth surfaces, or a pressure law
        object (:mod:`fastline.laws`: :class:`~fastline.laws.TabulatedLaw`, your own).
    method : {"newton", "picard"}
        Newton-Krylov (default) or the plain damped fixed point (for comparison).
    gamma : float
        Yang-Persson parameter of the theory, in (0, 1] (default 0.45).
    n : int, optional
        Grid points, in [16, 2^22] (default 1024; with ``accuracy``, the first grid tried).
    half_width : float, optional
        Half-width of the domain in m, the same for every load, at most 1e3 R and at least the
        Hertz half-width ``a`` of each load solved; default per load ``1.25 a + 8 sqrt(R u0)``.
    tol : float
        Residual tolerance (separation mismatch in units of u0; hertz: relative pressure
        change), in (0, 1e-2].
    max_iter : int, optional
        Newton steps / fixed-point sweeps allowed (defaults 100 / 5000; the fixed point also
        stops when it stagnates, see :func:`fastline._core.picard`).
    u0, beta : float, optional
        Exponential-law parameters for ``model="exponential"`` (m, dimensionless).
    theory : PerssonTheory, optional
        A prebuilt theory for ``psd`` and ``E_star`` (its gamma is used).
    hardness : float, optional
        Indentation hardness of the softer solid in Pa, for the plasticity diagnostic.
    warn : bool
        Emit a ``ConvergenceWarning`` when a solve does not converge and the diagnostics'
        ``ValidityWarning`` s.
    accuracy : float, optional
        Relative error wanted in p0, s and w/s, in [1e-8, 0.1] (not for ``model="hertz"``):
        each load is solved on grids refined until the estimated error is below it, and every
        result carries ``error_estimate`` (:mod:`fastline.resolution`, docs/accuracy.md).
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

    def __init__(
        self,
        psd: PSD | None,
        E_star: float,
        radius: float,
        *,
        model: str | PressureLaw = "persson",
        method: str = "newton",
        gamma: float = 0.45,
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
    ):
        self.E_star = in_span("E_star", E_star, E_STAR_RANGE, "Pa")
        self.radius = in_span("radius", radius, RADIUS_RANGE, "m")
        if method not in METHODS:
            raise ValueError(f"method must be one of {METHODS}, got {method!r}")
        self.method = method
        if n is not None:
            n = integer("n", n, 16, MAX_N, " (a solve needs about 500 bytes per cell)")
        self._n_given = n  # with accuracy=, the first grid tried
        self.n = DEFAULT_N if n is None else n
        self.accuracy = resolution.check_accuracy(accuracy)
        self.half_width = None
        if half_width is not None:
            self.half_width = in_span("half_width", half_width, (0.0, 1e3 * self.radius), "m")
        self.tol = finite_scalar("tol", tol)
        if not 0.0 < self.tol <= 1e-2:
            raise ValueError(f"tol must lie in (0, 1e-2], got {tol!r}")
        self.max_iter = None if max_iter is None else integer("max_iter", max_iter, 1)
        self.hardness = None if hardness is None else positive("hardness", hardness, "Pa")
        self.warn = bool(warn)
        if psd is not None and not isinstance(psd, PSD):
            raise TypeError(f"psd must be a fastline PSD or None, got {type(psd).__name__}")
        if theory is not None and not isinstance(theory, PerssonTheory):
            raise TypeError(f"theory must be a PerssonTheory or None, got {type(theory).__name__}")
        self.psd = psd
        self._theory, self._law = self._resolve_model(model, psd, theory, gamma, u0, beta)
        self.model = "hertz" if self._law is None else self._law.name
        if self.accuracy is not None and self._law is None:
            raise ValueError("accuracy needs a pressure law (model='hertz' converges at order ~1)")

    # -- construction stages ----------------------------------------------------------------
    def _resolve_model(self, model, psd, theory, gamma, u0, beta):
        """(theory or None, law or None for hertz) from the ``model`` argument."""
        if isinstance(model, str):
            if model not in MODELS:
                raise ValueError(f"model must be one of {MODELS} or a pressure law, got {model!r}")
            if model == "hertz":
                return None, None
            if psd is None:
                raise ValueError(f"psd must be a PSD for model={model!r} (None only for 'hertz')")
            if theory is None:
                theory = shared_theory(psd, self.E_star, finite_scalar("gamma", gamma))
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

    def __repr__(self):
        return (
            f"LineContact({self.psd!r}, E_star={self.E_star!r}, radius={self.radius!r}, "
            f"model={self.model!r}, method={self.method!r}, n={self.n})"
        )

    # -- solving ------------------------------------------------------------------------------
    def solve(self, load: float, initial: LineContactResult | None = None) -> LineContactResult:
        """Solve one load (N/m); ``initial`` is a neighbouring solution to start from.

        Stages: check the load, size the grid, make the initial guess, run the core method,
        measure the profile, run the diagnostics.
        """
        load = self._check_load("load", load)
        if initial is not None and not isinstance(initial, LineContactResult):
            raise TypeError(
                f"initial must be a LineContactResult or None, got {type(initial).__name__}"
            )
        if self.accuracy is not None:  # grids chosen by the error estimate
            return resolution.solve_to_accuracy(self, load, initial)
        grid = self._grid(load)
        start = None if initial is None else _rescaled_start(grid, initial)
        return self._solve_on(grid, start, self.warn)

    def _solve_on(self, grid: _LineGrid, start: np.ndarray | None, warn: bool) -> LineContactResult:
        """Run the core from ``start`` (ln p; None: cold) and finish the result."""
        outcome = self._run(grid, start)
        result = self._result(grid, outcome)
        if not result.converged and warn:
            warnings.warn(f"fastline: {result.message}", ConvergenceWarning, stacklevel=3)
        result.diagnostics.update(assess(result, self._theory, self.hardness, warn=warn))
        return result

    def sweep(
        self, loads: Iterable[float], progress: Callable[[], object] | None = None
    ) -> list[LineContactResult]:
        """Solve a series of loads (N/m) by continuation; results in the order given.

        The loads are solved in increasing order. Each solve starts from a prediction made
        from the solutions already found: ln p on the (relative) grid extrapolated in ln f_N
        by a polynomial through the last ``SWEEP_PREDICTOR_ORDER + 1`` of them. Over the
        paper's 50-load sweeps this costs fewer FFT convolutions than independent solves
        (docs/performance.md gives the figure); each result is the converged solution at its
        load, equal to an independent solve to the solver tolerance. Warnings are emitted once
        per cause for the whole sweep, naming the loads concerned
        (:func:`fastline.diagnostics.warn_once`). ``progress``, if given, is called with no
        argument after each solve (e.g. a tqdm bar's ``update``).
        """
        loads = self._check_loads(loads)
        if self.accuracy is not None:  # each load on its own grids: no continuation
            return resolution.sweep_to_accuracy(self, loads, progress)
        out: list[LineContactResult | None] = [None] * loads.size
        history: list[tuple[float, np.ndarray]] = []  # (ln f_N, ln p on the grid)
        for i in np.argsort(loads, kind="stable"):
            grid = self._grid(float(loads[i]))
            result = self._solve_on(grid, self._predict(grid, history), warn=False)
            if not result.converged and history:  # the prediction misled Newton: start cold
                cold = self._solve_on(grid, None, warn=False)
                cold.convolutions += result.convolutions  # count all the work done
                cold.diagnostics["restarted_cold"] = True
                result = cold
            history = (history + [(math.log(grid.hertz.load), _log_pressure(result))])[-4:]
            out[i] = result
            if progress is not None:
                progress()
        if self.warn:
            _warn_sweep(out)
        return out  # type: ignore[return-value]

    def estimate_error(self, result: LineContactResult) -> resolution.ErrorEstimate:
        """Relative errors of a result of this model from one companion solve on the same
        domain (:func:`fastline.resolution.estimate_error`); also stored as
        ``result.error_estimate``."""
        resolution.check_result(self, result)
        if self._law is None:
            raise ValueError("estimate_error needs a pressure law (not model='hertz')")
        return resolution.estimate_error(self, result)

    def _with_grid(self, n: int, half_width: float) -> LineContact:
        """This model on ``n`` cells over ``[-half_width, half_width]`` (m), one solve per
        load, silent: a grid of the accuracy loop. Shares theory, law and settings."""
        other = copy.copy(self)
        other.n, other._n_given, other.half_width = n, n, half_width
        other.accuracy, other.warn = None, False
        return other

    def _check_load(self, name: str, load) -> float:
        """A load per unit length in [1e-12, 1e4] E* R (N/m): the Hertz half-width stays
        between 1e-6 R and ~100 R, where every quantity of the solve is representable."""
        lo, hi = LOAD_RANGE
        scale = self.E_star * self.radius
        return in_span(name, load, (lo * scale, hi * scale), f"N/m ([{lo:g}, {hi:g}] E* R)")

    def _check_loads(self, loads) -> np.ndarray:
        arr = np.asarray(loads if isinstance(loads, np.ndarray) else list(loads), dtype=float)
        if arr.ndim != 1 or arr.size == 0:
            raise ValueError("loads must be a non-empty 1-D sequence of loads in N/m")
        for f in arr:
            self._check_load("loads", f)
        return arr

    # -- solve stages -------------------------------------------------------------------------
    def _u0(self) -> float:
        return 0.0 if self._law is None else self._law.u0

    def _grid(self, load: float) -> _LineGrid:
        hz = hertz_line_contact(self.E_star, self.radius, load)
        half = self.half_width
        if half is None:
            half = 1.25 * hz.a + 8.0 * math.sqrt(self.radius * self._u0())
        elif half < hz.a:
            raise ValueError(
                f"half_width = {half:.6g} m cuts the contact: at load {load:.6g} N/m the Hertz "
                f"half-width alone is a = {hz.a:.6g} m; give half_width >= a (the default, "
                "None, sizes the domain as 1.25 a + 8 sqrt(R u0))"
            )
        return _build_grid(self.n, half, self.radius, self.E_star, hz)

    def _alpha(self, delta: float) -> float:
        """h_rms / delta; 0 for smooth surfaces (hertz without a spectrum), NaN when unknown."""
        if self.psd is None:
            return 0.0 if self._law is None else float("nan")
        return self.psd.h_rms / delta

    def _cold_start(self, grid: _LineGrid) -> np.ndarray:
        """ln p to start from without a neighbour: Hertz and Gaussian profiles blended."""
        x, load, hz = grid.x, grid.hertz.load, grid.hertz
        if self._law is None:  # hard contact: uniform pressure on the central third
            return np.where(np.abs(x) <= grid.half_width / 3.0, 0.0, -np.inf)
        alpha = self._alpha(hz.delta)
        if not math.isfinite(alpha):
            alpha = 2.0 * self._u0() / hz.delta
        gs = gaussian_line_contact(self._u0(), self.radius, load)
        # weights alpha/(alpha + 0.3) and 0.3/(alpha + 0.3), in logarithms (no 1 - 1 at huge alpha)
        ln_wh = math.log(0.3) - math.log(alpha + 0.3)
        ln_wg = math.log(alpha) - math.log(alpha + 0.3)
        with np.errstate(divide="ignore"):
            lh = ln_wh + math.log(hz.p0) + 0.5 * np.log(np.maximum(1 - (x / hz.a) ** 2, 0))
        lg = ln_wg + math.log(gs.p0) - x * x / (2.0 * gs.s**2)
        return normalise(np.logaddexp(lh, lg), load, grid.disc.weights)

    def _predict(self, grid: _LineGrid, history: list[tuple[float, np.ndarray]]):
        """ln p at this load extrapolated from earlier solutions of this model (same grid
        shape), by the Lagrange polynomial in ln f_N through the last ones; None if none."""
        if not history or self._alpha(grid.hertz.delta) < SWEEP_WARM_ALPHA:
            return None
        t = math.log(grid.hertz.load)
        order = SWEEP_PREDICTOR_ORDER if t - history[-1][0] <= PREDICTOR_MAX_STEP else 0
        pts = history[-(order + 1) :]
        v = np.zeros(self.n)
        for i, (ti, vi) in enumerate(pts):
            weight = math.prod((t - tj) / (ti - tj) for j, (tj, _) in enumerate(pts) if j != i)
            v += weight * vi
        return v

    def _run(self, grid: _LineGrid, start: np.ndarray | None) -> _core.Outcome:
        v = self._cold_start(grid) if start is None else start
        if self._law is None:
            max_iter = self.max_iter or 10 * self.n
            p = _core.pressure_of(v)  # exactly 0 off the predicted contact
            return _core.hard_contact(grid.disc, p, grid.hertz.delta, self.tol, max_iter)
        v = normalise(v, grid.hertz.load, grid.disc.weights)
        if self.method == "newton":
            return _core.newton(grid.disc, self._law, v, self.tol, self.max_iter or _MAX_NEWTON)
        return _core.picard(grid.disc, self._law, v, self.tol, self.max_iter or _MAX_PICARD_SWEEPS)

    def _result(self, grid: _LineGrid, out: _core.Outcome) -> LineContactResult:
        x, dx, hz = grid.x, grid.dx, grid.hertz
        p = out.pressure
        if self._law is None:
            separation, real = out.separation, (p > 0.0).astype(float)
        else:
            separation = self._law.separation_and_slope(out.v)[0]
            real = self._law.real_area(p)
        p0 = _peak(p)
        s = _std(x, p, dx)
        w = _fwhm(x, p, p0)
        op = grid.disc.op
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
            alpha=self._alpha(hz.delta),
            delta=hz.delta,
            u1=out.u1 + log_reference_shift(hz.load, dx, self.E_star, self.radius),
            converged=bool(out.converged),
            iterations=int(out.iterations),
            convolutions=int(op.convolutions),
            residual=float(out.residual),
            message=out.message,
            model=self.model,
            method=self.method,
            load=hz.load,
            radius=self.radius,
            E_star=self.E_star,
            dx=dx,
            force_error=abs(p.sum() * dx - hz.load) / hz.load,
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
    psd: PSD | None, E_star: float, radius: float, load: float, **options
) -> LineContactResult:
    """Solve for the nominal pressure under a rigid cylinder on a rough elastic half-space.

    ``solve_line_contact(psd, E_star, radius, load, **options)`` is
    ``LineContact(psd, E_star, radius, **options).solve(load)``; the theory of a spectrum is
    built once and shared between calls while the spectrum object lives. For many loads of one
    scene, keep a :class:`LineContact` (and use its ``sweep``).

    Parameters
    ----------
    psd : PSD or None
        Combined roughness spectrum; None only with ``model="hertz"``.
    E_star : float
        Effective modulus in Pa (paper eq. 1).
    radius : float
        Cylinder radius R in m.
    load : float
        Normal load per unit length f_N in N/m.
    **options
        Keyword options of :class:`LineContact` (model, method, gamma, n, half_width, tol,
        max_iter, u0, beta, theory, hardness, warn, accuracy).

    Returns
    -------
    LineContactResult
    """
    return LineContact(psd, E_star, radius, **options).solve(load)


def profile(psd, E_star, radius, load, **options) -> tuple[np.ndarray, np.ndarray]:
    """Pressure profile ``(x [m], p [Pa])`` of one scene (see :func:`solve_line_contact`)."""
    res = solve_line_contact(psd, E_star, radius, load, **options)
    return res.x, res.pressure


def _per_load(attr: str, psd, E_star, radius, load, options) -> float | np.ndarray:
    loads = np.asarray(load, dtype=np.float64)
    lc = LineContact(psd, E_star, radius, **options)
    if loads.ndim == 0:
        return float(getattr(lc.solve(float(loads)), attr))
    results = lc.sweep(loads.ravel())
    return np.array([getattr(r, attr) for r in results]).reshape(loads.shape)


def w_over_s(psd, E_star, radius, load: float | Sequence[float], **options):
    """FWHM-to-standard-deviation ratio w/s; a float, or an array for an array of loads."""
    return _per_load("w_over_s", psd, E_star, radius, load, options)


def p0_ratio(psd, E_star, radius, load: float | Sequence[float], **options):
    """Peak-pressure ratio p0(rough)/p0(Hertz); a float, or an array for an array of loads."""
    return _per_load("p0_ratio", psd, E_star, radius, load, options)
