"""A line-contact seal under pressure: the fluid in the interface coupled to the contact.

docs/leakage.md, "The seal under pressure". The dry contact (a solved line contact) gives the
mean gap ``u_0(x)``, pressure ``p_0(x)`` and approach. Under a pressure drop dP the fluid
pressure ``p_f(x)`` in the interface lifts the walls: on the cells of the solved contact,

    u = u_0 - d_delta + K (p_c + p_l - p_0)          (half-space, the solve's operator K),
    p_c = p(u)                                         (the pressure law: contact pressure),
    sum (p_c + p_l - p_0) dx = 0                       (the load is held),
    p_l = p_f - dP H(-x)                               (fluid load on the body: see below),
    Q / L = -(g^3 / (12 eta)) dp_f/dx  (same on every face),  p_f(x_0) = dP,  p_f(x_end) = 0,

with g = g(p_c) the local gap of the leak rate (the critical junction's u_c, or the effective
medium's) and the face conductances the harmonic means of the cells' (strips in series). The
fluid upstream of the contact presses on the body's upstream half: a load dP on a half-plane
has no finite displacement on a half-space, so that far-field part, ``dP H(-x)`` with the step
at the body's axis, is taken as carried by the body's support (the groove wall of an O-ring),
and the half-space sees only the departure ``p_f - dP H(-x)``, compact on the contact.

The unknowns (u, p_f, d_delta, Q) solve the 2n + 2 equations by Newton's method with the exact
Jacobian (dense; the derivatives of the law and of ln g by central differences) and a
backtracking line search; dP sweeps by continuation, each dP started from the last solution,
the step halved when Newton fails. Where the gap of a strip is below the molecular floor (or the
strip does not percolate) its conductance is clamped at that of ``CLAMP`` times the floor (the
equations stay solvable; the seal is reported sealed, Q = 0). The continuation that fails for
every step down to ``MIN_STEP`` of dP has reached lift-off (blow-by): no solution of the
static seal holds the load beyond it.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike

from fastline.elastic import influence_coefficients
from fastline.leakage.flow import GAP_FLOOR, _flow_table, leak_rate

if TYPE_CHECKING:  # annotations only
    from fastline.contact.line import LineContactResult
    from fastline.theory.persson import PerssonTheory

__all__ = ["SealResult", "SealSweep", "seal_leak"]

#: clamp of the local gap in the conductance, as a fraction of the floor (1e-12 m without one)
CLAMP = 1e-2
#: Newton: relative residual target (pressures over dP and p0, gaps over u_0) and step limit
TOL, MAX_NEWTON = 1e-10, 40
#: continuation: smallest dP step, as a fraction of the last converged dP, before lift-off
MIN_STEP = 1e-3
#: where the fluid's load on the body starts to count (see seal_leak), and the pressure, as a
#: fraction of the peak, that marks the upstream edge of the dry contact
SUPPORTS, EDGE = ("edge", "axis"), 1e-3
#: lift-off: the contact carries less than this share of the load (the fluid film the rest)
LIFT = 0.01
#: largest number of cells of the dense coupled system
MAX_CELLS = 2048


@dataclass
class SealResult:
    """The seal at one pressure drop (arrays per cell of the line contact; SI units).

    Attributes
    ----------
    pressure_drop : float
        dP in Pa.
    Q : float
        Leak rate in m^3/s over the seal length (0 when sealed; ``inf`` at and beyond
        lift-off, where the static seal is open and no profile is computed).
    x, contact_pressure, fluid_pressure, gap, local_gap : ndarray
        Cell centres (m), p_c and p_f (Pa), the mean gap u (m) and the local gap g(p_c) of the
        leak rate (m, before the clamp).
    approach_change : float
        d_delta in m (positive: the body moves towards the counter-face).
    sealed, lifted_off, converged : bool
        Some strip is sealed (its gap below the floor, or no percolation); the dP is at or
        beyond lift-off (the arrays are then zeros); Newton converged.
    diagnostics : dict
        ``iterations``, ``residual`` (relative), ``force_error`` (relative to the load),
        ``mass_error`` (largest relative departure of a face's flux from Q, over the faces
        that hold at least 1e-4 of the resistance), ``peak_contact_pressure`` (Pa),
        ``contact_load_share`` (the share of the load the contact carries).
    """

    pressure_drop: float
    Q: float
    x: np.ndarray
    contact_pressure: np.ndarray
    fluid_pressure: np.ndarray
    gap: np.ndarray
    local_gap: np.ndarray
    approach_change: float
    sealed: bool
    lifted_off: bool
    converged: bool
    diagnostics: dict = field(default_factory=dict)

    def __repr__(self):
        state = "lifted off" if self.lifted_off else ("sealed" if self.sealed else "leaks")
        return (
            f"SealResult(dP={self.pressure_drop:.4g} Pa, Q={self.Q:.4g} m^3/s, {state}, "
            f"converged={self.converged})"
        )


@dataclass
class SealSweep:
    """Leak rate against pressure drop, from the smallest dP up to lift-off.

    Attributes
    ----------
    pressure_drops, Q : ndarray
        The dP asked for (Pa, ascending) and the leak rate at each (m^3/s).
    results : list of SealResult
        One per dP asked for.
    lift_off_pressure : float or None
        The pressure drop (Pa) at which the contact's share of the load falls to ``LIFT`` (the
        fluid holds the body off), by bisection to ``MIN_STEP`` relative; None if every dP
        asked for holds.
    uncoupled_Q : ndarray
        The leak rate of the dry contact (:func:`fastline.leak_rate`) at each dP, for comparison.
    diagnostics : dict
        ``newton_steps`` (in all), ``continuation_steps``, ``halvings``.
    """

    pressure_drops: np.ndarray
    Q: np.ndarray
    results: list
    lift_off_pressure: float | None
    uncoupled_Q: np.ndarray
    diagnostics: dict

    def __repr__(self):
        lift = "none" if self.lift_off_pressure is None else f"{self.lift_off_pressure:.4g} Pa"
        return f"SealSweep({self.pressure_drops.size} pressure drops, lift-off {lift})"


@dataclass
class _System:
    """The fixed pieces of the coupled equations of one dry contact."""

    x: np.ndarray
    dx: float
    K: np.ndarray
    u0: np.ndarray
    p0: np.ndarray
    upstream: np.ndarray
    law: object
    log_gap: object
    g_clamp: float
    viscosity: float
    length: float
    rigid: bool


def _local_gap(sys: _System, pc: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(ln g, sealed) of the leak rate's local gap at contact pressures pc (g = +inf at 0)."""
    log_g, sealed = sys.log_gap(pc)
    return log_g, sealed


def _inverse_cube(sys: _System, u: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(p_c, dp_c/du, g^-3 with the clamp, d(g^-3)/du) at the mean gaps u (central
    differences of the law and of ln g in u, step 1e-6 u)."""
    h = 1e-6 * u
    p = sys.law(u)
    p_up, p_dn = sys.law(u + h), sys.law(u - h)
    dp = (p_up - p_dn) / (2.0 * h)
    floor = math.log(sys.g_clamp)
    lg = np.maximum(_local_gap(sys, p)[0], floor)
    lg_up = np.maximum(_local_gap(sys, p_up)[0], floor)
    lg_dn = np.maximum(_local_gap(sys, p_dn)[0], floor)
    with np.errstate(over="ignore", invalid="ignore"):
        inv = np.exp(-3.0 * lg)
        d_lg = np.where(np.isfinite(lg_up - lg_dn), (lg_up - lg_dn) / (2.0 * h), 0.0)
    return p, dp, inv, np.nan_to_num(-3.0 * inv * d_lg)


def _equations(sys: _System, y: np.ndarray, dP: float, r0: float, jac: bool):
    """Scaled residual of the coupled equations (module docstring) and, with ``jac``, its
    Jacobian: rows gap (n), force (1), faces (n - 1), the two ends (2); columns u, p_f, the
    change of approach and the flux variable phi (``12 eta Q / L = phi / r0``)."""
    n = sys.x.size
    u, pf, dd, phi = y[:n], y[n : 2 * n], y[2 * n], y[2 * n + 1]
    pc, dpc, inv, dinv = _inverse_cube(sys, u)
    r = 0.5 * sys.dx * (inv[:-1] + inv[1:])  # face resistances (strips in series)
    su, sf = float(np.median(sys.u0)), float(np.sum(sys.p0) * sys.dx)
    load = pc + pf - dP * sys.upstream - sys.p0
    F = np.empty(2 * n + 2)
    F[:n] = (u - sys.u0 + dd - (0.0 if sys.rigid else sys.K @ load)) / su
    F[n] = dd / su if sys.rigid else np.sum(load) * sys.dx / sf
    F[n + 1 : 2 * n] = (pf[:-1] - pf[1:] - phi * r / r0) / dP
    F[2 * n], F[2 * n + 1] = (pf[0] - dP) / dP, pf[-1] / dP
    if not jac:
        return F, None
    J = np.zeros((2 * n + 2, 2 * n + 2))
    if sys.rigid:
        J[:n, :n] = np.eye(n) / su
        J[n, 2 * n] = 1.0 / su
    else:
        J[:n, :n] = (np.eye(n) - sys.K * dpc) / su
        J[:n, n : 2 * n] = -sys.K / su
        J[:n, 2 * n] = 1.0 / su
        J[n, :n], J[n, n : 2 * n] = dpc * sys.dx / sf, sys.dx / sf
    k = np.arange(n - 1)
    J[n + 1 + k, n + k], J[n + 1 + k, n + 1 + k] = 1.0 / dP, -1.0 / dP
    J[n + 1 + k, k] = -phi * 0.5 * sys.dx * dinv[:-1] / r0 / dP
    J[n + 1 + k, k + 1] = -phi * 0.5 * sys.dx * dinv[1:] / r0 / dP
    J[n + 1 + k, 2 * n + 1] = -r / r0 / dP
    J[2 * n, n], J[2 * n + 1, 2 * n - 1] = 1.0 / dP, 1.0 / dP
    return F, J


def _newton(sys: _System, y: np.ndarray, dP: float, r0: float) -> tuple[np.ndarray, bool, int]:
    """Newton with a backtracking line search on |F|^2, the mean gaps kept > 0."""
    n = sys.x.size
    F, J = _equations(sys, y, dP, r0, jac=True)
    norm = float(np.max(np.abs(F)))
    for it in range(1, MAX_NEWTON + 1):
        try:
            step = np.linalg.solve(J, -F)
        except np.linalg.LinAlgError:
            return y, False, it
        du = step[:n]
        shrink = np.min(np.where(du < 0.0, -0.5 * y[:n] / np.minimum(du, -1e-300), np.inf))
        alpha = min(1.0, float(shrink))
        while alpha > 1e-6:
            trial = y + alpha * step
            F_t, _ = _equations(sys, trial, dP, r0, jac=False)
            if np.all(np.isfinite(F_t)) and np.sum(F_t**2) < (1.0 - 1e-4 * alpha) * np.sum(F**2):
                break
            alpha *= 0.5
        else:
            return y, False, it
        y = trial
        F, J = _equations(sys, y, dP, r0, jac=True)
        norm = float(np.max(np.abs(F)))
        if norm < TOL:
            return y, True, it
    return y, norm < TOL, MAX_NEWTON


def seal_leak(
    result: LineContactResult,
    pressure_drops: ArrayLike,
    viscosity: float,
    length: float | None = None,
    *,
    theory: PerssonTheory | None = None,
    threshold: float | None = None,
    method: str = "critical-junction",
    gap_floor: float = GAP_FLOOR,
    support: str = "edge",
    rigid: bool = False,
) -> SealSweep:
    """Leak rate of a line-contact seal against the pressure drop it holds, with the fluid
    pressure in the interface coupled to the contact (module docstring; docs/leakage.md,
    "The seal under pressure"), from the smallest dP up to lift-off.

    Parameters
    ----------
    result : LineContactResult
        The dry contact (``model="persson"``), at most ``MAX_CELLS`` cells.
    pressure_drops : array_like
        Pressure drops dP in Pa (> 0), swept in ascending order by continuation.
    viscosity, length, theory, threshold, method, gap_floor
        As in :func:`fastline.leak_rate` (Pa s, m, -, -, str, m).
    support : {"edge", "axis"}
        Where the fluid's load on the body starts to count (the step of ``dP H``): the
        upstream edge of the dry contact (a body held by a force: the fluid lifts it) or the
        body's axis (an O-ring in its groove: the contact pressure rises with dP).
    rigid : bool
        Hold the mean gap at the dry contact's (a rigid body): the uncoupled leak rate, for
        comparison.

    Returns
    -------
    SealSweep
    """
    dPs = _pressure_drops(pressure_drops)
    if not hasattr(result, "x"):
        name = type(result).__name__
        raise TypeError(f"the coupled seal is for a line contact, got a {name} (not available)")
    if support not in SUPPORTS:
        raise ValueError(f"support must be one of {SUPPORTS}, got {support!r}")
    dry = [leak_rate(result, float(d), viscosity, length, theory=theory, threshold=threshold,
                     method=method, gap_floor=gap_floor, warn=False) for d in dPs]  # fmt: skip
    sys = _system(result, dry[0], theory, rigid, support)
    inv = _inverse_cube(sys, sys.u0)[2]
    r0 = float(np.sum(0.5 * sys.dx * (inv[:-1] + inv[1:])))
    counts = [0, 0, 0]
    results, lift = _sweep(sys, dPs, r0, counts)
    return SealSweep(
        pressure_drops=dPs,
        Q=np.array([r.Q for r in results]),
        results=results,
        lift_off_pressure=lift,
        uncoupled_Q=np.array([k.Q for k in dry]),
        diagnostics={"newton_steps": counts[0], "continuation_steps": counts[1],
                     "halvings": counts[2]},
    )  # fmt: skip


def _sweep(sys: _System, dPs: np.ndarray, r0: float, counts: list) -> tuple[list, float | None]:
    """The results at each dP by continuation, and the lift-off pressure (or None)."""
    y, last, results = _start(sys, dPs[0], r0), 0.0, []
    lift, held = None, (None, 0.0)  # the last state that holds the load, and its dP
    for dP in dPs:
        if lift is not None:  # the static seal is open: nothing to solve
            results.append(_beyond(sys, float(dP)))
            continue
        y, last, ok = _continue(sys, y, last, float(dP), r0, counts)
        if ok and not _lifted(sys, y):
            held = (y, last)
            results.append(_result(sys, y, float(dP), r0, lifted=False))
            continue
        # lifted off on the way to dP (or no solution beyond ``last``): bracket and bisect
        top = last if (ok or last > held[1]) else float(dP)
        lift = _lift_off(sys, held, max(top, held[1] * (1 + MIN_STEP)), r0, counts)
        results.append(_beyond(sys, float(dP)))
    return results, lift


def _pressure_drops(pressure_drops) -> np.ndarray:
    d = np.atleast_1d(np.asarray(pressure_drops, dtype=float))
    if d.ndim != 1 or d.size == 0 or not np.all(np.isfinite(d)) or np.any(d <= 0.0):
        raise ValueError(
            "pressure_drops must be one or more finite pressure drops > 0 Pa (allowed range "
            "(0, inf))"
        )
    return np.sort(d)


def _system(result, leak, theory, rigid: bool, support: str) -> _System:
    """The coupled equations' fixed pieces from the dry contact and its leak rate."""
    n = result.x.size
    if n > MAX_CELLS:
        raise ValueError(f"the contact has {n} cells; the coupled seal takes at most {MAX_CELLS}")
    if getattr(result, "model", None) != "persson":
        raise ValueError("the coupled seal needs a model='persson' line contact")
    th = result.theory if theory is None else theory
    from scipy.linalg import toeplitz  # lazy: only when a seal is solved

    K = toeplitz(influence_coefficients(n)) * (result.dx / result.E_star)
    table = _flow_table(th, leak)
    w1 = 1.0 / math.sqrt(float(th.psd.cumulative(th.psd.q1)))

    def log_gap(p):
        return table.log_gap(np.ascontiguousarray(w1 * p / th.E_star, dtype=np.float64))

    floor = leak.gap_floor if leak.gap_floor > 0.0 else 1e-10
    x = np.asarray(result.x, dtype=float)
    return _System(
        x=x, dx=float(result.dx), K=K, u0=np.asarray(result.separation, dtype=float),
        p0=np.asarray(result.pressure, dtype=float),
        upstream=_upstream(x, np.asarray(result.pressure, dtype=float), support),
        law=th.pressure, log_gap=log_gap, g_clamp=CLAMP * floor, viscosity=leak.viscosity,
        length=leak.length, rigid=bool(rigid),
    )  # fmt: skip


def _upstream(x: np.ndarray, p0: np.ndarray, support: str) -> np.ndarray:
    """The step ``H`` of the far-field fluid load: 1 upstream of the step, 0 downstream (1/2
    on a cell centred on it): the body's axis, or the upstream edge of the dry contact (the
    first cell with ``p0 >= EDGE * max(p0)``)."""
    step = 0.0 if support == "axis" else float(x[np.argmax(p0 >= EDGE * p0.max())])
    return np.where(x < step, 1.0, np.where(x == step, 0.5, 0.0))


def _start(sys: _System, dP: float, r0: float) -> np.ndarray:
    """The uncoupled state at dP: the dry gaps and the fluid pressure of strips in series."""
    inv = _inverse_cube(sys, sys.u0)[2]
    r = 0.5 * sys.dx * (inv[:-1] + inv[1:])
    pf = dP * (1.0 - np.concatenate([[0.0], np.cumsum(r)]) / r0)
    return np.concatenate([sys.u0, pf, [0.0, dP]])


def _continue(sys, y, last, dP, r0, counts) -> tuple[np.ndarray, float, bool]:
    """Continuation from the solution at ``last`` (0: none yet) to dP: the step halved on a
    failure and doubled after a success, stopping where the body lifts off; returns (solution,
    dP reached, whether that solution holds the load at dP)."""
    n = sys.x.size
    step = dP - last
    while True:
        target = min(dP, last + step)
        trial = y.copy()
        if last > 0.0:
            trial[n : 2 * n] *= target / last
            trial[2 * n + 1] *= target / last
        sol, ok, its = _newton(sys, trial, target, r0)
        counts[0] += its
        counts[1] += 1
        if ok:
            y, last = sol, target
            if _lifted(sys, y):
                return y, last, False
            if target >= dP:
                return y, last, True
            step *= 2.0
            continue
        counts[2] += 1
        step *= 0.5
        if step <= MIN_STEP * max(last, MIN_STEP * dP):
            return y, last, False


def _lifted(sys: _System, y: np.ndarray) -> bool:
    """The contact carries less than ``LIFT`` of the load: the fluid holds the body off."""
    n = sys.x.size
    return float(np.sum(sys.law(y[:n]))) < LIFT * float(np.sum(sys.p0))


def _lift_off(sys, held, dP, r0, counts) -> float:
    """The lift-off pressure drop between the last dP that held and dP, by bisection (each
    trial continued from the state that held), to ``MIN_STEP`` relative."""
    y_lo, lo = held
    if y_lo is None:  # lifted off at the first pressure drop
        y_lo, lo = _start(sys, MIN_STEP * dP, r0), 0.0
    hi = dP
    while hi - lo > MIN_STEP * hi:
        mid = 0.5 * (lo + hi)
        y, reached, ok = _continue(sys, y_lo, lo, mid, r0, counts)
        if ok:
            y_lo, lo = y, mid
        else:
            hi = min(hi, reached) if reached > lo else mid
    return 0.5 * (lo + hi)


def _beyond(sys: _System, dP: float) -> SealResult:
    """A pressure drop the continuation did not reach (flagged, no numbers)."""
    empty = np.zeros(sys.x.size)
    return SealResult(dP, math.inf, sys.x, empty, empty, empty, empty, 0.0, False, True, False,
                      {"message": "at or beyond lift-off: the static seal is open"})  # fmt: skip


def _result(sys, y, dP, r0, lifted: bool) -> SealResult:
    n = sys.x.size
    u, pf, dd, phi = y[:n], y[n : 2 * n], float(y[2 * n]), float(y[2 * n + 1])
    pc, _, inv, _ = _inverse_cube(sys, u)
    log_g, perc = _local_gap(sys, pc)
    floor = sys.g_clamp / CLAMP
    sealed = bool(np.any(perc) or np.any(log_g < math.log(floor)))
    F, _ = _equations(sys, y, dP, r0, jac=False)
    r = 0.5 * sys.dx * (inv[:-1] + inv[1:])
    q_hat = phi / r0
    carries = r >= 1e-4 * r.sum()  # the faces that hold a share of the resistance
    flux = (pf[:-1] - pf[1:])[carries] / r[carries]
    Q = 0.0 if sealed else sys.length * q_hat / (12.0 * sys.viscosity)
    with np.errstate(over="ignore"):
        g = np.exp(log_g)
    return SealResult(
        pressure_drop=dP, Q=Q, x=sys.x, contact_pressure=pc, fluid_pressure=pf, gap=u,
        local_gap=g, approach_change=dd, sealed=sealed, lifted_off=lifted,
        converged=bool(np.max(np.abs(F)) < TOL),
        diagnostics={
            "residual": float(np.max(np.abs(F))),
            "force_error": 0.0 if sys.rigid else abs(float(F[n])),
            "mass_error": float(np.max(np.abs(flux - q_hat)) / abs(q_hat)),
            "peak_contact_pressure": float(pc.max()),
            "contact_load_share": float(np.sum(pc) / np.sum(sys.p0)),
        },
    )  # fmt: skip
