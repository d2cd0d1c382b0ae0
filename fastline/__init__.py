"""fastline: nominal contact pressure of a cylinder on a randomly rough elastic half-space.

Full Persson contact theory (compiled with Numba) and a fast line-contact solver
(log-kernel convolution by zero-padded FFT); the same for a sphere on a flat (point contact,
axisymmetric ring operator). See README.md and docs/.
"""

from __future__ import annotations

import importlib
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:  # the same names, eagerly, for type checkers and IDEs
    from fastline import io, paper, plotting, topography  # light: heavy deps load on first use
    from fastline.asperity import GreenwoodWilliamsonLaw, SummitStatistics
    from fastline.axisymmetric import RingKernelOperator
    from fastline.batch import SweepTable, sweep
    from fastline.diagnostics import ValidityWarning, assess, warn_once
    from fastline.elastic import LogKernelOperator, influence_coefficients
    from fastline.laws import ExponentialLaw, PerssonLaw, PressureLaw, TabulatedLaw
    from fastline.leakage import (
        CriticalGap,
        LeakageWarning,
        LeakResult,
        leak_rate,
        leak_rate_profile,
    )
    from fastline.limits import (
        WS_GAUSSIAN,
        WS_HERTZ,
        WS_HERTZ_SPHERE,
        alpha,
        gaussian_line_contact,
        gaussian_point_contact,
        hertz_line_contact,
        hertz_point_contact,
        p0_ratio_gaussian,
        p0_ratio_gaussian_sphere,
        penetration,
    )
    from fastline.line_contact import (
        ConvergenceWarning,
        LineContact,
        LineContactResult,
        p0_ratio,
        profile,
        solve_line_contact,
        w_over_s,
    )
    from fastline.persson import (
        ExponentialFit,
        PerssonTables,
        PerssonTheory,
        pressure_at,
        separation_at,
    )
    from fastline.point_contact import PointContact, PointContactResult, solve_point_contact
    from fastline.resolution import AccuracyWarning, ErrorEstimate
    from fastline.spectra import PSD, SelfAffinePSD, SumPSD, TabulatedPSD, effective_modulus

__version__ = "0.2.0"

#: public name -> the module that defines it; loaded on first access (PEP 562), so that
#: ``import fastline`` costs only what the names a program uses need (a line-contact solve
#: never imports the leakage, topography, batch or plotting modules)
_LAZY = {
    "io": "fastline.io",
    "paper": "fastline.paper",
    "plotting": "fastline.plotting",
    "topography": "fastline.topography",
    "GreenwoodWilliamsonLaw": "fastline.asperity",
    "SummitStatistics": "fastline.asperity",
    "RingKernelOperator": "fastline.axisymmetric",
    "SweepTable": "fastline.batch",
    "sweep": "fastline.batch",
    "ValidityWarning": "fastline.diagnostics",
    "assess": "fastline.diagnostics",
    "warn_once": "fastline.diagnostics",
    "LogKernelOperator": "fastline.elastic",
    "influence_coefficients": "fastline.elastic",
    "ExponentialLaw": "fastline.laws",
    "PerssonLaw": "fastline.laws",
    "PressureLaw": "fastline.laws",
    "TabulatedLaw": "fastline.laws",
    "CriticalGap": "fastline.leakage",
    "LeakageWarning": "fastline.leakage",
    "LeakResult": "fastline.leakage",
    "leak_rate": "fastline.leakage",
    "leak_rate_profile": "fastline.leakage",
    "WS_GAUSSIAN": "fastline.limits",
    "WS_HERTZ": "fastline.limits",
    "WS_HERTZ_SPHERE": "fastline.limits",
    "alpha": "fastline.limits",
    "gaussian_line_contact": "fastline.limits",
    "gaussian_point_contact": "fastline.limits",
    "hertz_line_contact": "fastline.limits",
    "hertz_point_contact": "fastline.limits",
    "p0_ratio_gaussian": "fastline.limits",
    "p0_ratio_gaussian_sphere": "fastline.limits",
    "penetration": "fastline.limits",
    "ConvergenceWarning": "fastline.line_contact",
    "LineContact": "fastline.line_contact",
    "LineContactResult": "fastline.line_contact",
    "p0_ratio": "fastline.line_contact",
    "profile": "fastline.line_contact",
    "solve_line_contact": "fastline.line_contact",
    "w_over_s": "fastline.line_contact",
    "ExponentialFit": "fastline.persson",
    "PerssonTables": "fastline.persson",
    "PerssonTheory": "fastline.persson",
    "pressure_at": "fastline.persson",
    "separation_at": "fastline.persson",
    "PointContact": "fastline.point_contact",
    "PointContactResult": "fastline.point_contact",
    "solve_point_contact": "fastline.point_contact",
    "AccuracyWarning": "fastline.resolution",
    "ErrorEstimate": "fastline.resolution",
    "PSD": "fastline.spectra",
    "SelfAffinePSD": "fastline.spectra",
    "SumPSD": "fastline.spectra",
    "TabulatedPSD": "fastline.spectra",
    "effective_modulus": "fastline.spectra",
}


def __getattr__(name: str) -> Any:
    module = _LAZY.get(name)
    if module is None:
        raise AttributeError(f"module 'fastline' has no attribute {name!r}")
    value = importlib.import_module(module)
    if module != f"fastline.{name}":
        value = getattr(value, name)
    globals()[name] = value  # later look-ups skip this function
    return value


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(__all__))


__all__ = [
    "PSD",
    "SelfAffinePSD",
    "TabulatedPSD",
    "SumPSD",
    "effective_modulus",
    "PerssonTheory",
    "ExponentialFit",
    "PerssonTables",
    "pressure_at",
    "separation_at",
    "PressureLaw",
    "PerssonLaw",
    "ExponentialLaw",
    "TabulatedLaw",
    "GreenwoodWilliamsonLaw",
    "SummitStatistics",
    "LogKernelOperator",
    "influence_coefficients",
    "hertz_line_contact",
    "gaussian_line_contact",
    "p0_ratio_gaussian",
    "penetration",
    "alpha",
    "WS_HERTZ",
    "WS_GAUSSIAN",
    "LineContact",
    "solve_line_contact",
    "sweep",
    "SweepTable",
    "profile",
    "w_over_s",
    "p0_ratio",
    "LineContactResult",
    "PointContact",
    "solve_point_contact",
    "PointContactResult",
    "hertz_point_contact",
    "gaussian_point_contact",
    "p0_ratio_gaussian_sphere",
    "WS_HERTZ_SPHERE",
    "RingKernelOperator",
    "ConvergenceWarning",
    "ValidityWarning",
    "AccuracyWarning",
    "ErrorEstimate",
    "assess",
    "warn_once",
    "io",
    "paper",
    "plotting",
    "topography",
    "leak_rate",
    "leak_rate_profile",
    "LeakResult",
    "CriticalGap",
    "LeakageWarning",
]
