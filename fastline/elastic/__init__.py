"""Elastic half-space operators and their solver: the line contact's log-kernel operator
(:mod:`~fastline.elastic.line`, applied by FFT in :mod:`~fastline.elastic.convolution`), the
point contact's ring operator (:mod:`~fastline.elastic.ring`) and the preconditioned conjugate
gradients of the line contact's Newton systems (:mod:`~fastline.elastic.pcg`, with its
two-level preconditioner in :mod:`~fastline.elastic.preconditioner`). Imports only
:mod:`fastline._lib` and :mod:`fastline.errors`.
"""

from __future__ import annotations

import lazy_loader as _lazy

#: what the other subpackages may use, by the module that defines it (loaded on first use)
__getattr__, __dir__, __all__ = _lazy.attach(
    __name__,
    submod_attrs={
        "convolution": [
            "KernelTables",
            "KernelScale",
            "convolve",
            "apply_kernel",
            "segment_sum",
            "prefix_sums",
        ],
        "preconditioner": ["TwoLevel", "CORE_THETA", "WIDE_THETA", "EDGE_SHARE", "FROZEN_THETA"],
        "pcg": [
            "CGSettings",
            "workspace_size",
            "solve_newton_system",
            "system_address",
            "system_types",
            "call_system",
        ],
        "line": [
            "LogKernelOperator",
            "influence_coefficients",
            "log_reference_shift",
            "log_reference_shift_unchecked",
            "coarse_aggregates",
            "compiled_tables",
            "compiled_workspace",
            "compile_system_elsewhere",
            "KHAT0",
        ],
        "ring": [
            "BalancingPreconditioner",
            "RingKernelOperator",
            "disc_interaction",
            "ring_areas",
            "ring_edges",
            "ring_influence_coefficients",
            "MAX_N",
        ],
    },
)
