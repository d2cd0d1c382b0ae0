"""The q quadrature of tabulated spectra (fastline.theory.quadrature): accurate and table-size free.

References: ``naive.separation_tabulated`` (Gauss-Legendre per table interval, so every kink is
a panel edge; its own F) and the analytic spectrum that a dense table samples.
"""

from __future__ import annotations

import functools
import math

import naive
import numpy as np
import pytest
from scipy.special import erfinv

from fastline.theory.persson import PerssonTheory, TableSettings
from fastline.theory.spectra import SelfAffinePSD, TabulatedPSD

E_STAR = 1.33e9
GAMMA = 0.45
RTOL_REF = 1e-6  # default-rtol theory of a table vs the per-interval reference
RTOL_MASS = 1e-9  # sum of the quadrature weights vs int w q^2 C dq (exact for constants)
RTOL_SAMPLED = 1e-6  # theory of a dense table vs theory of the spectrum it samples
MAX_NODES = 400  # quadrature nodes at rtol 1e-6, whatever the table size
SURFACE1 = SelfAffinePSD(10e-6, 0.8, 1e3, 1e4, 1e9)


def _noisy(n, seed, linear=False):
    """SURFACE1 sampled at n points with chi-squared(2) noise: a raw periodogram's scatter.

    ``linear``: k_m = m dk as a periodogram of a profile has (coarse in ln q at low m).
    """
    rng = np.random.default_rng(seed)
    q = np.arange(1, n + 1) * (1e9 / n) if linear else np.geomspace(1e3, 1e9, n)
    return q, SURFACE1(q) * rng.exponential(size=n)


TABLES = {
    "smooth_H0.3_2000": lambda: _sampled(SelfAffinePSD(10e-6, 0.3, 1e3, 1e4, 1e9), 2000),
    "smooth_H1_2000": lambda: _sampled(SelfAffinePSD(10e-6, 1.0, 1e3, 1e4, 1e9), 2000),
    "coarse_25": lambda: _sampled(SURFACE1, 25),
    "noisy_3000": lambda: _noisy(3000, 1),
    "periodogram_4096": lambda: _noisy(4096, 2, linear=True),
    "zeros_inside": lambda: _with_zeros(),
}


def _sampled(psd, n):
    q = np.geomspace(psd.q0, psd.q1, n)
    return q, psd(q)


def _with_zeros():
    q, C = _noisy(600, 3)
    C[200:230] = 0.0  # a dropout band: two live stretches
    return q, C


@functools.cache
def _case(name):
    q, C = TABLES[name]()
    psd = TabulatedPSD(q, C)
    w1 = 1.0 / math.sqrt(float(psd.cumulative(psd.q1)))
    p99 = float(erfinv(0.99)) * E_STAR / w1  # P(q1, p) = 0.99
    p = np.concatenate([np.geomspace(1e-9, 1e-3, 3) * E_STAR, np.geomspace(0.2, 1.0, 3) * p99])
    return psd, p, naive.separation_tabulated(q, C, E_STAR, p, GAMMA, points=8)


@pytest.mark.parametrize("name", list(TABLES))
def test_separation_vs_reference(name):
    psd, p, ref = _case(name)
    th = PerssonTheory(psd, E_STAR, gamma=GAMMA)
    np.testing.assert_allclose(th.separation(p), ref, rtol=RTOL_REF, atol=0.0)
    np.testing.assert_allclose(th.separation_table(p)[0], ref, rtol=RTOL_REF, atol=0.0)


@pytest.mark.parametrize("rtol", [1e-4, 1e-8])
def test_rtol_setting(rtol):
    psd, p, ref = _case("noisy_3000")
    th = PerssonTheory(psd, E_STAR, gamma=GAMMA, rtol=rtol)
    np.testing.assert_allclose(th.separation(p), ref, rtol=rtol, atol=0.0)


@pytest.mark.parametrize("n", [1_000, 100_000])
def test_dense_table_matches_its_spectrum(n):
    """A dense log-log table of SURFACE1 (interpolation error ~1e-10) gives its theory."""
    q = np.geomspace(1e3, 1e9, n)
    q[np.argmin(np.abs(q - 1e4))] = 1e4  # the roll-off kink on a node
    table = PerssonTheory(TabulatedPSD(q, SURFACE1(q)), E_STAR)
    exact = PerssonTheory(SURFACE1, E_STAR)
    p = np.geomspace(1e-8, 1e-1, 8) * E_STAR
    np.testing.assert_allclose(table.separation(p), exact.separation(p), rtol=RTOL_SAMPLED)


def test_node_count_independent_of_table_size():
    """The build does not follow the table: the same few hundred nodes for 10^2..10^5 points."""
    counts = []
    for n in (100, 10_000, 100_000):
        q, C = _noisy(n, 4, linear=True)
        counts.append(PerssonTheory(TabulatedPSD(q, C), E_STAR)._q.size)
    assert max(counts) <= MAX_NODES
    assert max(counts) - min(counts) <= 0.2 * max(counts)


@pytest.mark.parametrize("name", ["noisy_3000", "periodogram_4096", "zeros_inside"])
def test_rule_is_a_positive_gauss_rule(name):
    """Positive weights, nodes increasing in A inside [q0, q1], A exact at the nodes, and the total
    weight equal to int w q^2 C dq (the rule is exact for constants; 1e-13 of it is dropped)."""
    psd = _case(name)[0]
    th = PerssonTheory(psd, E_STAR)
    q, W = th._q, th._W
    w = th._s * E_STAR
    assert np.all(W > 0.0)
    assert np.all(np.diff(w) < 0.0)  # A increasing (q may round to q0 at the lowest nodes)
    assert np.all(np.diff(q) >= 0.0)
    assert psd.q0 <= q[0] and q[-1] <= psd.q1
    # q_j inverts A: exact to rounding where q - q0 is resolved (A ~ q - q0 near q0)
    far = q > psd.q0 * (1.0 + 1e-6)
    assert np.count_nonzero(far) > 0.5 * q.size
    np.testing.assert_allclose(psd.cumulative(q[far]), 1.0 / w[far] ** 2, rtol=1e-9)
    dm, w_ref = naive.tabulated_nodes(*TABLES[name](), points=8)
    mass = float(np.sum(dm * w_ref))  # int w q^2 C dq
    assert float(np.sum(W)) / math.sqrt(math.pi) == pytest.approx(mass, rel=RTOL_MASS)


def test_tiny_tables():
    """Two points, and a table whose first interval holds almost all of nu."""
    for q, C in [([1e3, 1e6], [1e-20, 1e-32]), ([1e3, 1.001e3, 1e6], [1e-20, 1e-20, 1e-32])]:
        psd = TabulatedPSD(q, C)
        th = PerssonTheory(psd, E_STAR)
        p = np.geomspace(1e-8, 1.0, 4) * float(erfinv(0.99)) * E_STAR * psd.rms_slope / 2**0.5
        ref = naive.separation_tabulated(q, C, E_STAR, p, GAMMA)
        np.testing.assert_allclose(th.separation(p), ref, rtol=RTOL_REF)


def test_settings_have_a_tabulated_rule():
    for rtol in (1e-4, 1e-6, 1e-8):
        rule = TableSettings.for_rtol(rtol).tabulated
        assert rule.bins >= 16 and rule.order >= 6
