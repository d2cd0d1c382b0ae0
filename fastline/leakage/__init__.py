"""Seal leakage: the leak rate of a contact's pressure profile through Persson's critical
junctions or the effective medium (:mod:`~fastline.leakage.flow`,
:mod:`~fastline.leakage.medium`), the seal under pressure with the fluid in the interface
coupled to a line or point contact (:mod:`~fastline.leakage.seal`; its equations in
:mod:`~fastline.leakage.seal_system`, its compiled Newton system in
:mod:`~fastline.leakage.seal_kernels`), on the interface statistics of
:mod:`fastline.theory.interface` (re-exported here).
"""

from __future__ import annotations

import lazy_loader as _lazy

from fastline.errors import LeakageWarning
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

#: what the other subpackages may use, by the module that defines it (loaded on first use)
__getattr__, __dir__, __all__ = _lazy.attach(
    __name__,
    submod_attrs={
        "flow": ["GAP_FLOOR", "LeakResult", "leak_rate", "leak_rate_profile"],
        "medium": ["effective_gap", "effective_gap_of"],
        "seal": ["SealResult", "SealSweep", "seal_leak"],
    },
)
__all__ += [
    "LeakageWarning",
    "THRESHOLD_BRUGGEMAN",
    "THRESHOLD_NUMERICAL",
    "THRESHOLD_PERSSON",
    "CriticalGap",
    "apparent_area",
    "critical_gap",
    "edge_separation",
    "mean_separation",
]
