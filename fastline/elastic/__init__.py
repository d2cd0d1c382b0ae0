"""Elastic half-space operators and their solver: the line contact's log-kernel operator,
the point contact's ring operator and the preconditioned conjugate gradients of the Newton
systems (:mod:`~fastline.elastic.line`, :mod:`~fastline.elastic.ring`,
:mod:`~fastline.elastic.pcg`). Imports only :mod:`fastline._lib` and :mod:`fastline.errors`.
"""

from __future__ import annotations

import lazy_loader as _lazy

#: what the other subpackages may use, by the module that defines it (loaded on first use)
__getattr__, __dir__, __all__ = _lazy.attach(
    __name__,
    submod_attrs={
        "line": [
            "LogKernelOperator",
            "influence_coefficients",
            "log_reference_shift",
        ],
        "ring": [
            "BalancingPreconditioner",
            "RingKernelOperator",
            "disc_interaction",
            "ring_areas",
            "ring_edges",
            "ring_influence_coefficients",
        ],
        "pcg": [],
    },
)
