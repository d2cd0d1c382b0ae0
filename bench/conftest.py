"""Shared scene and fixtures for the fastline benchmarks (paper section 3 scene).

The scene itself (surfaces, E*, R, ``load_for_alpha``) is defined once, in
:mod:`fastline.reports.paper`.
"""

from __future__ import annotations

import numpy as np
import pytest

import fastline as fl
from fastline.reports.paper import E_STAR, RADIUS, load_for_alpha, surfaces

__all__ = ["ALPHAS", "E_STAR", "PICARD_CAP", "RADIUS", "SWEEP_LOADS", "load_for_alpha", "surfaces"]

ALPHAS = (1e-4, 1e-3, 1e-2, 0.1, 1.0, 10.0, 100.0, 1e3)
PICARD_CAP = 2000
SWEEP_LOADS = np.geomspace(1e3, 1.5e6, 25)  # N/m


@pytest.fixture(scope="session")
def psd1():
    return surfaces()[0]


@pytest.fixture(scope="session")
def theory1(psd1):
    return fl.PerssonTheory(psd1, E_STAR)
