"""Measured surfaces on the command line: ``fastline psd SCAN``.

``fastline psd`` reads a line scan, parallel line scans or a height map and prints its
spectrum C(q) (the data's h_rms and rms slope, the usable wavenumber range and why, what was
left out above it, the fitted self-affine model: ``ScanSpectrum.summary``), writes the table
``--psd`` reads and a figure. ``--scan FILE`` on ``profile``, ``sweep`` and ``leak`` takes the
spectrum of a scene straight from a measurement (:mod:`fastline.cli.scene`, which holds the
options and the analysis both share). Argument parsing and printing only: the analysis is
:func:`fastline.surfaces.analyse_scan` (docs/topography.md), the table
:func:`fastline.io.write_spectrum`, the figure :func:`fastline.plotting.plot_measured_psd`.
:mod:`fastline.cli.app` wires :func:`psd_parser` and :func:`cmd_psd` in.

SI units throughout: lengths in m whatever the file's units, wavenumbers in 1/m, C(q) in m^4.
"""

from __future__ import annotations

import argparse

import fastline as fl
from fastline.cli.common import figure_options, require_matplotlib, save
from fastline.cli.scene import scan_analysis, scan_checks, scan_options

__all__ = ["psd_parser", "cmd_psd"]


def psd_parser(sub: argparse._SubParsersAction, fmt: type[argparse.HelpFormatter]) -> None:
    """The ``psd`` command: a measured surface's spectrum, its table and figure."""
    p = sub.add_parser(
        "psd",
        help="spectrum C(q) of a measured surface: summary, fit, table for --psd, figure",
        formatter_class=fmt,
        description="Read a line scan, parallel line scans or a height map and print its "
        "spectrum: h_rms and rms slope of the data, the usable wavenumber range and the rule "
        "behind each end, the fitted self-affine model (H, q_r, h_rms with standard errors) "
        "and the C(q) table. --out writes the table (q [1/m], C(q) [m^4], Persson's isotropic "
        "convention h_rms^2 = 2 pi int q C dq) that --psd reads; --plot a figure of C1D (line "
        "scans), C(q) and the fit. Exit status 0 done, 2 bad usage or input.",
    )
    p.add_argument(
        "scan",
        metavar="SCAN",
        help="the measurement: text (.txt .csv .dat .tsv .prn; one column of heights with "
        "--dx, two columns x and h, or one scan per line with --dx; header lines, parameter "
        "blocks, a count line, an index column and trailing separators skipped, UTF-8 or "
        "UTF-16, units read from the header), .npy, or an instrument file (X3P, SDF, OPDx, "
        'Mitutoyo, Keyence, Zygo, Sensofar, ...), which needs pip install "fastline-contact'
        '[topography]" to be read (it also reads text fastline cannot)',
    )
    scan_options(p, standalone=True)
    p.add_argument(
        "--out",
        metavar="FILE",
        help="write the isotropic C(q) table to FILE: two columns q [1/m], C(q) [m^4], the "
        "measurement and fit in '#' header lines (for --psd FILE)",
    )
    p.add_argument(
        "--plot",
        metavar="FILE",
        help="write a figure of C1D(k) (line scans), C(q) and the fit, log-log",
    )
    figure_options(p)


def cmd_psd(args: argparse.Namespace) -> int:
    """Run ``fastline psd SCAN``; returns the exit status (0 done)."""
    scan_checks(args)
    for path in (args.out, args.plot):
        if path is not None:
            fl.io.check_output_file(path)
    if args.plot is not None:
        require_matplotlib()
    scan = scan_analysis(args)
    print(scan.summary(table=True))
    written = []
    if args.out:
        title = (
            f"fastline psd: isotropic power spectrum C(q) of {args.scan}\n"
            "Persson's convention, h_rms^2 = 2 pi int q C dq; columns q [1/m], C(q) [m^4]; "
            "read it with --psd FILE or fastline.io.read_spectrum"
        )
        meta = {"fastline_version": fl.__version__, **scan.metadata()}
        fl.io.write_spectrum(args.out, scan.psd, meta, title=title)
        written.append(args.out)
    if args.plot:
        save(fl.plotting.plot_measured_psd(scan), args.plot, args)
        written.append(args.plot)
    if written:
        print(f"wrote {', '.join(written)}")
    return 0
