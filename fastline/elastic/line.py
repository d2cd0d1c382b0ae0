"""Plane-strain logarithmic-kernel operator for a line contact (docs/theory.md section 4).

Conventions
-----------
The nominal pressure is piecewise constant: ``p_j`` [Pa] acts on the cell of width ``dx`` [m]
centred on the grid point ``x_j = x_0 + j*dx`` (``j = 0 .. n-1``).  The elastic displacement
(gap increase, positive away from the cylinder) at the collocation point ``x_i`` is

    (K p)_i = -(2 / (pi E*)) * sum_j p_j * int_{cell j} ln(|x_i - x'| / dx) dx'      [m]

With ``g(t) = t ln|t| - t`` (``g(0) = 0``, an antiderivative of ``ln|t|``) the integral over a cell
is exact and

    K_ij = (dx / E*) * khat_{|i-j|},   khat_m = -(2/pi) * [g(m + 1/2) - g(m - 1/2)],

so ``K`` is a symmetric Toeplitz matrix (``khat`` is dimensionless).  ``khat_0 > 0``; ``khat_m``
decreases like ``-(2/pi) ln m`` for large ``m``.

Reference length
----------------
The length inside the logarithm is the cell width ``dx``.  Any other reference length ``L``
changes every displacement by the same constant

    -(2 / (pi E*)) * ln(dx / L) * sum_j p_j dx      [m]

(i.e. ``u_L = u_dx + shift``), proportional to the load per unit length ``f = sum_j p_j dx``
[N/m].  A uniform constant is absorbed by the rigid-body approach ``u1``, so the choice of
reference length never changes pressures; :func:`log_reference_shift` returns the constant, for
comparing ``u1`` between grids or with an analytic solution written with another length.  On
zero-sum pressure increments the shift vanishes, which is why ``K`` restricted to that subspace
(positive definite, see the tests) does not depend on ``L``.

Implementation
--------------
:meth:`LogKernelOperator.apply` computes the *linear* convolution ``K p`` with a zero-padded
real FFT of length ``2n`` (pyFFTW): the kernel is embedded in the circulant
``[k_0 .. k_{n-1}, 0, k_{n-1} .. k_1]`` whose spectrum is real (the embedding is symmetric).  The
dimensionless spectrum is built once per ``n`` and shared read-only by all operators; each
operator only scales the result by ``dx / E*``.  FFTW plans and their aligned buffers are built
once per ``n`` *per thread* (``threading.local``), so concurrent ``apply`` calls from different
threads never share a buffer.  Plans use ``FFTW_ESTIMATE`` and ``threads=1``; no global FFTW or
pyFFTW state is changed.
"""

from __future__ import annotations

import math
import os
import threading
from collections import OrderedDict

import numpy as np
from numpy.typing import ArrayLike

from fastline._lib import fftw as _fftw
from fastline._lib.native import compile_elsewhere
from fastline._lib.validate import finite_scalar, integer, positive
from fastline.elastic.convolution import KernelScale, KernelTables, apply_kernel, prefix_sums
from fastline.elastic.pcg import (
    CGSettings,
    solve_newton_system,
    system_types,
    workspace_size,
)

__all__ = [
    "LogKernelOperator",
    "influence_coefficients",
    "log_reference_shift",
    "log_reference_shift_unchecked",
    "coarse_aggregates",
    "compiled_tables",
    "compiled_workspace",
    "compile_system_elsewhere",
    "KHAT0",
]

_TWO_OVER_PI = 2.0 / math.pi
#: ``khat_0 = -(2/pi) (-ln 2 - 1)``, the first of :func:`influence_coefficients`
KHAT0 = -_TWO_OVER_PI * (-math.log(2.0) - 1.0)


def influence_coefficients(n: int) -> np.ndarray:
    """Dimensionless influence coefficients ``khat_0 .. khat_{n-1}`` of the log kernel.

    ``khat_m = -(2/pi) [g(m + 1/2) - g(m - 1/2)]`` with ``g(t) = t ln|t| - t``; the physical
    coefficients are ``K_ij = (dx / E*) khat_{|i-j|}`` (module docstring).

    Parameters
    ----------
    n : int
        Number of coefficients, ``n >= 1``.

    Returns
    -------
    ndarray, shape (n,)
        ``khat_m`` for ``m = 0 .. n-1`` (dimensionless).

    Notes
    -----
    The difference ``g(m + 1/2) - g(m - 1/2)`` is rewritten without the cancellation between two
    terms of size ``m ln m``:

    * ``m = 0``: ``2 g(1/2) = -ln 2 - 1``;
    * ``m >= 1``: ``[atanh(y)/y - 1] + ln m + (1/2) log1p(-y^2)`` with ``y = 1/(2m)``,

    whose relative error stays ~1e-15 for every ``m`` (no growth with ``m``).
    """
    n = integer("n", n, 1)
    d = np.empty(n, dtype=np.float64)
    d[0] = -math.log(2.0) - 1.0
    if n > 1:
        m = np.arange(1, n, dtype=np.float64)
        y = 0.5 / m
        d[1:] = (np.arctanh(y) / y - 1.0) + np.log(m) + 0.5 * np.log1p(-(y * y))
    return -_TWO_OVER_PI * d


def log_reference_shift(load: float, dx: float, E_star: float, length: float) -> float:
    """Uniform displacement change when the log reference length goes from ``dx`` to ``length``.

    Returns ``-(2 / (pi E*)) ln(dx / length) * load``: the displacement computed with
    ``ln(|x - x'| / length)`` equals the one from :class:`LogKernelOperator` (reference ``dx``)
    plus this constant.  The rigid approach ``u1`` absorbs it (``u1_length = u1_dx - shift``).

    Parameters
    ----------
    load : float
        Net load per unit length ``sum_j p_j dx`` [N/m] (any finite value).
    dx : float
        Cell width [m], > 0.
    E_star : float
        Effective modulus [Pa], > 0.
    length : float
        The other reference length [m], > 0.

    Returns
    -------
    float
        The constant shift [m].
    """
    load = finite_scalar("load", load)
    dx = positive("dx", dx, "m")
    E_star = positive("E_star", E_star, "Pa")
    length = positive("length", length, "m")
    return log_reference_shift_unchecked(load, dx, E_star, length)


def log_reference_shift_unchecked(load: float, dx: float, E_star: float, length: float) -> float:
    """:func:`log_reference_shift` of values already checked (a solver's own), no checks."""
    return -_TWO_OVER_PI / E_star * math.log(dx / length) * load


# --------------------------------------------------------------------------------------------
# Caches: the dimensionless kernel spectra (shared, read-only) and per-thread FFT plans, each
# bounded (least recently used out) so that a code that adapts n does not grow without limit.

#: grid sizes whose kernel spectra are kept (shared by all threads; ~24 n bytes each)
SPECTRA_KEPT = 32
#: grid sizes whose FFT plans and buffers each thread keeps (~60 n bytes each plus FFTW's plan)
PLANS_KEPT = 8

_spectrum_lock = threading.Lock()
_spectra: OrderedDict[int, np.ndarray] = OrderedDict()
_strang: OrderedDict[int, np.ndarray] = OrderedDict()
_real_spectra: OrderedDict[int, np.ndarray] = OrderedDict()
_prefixes: OrderedDict[int, np.ndarray] = OrderedDict()
_strang_writable: OrderedDict[int, np.ndarray] = OrderedDict()
_table_sets: OrderedDict[int, tuple[np.ndarray, np.ndarray, np.ndarray]] = OrderedDict()
_local = threading.local()


def _cached(store: OrderedDict, n: int, build, readonly: bool = True) -> np.ndarray:
    """``store[n]``, built by ``build(n)`` (and made read-only unless ``readonly`` is False:
    the compiled kernels' tables stay writable so that Numba compiles each kernel for one array
    type; the kernels never write to them); at most ``SPECTRA_KEPT`` kept."""
    with _spectrum_lock:
        spec = store.get(n)
        if spec is not None:
            store.move_to_end(n)
            return spec
    spec = build(n)  # outside the lock: two threads may both build it, both results are equal
    spec.flags.writeable = not readonly
    with _spectrum_lock:
        store[n] = spec
        store.move_to_end(n)
        while len(store) > SPECTRA_KEPT:
            store.popitem(last=False)
    return spec


def _build_kernel_spectrum(n: int) -> np.ndarray:
    khat = influence_coefficients(n)
    circ = np.zeros(2 * n, dtype=np.float64)
    circ[:n] = khat
    circ[n + 1 :] = khat[:0:-1]
    # symmetric embedding -> real spectrum (imaginary part is round-off only)
    return np.repeat(np.fft.rfft(circ).real / (2 * n), 2)


def _kernel_spectrum(n: int) -> np.ndarray:
    """Read-only rfft of the circulant embedding of ``khat``, pre-divided by ``2n``.

    Stored as float64 of length ``2(n+1)`` with every value repeated twice, so that it multiplies
    the float64 view of the complex spectrum (real and imaginary parts) in one real product.
    """
    return _cached(_spectra, n, _build_kernel_spectrum)


def _build_real_spectrum(n: int) -> np.ndarray:
    return _build_kernel_spectrum(n)[::2].copy()


def _build_prefix(n: int) -> np.ndarray:
    return prefix_sums(influence_coefficients(n))


def compiled_tables(n: int) -> KernelTables:
    """Real kernel spectrum / 2n (length n + 1), Strang spectrum and Toeplitz prefix sums
    (:class:`fastline.elastic.convolution.KernelTables`; kept together per n: one look-up per
    solve)."""
    with _spectrum_lock:
        tables = _table_sets.get(n)
        if tables is not None:
            _table_sets.move_to_end(n)
            return tables
    tables = KernelTables(
        _cached(_real_spectra, n, _build_real_spectrum, readonly=False),
        _cached(_strang_writable, n, _build_strang_spectrum, readonly=False),
        _cached(_prefixes, n, _build_prefix, readonly=False),
    )
    with _spectrum_lock:
        _table_sets[n] = tables
        while len(_table_sets) > SPECTRA_KEPT:
            _table_sets.popitem(last=False)
    return tables


def _build_strang_spectrum(n: int) -> np.ndarray:
    khat = influence_coefficients(n + 1)
    lam = np.fft.rfft(np.concatenate([khat, khat[-2:0:-1]])).real
    lam[0] = lam[1:].max()
    return lam


def _strang_spectrum(n: int) -> np.ndarray:
    """Eigenvalues (dimensionless, length ``n + 1``) of the Strang circulant of size ``2n`` built
    from ``khat_0 .. khat_n``; read-only, cached per ``n``.

    The log kernel's circulant has a large negative mean (``khat_m ~ -(2/pi) ln m``), i.e. a
    negative zero-frequency eigenvalue. Constants carry load, not shape, and the solver keeps
    the load fixed, so that eigenvalue is replaced by the largest of the others (``shift`` in
    :meth:`LogKernelOperator.circulant_inverse` keeps every eigenvalue positive). Unlike the
    zero-padded embedding used by :meth:`LogKernelOperator.apply` (whose spectrum alternates in
    sign at high frequency), this circulant is positive definite, so it can precondition CG.
    """
    return _cached(_strang, n, _build_strang_spectrum)


def compiled_workspace(size: int) -> np.ndarray:
    """This thread's float64 work space for the compiled solves, at least ``size`` elements
    (one buffer per thread, grown to the largest size asked: ~40 n floats, 5 MB at n = 16384).
    Kept between solves: a fresh allocation of this size comes from the operating system page
    by page, which took 35-45% of a solve at n >= 4096."""
    ws = getattr(_local, "compiled_ws", None)
    if ws is None or ws.size < size:
        ws = _local.compiled_ws = np.empty(size)
    return ws[:size]


#: the directory that holds the fastline package (for a second process to import the same one)
_PACKAGE_PARENT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
#: what a second process runs to compile the Newton systems' solver into the cache, for the
#: argument types of :func:`fastline.elastic.pcg.system_types` (its ``system_address``)
_SYSTEM_ELSEWHERE = """
import numpy as np
from fastline.elastic.convolution import KernelScale
from fastline.elastic.line import compiled_tables
from fastline.elastic.pcg import system_address
system_address((0, 0, 0, 0), compiled_tables(16), KernelScale(1.0, 1.0), np.empty(1))
"""


def compile_system_elsewhere() -> bool:
    """Start compiling the line contact's Newton-system solver (the largest of its kernels,
    ~40% of its compilation) in a second process, into the on-disk cache, if neither this
    process nor the cache has it (:func:`fastline._lib.native.compile_elsewhere`: more than one
    CPU, the cache on). Called when a line contact is set up, before its first kernels compile:
    the compiled Newton kernel calls the solver by address, so this process compiles the rest
    meanwhile and then loads the solver from the cache. Returns whether a process started."""
    if solve_newton_system.overloads:  # compiled or loaded in this process already
        return False
    fft, tables, op = (0, 0, 0, 0), compiled_tables(16), KernelScale(1.0, 1.0)
    argtypes = system_types(fft, tables, op, np.empty(1))
    return compile_elsewhere(solve_newton_system, argtypes, _SYSTEM_ELSEWHERE, _PACKAGE_PARENT)


def _workspace(n: int):
    """This thread's (input head, complex view, output head, fwd, bwd, plans) for size ``n``;
    each thread keeps the ``PLANS_KEPT`` most recently used sizes."""
    plans = getattr(_local, "plans", None)
    if plans is None:
        plans = _local.plans = OrderedDict()
    ws = plans.get(n)
    if ws is not None:
        plans.move_to_end(n)
        return ws
    import pyfftw  # here, not at import: pyfftw pulls in dask.array when dask is installed

    nfft = 2 * n
    rin = pyfftw.empty_aligned(nfft, dtype=np.float64)
    cbuf = pyfftw.empty_aligned(n + 1, dtype=np.complex128)
    rout = pyfftw.empty_aligned(nfft, dtype=np.float64)
    fwd = pyfftw.FFTW(
        rin,
        cbuf,
        direction="FFTW_FORWARD",
        flags=("FFTW_ESTIMATE",),  # r2c: FFTW preserves the input by default
        threads=1,
    )
    bwd = pyfftw.FFTW(
        cbuf,
        rout,
        direction="FFTW_BACKWARD",
        flags=("FFTW_ESTIMATE", "FFTW_DESTROY_INPUT"),
        threads=1,
    )
    rin[:] = 0.0  # the padding half rin[n:] stays zero for ever
    ws = (rin[:n], cbuf.view(np.float64), rout[:n], fwd.execute, bwd.execute, fwd, bwd)
    plans[n] = ws
    while len(plans) > PLANS_KEPT:
        plans.popitem(last=False)
    return ws


class LogKernelOperator:
    """Plane-strain log-kernel compliance ``K`` on a uniform grid (module docstring).

    Parameters
    ----------
    n : int
        Number of cells, ``n >= 2``.
    dx : float
        Cell width [m], > 0.
    E_star : float
        Effective plane-strain modulus ``E*`` [Pa], > 0.

    Attributes
    ----------
    n, dx, E_star
        As given (``dx``, ``E_star`` as floats).
    diagonal : float
        ``K_00 = (dx / E*) khat_0`` [m/Pa].
    convolutions : int
        Number of FFT convolutions of length ``2n`` made by this instance: :meth:`apply` calls
        and :meth:`CirculantInverse.apply` calls of its preconditioners (not synchronised: exact
        only if the instance is not used from several threads at once).
    circulant_solves : int
        How many of those were preconditioner solves.

    Notes
    -----
    ``apply`` is thread-safe: FFT plans and buffers are per thread and per ``n`` (built on first
    use in each thread, then reused by every operator of that size), the kernel spectrum per
    ``n`` is shared read-only.  ``apply`` does not check ``p`` for NaN/inf (hot path).
    """

    __slots__ = (
        "n",
        "dx",
        "E_star",
        "diagonal",
        "convolutions",
        "circulant_solves",
        "_scale",
    )

    def __init__(self, n: int, dx: float, E_star: float) -> None:
        self._set(integer("n", n, 2), positive("dx", dx, "m"), positive("E_star", E_star, "Pa"))

    @classmethod
    def _unchecked(cls, n: int, dx: float, E_star: float) -> LogKernelOperator:
        """An operator of values already checked (a solver's own grid): no validation, which
        was a tenth of the Python time of a warm line-contact solve."""
        op = cls.__new__(cls)
        op._set(n, dx, E_star)
        return op

    def _set(self, n: int, dx: float, E_star: float) -> None:
        self.n, self.dx, self.E_star = n, dx, E_star
        self._scale = dx / E_star
        self.diagonal = self._scale * KHAT0
        self.convolutions = 0
        self.circulant_solves = 0

    @property
    def kernel_scale(self) -> KernelScale:
        """``(dx / E*, K00)`` in m/Pa, as the compiled solvers take the operator's scale."""
        return KernelScale(self._scale, self.diagonal)

    def __repr__(self) -> str:
        return f"LogKernelOperator(n={self.n}, dx={self.dx!r}, E_star={self.E_star!r})"

    def apply(self, p: ArrayLike, out: np.ndarray | None = None) -> np.ndarray:
        """Return the displacement ``K p``.

        Parameters
        ----------
        p : array_like, shape (n,)
            Cell pressures [Pa] (any real values; not checked for NaN/inf).
        out : ndarray, shape (n,), float64, optional
            Destination; may be ``p`` itself.

        Returns
        -------
        ndarray, shape (n,)
            Displacements [m] (``out`` if given).
        """
        n = self.n
        if np.shape(p) != (n,):
            raise ValueError(f"p must have shape ({n},), got {np.shape(p)}")
        if _fftw.AVAILABLE:
            if out is None:
                out = np.empty(n)
            elif not isinstance(out, np.ndarray) or out.shape != (n,) or out.dtype != np.float64:
                raise ValueError(f"out must be a float64 ndarray of shape ({n},)")
            x = np.ascontiguousarray(p, dtype=np.float64)
            kspec = _cached(_real_spectra, n, _build_real_spectrum, readonly=False)
            x = x if x is not out else x.copy()
            fft = _fftw.acquire(2 * n)
            try:
                apply_kernel(x, kspec, self._scale, *fft, out)
            finally:
                _fftw.release(2 * n)
            self.convolutions += 1
            return out
        head_in, cview, head_out, fwd, bwd, _, _ = _workspace(n)
        np.copyto(head_in, p)
        fwd()
        np.multiply(cview, _kernel_spectrum(n), out=cview)
        bwd()
        if out is None:
            out = np.multiply(head_out, self._scale)
        else:
            if not isinstance(out, np.ndarray) or out.shape != (n,) or out.dtype != np.float64:
                raise ValueError(f"out must be a float64 ndarray of shape ({n},)")
            np.multiply(head_out, self._scale, out=out)
        self.convolutions += 1
        return out

    __call__ = apply

    def circulant_inverse(self, shift: float) -> CirculantInverse:
        """An approximate inverse of ``K + shift I`` for vectors supported on at most n cells.

        The block of ``K`` seen by such a vector is a symmetric Toeplitz matrix; it is replaced
        by the Strang circulant of size ``2n`` (the vector zero-padded), whose inverse is
        diagonal in Fourier space. Used as the preconditioner of the loaded core, where the
        elastic compliance dominates (:class:`BlockPreconditioner`).

        Parameters
        ----------
        shift : float
            Diagonal term [m/Pa], >= 0 (a representative value of the model's ``|du/dp|``).
        """
        shift = finite_scalar("shift", shift)
        if shift < 0.0:
            raise ValueError(f"shift must be >= 0 (allowed range [0, inf)), got {shift!r}")
        eig = self._scale * _strang_spectrum(self.n) + shift
        # the backward FFT is unnormalised: fold 1/(2n) into the inverse eigenvalues
        return CirculantInverse(self, np.repeat(1.0 / (eig * (2 * self.n)), 2))

    def solve_newton(
        self, D: np.ndarray, w: np.ndarray, rhs: np.ndarray, rtol: float, maxit: int
    ) -> tuple[np.ndarray, float, int] | None:
        """Solve the Newton system ``(D + K) dp + du1 = rhs``, ``sum(w dp) = 0`` in one compiled
        call (:mod:`fastline.elastic.pcg`: projected CG, two-level preconditioner, FFTs
        included). Returns ``dp, du1, iterations`` and counts the FFT convolutions; None if the
        compiled FFT path is not available (the caller then uses :meth:`preconditioner`)."""
        if not _fftw.AVAILABLE:
            return None
        tables = compiled_tables(self.n)
        dp = np.empty(self.n)
        N = 2 * self.n
        fft = _fftw.acquire(N)
        try:
            du1, its, kapps, circ = solve_newton_system(
                fft,
                tables,
                self.kernel_scale,
                D,
                w,
                rhs,
                CGSettings(rtol, maxit, coarse_aggregates(self.n)),
                dp,
                compiled_workspace(workspace_size(self.n)),
            )
        finally:
            _fftw.release(N)
        self.convolutions += kapps + circ
        self.circulant_solves += circ
        return dp, du1, its

    def preconditioner(self, D: np.ndarray) -> BlockPreconditioner:
        """An approximate inverse of ``D + K`` for the Newton-Krylov core
        (:mod:`fastline.contact.core`).

        Parameters
        ----------
        D : ndarray, shape (n,)
            The law's ``|du/dp|`` on each cell [m/Pa], > 0.
        """
        return BlockPreconditioner(self, D)

    def dense(self) -> np.ndarray:
        """The dense ``(n, n)`` matrix ``K`` [m/Pa]; O(n^2) memory and time, for tests/reference."""
        khat = influence_coefficients(self.n)
        idx = np.arange(self.n)
        return self._scale * khat[np.abs(idx[:, None] - idx[None, :])]


#: core block of the preconditioner: cells with |du/dp| < CORE_THETA * K00. Measured totals over
#: 20 hard scenes (4 surfaces x alpha 1e-4..0.1, n = 1024): 3 -> 1262, 6 -> 1277, 10 -> 1407
#: convolutions; at n = 8192, 10 did better (1738 vs 1873). 0.1 and 0.3 lost up to 2x at 1e-2.
CORE_THETA = 3.0
_CORE_MIN_CELLS = 8


def coarse_aggregates(n: int) -> int:
    """Aggregates of the compiled solver's coarse space (:mod:`fastline.elastic.pcg`) on n
    cells: 16 below n = 512, 32 below n = 4096, 64 below n = 16384, 128 from there (at most a
    quarter of the wide block's cells).

    The slowest modes of the preconditioned system sit at the rim of the loaded core, which
    widens in cells with n, so a finer coarse space pays more at larger n; its cost per
    application is O(nc n). Convolutions over the 40 count scenes per n (5 hard surfaces x 8
    alphas 1e-4..1e3) and CPU time of their warm solves, same run, two rounds:

    ======  ===================  ===================  ===================  ==================
    n       nc = 16              nc = 32              nc = 64              nc = 128
    ======  ===================  ===================  ===================  ==================
    256     664 (31), 8-9 ms     642 (29), 9 ms
    1024    800 (45), 17 ms      750 (39), 17 ms
    2048                         756 (41), 44 ms      716 (39), 42-57 ms
    4096    956 (59), 85-93 ms   864 (51), 85-90 ms   783 (45), 93 ms
    8192                         993 (71), 204-215    869 (55), 218-227    832 (51) [nc 96]
    16384   1290 (99), 598-642   1138 (81), 512-594   1041 (65), 514-527   920 (55), 576-579
    ======  ===================  ===================  ===================  ==================

    (worst scene in brackets; times in ms.) Measured after the coarse products were fused
    (four aggregate edges per pass); before, 32 aggregates cost more time than they saved.

    The count target (convolutions per solve <= 30, docs/performance.md) moved the steps down to 64
    from n = 4096 and 128 from n = 16384, trading time for count: over the same 40 scenes per n,
    today's solver (``python -m bench.count_grid``), 4096: 787 (47) -> 710 (41), 16384: 967 (61) ->
    847 (53); warm time of surface 1's 8 alphas, three interleaved rounds, +6% at 4096 (14.0 -> 14.9
    ms) and +9% at 16384 (83 -> 91 ms). 8192 keeps 64: 128 there gave 809 (49) -> 740 (43) for +25%
    time. The spectrum behind it is in :mod:`fastline.elastic.pcg`.

    Once the zero-load projection no longer cost a circulant solve per Newton step, the count
    had room below 30 at small n, and 16 aggregates pay there. Over the 40 scenes per n, today's
    solver, convolutions (worst) and summed best-of-5 CPU time of the warm solves, two
    interleaved rounds: n = 256: 498 (21), 4.9-5.3 ms with 32; 525 (25), 4.4-4.5 ms with 16;
    575 (28) with 8; 768 (41) with none. n = 512: 531 (26), 7.6 ms with 32; 577 (30),
    7.0-7.4 ms with 16 (kept at 32: the count at its limit). n = 1024: 575 (28), 14-18 ms with
    32; 658 (38), 15.7-15.8 ms with 16.
    """
    if n < 512:
        return 16
    if n < 4096:
        return 32
    return 64 if n < 16384 else 128


class BlockPreconditioner:
    """``M^-1 ~ (D + K)^-1``, block-diagonal (symmetric positive definite).

    * Loaded core, the cells from the first to the last with ``D < CORE_THETA * K00``: there
      the elastic compliance dominates and ``K`` restricted to the block is a Toeplitz matrix.
      It is replaced by the Strang circulant of ``K + median(D) I`` (size 2n, exact inverse by
      FFT; :meth:`LogKernelOperator.circulant_inverse`). This flattens the log kernel's spread
      of eigenvalues (~n on the core) that Jacobi leaves to CG.
    * Elsewhere, Jacobi ``1/(D + K00)``: where ``D >> K00`` the rows are nearly decoupled.

    Each application of the core block costs one FFT convolution (counted). Measured at n =
    1024 (surface 1): CG steps per Newton step fall from 13-25 to 3-8 for alpha <= 1e-2.
    """

    __slots__ = ("minv", "core", "cinv")

    def __init__(self, op: LogKernelOperator, D: np.ndarray) -> None:
        self.minv = 1.0 / (D + op.diagonal)
        core = np.flatnonzero(D < CORE_THETA * op.diagonal)
        self.core = None
        self.cinv = None
        if core.size >= _CORE_MIN_CELLS:
            i0, i1 = int(core[0]), int(core[-1]) + 1
            self.core = slice(i0, i1)
            self.cinv = op.circulant_inverse(float(np.median(D[i0:i1])))

    def __call__(self, y: np.ndarray) -> np.ndarray:
        out = self.minv * y
        if self.core is not None:
            self.cinv.apply(y[self.core], out[self.core])
        return out


class CirculantInverse:
    """``y -> C^{-1} y`` for the Strang circulant C of ``K + shift I`` (see
    :meth:`LogKernelOperator.circulant_inverse`); one FFT convolution per call, counted on the
    operator. Thread-safe like :meth:`LogKernelOperator.apply`."""

    __slots__ = ("_op", "_inv")

    def __init__(self, op: LogKernelOperator, inv_spec: np.ndarray) -> None:
        self._op = op
        self._inv = inv_spec

    def apply(self, y: np.ndarray, out: np.ndarray) -> np.ndarray:
        """Write ``(C^{-1} y)[:m]`` into ``out`` (both of length ``m <= n``) and return it."""
        m = y.shape[0]
        op = self._op
        head_in, cview, head_out, fwd, bwd, _, _ = _workspace(op.n)
        head_in[:m] = y
        head_in[m:] = 0.0
        fwd()
        np.multiply(cview, self._inv, out=cview)
        bwd()
        out[:] = head_out[:m]
        op.convolutions += 1
        op.circulant_solves += 1
        return out
