"""``fastline leak``: the leak rate of the seal a scene forms, for one load or a load sweep.

A cylinder on a flat (the default) leaks across the contact line, along x, over a seal of length
``--length``; with ``--geometry sphere`` a ball pressed on a flat seat leaks radially, from the
edge of the seat's hole (``--inner-radius``) outwards through the rings around the axis.
Argument parsing and printing only: the contact is solved by :class:`fastline.LineContact` or
:class:`fastline.PointContact`, the leak rate is :func:`fastline.leak_rate` (Persson's
critical-junction theory, the strips or rings of the contact in series; docs/leakage.md), the
files are written by :mod:`fastline.io`, the figures drawn by :mod:`fastline.plotting`.
:mod:`fastline.cli.app` wires :func:`leak_parser` and :func:`cmd_leak` in.

SI units throughout: m, Pa, Pa s, m^3/s, N/m (load per unit cylinder length), N (load on a
sphere).
"""

from __future__ import annotations

import argparse
import inspect

import fastline as fl
from fastline import theory
from fastline.cli.common import (
    GEOMETRY_DEFAULTS,
    CLIError,
    check_outputs,
    convergence_status,
    count,
    figure_options,
    fraction,
    geometry_defaults,
    material_options,
    metadata,
    number,
    numerics_options,
    persson_theory,
    positive,
    progress,
    report_warnings,
    result_lines,
    save,
    solve_kwargs,
    spectrum_line,
    spectrum_options,
    warn,
)
from fastline.cli.scene import scan_options, scene
from fastline.cli.sphere import sphere_meta, sphere_result_lines

__all__ = ["leak_parser", "cmd_leak", "LEAK_SWEEP_DEFAULTS"]

#: defaults of the load-sweep options of ``leak --sweep`` for a cylinder (those of ``sweep``;
#: a sphere's loads are in ``GEOMETRY_DEFAULTS["sphere"]``)
LEAK_SWEEP_DEFAULTS = {
    "loads_from": GEOMETRY_DEFAULTS["cylinder"]["loads_from"],
    "loads_to": GEOMETRY_DEFAULTS["cylinder"]["loads_to"],
    "loads_num": 20,
}
#: seal length [m] of a cylinder when --length is not given
_DEFAULT_LENGTH = 1.0
#: cells of the contact with --coupled when --n is not given (a dense Newton system)
COUPLED_N = 256
#: the molecular floor of the gap [m] when --gap-floor is not given: fl.leak_rate's default
GAP_FLOOR = inspect.signature(fl.leak_rate).parameters["gap_floor"].default


def leak_parser(sub: argparse._SubParsersAction, fmt: type[argparse.HelpFormatter]) -> None:
    """The ``leak`` command: the options of ``profile``, the fluid and seal, ``--sweep``."""
    p = sub.add_parser(
        "leak",
        help="leak rate of a seal, line or point contact (Persson's critical-junction theory); "
        "--sweep: against load",
        formatter_class=fmt,
        description="Solve one scene and compute the leak rate of the seal it forms, from "
        "Persson's critical-junction theory (docs/leakage.md). A cylinder on a flat (the "
        "default) leaks across the contact line (along x) over a seal of length --length, the "
        "strips of the contact in series. With --geometry sphere a ball pressed on a flat seat "
        "leaks radially: the fluid enters at the edge of the seat's hole (--inner-radius, "
        "required) and flows outwards through the rings around the axis, in series. Prints "
        "the volume flow Q [m^3/s], the conductance, whether the contact is sealed and where "
        "the flow resistance sits. With --sweep: Q against a log-spaced series of loads "
        "(--loads-from/--loads-to/--loads-num instead of --load), how much squeeze stops the "
        "leak.",
    )
    spectrum_options(p)
    scan_options(p)
    material_options(p, load=True, geometry=True)  # --load: one scene, not with --sweep
    _fluid_options(p, theory.THRESHOLD_PERSSON)
    _sweep_options(p)
    numerics_options(p, geometry=True)
    p.add_argument(
        "--csv",
        metavar="FILE",
        help="write x [m] (a sphere: r [m] from the axis), p [Pa], u_c [m], sigma [m^3/(Pa s)], "
        "resistance share and sealed columns (with --sweep: load [N/m] or, for a sphere, [N], "
        "alpha, p0 [Pa], Q [m^3/s], conductance [m^2/(Pa s) per unit length; a sphere: "
        "m^3/(Pa s)], sealed, share in FWHM, 90%% width [m], min gap [m], converged) to FILE",
    )
    p.add_argument(
        "--plot",
        metavar="FILE",
        help="write a figure of p and u_c against x (a sphere: against r, the hole shaded; with "
        "--sweep: Q against load, log-log)",
    )
    figure_options(p)


def non_negative(text: str) -> float:
    """A finite number >= 0."""
    v = number(text)
    if v < 0.0:
        raise argparse.ArgumentTypeError(f"must be >= 0, got {text!r}")
    return v


def _fluid_options(p: argparse.ArgumentParser, threshold: float) -> None:
    g = p.add_argument_group("fluid and seal")
    g.add_argument(
        "--pressure-drop",
        type=positive,
        nargs="+",
        required=True,
        metavar="PA",
        help="fluid pressure difference across the seal dP [Pa] (required; several with "
        "--coupled: the leak rate against dP)",
    )
    g.add_argument(
        "--coupled",
        action="store_true",
        help="the seal under pressure: the fluid pressure in the interface coupled to the "
        "contact (it lifts the walls), Q against each --pressure-drop and the lift-off "
        "pressure; a cylinder's seal, or a sphere's with --inner-radius "
        f"(default --n {COUPLED_N}; docs/leakage.md)",
    )
    g.add_argument(
        "--viscosity",
        type=positive,
        required=True,
        metavar="PA_S",
        help="dynamic viscosity of the fluid eta [Pa s] (required; water at 20 C: 1e-3)",
    )
    g.add_argument(
        "--length",
        type=positive,
        metavar="M",
        help="seal length L_y across the flow [m] (an O-ring's circumference; default 1); "
        "a cylinder only: the rings around a sphere's hole have their circumferences",
    )
    g.add_argument(
        "--inner-radius",
        type=positive,
        metavar="M",
        help="radius r_in [m] of the hole in the flat seat that the ball closes (required with "
        "--geometry sphere, not for a cylinder): the fluid flows radially from r = r_in "
        "outwards; keep it small against the contact (a warning above 0.1 of the half width "
        "at half maximum of p)",
    )
    g.add_argument(
        "--threshold",
        type=fraction,
        metavar="A",
        help="percolation threshold of the real contact area [-], in (0, 1) (default "
        f"{threshold:g}, Persson, for the critical junction; 0.5, Bruggeman, for the effective "
        "medium; 0.415 numerical studies)",
    )
    g.add_argument(
        "--mean-free-path",
        type=positive,
        metavar="M",
        help="mean free path of a gas [m] (about 70e-9 for air at 1 bar): warns when the flow "
        "is not viscous; omit for liquids",
    )
    _method_options(g)


def _method_options(g) -> None:
    """The local gap measure of the leak rate and its molecular floor."""
    g.add_argument(
        "--method",
        choices=("critical-junction", "effective-medium"),
        default="critical-junction",
        help="local gap of a strip: the critical junction u_c (default) or the effective-medium "
        "gap of Bruggeman's equation over the theory's gap distribution",
    )
    g.add_argument(
        "--gap-floor",
        type=non_negative,
        default=GAP_FLOOR,
        metavar="M",
        help=f"molecular floor of the gap [m] (default {GAP_FLOOR:g}): a strip with a smaller "
        "gap is sealed; 0 switches it off",
    )


def _sweep_options(p: argparse.ArgumentParser) -> None:
    cyl, sph = GEOMETRY_DEFAULTS["cylinder"], GEOMETRY_DEFAULTS["sphere"]
    g = p.add_argument_group("load sweep")
    g.add_argument(
        "--sweep",
        action="store_true",
        help="leak rate against log-spaced loads instead of one --load",
    )
    g.add_argument(
        "--loads-from",
        type=positive,
        metavar="LOAD",
        help=f"smallest load per unit length [N/m] (with --sweep; default {cyl['loads_from']:g})"
        f"; with --geometry sphere the total load F [N] (default {sph['loads_from']:g})",
    )
    g.add_argument(
        "--loads-to",
        type=positive,
        metavar="LOAD",
        help=f"largest load per unit length [N/m] (with --sweep; default {cyl['loads_to']:g}); "
        f"with --geometry sphere the total load F [N] (default {sph['loads_to']:g})",
    )
    g.add_argument(
        "--loads-num",
        type=count,
        metavar="N",
        help=f"number of loads (with --sweep; default {LEAK_SWEEP_DEFAULTS['loads_num']})",
    )


def _leak_checks(args) -> str:
    """Reject what cannot give a leak rate, before any work; fill in the defaults that depend
    on the geometry (load, loads, n, the cylinder's seal length) and the method (the
    threshold). Returns the geometry."""
    _coupled_checks(args)
    if args.threshold is None:
        bruggeman = args.method == "effective-medium"
        args.threshold = theory.THRESHOLD_BRUGGEMAN if bruggeman else theory.THRESHOLD_PERSSON
    if theory.get_variant(args.variant).area_correction:
        raise CLIError(
            f"--variant {args.variant} corrects the contact area, which the critical-junction "
            "leak theory does not: use yang-persson-energy or yang-persson-printed"
        )
    if args.model == "hertz":
        raise CLIError(
            "--model hertz is for smooth surfaces: a leak rate needs a roughness spectrum "
            "(use --model persson or exponential)"
        )
    _flow_path_checks(args)
    given = [f"--{k.replace('_', '-')}" for k in LEAK_SWEEP_DEFAULTS if getattr(args, k)]
    if not args.sweep and given:
        raise CLIError(f"{', '.join(given)} need --sweep")
    if args.sweep and args.load is not None:
        raise CLIError("--load is for one scene: with --sweep give --loads-from/--loads-to")
    geometry = geometry_defaults(args)  # the load (unused by --sweep), the loads, n
    if args.loads_num is None:
        args.loads_num = LEAK_SWEEP_DEFAULTS["loads_num"]
    if args.sweep and args.loads_to < args.loads_from:
        raise CLIError("--loads-to must be >= --loads-from")
    return geometry


def _coupled_checks(args) -> None:
    """--coupled: one scene, any number of pressure drops; without it, one."""
    drops = args.pressure_drop
    if not args.coupled:
        if len(drops) > 1:
            raise CLIError("several --pressure-drop values need --coupled (Q against dP)")
        args.pressure_drop = drops[0]
        return
    if args.sweep:
        raise CLIError(
            "--coupled is for one scene (not with --sweep): it sweeps the pressure drops"
        )
    if args.n is None:
        args.n = COUPLED_N
    args.pressure_drops, args.pressure_drop = sorted(drops), min(drops)


def _flow_path_checks(args) -> None:
    """Where the fluid flows: across a cylinder's contact over --length, or radially out of the
    hole a sphere closes (--inner-radius); the cylinder's seal length defaults to 1 m."""
    if args.geometry == "sphere":
        if args.inner_radius is None:
            raise CLIError(
                "--geometry sphere needs --inner-radius: the radius [m] of the hole in the flat "
                "seat where the fluid enters (the leak is the radial flow from there outwards)"
            )
        if args.length is not None:
            raise CLIError(
                "--length is for a cylinder's seal: the flow out of a sphere's hole is radial, "
                "through whole rings (their circumferences are the length); drop --length"
            )
        return
    if args.inner_radius is not None:
        raise CLIError(
            "--inner-radius is for --geometry sphere (radial flow out of the hole a ball "
            "closes); a cylinder's seal leaks across the contact over --length"
        )
    if args.length is None:
        args.length = _DEFAULT_LENGTH


def _check_inner_radius(args, results) -> None:
    """The hole must lie inside the solved profile of every load: a point contact's profile
    ends at r = (n - 1/2) dr, a domain that grows with the load."""
    if args.inner_radius is None:
        return
    edges = [(r.r.size - 0.5) * r.dr for r in results]
    if args.inner_radius < min(edges):
        return
    k = edges.index(min(edges))
    outside = [r.load for r, e in zip(results, edges, strict=True) if args.inner_radius >= e]
    raise CLIError(
        f"--inner-radius {args.inner_radius:.6g} m is at or beyond the outer edge of the solved "
        f"profile ({_loads_span(outside, len(results), 'F', 'N')}): the profile of F = "
        f"{results[k].load:.4g} N ends at r = {edges[k]:.6g} m, its Hertz contact radius is "
        f"{results[k].hertz_radius:.4g} m; the hole must lie inside the contact (give a smaller "
        "--inner-radius)"
    )


def _leak_of(r, th, args):
    return fl.leak_rate(
        r,
        args.pressure_drop,
        args.viscosity,
        args.length,
        inner_radius=args.inner_radius,
        theory=th,
        threshold=args.threshold,
        method=args.method,
        mean_free_path=args.mean_free_path,
        gap_floor=args.gap_floor,
        warn=False,
        law=args.model if isinstance(args.model, fl.CalibratedLaw) else None,
    )


def _leak_meta(psd, E, args, source) -> dict:
    meta = (sphere_meta if args.geometry == "sphere" else metadata)(psd, E, args, source)
    if args.mean_free_path is not None:
        meta["mean_free_path_m"] = args.mean_free_path
    return meta


def _fluid_line(args) -> str:
    if args.inner_radius is None:
        path = f"seal length {args.length:.6g} m"
    else:
        path = f"radial flow from r = inner radius {args.inner_radius:.6g} m outwards"
    return (
        f"fluid, seal      pressure drop {args.pressure_drop:.6g} Pa, viscosity "
        f"{args.viscosity:.6g} Pa s, {path}, threshold {args.threshold:g} ({args.method} "
        f"theory), gap floor {args.gap_floor:g} m"
    )


def _sealed_lines(leak, strip: str, strips: str) -> list[str]:
    """The lines of a sealed contact: how many strips seal, by which cause."""
    d, t, floor = leak.diagnostics, leak.threshold, leak.gap_floor
    n_floor, n_all = d["n_below_floor"], d["n_strips"]
    if leak.sealed_by == "gap floor":
        why = (
            f"yes: {n_floor} of {n_all} {strips} have a gap below the molecular floor {floor:g} "
            f"m (no {strip} reaches a real contact area P(q1, p) >= {t:g})"
        )
    else:
        n_contact = d["n_sealed"] - n_floor
        more = f", {n_floor} more with the gap below the {floor:g} m floor" if n_floor else ""
        why = (
            f"yes: {d['n_sealed']} of {n_all} {strips} sealed: {n_contact} with a real contact "
            f"area P(q1, p) >= {t:g} (no channel percolates there){more}"
        )
    return [
        "leak rate Q      0 m^3/s (sealed)",
        f"sealed           {why}",
        f"resistance       infinite in the sealed {strips}, {leak.resistance_width:.4g} m "
        "of the contact",
    ]


def _gap_line(leak, strip: str) -> str:
    """The local gap at the strip of highest resistance, named as the method defines it."""
    gap = leak.diagnostics["min_gap"]
    if "law" in leak.diagnostics["gap_table"]:
        return (
            f"hydraulic gap    {gap:.6g} m (the calibrated law's g at the {strip} of highest "
            "resistance)"
        )
    if leak.method == "effective-medium":
        return (
            f"effective gap    {gap:.6g} m (u_eff of Bruggeman's effective medium at the {strip} "
            "of highest resistance)"
        )
    return f"critical gap     {gap:.6g} m (u_c at the {strip} of highest resistance)"


def _leak_lines(leak) -> list[str]:
    d, t = leak.diagnostics, leak.threshold
    radial = leak.inner_radius is not None
    strip, strips = ("ring", "rings") if radial else ("strip", "strips")
    if leak.sealed:
        lines = _sealed_lines(leak, strip, strips)
    else:
        conductance = (
            f"conductance      {leak.conductance:.6g} m^3/(Pa s) of the whole contact "
            "(Q = conductance * pressure drop)"
            if radial
            else f"conductance      {leak.conductance:.6g} m^2/(Pa s) per unit seal length "
            "(Q = conductance * length * pressure drop)"
        )
        fwhm = "inside the FWHM of p (r <= w/2)" if radial else "inside the FWHM of p"
        lines = [
            f"leak rate Q      {leak.Q:.6g} m^3/s",
            conductance,
            f"sealed           no (real contact area P(q1, p) < {t:g} in every {strip}"
            f"{' the flow crosses' if radial else ''})",
            f"resistance       {leak.share_in_fwhm:.1%} of it {fwhm}; 90% of it within "
            f"{leak.resistance_width:.4g} m",
            _gap_line(leak, strip),
            f"junctions across {d['junctions_across']:.3g} (roll-off wavelengths 2pi/qr = "
            f"{d['rolloff_wavelength']:.3g} m across the 90% width; the theory wants >= 5)",
        ]
    if radial:
        lines.append(
            f"orifice share    {d['orifice_share']:.3g} (inner radius over the half width at "
            "half maximum of p; the solid contact's pressure wants it <= 0.1)"
        )
    lines.append(
        f"dP / p0          {d['fluid_pressure_ratio']:.3g} (pressure drop over the peak contact "
        "pressure; the theory wants it small)"
    )
    if d["knudsen"] is not None:
        lines.append(
            f"Knudsen number   {d['knudsen']:.3g} (mean free path / "
            f"{'u_eff' if leak.method == 'effective-medium' else 'u_c'}; viscous flow below 0.1)"
        )
    return lines


def _load_name(results) -> tuple[str, str]:
    """The load's symbol and unit of these results: f_N in N/m (cylinder), F in N (sphere)."""
    return getattr(results[0], "LOAD_SYMBOL", "f_N"), getattr(results[0], "LOAD_UNIT", "N/m")


def _loads_span(loads: list[float], total: int, symbol: str = "f_N", unit: str = "N/m") -> str:
    if total == 1:
        return f"{symbol} = {loads[0]:.4g} {unit}"
    head = f"{len(loads)} of {total} loads: {symbol}"
    if len(loads) <= 4:
        return f"{head} = {', '.join(f'{f:.4g}' for f in loads)} {unit}"
    return f"{head} from {min(loads):.4g} to {max(loads):.4g} {unit}"


def _report_leak_warnings(results, leaks) -> None:
    """The solves' diagnostics, then each leakage warning once, naming the loads."""
    report_warnings(results)
    found: dict[str, list[float]] = {}
    for r, k in zip(results, leaks, strict=True):
        for msg in k.diagnostics["warnings"]:
            found.setdefault(msg, []).append(r.load)
    for msg, loads in found.items():
        warn(f"{msg} [{_loads_span(loads, len(leaks), *_load_name(results))}]")


def _sealing_line(results, leaks) -> str:
    symbol, unit = _load_name(results)
    sealed = [r.load for r, k in zip(results, leaks, strict=True) if k.sealed]
    open_ = [r for r, k in zip(results, leaks, strict=True) if not k.sealed]
    if not sealed:
        p0 = max(r.p0 for r in results)
        return f"sealing          no load of the sweep seals (largest p0 {p0:.4g} Pa)"
    if not open_:
        return (
            f"sealing          every load of the sweep seals (from {symbol} = "
            f"{min(sealed):.4g} {unit})"
        )
    below = [r.load for r in open_ if r.load < min(sealed)]
    last = f" (the largest load that leaks below it: {max(below):.4g} {unit})" if below else ""
    return f"sealing          sealed from {symbol} = {min(sealed):.4g} {unit} on{last}"


def _causes_line(results, leaks) -> str | None:
    """Which cause seals which loads of a sweep (None when no load seals)."""
    symbol, unit = _load_name(results)
    k0, total, parts = leaks[0], len(leaks), []
    causes = (  # in the order of rising load
        ("gap floor", f"the gap is below the molecular floor {k0.gap_floor:g} m"),
        ("percolation", f"the real contact area percolates (P(q1, p) >= {k0.threshold:g})"),
    )
    for cause, text in causes:
        loads = [r.load for r, k in zip(results, leaks, strict=True) if k.sealed_by == cause]
        if loads:
            parts.append(f"{text} at {_loads_span(loads, total, symbol, unit)}")
    return f"sealed by        {'; '.join(parts)}" if parts else None


def _contact(geometry: str):
    """(one-call solver, reusable model class, result lines) of the geometry."""
    if geometry == "sphere":
        return fl.solve_point_contact, fl.PointContact, sphere_result_lines
    return fl.solve_line_contact, fl.LineContact, result_lines


def _leak_one(args, geometry, psd, E, source, th) -> int:
    solve, _, result_lines = _contact(geometry)
    r = solve(psd, E, args.radius, args.load, model=args.model, **solve_kwargs(args, th))
    _check_inner_radius(args, [r])
    leak = _leak_of(r, th, args)
    print(spectrum_line(psd, source))
    print("\n".join(result_lines(r, r.diagnostics)))
    print(_fluid_line(args))
    print("\n".join(_leak_lines(leak)))
    _report_leak_warnings([r], [leak])
    if args.csv:
        fl.io.write_leak_csv(args.csv, leak, _leak_meta(psd, E, args, source), result=r)
    if args.plot:
        save(fl.plotting.plot_leak(leak), args.plot, args)
    return convergence_status([r])


def _leak_sweep(args, geometry, psd, E, source, th) -> int:
    import numpy as np

    _, model_class, _ = _contact(geometry)
    loads = np.geomspace(args.loads_from, args.loads_to, args.loads_num)
    model = model_class(psd, E, args.radius, model=args.model, **solve_kwargs(args, th))
    with progress(len(loads), "leak sweep") as bar:
        results = model.sweep(loads, progress=bar.update)
    _check_inner_radius(args, results)
    leaks = [_leak_of(r, th, args) for r in results]
    print(spectrum_line(psd, source))
    load_head = "load [N/m]"
    if geometry == "sphere":
        print(f"geometry         sphere on a flat, R = {args.radius:.6g} m; loads F in N")
        load_head = "load F [N]"
    print(_fluid_line(args))
    print(
        f"{load_head:>12}{'alpha':>11}{'p0 [Pa]':>12}{'Q [m^3/s]':>13}{'sealed':>8}"
        f"{'in FWHM':>9}{'90% width [m]':>15}{'conv':>6}"
    )
    for r, k in zip(results, leaks, strict=True):
        # where the resistance sits is meaningless once it is infinite
        where = (
            f"{'-':>9}{'-':>15}"
            if k.sealed
            else f"{k.share_in_fwhm:>9.3f}{k.resistance_width:>15.4g}"
        )
        print(
            f"{r.load:>12.4g}{r.alpha:>11.4g}{r.p0:>12.5g}{k.Q:>13.4e}"
            f"{'yes' if k.sealed else 'no':>8}{where}{'yes' if r.converged else 'NO':>6}"
        )
    print(_sealing_line(results, leaks))
    causes = _causes_line(results, leaks)
    if causes:
        print(causes)
    _report_leak_warnings(results, leaks)
    if args.csv:
        fl.io.write_leak_sweep_csv(args.csv, results, leaks, _leak_meta(psd, E, args, source))
    if args.plot:
        save(fl.plotting.plot_leak_sweep(loads, leaks), args.plot, args)
    return convergence_status(results)


def cmd_leak(args: argparse.Namespace) -> int:
    """Run ``fastline leak``; returns the exit status (0 done, 1 a solve did not converge)."""
    psd, E, source = scene(args)
    geometry = _leak_checks(args)
    check_outputs(args)
    th = persson_theory(psd, E, args)
    if args.sweep:
        return _leak_sweep(args, geometry, psd, E, source, th)
    if args.coupled:
        return _leak_coupled(args, geometry, psd, E, source, th)
    return _leak_one(args, geometry, psd, E, source, th)


def _leak_coupled(args, geometry, psd, E, source, th) -> int:
    """One scene, the seal under each pressure drop (fl.seal_leak)."""
    solve, _, result_lines = _contact(geometry)
    r = solve(psd, E, args.radius, args.load, model=args.model, **solve_kwargs(args, th))
    _check_inner_radius(args, [r])
    law = args.model if isinstance(args.model, fl.CalibratedLaw) else None
    try:
        sweep = fl.seal_leak(
            r, args.pressure_drops, args.viscosity, args.length, inner_radius=args.inner_radius,
            theory=th, threshold=args.threshold, method=args.method, gap_floor=args.gap_floor,
            law=law,
        )  # fmt: skip
    except ValueError as e:  # the option's name, not the function's
        raise CLIError(str(e).replace("pressure_drops must", "--pressure-drop must")) from None
    print(spectrum_line(psd, source))
    print("\n".join(result_lines(r, r.diagnostics)))
    print(_fluid_line(args).replace(f"pressure drop {args.pressure_drop:.6g} Pa", "coupled"))
    print(f"{'dP [Pa]':>12}{'Q [m^3/s]':>13}{'uncoupled Q':>13}{'peak p_c':>12}"
          f"{'load on p_c':>13}{'state':>12}")  # fmt: skip
    for k, q_dry in zip(sweep.results, sweep.uncoupled_Q, strict=True):
        state = "lifted off" if k.lifted_off else ("sealed" if k.sealed else "leaks")
        peak = k.diagnostics.get("peak_contact_pressure", 0.0)
        share = k.diagnostics.get("contact_load_share", 0.0)
        print(f"{k.pressure_drop:>12.4g}{k.Q:>13.4e}{q_dry:>13.4e}{peak:>12.4g}{share:>13.3f}"
              f"{state:>12}")  # fmt: skip
    lift = sweep.lift_off_pressure
    print(
        "lift-off         none up to the largest pressure drop"
        if lift is None
        else f"lift-off         dP = {lift:.4g} Pa (the contact carries < 1% of the load)"
    )
    if sweep.geometry == "point":
        share = sweep.diagnostics["orifice_share"]
        print(f"orifice share    {share:.3g} (inner radius over the half width at half maximum "
              "of p; the hole should be small against the contact)")  # fmt: skip
    report_warnings([r])
    if args.plot:
        save(fl.plotting.plot_seal(sweep), args.plot, args)
    bad = [k for k in sweep.results if not (k.converged or k.lifted_off)]
    return max(convergence_status([r]), 1 if bad else 0)
