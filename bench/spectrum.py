"""Spectrum of a line-contact solve's preconditioned Newton system: ``python -m bench.spectrum``.

Solves one scene through the Python Newton loop (the compiled Newton-system solver of
:mod:`fastline.elastic.pcg` for each system; same steps and CG counts as the compiled loop),
records every Newton system, and analyses one of them: the eigenvalues of ``B H`` on zero-load
increments of the cells that are not frozen (``H = D + K``, ``B`` the two-level preconditioner
with the projection onto zero load, exactly as the compiled CG applies it), where the slowest
modes live, and how many CG iterations variants of the preconditioner would need on that system
(simulated PCG with the compiled loop's stopping rule; the Newton trajectory is kept fixed).

    python -m bench.spectrum --n 4096 --alpha 1e-2 --step 4 --dense
    python -m bench.spectrum --n 16384 --alpha 1e-2 --step 4 --nc 64 128 256
    python -m bench.spectrum --n 16384 --alpha 1e-2 --solver-nc 64   # 64 aggregates instead of 128

``--solver-nc`` replaces :func:`fastline.elastic.line.coarse_aggregates` for the whole run (the
solve and the analysed preconditioner); ``--nc`` simulates other aggregate counts on the recorded
systems.

``--dense`` (n <= 4096: ~25-40 s at 4096): all eigenvalues; otherwise preconditioned Lanczos
with full reorthogonalisation (``--lanczos`` vectors; the extreme eigenvalues converge).
Regions of a mode (shares of its squared amplitude): the core (circulant block, ``D <
CORE_THETA K00``), the rest of the wide block (the contact edge, Jacobi + coarse), the other live
cells (Jacobi only).
"""

from __future__ import annotations

import argparse
import math
import time
import warnings

import numpy as np

import fastline as fl
from fastline._lib import fftw as _fftw
from fastline._lib.fftw import aligned_buffers
from fastline.contact import line as _line_contact
from fastline.elastic import line as elastic
from fastline.elastic import preconditioner as tp
from fastline.elastic.convolution import apply_kernel
from fastline.elastic.line import influence_coefficients
from fastline.reports.paper import E_STAR, RADIUS, load_for_alpha, surfaces


def capture(psd, alpha: float, n: int):
    """``(result, systems)``: a default solve through the Python Newton loop, and every Newton
    system it solved (dicts of op, D, w, rhs, rtol, its)."""
    systems = []
    cls = elastic.LogKernelOperator
    orig_compiled, orig_solve = _line_contact.solve_compiled, cls.solve_newton

    def recording(self, D, w, rhs, rtol, maxit):
        out = orig_solve(self, D, w, rhs, rtol, maxit)
        systems.append(dict(op=self, D=D.copy(), w=w.copy(), rhs=rhs.copy(), rtol=rtol, its=out[2]))
        return out

    _line_contact.solve_compiled = lambda *a, **k: None
    cls.solve_newton = recording
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            load = load_for_alpha(alpha, psd.h_rms, E_STAR)
            res = fl.solve_line_contact(psd, E_STAR, RADIUS, load, n=n, warn=False)
    finally:
        _line_contact.solve_compiled, cls.solve_newton = orig_compiled, orig_solve
    return res, systems


class TwoLevel:
    """The compiled preconditioner: the set-up stages of ``solve_newton_system``
    (``_smoother``, ``_coarse_level``), and ``R B R`` by its ``_precondition``; ``nc_max`` as
    the solver's."""

    def __init__(self, op, D: np.ndarray, nc_max: int | None = None) -> None:
        n = self.n = D.shape[0]
        self.kspec, strang, prefix = elastic.compiled_tables(n)
        self.scale, K00 = op._scale, op.diagonal
        self.K00, self.D = K00, D
        nc_max = elastic.coarse_aggregates(n) if nc_max is None else min(nc_max, n // 4)
        self.minv, self.S, self.cinv = np.zeros(n), np.zeros(n), np.zeros(n + 1)
        self.Tc, U = np.zeros(2 * n), np.zeros(2 * n + 1)
        self.e = np.zeros(nc_max + 1, np.int64)
        self.L = np.zeros((max(nc_max, 1), max(nc_max, 1)))
        self.span = np.zeros(5, np.int64)
        tp._smoother(D, K00, self.scale, strang, self.minv, self.S, self.cinv, self.span)
        coarse = (self.e, self.Tc, U, self.L)
        tp._coarse_level(D, K00, self.scale, prefix, nc_max, coarse, np.zeros(n), self.span)
        self.f0, self.f1, self.i0, self.i1, self.nc = (int(v) for v in self.span)
        self.j0, self.j1 = tp._first_last(D, tp.WIDE_THETA * K00)
        self.live = self.minv > 0.0
        self.fft = _fftw.acquire(2 * n)  # kept for the life of the process (a script)
        a, c = aligned_buffers(2 * n)
        work = np.zeros(3 * n + min(n, 64))
        work[2 * n : 3 * n] = 1.0
        self.bufs = (a, c, work)
        self.g = np.zeros(2 * nc_max + 2)
        v = self.B(np.ones(n), circulant=False)  # the projection's direction, as the solver's
        self._v, self._sv = v, v.sum()

    def B(self, y: np.ndarray, circulant: bool = True) -> np.ndarray:
        out = np.empty(self.n)
        pre = (self.minv, self.S, self.cinv, self.Tc)
        prec = tp.TwoLevel(self.D, self.scale, pre, self.L, self.e, self.span, self.g)
        y = np.ascontiguousarray(y, dtype=np.float64)
        tp._precondition(y, 0.0, out, prec, tuple(self.fft), self.bufs, circulant)
        return out

    def Bp(self, y: np.ndarray) -> np.ndarray:
        """``Pi B Pi*`` with the solver's projection onto zero load along ``v = B~ 1``
        (:func:`fastline.elastic.pcg._projected_precondition`; uniform weights)."""
        z = self.B(y - self._v.dot(y) / self._sv)
        return z - self._v * (z.sum() / self._sv)

    def H(self, x: np.ndarray) -> np.ndarray:
        out = np.empty(self.n)
        apply_kernel(
            np.ascontiguousarray(x, dtype=np.float64), self.kspec, self.scale, *self.fft, out
        )
        return (out + self.D * x) * self.live

    def shares(self, x: np.ndarray) -> tuple[float, float, float]:
        """Shares of ``x**2`` in the core, the rest of the wide block, the other live cells."""
        e2 = x**2 / np.sum(x**2)
        idx = np.arange(self.n)
        core = (idx >= self.i0) & (idx < self.i1)
        wide = (idx >= self.j0) & (idx < self.j1) & ~core
        return float(e2[core].sum()), float(e2[wide].sum()), float(e2[~core & ~wide].sum())


def lanczos(pc: TwoLevel, k: int, seed: int = 0):
    """Ritz values and primal Ritz vectors of ``Bp H`` on zero-load live increments:
    preconditioned Lanczos (residual vectors u, preconditioned v = Bp u, ``v_i . u_j = delta``)
    with full reorthogonalisation."""
    live = pc.live
    r = np.random.default_rng(seed).standard_normal(pc.n) * live
    z = pc.Bp(r)
    beta = math.sqrt(r @ z)
    U, V, alphas, betas = [r / beta], [z / beta], [], []
    for j in range(k):
        Hv = pc.H(V[j])
        a = V[j] @ Hv
        w = Hv - a * U[j] - (betas[-1] * U[j - 1] if j else 0.0)
        Um, Vm = np.array(U), np.array(V)
        for _ in range(2):
            w -= Um.T @ (Vm @ w)
            w -= live * w[live].mean()  # constants: in Bp's null space, they would only grow
        alphas.append(a)
        z = pc.Bp(w)
        b2 = w @ z
        if b2 <= 1e-28 * a * a:
            break
        betas.append(math.sqrt(b2))
        U.append(w / betas[-1])
        V.append(z / betas[-1])
    m = len(alphas)
    T = np.diag(alphas) + np.diag(betas[: m - 1], 1) + np.diag(betas[: m - 1], -1)
    lam, Y = np.linalg.eigh(T)
    return lam, np.array(V[:m]).T @ Y


def dense_spectrum(pc: TwoLevel):
    """All eigenvalues (and eigenvectors, zero on frozen cells) of ``Bp H`` on zero-load live
    increments: ``Z`` an orthonormal basis of them, ``eig(Z^T Bp Z . Z^T H Z)``."""
    n, live = pc.n, np.flatnonzero(pc.live)
    m = live.size
    eye = np.eye(n)
    Bm = np.array([pc.B(eye[i]) for i in live]).T[live]
    Bm = 0.5 * (Bm + Bm.T)
    v = pc._v[live]
    Pi = np.eye(m) - np.outer(v, np.ones(m)) / v.sum()  # the solver's projection (Bp)
    Bp = Pi @ Bm @ Pi.T
    idx = np.arange(n)
    H = pc.scale * influence_coefficients(n)[np.abs(idx[:, None] - idx[None, :])]
    H[np.diag_indices(n)] += pc.D
    H = H[np.ix_(live, live)]
    u = np.full(m, 1.0 / math.sqrt(m))  # Householder: Q e1 = ones / sqrt(m)
    u[0] -= 1.0
    u /= np.linalg.norm(u)
    Z = (np.eye(m) - 2.0 * np.outer(u, u))[:, 1:]
    Lc = np.linalg.cholesky(Z.T @ H @ Z)
    lam, Y = np.linalg.eigh(Lc.T @ (Z.T @ Bp @ Z) @ Lc)
    X = np.zeros((n, m - 1))
    X[live] = Z @ np.linalg.solve(Lc.T, Y)
    return lam, X


def pcg_iterations(pc: TwoLevel, rhs: np.ndarray, rtol: float, maxit: int = 400) -> int:
    """CG iterations of the compiled loop's projected PCG on this system with ``pc`` (stops on
    the Jacobi-weighted norm of the mean-free residual, as ``solve_newton_system``)."""
    jac = pc.minv

    def norm(r):
        t = r - (jac @ r) / jac.sum()
        return math.sqrt(jac @ (t * t))

    res = rhs * pc.live
    z = pc.Bp(res)
    d, rz, r0 = z.copy(), res @ z, norm(res)
    for its in range(1, maxit + 1):
        Hd = pc.H(d)
        res = res - (rz / (d @ Hd)) * Hd
        if norm(res) <= rtol * r0:
            return its
        z = pc.Bp(res)
        rz, rz_old = res @ z, rz
        d = z + (rz / rz_old) * d
    return maxit


def report(n: int, alpha: float, step: int, dense: bool, k: int, ncs: list[int]) -> None:
    res, systems = capture(surfaces()[0], alpha, n)
    sysm = systems[step - 1]
    its = [s["its"] for s in systems]
    print(f"surface 1, alpha {alpha:g}, n {n}: {res.convolutions} convolutions, CG/step {its}")
    pc = TwoLevel(sysm["op"], sysm["D"])
    print(
        f"Newton system {step}: rtol {sysm['rtol']:.2g}, {sysm['its']} CG iterations; live cells"
        f" [{pc.f0}, {pc.f1}), core [{pc.i0}, {pc.i1}), wide block [{pc.j0}, {pc.j1}), nc {pc.nc}"
    )
    t = time.perf_counter()
    lam, X = dense_spectrum(pc) if dense else lanczos(pc, k)
    how = "dense" if dense else f"Lanczos, {k} vectors"
    print(f"eigenvalues of B H ({how}, {time.perf_counter() - t:.1f} s):", end=" ")
    print(f"[{lam[0]:.3g}, {lam[-1]:.3g}], condition number {lam[-1] / lam[0]:.3g}")
    print(f"  lowest 8:  {np.array2string(lam[:8], precision=3)}")
    print(f"  highest 8: {np.array2string(lam[-8:], precision=3)}")
    if dense:
        q = np.quantile(lam, [0.01, 0.05, 0.25, 0.5, 0.75, 0.95, 0.99])
        print(f"  quantiles 1/5/25/50/75/95/99%: {np.array2string(q, precision=3)}")
        print(f"  below 0.5: {(lam < 0.5).sum()}, above 2: {(lam > 2).sum()} of {lam.size}")
    for j in (0, 1, 2, 3, -4, -3, -2, -1):
        x = X[:, j]
        peak = int(np.argmax(np.abs(x)))
        big = np.flatnonzero(np.abs(x) > 0.1 * np.abs(x[peak]))
        big = big[(big < pc.n // 2) == (peak < pc.n // 2)]  # the peak's half (modes pair up)
        core, edge, rest = pc.shares(x)
        print(
            f"  mode {lam[j]:.3g}: core {core:.2f} edge {edge:.2f} Jacobi {rest:.2f}; peak at cell"
            f" {peak} (D/K00 {pc.D[peak] / pc.K00:.3g}), > 10% of it on [{big[0]}, {big[-1]}]"
        )
    for nc in ncs:
        sim = [pcg_iterations(TwoLevel(s["op"], s["D"], nc), s["rhs"], s["rtol"]) for s in systems]
        conv = res.convolutions + 2 * (sum(sim) - sum(its))
        print(f"simulated with nc_max {nc}: CG/step {sim}, ~{conv} convolutions")


if __name__ == "__main__":
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--n", type=int, default=1024)
    ap.add_argument("--alpha", type=float, default=1e-2)
    ap.add_argument("--step", type=int, default=4, help="Newton system (1-based)")
    ap.add_argument("--dense", action="store_true", help="all eigenvalues (n <= 4096)")
    ap.add_argument("--lanczos", type=int, default=150, help="Lanczos vectors")
    ap.add_argument("--nc", type=int, nargs="*", default=[], help="aggregate counts to simulate")
    ap.add_argument("--solver-nc", type=int, help="the solver's aggregate count, for any n")
    a = ap.parse_args()
    if a.solver_nc:
        elastic.coarse_aggregates = lambda n: a.solver_nc
    report(a.n, a.alpha, a.step, a.dense, a.lanczos, a.nc)
