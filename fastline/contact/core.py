"""The contact core shared by every geometry: Newton-Krylov, damped fixed point, hard contact.

A geometry (the cylinder of :mod:`fastline.contact.line`, later the sphere) reduces a scene to a
:class:`Discretisation`:

* ``gap`` - the rigid gap ``g_i`` of each cell in m (``x^2/2R`` for a cylinder);
* ``weights`` - the load ``w_i`` carried by unit pressure on cell i (cell width dx in m for a line
  contact, so that ``sum(w p)`` is a load per unit length; a ring area in m^2 for a sphere);
* ``op`` - the elastic operator: ``op.apply(p) -> K p`` in m (the displacement at each cell),
  ``op.preconditioner(D)`` returning an approximate inverse of ``D + K`` on zero-load
  increments, and the counters ``op.convolutions`` / ``op.circulant_solves``;
* ``load`` - the total load ``sum(w p)`` to carry.

The core never looks at coordinates. Equations (docs/theory.md, "Line contact"): unknown
pressure ``p_i > 0`` and rigid approach ``u1`` with

    u_law(p_i) = u1 + g_i + (K p)_i,        sum_i w_i p_i = load.

Symmetry: ``W K`` (W = diag(w)) is symmetric for an energy-consistent discretisation, so the
Newton matrix ``D + K`` is self-adjoint in the inner product ``<a, b> = sum_i w_i a_i b_i`` and
positive definite on the zero-load subspace ``<1, dp> = 0`` (docs/theory.md). Projected
conjugate gradients therefore work in that inner product; for a uniform grid it is the plain one.

Methods (each returns an :class:`Outcome`):

* :func:`newton` - Newton on ``v = ln p`` in the u(p) form (default, robust in the stiff
  Hertz-like regime);
* :func:`picard` - the plain damped fixed point ``p <- p_law(u1 + g + K p)``, kept for comparison;

Smooth surfaces (``p >= 0``, ``gap >= 0``, ``p gap = 0``) are solved in
:mod:`fastline.contact.hard`, on the same :class:`Discretisation`.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any, Protocol

import numpy as np

from fastline.contact import kernels
from fastline.errors import ConvergenceWarning

if TYPE_CHECKING:
    from fastline.theory.laws import PressureLaw

__all__ = [
    "ConvergenceWarning",
    "Discretisation",
    "Outcome",
    "dot",
    "newton",
    "picard",
]

ETA_MAX, ETA_FLOOR = 0.1, 1e-3  # inexact-Newton forcing term bounds
#: every step's forcing is at least ``min(ETA_MAX, ETA_RES_SCALE * res)`` (eta ~ ||F||, which keeps
#: Newton's quadratic rate: Dembo, Eisenstat & Steihaug, SIAM J. Numer. Anal. 19, 400 (1982)).
#: Eisenstat-Walker alone asks ``eta = 1e-3`` at the second step of a cold start at alpha <= 1e-2,
#: since the first step cuts the residual ~100x, from 1e2-1e3 to ~1.5, while the next steps are
#: still far from the quadratic regime (1.5 -> 0.2 at any eta): 5-13 CG iterations for nothing. Over
#: the 160 count scenes (5 hard surfaces, alpha 1e-4..1e3, n 256..16384) the total fell 4643 -> 4446
#: convolutions with 0.5 (2: 4459; 0.25 with the aggregates of
#: :func:`fastline.elastic.preconditioner._aggregate_edges`: 1% more than 0.5). The first step has
#: no Eisenstat-Walker history and takes these floors alone: a start already close to the solution
#: (a sweep's prediction, res0 ~ 1e-3) is solved to ETA_FLOOR instead of ETA_MAX, which saves a
#: Newton step. (It had a rule of its own, ``min(ETA_MAX, 5 res0)``: the paper's 50-load sweeps 1089
#: -> 1054 convolutions on surface 3 against ETA_MAX. Since each Newton system lost its circulant
#: solve of ``B 1`` (docs/performance.md) the floors alone do better: the 50-load sweeps 470 / 473 /
#: 629 -> 470 / 468 / 609 convolutions, the 64-load sweeps at n = 256 553 / 553 / 561 -> 554 / 548 /
#: 562, the sphere's 20-load sweeps and the 160 count scenes, nested starts included, unchanged; 2
#: res0 and 1 res0 fell between, 617 and 611 on surface 3.)
ETA_RES_SCALE = 0.5
MAX_CG = 400
#: largest change of ln p per Newton step where p > 1e-6 max(p) (2 cost 5% more convolutions
#: over 40 hard scenes and up to 1.7x more near alpha = 0.1; 8 keeps a guard against overflow)
DV_MAX = 8.0
#: halvings the line search tries before it declares the direction useless
LINE_SEARCH_HALVINGS = 10
#: tightest inner accuracy the safeguard asks for before a solve is declared stalled
ETA_RETRY_MIN = 1e-12
#: round-off floor of the residual in units of eps * (size of the cancelling terms), see
#: :func:`roundoff_floor` (6x the largest FFT error measured)
ROUNDOFF_FACTOR = 16.0
#: a line search that fails below this multiple of a raised (round-off) tolerance ends the solve
#: as converged: the residual there is noise (seen at alpha 8e-14 and 8e-9, R = 1 km)
FLOOR_STALL = 4.0
#: the damped fixed point stops when its best residual improved by less than this fraction...
PICARD_STAGNATION = 0.01
#: ...over this many accepted sweeps
PICARD_WINDOW = 200
#: ...or when, at the rate of that window, reaching the tolerance needs more than this many
#: times the sweeps max_iter leaves. The converged fixed points of the sphere (paper surfaces
#: 1-3 and q1/q0 = 1e10, both laws, alpha 3e-3..10, n = 128: 25-4,519 sweeps) asked at most
#: 0.77 times the sweeps left at any window; those that did not converge, 10-700 times
PICARD_SLOW = 3.0
_EPS = float(np.finfo(np.float64).eps)


class Operator(Protocol):
    """What the core needs of an elastic operator (see the module docstring)."""

    convolutions: int
    circulant_solves: int

    def apply(self, p: np.ndarray) -> np.ndarray: ...

    def preconditioner(self, D: np.ndarray) -> Any: ...


@dataclass
class Discretisation:
    """A scene reduced to what the core needs (module docstring). Units: m, Pa, N or N/m."""

    gap: np.ndarray
    weights: np.ndarray
    op: Operator
    load: float
    #: the whole Newton iteration in one compiled call, where the geometry has one
    #: (the line contact: :func:`fastline.contact.line_newton.solve_compiled`), or None
    compiled: Callable | None = None


@dataclass
class Outcome:
    """What a core method returns (one type for every method).

    Attributes
    ----------
    v : ndarray
        ``ln p`` on the cells (p in Pa); for :func:`hard_contact` the pressure itself is in
        ``pressure`` and ``v`` is None.
    u1 : float
        Rigid approach in m (reference length of the geometry's kernel).
    residual : float
        Final residual in the method's own unit (see each method).
    converged : bool
    iterations : int
        Newton steps, fixed-point sweeps or constrained-CG iterations.
    message : str
    info : dict
        Method-specific counts (``cg_iterations``, ``damping``...).
    pressure : ndarray, optional
        Pressure in Pa (always set; ``exp(v)`` for the p(u) methods).
    separation : ndarray, optional
        The gap (hard contact), or the law's separation at the final iterate when the method
        computed it (the compiled Newton), in m; None otherwise (the caller asks the law).
    """

    v: np.ndarray | None
    u1: float
    residual: float
    converged: bool
    iterations: int
    message: str
    info: dict = field(default_factory=dict)
    pressure: np.ndarray | None = None
    separation: np.ndarray | None = None


# ----------------------------------------------------------------------------------------------
# shared pieces
# ----------------------------------------------------------------------------------------------
def dot(a: np.ndarray, b: np.ndarray) -> float:
    """``sum(a * b)`` without BLAS: NumPy's ``dot`` hands vectors above ~10^4 elements to a
    threaded BLAS, and on a loaded machine (a cluster node running many solvers) its threads
    fight for cores: at n = 16384 one ``np.dot`` measured 7.8 ms against 12 us for this."""
    return float(np.add.reduce(a * b))


def normalise(v: np.ndarray, load: float, weights: np.ndarray) -> np.ndarray:
    """Shift v so that ``sum(w exp(v)) = load`` exactly (log-sum-exp, no overflow; terms below
    e^-460 of the largest are left out rather than computed as slow subnormal numbers)."""
    out = np.array(v, dtype=np.float64)
    w = np.ascontiguousarray(weights, dtype=np.float64)
    kernels.normalise_into(out, float(load), w)
    return out


def pressure_of(v: np.ndarray) -> np.ndarray:
    """exp(v), flushed to 0 below 1e-200 of the peak and below 1e-290 Pa (``LN_FLOOR``)."""
    v = np.ascontiguousarray(v, dtype=np.float64)
    p = np.empty_like(v)
    kernels.pressure_into(v, p)
    return p


def _forcing(res: float, res_prev: float, eta_prev: float, tol: float) -> float:
    """Relative accuracy of the inner linear solve (inexact Newton).

    Eisenstat & Walker's choice 2 (SIAM J. Sci. Comput. 17, 16 (1996)): loose while the residual
    falls slowly, tight when Newton converges fast; never tighter than ``ETA_FLOOR`` nor than
    what is needed to reach ``tol`` in this step. Against a fixed 1e-2 it saved 5% of the
    convolutions over 40 hard scenes at n = 1024 (total 1565 -> 1487, worst 99 -> 90). Never
    tighter than ``ETA_RES_SCALE * res`` either (far from the solution a tight inner solve buys
    nothing).
    """
    if math.isnan(res_prev):  # the first step: the floors below alone
        eta = 0.0
    else:
        eta = 0.9 * (res / res_prev) ** 2
        if 0.9 * eta_prev**2 > 0.1:
            eta = max(eta, 0.9 * eta_prev**2)
    return min(ETA_MAX, max(eta, ETA_RES_SCALE * res, ETA_FLOOR, 0.5 * tol / res))


def _projected_pcg(op, D, w, rhs, prec, rtol, maxit):
    """Solve ``(D + K) dp + du1 = rhs`` with ``<1, dp> = sum(w dp) = 0`` by projected PCG.

    CG runs in the inner product ``<a, b> = sum(w a b)`` in which ``D + K`` is self-adjoint
    (module docstring). The projection keeps every search direction at zero net load, where
    ``D + K`` is positive definite; ``du1`` is the multiplier. The load itself is restored
    exactly by :func:`normalise` after the step, so the increment carries none.
    Returns ``dp, du1, iterations``.
    """
    m1 = prec(np.ones_like(rhs))
    sm = dot(w, m1)

    def proj(y):
        my = prec(y)
        lam = dot(w, my) / sm
        return my - lam * m1, lam

    dp = np.zeros_like(rhs)
    res = rhs.copy()
    z, lam = proj(res)
    wres = w * res
    rz = dot(wres, z)
    rz0 = rz
    d = z.copy()
    it = 0
    while it < maxit and rz > rtol * rtol * rz0 and rz > 0.0:
        Hd = D * d + op.apply(d)
        a = rz / dot(w * d, Hd)
        dp += a * d
        res -= a * Hd
        z, lam = proj(res)
        rz_new = dot(w * res, z)
        d = z + (rz_new / rz) * d
        rz = rz_new
        it += 1
    return dp, lam, it


# ----------------------------------------------------------------------------------------------
# Newton on v = ln p
# ----------------------------------------------------------------------------------------------
@dataclass
class _Iterate:
    """A Newton iterate on ``v = ln p`` and what follows from it."""

    v: np.ndarray
    p: np.ndarray
    U: np.ndarray  # the law's separation u_law(p) [m]
    dU: np.ndarray  # du_law / dv [m]
    u1: float
    gk: np.ndarray  # rigid gap plus elastic displacement g + K p [m]
    r: np.ndarray  # residual u_law - u1 - g - K p [m]
    phi: float  # ||r||_2, the line search's merit
    size: float  # largest term the residual subtracts, max(|g + K p|, |u1|) [m]


def _newton_direction(disc: Discretisation, D: np.ndarray, r: np.ndarray, eta: float):
    """``dp, du1, CG iterations`` of the Newton system: the operator's own compiled solver when
    it has one (the line contact), projected PCG with its preconditioner otherwise."""
    solve = getattr(disc.op, "solve_newton", None)
    out = None if solve is None else solve(D, disc.weights, r, eta, MAX_CG)
    if out is None:
        out = _projected_pcg(disc.op, D, disc.weights, r, disc.op.preconditioner(D), eta, MAX_CG)
    return out


def _evaluate(disc: Discretisation, law, v: np.ndarray, u1: float | None) -> _Iterate:
    """Pressure, law, elastic displacement and residual at ``v`` (one K application).

    ``u1=None`` takes the load-weighted least-squares value of the rigid approach.
    """
    p = pressure_of(v)
    U, dU = law.separation_and_slope(v)
    gk = disc.gap + disc.op.apply(p)
    if u1 is None:
        u1 = dot(disc.weights * p, U - gk) / dot(disc.weights, p)
    r = U - u1 - gk
    size = max(float(np.max(np.abs(gk))), abs(u1))
    return _Iterate(v, p, U, dU, u1, gk, r, float(np.linalg.norm(r)), size)


def law_fault(law, v: np.ndarray, U: np.ndarray, dU: np.ndarray) -> str | None:
    """What is wrong when the law's separation ``U`` or slope ``dU`` at ``v = ln p`` is not
    finite (NaN or inf), in words naming the law and the pressures; None when all are finite."""
    bad = ~(np.isfinite(U) & np.isfinite(dU))
    if not bad.any():
        return None
    with np.errstate(over="ignore"):
        p = np.exp(v[bad])
    i = int(np.flatnonzero(bad)[0])
    return (
        f"the pressure law {type(law).__name__} returned non-finite values (NaN/inf) at "
        f"{int(bad.sum())} of {bad.size} pressures, p = {p.min():.3g} to {p.max():.3g} Pa "
        f"(e.g. u = {float(U[i]):.3g} m, du/dln p = {float(dU[i]):.3g} m at p = {p[0]:.3g} Pa)"
    )


def _start(disc: Discretisation, law, v: np.ndarray) -> _Iterate:
    """:func:`_evaluate` at the start ``v``, and a ValueError naming the law when it is not
    finite there, before any work: the solve could only end in a NaN residual (a law must be
    finite for every p > 0)."""
    with np.errstate(invalid="ignore", over="ignore"):  # inf - inf: the error below says it
        it = _evaluate(disc, law, v, None)
    fault = law_fault(law, it.v, it.U, it.dU)
    if fault is not None:
        raise ValueError(
            f"model: at the start of the solve, {fault}; a pressure law must give a finite u and "
            "a finite slope du/dln p < 0 for every p > 0 (fastline.theory.laws.PressureLaw)"
        )
    return it


def roundoff_floor(size: float, u_ref: float) -> float:
    """Smallest residual (in units of ``u_ref``) that can be told from round-off.

    ``r = u_law - u1 - (g + K p)`` subtracts terms of size ``size``; the FFT product alone
    carries an error of up to 2.7 eps size (measured against an extended-precision dense
    product, n = 256..4096), so the residual cannot be trusted below ``ROUNDOFF_FACTOR`` eps
    size. This matters in the Hertz-like regime, where size ~ delta = h_rms / alpha >> u0:
    at alpha = 1e-6 the floor is ~2e-8 (Newton used to stall there at tol 1e-8).
    """
    return ROUNDOFF_FACTOR * np.finfo(np.float64).eps * size / u_ref


def _line_search(disc, law, it: _Iterate, dv, du1) -> tuple[_Iterate, float, str | None]:
    """Backtracking on ``||r||`` (Armijo) from the step allowed by ``DV_MAX``.

    The guard limits the change of ln p where it matters: where the pressure is within 1e-6 of
    the peak, and wherever the law is not yet in its linear (exponential-law) regime
    ``du/dln p ~ -u0``; in the far tails u_law is linear in ln p and a large change is
    harmless. Returns the new iterate and the step length, or the old iterate and 0 when
    ``LINE_SEARCH_HALVINGS`` halvings give no decrease: the direction is then not a descent
    direction. The third value: :func:`law_fault` of the first trial where the law was not
    finite, when the search failed (None otherwise).
    """
    guard = (it.p > 1e-6 * it.p.max()) | (it.dU > -0.5 * law.u0)
    t = min(1.0, DV_MAX / max(1e-300, float(np.max(np.abs(dv[guard])))))
    fault = None
    for _ in range(LINE_SEARCH_HALVINGS + 1):
        v_new = normalise(it.v + t * dv, disc.load, disc.weights)
        new = _best_u1(_evaluate(disc, law, v_new, it.u1 + t * du1))
        if new.phi < (1.0 - 1e-4 * t) * it.phi:
            return new, t, None
        if fault is None and not math.isfinite(new.phi):
            fault = law_fault(law, new.v, new.U, new.dU)
        t *= 0.5
    return it, 0.0, fault


def _best_u1(it: _Iterate) -> _Iterate:
    """``it`` with the rigid approach that minimises the merit ``||r||`` at its pressure
    (``u1 + mean(r)``). Newton's ``du1`` is scaled with the step in ln p, which the guard of
    :func:`_line_search` may cut to a sliver; an approach left behind then holds a uniform
    residual that no direction in ln p removes (seen at alpha 4e3-9e4, where ``K p`` is tiny
    beside the gap: 36 of 597 random point contacts of ``python -m bench.point_campaign``
    stopped at residuals 1e-6..5e-5). On the path with the best approach the slope of the
    merit is that along ``(dv, du1)`` (its derivative in u1 vanishes there), so a descent
    direction stays one."""
    shift = float(np.mean(it.r))
    it.u1 += shift
    it.r = it.r - shift
    it.phi = float(np.linalg.norm(it.r))
    return it


def _message(ok: bool, res: float, tol: float, tol_eff: float, work: str, stalled=False) -> str:
    """The outcome in words: converged or not, against which tolerance, after what work."""
    if ok:
        raised = "" if tol_eff == tol else f" (tol {tol:.1e} raised to the round-off floor)"
        if stalled:
            raised += ", where no step decreases it further"
        return f"converged: residual {res:.2e} < {tol_eff:.1e}{raised} after {work}"
    why = "line search failed" if stalled else "max_iter"
    return f"not converged: residual {res:.2e} (tol {tol_eff:.1e}) after {work} ({why})"


def _newton_compiled(disc: Discretisation, law, v, tol, max_iter, form=None) -> Outcome | None:
    """The same iteration in one compiled call, when the operator and the law provide one
    (the line contact with a shipped law: :mod:`fastline.contact.line_newton`); None otherwise.
    ``form`` is the law's ``_compiled_form()`` if the caller keeps it (a model does)."""
    run = disc.compiled
    if form is None:
        make = getattr(law, "_compiled_form", None)
        form = None if make is None else make()
    if run is None or form is None:
        return None
    v = np.array(v, dtype=np.float64)
    out = run(disc.op, disc.gap, disc.weights, disc.load, form, law.u0, v, tol, max_iter)
    if out is None:
        return None
    u1, res, status, steps, cg, tol_eff, hist, u = out
    return compiled_outcome(v, u1, res, status, steps, cg, tol, tol_eff, hist, pressure_of(v), u)


def compiled_outcome(v, u1, res, status, steps, cg, tol, tol_eff, hist, p, u) -> Outcome:
    """The :class:`Outcome` of a compiled Newton solve (:mod:`fastline.contact.line_newton`: status
    0 converged, 1 max_iter, 2 line search failed; ``hist`` its (residual, CG iterations, step)
    rows of the steps taken; ``p`` the pressure, ``u`` the law's separation)."""
    status, steps = int(status), int(steps)
    message = _message(status == 0, res, tol, tol_eff, f"{steps} Newton steps", status == 2)
    history = [(r, int(c), t) for r, c, t in hist.tolist()]
    info = {"cg_iterations": int(cg), "newton_history": history, "tol_effective": tol_eff}
    return Outcome(v, u1, res, status == 0, steps, message, info, p, u)


def newton(
    disc: Discretisation,
    law: PressureLaw,
    v: np.ndarray,
    tol: float,
    max_iter: int,
    form: tuple | None = None,
) -> Outcome:
    """Newton-Krylov on ``v = ln p`` in the u(p) form.

    Each step solves ``(D + K) dp + du1 = r`` (``dp = p dv``, ``D = |du_law/dp|``) by projected
    PCG to a relative accuracy set by Eisenstat-Walker forcing, with the geometry's
    preconditioner, then backtracks on ``||r||``; residual ``max |u_law(p) - u1 - g - K p| / u0``.

    Safeguard: CG stops on the preconditioned residual, whose scale spans many decades (D runs
    from ~0 in full contact to huge outside), so a loose inner solve need not be a descent
    direction for ``||r||``. When the line search finds no decrease, the step is solved again
    1000 times more accurately, and the forcing stays capped there for the rest of the solve.
    Without it, Newton stalled at residual 0.51 and 1.2e-3 in two scenes of the random campaign
    whose centres reach full contact (docs/theory.md, numerics notes).

    ``form``: the law's ``_compiled_form()``, when the caller keeps it (else asked here).
    """
    u_ref = law.u0
    fast = _newton_compiled(disc, law, v, tol, max_iter, form)
    if fast is not None:
        return fast
    it = _best_u1(_start(disc, law, v))
    steps = cg_total = 0
    res_prev = eta = math.nan
    eta_cap = ETA_MAX
    fault = None  # the law's non-finite values that stopped the last line search
    history: list[tuple[float, int, float]] = []  # (residual, CG iterations, step length)
    while True:
        res = float(np.max(np.abs(it.r))) / u_ref
        tol_eff = max(tol, roundoff_floor(it.size, u_ref))
        stalled = eta_cap < ETA_RETRY_MIN
        # no descent left at the noise level of a raised tolerance: as converged as float64 allows
        at_floor = stalled and tol_eff > tol and res < FLOOR_STALL * tol_eff
        if at_floor:
            tol_eff = FLOOR_STALL * tol_eff
        if res < tol_eff or steps >= max_iter or stalled:
            ok = res < tol_eff
            message = _message(ok, res, tol, tol_eff, f"{steps} Newton steps", stalled)
            info = {"cg_iterations": cg_total, "newton_history": history, "tol_effective": tol_eff}
            if fault is not None and not ok:
                message = message.replace("(line search failed)", f"(line search failed: {fault})")
                info["law_fault"] = fault
            return Outcome(it.v, it.u1, res, ok, steps, message, info, it.p)
        steps += 1
        psafe = np.maximum(it.p, 1e-300)
        D = np.minimum(np.maximum(-it.dU, 1e-300 * u_ref) / psafe, 1e300)
        eta = min(_forcing(res, res_prev, eta, tol_eff), eta_cap)
        res_prev = res
        dp, du1, cg_its = _newton_direction(disc, D, it.r, eta)
        cg_total += cg_its
        it, t, fault = _line_search(disc, law, it, dp / psafe, du1)
        history.append((res, cg_its, t))
        if t == 0.0:  # not a descent direction: solve the step more accurately
            eta_cap = eta * 1e-3


# ----------------------------------------------------------------------------------------------
# plain damped fixed point (for comparison)
# ----------------------------------------------------------------------------------------------
def _log_pressure(law, u: np.ndarray) -> np.ndarray:
    """ln p_law(u), without overflow when the law provides ``log_pressure``."""
    if hasattr(law, "log_pressure"):
        return law.log_pressure(u)
    with np.errstate(over="ignore", divide="ignore"):
        return np.log(law.pressure(u))


def _solve_u1(law, base: np.ndarray, load: float, w: np.ndarray, u1: float) -> float:
    """u1 with ``sum(w p_law(u1 + base)) = load``, by Newton on the log of the load.

    ``ln sum(w p)`` decreases monotonically in u1 with slope ``-<1/|du/dv|>`` (weights w p);
    everything is done in logarithms, so no pressure overflows.
    """
    target = math.log(load)
    lw = np.log(w)
    base_size = float(np.max(np.abs(base)))
    for _ in range(100):
        lp = _log_pressure(law, u1 + base)
        lp_max = float(np.max(lp))
        share = np.exp(lw + lp - lp_max)
        total = float(share.sum())
        _, dU = law.separation_and_slope(lp)
        slope = float(dot(share / total, 1.0 / dU))  # d ln(load) / du1 < 0
        step = (lp_max + math.log(total) - target) / slope
        u1 -= max(min(step, 20.0 * law.u0), -20.0 * law.u0)
        # below the round-off of u1 + base no step can change the load: 100 iterations of no
        # effect per sweep where |u1| >> u0 (a Hertz-like sphere: 2/3 of a sweep's time)
        if abs(step) < max(1e-14 * law.u0, 4.0 * _EPS * (abs(u1) + base_size)):
            break
    return u1


def picard(
    disc: Discretisation,
    law: PressureLaw,
    v: np.ndarray,
    tol: float,
    max_iter: int,
    omega: float = 0.5,
) -> Outcome:
    """Damped fixed point ``v <- (1 - omega) v + omega ln p_law(u1 + g + K p)``.

    u1 is re-solved every sweep so that the load is carried exactly. The damping halves
    whenever the residual grows (the sweep is rejected) and recovers slowly while it falls,
    which keeps the plain loop from blowing up in the stiff regime; it then slows down like
    ``1/alpha``. It stops when the residual (as for :func:`newton`) is below the tolerance,
    after ``max_iter`` sweeps (rejected ones included: each costs a product with K), or, said
    in the message, when it cannot get there (:func:`_picard_stop`).
    """
    it = _start(disc, law, v)
    u1 = it.u1
    best = [math.inf]  # best residual after each accepted sweep
    sweeps = 0
    while True:
        res = float(np.max(np.abs(it.r))) / law.u0
        tol_eff = max(tol, roundoff_floor(it.size, law.u0))
        why = _picard_stop(best, tol_eff, max_iter - sweeps)
        if res < tol_eff or sweeps >= max_iter or why:
            ok = res < tol_eff
            message = _message(ok, res, tol, tol_eff, f"{sweeps} sweeps")
            if why and not ok:
                message = message.replace("(max_iter)", f"({why}; use method='newton')")
            info = {"damping": omega, "stopped": why if not ok else None}
            return Outcome(it.v, it.u1, res, ok, sweeps, message, info, it.p)
        sweeps += 1
        u1 = _solve_u1(law, it.gk, disc.load, disc.weights, u1)
        v_law = _log_pressure(law, u1 + it.gk)
        new = _evaluate(
            disc, law, normalise((1.0 - omega) * it.v + omega * v_law, disc.load, disc.weights), u1
        )
        new_res = float(np.max(np.abs(new.r))) / law.u0
        if not math.isfinite(new_res):  # the law (or its inverse) gave NaN or inf: stop here
            return _picard_fault(law, it, new, v_law, res, tol, tol_eff, sweeps, omega)
        if new_res > res and omega > 1e-6:
            omega *= 0.5  # reject the sweep, retry with more damping
            continue
        it = new
        best.append(min(best[-1], new_res))
        omega = min(0.5, 1.2 * omega)


def _picard_stop(best: list[float], tol: float, left: int) -> str | None:
    """Why the fixed point should stop now, or None. ``best``: the best residual after each
    accepted sweep (``inf`` first); ``left``: the sweeps ``max_iter`` still allows.

    * stagnation: less than ``PICARD_STAGNATION`` relative progress over the last
      ``PICARD_WINDOW`` accepted sweeps;
    * too slow: at the geometric rate of those sweeps, reaching ``tol`` takes more than
      ``PICARD_SLOW`` times the sweeps left. The work of a solve is then bounded by what its
      own progress shows it can reach, not by ``max_iter`` alone: a sphere at alpha 4e-4
      went on for 4,138 sweeps (48 s at n = 64) at 1-2 % per 200 sweeps with residual 75.
    """
    if len(best) <= PICARD_WINDOW:
        return None
    now, then = best[-1], best[-PICARD_WINDOW - 1]
    if now > (1.0 - PICARD_STAGNATION) * then:
        return f"stagnated over {PICARD_WINDOW} sweeps"
    needed = PICARD_WINDOW * math.log(now / tol) / math.log(then / now)
    if needed > PICARD_SLOW * left:
        return (
            f"too slow: at the rate of the last {PICARD_WINDOW} sweeps ({then:.2e} -> {now:.2e})"
            f" it needs ~{needed:.2g} sweeps more, max_iter leaves {left}"
        )
    return None


def _picard_fault(law, it: _Iterate, new: _Iterate, v_law, res, tol, tol_eff, sweeps, omega):
    """The not-converged :class:`Outcome` of a fixed point whose sweep met non-finite values of
    the law (``v_law``: ln p of its inverse at the sweep's separations), at the last finite
    iterate ``it``, with a message naming the law."""
    fault = None if not np.all(np.isfinite(v_law)) else law_fault(law, new.v, new.U, new.dU)
    if fault is None:  # the inverse failed first
        fault = (
            f"the pressure law {type(law).__name__} returned non-finite values (NaN/inf) of "
            "ln p(u), its inverse (log_pressure or pressure)"
        )
    message = _message(False, res, tol, tol_eff, f"{sweeps} sweeps").replace(
        "(max_iter)", f"({fault})"
    )
    info = {"damping": omega, "law_fault": fault}
    return Outcome(it.v, it.u1, res, False, sweeps, message, info, it.p)
