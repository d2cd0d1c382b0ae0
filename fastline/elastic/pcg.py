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

Spectrum against n (``python -m bench.spectrum``, surface 1, the 4th Newton system, rtol 1e-3,
with 32 aggregates below n = 8192 and 64 from there, the solver before the count target of
docs/performance.md).
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
alphas 1e-4..1e3 x n = 256..16384: 2976 with this module):

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

Kept for the count target: the projection onto zero load along ``B~ 1`` (the preconditioner without
its circulant, no FFT) in the symmetric form ``Pi B Pi*`` (:func:`_projected_precondition`) instead
of the B-orthogonal ``Pi B`` along ``B 1`` (one circulant solve per Newton system): each Newton step
now costs ``2 k + 1``. Over the 160 count scenes 2230 -> 1976 convolutions, per-n maxima 25 / 33 /
29 / 33 -> 21 / 28 / 27 / 29 (the same CG counts, system for system, in the simulation). Why the
kept ``B 1`` of the previous system (below) failed and this does not: a v other than ``B 1`` in the
one-sided form ``Pi B`` makes the preconditioner unsymmetric; in the two-sided form any v keeps it
symmetric. A random campaign (``python -m bench.campaign``, 240 scenes, alpha 1e-6..1e4, n
128..8192): 3920 -> 3452 convolutions, at most 77 -> 66, every scene converged (one at alpha 1.6e-6,
n 8192, had not); the hard contact (``python -m bench.hard``): 18 / 9 / 18 / 9 -> 16 / 8 / 16 / 8 at
n = 256 / 1024 / 4096 / 16384.

Kept for the count target: 64 aggregates from n = 4096, 128 from 16384
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
The line contact's Newton kernel calls :func:`solve_newton_system` through the address of its
compiled code (:func:`system_address`, :data:`call_system`; :mod:`fastline._lib.native`): it is
compiled once, on its own, and not linked into the Newton kernel and optimised there again (as a
Numba call would, and as inlining it did); the two compile independently, in two processes when
the cache holds neither. CPU of the first answer's compilations, empty cache, Numba's event API
(``python -m bench.compile_profile``, one run each at load 9-12): 25.5 s in one process with the
solver inlined; 10.5 s in the first process and 14.4 s in the second with it called by address.

Where the time goes (surface 1, alpha = 1e-2, per solve; a C clock around the stages, same
run as the version before the count target). n = 4096 (6 Newton systems, 57 FFT convolutions, 22 CG
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
from typing import TYPE_CHECKING, NamedTuple

import numba
import numpy as np

from fastline._lib.fftw import ALIGN_PAD, aligned_size, aligned_views
from fastline._lib.jit import JIT
from fastline._lib.native import caller, native_address
from fastline.elastic.convolution import convolve
from fastline.elastic.preconditioner import TwoLevel, _coarse_level, _precondition, _smoother

if TYPE_CHECKING:
    from fastline.elastic.convolution import KernelScale, KernelTables

#: interleaved partial sums of the reductions (strip length)
_STRIP = 64

__all__ = [
    "CGSettings",
    "workspace_size",
    "solve_newton_system",
    "system_address",
    "system_types",
    "call_system",
]


#: CG stops when its residual has not improved for this many iterations (round-off)
_STAGNATION = 20


class CGSettings(NamedTuple):
    """How far :func:`solve_newton_system` solves, and the size of its coarse level."""

    #: relative decrease of the Jacobi-weighted residual norm at which CG stops (dimensionless)
    rtol: float
    #: most CG iterations
    maxit: int
    #: most coarse aggregates (:func:`fastline.elastic.line.coarse_aggregates`)
    nc_max: int


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


# ----------------------------------------------------------------------------------------------
# projected preconditioned conjugate gradients
# ----------------------------------------------------------------------------------------------
def workspace_size(n: int) -> int:
    """float64 elements of the work space :func:`solve_newton_system` takes for n cells."""
    return aligned_size(2 * n) + (3 * n + min(n, _STRIP)) + (3 * n + 1) + (4 * n + 1) + 8 * n


@numba.njit(**JIT)
def solve_newton_system(
    fft: tuple,
    tables: KernelTables,
    op: KernelScale,
    D: np.ndarray,
    w: np.ndarray,
    rhs: np.ndarray,
    settings: CGSettings,
    dp: np.ndarray,
    ws: np.ndarray,
) -> tuple[float, int, int, int]:
    """Solve ``(D + K) dp + du1 = rhs``, ``sum(w dp) = 0`` (module docstring) into ``dp``.

    ``fft``: FFT plans of length 2n (:func:`fastline._lib.fftw.acquire`); ``tables``, ``op``:
    :class:`~fastline.elastic.convolution.KernelTables`, ``KernelScale`` (m/Pa); ``D`` (m/Pa),
    ``w`` (m), ``rhs`` (m): the system; ``settings``: :class:`CGSettings`; ``dp`` (Pa): the
    solution. Stages: :func:`_smoother`, :func:`_coarse_level`, :func:`_pcg_start`, :func:`_pcg`,
    :func:`_pcg_finish`. Returns ``(du1, iterations, k_applications, circulant_solves)``. ``ws``:
    work space of :func:`workspace_size` ``(n)`` elements, its contents irrelevant: every work
    array is a view into it (a caller keeps one per thread: fresh pages took 35-45% of a solve
    at n >= 4096); plain loops, homogeneous tuples of arrays (NumPy costs compile time)."""
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
    o2, o3 = nc_max * nc_max, nc_max * nc_max + 2 * nc_max + 2  # one allocation (one np.empty
    small = np.empty(o3 + nc_max + 6)  # to compile): L, g, then e and span as int64 views
    L, g, ints = small[:o2].reshape((nc_max, nc_max)), small[o2:o3], small[o3:].view(np.int64)
    e, span = ints[: nc_max + 1], ints[nc_max + 1 :]
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


#: what :func:`solve_newton_system` returns: ``(du1, iterations, k_applications,
#: circulant_solves)``
_SYSTEM_RETURN = numba.types.Tuple((numba.float64, numba.int64, numba.int64, numba.int64))
#: the work arrays a compiled caller passes (``D, rhs, dp, ws``: views into its work space)
_VECTOR = numba.types.Array(numba.float64, 1, "C")
#: argument positions of those arrays in :func:`solve_newton_system`
_VECTOR_ARGS = (3, 5, 7, 8)
#: argument types -> address of the compiled :func:`solve_newton_system` in this process
_addresses: dict = {}


def _check_system_args(argtypes: list) -> str:
    """Why a compiled caller's arguments do not fit :func:`system_address`'s kernel ("" if they
    do)."""
    wrong = [k for k in _VECTOR_ARGS if argtypes[k] != _VECTOR]
    if len(argtypes) != 9 or wrong:
        return f"call_system: arguments {wrong} must be {_VECTOR} (got {argtypes})"
    return ""


#: ``call_system(address, (fft, tables, op, D, w, rhs, settings, dp, ws))``: call
#: :func:`solve_newton_system` compiled at ``address`` (:func:`system_address`) from another
#: kernel; returns what it returns
call_system = caller(_SYSTEM_RETURN, _check_system_args)


def system_types(fft: tuple, tables: KernelTables, op: KernelScale, w: np.ndarray) -> tuple:
    """The Numba types of the arguments a compiled caller passes :func:`solve_newton_system`
    with these FFT plans, tables, kernel scale and weights (``D, rhs, dp, ws`` C-contiguous
    float64 views into its work space)."""
    vec = np.empty(1)
    return numba.typeof((fft, tables, op, vec, w, vec, CGSettings(0.0, 0, 0), vec, vec)).types


def system_address(fft: tuple, tables: KernelTables, op: KernelScale, w: np.ndarray) -> int:
    """The address of :func:`solve_newton_system` compiled (or loaded from the cache) for the
    arguments of :func:`system_types`, for :data:`call_system`.

    Called this way, the Newton system's solver is compiled once, on its own: the Newton
    kernel that calls it does not link its code in and optimise it again, and the two compile
    independently, in two processes when neither is cached (:mod:`fastline._lib.native`)."""
    flags = w.flags  # the key: what sets w's Numba type (cheaper than typing it)
    key = (w.dtype.char, w.ndim, flags.c_contiguous, flags.f_contiguous, flags.writeable, len(fft))
    address = _addresses.get(key)
    if address is None:
        argtypes = system_types(fft, tables, op, w)
        address = _addresses[key] = native_address(solve_newton_system, argtypes, _SYSTEM_RETURN)
    return address


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
    # circulant False (no FFT), as a run-time bool (n < 0): a constant would be typed as a
    # literal and compile a second _precondition
    _precondition(ones, 0.0, m1, prec, fft, bufs, n < 0)
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
    circ = _precondition(res, shift, z, prec, fft, bufs, n > 0)  # True, typed at run time
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
