"""Boundary-element checks of the theory on the user's own surface.

A periodic 2D FFT boundary-element solver (constrained conjugate gradients, Polonsky & Keer,
Wear 231, 206 (1999)) for a rigid cylinder, sphere or flat pressed on an elastic half-space
with a random surface of a given spectrum, the ensemble nominal pressure with error bars, and a
Reynolds flow through the gap of a nominally flat contact.

Modules: :mod:`~fastline.bem.surface` (grids, random surfaces, spectrum estimate),
:mod:`~fastline.bem.halfspace` (Love's influence coefficients, FFT convolution),
:mod:`~fastline.bem.contact` (the CCG solver), :mod:`~fastline.bem.flow` (Reynolds flow),
:mod:`~fastline.bem.scene` (scenes and their default grids),
:mod:`~fastline.bem.ensemble` (realisations, ensembles),
:mod:`~fastline.bem.compare` (theory against the ensemble in units of its error bar).
"""

from fastline.bem.compare import (
    Difference,
    LineComparison,
    PointComparison,
    ProfileComparison,
    compare_line_contact,
    compare_point_contact,
)
from fastline.bem.contact import (
    ContactResult,
    cylinder_gap,
    image_curvature,
    solve_contact,
    sphere_gap,
)
from fastline.bem.ensemble import (
    FlatEnsemble,
    ProfileEnsemble,
    Realization,
    ensemble_executor,
    run_ensemble,
    run_realization,
)
from fastline.bem.flow import FlowResult, reynolds_flow
from fastline.bem.halfspace import ElasticHalfSpace, love_coefficient
from fastline.bem.scene import (
    Scene,
    flat_contact_scene,
    line_contact_scene,
    point_contact_scene,
    with_grid,
)
from fastline.bem.surface import (
    Grid,
    RoughSurface,
    isotropic_spectrum,
    lattice_moments,
    random_surface,
    spectral_grid,
)

__all__ = [
    "Grid",
    "RoughSurface",
    "spectral_grid",
    "lattice_moments",
    "random_surface",
    "isotropic_spectrum",
    "ElasticHalfSpace",
    "love_coefficient",
    "ContactResult",
    "solve_contact",
    "cylinder_gap",
    "sphere_gap",
    "image_curvature",
    "FlowResult",
    "reynolds_flow",
    "Scene",
    "Realization",
    "ProfileEnsemble",
    "FlatEnsemble",
    "line_contact_scene",
    "point_contact_scene",
    "flat_contact_scene",
    "run_realization",
    "run_ensemble",
    "ensemble_executor",
    "with_grid",
    "Difference",
    "ProfileComparison",
    "LineComparison",
    "PointComparison",
    "compare_line_contact",
    "compare_point_contact",
]
