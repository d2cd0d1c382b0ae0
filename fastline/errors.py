"""Every warning and exception class of fastline, in one place.

Filter them by class: ``warnings.simplefilter("ignore", fastline.ValidityWarning)`` silences
the validity notes of solves, leak rates and accuracy estimates (its subclasses
:class:`AccuracyWarning` and :class:`LeakageWarning` included); :class:`ConvergenceWarning`
marks a solve that stopped before its tolerance (``converged=False``).
"""

from __future__ import annotations

__all__ = [
    "ValidityWarning",
    "ConvergenceWarning",
    "AccuracyWarning",
    "LeakageWarning",
    "NarrowContactWarning",
    "TopographyWarning",
    "SceneFailureWarning",
    "SpectrumFileError",
    "ImplausibleSpectrumError",
    "UnitWarning",
    "CalibrationWarning",
    "CalibrationFileError",
]


class ValidityWarning(UserWarning):
    """A scene is outside the assumptions of the model (elasticity, half-space, mean field,
    exponential law) or its result is limited by the grid."""


class ConvergenceWarning(RuntimeWarning):
    """A solve stopped before reaching its tolerance (``converged=False``)."""


class AccuracyWarning(ValidityWarning):
    """A solve with ``accuracy=`` stopped before its error estimate met the accuracy."""


class LeakageWarning(ValidityWarning):
    """A leak-rate estimate is outside the assumptions of the critical-junction theory."""


class NarrowContactWarning(ValidityWarning):
    """A boundary-element contact too narrow to compare widths: narrower than the longest
    roughness wavelength ``2 pi / q0`` (the theory's mean field does not hold and each
    realisation's width is set by a few asperities), or spanning too few cells of the grid."""


class TopographyWarning(UserWarning):
    """A measurement that looks wrong (units) or a spectrum that needed repair."""


class SceneFailureWarning(UserWarning):
    """Some scenes of a sweep failed (their rows carry the error text)."""


class UnitWarning(UserWarning):
    """An input whose size suggests a unit slip (an effective modulus typed in MPa as Pa)."""


class SpectrumFileError(ValueError):
    """A spectrum file that cannot be read or does not look like a spectrum."""


class ImplausibleSpectrumError(ValueError):
    """A spectrum whose h_rms lies outside the span of any measured surface (``h_rms``, m, and
    that ``span``, (lo, hi) in m): most often a unit slip in C(q) or in the heights it came
    from."""

    def __init__(self, message: str, h_rms: float, span: tuple[float, float]) -> None:
        super().__init__(message)
        self.h_rms = h_rms
        self.span = span


class CalibrationWarning(ValidityWarning):
    """A boundary-element calibration that is under-resolved, did not converge everywhere or
    left part of its law uncalibrated."""


class CalibrationFileError(ValueError):
    """A calibrated-law file that is corrupt, of another format version, or made for another
    spectrum or modulus."""
