"""Boundary-element checks of the theory on the user's own surface.

A periodic 2D FFT boundary-element solver (constrained conjugate gradients, Polonsky & Keer,
Wear 231, 206 (1999)) for a rigid cylinder, sphere or flat pressed on an elastic half-space
with a random surface of a given spectrum, the ensemble nominal pressure with error bars, and a
Reynolds flow through the gap of a nominally flat contact.

Modules: :mod:`~fastline.bem.surface` (grids, random surfaces, spectrum estimate),
:mod:`~fastline.bem.halfspace` (Love's influence coefficients, FFT convolution),
:mod:`~fastline.bem.contact` (the CCG solver), :mod:`~fastline.bem.flow` (Reynolds flow),
:mod:`~fastline.bem.pcg_flow` (the flow's iterative stage: multigrid-preconditioned CG),
:mod:`~fastline.bem.scene` (scenes and their default grids),
:mod:`~fastline.bem.ensemble` (realisations, ensembles),
:mod:`~fastline.bem.compare` (theory against the ensemble in units of its error bar),
:mod:`~fastline.bem.calibration` (a pressure law calibrated on flat-contact ensembles).
"""

from __future__ import annotations

import lazy_loader as _lazy

#: what the other subpackages may use, by the module that defines it (loaded on first use)
__getattr__, __dir__, __all__ = _lazy.attach(
    __name__,
    submod_attrs={
        "calibration": ["calibrate", "pressure_range", "MIN_CELLS_PER_WAVELENGTH"],
        "compare": [
            "Difference",
            "LineComparison",
            "PointComparison",
            "ProfileComparison",
            "compare_line_contact",
            "compare_point_contact",
        ],
        "contact": [
            "ContactResult",
            "cylinder_gap",
            "image_curvature",
            "solve_contact",
            "sphere_gap",
        ],
        "ensemble": [
            "FlatEnsemble",
            "ProfileEnsemble",
            "Realization",
            "ensemble_executor",
            "run_ensemble",
            "run_realization",
        ],
        "flow": ["FlowResult", "reynolds_flow"],
        "halfspace": ["ElasticHalfSpace", "love_coefficient"],
        "scene": [
            "Scene",
            "flat_contact_scene",
            "line_contact_scene",
            "point_contact_scene",
            "with_grid",
        ],
        "surface": [
            "Grid",
            "RoughSurface",
            "isotropic_spectrum",
            "lattice_moments",
            "random_surface",
            "spectral_grid",
        ],
    },
)
