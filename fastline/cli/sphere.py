"""``--geometry sphere``: the commands ``profile``, ``sweep`` and ``paper`` for a sphere on a flat.

A rigid sphere of radius R on the rough elastic half-space (a point contact): p(r), the FWHM w
along a diameter, s^2 = int r^2 p dA / (2F), alpha = h_rms / delta with delta = a^2/R; the load
is the total load F on the sphere in N. Argument parsing and printing only: the solver is
:mod:`fastline.contact.point`, files :mod:`fastline.io` and
:func:`fastline.reports.paper.write_sphere_files`, figures :mod:`fastline.reports.plotting`.
:mod:`fastline.cli.app` dispatches here when :func:`geometry_defaults` returns ``"sphere"``.

SI units throughout: m, 1/m, Pa, N (load on a sphere), N/m (load per unit cylinder length).
"""

from __future__ import annotations

import argparse
import time

from fastline.cli.common import (
    CLIError,
    _alpha_cell,
    _asperity_lines,
    _check_outputs,
    _convergence_status,
    _law_lines,
    _meta,
    _positive,
    _progress,
    _report_warnings,
    _roughness_lines,
    _save,
    _scene,
    _solve_kwargs,
    _spectrum_line,
    _theory,
    run_profile,
)

__all__ = [
    "GEOMETRIES",
    "GEOMETRY_DEFAULTS",
    "geometry_defaults",
    "cmd_sphere_profile",
    "cmd_sphere_sweep",
    "cmd_sphere_paper",
]

GEOMETRIES = ("cylinder", "sphere")
#: defaults that depend on the geometry (loads in N/m for a cylinder, N for a sphere)
GEOMETRY_DEFAULTS = {
    "cylinder": {"load": 1e4, "loads_from": 1e3, "loads_to": 1.5e6, "n": 1024},
    "sphere": {"load": 10.0, "loads_from": 0.1, "loads_to": 1e3, "n": 512},
}


def _geometry_options(m, load: bool) -> None:
    """--geometry, --radius and (``load``) --load, whose unit follows the geometry."""
    m.add_argument(
        "--geometry",
        choices=GEOMETRIES,
        default="cylinder",
        help="rigid cylinder on a flat (line contact, default) or sphere on a flat (point "
        "contact); the load is per unit length [N/m] for a cylinder, the total load [N] for a "
        "sphere",
    )
    m.add_argument(
        "--radius",
        type=_positive,
        default=0.01,
        metavar="M",
        help="cylinder radius R [m], or the sphere's with --geometry sphere (default 0.01)",
    )
    if load:
        m.add_argument(
            "--load",
            type=_positive,
            metavar="LOAD",
            help="normal load per unit cylinder length f_N [N/m] (default 1e4); with "
            "--geometry sphere the total load F on the sphere [N] (default 10)",
        )


def geometry_defaults(args: argparse.Namespace) -> str:
    """Fill the options whose default depends on the geometry; returns the geometry."""
    geometry = getattr(args, "geometry", "cylinder")
    for key, value in GEOMETRY_DEFAULTS[geometry].items():
        if hasattr(args, key) and getattr(args, key) is None:
            setattr(args, key, value)
    return geometry


def _sphere_result_lines(r, diag) -> list[str]:
    a = r.hertz_radius
    r99, r1 = r.load_radius(0.99), r.pressure_radius(0.01)
    lines = [
        f"model            {r.model} (method {r.method}, n = {r.diagnostics.get('n', '?')} "
        "cells from the axis)",
        "geometry         sphere on a flat (point contact)",
        f"load F           {r.load:.6g} N (total load on the sphere)",
        f"E*, R            {r.E_star:.6g} Pa, {r.radius:.6g} m (sphere radius)",
        *_roughness_lines(r, diag, delta="delta = a^2/R"),
        f"Hertz radius a   {a:.6g} m (Hertz contact diameter {2 * a:.6g} m)",
        f"peak pressure p0 {r.p0:.6g} Pa",
        f"p0 / p0(Hertz)   {r.p0_ratio:.6g}",
        f"std. dev. s      {r.s:.6g} m (s^2 = int r^2 p dA / 2F, along a diameter)",
        f"FWHM w           {r.fwhm:.6g} m along a diameter ({diag['fwhm_cells']:.3g} grid cells)",
        f"w/s              {r.w_over_s:.6g}   (Hertz sphere 3.873, Gaussian 2.355)",
        f"99% of F within  r = {r99:.6g} m (diameter {2 * r99:.6g} m)",
        f"p = 1% p0 at     r = {r1:.6g} m (diameter {2 * r1:.6g} m)",
    ]
    lines += _asperity_lines(diag)
    lines.append(f"contact radius/R {diag['half_width_over_radius']:.4g}")
    if diag.get("longest_wavelength") is not None:
        lines.append(
            f"width / (2pi/q0) {diag['contact_width'] / diag['longest_wavelength']:.3g} "
            "(contact diameter over the longest roughness wavelength; the theory wants >= 1)"
        )
    lines += _law_lines(diag)
    d = r.diagnostics
    lines += [
        f"converged        {'yes' if r.converged else 'NO'} ({r.iterations} iterations, "
        f"{r.convolutions} operator applications: {d['k_applications']} products with K, "
        f"{d['preconditioner_solves']} preconditioner solves; residual {r.residual:.3g})",
        f"force error      {r.force_error:.3g} (relative); edge pressure {r.edge_pressure:.3g} p0",
    ]
    if r.message:
        lines.append(f"solver message   {r.message}")
    return lines


def _sphere_meta(psd, E_star, args, source):
    return {**_meta(psd, E_star, args, source), "geometry": "sphere"}


def cmd_sphere_profile(args: argparse.Namespace) -> int:
    """``fastline profile --geometry sphere``: one scene; returns the exit status."""
    from fastline.contact.point import solve_point_contact
    from fastline.io import write_point_profile_csv

    return run_profile(
        args, solve_point_contact, _sphere_result_lines, write_point_profile_csv, _sphere_meta
    )


def cmd_sphere_sweep(args: argparse.Namespace) -> int:
    """``fastline sweep --geometry sphere``: log-spaced loads F; returns the exit status."""
    import numpy as np

    from fastline.contact.point import PointContact

    psd, E, source = _scene(args)
    if args.loads_to < args.loads_from:
        raise CLIError("--loads-to must be >= --loads-from")
    _check_outputs(args)
    loads = np.geomspace(args.loads_from, args.loads_to, args.loads_num)
    th = _theory(psd, E, args)
    table = None
    if args.workers is None and args.scheduler is None:
        model = PointContact(psd, E, args.radius, model=args.model, **_solve_kwargs(args, th))
        with _progress(len(loads), "sweep") as bar:
            results = model.sweep(loads, progress=bar.update)
    else:
        results, table = _sweep_on_executor(psd, E, args, loads)
    print(_spectrum_line(psd, source, args.model))
    print(f"geometry         sphere on a flat, R = {args.radius:.6g} m; loads F in N")
    print(
        f"{'load F [N]':>12}{'alpha':>12}{'p0 [Pa]':>13}{'p0 ratio':>10}{'s [m]':>12}"
        f"{'w [m]':>12}{'w/s':>8}{'conv':>6}"
    )
    for r in results:
        print(
            f"{r.load:>12.4g}{_alpha_cell(r, 12)}{r.p0:>13.5g}{r.p0_ratio:>10.5f}{r.s:>12.4g}"
            f"{r.fwhm:>12.4g}{r.w_over_s:>8.4f}{'yes' if r.converged else 'NO':>6}"
        )
    if table is None:
        _report_warnings(results)
    if args.csv:
        from fastline.io import write_point_sweep_csv

        write_point_sweep_csv(args.csv, results, _sphere_meta(psd, E, args, source))
    if args.plot:
        from fastline.reports.plotting import plot_sweep

        gu = th.exponential_fit().gamma_u if th is not None else None
        _save(plot_sweep(results, gamma_u=gu), args.plot, args)
    if table is None:
        return _convergence_status(results)
    from fastline.cli.app import _table_status

    return _table_status(table)


def _sweep_on_executor(psd, E, args, loads):
    """--workers/--scheduler: the loads as sphere scenes of :func:`fastline.sweep` (the
    cylinder's path, :func:`fastline.cli.app._sweep_in_parallel`); rows with the attributes of a
    :class:`~fastline.PointContactResult` that the table, the CSV file and the figure read
    (``hertz_radius`` tells the figure it is a sphere) and the sweep's table."""
    from types import SimpleNamespace

    from fastline.cli.app import _sweep_in_parallel  # here: fastline.cli.app imports this module
    from fastline.theory.limits import hertz_point_contact

    rows, table = _sweep_in_parallel(psd, E, args, loads)
    names = ("load", "alpha", "p0", "p0_ratio", "s", "fwhm", "w_over_s", "converged")
    results = [
        SimpleNamespace(
            **{k: row[k].item() for k in names},
            model=args.model,  # the table's rows name no model; the printed table asks
            hertz_radius=hertz_point_contact(E, args.radius, float(row["load"])).a,
        )
        for row in rows
    ]
    return results, table


def cmd_sphere_paper(args: argparse.Namespace) -> int:
    """``fastline paper --geometry sphere``: the sphere versions of Figs. 3-5; returns the exit
    status."""
    from fastline.io import spectrum_summary
    from fastline.reports import paper

    _check_outputs(args)
    t0 = time.perf_counter()
    with _progress(len(paper.SURFACES) * args.loads, "paper (sphere)") as bar:
        data = paper.sphere_paper_data(
            q1=args.q1,
            loads=args.loads,
            n=args.n,
            gamma=args.gamma,
            max_iter=args.max_iter,
            hardness=args.hardness,
            progress=lambda _label: bar.update(),
            variant=args.variant,
        )
    elapsed = time.perf_counter() - t0
    written = paper.write_sphere_files(data, args.out, format=args.format, dpi=args.dpi)
    lo, hi = paper.SPHERE_ALPHA_RANGE
    print(
        f"fastline paper (sphere): E* = {paper.E_STAR:g} Pa, R = {paper.RADIUS:g} m (sphere), "
        f"q0 = {paper.Q0:g} 1/m, qr = {paper.QR:g} 1/m, q1 = {args.q1:g} 1/m, gamma = "
        f"{args.gamma:g}, n = {args.n}; {args.loads} loads per surface, alpha {lo:g}..{hi:g}; "
        f"solved in {elapsed:.2f} s"
    )
    print(
        f"{'surface':<10}{'h_rms [m]':>10}{'H':>5}{'gamma_u':>9}{'load F range [N]':>23}"
        f"{'w/s range':>17}{'p0 ratio range':>21}{'not conv.':>10}"
    )
    for s in data.surfaces:
        rs = s.results
        f, ws, pr = ([getattr(r, k) for r in rs] for k in ("load", "w_over_s", "p0_ratio"))
        bad = sum(not r.converged for r in rs)
        print(
            f"{s.label:<10}{s.h_rms:>10.3g}{s.hurst:>5.2g}{s.gamma_u:>9.4f}"
            f"{min(f):>11.3g}-{max(f):<11.3g}{min(ws):>8.4f}-{max(ws):<8.4f}"
            f"{min(pr):>10.4g}-{max(pr):<10.4g}{bad:>10d}"
        )
    print(
        f"spectra          q {paper.Q0:g}-{args.q1:g} 1/m (longest wavelength "
        f"{spectrum_summary(data.surfaces[0].psd)['longest_wavelength']:.3g} m)"
    )
    _report_warnings(data.results)
    print(f"wrote {', '.join(written)} to {args.out}")
    return _convergence_status(data.results)
