"""Tests for fastline.elastic.line: the plane-strain log-kernel operator."""

from __future__ import annotations

import math
import os
import subprocess
import sys
import threading

import numpy as np
import pytest
import scipy.linalg
from scipy.integrate import quad

import fastline._lib.fftw
from fastline.elastic.line import LogKernelOperator, influence_coefficients, log_reference_shift
from fastline.theory.limits import hertz_line_contact

RTOL_EXACT = 1e-12  # FFT product vs dense product, closed form vs quadrature
RTOL_CONTINUUM = 1e-3  # discretised Hertz displacement vs the continuum parabola
EIG_FLOOR = 1e-3  # smallest zero-sum eigenvalue of K, in units of dx / E* (observed ~0.74)

E_STAR = 1.33e9  # Pa (paper's scenes)
RADIUS = 0.01  # m


def _rng(seed=20240601):
    return np.random.default_rng(seed)


@pytest.mark.parametrize("n", [17, 64, 255, 1000])
def test_apply_matches_dense(n):
    rng = _rng(n)
    op = LogKernelOperator(n, dx=3.7e-6, E_star=E_STAR)
    dense = op.dense()
    for _ in range(3):
        p = rng.uniform(0.0, 1e8, size=n)
        expected = dense @ p
        got = op.apply(p)
        assert np.linalg.norm(got - expected) <= RTOL_EXACT * np.linalg.norm(expected)
    assert op.convolutions == 3


def test_apply_out_argument_and_aliasing():
    n = 64
    p = _rng().uniform(0.0, 1.0, n)
    op = LogKernelOperator(n, dx=1e-5, E_star=E_STAR)
    ref = op.apply(p)
    out = np.empty(n)
    assert op.apply(p, out=out) is out
    np.testing.assert_array_equal(out, ref)
    q = p.copy()
    op.apply(q, out=q)  # in place
    np.testing.assert_array_equal(q, ref)
    with pytest.raises(ValueError, match="p must have shape"):
        op.apply(np.ones(n + 1))
    with pytest.raises(ValueError, match="out"):
        op.apply(p, out=np.empty(n, dtype=np.float32))


def test_dense_is_symmetric_toeplitz_with_diagonal():
    op = LogKernelOperator(40, dx=2e-6, E_star=E_STAR)
    K = op.dense()
    np.testing.assert_array_equal(K, K.T)
    khat = influence_coefficients(40)
    np.testing.assert_allclose(K[0], khat * op.dx / op.E_star, rtol=RTOL_EXACT, atol=0)
    np.testing.assert_allclose(np.diag(K), op.diagonal, rtol=RTOL_EXACT)


@pytest.mark.parametrize("m", [0, 1, 2, 3, 7, 50, 1000, 12345])
def test_coefficients_match_quadrature(m):
    khat = influence_coefficients(m + 1)[m]

    def integrand(t):
        return -(2.0 / math.pi) * math.log(abs(t))

    points = [0.0] if m == 0 else None
    ref, _ = quad(integrand, m - 0.5, m + 0.5, points=points, epsabs=0.0, epsrel=1e-13, limit=200)
    assert khat == pytest.approx(ref, rel=RTOL_EXACT, abs=0.0)


def test_coefficients_closed_form_m0():
    # -(2/pi) * 2 g(1/2) with g(t) = t ln|t| - t
    g_half = 0.5 * math.log(0.5) - 0.5
    assert influence_coefficients(1)[0] == pytest.approx(-(2 / math.pi) * 2 * g_half, rel=1e-15)


def test_positive_definite_on_zero_sum_subspace():
    worst = math.inf
    for n in range(16, 201):
        K = LogKernelOperator(n, dx=1.0, E_star=1.0).dense()
        basis = scipy.linalg.null_space(np.ones((1, n)))  # orthonormal, n x (n-1)
        assert basis.shape == (n, n - 1)
        eig = np.linalg.eigvalsh(basis.T @ K @ basis)
        assert eig.shape == (n - 1,)
        worst = min(worst, eig[0])
        assert eig[0] > EIG_FLOOR, f"n={n}: smallest zero-sum eigenvalue {eig[0]}"
    assert worst > 0.0


def test_projected_operator_has_single_null_direction():
    # P K P has the constant vector as its only null direction: exactly one eigenvalue ~ 0
    n = 50
    K = LogKernelOperator(n, dx=1.0, E_star=1.0).dense()
    P = np.eye(n) - np.full((n, n), 1.0 / n)
    eig = np.linalg.eigvalsh(P @ K @ P)
    assert np.sum(np.abs(eig) < 1e-10) == 1
    assert np.sum(eig > EIG_FLOOR) == n - 1


def _hammer(op, p, repeats, barrier, results, key):
    barrier.wait()
    out = None
    for _ in range(repeats):
        out = op.apply(p)
    results[key] = out


@pytest.mark.parametrize("n_a,n_b", [(256, 256), (256, 300), (1000, 37)])
def test_thread_safety(n_a, n_b):
    rng = _rng(n_a * 1000 + n_b)
    op_a = LogKernelOperator(n_a, dx=1e-6, E_star=E_STAR)
    op_b = LogKernelOperator(n_b, dx=7.3e-5, E_star=2.1e11)
    p_a = rng.uniform(0.0, 1e7, n_a)
    p_b = rng.uniform(0.0, 1e9, n_b)
    ref_a = op_a.apply(p_a)
    ref_b = op_b.apply(p_b)
    results = {}
    barrier = threading.Barrier(2)
    threads = [
        threading.Thread(target=_hammer, args=(op_a, p_a, 200, barrier, results, "a")),
        threading.Thread(target=_hammer, args=(op_b, p_b, 200, barrier, results, "b")),
    ]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    np.testing.assert_array_equal(results["a"], ref_a)
    np.testing.assert_array_equal(results["b"], ref_b)
    assert op_a.convolutions == 201
    assert op_b.convolutions == 201


def test_thread_safety_every_result_checked():
    # every intermediate result, not only the last one, must be uncorrupted
    n = 128
    ops = [LogKernelOperator(n, dx=dx, E_star=E_STAR) for dx in (1e-6, 3e-6)]
    ps = [_rng(s).uniform(0.0, 1e7, n) for s in (1, 2)]
    refs = [op.apply(p) for op, p in zip(ops, ps, strict=True)]
    bad = []
    barrier = threading.Barrier(2)

    def work(i):
        barrier.wait()
        for _ in range(200):
            if not np.array_equal(ops[i].apply(ps[i]), refs[i]):
                bad.append(i)

    threads = [threading.Thread(target=work, args=(i,)) for i in range(2)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert bad == []


@pytest.mark.parametrize(
    "kwargs,name",
    [
        ({"n": 1, "dx": 1e-6, "E_star": 1e9}, "n"),
        ({"n": 0, "dx": 1e-6, "E_star": 1e9}, "n"),
        ({"n": 16.5, "dx": 1e-6, "E_star": 1e9}, "n"),
        ({"n": True, "dx": 1e-6, "E_star": 1e9}, "n"),
        ({"n": 16, "dx": 0.0, "E_star": 1e9}, "dx"),
        ({"n": 16, "dx": -1e-6, "E_star": 1e9}, "dx"),
        ({"n": 16, "dx": float("nan"), "E_star": 1e9}, "dx"),
        ({"n": 16, "dx": float("inf"), "E_star": 1e9}, "dx"),
        ({"n": 16, "dx": 1e-6, "E_star": 0.0}, "E_star"),
        ({"n": 16, "dx": 1e-6, "E_star": float("nan")}, "E_star"),
    ],
)
def test_operator_validation(kwargs, name):
    with pytest.raises(ValueError, match=name):
        LogKernelOperator(**kwargs)


def test_coefficients_validation():
    for bad in (0, -3, 2.5, None):
        with pytest.raises(ValueError, match="n"):
            influence_coefficients(bad)


def test_log_reference_shift():
    n, dx, L = 200, 2e-6, 1e-3
    op = LogKernelOperator(n, dx=dx, E_star=E_STAR)
    p = _rng(5).uniform(0.0, 1e8, n)
    load = p.sum() * dx
    shift = log_reference_shift(load, dx, E_STAR, L)
    # dense matrix with ln(|x - x'| / L): K_L = K_dx - (2/(pi E*)) ln(dx/L) dx
    K_L = op.dense() - (2.0 / (math.pi * E_STAR)) * math.log(dx / L) * dx
    np.testing.assert_allclose(K_L @ p, op.apply(p) + shift, rtol=RTOL_EXACT)
    assert log_reference_shift(load, dx, E_STAR, dx) == 0.0
    with pytest.raises(ValueError, match="length"):
        log_reference_shift(load, dx, E_STAR, 0.0)
    with pytest.raises(ValueError, match="load"):
        log_reference_shift(float("nan"), dx, E_STAR, L)


@pytest.mark.parametrize("n", [4001, 4000])
def test_hertz_displacement_is_parabolic(n):
    # Hertz: inside the contact the elastic displacement is const - x^2 / (2R)
    hertz = hertz_line_contact(E_STAR, RADIUS, 1e4)
    half = 1.5 * hertz.a
    dx = 2.0 * half / n
    x = -half + dx * (np.arange(n) + 0.5)  # cell centres, symmetric about 0
    p = hertz.pressure(x)
    u = LogKernelOperator(n, dx=dx, E_star=E_STAR).apply(p)
    core = np.abs(x) < 0.8 * hertz.a
    c2, c1, _ = np.polyfit(x[core], u[core], 2)
    assert c2 == pytest.approx(-1.0 / (2.0 * RADIUS), rel=RTOL_CONTINUUM)
    assert abs(c1) * hertz.a < RTOL_CONTINUUM * abs(c2) * hertz.a**2  # symmetric
    # and the second difference at the centre agrees as well
    i = int(np.argmin(np.abs(x)))
    d2 = (u[i + 1] - 2.0 * u[i] + u[i - 1]) / dx**2
    assert d2 == pytest.approx(-1.0 / RADIUS, rel=RTOL_CONTINUUM)


# ---- the preconditioner's circulant inverse ------------------------------------------------
def _strang_dense(n, dx, shift):
    """Dense Strang circulant of size 2n (from khat_0..khat_n), K + shift I, with its
    zero-frequency eigenvalue moved to the largest other one (as documented)."""
    kh = influence_coefficients(n + 1) * (dx / E_STAR)
    col = np.concatenate([kh, kh[-2:0:-1]])
    size = 2 * n
    C = scipy.linalg.circulant(col) + shift * np.eye(size)
    lam = np.fft.rfft(col).real
    return C + (lam[1:].max() - lam[0]) * np.ones((size, size)) / size


@pytest.mark.parametrize("n,m", [(16, 16), (33, 20), (64, 1)])
def test_circulant_inverse_matches_dense_solve(n, m):
    dx, shift = 2e-6, 3e-15
    op = LogKernelOperator(n, dx=dx, E_star=E_STAR)
    y = _rng(n + m).standard_normal(m)
    want = np.linalg.solve(_strang_dense(n, dx, shift), np.concatenate([y, np.zeros(2 * n - m)]))
    got = op.circulant_inverse(shift).apply(y, np.empty(m))
    np.testing.assert_allclose(got, want[:m], rtol=0.0, atol=RTOL_EXACT * np.abs(want).max())
    # the block the vector sees is K's own block (Toeplitz): C agrees with K there
    C = _strang_dense(n, dx, 0.0)
    np.testing.assert_allclose(C[:m, :m] - C[0, 0] + op.diagonal, op.dense()[:m, :m])
    assert op.convolutions == 1 and op.circulant_solves == 1


def test_circulant_inverse_is_positive_definite():
    op = LogKernelOperator(200, dx=1e-6, E_star=E_STAR)
    inv = op.circulant_inverse(0.0)
    M = np.column_stack([inv.apply(e, np.empty(120)) for e in np.eye(120)])
    np.testing.assert_allclose(M, M.T, rtol=0.0, atol=RTOL_EXACT * np.abs(M).max())
    assert np.linalg.eigvalsh(0.5 * (M + M.T)).min() > 0.0
    with pytest.raises(ValueError, match="shift"):
        op.circulant_inverse(-1.0)


# ---- the compiled path (FFTW called from Numba) ----------------------------------------------
RTOL_NEWTON_SYSTEM = 1e-8  # compiled PCG at rtol 1e-12 vs a dense solve, normwise (cond ~1e15)
RTOL_FALLBACK = 1e-8  # p0 and w/s of the compiled path against the pyFFTW fallback (tol 1e-8)


@pytest.mark.skipif(not fastline._lib.fftw.AVAILABLE, reason="no FFTW library found")
@pytest.mark.parametrize("n", [17, 64, 257])
def test_compiled_newton_system_against_dense(n):
    """(D + K) dp + du1 = r, sum(w dp) = 0 solved by the compiled two-level PCG equals the dense
    saddle-point solve, for D spanning the regimes of a solve (core, edge, frozen tail)."""
    rng = np.random.default_rng(n)
    op = LogKernelOperator(n, 1e-5, 1e9)
    x = np.linspace(-1.0, 1.0, n)
    D = op.diagonal * np.where(np.abs(x) < 0.6, 1e-3, 10.0 ** (4 * (np.abs(x) - 0.6) / 0.4))
    D[-2:] = 1e300  # frozen cells
    w = np.full(n, 1e-5)
    r = rng.standard_normal(n) * 1e-6
    dp, du1, its = op.solve_newton(D, w, r, 1e-12, 400)
    # the two frozen cells decouple (D = 1e300, dp ~ 1e-306): the dense saddle-point system of
    # the active cells, unknowns dp and the multiplier du1
    m = n - 2
    A = np.zeros((m + 1, m + 1))
    A[:m, :m] = np.diag(D[:m]) + op.dense()[:m, :m]
    A[:m, m] = 1.0
    A[m, :m] = w[:m]
    ref = np.linalg.solve(A, np.r_[r[:m], 0.0])
    assert np.max(np.abs(dp[:m] - ref[:m])) < RTOL_NEWTON_SYSTEM * np.abs(ref[:m]).max()
    assert du1 == pytest.approx(ref[m], rel=RTOL_NEWTON_SYSTEM)
    assert abs(np.dot(w, dp)) < 1e-12 * np.dot(w, np.abs(dp))
    assert op.convolutions > its  # K products and circulant solves, counted


@pytest.mark.skipif(not fastline._lib.fftw.AVAILABLE, reason="no FFTW library found")
def test_compiled_apply_against_dense():
    for n in (16, 100, 1025):
        op = LogKernelOperator(n, 2e-6, 3e9)
        p = np.random.default_rng(n).random(n)
        assert np.allclose(op.apply(p), op.dense() @ p, rtol=1e-12, atol=1e-15 * op.diagonal)


def test_fallback_path_gives_the_same_solutions():
    """FASTLINE_PURE_PYFFTW=1 (no compiled FFT: pyFFTW and the Python CG) solves the same
    scenes to the solver tolerance."""
    code = (
        "import fastline as fl, math\n"
        "from fastline._lib import fftw as _fftw\n"
        "psd = fl.SelfAffinePSD(10e-6, 0.8, 1e3, 1e4, 1e9)\n"
        "for a in (1e-3, 0.1, 10.0):\n"
        "    r = fl.solve_line_contact(psd, 1.33e9, 0.01, math.pi/4*psd.h_rms*1.33e9/a, n=256)\n"
        "    print(repr(r.p0), repr(r.w_over_s), r.converged, _fftw.AVAILABLE)\n"
    )
    outs = []
    for flag in ("1", ""):
        env = dict(os.environ, FASTLINE_PURE_PYFFTW=flag)
        run = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True)
        assert run.returncode == 0, run.stderr
        outs.append([line.split() for line in run.stdout.strip().splitlines()])
    assert all(row[3] == "False" for row in outs[0])
    for pure, fast in zip(*outs, strict=True):
        assert pure[2] == fast[2] == "True"
        assert float(pure[0]) == pytest.approx(float(fast[0]), rel=RTOL_FALLBACK)
        assert float(pure[1]) == pytest.approx(float(fast[1]), rel=RTOL_FALLBACK)


def test_fftw_library_is_found():
    """pyFFTW's wheel (or the system) provides FFTW: the fast path is on in CI."""
    assert fastline._lib.fftw.AVAILABLE, "no FFTW library: the compiled FFT path is off"
    assert fastline._lib.fftw.library_path
