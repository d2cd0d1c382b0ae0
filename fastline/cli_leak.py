"""``fastline leak``: the leak rate of the seal a scene forms, for one load or a load sweep.

Argument parsing and printing only: the leak rate is :func:`fastline.leakage.leak_rate`
(Persson's critical-junction theory, the strips of the contact in series; docs/leakage.md), the
files are written by :mod:`fastline.io`, the figures drawn by :mod:`fastline.plotting`.
:mod:`fastline.cli` wires :func:`leak_parser` and :func:`cmd_leak` in.

SI units throughout: m, Pa, Pa s, m^3/s, N/m (load per unit cylinder length).
"""

from __future__ import annotations

import argparse

from fastline._cli_common import (
    CLIError,
    _check_outputs,
    _convergence_status,
    _count,
    _figure_options,
    _fraction,
    _material_options,
    _meta,
    _numerics_options,
    _positive,
    _progress,
    _report_warnings,
    _result_lines,
    _save,
    _scene,
    _solve_kwargs,
    _spectrum_line,
    _spectrum_options,
    _theory,
    _warn,
)
from fastline.cli_psd import _scan_options

__all__ = ["leak_parser", "cmd_leak", "LEAK_SWEEP_DEFAULTS"]

#: defaults of the load-sweep options of ``leak --sweep`` (those of ``sweep``)
LEAK_SWEEP_DEFAULTS = {"loads_from": 1e3, "loads_to": 1.5e6, "loads_num": 20}
_DEFAULT_LOAD = 1e4


def leak_parser(sub: argparse._SubParsersAction, fmt: type[argparse.HelpFormatter]) -> None:
    """The ``leak`` command: the options of ``profile``, the fluid and seal, ``--sweep``."""
    from fastline.leakage import THRESHOLD_PERSSON

    p = sub.add_parser(
        "leak",
        help="leak rate of a seal (Persson's critical-junction theory); --sweep: against load",
        formatter_class=fmt,
        description="Solve one scene and compute the leak rate of the seal it forms: the volume "
        "flow Q [m^3/s] of a fluid across the contact line (along x) for a seal of length "
        "--length, from Persson's critical-junction theory with the strips of the contact in "
        "series (docs/leakage.md). Prints Q, the conductance, whether the contact is sealed and "
        "where along x the flow resistance sits. With --sweep: Q against a log-spaced series of "
        "loads (--loads-from/--loads-to/--loads-num instead of --load), how much squeeze stops "
        "the leak.",
    )
    _spectrum_options(p)
    _scan_options(p)
    _material_options(p, load=True)
    p.set_defaults(load=None)  # 1e4 for one scene; not combined with --sweep
    g = p.add_argument_group("fluid and seal")
    g.add_argument(
        "--pressure-drop",
        type=_positive,
        required=True,
        metavar="PA",
        help="fluid pressure difference across the seal dP [Pa] (required)",
    )
    g.add_argument(
        "--viscosity",
        type=_positive,
        required=True,
        metavar="PA_S",
        help="dynamic viscosity of the fluid eta [Pa s] (required; water at 20 C: 1e-3)",
    )
    g.add_argument(
        "--length",
        type=_positive,
        default=1.0,
        metavar="M",
        help="seal length L_y across the flow [m] (an O-ring's circumference; default 1)",
    )
    g.add_argument(
        "--threshold",
        type=_fraction,
        default=THRESHOLD_PERSSON,
        metavar="A",
        help="percolation threshold of the apparent contact area [-], in (0, 1) (default "
        f"{THRESHOLD_PERSSON:g}, Persson; 0.415 numerical studies; 0.5 Bruggeman)",
    )
    g.add_argument(
        "--mean-free-path",
        type=_positive,
        metavar="M",
        help="mean free path of a gas [m] (about 70e-9 for air at 1 bar): warns when the flow "
        "is not viscous; omit for liquids",
    )
    g = p.add_argument_group("load sweep")
    g.add_argument(
        "--sweep",
        action="store_true",
        help="leak rate against log-spaced loads instead of one --load",
    )
    g.add_argument(
        "--loads-from",
        type=_positive,
        metavar="N/M",
        help="smallest load per unit length [N/m] (with --sweep; default 1e3)",
    )
    g.add_argument(
        "--loads-to",
        type=_positive,
        metavar="N/M",
        help="largest load per unit length [N/m] (with --sweep; default 1.5e6)",
    )
    g.add_argument(
        "--loads-num",
        type=_count,
        metavar="N",
        help="number of loads (with --sweep; default 20)",
    )
    _numerics_options(p)
    p.add_argument(
        "--csv",
        metavar="FILE",
        help="write x [m], p [Pa], u_c [m], sigma [m^3/(Pa s)], resistance share and sealed "
        "columns (with --sweep: load [N/m], alpha, p0 [Pa], Q [m^3/s], conductance "
        "[m^2/(Pa s)], sealed, share in FWHM, 90%% width [m], min gap [m], converged) to FILE",
    )
    p.add_argument(
        "--plot",
        metavar="FILE",
        help="write a figure of p(x) and u_c(x) (with --sweep: Q against load, log-log)",
    )
    _figure_options(p)


def _leak_checks(args) -> None:
    """Reject what cannot give a leak rate, before any work; fill in the load defaults."""
    from fastline.variants import get_variant

    if get_variant(args.variant).area_correction:
        raise CLIError(
            f"--variant {args.variant} corrects the contact area, which the critical-junction "
            "leak theory does not: use yang-persson-energy or yang-persson-printed"
        )
    if args.model == "hertz":
        raise CLIError(
            "--model hertz is for smooth surfaces: a leak rate needs a roughness spectrum "
            "(use --model persson or exponential)"
        )
    given = [f"--{k.replace('_', '-')}" for k in LEAK_SWEEP_DEFAULTS if getattr(args, k)]
    if not args.sweep:
        if given:
            raise CLIError(f"{', '.join(given)} need --sweep")
        args.load = _DEFAULT_LOAD if args.load is None else args.load
        return
    if args.load is not None:
        raise CLIError("--load is for one scene: with --sweep give --loads-from/--loads-to")
    for key, value in LEAK_SWEEP_DEFAULTS.items():
        if getattr(args, key) is None:
            setattr(args, key, value)
    if args.loads_to < args.loads_from:
        raise CLIError("--loads-to must be >= --loads-from")


def _leak_of(r, th, args):
    from fastline.leakage import leak_rate

    return leak_rate(
        r,
        args.pressure_drop,
        args.viscosity,
        args.length,
        theory=th,
        threshold=args.threshold,
        mean_free_path=args.mean_free_path,
        warn=False,
    )


def _leak_meta(psd, E, args, source) -> dict:
    meta = _meta(psd, E, args, source)
    if args.mean_free_path is not None:
        meta["mean_free_path_m"] = args.mean_free_path
    return meta


def _fluid_line(args) -> str:
    return (
        f"fluid, seal      pressure drop {args.pressure_drop:.6g} Pa, viscosity "
        f"{args.viscosity:.6g} Pa s, seal length {args.length:.6g} m, threshold "
        f"{args.threshold:g} (critical-junction theory)"
    )


def _leak_lines(leak) -> list[str]:
    d, t = leak.diagnostics, leak.threshold
    if leak.sealed:
        lines = [
            "leak rate Q      0 m^3/s (sealed)",
            f"sealed           yes: {d['n_sealed']} of {d['n_strips']} strips have a real contact "
            f"area P(q1, p) >= {t:g} (no channel percolates there)",
            f"resistance       infinite in the sealed strips, {leak.resistance_width:.4g} m of "
            "the contact",
        ]
    else:
        lines = [
            f"leak rate Q      {leak.Q:.6g} m^3/s",
            f"conductance      {leak.conductance:.6g} m^2/(Pa s) per unit seal length "
            "(Q = conductance * length * pressure drop)",
            f"sealed           no (real contact area P(q1, p) < {t:g} in every strip)",
            f"resistance       {leak.share_in_fwhm:.1%} of it inside the FWHM of p; 90% of it "
            f"within {leak.resistance_width:.4g} m",
            f"critical gap     {d['min_gap']:.6g} m (u_c at the strip of highest resistance)",
            f"junctions across {d['junctions_across']:.3g} (roll-off wavelengths 2pi/qr = "
            f"{d['rolloff_wavelength']:.3g} m across the 90% width; the theory wants >= 5)",
        ]
    lines.append(
        f"dP / p0          {d['fluid_pressure_ratio']:.3g} (pressure drop over the peak contact "
        "pressure; the theory wants it small)"
    )
    if d["knudsen"] is not None:
        lines.append(
            f"Knudsen number   {d['knudsen']:.3g} (mean free path / u_c; viscous flow below 0.1)"
        )
    return lines


def _loads_span(loads: list[float], total: int) -> str:
    if total == 1:
        return f"f_N = {loads[0]:.4g} N/m"
    head = f"{len(loads)} of {total} loads: f_N"
    if len(loads) <= 4:
        return f"{head} = {', '.join(f'{f:.4g}' for f in loads)} N/m"
    return f"{head} from {min(loads):.4g} to {max(loads):.4g} N/m"


def _report_leak_warnings(results, leaks) -> None:
    """The solves' diagnostics, then each leakage warning once, naming the loads."""
    _report_warnings(results)
    found: dict[str, list[float]] = {}
    for r, k in zip(results, leaks, strict=True):
        for msg in k.diagnostics["warnings"]:
            found.setdefault(msg, []).append(r.load)
    for msg, loads in found.items():
        _warn(f"{msg} [{_loads_span(loads, len(leaks))}]")


def _sealing_line(results, leaks) -> str:
    sealed = [r.load for r, k in zip(results, leaks, strict=True) if k.sealed]
    open_ = [r for r, k in zip(results, leaks, strict=True) if not k.sealed]
    if not sealed:
        p0 = max(r.p0 for r in results)
        return f"sealing          no load of the sweep seals (largest p0 {p0:.4g} Pa)"
    if not open_:
        return f"sealing          every load of the sweep seals (from f_N = {min(sealed):.4g} N/m)"
    below = [r.load for r in open_ if r.load < min(sealed)]
    last = f" (the largest load that leaks below it: {max(below):.4g} N/m)" if below else ""
    return f"sealing          sealed from f_N = {min(sealed):.4g} N/m on{last}"


def _leak_one(args, psd, E, source, th) -> int:
    from fastline.line_contact import solve_line_contact

    r = solve_line_contact(
        psd, E, args.radius, args.load, model=args.model, **_solve_kwargs(args, th)
    )
    leak = _leak_of(r, th, args)
    print(_spectrum_line(psd, source))
    print("\n".join(_result_lines(r, r.diagnostics)))
    print(_fluid_line(args))
    print("\n".join(_leak_lines(leak)))
    _report_leak_warnings([r], [leak])
    if args.csv:
        from fastline.io import write_leak_csv

        write_leak_csv(args.csv, leak, _leak_meta(psd, E, args, source), result=r)
    if args.plot:
        from fastline.plotting import plot_leak

        _save(plot_leak(leak), args.plot, args)
    return _convergence_status([r])


def _leak_sweep(args, psd, E, source, th) -> int:
    import numpy as np

    from fastline.line_contact import LineContact

    loads = np.geomspace(args.loads_from, args.loads_to, args.loads_num)
    model = LineContact(psd, E, args.radius, model=args.model, **_solve_kwargs(args, th))
    with _progress(len(loads), "leak sweep") as bar:
        results = model.sweep(loads, progress=bar.update)
    leaks = [_leak_of(r, th, args) for r in results]
    print(_spectrum_line(psd, source))
    print(_fluid_line(args))
    print(
        f"{'load [N/m]':>12}{'alpha':>11}{'p0 [Pa]':>12}{'Q [m^3/s]':>13}{'sealed':>8}"
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
    _report_leak_warnings(results, leaks)
    if args.csv:
        from fastline.io import write_leak_sweep_csv

        write_leak_sweep_csv(args.csv, results, leaks, _leak_meta(psd, E, args, source))
    if args.plot:
        from fastline.plotting import plot_leak_sweep

        _save(plot_leak_sweep(loads, leaks), args.plot, args)
    return _convergence_status(results)


def cmd_leak(args: argparse.Namespace) -> int:
    """Run ``fastline leak``; returns the exit status (0 done, 1 a solve did not converge)."""
    psd, E, source = _scene(args)
    _leak_checks(args)
    _check_outputs(args)
    th = _theory(psd, E, args)
    if args.sweep:
        return _leak_sweep(args, psd, E, source, th)
    return _leak_one(args, psd, E, source, th)
