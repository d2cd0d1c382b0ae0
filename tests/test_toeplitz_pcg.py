"""The compiled Newton-system solver's building blocks against dense NumPy references.

The solver itself is tested against a dense saddle-point solve in tests/test_elastic.py; here
the prefix-sum forms of the coarse level (no n x nc matrix) and the strip-wise reductions.
"""

from __future__ import annotations

import math

import naive
import numpy as np
import pytest

from fastline._toeplitz_pcg import (
    _STRIP,
    _coarse_matrices,
    _coarse_product,
    _coarse_restrict,
    _dot,
    _jacobi_norm,
    _log_sum,
    _wdot,
    prefix_sums,
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
    _coarse_matrices(D, SCALE, prefix_sums(khat), J0, J1, NC, e, Tc, U, L)
    return K, D, e, Tc, L


def test_aggregates_tile_the_wide_block():
    e = _scene()[2]
    assert e[0] == J0 and e[-1] == J1
    assert set(np.diff(e)) <= {(J1 - J0) // NC, (J1 - J0) // NC + 1}


def test_coarse_product_is_the_dense_h_p_product():
    K, D, e, Tc, _ = _scene()
    HP, _ = naive.coarse_operator(D, K, e)
    c = np.random.default_rng(1).standard_normal(NC)
    out = np.random.default_rng(2).standard_normal(N)
    want = out - HP @ c
    _coarse_product(c, D, SCALE, e, NC, Tc, np.empty(NC + 1), out)
    np.testing.assert_allclose(out, want, rtol=0.0, atol=RTOL_COARSE * np.abs(HP @ c).max())


def test_coarse_restrict_is_the_dense_transposed_product():
    K, D, e, Tc, _ = _scene()
    HP, _ = naive.coarse_operator(D, K, e)
    z = np.random.default_rng(3).standard_normal(N)
    g = np.empty(NC + 1)
    _coarse_restrict(z, D, SCALE, e, NC, Tc, np.empty(_STRIP), g)
    want = HP.T @ z
    np.testing.assert_allclose(g[:NC], want, rtol=0.0, atol=RTOL_COARSE * np.abs(want).max())


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
    assert _dot(a, b, acc) == pytest.approx(a @ b, abs=RTOL_ROUNDOFF * scale)
    assert _wdot(w, a, b, acc) == pytest.approx(np.sum(w * a * b), abs=RTOL_ROUNDOFF * scale)
    res = a + 10.0  # a mean far above the spread: the mean is removed before squaring
    mean = np.sum(w * res) / w.sum()
    want = math.sqrt(np.sum(w * (res - mean) ** 2))
    got = _jacobi_norm(res, w, _dot(w, res, acc) / w.sum(), acc)
    assert got == pytest.approx(want, rel=RTOL_ROUNDOFF)


def test_log_sum_in_blocks_and_past_the_range_of_a_product():
    x = np.random.default_rng(5).uniform(1e-12, 1e-9, 21)
    assert _log_sum(x) == pytest.approx(np.log(x).sum(), rel=RTOL_ROUNDOFF)
    x[3:5] = 1e-300, 1e300  # a block product under- or overflowing: one logarithm per value
    x[9] = 1e-250
    assert _log_sum(x) == pytest.approx(np.log(x).sum(), rel=RTOL_ROUNDOFF)
