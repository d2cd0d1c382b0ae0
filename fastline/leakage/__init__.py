"""Seal leakage: the leak rate of a contact's pressure profile through Persson's critical
junctions (:mod:`~fastline.leakage.flow`), on the interface statistics of
:mod:`fastline.theory.interface` (re-exported here).
"""

from __future__ import annotations

from fastline.errors import LeakageWarning
from fastline.leakage.flow import (
    LeakResult,
    leak_rate,
    leak_rate_profile,
)
from fastline.theory.interface import (
    THRESHOLD_BRUGGEMAN,
    THRESHOLD_NUMERICAL,
    THRESHOLD_PERSSON,
    CriticalGap,
    apparent_area,
    critical_gap,
    edge_separation,
    mean_separation,
)

__all__ = [
    "LeakResult",
    "LeakageWarning",
    "CriticalGap",
    "apparent_area",
    "mean_separation",
    "edge_separation",
    "critical_gap",
    "THRESHOLD_PERSSON",
    "THRESHOLD_NUMERICAL",
    "THRESHOLD_BRUGGEMAN",
    "leak_rate",
    "leak_rate_profile",
]
