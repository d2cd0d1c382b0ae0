"""A seal under pressure: the fluid in the interface coupled to a line or a point contact.

docs/leakage.md, "The seal under pressure". The dry contact (a solved line or point contact)
gives the mean gap ``u_0``, pressure ``p_0`` and approach. Under a pressure drop dP the fluid
pressure ``p_f`` in the interface lifts the walls: on the cells of the solved contact,

    u = u_0 - d_delta + K (p_c + p_l - p_0)          (half-space, the solve's operator K),
    p_c = p(u)                                         (the pressure law: contact pressure),
    sum w (p_c + p_l - p_0) = 0                        (the load is held),
    Q = -(L / (12 eta)) g^3 dp_f/dx   (line),   Q = -(2 pi r / (12 eta)) g^3 dp_f/dr   (point),

with g = g(p_c) the local gap of the leak rate (the critical junction's u_c, the effective
medium's, or a calibrated law's hydraulic gap) and ``p_l`` the fluid's load on the body
(:mod:`fastline.leakage.seal_system`: across a line contact ``p_f - dP H``, the far field
carried by the body's support; out of a point contact's hole, dP in the hole and ``p_f`` on
the rings, a compact load).

The unknowns (u, p_f, d_delta, Q) solve these equations by Newton's method with the exact
Jacobian (the derivatives of the law and of ln g by central differences) and a backtracking
line search: by default each Newton system is reduced to the gaps (the fluid pressures follow
from the links in series) and solved by compiled kernels without BLAS
(:mod:`fastline.leakage.seal_kernels`); ``solver="dense"`` solves the full system with NumPy
(the reference). dP sweeps by continuation, each dP started from the last solution, the step
halved when Newton fails. Where the gap of a strip is below the molecular floor (or the strip
does not percolate) its conductance is clamped at that of ``CLAMP`` times the floor (the
equations stay solvable; the seal is reported sealed, Q = 0). The continuation that fails for
every step down to ``MIN_STEP`` of dP, or whose contact carries less than ``LIFT`` of the load,
has reached lift-off (blow-by): no solution of the static seal holds the load beyond it.
"""

from __future__ import annotations

import math
import warnings
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike

from fastline._lib.validate import boolean, real_array
from fastline.errors import LeakageWarning
from fastline.leakage.flow import GAP_FLOOR, MAX_ORIFICE_SHARE, _flow_table, leak_rate
from fastline.leakage.seal_kernels import reduced_step, stiffness_product
from fastline.leakage.seal_system import (
    SUPPORTS,
    System,
    contact_radius,
    equations,
    inverse_cube,
    line_system,
    point_system,
    residual,
    start,
)
from fastline.theory.interface import sealing_argument

if TYPE_CHECKING:  # annotations only
    from fastline.contact.line import LineContactResult
    from fastline.contact.point import PointContactResult
    from fastline.theory.calibrated import CalibratedLaw
    from fastline.theory.persson import PerssonTheory

__all__ = ["SealResult", "SealSweep", "seal_leak"]

#: clamp of the local gap in the conductance, as a fraction of the floor (1e-12 m without one)
CLAMP = 1e-2
#: Newton: relative residual target (pressures over dP and p0, gaps over u_0) and step limit
TOL, MAX_NEWTON = 1e-10, 40
#: continuation: smallest dP step, as a fraction of the last converged dP, before lift-off
MIN_STEP = 1e-3
#: lift-off: the contact carries less than this share of the load (the fluid film the rest)
LIFT = 0.01
#: largest number of cells of the coupled system
MAX_CELLS = 2048
#: largest pressure drop, as a multiple of the contact's modulus E*: a fluid pressure of 100 E*
#: strains the body a hundredfold (no seal meets it; the static seal lifts off near its peak
#: contact pressure, far below E*), and beyond it the sweep's arithmetic overflows
MAX_DROP = 100.0
#: the Newton systems' solvers: the compiled reduced system, or NumPy's dense solve
SOLVERS = ("compiled", "dense")
#: the warning of a hole wide against the contact (``diagnostics["orifice_share"]``)
ORIFICE = (
    "fastline.seal_leak: the hole (inner_radius) is wider than 0.1 of the dry contact's half "
    "width at half maximum of p (diagnostics['orifice_share']): the dry contact ignores the "
    "hole, which a hole of that size changes"
)


@dataclass
class SealResult:
    """The seal at one pressure drop (arrays per cell of the contact; SI units).

    Attributes
    ----------
    pressure_drop : float
        dP in Pa.
    Q : float
        Leak rate in m^3/s (over the seal length of a line contact; out of the hole of a point
        contact). 0 when sealed; ``inf`` at and beyond lift-off, where the static seal is open
        and no profile is computed.
    x, contact_pressure, fluid_pressure, gap, local_gap : ndarray
        Cell centres (m: x of a line contact, r of a point contact), p_c and the fluid's
        pressure on each cell (Pa: the load it puts on the body; dP inside a point contact's
        hole), the mean gap u (m) and the local gap g(p_c) of the leak rate (m, before the
        clamp).
    approach_change : float
        d_delta in m (positive: the body moves towards the counter-face).
    sealed, lifted_off, converged : bool
        Some strip is sealed (its gap below the floor, or no percolation); the dP is at or
        beyond lift-off (the arrays are then zeros); Newton converged.
    diagnostics : dict
        ``iterations``, ``residual`` (relative), ``force_error`` (relative to the load),
        ``mass_error`` (largest relative departure of a link's flux from Q, over the links
        that hold at least 1e-4 of the resistance), ``peak_contact_pressure`` (Pa),
        ``contact_load_share`` (the share of the load the contact carries).
    nodes, node_pressure : ndarray
        The flow nodes (m: a line contact's cell centres; a point contact's hole edge and the
        ring edges beyond it) and p_f there (Pa).
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
    nodes: np.ndarray = field(default_factory=lambda: np.zeros(0))
    node_pressure: np.ndarray = field(default_factory=lambda: np.zeros(0))

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
        ``newton_steps`` (in all), ``continuation_steps``, ``halvings``, ``solver``; a point
        contact adds ``orifice_share`` (the hole's radius over the half width at half maximum
        of p_0) and ``contact_radius`` (m, where p_0 falls below 1e-3 of its peak).
    geometry : str
        ``"line"`` or ``"point"``.
    inner_radius : float or None
        The hole's radius of a point contact (m).
    """

    pressure_drops: np.ndarray
    Q: np.ndarray
    results: list
    lift_off_pressure: float | None
    uncoupled_Q: np.ndarray
    diagnostics: dict
    geometry: str = "line"
    inner_radius: float | None = None

    def __repr__(self):
        lift = "none" if self.lift_off_pressure is None else f"{self.lift_off_pressure:.4g} Pa"
        return (
            f"SealSweep({self.geometry} contact, {self.pressure_drops.size} pressure drops, "
            f"lift-off {lift})"
        )


@dataclass
class _Run:
    """What every Newton solve of one sweep shares: the system, R_0, the solver, counts."""

    sys: System
    r0: float
    solver: str
    counts: list


def seal_leak(
    result: LineContactResult | PointContactResult,
    pressure_drops: ArrayLike,
    viscosity: float,
    length: float | None = None,
    *,
    inner_radius: float | None = None,
    theory: PerssonTheory | None = None,
    threshold: float | None = None,
    method: str = "critical-junction",
    gap_floor: float = GAP_FLOOR,
    support: str = "edge",
    rigid: bool = False,
    law: CalibratedLaw | None = None,
    solver: str = "compiled",
) -> SealSweep:
    """Leak rate of a line or point contact's seal against dP up to lift-off, the fluid in the
    interface coupled to the contact (module docstring; docs/leakage.md, seal under pressure).

    Parameters
    ----------
    result : LineContactResult or PointContactResult
        The dry contact (``model="persson"`` or ``law``), at most ``MAX_CELLS`` cells.
    pressure_drops : array_like
        Pressure drops dP in Pa, in (0, ``MAX_DROP`` E*], swept ascending by continuation.
    viscosity, length, inner_radius, theory, threshold, method, gap_floor, law
        As in :func:`fastline.leak_rate` (Pa s, m, m, -, -, str, m, -): ``length`` for a line
        contact only, ``inner_radius`` (the hole, inside the contact) for a point contact only.
    support : {"edge", "axis"}
        Line contact: where the fluid's load on the body starts (the step of ``dP H``): the
        upstream edge of the dry contact (a body held by a force: the fluid lifts it) or the
        body's axis (an O-ring in its groove). A point contact: ``"edge"`` only.
    rigid : bool
        Hold the mean gap at the dry contact's (a rigid body): the uncoupled leak rate.
    solver : {"compiled", "dense"}
        The Newton systems' solver: reduced and compiled (no BLAS threads), or NumPy's dense
        solve of the full system (the reference).

    Returns
    -------
    SealSweep

    Raises
    ------
    TypeError, ValueError
        Not a line- or point-contact result; an input outside its range, another model than
        the law's, a hole at or beyond the contact's edge, more than ``MAX_CELLS`` cells.
    """
    dPs, rigid = _checked(pressure_drops, support, solver, rigid, getattr(result, "E_star", None))
    dry = [leak_rate(result, float(d), viscosity, length, inner_radius=inner_radius,
                     theory=theory, threshold=threshold, method=method, gap_floor=gap_floor,
                     warn=False, law=law) for d in dPs]  # fmt: skip
    sys = _system(result, dry[0], theory, law, rigid, support)
    run = _Run(sys, start(sys, float(dPs[0]))[1], solver, [0, 0, 0])
    results, lift = _sweep(run, dPs)
    return SealSweep(
        pressure_drops=dPs, Q=np.array([r.Q for r in results]), results=results,
        lift_off_pressure=lift, uncoupled_Q=np.array([k.Q for k in dry]), geometry=sys.geometry,
        diagnostics=_diagnostics(run, dry[0], result), inner_radius=dry[0].inner_radius,
    )  # fmt: skip


def _diagnostics(run: _Run, dry, result) -> dict:
    """The sweep's counts; a point contact's hole against the contact (warned when wide)."""
    diag = {"newton_steps": run.counts[0], "continuation_steps": run.counts[1],
            "halvings": run.counts[2], "solver": run.solver}  # fmt: skip
    if run.sys.geometry == "point":
        diag.update(orifice_share=dry.diagnostics["orifice_share"],
                    contact_radius=contact_radius(result))  # fmt: skip
        if diag["orifice_share"] > MAX_ORIFICE_SHARE:
            warnings.warn(ORIFICE, LeakageWarning, stacklevel=3)
    return diag


def _checked(pressure_drops, support: str, solver: str, rigid, E_star) -> tuple[np.ndarray, bool]:
    """The pressure drops, ascending, and ``rigid`` (the choices of support and solver too),
    checked; dP at most ``MAX_DROP`` E* (``E_star`` None: not a contact result, which
    :func:`leak_rate` refuses)."""
    rigid = boolean("rigid", rigid)
    if support not in SUPPORTS:
        raise ValueError(f"support must be one of {SUPPORTS}, got {support!r}")
    if solver not in SOLVERS:
        raise ValueError(f"solver must be one of {SOLVERS}, got {solver!r}")
    d = np.atleast_1d(real_array("pressure_drops", pressure_drops))
    if d.ndim != 1 or d.size == 0 or not np.all(np.isfinite(d)) or np.any(d <= 0.0):
        raise ValueError(
            "pressure_drops must be one or more finite pressure drops > 0 Pa (allowed range "
            "(0, inf))"
        )
    top = None if E_star is None else MAX_DROP * float(E_star)
    if top is not None and d.max() > top:
        raise ValueError(
            f"pressure_drops must lie in (0, {top:.6g}] Pa ({MAX_DROP:g} E*, the contact's "
            f"modulus E* = {float(E_star):.6g} Pa), got {d.max():.6g}: a fluid pressure of "
            f"{MAX_DROP:g} E* would strain the body a hundredfold (no seal holds it; the "
            "static seal lifts off near its peak contact pressure, far below E*)"
        )
    return np.sort(d), rigid


def _system(result, leak, theory, law, rigid: bool, support: str) -> System:
    """The coupled equations' fixed pieces from the dry contact and its leak rate (already
    validated by :func:`fastline.leak_rate`)."""
    n = result.pressure.size
    if n > MAX_CELLS:
        raise ValueError(f"the contact has {n} cells; the coupled seal takes at most {MAX_CELLS}")
    want = "persson" if law is None else getattr(law, "name", "calibrated")
    if getattr(result, "model", None) != want:
        raise ValueError(
            f"the coupled seal needs a contact solved with model={want!r} (the law whose p(u) "
            f"it continues), got model={getattr(result, 'model', None)!r}"
        )
    if law is not None:
        pressure, log_gap = law.pressure, law.log_hydraulic_gap
    else:
        th = result.theory if theory is None else theory
        table = _flow_table(th, leak)
        pressure = th.pressure

        def log_gap(p):
            return table.log_gap(sealing_argument(th, p))

    floor = leak.gap_floor if leak.gap_floor > 0.0 else 1e-10
    point = leak.inner_radius is not None
    flow = (leak.viscosity, 1.0 if point else leak.length)
    if not point:
        return line_system(result, pressure, log_gap, CLAMP * floor, flow, rigid, support)
    if support != "edge":
        raise ValueError(
            f"support={support!r} is for a line contact; a point contact's fluid load is "
            "compact (leave support at 'edge')"
        )
    edge = contact_radius(result)
    if leak.inner_radius >= edge:
        raise ValueError(
            f"inner_radius must lie inside the contact, below {edge:.6g} m (where p falls to "
            f"1e-3 of its peak; allowed range (0, {edge:.6g}) m), got {leak.inner_radius:.6g}: "
            "a hole larger than the contact leaves no seal"
        )
    return point_system(result, pressure, log_gap, CLAMP * floor, flow, rigid, leak.inner_radius)


def _sweep(run: _Run, dPs: np.ndarray) -> tuple[list, float | None]:
    """The results at each dP by continuation, and the lift-off pressure (or None)."""
    y, last, results = start(run.sys, float(dPs[0]))[0], 0.0, []
    lift, held = None, (None, 0.0)  # the last state that holds the load, and its dP
    for dP in dPs:
        if lift is not None:  # the static seal is open: nothing to solve
            results.append(_beyond(run.sys, float(dP)))
            continue
        y, last, ok = _continue(run, y, last, float(dP))
        if ok and not _lifted(run.sys, y):
            held = (y, last)
            results.append(_result(run, y, float(dP)))
            continue
        # lifted off on the way to dP (or no solution beyond ``last``): bracket and bisect
        top = last if (ok or last > held[1]) else float(dP)
        lift = _lift_off(run, held, max(top, held[1] * (1 + MIN_STEP)))
        results.append(_beyond(run.sys, float(dP)))
    return results, lift


def _continue(run: _Run, y, last, dP) -> tuple[np.ndarray, float, bool]:
    """Continuation from the solution at ``last`` (0: none yet) to dP: the step halved on a
    failure and doubled after a success, stopping where the body lifts off; returns (solution,
    dP reached, whether that solution holds the load at dP)."""
    n, N = run.sys.n, run.sys.nodes.size
    step = dP - last
    while True:
        target = min(dP, last + step)
        trial = y.copy()
        if last > 0.0:
            trial[n : n + N] *= target / last
            trial[n + N + 1] *= target / last
        sol, ok, its = _newton(run, trial, target)
        run.counts[0] += its
        run.counts[1] += 1
        if ok:
            y, last = sol, target
            if _lifted(run.sys, y):
                return y, last, False
            if target >= dP:
                return y, last, True
            step *= 2.0
            continue
        run.counts[2] += 1
        step *= 0.5
        if step <= MIN_STEP * max(last, MIN_STEP * dP):
            return y, last, False


def _evaluate(run: _Run, y: np.ndarray, dP: float):
    """(law values, scaled residual) at y, the gap rows' product with K compiled."""
    sys = run.sys
    vals = inverse_cube(sys, y[: sys.n])
    return vals, residual(sys, y, dP, run.r0, vals, stiffness_product)


def _newton(run: _Run, y: np.ndarray, dP: float) -> tuple[np.ndarray, bool, int]:
    """Newton with a backtracking line search on |F|^2, the mean gaps kept > 0."""
    n = run.sys.n
    vals, F = _evaluate(run, y, dP)
    norm = float(np.max(np.abs(F)))
    for it in range(1, MAX_NEWTON + 1):
        step = _direction(run, y, vals, F, dP)
        if step is None or not np.all(np.isfinite(step)):
            return y, False, it
        du = step[:n]
        shrink = np.min(np.where(du < 0.0, -0.5 * y[:n] / np.minimum(du, -1e-300), np.inf))
        alpha = min(1.0, float(shrink))
        while alpha > 1e-6:
            trial = y + alpha * step
            vals_t, F_t = _evaluate(run, trial, dP)
            if np.all(np.isfinite(F_t)) and np.sum(F_t**2) < (1.0 - 1e-4 * alpha) * np.sum(F**2):
                break
            alpha *= 0.5
        else:
            return y, False, it
        y, vals, F = trial, vals_t, F_t
        norm = float(np.max(np.abs(F)))
        if norm < TOL:
            return y, True, it
    return y, norm < TOL, MAX_NEWTON


def _direction(run: _Run, y, vals, F, dP) -> np.ndarray | None:
    """The Newton step: the compiled reduced system, or the dense system by NumPy."""
    if run.solver == "compiled":
        return reduced_step(run.sys, y, vals, F, dP, run.r0)
    _, J = equations(run.sys, y, dP, run.r0, jac=True)
    try:
        return np.linalg.solve(J, -F)
    except np.linalg.LinAlgError:
        return None


def _lifted(sys: System, y: np.ndarray) -> bool:
    """The contact carries less than ``LIFT`` of the load: the fluid holds the body off."""
    return float(sys.w @ sys.law(y[: sys.n])) < LIFT * float(sys.w @ sys.p0)


def _lift_off(run: _Run, held, dP) -> float:
    """The lift-off pressure drop between the last dP that held and dP, by bisection (each
    trial continued from the state that held), to ``MIN_STEP`` relative."""
    y_lo, lo = held
    if y_lo is None:  # lifted off at the first pressure drop
        y_lo, lo = start(run.sys, MIN_STEP * dP)[0], 0.0
    hi = dP
    while hi - lo > MIN_STEP * hi:
        mid = 0.5 * (lo + hi)
        y, reached, ok = _continue(run, y_lo, lo, mid)
        if ok:
            y_lo, lo = y, mid
        else:
            hi = min(hi, reached) if reached > lo else mid
    return 0.5 * (lo + hi)


def _beyond(sys: System, dP: float) -> SealResult:
    """A pressure drop the continuation did not reach (flagged, no numbers)."""
    empty = np.zeros(sys.n)
    return SealResult(dP, math.inf, sys.x, empty, empty, empty, empty, 0.0, False, True, False,
                      {"message": "at or beyond lift-off: the static seal is open"},
                      sys.nodes, np.zeros(sys.nodes.size))  # fmt: skip


def _result(run: _Run, y, dP) -> SealResult:
    sys, r0 = run.sys, run.r0
    n, N = sys.n, sys.nodes.size
    u, pf, dd, phi = y[:n], y[n : n + N], float(y[n + N]), float(y[n + N + 1])
    vals, F = _evaluate(run, y, dP)
    pc, _, inv, _ = vals
    log_g, perc = sys.log_gap(pc)
    sealed = bool(np.any(perc) or np.any(log_g < math.log(sys.g_clamp / CLAMP)))
    r = sys.resistances(inv)
    q_hat = phi / r0
    carries = r >= 1e-4 * r.sum()  # the links that hold a share of the resistance
    flux = (pf[:-1] - pf[1:])[carries] / r[carries]
    with np.errstate(over="ignore"):
        g = np.exp(log_g)
    fluid = pf.copy() if sys.geometry == "line" else sys.fluid_load(pf, dP)  # on the cells
    return SealResult(
        pressure_drop=dP, Q=0.0 if sealed else sys.length * q_hat / (12.0 * sys.viscosity),
        x=sys.x, contact_pressure=pc, fluid_pressure=fluid, gap=u, local_gap=g,
        approach_change=dd, sealed=sealed,
        lifted_off=False, converged=bool(np.max(np.abs(F)) < TOL),
        diagnostics={
            "residual": float(np.max(np.abs(F))),
            "force_error": 0.0 if sys.rigid else abs(float(F[n])),
            "mass_error": float(np.max(np.abs(flux - q_hat)) / abs(q_hat)),
            "peak_contact_pressure": float(pc.max()),
            "contact_load_share": float(sys.w @ pc / (sys.w @ sys.p0)),
        },
        nodes=sys.nodes, node_pressure=pf,
    )  # fmt: skip
