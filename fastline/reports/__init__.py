"""Reports on fastline's results: the paper's scenes (:mod:`~fastline.reports.paper`, also
``fastline.paper``), figures (:mod:`~fastline.reports.plotting`, also ``fastline.plotting``,
which gathers :mod:`~fastline.reports.contact_figures`, :mod:`~fastline.reports.leak_figures`,
:mod:`~fastline.reports.validation_figures` and :mod:`~fastline.reports.scan_figures` on the
shared pieces of :mod:`~fastline.reports.figures`) and the theory judged against the
boundary-element method (:mod:`~fastline.reports.validation`).

Each module loads on first use (matplotlib and the boundary-element solver only when asked
for)."""

from __future__ import annotations

import lazy_loader as lazy

__getattr__, __dir__, __all__ = lazy.attach(
    __name__,
    submodules=[
        "paper",
        "plotting",
        "validation",
        "figures",
        "contact_figures",
        "leak_figures",
        "validation_figures",
        "scan_figures",
    ],
)
