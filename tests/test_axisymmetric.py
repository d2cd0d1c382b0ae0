"""Tests for fastline.elastic.ring: the ring operator of a point contact and its preconditioner."""

from __future__ import annotations

import math
import warnings

import numpy as np
import pytest
import scipy.linalg
from naive import ring_cell_coefficient
from scipy.integrate import IntegrationWarning
from scipy.special import ellipe, ellipk

from fastline.elastic.ring import (
    MAX_N,
    BalancingPreconditioner,
    RingKernelOperator,
    _g_elliptic,
    _g_series,
    disc_interaction,
    ring_areas,
    ring_edges,
    ring_influence_coefficients,
)

RTOL_ROUNDOFF = 1e-13  # closed forms that differ only in rounding
RTOL_QUADRATURE = 1e-10  # closed-form coefficients vs nested quad of the ring kernel
#: the same at cell 2000 (n > 2000): the four-term difference of disc interactions ~i^3 loses
#: ~i^2 eps near the diagonal (measured 2.7e-10 at i = 2000, 1.1e-9 at i = 4000)
RTOL_QUADRATURE_FAR = 1e-9
RTOL_SYMMETRY = 1e-14  # w_i K_ij vs w_j K_ji, relative to the largest entry
HERTZ_ORDER_MIN = 1.7  # observed order of the Hertz displacement error: 1.8-2.2

E_STAR = 1.33e9


# ---- closed forms ---------------------------------------------------------------------------
def test_disc_interaction_closed_forms():
    a = np.array([0.3, 1.0, 7.0])
    assert np.allclose(disc_interaction(a, a), 16.0 * np.pi * a**3 / 3.0, rtol=RTOL_ROUNDOFF)
    assert np.allclose(disc_interaction(a, 2 * a), disc_interaction(2 * a, a), rtol=0, atol=0)
    assert np.allclose(disc_interaction(5 * a, 3 * a), 125 * disc_interaction(a, 0.6 * a))
    # the elliptic form (1 + m) E - (1 - m) K, directly, away from its cancellation at small m
    k = np.array([0.55, 0.8, 0.99])
    m = k * k
    direct = 8 * np.pi * ((1 + m) * ellipe(m) - (1 - m) * ellipk(m)) / 3.0
    assert np.allclose(disc_interaction(k, 1.0), direct, rtol=RTOL_ROUNDOFF)
    # a small disc at the centre of a large one feels the central displacement 2 pi c:
    # Phi ~ pi a^2 * 2 pi c (1 - (a/c)^2 / 8 ...)
    small = disc_interaction(1e-4, 1.0)
    assert small == pytest.approx(2 * np.pi**2 * 1e-8 * (1 - 1e-8 / 8), rel=RTOL_ROUNDOFF)


def test_series_and_elliptic_forms_join():
    """G(k) switches from its power series to the elliptic form at k^2 = 1/4: both agree there
    (and on either side, where the elliptic form has not yet lost digits to cancellation)."""
    m = np.array([0.15, 0.2, 0.25, 0.3, 0.5])
    series, elliptic = _g_series(m), _g_elliptic(m, 1.0 - m)
    assert np.allclose(series, elliptic, rtol=1e-14, atol=0)


def test_cells():
    e = ring_edges(4)
    assert np.array_equal(e, [0.0, 0.5, 1.5, 2.5, 3.5])
    w = ring_areas(4)
    assert np.allclose(w, [np.pi / 4, 2 * np.pi, 4 * np.pi, 6 * np.pi], rtol=RTOL_ROUNDOFF)
    assert w.sum() == pytest.approx(np.pi * 3.5**2, rel=RTOL_ROUNDOFF)


@pytest.mark.parametrize(
    "i, j",
    [(0, 0), (1, 1), (0, 1), (1, 0), (5, 5), (5, 6), (30, 30), (30, 31), (10, 40), (40, 10),
     (63, 0), (63, 62)],
)  # fmt: skip
def test_coefficients_against_quadrature(i, j):
    khat = ring_influence_coefficients(64)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", IntegrationWarning)
        ref = ring_cell_coefficient(i, j)
    assert khat[i, j] == pytest.approx(ref, rel=RTOL_QUADRATURE)


def _coefficient(i, j):
    """khat_ij of a large grid from the four disc interactions (no n x n matrix)."""
    edge = (0.0 if j == 0 else j - 0.5), j + 0.5
    inner = 0.0 if i == 0 else i - 0.5
    phi = [disc_interaction(a, b) for a in (i + 0.5, inner) for b in (edge[1], edge[0])]
    return (phi[0] - phi[1] - phi[2] + phi[3]) / (np.pi * ring_areas(i + 1)[i])


@pytest.mark.parametrize("i, j", [(2000, 0), (4000, 1), (1000, 10), (2000, 2000), (2000, 1990)])
def test_coefficients_of_outer_rings_against_quadrature(i, j):
    """Far from the diagonal the small coefficients need the power series of G (without it
    the error at (2000, 0) was 2.6e-6)."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", IntegrationWarning)
        ref = ring_cell_coefficient(i, j)
    assert _coefficient(i, j) == pytest.approx(ref, rel=RTOL_QUADRATURE_FAR)


def test_leading_block_is_the_smaller_grid():
    big, small = ring_influence_coefficients(200), ring_influence_coefficients(50)
    assert np.allclose(big[:50, :50], small, rtol=1e-12, atol=0)


# ---- structure ------------------------------------------------------------------------------
@pytest.mark.parametrize("n", [16, 101, 256])
def test_weighted_matrix_is_symmetric_positive_definite(n):
    wk = ring_areas(n)[:, None] * ring_influence_coefficients(n)
    assert np.max(np.abs(wk - wk.T)) <= RTOL_SYMMETRY * np.max(np.abs(wk))
    eig = np.linalg.eigvalsh(0.5 * (wk + wk.T))
    assert eig.min() > 0.0
    # the Newton matrix W (D + K) on zero-load increments (sum w dp = 0), D >= 0
    z = scipy.linalg.null_space(ring_areas(n)[None, :])
    D = np.random.default_rng(n).uniform(0.0, 10.0, n) * np.diagonal(wk) / ring_areas(n)
    newton = ring_areas(n)[:, None] * (np.diag(D) + ring_influence_coefficients(n))
    assert np.linalg.eigvalsh(z.T @ (0.5 * (newton + newton.T)) @ z).min() > 0.0


def test_apply_matches_dense_and_counts():
    n = 77
    op = RingKernelOperator(n, 2e-6, E_STAR)
    p = np.random.default_rng(1).uniform(0, 1e8, n)
    ref = op.dense() @ p
    got = op.apply(p)
    assert np.linalg.norm(got - ref) <= RTOL_ROUNDOFF * np.linalg.norm(ref)
    out = np.empty(n)
    assert op.apply(p, out=out) is out and np.array_equal(out, got)
    assert op.convolutions == 2 and op.circulant_solves == 0
    assert np.allclose(op.weights, ring_areas(n) * 4e-12, rtol=RTOL_ROUNDOFF)


# ---- against the continuum ------------------------------------------------------------------
def _hertz_cells(n, a=1.0, p0=1.0, extent=1.5):
    """Operator (E* = 1) on [0, extent a] and the cell averages of p0 sqrt(1 - r^2/a^2), from
    the exact load outside radius x, F (1 - x^2/a^2)^(3/2) with F = 2 pi a^2 p0 / 3."""
    dr = extent * a / (n - 0.5)
    op = RingKernelOperator(n, dr, 1.0)
    e = ring_edges(n) * dr
    outside = 2 * np.pi * a * a * p0 / 3 * np.maximum(1 - (e / a) ** 2, 0.0) ** 1.5
    return op, e, (outside[:-1] - outside[1:]) / op.weights


def test_hertz_displacement_is_parabolic_inside():
    """p = p0 sqrt(1 - r^2/a^2) gives u = (pi p0 / (4 a E*)) (2 a^2 - r^2) for r < a
    (Johnson eq. 3.41); compared cell-averaged, the error falls like n^-2."""
    errs = []
    for n in (64, 256):
        op, e, p = _hertz_cells(n)
        u = op.apply(p)
        inside = e[1:] <= 1.0
        exact = np.pi / 4 * (2.0 - 0.5 * (e[1:] ** 2 + e[:-1] ** 2))
        errs.append(np.max(np.abs(u - exact)[inside]) / exact[0])
    assert errs[1] < 2e-5
    assert math.log(errs[0] / errs[1]) / math.log(4.0) > HERTZ_ORDER_MIN


def test_boussinesq_far_field():
    """Far from a loaded disc of radius a the cell averages tend to F/(pi E* r_i)
    (the cell average of 1/r over ring i is exactly 1/r_i); the rest is O((a/r)^2)."""
    n, dr = 400, 1e-6
    op = RingKernelOperator(n, dr, E_STAR)
    p = np.zeros(n)
    p[:5] = 3e7
    a = 4.5 * dr
    force = op.weights @ p
    u = op.apply(p)
    r = np.arange(n) * dr
    far = r >= 10 * a
    rel = np.abs(u[far] * np.pi * E_STAR * r[far] / force - 1.0)
    assert np.all(rel <= (a / r[far]) ** 2)
    # the leading correction of a uniform disc, a^2 / (8 r^2)
    assert rel[-1] == pytest.approx((a / r[-1]) ** 2 / 8.0, rel=0.05)


# ---- preconditioner -------------------------------------------------------------------------
def _hertz_like_D(n):
    """|du/dp| of a Hertz-like scene: ~0 in the loaded core, huge outside, a steep transition."""
    x = np.linspace(0.0, 1.5, n)
    return 10.0 ** np.clip(40.0 * (x - 0.8), -30.0, 250.0) * 1e-14


def test_preconditioner_is_symmetric_positive_definite():
    n = 64
    op = RingKernelOperator(n, 1e-6, E_STAR)
    prec = op.preconditioner(_hertz_like_D(n))
    M = np.column_stack([prec(col) for col in np.eye(n)])
    wm = op.weights[:, None] * M
    assert np.max(np.abs(wm - wm.T)) <= 1e-10 * np.max(np.abs(wm))
    s = 1.0 / np.sqrt(np.diagonal(wm))  # the diagonal spans ~300 decades
    assert np.linalg.eigvalsh(wm * s[:, None] * s[None, :]).min() > 0.0
    assert op.circulant_solves == op.convolutions == n


def _pcg_iterations(op, D, prec, rhs, rtol=1e-8):
    """Plain PCG in the inner product <a, b> = sum w a b; iterations to rtol."""
    w = op.weights
    x = np.zeros_like(rhs)
    r = rhs.copy()
    z = prec(r)
    d = z.copy()
    rz = rz0 = np.dot(w * r, z)
    for it in range(1, 2000):
        Ad = D * d + op.apply(d)
        a = rz / np.dot(w * d, Ad)
        x += a * d
        r -= a * Ad
        z = prec(r)
        rz_new = np.dot(w * r, z)
        if rz_new < rtol * rtol * rz0:
            return it
        d = z + (rz_new / rz) * d
        rz = rz_new
    return it


def test_balancing_beats_jacobi():
    """The coarse space takes the smooth modes that Jacobi leaves to CG: Jacobi's iterations
    grow like sqrt(n) (measured 41, 56, 72 at n = 128, 256, 512), the balancing
    preconditioner's hardly (24, 27, 31)."""
    its = {}
    for n in (128, 512):
        op = RingKernelOperator(n, 1e-6, E_STAR)
        D = _hertz_like_D(n)
        rhs = np.random.default_rng(3).standard_normal(n) * 1e-6
        jacobi = 1.0 / (D + op.diagonal)
        its[n] = (
            _pcg_iterations(op, D, lambda y, j=jacobi: j * y, rhs),
            _pcg_iterations(op, D, BalancingPreconditioner(op, D), rhs),
        )
    assert its[512][1] < 0.6 * its[512][0]
    assert its[512][0] > 1.5 * its[128][0]
    assert its[512][1] < 1.4 * its[128][1]


# ---- bad input ------------------------------------------------------------------------------
@pytest.mark.parametrize(
    "kwargs, match",
    [
        ({"n": 1}, "n must be an integer in"),
        ({"n": MAX_N + 1}, "dense"),
        ({"n": 2.5}, "n must be an integer"),
        ({"n": True}, "n must be an integer"),
        ({"dr": 0.0}, "dr must be > 0"),
        ({"dr": float("nan")}, "dr must be finite"),
        ({"E_star": -1.0}, "E_star must be > 0"),
    ],
)
def test_bad_input(kwargs, match):
    args = {"n": 8, "dr": 1e-6, "E_star": E_STAR, **kwargs}
    with pytest.raises(ValueError, match=match):
        RingKernelOperator(**args)


def test_bad_apply_arguments():
    op = RingKernelOperator(8, 1e-6, E_STAR)
    with pytest.raises(ValueError, match="shape"):
        op.apply(np.ones(7))
    with pytest.raises(ValueError, match="out must be"):
        op.apply(np.ones(8), out=np.empty(8, dtype=np.float32))
    p = np.ones(8)
    with pytest.raises(ValueError, match="share memory"):
        op.apply(p, out=p)
    with pytest.raises(ValueError, match="n must be an integer in"):
        ring_influence_coefficients(0)
