"""Figures of contact results: C(q), p(x), w/s and p0/p0_Hertz against alpha, leak rates,
the theory against the boundary-element method and measured spectra.

Each function draws into a given matplotlib ``Axes`` (``ax=``) or makes its own
:class:`matplotlib.figure.Figure` (no pyplot, no global backend change) and returns the figure.
matplotlib is imported only when a figure is made (install it with the ``plot`` extra).

Conventions: alpha on a log axis, SI units with mm and MPa for profiles, no titles (captions
belong to the document), reference lines labelled, legends outside the data.

The figures are defined by concern and gathered here: :mod:`~fastline.reports.contact_figures`
(spectra, profiles, load sweeps), :mod:`~fastline.reports.leak_figures` (leak rates),
:mod:`~fastline.reports.validation_figures` (theory against BEM),
:mod:`~fastline.reports.scan_figures` (measured spectra), on the shared pieces of
:mod:`~fastline.reports.figures` (figures, axes, legends, :func:`save_figure`).

>>> import fastline as fl                                              # doctest: +SKIP
>>> res = [fl.solve_line_contact(psd, 1.33e9, 0.01, f) for f in (1e3, 1e4, 1e5)]
>>> fig = fl.plotting.plot_sweep(res)
>>> fl.plotting.save_figure(fig, "sweep.pdf")
"""

from __future__ import annotations

from fastline.reports.contact_figures import (
    plot_p0_ratio,
    plot_profile,
    plot_psd,
    plot_sweep,
    plot_w_over_s,
)
from fastline.reports.figures import DEFAULT_DPI as DEFAULT_DPI
from fastline.reports.figures import FORMATS, figure_format, save_figure
from fastline.reports.leak_figures import GAP_FLOOR as GAP_FLOOR
from fastline.reports.leak_figures import plot_leak, plot_leak_sweep, plot_seal
from fastline.reports.scan_figures import plot_measured_psd
from fastline.reports.validation_figures import plot_flat_validation, plot_validation

__all__ = [
    "FORMATS",
    "figure_format",
    "plot_psd",
    "plot_profile",
    "plot_w_over_s",
    "plot_p0_ratio",
    "plot_sweep",
    "plot_leak",
    "plot_leak_sweep",
    "plot_seal",
    "plot_validation",
    "plot_flat_validation",
    "plot_measured_psd",
    "save_figure",
]
