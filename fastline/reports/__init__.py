"""Reports on fastline's results: the paper's scenes (:mod:`~fastline.reports.paper`, also
``fastline.paper``), figures (:mod:`~fastline.reports.plotting`, also ``fastline.plotting``)
and the theory judged against the boundary-element method
(:mod:`~fastline.reports.validation`).

Each module loads on first use (matplotlib and the boundary-element solver only when asked
for)."""

from __future__ import annotations

import lazy_loader as lazy

__getattr__, __dir__, __all__ = lazy.attach(
    __name__, submodules=["paper", "plotting", "validation"]
)
