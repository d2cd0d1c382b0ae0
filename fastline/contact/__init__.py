"""Nominal contact pressure: the shared Newton core (:mod:`~fastline.contact.core`,
:mod:`~fastline.contact.model`, compiled kernels in :mod:`~fastline.contact.kernels`,
:mod:`~fastline.contact.line_newton` and :mod:`~fastline.contact.line_sweep`, hard contact in
:mod:`~fastline.contact.hard`), the line and point contacts (:mod:`~fastline.contact.line`,
:mod:`~fastline.contact.point`), their result base (:mod:`~fastline.contact.result`), validity
diagnostics and the grid's error estimate (:mod:`~fastline.contact.diagnostics`,
:mod:`~fastline.contact.resolution`), and a result's profile figure
(:mod:`~fastline.contact.figure`).
"""

from __future__ import annotations

import lazy_loader as _lazy

#: what the other subpackages may use, by the module that defines it (loaded on first use)
__getattr__, __dir__, __all__ = _lazy.attach(
    __name__,
    submod_attrs={
        "diagnostics": [
            "ValidityWarning",
            "assess",
            "regime",
            "summarise_warnings",
            "warn_once",
            "CAUSES",
            "HERTZ_LIKE_ALPHA",
            "GAUSSIAN_LIKE_ALPHA",
            "RESOLUTION_CELLS",
            "EDGE_LIMIT",
        ],
        "figure": ["plot_profile"],
        "line": [
            "ConvergenceWarning",
            "LineContact",
            "LineContactResult",
            "solve_line_contact",
            "profile",
            "w_over_s",
            "p0_ratio",
        ],
        "point": [
            "PointContact",
            "PointContactResult",
            "solve_point_contact",
        ],
        "resolution": [
            "ACCURACY_RANGE",
            "ACCEPT_MARGIN",
            "AccuracyWarning",
            "ErrorEstimate",
            "estimate_error",
            "solve_to_accuracy",
            "sweep_to_accuracy",
        ],
    },
)
