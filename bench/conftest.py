"""Shared scene and fixtures for the fastline benchmarks (paper section 3 scene)."""

from __future__ import annotations

import math

import numpy as np
import pytest

import fastline as fl

E_STAR = 1.33e9  # Pa
RADIUS = 0.01  # m
ALPHAS = (1e-4, 1e-3, 1e-2, 0.1, 1.0, 10.0, 100.0, 1e3)
PICARD_CAP = 2000
SWEEP_LOADS = np.geomspace(1e3, 1.5e6, 25)  # N/m


def surfaces():
    """The paper's three surfaces (q1 = 1e9 1/m)."""
    return (
        fl.SelfAffinePSD(10e-6, 0.8, 1e3, 1e4, 1e9),
        fl.SelfAffinePSD(10e-6, 1.0, 1e3, 1e4, 1e9),
        fl.SelfAffinePSD(1e-6, 0.8, 1e3, 1e4, 1e9),
    )


def load_for_alpha(alpha, h_rms=10e-6, E_star=E_STAR):
    """f_N with h_rms / delta = alpha, delta = 4 f_N / (pi E*)."""
    return math.pi / 4.0 * h_rms * E_star / alpha


@pytest.fixture(scope="session")
def psd1():
    return surfaces()[0]


@pytest.fixture(scope="session")
def theory1(psd1):
    return fl.PerssonTheory(psd1, E_STAR)
