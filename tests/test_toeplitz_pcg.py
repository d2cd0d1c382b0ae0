"""The compiled Newton-system solver's building blocks against dense NumPy references.

The solver itself is tested against a dense saddle-point solve in tests/test_elastic.py; here
the prefix-sum forms of the coarse level (no n x nc matrix) and the strip-wise reductions.
"""

from __future__ import annotations

import math

import naive
import numpy as np
import pytest

from fastline.elastic.convolution import prefix_sums, segment_sum
from fastline.elastic.pcg import _STRIP, _jacobi_norm, _projected_precondition, _wdot
from fastline.elastic.preconditioner import (
    TwoLevel,
    _aggregate_edges,
    _coarse_matrices,
    _edge_correlations,
    _live_span,
    _precondition,
    _subtract_edge_combination,
)

RTOL_ROUNDOFF = 1e-12  # reordered sums of O(n) terms
RTOL_COARSE = 1e-10  # prefix-sum differences of ~n-term sums against the dense product

N, J0, J1, NC = 150, 30, 121, 6  # wide block [J0, J1) cut into NC aggregates of 15-16 cells
SCALE = 2.0


def _scene():
    K = naive.log_kernel_matrix(N, 1.0, 1.0)
    khat = K[0] / SCALE  # K = SCALE * toeplitz(khat), as the solver writes it
    D = np.random.default_rng(7).uniform(0.1, 3.0, N) * K[0, 0]
    e = np.empty(NC + 1, np.int64)
    Tc, U, L = np.empty(2 * N), np.empty(2 * N + 1), np.empty((NC, NC))
    _aggregate_edges(D, K[0, 0], J0, J1, NC, e, np.empty(N))
    _coarse_matrices(D, SCALE, prefix_sums(khat), J0, J1, NC, e, Tc, U, L)
    return K, D, e, Tc, L


def test_aggregates_tile_the_wide_block():
    e = _scene()[2]
    assert e[0] == J0 and e[-1] == J1
    assert np.all(np.diff(e) >= 1)


#: a wide block placed symmetrically in the grid, as a symmetric solve has it
S0, S1 = 30, N - 30


def _edges(D, nc=NC):
    e = np.empty(nc + 1, np.int64)
    _aggregate_edges(D, 1.0, S0, S1, nc, e, np.empty(N))
    return e


def test_aggregates_of_a_flat_block_have_nearly_equal_widths():
    widths = np.diff(_edges(np.full(N, 0.5)))
    assert widths.max() - widths.min() <= 2  # counted from both ends, they meet in the middle


@pytest.mark.parametrize("nc", [NC, NC + 1])
def test_aggregates_are_mirror_symmetric_and_dense_where_d_changes(nc):
    """A symmetric D (flat core, steep rims) gives mirror-image edges, narrower aggregates on
    the rims than in the core."""
    centre = 0.5 * (N - 1)
    r = np.abs(np.arange(N) - centre) / (0.5 * (S1 - S0))
    D = np.exp(np.clip(12.0 * (r - 0.6), 0.0, None)) * 1e-2  # 1e-2 in the core, rising 12/unit
    e = _edges(D, nc)
    assert np.array_equal(e - S0, (S1 - e)[::-1])
    widths = np.diff(e)
    assert widths[0] < widths[nc // 2] and widths[-1] < widths[nc // 2]


def _two_level(frozen):
    """The compiled preconditioner on the scene with ``frozen`` cells at each end, without
    a circulant (no FFT plans needed), and its dense reference
    ``B = C + (I - C H) M (I - H C)``, ``C = P (L L^T)^-1 P^T``, ``M = diag(1/(D + K00))``:
    ``(apply(y, shift=0, core=None, circulant=True), project(r, w, v), B, minv)``; ``core =
    (i0, i1)`` declares a loaded core, whose circulant ``circulant=False`` must leave out;
    ``project`` is :func:`_projected_precondition` along v with cell weights w."""
    K, D, e, Tc, L = _scene()
    HP, P = naive.coarse_operator(D, K, e)
    Lf = np.tril(L)
    A = Lf @ Lf.T
    minv = 1.0 / (D + K[0, 0])
    minv[:frozen] = 0.0
    minv[N - frozen :] = 0.0
    f0, f1 = _live_span(minv)
    assert (f0, f1) == (frozen, N - frozen)
    R = np.diag((minv > 0.0).astype(float))
    C, HC = P @ np.linalg.solve(A, P.T), HP @ np.linalg.solve(A, P.T)  # H P: N x NC
    B = R @ (C + (np.eye(N) - HC.T) @ np.diag(minv) @ (np.eye(N) - HC)) @ R
    work, g = np.empty(3 * N + _STRIP), np.empty(2 * NC + 2)
    work[2 * N : 3 * N] = 1.0  # its ones segment
    a, c = np.empty(2 * N), np.empty(2 * N + 2)  # FFT buffers: unused without a circulant
    none = np.empty(0)

    def apply(y, shift=0.0, core=None, circulant=True):
        i0, i1 = core or (0, 0)
        span = np.array([f0, f1, i0, i1, NC])  # live span, core, NC aggregates
        out = np.empty(N)
        pre = (minv, none, none, Tc)
        prec = TwoLevel(D, SCALE, pre, L, e, span, g)
        ffts = _precondition(y, shift, out, prec, (0, 0, 0, 0), (a, c, work), circulant)
        assert ffts == 0
        return out

    def project(r, w, v):
        span = np.array([f0, f1, 0, 0, NC])
        z, s_v = np.empty(N), float(w @ v)
        pre = (minv, none, none, Tc)
        prec = TwoLevel(D, SCALE, pre, L, e, span, g)
        ffts = _projected_precondition(r, z, w, v, s_v, prec, (0, 0, 0, 0), (a, c, work))
        assert ffts == 0
        return z

    return apply, project, B, minv


@pytest.mark.parametrize("frozen", [0, 7])
def test_two_level_preconditioner_is_the_dense_product(frozen):
    """Jacobi smoother (no core) and the coarse correction, ``H P c`` and ``(H P)^T z`` from the
    prefix sums, against the dense two-level operator, with ``frozen`` cells at each end (M
    and R zero there; the coarse products then run over the span between them only)."""
    apply, _, B, minv = _two_level(frozen)
    y = np.random.default_rng(3).standard_normal(N)
    want = B @ y
    out = apply(y)
    assert np.all(out[minv == 0.0] == 0.0)
    np.testing.assert_allclose(out, want, rtol=0.0, atol=RTOL_COARSE * np.abs(want).max())


def test_preconditioner_without_circulant_and_with_a_shift():
    """``circulant=False`` leaves a declared core to Jacobi (the zero-load projection's
    direction ``B~ 1``, no FFT), and ``shift`` is subtracted from y first (``Pi* r``)."""
    apply, _, B, _ = _two_level(5)
    y = np.random.default_rng(4).standard_normal(N)
    want = B @ (y - 0.3)
    out = apply(y, shift=0.3, core=(40, 110), circulant=False)
    np.testing.assert_allclose(out, want, rtol=0.0, atol=RTOL_COARSE * np.abs(want).max())


@pytest.mark.parametrize("direction", ["B1", "random"])
def test_zero_load_projection_is_symmetric_along_any_direction(direction):
    """``Pi B Pi*`` (:func:`_projected_precondition`) column by column against the dense
    operator: symmetric, blind to constants (the load's multiplier), its output on zero load;
    along ``v = B 1`` it equals the B-orthogonal ``Pi B`` the solver used before."""
    _, project, B, minv = _two_level(5)
    live = (minv > 0.0).astype(float)
    w = np.full(N, 0.7)  # uniform cell weights, as the line contact's
    rng = np.random.default_rng(5)
    v = B @ np.ones(N) if direction == "B1" else rng.uniform(0.5, 1.5, N) * live
    s_v = float(w @ v)
    M = np.array([project(col, w, v) for col in np.eye(N)]).T
    scale = np.abs(M).max()
    np.testing.assert_allclose(M, M.T, rtol=0.0, atol=RTOL_COARSE * scale)
    y = rng.standard_normal(N)
    assert np.abs(M @ np.ones(N)).max() <= RTOL_COARSE * scale * N
    assert abs(w @ (M @ y)) <= RTOL_COARSE * scale * N * np.abs(y).max()
    if direction == "B1":
        z = B @ y
        want = z - v * (w @ z) / s_v
        np.testing.assert_allclose(M @ y, want, rtol=0.0, atol=RTOL_COARSE * np.abs(want).max())


def test_coarse_factor_is_galerkin_matrix_plus_a_constant_mode_penalty():
    """L L^T = P^T H P + beta s s^T (s the aggregate sizes, beta > 0): the Galerkin matrix
    from second-order prefix sums, its constant mode penalised."""
    K, D, e, _, L = _scene()
    HP, P = naive.coarse_operator(D, K, e)
    A = P.T @ HP
    Lf = np.tril(L)
    M = Lf @ Lf.T - A
    s = np.diff(e).astype(float)
    beta = s @ M @ s / (s @ s) ** 2
    assert beta > 0.0
    np.testing.assert_allclose(
        M, beta * np.outer(s, s), rtol=0.0, atol=RTOL_COARSE * np.abs(A).max()
    )


@pytest.mark.parametrize("n", [1, 5, _STRIP - 1, _STRIP, _STRIP + 1, 3 * _STRIP + 7])
def test_strip_reductions_equal_numpy(n):
    rng = np.random.default_rng(n)
    w, a, b = rng.uniform(0.5, 1.5, n), rng.standard_normal(n), rng.standard_normal(n)
    acc = np.empty(min(n, _STRIP))
    scale = np.abs(a * b).sum() * 1.5
    ones = np.ones(n)
    assert _wdot(ones, a, b, acc) == pytest.approx(a @ b, abs=RTOL_ROUNDOFF * scale)
    assert _wdot(w, a, b, acc) == pytest.approx(np.sum(w * a * b), abs=RTOL_ROUNDOFF * scale)
    res = a + 10.0  # a mean far above the spread: the mean is removed before squaring
    mean = np.sum(w * res) / w.sum()
    want = math.sqrt(np.sum(w * (res - mean) ** 2))
    got = _jacobi_norm(res, w, w.sum(), ones, np.empty(n), acc)
    assert got == pytest.approx(want, rel=RTOL_ROUNDOFF)


@pytest.mark.parametrize(("n", "nc"), [(9, 3), (10, 4), (63, 7), (150, 16)])
def test_edge_window_products_equal_numpy(n, nc):
    """The coarse level's products with the shifted windows ``Tc[n - e_j : 2n - e_j]``, four
    edges per pass and a remainder (nc + 1 = 4, 5, 8, 17; n not a multiple of 4 too), over
    the whole grid and over a span ``[lo, hi)`` of it (the rest of r untouched)."""
    rng = np.random.default_rng(n + nc)
    Tc, x = rng.standard_normal(2 * n), rng.standard_normal(n)
    e = np.sort(rng.choice(np.arange(1, n), nc + 1, replace=False)).astype(np.int64)
    windows = np.array([Tc[n - ej : 2 * n - ej] for ej in e])  # (nc + 1) x n
    scale = np.abs(windows).sum(axis=1).max() * np.abs(x).max()
    c = rng.standard_normal(nc + 1)
    for lo, hi in ((0, n), (1, n - 2), (3, 3)):
        inside = (np.arange(n) >= lo) & (np.arange(n) < hi)
        g = np.full(nc + 1, np.nan)
        _edge_correlations(x, Tc, e, nc, g, lo, hi)
        want = windows @ np.where(inside, x, 0.0)
        np.testing.assert_allclose(g, want, rtol=0.0, atol=RTOL_ROUNDOFF * scale)
        r = x.copy()
        _subtract_edge_combination(r, Tc, e, nc, c, lo, hi)
        want = np.where(inside, x - c @ windows, x)
        np.testing.assert_allclose(r, want, rtol=0.0, atol=RTOL_ROUNDOFF * scale)
    lo, hi = int(e[0]), int(e[-1])
    got = segment_sum(x, Tc, lo, hi)
    assert got == pytest.approx(x[lo:hi] @ Tc[lo:hi], abs=RTOL_ROUNDOFF * scale)


def test_live_span_of_frozen_cells():
    assert _live_span(np.array([0.0, 0.0, 1.0, 0.0, 2.0, 0.0])) == (2, 5)
    assert _live_span(np.zeros(4)) == (0, 0)
    assert _live_span(np.ones(3)) == (0, 3)
