"""fastline: nominal contact pressure of a cylinder on a randomly rough elastic half-space.

Full Persson contact theory (compiled with Numba) and a fast line-contact solver
(log-kernel convolution by zero-padded FFT); the same for a sphere on a flat (point contact,
axisymmetric ring operator). See README.md and docs/.
"""

from fastline import io, paper, plotting, topography  # light: heavy deps load on first use
from fastline.asperity import GreenwoodWilliamsonLaw, SummitStatistics
from fastline.axisymmetric import RingKernelOperator
from fastline.batch import SweepTable, sweep
from fastline.diagnostics import ValidityWarning, assess, warn_once
from fastline.elastic import LogKernelOperator, influence_coefficients
from fastline.laws import ExponentialLaw, PerssonLaw, PressureLaw, TabulatedLaw
from fastline.leakage import CriticalGap, LeakageWarning, LeakResult, leak_rate, leak_rate_profile
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
