"""Compiled solver of the line contact's Newton system (the hot loop of every solve).

Each Newton step of :func:`fastline.contact.core.newton` solves

    (D + K) dp + du1 = r,        sum_i w_i dp_i = 0,

K the Toeplitz log-kernel compliance (:mod:`fastline.elastic.line`), D = |du_law/dp| > 0 diagonal.
This module does it in one compiled call, FFTs included (:mod:`fastline._lib.fftw`):
projected conjugate gradients in the inner product ``<a, b> = sum w a b`` with the
projection onto zero-load increments (du1 is the multiplier), preconditioned by
a two-level method:

* smoother: Jacobi ``1/(D + K00)``, except on the loaded core (cells from the first to the last
  with ``D < CORE_THETA K00``) where a Strang circulant of ``K + d I`` (d the geometric mean of
  D there) is inverted by FFT, scaled by ``S_i = sqrt((K00 + d)/(K00 + D_i))`` so that cells
  whose D departs from d keep their own diagonal (one FFT convolution per application);
* coarse correction on the smooth modes of the wide block (cells with ``D < WIDE_THETA K00``:
  the core plus the contact edge, where D spans five decades and neither Jacobi nor a circulant
  fits), ``nc`` piecewise-constant aggregates, applied multiplicatively:
  ``B = C + (I - C H) S (I - H C)``, ``C = P (P^T H P)^-1 P^T``. The aggregates are denser
  where ln(D + K00) changes fast (``EDGE_SHARE``, :func:`_aggregate_edges`): the slowest modes
  of the preconditioned system sit at the rim of the core, where the smoother switches from
  the circulant to Jacobi, and that rim widens in cells with n. Products with ``H P`` come
  from prefix sums of the Toeplitz coefficients (no FFT, no n x nc matrix):
  ``sum_{j in [a, b)} khat_|i-j| = T[i-a+n] - T[i-b+n]``, so ``H P c`` is one AXPY per
  aggregate edge and ``(H P)^T z`` one dot product per edge, and ``P^T H P`` is four values of
  the prefix sums of T per entry (O(nc^2) after an O(n) sum). The coarse matrix penalises its
  constant mode (the projection handles constants; the log kernel's constant mode is strongly
  negative).
* cells with ``D > FROZEN_THETA K00`` are decoupled: CG leaves them out (``R B R``, R zeroing
  them; their vectors would hold subnormal numbers ~r/D, D up to 1e300, which slowed FFTs and
  dot products 10-100x) and they get the Jacobi update from the final residual.

Dense analysis at n = 1024: the condition number of the preconditioned system on zero-load
increments falls from 5-32 (the circulant alone) to 1.3-4 (two-level, 32 aggregates). CG stops
when the Jacobi-weighted norm of the projected residual fell by ``rtol`` (known before the next
preconditioner application, which is then saved), and returns the best iterate it saw.

Spectrum against n (issue 13; ``python -m bench.spectrum``, surface 1, the 4th Newton system,
rtol 1e-3, with 32 aggregates below n = 8192 and 64 from there, the solver before issue 13).
Eigenvalues of ``B H`` on zero-load increments, dense at n = 1024 and 4096, Lanczos at 16384:

======  =====================================  =====================================
n       alpha = 1e-2                           alpha = 1e-3
======  =====================================  =====================================
1024    [0.55, 1.25], kappa 2.3, 5 CG its      [0.85, 1.13], kappa 1.3 (rtol 0.02)
4096    [0.45, 2.15], kappa 4.7, 7 CG its      [0.43, 1.36], kappa 3.2, 4 CG its
16384   [0.70, 6.75], kappa 9.7, 10 CG its     [0.22, 1.49], kappa 6.8, 7 CG its
======  =====================================  =====================================

The bulk is tight (at 4096: 50% of the eigenvalues within 0.99-1.03, 98% within 0.68-1.33); the
ends are a spread of mirror pairs (the left and right rims), not a few deflatable outliers
(16384, alpha 1e-2: 6.75, 5.47, 4.73, 4.26, ... at the top, 0.70, 0.73, 0.74, ... at the bottom).
They all sit at the core's rim, ``D ~ CORE_THETA K00``. Inside it (D/K00 2-10), a mode smooth
over more than ~D/K00 cells (the log kernel's energy above D) gets ``lambda -> S_i^2 = (K00 + d)
/ (K00 + D_i) < 1`` from the scaled circulant; outside it (D/K00 10-20, the Jacobi cells of the
wide block) Jacobi misses the same modes' log-kernel energy: lambda > 1. Those modes span
40-650 cells (2-7 sign changes); the band they live in widens in cells with n, while the
aggregates there are ~100-150 cells wide at n = 16384: the coarse space cannot resolve them
unless nc grows like n. With 4-cell aggregates over the whole wide block (nc 2100 at n = 16384)
kappa falls to 3.5, the bulk to [0.91, 1.42], and the top outliers move to the wide block's
own rim (3.2 at D/K00 ~ 100), but the solve still takes 37 convolutions (CG 1, 2, 3, 4, 3).
Each Newton step cost ``2 k + 2`` convolutions (k CG iterations, plus ``B 1``, the first
preconditioner application and the line search's residual) and the hard scenes take 5 Newton
steps: <= 30 needed at most 9 CG iterations over the five systems, i.e. the rtol-1e-3 system in
<= 3, a per-iteration reduction <= 0.1, kappa <~ 1.5 at every n. This preconditioner reaches
that only at n <= 1024 (simulated: 25 convolutions with 128 aggregates at n = 1024, alpha
1e-2); at n = 16384 not even with the O(n^2) coarse level of 4-cell aggregates (37, above).

Tried and not kept (FFT convolutions over the 160 scenes of the count test, 5 hard surfaces x 8
alphas 1e-4..1e3 x n = 256..16384: 2976 with this module; issue 13):

* no circulant (Jacobi and the coarse level only): 6213, and 209 at n = 16384, alpha 1e-4;
  the circulant also only in the tight systems (``rtol < 0.05``): more Newton steps, 33 -> 35-38
  at n = 1024, alpha 1e-2;
* the projection ``P B P`` (P the w-orthogonal projection onto zero load) instead of the
  B-orthogonal one: it saves the circulant solve of ``B 1`` per system, but at n = 1024,
  alpha 1e-2 it took 46 convolutions instead of 33;
* ``B 1`` of the previous Newton system kept while D moved by less than a threshold of 1% or
  5% (one of the two was measured: both runs shared a Numba cache, which does not key on module
  constants; the preconditioner is then slightly unsymmetric): 3013, single scenes doubling
  (21 -> 41);
* Krylov recycling: the previous systems' CG directions (at most 16, their K products kept,
  so the new system's Galerkin matrix needs no FFT) deflated from this system's CG: 2813, but
  worse at n = 1024 (worst 33 -> 35), for 2 x 16 extra vector passes per iteration;
* the circulant's shift at 0.3x or 3x the geometric mean of D: worse at n = 1024 and 4096.

Issue 13, kept: the projection onto zero load along ``B~ 1`` (the preconditioner without its
circulant, no FFT) in the symmetric form ``Pi B Pi*`` (:func:`_projected_precondition`) instead
of the B-orthogonal ``Pi B`` along ``B 1`` (one circulant solve per Newton system): each Newton
step now costs ``2 k + 1``. Over the 160 count scenes 2230 -> 1976 convolutions, per-n maxima
25 / 33 / 29 / 33 -> 21 / 28 / 27 / 29 (the same CG counts, system for system, in the
simulation). Why the kept ``B 1`` of the previous system (below) failed and this does not: a
v other than ``B 1`` in the one-sided form ``Pi B`` makes the preconditioner unsymmetric; in
the two-sided form any v keeps it symmetric. A random campaign (``python -m bench.campaign``,
240 scenes, alpha 1e-6..1e4, n 128..8192): 3920 -> 3452 convolutions, at most 77 -> 66, every
scene converged (one at alpha 1.6e-6, n 8192, had not); the hard contact (``python -m
bench.hard``): 18 / 9 / 18 / 9 -> 16 / 8 / 16 / 8 at n = 256 / 1024 / 4096 / 16384.

Issue 13, kept: 64 aggregates from n = 4096, 128 from 16384
(:func:`fastline.elastic.line.coarse_aggregates`): 2976 -> 2779 over the 160 scenes, per-n maxima
25 / 33 / 47 / 61 -> 25 / 33 / 41 / 53, for +0-6% warm time at n = 4096 and +9% at 16384.
Tried and not kept there ("simulated": every scene's recorded Newton systems re-solved by PCG
with the variant, the Newton trajectory fixed, ``bench/spectrum.py``; exact for the solver):

* 64 aggregates already at n = 1024: 648 -> 596, worst 33 -> 29, but +19% time at n = 1024
  (3.0 -> 3.6 ms, three interleaved rounds); 128 at n = 8192: 809 (49) -> 740 (43) for +25%
  time; nc = n / 64 (256 at 16384): worst 45, +65% time at 16384; n / 32: worst 41, 5x the time;
* the core and wide blocks' thresholds (simulated; CORE_THETA 20, 30, 100 x WIDE_THETA 100,
  1000): totals 2650-2906, but the maxima at n = 256-1024 rise (25 / 33 -> up to 29 / 39);
* the aggregates concentrated in the rim band (a share of 0.5-0.7 of the density on a Gaussian
  in log10 D around 3-30 K00, simulated on the worst scenes): from 6 fewer to 6 more
  convolutions per scene; the number of aggregates matters, not where in the band they sit;
* piecewise-linear (hat) coarse functions on the same nodes (simulated, nc 32 / 64): 0-4 fewer
  per worst scene (16384, alpha 1e-2: 61 -> 57); not worth Galerkin matrices from third-order
  prefix sums;
* the additive two-level form ``B = S + C`` (no ``H P`` product per application, so nc could
  grow at O(n) cost): far worse at any nc (16384, alpha 1e-2: 101-111 for nc 32-512);
* the correlations ``(H P)^T z`` vectorised as strip sums, to afford more aggregates: 0.32-0.46
  ns per cell and edge against 0.17-0.19 for the four chains (the combination ``H P c`` takes
  0.09).

Written in plain loops over arrays (no NumPy linear algebra, no sorting; arrays grouped only in
homogeneous tuples): Numba compiles that in a fraction of the time, and first-call compilation
is a real cost to users (the first version, with ``np.linalg.cholesky``, ``np.median`` and
mixed tuples, took 18 s to compile cold). The solve's stages (:func:`_smoother`,
:func:`_coarse_level`, :func:`_pcg_start`, :func:`_pcg`, :func:`_pcg_finish`) are inlined into
:func:`solve_newton_system` by Numba (``inline="always"``): as separate compiled functions they
cost ~2 s more of cold compilation (each is linked into its callers and optimised again there),
inlined the same as one long function (CPU time of the first answer, empty cache, two
interleaved rounds: 17.1-19.1 s before the split, 17.9-18.9 s inlined, 19.2-20.7 s not).

Where the time goes (surface 1, alpha = 1e-2, per solve; a C clock around the stages, same
run as the version before, issue 13). n = 4096 (6 Newton systems, 57 FFT convolutions, 22 CG
iterations, 4.3 ms): the systems take 3.2 ms, of which FFT convolutions 1.75 ms (54%), the
coarse products 0.54 ms (17%; 1.19 ms when each aggregate edge was a pass of strip sums of its
own), set-ups 0.27 ms (9%, mostly logarithms, ~5 ns each, one or two per cell), the rest CG
vector work and reductions. n = 256 (29 convolutions of ~1.5 us, 0.19 ms): a quarter in FFTs;
the rest is spread over per-call work (the coarse products 33 us, two 16 x 16 triangular
solves per preconditioner application at 0.28 us, set-ups ~4 us per system) and the Python
around the compiled solve (30-50 us). Loops are written so that LLVM vectorises them: sums in
strips of partial sums (:func:`_wdot`), slices instead of offset indices (``x[i + o]`` with
``o`` unknown keeps a wrap-around test in the loop); reductions it cannot vectorise (Numba
runs LLVM without its SLP vectoriser, and the JIT options allow no reassociation) run in four
independent chains (:func:`segment_sum`), except the coarse correlations, the largest of them,
compiled with reassociation (:data:`fastline._lib.jit.JIT_SUMS`; the coarse products 0.27 -> 0.16
ns per cell and edge).
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numba
import numpy as np

from fastline._lib.fftw import ALIGN_PAD, aligned_buffers, aligned_size, aligned_views, execute
from fastline._lib.jit import JIT, JIT_SUMS

#: core block of the smoother: cells with D < CORE_THETA K00
CORE_THETA = 10.0
_CORE_MIN_CELLS = 8
#: wide block of the coarse correction: cells with D < WIDE_THETA K00
WIDE_THETA = 100.0
#: share of the coarse aggregates placed by the variation of ln(D + K00) across the wide block
#: (the rest by width; :func:`_aggregate_edges`)
EDGE_SHARE = 0.7
#: decoupled cells, left out of CG: D > FROZEN_THETA K00
FROZEN_THETA = 1e10
#: interleaved partial sums of the reductions (strip length)
_STRIP = 64
#: CG stops when its residual has not improved for this many iterations (round-off)
_STAGNATION = 20
#: entries of ``span``, the preconditioner's integers: the live span [f0, f1), the core
#: [i0, i1), the number of aggregates
_F0, _F1, _I0, _I1, _NC = 0, 1, 2, 3, 4


class KernelTables(NamedTuple):
    """The log kernel's tables for n cells, dimensionless (K = scale * toeplitz(khat);
    :func:`fastline.elastic.line.compiled_tables` keeps them per n)."""

    #: spectrum of the zero-padded circulant embedding of khat, divided by 2n (n + 1 values)
    kspec: np.ndarray
    #: spectrum of khat's Strang circulant (n + 1 values)
    strang: np.ndarray
    #: prefix sums of the two-sided khat (2n values, :func:`prefix_sums`)
    prefix: np.ndarray


class KernelScale(NamedTuple):
    """The scale of the log kernel's compliance ``K = scale * toeplitz(khat)`` on a grid."""

    #: dx / E* (m/Pa)
    scale: float
    #: ``K00 = scale * khat_0``, the compliance's diagonal (m/Pa)
    diagonal: float


class CGSettings(NamedTuple):
    """How far :func:`solve_newton_system` solves, and the size of its coarse level."""

    #: relative decrease of the Jacobi-weighted residual norm at which CG stops (dimensionless)
    rtol: float
    #: most CG iterations
    maxit: int
    #: most coarse aggregates (:func:`fastline.elastic.line.coarse_aggregates`)
    nc_max: int


class TwoLevel(NamedTuple):
    """The two-level preconditioner of one Newton system as set up by :func:`_smoother` and
    :func:`_coarse_level` (module docstring), what :func:`_precondition` applies."""

    #: the system's diagonal ``|du_law/dp|`` (n values, m/Pa)
    D: np.ndarray
    #: dx / E* (m/Pa)
    scale: float
    #: ``(minv, S, cinv, Tc)``: Jacobi ``1/(D + K00)`` (Pa/m, 0 on frozen cells), the core's
    #: scales S (dimensionless), the inverse Strang spectrum (Pa/m, the FFT's 1/(2n)
    #: included), the centred prefix sums Tc of khat (dimensionless, 2n values)
    pre: tuple
    #: Cholesky factor of the coarse matrix ``P^T H P`` (nc_max x nc_max, leading nc x nc, m/Pa)
    L: np.ndarray
    #: the aggregates' edges (cells, int64, nc_max + 1)
    e: np.ndarray
    #: ``(f0, f1, i0, i1, nc)``: the live span, the core, the number of aggregates (int64)
    span: np.ndarray
    #: work array of 2 nc_max + 2 elements
    g: np.ndarray


# ----------------------------------------------------------------------------------------------
# FFT convolutions
# ----------------------------------------------------------------------------------------------
@numba.njit(**JIT)
def convolve(x, m, spec, fr2c, fc2r, pf, pb, a, c, out):
    """``out[:m] = (IFFT(spec * FFT([x[:m], 0...])))[:m]``: a linear convolution with the
    kernel whose real spectrum (normalisation included) is ``spec``; one FFT convolution."""
    for i in range(m):
        a[i] = x[i]
    for i in range(m, a.shape[0]):
        a[i] = 0.0
    execute(fr2c, pf, a.ctypes.data, c.ctypes.data)
    for k in range(spec.shape[0]):  # c holds (re, im) pairs; spec is real
        c[2 * k] *= spec[k]
        c[2 * k + 1] *= spec[k]
    execute(fc2r, pb, c.ctypes.data, a.ctypes.data)
    for i in range(m):
        out[i] = a[i]


@numba.njit(**JIT)
def apply_kernel(x, kspec, scale, fr2c, fc2r, pf, pb, out):
    """``out = K x`` with ``K = scale * toeplitz(khat)`` (``kspec``: spectrum of the zero-padded
    circulant embedding of khat, divided by 2n)."""
    n = x.shape[0]
    a, c = aligned_buffers(2 * n)
    convolve(x, n, kspec, fr2c, fc2r, pf, pb, a, c, out)
    for i in range(n):
        out[i] *= scale


# ----------------------------------------------------------------------------------------------
# reductions
# ----------------------------------------------------------------------------------------------
# The JIT options allow no reassociation, so ``s += a[i] * b[i]`` is one serial chain of
# additions (1.1 ns per cell). Here the sums run in ``acc.shape[0]`` interleaved partial sums
# (``acc`` a work array, ``_STRIP`` long): strips of that length are plain element-wise loops,
# which LLVM vectorises (0.2-0.25 ns per cell), in a fixed order (the same result on every run).
@numba.njit(**JIT)
def _wdot(w, a, b, acc):
    """``sum_i w_i a_i b_i`` (``w`` a vector of ones for a plain dot product)."""
    width = acc.shape[0]
    for k in range(width):
        acc[k] = 0.0
    for s in range(0, a.shape[0], width):
        m = min(width, a.shape[0] - s)
        sw, sa, sb = w[s : s + m], a[s : s + m], b[s : s + m]
        for k in range(m):
            acc[k] += sw[k] * sa[k] * sb[k]
    s0 = s1 = s2 = s3 = 0.0  # the partial sums, in four chains
    for k in range(0, width - 3, 4):
        s0 += acc[k]
        s1 += acc[k + 1]
        s2 += acc[k + 2]
        s3 += acc[k + 3]
    for k in range(width - width % 4, width):
        s0 += acc[k]
    return (s0 + s1) + (s2 + s3)


@numba.njit(**JIT)
def _jacobi_norm(res, jac, s_jac, ones, tmp, acc):
    """Jacobi-weighted norm of ``res`` with its Jacobi-weighted mean removed (the part the
    projection onto zero-load increments sees); ``tmp``: work array."""
    mean = _wdot(jac, res, ones, acc) / s_jac
    for i in range(res.shape[0]):
        tmp[i] = res[i] - mean
    return math.sqrt(_wdot(jac, tmp, tmp, acc))


# The coarse level's products with ``H P`` (:func:`_precondition`) take one shifted window
# ``Tc[n - e_j : 2n - e_j]`` of the prefix sums per aggregate edge: nc + 1 = 17 passes over n
# cells, as many multiply-adds as 8-17 FFT convolutions of size 2n. Both run four edges per
# pass (one load of x or r for four windows). The correlations are sums that LLVM vectorises
# once it may reassociate them (``JIT_SUMS``); before, four scalar chains per edge in registers
# (0.17-0.21 ns per cell and edge) beat the strip sums of :func:`_wdot` (0.27-0.69).
@numba.njit(**JIT)
def segment_sum(a, b, lo, hi):
    """``sum_{lo <= i < hi} a_i b_i`` in four chains (aggregate sums, a few to n cells)."""
    sa, sb = a[lo:hi], b[lo:hi]
    m = hi - lo
    m4 = m - m % 4
    s0 = s1 = s2 = s3 = 0.0
    for i in range(0, m4, 4):
        s0 += sa[i] * sb[i]
        s1 += sa[i + 1] * sb[i + 1]
        s2 += sa[i + 2] * sb[i + 2]
        s3 += sa[i + 3] * sb[i + 3]
    for i in range(m4, m):
        s0 += sa[i] * sb[i]
    return (s0 + s1) + (s2 + s3)


@numba.njit(**JIT_SUMS)
def _edge_correlations(x, Tc, e, nc, g, lo, hi):
    """``g[j] = sum_{lo <= i < hi} x_i Tc[n - e_j + i]`` for the edges ``j = 0..nc`` (n the
    length of x): ``(H P)^T x`` before differencing, x zero outside ``[lo, hi)``
    (:func:`_precondition`). Four edges per pass (one load of x for four windows), each sum
    vectorised by LLVM (``JIT_SUMS``: 0.064-0.073 ns per cell and edge at n = 512-16384,
    against 0.17-0.21 for four scalar chains per edge without reassociation)."""
    n = x.shape[0]
    xs = x[lo:hi]
    m = hi - lo
    j = 0
    while j + 4 <= nc + 1:
        t0 = Tc[n - e[j] + lo : n - e[j] + hi]
        t1 = Tc[n - e[j + 1] + lo : n - e[j + 1] + hi]
        t2 = Tc[n - e[j + 2] + lo : n - e[j + 2] + hi]
        t3 = Tc[n - e[j + 3] + lo : n - e[j + 3] + hi]
        s0 = s1 = s2 = s3 = 0.0
        for i in range(m):
            xi = xs[i]
            s0 += xi * t0[i]
            s1 += xi * t1[i]
            s2 += xi * t2[i]
            s3 += xi * t3[i]
        g[j] = s0
        g[j + 1] = s1
        g[j + 2] = s2
        g[j + 3] = s3
        j += 4
    for k in range(j, nc + 1):
        t = Tc[n - e[k] + lo : n - e[k] + hi]
        s = 0.0
        for i in range(m):
            s += xs[i] * t[i]
        g[k] = s


@numba.njit(**JIT)
def _subtract_edge_combination(r, Tc, e, nc, c, lo, hi):
    """``r_i -= sum_j c_j Tc[n - e_j + i]`` over the edges ``j = 0..nc``, for ``lo <= i < hi``
    (n the length of r): ``H P`` times a coarse vector where it is needed
    (:func:`_precondition`). Four edges per pass (vectorised: one store per cell for four
    windows instead of four)."""
    n = r.shape[0]
    rs = r[lo:hi]
    m = hi - lo
    j = 0
    while j + 4 <= nc + 1:
        c0, c1, c2, c3 = c[j], c[j + 1], c[j + 2], c[j + 3]
        t0 = Tc[n - e[j] + lo : n - e[j] + hi]
        t1 = Tc[n - e[j + 1] + lo : n - e[j + 1] + hi]
        t2 = Tc[n - e[j + 2] + lo : n - e[j + 2] + hi]
        t3 = Tc[n - e[j + 3] + lo : n - e[j + 3] + hi]
        for i in range(m):
            rs[i] -= (c0 * t0[i] + c1 * t1[i]) + (c2 * t2[i] + c3 * t3[i])
        j += 4
    for k in range(j, nc + 1):
        ck = c[k]
        t = Tc[n - e[k] + lo : n - e[k] + hi]
        for i in range(m):
            rs[i] -= ck * t[i]


# ----------------------------------------------------------------------------------------------
# preconditioner set-up
# ----------------------------------------------------------------------------------------------
@numba.njit(**JIT)
def _first_last(D, limit):
    """First and one-past-last cell with ``D < limit`` (0, 0 if none)."""
    i0 = -1
    i1 = 0
    for i in range(D.shape[0]):
        if D[i] < limit:
            if i0 < 0:
                i0 = i
            i1 = i + 1
    if i0 < 0:
        return 0, 0
    return i0, i1


@numba.njit(**JIT)
def _live_span(minv):
    """First and one-past-last cell that is not frozen (``minv > 0``; 0, 0 if none)."""
    n = minv.shape[0]
    f0 = 0
    while f0 < n and not minv[f0] > 0.0:
        f0 += 1
    f1 = n
    while f1 > f0 and not minv[f1 - 1] > 0.0:
        f1 -= 1
    return (f0, f1) if f0 < f1 else (0, 0)


@numba.njit(**JIT)
def _chol_solve(L, nc, b):
    """``b <- (L L^T)^-1 b`` for the leading nc x nc block, in place. Forward by rows, each
    dot product in four chains; backward by columns (independent updates): 0.29 against
    0.36 us at nc = 16 for the two solves as serial dot products."""
    for i in range(nc):
        Li = L[i]
        i4 = i - i % 4
        s0 = s1 = s2 = s3 = 0.0
        for j in range(0, i4, 4):
            s0 += Li[j] * b[j]
            s1 += Li[j + 1] * b[j + 1]
            s2 += Li[j + 2] * b[j + 2]
            s3 += Li[j + 3] * b[j + 3]
        for j in range(i4, i):
            s0 += Li[j] * b[j]
        b[i] = (b[i] - ((s0 + s1) + (s2 + s3))) / L[i, i]
    for i in range(nc - 1, -1, -1):
        bi = b[i] / L[i, i]
        b[i] = bi
        Li = L[i]
        for j in range(i):
            b[j] -= Li[j] * bi


@numba.njit(**JIT)
def _aggregate_edges(D, K00, j0, j1, nc, e, steps):
    """Edges ``e[0] = j0 < e[1] < ... < e[nc] = j1`` of the coarse aggregates: equal shares of
    the density ``(1 - EDGE_SHARE) / (j1 - j0) + EDGE_SHARE |d ln(D + K00)| / total`` per cell,
    i.e. by width in the core (where D << K00 and ln(D + K00) is flat) and by decades of D
    across the contact edge. Over the 160 count scenes (5 hard surfaces, alpha 1e-4..1e3,
    n 256..16384, with ``fastline.contact.core.ETA_RES_SCALE``): 4446 convolutions with equal
    widths, 3898 with a share of 0.5, 3713 with 0.7 (mirror-symmetric); the worst scene (alpha 1e-2,
    n 16384) 109 -> 99.

    Mirror-symmetric: the left half of the edges counts the share from ``j0``, the right half
    from ``j1``, an even ``nc`` puts the middle edge at the centre, so a symmetric D gives a
    symmetric preconditioner (and p(x) = p(-x) to round-off). Needs ``j1 - j0 >= 4 nc``.
    ``steps``: work array of ``j1 - j0`` elements or more (``|d ln(D + K00)|`` between cells: one
    logarithm per cell, where the three passes took two or three per cell)."""
    width = j1 - j0
    Db = D[j0:j1]
    for i in range(width):
        steps[i] = math.log(Db[i] + K00)
    for i in range(width - 1):  # in place: the step of ln(D + K00) from cell j0 + i to the next
        steps[i] = abs(steps[i + 1] - steps[i])
    total = 0.0
    for i in range(width - 1):
        total += steps[i]
    flat = (1.0 - EDGE_SHARE) / width if total > 0.0 else 1.0 / width
    steep = EDGE_SHARE / total if total > 0.0 else 0.0
    half = nc // 2
    e[0] = j0
    e[nc] = j1
    if 2 * half == nc:
        e[half] = (j0 + j1) // 2
    k = 1  # edge b opens when the share of the cells left of b reaches k / nc (1e-9: ties)
    acc = flat
    for b in range(j0 + 1, j1):
        if k >= (nc + 1) // 2:
            break
        if acc * nc >= k - 1e-9:
            e[k] = b
            k += 1
        acc += flat + steep * steps[b - j0 - 1]
    k = 1  # the same from the right: edge b with the share right of b reaching k / nc
    acc = flat
    for b in range(j1 - 1, j0, -1):
        if k >= (nc + 1) // 2:
            break
        if acc * nc >= k - 1e-9:
            e[nc - k] = b
            k += 1
        acc += flat + steep * steps[b - j0 - 1]
    for m in range(nc - 1, 0, -1):  # at least one cell each
        e[m] = min(e[m], e[m + 1] - 1)
    for m in range(1, nc):
        e[m] = max(e[m], e[m - 1] + 1)


@numba.njit(**JIT)
def _coarse_matrices(D, scale, prefix, j0, j1, nc, e, Tc, U, L):
    """For the aggregates with edges ``e`` (:func:`_aggregate_edges`): the centred prefix
    sums ``Tc = T - T[n]`` (for ``H P`` products, :func:`_precondition`) and the Cholesky
    factor ``L`` of ``P^T H P`` with its constant mode penalised.

    ``(P^T K P)_km = sum_{i in k} sum_{j in m} khat_|i-j|`` is four values of ``U``, the prefix
    sums of ``Tc`` over the window ``[n - (j1 - j0), n + (j1 - j0)]`` that the aggregates span:
    O(n + nc^2) instead of O(n nc). (Centring keeps ``U`` of the size of the sums it yields.)
    """
    n = D.shape[0]
    t_mid = prefix[n]
    for j in range(2 * n):
        Tc[j] = prefix[j] - t_mid
    width = j1 - j0
    lo = n - width
    U[0] = 0.0
    for j in range(2 * width):
        U[j + 1] = U[j] + Tc[lo + j]
    for k in range(nc):
        for m in range(nc):
            s = (U[e[k + 1] - e[m] + width] - U[e[k] - e[m] + width]) - (
                U[e[k + 1] - e[m + 1] + width] - U[e[k] - e[m + 1] + width]
            )
            L[k, m] = scale * s
    for k in range(nc):
        dsum = 0.0
        for i in range(e[k], e[k + 1]):
            dsum += D[i]
        L[k, k] += dsum
    sizes = 0.0
    energy = 0.0
    diag_max = 0.0
    for k in range(nc):
        sizes += (e[k + 1] - e[k]) ** 2
        diag_max = max(diag_max, abs(L[k, k]))
        for m in range(k):
            L[k, m] = L[m, k] = 0.5 * (L[k, m] + L[m, k])
    for k in range(nc):
        for m in range(nc):
            energy += L[k, m] * (e[k + 1] - e[k]) * (e[m + 1] - e[m])
    big = (2.0 * abs(energy) / sizes + nc * diag_max) / sizes
    for k in range(nc):
        for m in range(nc):
            L[k, m] += big * (e[k + 1] - e[k]) * (e[m + 1] - e[m])
    # in-place lower Cholesky factor
    for j in range(nc):
        acc = L[j, j]
        for k in range(j):
            acc -= L[j, k] * L[j, k]
        L[j, j] = math.sqrt(acc)
        for i in range(j + 1, nc):
            acc = L[i, j]
            for k in range(j):
                acc -= L[i, k] * L[j, k]
            L[i, j] = acc / L[j, j]


@numba.njit(**JIT, inline="always")
def _smoother(D, K00, scale, strang, minv, S, cinv, span):
    """Set up the smoother (module docstring): ``minv = 1/(D + K00)``, 0 on frozen cells; on
    the loaded core ``[i0, i1)`` the scales ``S`` and ``cinv``, the spectrum of the inverse
    Strang circulant of ``K + d I`` (d the geometric mean of D there; the FFT's 1/(2n)
    included). Writes the live span ``f0, f1`` (:func:`_live_span`) and the core ``i0, i1``
    (0, 0: none) into ``span``."""
    n = D.shape[0]
    for i in range(n):
        minv[i] = 0.0 if D[i] > FROZEN_THETA * K00 else 1.0 / (D[i] + K00)
    f0, f1 = _live_span(minv)
    i0, i1 = _first_last(D, CORE_THETA * K00)
    if i1 - i0 < _CORE_MIN_CELLS:
        i0 = i1 = 0
    else:
        Dc = D[i0:i1]
        logsum = 0.0
        for i in range(i1 - i0):
            logsum += math.log(Dc[i])
        shift = math.exp(logsum / (i1 - i0))  # geometric mean of D on the core
        for i in range(i1 - i0):
            S[i] = math.sqrt((K00 + shift) / (K00 + Dc[i]))
        for k in range(n + 1):
            cinv[k] = 1.0 / ((scale * strang[k] + shift) * (2 * n))
    span[_F0] = f0
    span[_F1] = f1
    span[_I0] = i0
    span[_I1] = i1


@numba.njit(**JIT, inline="always")
def _coarse_level(D, K00, scale, prefix, nc_max, coarse, steps, span):
    """Set up the coarse level on the wide block (cells with ``D < WIDE_THETA K00``): at most
    ``nc_max`` aggregates, a quarter of its cells, none below two (:func:`_aggregate_edges`,
    :func:`_coarse_matrices`). ``coarse = (e, Tc, U, L)``, written: the aggregates' edges
    (cells, int64, nc_max + 1), the centred prefix sums of khat (dimensionless, 2n), work for
    their sums (2n + 1) and the Cholesky factor of ``P^T H P`` (nc_max x nc_max, m/Pa). Writes
    the number of aggregates into ``span``; ``steps``: work array of n elements."""
    e, Tc, U, L = coarse
    j0, j1 = _first_last(D, WIDE_THETA * K00)
    nc = min(nc_max, (j1 - j0) // 4)
    if nc < 2:
        nc = 0
    else:
        _aggregate_edges(D, K00, j0, j1, nc, e, steps)
        _coarse_matrices(D, scale, prefix, j0, j1, nc, e, Tc, U, L)
    span[_NC] = nc


@numba.njit(**JIT)
def _precondition(y, shift, out, prec, fft, bufs, circulant):
    """``out = R B R (y - shift)`` (two-level, module docstring; R zeroes the frozen cells);
    returns the number of FFT convolutions. ``circulant`` False: Jacobi on the core too (no
    FFT; the direction of the zero-load projection, :func:`_pcg_start`). ``prec``: the
    preconditioner (:class:`TwoLevel`: ``D, scale, pre = (minv, S, cinv, Tc), L, e, span, g``)
    as set up by :func:`_smoother` and :func:`_coarse_level`; the coarse products run over the
    live span ``[f0, f1)`` only (a third of the grid is frozen in the scenes of the count
    test). ``fft``: the plans (:func:`fastline._lib.fftw.acquire`); ``bufs = (a, c, work)``:
    the FFT buffers and a work array of 3n + _STRIP elements, ``work[2n:3n]`` holding ones."""
    D, scale, pre, L, e, span, g = prec
    minv, S, cinv, Tc = pre
    fr2c, fc2r, pf, pb = fft
    a, c, work = bufs
    f0, f1, i0, i1, nc = span[_F0], span[_F1], span[_I0], span[_I1], span[_NC]
    n = y.shape[0]
    tmp, r1, ones = work[:n], work[n : 2 * n], work[2 * n : 3 * n]
    g1, g2 = g[: nc + 1], g[nc + 1 :]
    for i in range(n):  # R y, and the coarse right-hand side P^T R y
        r1[i] = y[i] - shift if minv[i] > 0.0 else 0.0
    for k in range(nc):
        g1[k] = segment_sum(r1, ones, e[k], e[k + 1])
    if nc > 0:  # r1 = R y - H P c1: the edge windows of Tc, then the diagonal
        _chol_solve(L, nc, g1)
        prev = 0.0
        for j in range(nc + 1):  # jumps of scale * c1 across the edges
            cj = g1[j] if j < nc else 0.0
            g2[j] = scale * (cj - prev)
            prev = cj
        _subtract_edge_combination(r1, Tc, e, nc, g2, f0, f1)  # (R drops the rest)
        for k in range(nc):
            for i in range(e[k], e[k + 1]):
                r1[i] -= D[i] * g1[k]
    for i in range(n):  # smoother: Jacobi, and the scaled circulant on the core
        out[i] = minv[i] * r1[i]
    ffts = 0
    m = i1 - i0 if circulant else 0
    if m > 0:
        for i in range(m):
            tmp[i] = S[i] * r1[i0 + i] if minv[i0 + i] > 0.0 else 0.0
        convolve(tmp, m, cinv, fr2c, fc2r, pf, pb, a, c, tmp)
        for i in range(m):
            if minv[i0 + i] > 0.0:
                out[i0 + i] = S[i] * tmp[i]
        ffts = 1
    if nc > 0:  # c2 = (P^T H P)^-1 (H P)^T z1, out = z1 + P (c1 - c2)
        _edge_correlations(out, Tc, e, nc, g2, f0, f1)  # g2 = (H P)^T z1, then the diagonal
        for k in range(nc):
            g2[k] = scale * (g2[k] - g2[k + 1]) + segment_sum(D, out, e[k], e[k + 1])
        _chol_solve(L, nc, g2)
        for k in range(nc):
            d = g1[k] - g2[k]
            for i in range(e[k], e[k + 1]):
                if minv[i] > 0.0:
                    out[i] += d
    return ffts


# ----------------------------------------------------------------------------------------------
# projected preconditioned conjugate gradients
# ----------------------------------------------------------------------------------------------
def workspace_size(n: int) -> int:
    """float64 elements of the work space :func:`solve_newton_system` takes for n cells."""
    return aligned_size(2 * n) + (3 * n + min(n, _STRIP)) + (3 * n + 1) + (4 * n + 1) + 8 * n


@numba.njit(**JIT)
def solve_newton_system(fft, tables, op, D, w, rhs, settings, dp, ws):
    """Solve ``(D + K) dp + du1 = rhs``, ``sum(w dp) = 0`` (module docstring) into ``dp``.

    ``fft``: the FFT plans of length 2n (:func:`fastline._lib.fftw.acquire`); ``tables``: the
    kernel's :class:`KernelTables` ``(kspec, strang, prefix)``; ``op``: its
    :class:`KernelScale` ``(scale, diagonal)`` (m/Pa); ``D`` (m/Pa), ``w`` (cell weights, m),
    ``rhs`` (m): the system; ``settings``: :class:`CGSettings` ``(rtol, maxit, nc_max)``;
    ``dp`` (Pa): the solution, written.

    Stages: set up the smoother (:func:`_smoother`) and the coarse level
    (:func:`_coarse_level`), start projected PCG (:func:`_pcg_start`), iterate (:func:`_pcg`),
    finish (:func:`_pcg_finish`). Returns ``(du1, iterations, k_applications,
    circulant_solves)``. ``ws``: float64 work space of :func:`workspace_size` ``(n)`` elements,
    its contents irrelevant; every n-sized work array is a view into it, so that a caller that
    keeps it (one per thread) makes a solve allocation-free: fresh allocations of this size
    come from the operating system page by page, which took 35-45% of a solve at n >= 4096.
    (Plain loops and homogeneous tuples of arrays: every NumPy convenience costs compile time.)
    """
    kspec, strang, prefix = tables
    scale, K00 = op
    rtol, maxit, nc_max = settings
    n = D.shape[0]
    # -- the work space: FFT buffers, work, smoother, coarse level, PCG vectors ---------------
    a, c = aligned_views(ws, 2 * n)
    o = 4 * n + ALIGN_PAD  # aligned_size(2 n)
    work = ws[o : o + 3 * n + min(n, _STRIP)]
    o += 3 * n + min(n, _STRIP)
    minv, S, cinv = ws[o : o + n], ws[o + n : o + 2 * n], ws[o + 2 * n : o + 3 * n + 1]
    o += 3 * n + 1
    Tc, U = ws[o : o + 2 * n], ws[o + 2 * n : o + 4 * n + 1]
    o += 4 * n + 1
    cg = (
        ws[o + 0 * n : o + 1 * n],  # m1 = B~ 1, the zero-load projection's direction
        ws[o + 1 * n : o + 2 * n],  # z, the preconditioned residual
        ws[o + 2 * n : o + 3 * n],  # d, the search direction
        ws[o + 3 * n : o + 4 * n],  # H d
        ws[o + 4 * n : o + 5 * n],  # Jacobi weights of the stopping test
        ws[o + 5 * n : o + 6 * n],  # the residual
        ws[o + 6 * n : o + 7 * n],  # the best iterate
        ws[o + 7 * n : o + 8 * n],  # its residual
    )
    bufs, pre = (a, c, work), (minv, S, cinv, Tc)
    span, e = np.zeros(5, np.int64), np.empty(nc_max + 1, np.int64)
    L, g = np.empty((nc_max, nc_max)), np.empty(2 * nc_max + 2)
    for i in range(2 * n, 3 * n):
        work[i] = 1.0  # the ones segment
    # -- set-up, then PCG --------------------------------------------------------------------
    _smoother(D, K00, scale, strang, minv, S, cinv, span)
    coarse = (e, Tc, U, L)
    _coarse_level(D, K00, scale, prefix, nc_max, coarse, cg[0], span)  # (m1 free till PCG)
    prec = TwoLevel(D, scale, pre, L, e, span, g)
    s_m1, s_jac, r0, circ = _pcg_start(w, rhs, prec, fft, bufs, cg)
    its, kapps, circ_loop = _pcg(w, kspec, rtol, maxit, (s_m1, s_jac, r0), prec, fft, bufs, cg, dp)
    du1 = _pcg_finish(D, w, minv, s_m1, s_jac, work, cg, dp)
    return du1, its, kapps, circ + circ_loop


@numba.njit(**JIT, inline="always")
def _pcg_start(w, rhs, prec, fft, bufs, cg):
    """PCG's start from ``dp = 0``: ``m1``, the direction of the projection onto zero load
    (:func:`_projected_precondition`), the Jacobi weights, the residual, the first direction.
    ``prec`` (:class:`TwoLevel`), ``fft``, ``bufs`` as in :func:`_precondition`; ``cg``: the
    PCG vectors (:func:`solve_newton_system`). Returns ``(sum w m1, sum w minv, the first
    Jacobi residual norm, circulant solves)``."""
    D = prec.D
    m1, z, d, Hd, jac, res, best_dp, best_res = cg
    minv = prec.pre[0]
    work = bufs[2]
    n = D.shape[0]
    tmp, ones, acc = work[:n], work[2 * n : 3 * n], work[3 * n :]
    _precondition(ones, 0.0, m1, prec, fft, bufs, False)  # no FFT
    for i in range(n):
        jac[i] = w[i] * minv[i]  # 0 on frozen cells: their residual is theirs alone
        res[i] = rhs[i]
    s_m1 = _wdot(w, m1, ones, acc)
    s_jac = _wdot(w, minv, ones, acc)
    circ = _projected_precondition(res, z, w, m1, s_m1, prec, fft, bufs)
    for i in range(n):
        d[i] = z[i]
        best_dp[i] = 0.0
        best_res[i] = res[i]
    return s_m1, s_jac, _jacobi_norm(res, jac, s_jac, ones, tmp, acc), circ


@numba.njit(**JIT, inline="always")
def _projected_precondition(res, z, w, v, s_v, prec, fft, bufs):
    """``z = Pi B Pi* res`` (one FFT convolution; returns the count): B the two-level
    preconditioner (:func:`_precondition`), ``Pi = I - v w^T / s_v`` the projection onto zero
    load (``sum w z = 0``) along ``v``, ``Pi* = I - 1 (w v)^T / s_v`` its adjoint in the
    inner product ``sum w a b`` (``s_v = sum w v``).

    ``Pi B Pi*`` is symmetric and positive on residuals modulo constants (the load's
    multiplier) for any v with ``s_v > 0``, so v is free; ``v = B 1`` gives the B-orthogonal
    projection (``Pi B Pi* = Pi B``), the best one. Here ``v = B~ 1``, B~ the same two-level
    preconditioner with Jacobi on the core instead of the circulant (no FFT): on the Newton
    systems of the worst count scenes (n = 1024 alpha 1e-2 and 1e-1, n = 4096 and 16384 alpha
    1e-3 and 1e-2) every system took the same number of CG iterations as with ``B 1``
    (simulated, the Newton trajectory fixed), which cost one circulant solve per system. A
    constant v (``P B P``, the w-orthogonal projection) took ~1.5x the iterations.

    ``prec`` (:class:`TwoLevel`), ``fft``, ``bufs``: as in :func:`_precondition`."""
    n = res.shape[0]
    ones, acc = bufs[2][2 * n : 3 * n], bufs[2][3 * n :]
    shift = _wdot(w, v, res, acc) / s_v  # Pi* res = res - shift
    circ = _precondition(res, shift, z, prec, fft, bufs, True)
    lam = _wdot(w, z, ones, acc) / s_v
    for i in range(n):
        z[i] -= lam * v[i]
    return circ


@numba.njit(**JIT, inline="always")
def _pcg(w, kspec, rtol, maxit, start, prec, fft, bufs, cg, dp):
    """Projected PCG from :func:`_pcg_start` until the Jacobi-weighted norm of the residual
    fell by ``rtol`` (or stagnated, or ``maxit``); keeps the best iterate (by that norm) in
    ``cg``. ``start = (s_m1, s_jac, r0)`` as :func:`_pcg_start` returns them: ``sum w m1``
    and ``sum w minv`` (Pa), the first Jacobi residual norm (m Pa^1/2); ``prec``
    (:class:`TwoLevel`), ``fft``, ``bufs`` as in :func:`_precondition`. Returns
    ``(iterations, K products, circulant solves)``."""
    s_m1, s_jac, r0 = start
    D, scale = prec.D, prec.scale
    m1, z, d, Hd, jac, res, best_dp, best_res = cg
    fr2c, fc2r, pf, pb = fft
    a, c, work = bufs
    n = D.shape[0]
    tmp, ones, acc = work[:n], work[2 * n : 3 * n], work[3 * n :]
    for i in range(n):
        dp[i] = 0.0
    rz = _wdot(w, res, z, acc)
    # the best iterate so far (by Jacobi residual) is what is returned: if round-off breaks CG
    # down at a tight tolerance (the log kernel's constant mode has a large negative energy, so
    # a tiny leak off zero load makes <d, H d> negative), nothing worse than it comes back
    best, best_its, its, kapps, circ = r0, 0, 0, 0, 0
    while its < maxit and rz > 0.0:
        convolve(d, n, kspec, fr2c, fc2r, pf, pb, a, c, Hd)
        kapps += 1
        for i in range(n):
            Hd[i] = D[i] * d[i] + scale * Hd[i]
        dHd = _wdot(w, d, Hd, acc)
        if not dHd > 0.0:
            break
        alpha = rz / dHd
        for i in range(n):
            dp[i] += alpha * d[i]
            res[i] -= alpha * Hd[i]
        its += 1
        rn = _jacobi_norm(res, jac, s_jac, ones, tmp, acc)
        if rn < best:
            best, best_its = rn, its
            for i in range(n):
                best_dp[i] = dp[i]
                best_res[i] = res[i]
        if rn <= rtol * r0 or its - best_its >= _STAGNATION:
            break
        circ += _projected_precondition(res, z, w, m1, s_m1, prec, fft, bufs)
        rz_new = _wdot(w, res, z, acc)
        beta = rz_new / rz
        for i in range(n):
            d[i] = z[i] + beta * d[i]
        rz = rz_new
    return its, kapps, circ


@numba.njit(**JIT, inline="always")
def _pcg_finish(D, w, minv, s_m1, s_jac, work, cg, dp):
    """``dp`` = the best iterate, moved back onto zero load, with the Jacobi update on the
    frozen cells; returns du1, the multiplier (the Jacobi-weighted mean of the residual)."""
    m1, _, _, _, jac, _, best_dp, best_res = cg
    n = D.shape[0]
    ones, acc = work[2 * n : 3 * n], work[3 * n :]
    lam = _wdot(jac, best_res, ones, acc) / s_jac
    drift = _wdot(w, best_dp, ones, acc) / s_m1
    for i in range(n):
        dp[i] = best_dp[i] - drift * m1[i]
        if minv[i] == 0.0:
            dp[i] = (best_res[i] - lam) / D[i]
    return lam


def prefix_sums(khat: np.ndarray) -> np.ndarray:
    """``T`` with ``T[0] = 0`` and ``T[j+1] = sum_{l <= j} khat_|l - (n-1)|`` (length 2n)."""
    two_sided = np.concatenate([khat[:0:-1], khat])
    return np.concatenate([[0.0], np.cumsum(two_sided)])
