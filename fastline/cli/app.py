"""Command-line interface: ``fastline paper | profile | sweep | leak | batch | psd | validate |
calibrate``
(``python -m fastline``).

Argument parsing and printing only: the scenes of the paper live in :mod:`fastline.paper`, files
in :mod:`fastline.io`, figures in :mod:`fastline.plotting`, validity checks in
:func:`fastline.assess`, measured surfaces in :func:`fastline.surfaces.analyse_scan`. This module
holds the parser, the cylinder's ``profile``, ``sweep``, ``batch`` and ``paper`` and
:func:`main`, on top of the others: the other commands have their own modules
(:mod:`fastline.cli.leak`, :mod:`fastline.cli.psd`, :mod:`fastline.cli.calibrate`,
:mod:`fastline.cli.sphere` for ``--geometry sphere``, :mod:`fastline.cli.validate`), the scene
of the options is :mod:`fastline.cli.scene` and what they all share is in
:mod:`fastline.cli.common`.

Exit status: 0 done; 1 a solve did not converge or a scene of a batch failed (results are still
printed and written); 2 bad usage or input (one ``fastline: error: ...`` line on stderr,
nothing solved).

SI units throughout: lengths in m, wavenumbers in 1/m, spectra C(q) in m^4, pressures and
moduli in Pa, loads per unit cylinder length in N/m.
"""

from __future__ import annotations

import argparse
import os
import re
import sys
import time
import warnings

import fastline as fl
from fastline import batch, theory
from fastline.cli.calibrate import calibrate_parser, cmd_calibrate
from fastline.cli.common import (
    GEOMETRIES,
    CLIError,
    alpha_cell,
    check_outputs,
    convergence_status,
    count,
    figure_options,
    geometry_defaults,
    material_options,
    metadata,
    model_checks,
    model_line,
    numerics_options,
    persson_theory,
    positive,
    progress,
    report_warnings,
    result_lines,
    run_table,
    save,
    solve_kwargs,
    spectrum_line,
    spectrum_options,
    sweep_in_parallel,
    table_status,
)
from fastline.cli.compile import cmd_compile, compile_parser
from fastline.cli.leak import cmd_leak, leak_parser
from fastline.cli.psd import cmd_psd, psd_parser
from fastline.cli.scene import run_profile, scan_options, scene
from fastline.cli.sphere import cmd_sphere_paper, cmd_sphere_profile, cmd_sphere_sweep
from fastline.cli.validate import cmd_validate, validate_parser

DESCRIPTION = """\
fastline: nominal contact pressure of a rigid cylinder (radius R) pressed onto a randomly rough
elastic half-space, from Persson's contact theory (Tiwari & Persson, "Cylinder-flat contact
mechanics with surface roughness"). The roughness enters through its power spectrum C(q); the
result is the pressure profile p(x) across the contact line, its peak p0, width (standard
deviation s, full width at half maximum w) and how far it is from the smooth Hertz solution,
measured by alpha = h_rms / delta (delta = 4 f_N / (pi E*), the Hertz penetration).

With --geometry sphere (profile, sweep, leak, paper) the same for a rigid sphere on the flat (a
point contact): p(r), the FWHM w along a diameter, s^2 = int r^2 p dA / (2F), delta = a^2/R; the
load is then the total load F on the sphere in N (leak: the radial flow out of a hole of radius
--inner-radius in the flat).

From a measurement: fastline psd SCAN turns a line scan or height map into the spectrum C(q)
(summary, fit, a table for --psd, a figure); --scan SCAN on profile, sweep and leak solves
straight from it.

SI units everywhere: m, 1/m, m^4, Pa, N/m (load per unit cylinder length), N (load on a sphere).
Exit status: 0 done, 1 a solve did not converge (or a scene of a batch failed), 2 bad usage
or input."""

EPILOG = """\
examples:
  fastline profile --h-rms 10e-6 --hurst 0.8 --load 1e4 --csv p.csv --plot p.png
  fastline profile --psd examples/psd_example.txt --E1 2.1e11 --nu1 0.3 --E2 5e6 --nu2 0.49 \\
                   --load 500
  fastline sweep --h-rms 1e-6 --loads-from 1e3 --loads-to 1e6 --loads-num 30 --csv sweep.csv
  fastline profile --geometry sphere --load 500 --E1 2.1e11 --nu1 0.3 --E2 7e10 --nu2 0.33
  fastline leak --h-rms 1e-6 --load 1e4 --pressure-drop 1e4 --viscosity 1e-3 --plot leak.png
  fastline leak --geometry sphere --h-rms 0.3e-6 --q0 5e4 --qr 5e5 --load 10 \\
                --inner-radius 20e-6 --pressure-drop 1e4 --viscosity 1e-3
  fastline sweep --loads-num 400 --workers 2 --csv sweep.csv
  fastline batch scenes.csv --out results.csv --workers 2
  fastline validate --alpha 1 --all-variants --gw --realizations 8 --plot validate.png
  fastline paper --out figs/ --format pdf
  fastline psd examples/scan_example.txt --dx 1e-6 --units um --out psd.csv --plot psd.png
  fastline profile --scan examples/scan_example.txt --dx 1e-6 --units um --q1 1e9 --extend"""

# a negative number as an option value ("--load -1e4"): argparse would take it for an option
_NEGATIVE_NUMBER = re.compile(r"^-(\d+\.?\d*|\.\d+)([eE][-+]?\d+)?$|^-(inf|nan)$", re.IGNORECASE)


class _Parser(argparse.ArgumentParser):
    """argparse that reports errors as a single line (no usage dump), exit status 2."""

    def error(self, message):  # noqa: D102
        raise CLIError(message)


def _join_negative_values(argv: list[str]) -> list[str]:
    """``["--load", "-1e4"]`` -> ``["--load=-1e4"]`` so the option's own check reports it."""
    out: list[str] = []
    for tok in argv:
        prev = out[-1] if out else ""
        if _NEGATIVE_NUMBER.match(tok) and prev.startswith("--") and "=" not in prev:
            out[-1] = f"{prev}={tok}"
        else:
            out.append(tok)
    return out


def _parallel_options(parser: argparse.ArgumentParser, default: str) -> None:
    g = parser.add_argument_group(
        "parallel execution",
        "Solve on several processes or a dask.distributed cluster (fastline.sweep): scenes of "
        "one model are cut into tasks of consecutive loads; the numbers do not depend on "
        f"where the tasks are solved. Default: {default}.",
    )
    g.add_argument(
        "--workers",
        type=count,
        metavar="N",
        help="solve on N local processes (1: in this process)",
    )
    g.add_argument(
        "--scheduler",
        metavar="ADDRESS",
        help="solve on the dask.distributed cluster whose scheduler is at ADDRESS, e.g. "
        'tcp://host:8786 (needs dask: pip install "fastline-contact[dask]" for the extra)',
    )
    g.add_argument(
        "--chunksize",
        type=count,
        metavar="K",
        help="scenes per task at most (default: about 64 tasks, 8 to 256 scenes each)",
    )


def build_parser() -> argparse.ArgumentParser:
    """The ``fastline`` argument parser (commands ``paper``, ``profile``, ``sweep``,
    ``batch``, ``leak``, ``psd``, ``validate``), one function per command."""
    fmt = argparse.RawDescriptionHelpFormatter
    parser = _Parser(prog="fastline", description=DESCRIPTION, epilog=EPILOG, formatter_class=fmt)
    parser.add_argument("--version", action="version", version=f"fastline {fl.__version__}")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND")

    _paper_parser(sub, fmt)
    _profile_parser(sub, fmt)
    _sweep_parser(sub, fmt)
    _batch_parser(sub, fmt)
    leak_parser(sub, fmt)
    psd_parser(sub, fmt)
    validate_parser(sub, fmt)
    compile_parser(sub, fmt)
    calibrate_parser(sub, fmt)
    return parser


def _paper_parser(sub, fmt) -> None:
    """The ``paper`` command: the paper's figures."""
    p = sub.add_parser(
        "paper",
        help="reproduce the paper's Figs. 2-5 (a figure + CSV each)",
        formatter_class=fmt,
        description="Reproduce Figs. 2-5 of Tiwari & Persson: C(q) of surfaces 1-3 (fig2_psd), "
        "p(x) rough vs Hertz at f_N = 1e4 N/m (fig3_profile), w/s vs alpha (fig4_ws) and "
        "p0(rough)/p0(Hertz) vs alpha with the Gaussian asymptote, eq. 14 (fig5_p0ratio). "
        "E* = 1.33 GPa, R = 1 cm, q0 = 1e3 1/m, qr = 1e4 1/m. With --geometry sphere: their "
        "sphere versions (fig3_profile_sphere, fig4_ws_sphere, fig5_p0ratio_sphere; R = 1 cm "
        "the sphere's radius), loads F [N] chosen per surface so that alpha = h_rms / delta "
        "(delta = a^2/R) is log-spaced over 1e-3..1e3.",
    )
    p.add_argument("--out", required=True, metavar="DIR", help="output directory (created)")
    p.add_argument(
        "--loads",
        type=count,
        default=40,
        metavar="N",
        help="loads per surface, log-spaced from 1e3 to 1.5e6 N/m (default 40); with --geometry "
        "sphere: loads F [N] log-spaced so that alpha runs over 1e-3..1e3",
    )
    p.add_argument(
        "--q1",
        type=positive,
        default=1e9,
        metavar="1/M",
        help="large-wavenumber cut-off q1 [1/m] (the paper does not state it; default 1e9)",
    )
    p.add_argument(
        "--geometry",
        choices=GEOMETRIES,
        default="cylinder",
        help="cylinder on a flat (the paper's figures, default) or sphere on a flat",
    )
    numerics_options(p, model=False, geometry=True)
    figure_options(p)


def _profile_parser(sub, fmt) -> None:
    """The ``profile`` command: one scene."""
    p = sub.add_parser(
        "profile",
        help="solve one scene: p(x), p0, widths, regime, diagnostics",
        formatter_class=fmt,
        description="Solve one cylinder-on-flat scene (or, with --geometry sphere, "
        "sphere-on-flat) and print the spectrum, the peak pressure, widths, alpha, regime, "
        "validity diagnostics and solver convergence.",
    )
    spectrum_options(p)
    scan_options(p)
    material_options(p, load=True, geometry=True)
    numerics_options(p, geometry=True)
    p.add_argument(
        "--csv",
        metavar="FILE",
        help="write x [m], p [Pa], u [m] columns to FILE (a sphere: r [m] from the axis)",
    )
    p.add_argument("--plot", metavar="FILE", help="write a figure of p(x) with Hertz to FILE")
    figure_options(p)


def _sweep_parser(sub, fmt) -> None:
    """The ``sweep`` command: a log-spaced series of loads."""
    p = sub.add_parser(
        "sweep",
        help="solve a log-spaced series of loads",
        formatter_class=fmt,
        description="Solve the scene for log-spaced loads and tabulate alpha, p0, p0 ratio, "
        "s, w and w/s.",
    )
    spectrum_options(p)
    scan_options(p)
    material_options(p, load=False, geometry=True)
    p.add_argument(
        "--loads-from",
        type=positive,
        metavar="LOAD",
        help="smallest load: per unit length [N/m] (default 1e3); with --geometry sphere the "
        "total load F [N] (default 0.1)",
    )
    p.add_argument(
        "--loads-to",
        type=positive,
        metavar="LOAD",
        help="largest load: per unit length [N/m] (default 1.5e6); with --geometry sphere the "
        "total load F [N] (default 1e3)",
    )
    p.add_argument(
        "--loads-num", type=count, default=20, metavar="N", help="number of loads (default 20)"
    )
    numerics_options(p, geometry=True)
    p.add_argument(
        "--csv",
        metavar="FILE",
        help="write the table (load [N/m] or, for a sphere, [N], alpha, p0 [Pa], p0_ratio, "
        "s [m], w [m], w_over_s, converged) to FILE",
    )
    p.add_argument("--plot", metavar="FILE", help="write a figure of w/s and p0 ratio vs alpha")
    figure_options(p)
    _parallel_options(
        p,
        "one continuation sweep in this process (its numbers differ from the tasks' within "
        "the solver tolerance)",
    )


def _batch_parser(sub, fmt) -> None:
    """The ``batch`` command: a table of scenes from a CSV file."""
    p = sub.add_parser(
        "batch",
        help="solve a table of scenes from a CSV file (in parallel)",
        formatter_class=fmt,
        description="Solve every scene (row) of a CSV file and write one row of results per "
        "scene. Columns (header row; units in the name optional, e.g. E_star or E_star_Pa): "
        "the spectrum as h_rms, hurst, q0, qr, q1 or as psd (a spectrum file, relative to the "
        "CSV file); E_star [Pa], radius [m], load [N/m; N with geometry sphere]; optional label, "
        "geometry (cylinder, the default, or sphere), "
        "model, law (a calibrated-law file, relative to the CSV file, in place of the model), "
        "method, n, variant (yang-persson-energy, yang-persson-printed, wang-mueser), "
        "gamma (default: the variant's), tol, max_iter, hardness [Pa]; an empty cell takes the "
        "default. A scene that fails (a value out of range, an unreadable spectrum or law file, "
        "a law made for another spectrum or E*) is reported in its row's error column; the "
        "others are solved.",
    )
    p.add_argument("scenes", metavar="SCENES.csv", help="the scene table")
    p.add_argument("--out", required=True, metavar="FILE", help="write the results (CSV) to FILE")
    p.add_argument(
        "--law",
        metavar="FILE",
        help="a calibrated law (fastline calibrate --out FILE) for the rows that name neither a "
        "model nor a law; checked against their spectra and E* before any solve. Workers read "
        "the file at its path (checksum checked): on a cluster, put it where they see it",
    )
    _parallel_options(p, "a local process per CPU")


# ----------------------------------------------------------------------------------------------
# commands
# ----------------------------------------------------------------------------------------------
def cmd_profile(args) -> int:
    """``fastline profile``: one scene; returns the exit status."""
    if geometry_defaults(args) == "sphere":
        return cmd_sphere_profile(args)
    return run_profile(args, fl.solve_line_contact, result_lines, fl.io.write_profile_csv, metadata)


def cmd_sweep(args) -> int:
    """``fastline sweep``: log-spaced loads; returns the exit status."""
    import numpy as np

    if geometry_defaults(args) == "sphere":
        return cmd_sphere_sweep(args)
    psd, E, source = scene(args)
    if args.loads_to < args.loads_from:
        raise CLIError("--loads-to must be >= --loads-from")
    check_outputs(args)
    loads = np.geomspace(args.loads_from, args.loads_to, args.loads_num)
    th = persson_theory(psd, E, args)
    table = None
    if args.workers is None and args.scheduler is None:
        model = fl.LineContact(psd, E, args.radius, model=args.model, **solve_kwargs(args, th))
        with progress(len(loads), "sweep") as bar:
            results = model.sweep(loads, progress=bar.update)
    else:
        results, table = sweep_in_parallel(psd, E, args, loads)
    print(spectrum_line(psd, source, args.model))
    if len(results):
        print(model_line(results[0]))
    print(
        f"{'load [N/m]':>12}{'alpha':>12}{'p0 [Pa]':>13}{'p0 ratio':>10}{'s [m]':>12}"
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
        fl.io.write_sweep_csv(args.csv, results, metadata(psd, E, args, source))
    if args.plot:
        gu = th.exponential_fit().gamma_u if th is not None else None
        save(fl.plotting.plot_sweep(results, gamma_u=gu), args.plot, args)
    return convergence_status(results) if table is None else table_status(table)


def cmd_batch(args) -> int:
    """``fastline batch``: a table of scenes from a CSV file; returns the exit status."""

    fl.io.check_output_file(args.out)
    scenes = batch.read_scenes(args.scenes)
    if args.law is not None:
        _default_law(scenes, args.law)
    table = run_table(scenes, args)
    table.to_csv(args.out)
    st = table.stats
    failed = int(table.failed.sum())
    ok = int(table.ok.sum())
    print(
        f"fastline batch: {st.scenes} scenes from {args.scenes}: {ok} converged, "
        f"{st.scenes - ok - failed} not converged, {failed} failed; {st.wall_seconds:.2f} s "
        f"({st.scenes_per_second:.0f} scenes/s, {st.tasks} task(s)) on {st.executor}"
    )
    status = table_status(table)
    print(f"wrote {args.out}")
    return status


def _default_law(scenes: dict[str, list], path: str) -> None:
    """``batch --law FILE``: FILE in the law cells of the rows that name neither a model nor a
    law, checked first against each distinct spectrum and E* of those rows that can be read
    here (a mismatch refuses the table; a row whose spectrum cannot be read fails alone)."""
    if not os.path.isfile(path):
        raise CLIError(f"--law {path}: no such file")
    size = len(next(iter(scenes.values())))
    laws = scenes.setdefault("law", [None] * size)
    models = scenes.get("model", [None] * size)
    rows = [i for i in range(size) if laws[i] is None and models[i] is None]
    if not rows:
        raise CLIError(
            f"--law {path}: every row names a model or a law; leave the model and law cells "
            "empty in the rows that should take it"
        )
    path = os.path.abspath(path)
    fl.CalibratedLaw.load(path)  # not a law file: one clear error
    checked = set()
    for i in rows:
        laws[i] = path
        key = _row_scene(scenes, i)
        if key is None or key in checked:
            continue
        checked.add(key)
        try:
            psd = (
                fl.io.read_spectrum(key[0])
                if isinstance(key[0], str)
                else fl.SelfAffinePSD(*key[0])
            )
            fl.CalibratedLaw.load(path, psd=psd, E_star=key[1])
        except fl.CalibrationFileError as e:
            raise CLIError(f"--law {e}") from None
        except (ValueError, TypeError):  # a bad cell: the row fails alone, fl.sweep says why
            continue


def _row_scene(scenes: dict[str, list], i: int) -> tuple | None:
    """(spectrum file or self-affine parameters, E*) of a row; None when a column is missing
    (fl.sweep refuses the table, naming it)."""
    names = ("psd",) if "psd" in scenes else ("h_rms", "hurst", "q0", "qr", "q1")
    if any(k not in scenes for k in (*names, "E_star")):
        return None
    spectrum = tuple(scenes[k][i] for k in names)
    return (spectrum[0] if "psd" in scenes else spectrum), scenes["E_star"][i]


def cmd_paper(args) -> int:
    """``fastline paper``: the paper's figures; returns the exit status."""
    paper = fl.paper
    if geometry_defaults(args) == "sphere":
        return cmd_sphere_paper(args)
    check_outputs(args)
    t0 = time.perf_counter()
    with progress(len(paper.SURFACES) * args.loads, "paper") as bar:
        data = paper.paper_data(
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
    t1 = time.perf_counter()
    written = paper.write_files(data, args.out, format=args.format, dpi=args.dpi)
    t_files = time.perf_counter() - t1
    print(
        f"fastline paper: E* = {paper.E_STAR:g} Pa, R = {paper.RADIUS:g} m, q0 = {paper.Q0:g} "
        f"1/m, qr = {paper.QR:g} 1/m, q1 = {args.q1:g} 1/m, gamma = {args.gamma:g}, "
        f"n = {args.n}; {args.loads} loads per surface; solved in {elapsed:.2f} s, files in "
        f"{t_files:.2f} s"
    )
    print(
        f"{'surface':<10}{'h_rms [m]':>10}{'H':>5}{'rms slope':>10}{'gamma_u':>9}"
        f"{'alpha range':>20}{'w/s range':>17}{'p0 ratio range':>17}{'not conv.':>10}"
    )
    for s in data.surfaces:
        rs = s.results
        a, ws, pr = ([getattr(r, k) for r in rs] for k in ("alpha", "w_over_s", "p0_ratio"))
        bad = sum(not r.converged for r in rs)
        slope = fl.io.spectrum_summary(s.psd)["rms_slope"]
        print(
            f"{s.label:<10}{s.h_rms:>10.3g}{s.hurst:>5.2g}{slope:>10.4g}{s.gamma_u:>9.4f}"
            f"{min(a):>10.3g}-{max(a):<9.3g}{min(ws):>8.4f}-{max(ws):<8.4f}"
            f"{min(pr):>8.4f}-{max(pr):<8.4f}{bad:>10d}"
        )
    print(
        f"spectra          q {paper.Q0:g}-{args.q1:g} 1/m (longest wavelength "
        f"{fl.io.spectrum_summary(data.surfaces[0].psd)['longest_wavelength']:.3g} m)"
    )
    report_warnings(data.results)
    print(f"wrote {', '.join(written)} to {args.out}")
    return convergence_status(data.results)


COMMANDS = {
    "paper": cmd_paper,
    "profile": cmd_profile,
    "sweep": cmd_sweep,
    "leak": cmd_leak,
    "batch": cmd_batch,
    "psd": cmd_psd,
    "validate": cmd_validate,
    "compile": cmd_compile,
    "calibrate": cmd_calibrate,
}


def main(argv: list[str] | None = None) -> int:
    """Run the command line; returns the exit status (0 done, 1 not converged, 2 bad input)."""
    argv = list(sys.argv[1:] if argv is None else argv)
    parser = build_parser()
    try:
        args = parser.parse_args(_join_negative_values(argv))
        if args.command is None:
            parser.print_help()
            return 2
        if args.command in ("profile", "sweep"):  # leak refuses --model hertz outright
            model_checks(args)
        if getattr(args, "variant", 0) is None:
            args.variant = theory.DEFAULT_VARIANT
        if getattr(args, "gamma", 0.0) is None:  # the variant's own gamma
            args.gamma = theory.get_variant(args.variant).default_gamma
        with warnings.catch_warnings(), _ReaderGuard() as guard:
            warnings.filterwarnings("ignore", category=fl.UnitWarning)  # the scene's check
            status = COMMANDS[args.command](args)  # printed them once
            sys.stdout.flush()  # a reader that left shows here, not in the interpreter's exit
        return _closed_pipe() if guard.left else status
    except (CLIError, ValueError) as e:
        msg = " ".join(str(e).split())
        print(f"fastline: error: {msg}", file=sys.stderr)
        return 2
    except BrokenPipeError:  # pragma: no cover - the guard's stream raised it anyway
        return _closed_pipe()


class _ReaderGuard:
    """``sys.stdout`` while a command runs: when its reader leaves (``fastline sweep ... |
    head -1``), what the command prints next is dropped and the command goes on to write its
    files; :func:`main` then returns the closed pipe's status."""

    def __init__(self) -> None:
        self.left = False
        self._stream = sys.stdout

    def __enter__(self) -> _ReaderGuard:
        sys.stdout = self
        return self

    def __exit__(self, *exc) -> None:
        sys.stdout = self._stream

    def write(self, text: str) -> int:
        if not self.left:
            try:
                return self._stream.write(text)
            except BrokenPipeError:
                self._gone()
        return len(text)

    def flush(self) -> None:
        if not self.left:
            try:
                self._stream.flush()
            except BrokenPipeError:
                self._gone()

    def _gone(self) -> None:
        self.left = True
        _closed_pipe()  # the interpreter's final flush then goes to the null device

    def __getattr__(self, name: str):
        return getattr(self._stream, name)


def _closed_pipe() -> int:
    """The exit status of a Unix tool whose reader closed the pipe (128 + SIGPIPE), with
    stdout pointed at the null device so that the interpreter's final flush stays silent."""
    try:
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, sys.stdout.fileno())
    except (OSError, ValueError, AttributeError):  # stdout is not a file (captured)
        pass
    return 128 + 13


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
