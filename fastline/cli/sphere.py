"""``--geometry sphere``: the commands ``profile``, ``sweep`` and ``paper`` for a sphere on a flat.

A rigid sphere of radius R on the rough elastic half-space (a point contact): p(r), the FWHM w
along a diameter, s^2 = int r^2 p dA / (2F), alpha = h_rms / delta with delta = a^2/R; the load
is the total load F on the sphere in N. Argument parsing and printing only: the solver is
:class:`fastline.PointContact`, files :mod:`fastline.io` and
:func:`fastline.paper.write_sphere_files`, figures :mod:`fastline.plotting`.
:mod:`fastline.cli.app` dispatches here when :func:`fastline.cli.common.geometry_defaults`
returns ``"sphere"``; :mod:`fastline.cli.leak` prints a sphere's solve with
:func:`sphere_result_lines`.

SI units throughout: m, 1/m, Pa, N (load on a sphere), N/m (load per unit cylinder length).
"""

from __future__ import annotations

import argparse
import time
from types import SimpleNamespace
from typing import TYPE_CHECKING

import fastline as fl
from fastline.cli.common import (
    CLIError,
    alpha_cell,
    asperity_lines,
    check_outputs,
    convergence_status,
    law_lines,
    metadata,
    model_line,
    persson_theory,
    progress,
    report_warnings,
    roughness_lines,
    save,
    solve_kwargs,
    spectrum_line,
    sweep_in_parallel,
    table_status,
)
from fastline.cli.scene import run_profile, scene

if TYPE_CHECKING:  # annotations only
    from fastline import PSD, PointContactResult

__all__ = [
    "sphere_result_lines",
    "sphere_meta",
    "cmd_sphere_profile",
    "cmd_sphere_sweep",
    "cmd_sphere_paper",
]


def sphere_result_lines(r: PointContactResult, diag: dict) -> list[str]:
    """The printed result of a sphere's solve (``profile``, ``leak``)."""
    a = r.hertz_radius
    r99, r1 = r.load_radius(0.99), r.pressure_radius(0.01)
    lines = [
        f"model            {r.model} (method {r.method}, n = {r.diagnostics.get('n', '?')} "
        "cells from the axis)",
        "geometry         sphere on a flat (point contact)",
        f"load F           {r.load:.6g} N (total load on the sphere)",
        f"E*, R            {r.E_star:.6g} Pa, {r.radius:.6g} m (sphere radius)",
        *roughness_lines(r, diag, delta="delta = a^2/R"),
        f"Hertz radius a   {a:.6g} m (Hertz contact diameter {2 * a:.6g} m)",
        f"peak pressure p0 {r.p0:.6g} Pa",
        f"p0 / p0(Hertz)   {r.p0_ratio:.6g}",
        f"std. dev. s      {r.s:.6g} m (s^2 = int r^2 p dA / 2F, along a diameter)",
        f"FWHM w           {r.fwhm:.6g} m along a diameter ({diag['fwhm_cells']:.3g} grid cells)",
        f"w/s              {r.w_over_s:.6g}   (Hertz sphere 3.873, Gaussian 2.355)",
        f"99% of F within  r = {r99:.6g} m (diameter {2 * r99:.6g} m)",
        f"p = 1% p0 at     r = {r1:.6g} m (diameter {2 * r1:.6g} m)",
    ]
    lines += asperity_lines(diag)
    lines.append(f"contact radius/R {diag['half_width_over_radius']:.4g}")
    if diag.get("longest_wavelength") is not None:
        lines.append(
            f"width / (2pi/q0) {diag['contact_width'] / diag['longest_wavelength']:.3g} "
            "(contact diameter over the longest roughness wavelength; the theory wants >= 1)"
        )
    lines += law_lines(diag)
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


def sphere_meta(psd: PSD, E_star: float, args: argparse.Namespace, source: str | None) -> dict:
    """The scene's metadata of a sphere's result file."""
    return {**metadata(psd, E_star, args, source), "geometry": "sphere"}


def cmd_sphere_profile(args: argparse.Namespace) -> int:
    """``fastline profile --geometry sphere``: one scene; returns the exit status."""
    return run_profile(
        args,
        fl.solve_point_contact,
        sphere_result_lines,
        fl.io.write_point_profile_csv,
        sphere_meta,
    )


def cmd_sphere_sweep(args: argparse.Namespace) -> int:
    """``fastline sweep --geometry sphere``: log-spaced loads F; returns the exit status."""
    import numpy as np

    psd, E, source = scene(args)
    if args.loads_to < args.loads_from:
        raise CLIError("--loads-to must be >= --loads-from")
    check_outputs(args)
    loads = np.geomspace(args.loads_from, args.loads_to, args.loads_num)
    th = persson_theory(psd, E, args)
    table = None
    if args.workers is None and args.scheduler is None:
        model = fl.PointContact(psd, E, args.radius, model=args.model, **solve_kwargs(args, th))
        with progress(len(loads), "sweep") as bar:
            results = model.sweep(loads, progress=bar.update)
    else:
        results, table = _sweep_on_executor(psd, E, args, loads)
    print(spectrum_line(psd, source, args.model))
    if len(results):
        print(model_line(results[0]))
    print(f"geometry         sphere on a flat, R = {args.radius:.6g} m; loads F in N")
    print(
        f"{'load F [N]':>12}{'alpha':>12}{'p0 [Pa]':>13}{'p0 ratio':>10}{'s [m]':>12}"
        f"{'w [m]':>12}{'w/s':>8}{'conv':>6}"
    )
    for r in results:
        print(
            f"{r.load:>12.4g}{alpha_cell(r, 12)}{r.p0:>13.5g}{r.p0_ratio:>10.5f}{r.s:>12.4g}"
            f"{r.fwhm:>12.4g}{r.w_over_s:>8.4f}{'yes' if r.converged else 'NO':>6}"
        )
    if table is None:
        report_warnings(results)
    if args.csv:
        fl.io.write_point_sweep_csv(args.csv, results, sphere_meta(psd, E, args, source))
    if args.plot:
        gu = th.exponential_fit().gamma_u if th is not None else None
        save(fl.plotting.plot_sweep(results, gamma_u=gu), args.plot, args)
    if table is None:
        return convergence_status(results)
    return table_status(table)


def _sweep_on_executor(psd, E, args, loads):
    """--workers/--scheduler: the loads as sphere scenes of :func:`fastline.sweep` (the
    cylinder's path, :func:`fastline.cli.common.sweep_in_parallel`); rows with the attributes of a
    :class:`~fastline.PointContactResult` that the table, the CSV file and the figure read
    (``hertz_radius`` tells the figure it is a sphere) and the sweep's table."""
    rows, table = sweep_in_parallel(psd, E, args, loads)
    names = ("load", "alpha", "p0", "p0_ratio", "s", "fwhm", "w_over_s", "converged")
    results = [
        SimpleNamespace(
            **{k: row[k].item() for k in names},
            model=args.model,  # the table's rows name no model; the printed table asks
            hertz_radius=fl.hertz_point_contact(E, args.radius, float(row["load"])).a,
        )
        for row in rows
    ]
    return results, table


def cmd_sphere_paper(args: argparse.Namespace) -> int:
    """``fastline paper --geometry sphere``: the sphere versions of Figs. 3-5; returns the exit
    status."""
    paper = fl.paper
    check_outputs(args)
    t0 = time.perf_counter()
    with progress(len(paper.SURFACES) * args.loads, "paper (sphere)") as bar:
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
        f"{fl.io.spectrum_summary(data.surfaces[0].psd)['longest_wavelength']:.3g} m)"
    )
    report_warnings(data.results)
    print(f"wrote {', '.join(written)} to {args.out}")
    return convergence_status(data.results)
