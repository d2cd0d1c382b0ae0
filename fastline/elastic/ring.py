"""Axisymmetric half-space operator for a point contact (docs/sphere.md, "The ring operator").

Conventions
-----------
The nominal pressure is piecewise constant on ``n`` cells of width ``dr`` [m] centred on
``r_j = j dr`` (``j = 0 .. n-1``): cell 0 is the disc ``r < dr/2``, cell ``j >= 1`` the ring
``(j - 1/2) dr < r < (j + 1/2) dr``. The cell edges are ``e_0 = 0`` and ``e_k = (k - 1/2) dr``,
the cell areas ``w_j = pi (e_{j+1}^2 - e_j^2)`` (``pi dr^2/4`` for the disc, ``2 pi r_j dr``
for a ring), so ``sum_j w_j p_j`` is the load in N exactly.

The elastic displacement of the half-space (gap increase, positive away from the sphere) under
an axisymmetric pressure is (Johnson, *Contact Mechanics*, 1985, eq. 3.96a, with ``1/E*``,
paper eq. 1, for the ``(1 - nu^2)/E`` of one solid: both surfaces together)

    u(r) = (4 / (pi E*)) int_0^inf p(rho) rho / (r + rho) K(k) drho,
    k = 2 sqrt(r rho) / (r + rho),

the azimuthal integral of Boussinesq's ``1 / (pi E* |x - x'|)``. The operator returns the
displacement *averaged over each cell* (area-weighted):

    (K p)_i = (1 / w_i) sum_j p_j int_{cell i} int_{cell j} dA dA' / (pi E* |x - x'|)      [m]

This is the Galerkin (energy-consistent) discretisation: ``w_i K_ij = w_j K_ji``, i.e.
``W K`` (``W = diag(w)``) is symmetric, as the conjugate gradients of :mod:`fastline.contact.core`
need, and positive definite (the kernel ``1/|x|`` has the positive Fourier transform
``2 pi / |q|``).

Exact influence coefficients
----------------------------
The double integral over two cells follows from the interaction of two concentric uniform
discs of radii ``a <= c``,

    Phi(a, c) = int_{|x|<a} int_{|x'|<c} dA dA' / |x - x'| = 8 pi c^3 G(a/c),
    G(k) = int_0^k t E(t) dt = [(1 + k^2) E(k) - (1 - k^2) K(k)] / 3,

because a disc of radius c under unit pressure displaces its surface by ``4 c E(r/c) / (pi E*)``
inside (Johnson 1985, section 3.4; E, K complete elliptic integrals of modulus k). ``G`` is
checked by differentiation: ``d/dk [(1 + k^2) E - (1 - k^2) K] = 3 k E``. A ring is a
difference of two discs, so

    w_i K_ij = [Phi(e_{i+1}, e_{j+1}) - Phi(e_{i+1}, e_j) - Phi(e_i, e_{j+1}) + Phi(e_i, e_j)]
               / (pi E*),

in closed form: no quadrature, and the logarithmic singularity of ``K(k)`` at ``rho = r`` is
integrated exactly. The coefficients scale as ``K_ij = (dr / E*) khat_ij`` with ``khat``
dimensionless, depending on the cell indices only, so ``khat`` is built once per ``n`` and
shared. Against a direct quadrature of the ring kernel (tests/naive.py) they agree to ~1e-13
in the first 64 cells; the four-term difference of disc interactions of size ~i^3 loses ~i^2
eps near the diagonal (2.7e-10 relative at cell 2000, 1.1e-9 at cell 4000, the largest grid),
and far from it, where the coefficients are small, ``G`` must be summed as its power series
below ``k^2 = 1/4`` (the elliptic form cancels like ``1/k^2``; with it the error at (2000, 0)
was 2.6e-6, with the series 2e-13).

The matrix is built by a compiled kernel straight into its one n x n array: the upper triangle
row by row from two rows of disc interactions, mirrored (``W khat`` is symmetric) and scaled.
Above ``k^2 = 1/4`` the kernel evaluates E and K by Gauss's arithmetic-geometric mean
(Abramowitz & Stegun 1964, 17.6), within 1.3e-15 of SciPy's ``ellipe``/``ellipkm1`` form for
``1 - k^2 > 1e-4``. A cold build at n = 4096 took 30 s and 1.2 GB of NumPy temporaries for
the (n + 1)^2 disc interactions (9x the matrix); it now takes the matrix's 8 n^2 bytes and
6 s at n = 4096 on a 2-core machine under a load average of 24 (docs/sphere.md, "Performance").

Application and preconditioner
------------------------------
``apply`` is a dense product with ``khat``, ``O(n^2)``, in a single-threaded compiled loop
(~30 us at the default n = 512, ~6 us at 256, ~130 us at 1024 on the 2-core test machine):
docs/sphere.md ("Performance") gives the figures and why no fast transform is used. The dense
matrix caps ``n`` (8 n^2 bytes: 134 MB at n = 4096; a point solve above 512 cells also keeps the
matrix of its nested start on n/4 cells, 1/16 more).

:class:`BalancingPreconditioner` approximates ``(D + K)^{-1}`` for the Newton-Krylov core by
Jacobi plus an exact solve on a coarse space of piecewise-constant blocks of cells, combined as a
balancing (two-level) preconditioner; see its docstring for the measured iteration counts.
"""

from __future__ import annotations

import threading
from collections import OrderedDict

import numba
import numpy as np
from numpy.typing import ArrayLike

from fastline._lib.jit import JIT
from fastline._lib.validate import integer, positive, real_array

__all__ = [
    "BalancingPreconditioner",
    "RingKernelOperator",
    "disc_interaction",
    "ring_areas",
    "ring_edges",
    "ring_influence_coefficients",
    "MAX_N",
]

#: largest n: the dense coefficient matrix takes 8 n^2 bytes (134 MB at 4096)
MAX_N = 4096
#: coefficient matrices kept (least recently used out); at most ~4 x 134 MB at MAX_N
MATRICES_KEPT = 4
#: k^2 below which G(k) is summed as a power series (terms fall at least 4x each)
_SERIES_BELOW = 0.25
_SERIES_TERMS = 30

_lock = threading.Lock()
_matrices: OrderedDict[int, np.ndarray] = OrderedDict()
_coarse: OrderedDict[tuple[int, int], tuple] = OrderedDict()


# ----------------------------------------------------------------------------------------------
# geometry of the cells (dimensionless: dr = 1)
# ----------------------------------------------------------------------------------------------
def ring_edges(n: int) -> np.ndarray:
    """Cell edges ``0, 1/2, 3/2, ..., n - 1/2`` in units of dr (length n + 1)."""
    n = integer("n", n, 1)
    e = np.empty(n + 1)
    e[0] = 0.0
    e[1:] = np.arange(n) + 0.5
    return e


def ring_areas(n: int) -> np.ndarray:
    """Cell areas in units of dr^2: ``pi/4`` for the central disc, ``2 pi j`` for ring j."""
    e = ring_edges(n)
    return np.pi * (e[1:] - e[:-1]) * (e[1:] + e[:-1])


# ----------------------------------------------------------------------------------------------
# exact influence coefficients
# ----------------------------------------------------------------------------------------------
def _g_series(m: np.ndarray) -> np.ndarray:
    """G(k) = (pi/4) m 2F1(-1/2, 1/2; 2; m), m = k^2 (accurate for m < 1/4)."""
    term = np.ones_like(m)
    total = np.ones_like(m)
    for j in range(_SERIES_TERMS):
        term = term * ((j - 0.5) * (j + 0.5) / ((j + 2.0) * (j + 1.0))) * m
        total += term
    return 0.25 * np.pi * m * total


def _g_elliptic(m: np.ndarray, m1: np.ndarray) -> np.ndarray:
    """G(k) = [(1 + m) E(m) - m1 K(m)] / 3, m = k^2, m1 = 1 - m given without cancellation."""
    from scipy.special import ellipe, ellipkm1  # here: SciPy's import costs ~0.2 s

    with np.errstate(invalid="ignore"):
        km1 = np.where(m1 > 0.0, m1 * ellipkm1(np.where(m1 > 0.0, m1, 1.0)), 0.0)
    return ((1.0 + m) * ellipe(m) - km1) / 3.0


def disc_interaction(a: ArrayLike, c: ArrayLike) -> np.ndarray:
    """``Phi(a, c) = int_{|x|<a} int_{|x'|<c} dA dA' / |x - x'|`` of two concentric discs.

    Parameters
    ----------
    a, c : array_like
        Disc radii (>= 0, any length unit L; broadcast together).

    Returns
    -------
    ndarray
        ``8 pi max^3 G(min/max)`` in L^3 (module docstring); 0 where a disc has radius 0.
        ``Phi(a, a) = 16 pi a^3 / 3``.
    """
    a, c = np.broadcast_arrays(real_array("a", a), real_array("c", c))
    return _phi(a, c)


def _phi(a: np.ndarray, c: np.ndarray) -> np.ndarray:
    """:func:`disc_interaction` of checked arrays of one shape: each entry is summed by the one
    form it needs (the series below ``k^2 = 1/4``, the elliptic form above), in place."""
    lo, hi = np.minimum(a, c), np.maximum(a, c)
    out = np.zeros(lo.shape)
    pos = hi > 0.0
    lo, hi = lo[pos], hi[pos]
    m = (lo / hi) ** 2
    small = m < _SERIES_BELOW
    g = np.empty_like(m)
    g[small] = _g_series(m[small])
    big = ~small
    lb, hb = lo[big], hi[big]
    g[big] = _g_elliptic(m[big], (hb - lb) * (hb + lb) / hb**2)  # 1 - m without cancellation
    out[pos] = 8.0 * np.pi * hi**3 * g
    return out


@numba.njit(**JIT)
def _g_scalar(lo, hi):
    """``G(lo / hi)`` of :func:`disc_interaction` for ``0 <= lo <= hi``, ``hi > 0``.

    Below ``k^2 = 1/4`` the power series (summed until its terms fall below 1e-17 of the
    sum); above it ``[(1 + m) E - m1 K] / 3`` with ``K = pi / (2 AGM(1, sqrt(m1)))`` and
    ``E = K [(1 + m1)/2 - sum_{j>=1} 2^(j-1) c_j^2]``, ``c_1 = m / (2 (1 + sqrt(m1)))``,
    ``c_{j+1} = c_j^2 / (4 a_{j+1})`` (Gauss's arithmetic-geometric mean; Abramowitz &
    Stegun 1964, 17.6): no difference of nearly equal numbers, ``m1 = 1 - m`` from the radii.
    """
    m = (lo / hi) ** 2
    if m < _SERIES_BELOW:
        term = 1.0
        total = 1.0
        for j in range(_SERIES_TERMS):
            term = term * ((j - 0.5) * (j + 0.5) / ((j + 2.0) * (j + 1.0))) * m
            total += term
            if abs(term) < 1e-17 * total:
                break
        return 0.25 * np.pi * m * total
    m1 = (hi - lo) * (hi + lo) / (hi * hi)
    if m1 <= 0.0:
        return 2.0 / 3.0  # E(1) = 1, m1 K -> 0
    a = 1.0
    b = np.sqrt(m1)
    c = m / (2.0 * (1.0 + b))
    a, b = 0.5 * (a + b), np.sqrt(a * b)
    power = 1.0
    tail = 0.0
    for _ in range(40):
        tail += power * c * c
        if c < 1e-17 * a:
            break
        a, b = 0.5 * (a + b), np.sqrt(a * b)
        c = c * c / (4.0 * a)
        power *= 2.0
    k = 0.5 * np.pi / a
    e = k * (0.5 * (1.0 + m1) - tail)
    return ((1.0 + m) * e - m1 * k) / 3.0


@numba.njit(**JIT)
def _interaction_rows(e, out):
    """``out[i, j] = Phi(e_i+1, e_j+1) - Phi(e_i+1, e_j) - Phi(e_i, e_j+1) + Phi(e_i, e_j)``
    for ``j >= i`` (the cell interactions times 1/(8 pi); the lower triangle is left alone),
    from two rows of disc interactions at a time."""
    n = e.size - 1
    prev = np.zeros(n + 1)  # Phi(e_0 = 0, .) = 0
    cur = np.zeros(n + 1)
    for i in range(n):
        ri = e[i + 1]
        for j in range(max(i - 1, 0), n + 1):
            lo, hi = min(ri, e[j]), max(ri, e[j])
            cur[j] = hi * hi * hi * _g_scalar(lo, hi)
        for j in range(i, n):
            out[i, j] = cur[j + 1] - cur[j] - prev[j + 1] + prev[j]
        prev, cur = cur, prev


@numba.njit(**JIT)
def _mirror_scaled(out, scale):
    """Copy the upper triangle of ``out`` onto the lower, then ``out[:, j] *= scale[j]``."""
    n = out.shape[0]
    for i in range(n):
        for j in range(i):
            out[i, j] = out[j, i]
    for i in range(n):
        for j in range(n):
            out[i, j] *= scale[j]


def _build_matrix_t(n: int) -> np.ndarray:
    """``khat`` transposed (C-contiguous), built in one n x n array and no other of that size.

    ``W khat`` is symmetric: ``khat^T = M diag(8 / w)`` with ``M`` the cell interactions over
    ``8 pi`` (:func:`_interaction_rows`, the upper triangle, mirrored); ``8 pi / (pi w)``.
    """
    out = np.empty((n, n))
    _interaction_rows(ring_edges(n), out)
    _mirror_scaled(out, 8.0 / ring_areas(n))
    return out


def _cached(store: OrderedDict, key, build):
    with _lock:
        hit = store.get(key)
        if hit is not None:
            store.move_to_end(key)
            return hit
    value = build()  # outside the lock: two threads may both build it, both results are equal
    with _lock:
        store[key] = value
        store.move_to_end(key)
        while len(store) > MATRICES_KEPT:
            store.popitem(last=False)
    return value


def _khat_t(n: int) -> np.ndarray:
    """``khat`` transposed, C-contiguous and read-only (the kernel reads its rows)."""

    def build():
        kt = _build_matrix_t(n)
        kt.flags.writeable = False
        return kt

    return _cached(_matrices, n, build)


def _khat(n: int) -> np.ndarray:
    return _khat_t(n).T


def ring_influence_coefficients(n: int) -> np.ndarray:
    """Dimensionless influence coefficients ``khat`` (n x n) of the ring operator.

    ``K_ij = (dr / E*) khat_ij`` is the displacement averaged over cell i per unit pressure on
    cell j (module docstring); ``ring_areas(n)[i] * khat[i, j]`` is symmetric. The matrix
    depends on n only through its size: the leading m x m block is ``khat`` for m cells.

    Parameters
    ----------
    n : int
        Number of cells, in [1, 4096].

    Returns
    -------
    ndarray, shape (n, n)
        Read-only view of the cached matrix (stored transposed, column-major here).
    """
    return _khat(integer("n", n, 1, MAX_N, " (the coefficient matrix is dense: 8 n^2 bytes)"))


# ----------------------------------------------------------------------------------------------
# compiled kernels. Single-threaded on purpose: a multi-threaded BLAS product made a solve at
# n = 512 take 95 ms instead of 6 ms on a busy 2-core machine (its threads wait for cores),
# and callers run solves in threads of their own. The loops are written as column updates
# (axpy), which vectorise without reassociating sums.
# ----------------------------------------------------------------------------------------------
@numba.njit(**JIT)
def _product(kt, p, scale, out):
    """``out = scale * kt.T @ p`` for a square C-contiguous ``kt``, four columns at a time."""
    n = kt.shape[0]
    for i in range(n):
        out[i] = 0.0
    j = 0
    while j + 3 < n:
        p0, p1, p2, p3 = p[j], p[j + 1], p[j + 2], p[j + 3]
        r0, r1, r2, r3 = kt[j], kt[j + 1], kt[j + 2], kt[j + 3]
        for i in range(n):
            out[i] += r0[i] * p0 + r1[i] * p1 + r2[i] * p2 + r3[i] * p3
        j += 4
    while j < n:
        pj, rj = p[j], kt[j]
        for i in range(n):
            out[i] += rj[i] * pj
        j += 1
    for i in range(n):
        out[i] *= scale
    return out


@numba.njit(**JIT)
def _balance(y, w, minv, ap, apt, chol, scale, b, out):
    """``out = Q y + (I - Q A) J (I - A Q) y`` (:class:`BalancingPreconditioner`).

    ``ap`` is ``A P`` (n x nc) and ``apt`` its transpose (nc x n), both C-contiguous;
    ``chol``, ``scale`` the coarse factor (:func:`_coarse_factor`); cells ``[k b, (k + 1) b)``
    form coarse block k.
    """
    n, nc = ap.shape
    c = np.zeros(nc)
    for i in range(n):
        c[i // b] += w[i] * y[i]
    cy = _coarse_solve(chol, scale, c)  # Ac^-1 P^T W y
    t = y.copy()  # J (y - A P cy)
    for k in range(nc):
        row, ck = apt[k], cy[k]
        for i in range(n):
            t[i] -= row[i] * ck
    for i in range(n):
        t[i] *= minv[i]
    d = np.zeros(nc)  # (A P)^T W t
    for i in range(n):
        row, wt = ap[i], w[i] * t[i]
        for k in range(nc):
            d[k] += row[k] * wt
    ct = _coarse_solve(chol, scale, d)
    for i in range(n):
        out[i] = t[i] + cy[i // b] - ct[i // b]
    return out


@numba.njit(**JIT)
def _coarse_factor(a):
    """Cholesky factor L of ``S a S`` (S = diag(a)^-1/2, so unit diagonal: the diagonal of the
    coarse matrix may span 300 decades) and S; L = 0 if not numerically positive definite."""
    m = a.shape[0]
    s = np.empty(m)
    for i in range(m):
        s[i] = 1.0 / np.sqrt(a[i, i])
    L = np.zeros((m, m))
    for j in range(m):
        d = a[j, j] * s[j] * s[j]
        for k in range(j):
            d -= L[j, k] * L[j, k]
        if not d > 0.0:
            return np.zeros((m, m)), s
        L[j, j] = np.sqrt(d)
        for i in range(j + 1, m):
            v = a[i, j] * s[i] * s[j]
            for k in range(j):
                v -= L[i, k] * L[j, k]
            L[i, j] = v / L[j, j]
    return L, s


@numba.njit(**JIT)
def _coarse_solve(L, s, c):
    """``a^-1 c`` from :func:`_coarse_factor` (0 if the factorisation failed)."""
    m = c.size
    if L[0, 0] == 0.0:
        return np.zeros(m)
    z = np.empty(m)
    for i in range(m):  # L z = S c
        v = s[i] * c[i]
        for k in range(i):
            v -= L[i, k] * z[k]
        z[i] = v / L[i, i]
    x = np.empty(m)
    for i in range(m - 1, -1, -1):  # L^T x = z
        v = z[i]
        for k in range(i + 1, m):
            v -= L[k, i] * x[k]
        x[i] = v / L[i, i]
    for i in range(m):
        x[i] *= s[i]
    return x


# ----------------------------------------------------------------------------------------------
# the operator
# ----------------------------------------------------------------------------------------------
class RingKernelOperator:
    """Cell-averaged half-space displacement under axisymmetric pressure (module docstring).

    Parameters
    ----------
    n : int
        Number of cells (central disc and rings), in [2, 4096].
    dr : float
        Cell width [m], > 0.
    E_star : float
        Effective modulus ``E*`` [Pa], > 0.

    Attributes
    ----------
    n, dr, E_star
        As given.
    weights : ndarray
        Cell areas [m^2] (the load carried by unit pressure on each cell).
    diagonal : ndarray
        ``K_ii`` [m/Pa].
    convolutions : int
        Operator-like applications made by this instance: dense products with K (``apply``)
        plus preconditioner applications (each O(n n_c), n_c <= ``COARSE_MAX``; counted so that
        the figure is comparable with the line contact's FFT convolutions). Not synchronised:
        exact only if the instance is not used from several threads at once.
    circulant_solves : int
        How many of those were preconditioner applications (the name is the core's protocol).

    Notes
    -----
    ``apply`` is thread-safe (the coefficient matrix is shared read-only) and does not check
    ``p`` for NaN/inf (hot path).
    """

    __slots__ = (
        "n",
        "dr",
        "E_star",
        "weights",
        "diagonal",
        "convolutions",
        "circulant_solves",
        "_scale",
        "_kt",
    )

    def __init__(self, n: int, dr: float, E_star: float) -> None:
        self.n = integer("n", n, 2, MAX_N, " (the coefficient matrix is dense: 8 n^2 bytes)")
        self.dr = positive("dr", dr, "m")
        self.E_star = positive("E_star", E_star, "Pa")
        self._scale = self.dr / self.E_star
        self._kt = _khat_t(self.n)
        self.weights = ring_areas(self.n) * (self.dr * self.dr)
        self.diagonal = self._scale * np.diagonal(self._kt).copy()
        self.convolutions = 0
        self.circulant_solves = 0

    def __repr__(self) -> str:
        return f"RingKernelOperator(n={self.n}, dr={self.dr!r}, E_star={self.E_star!r})"

    def apply(self, p: ArrayLike, out: np.ndarray | None = None) -> np.ndarray:
        """Return the cell-averaged displacement ``K p``.

        Parameters
        ----------
        p : array_like, shape (n,)
            Cell pressures [Pa] (any real values; not checked for NaN/inf).
        out : ndarray, shape (n,), float64, optional
            Destination (must not be ``p``).

        Returns
        -------
        ndarray, shape (n,)
            Displacements [m] (``out`` if given).
        """
        n = self.n
        if np.shape(p) != (n,):
            raise ValueError(f"p must have shape ({n},), got {np.shape(p)}")
        if out is None:
            out = np.empty(n)
        elif not isinstance(out, np.ndarray) or out.shape != (n,) or out.dtype != np.float64:
            raise ValueError(f"out must be a float64 ndarray of shape ({n},)")
        elif np.shares_memory(out, p):
            raise ValueError("out must not share memory with p")
        _product(self._kt, np.ascontiguousarray(p, dtype=np.float64), self._scale, out)
        self.convolutions += 1
        return out

    __call__ = apply

    def preconditioner(self, D: ArrayLike) -> BalancingPreconditioner:
        """An approximate inverse of ``D + K`` for the Newton-Krylov core
        (:mod:`fastline.contact.core`).

        Parameters
        ----------
        D : ndarray, shape (n,)
            The law's ``|du/dp|`` on each cell [m/Pa], >= 0.
        """
        return BalancingPreconditioner(self, D)

    def dense(self) -> np.ndarray:
        """The dense ``(n, n)`` matrix ``K`` [m/Pa] (a copy)."""
        return self._scale * self._kt.T


# ----------------------------------------------------------------------------------------------
# preconditioner
# ----------------------------------------------------------------------------------------------
#: largest coarse space: cells are grouped in blocks of ceil(n / COARSE_MAX) (at least
#: COARSE_BLOCK_MIN). Measured total CG iterations over alpha = 1e-4, 1e-3, 1e-2, 0.1 (paper
#: surface 1): see BalancingPreconditioner.
COARSE_MAX = 64
COARSE_BLOCK_MIN = 4


def coarse_block(n: int) -> int:
    """Cells per coarse block for n cells."""
    return max(COARSE_BLOCK_MIN, -(-n // COARSE_MAX))


def _coarse_parts(n: int, b: int) -> tuple:
    """(starts, KP, Ac): block starts, ``khat P`` (n x nc) and ``P^T W khat P`` (nc x nc), with
    P the piecewise-constant block indicator and W the dimensionless cell areas."""

    def build():
        starts = np.arange(0, n, b)
        kt = _khat_t(n)  # khat P from blocks of the stored transpose's contiguous rows (0.4 s
        kpt = np.empty((starts.size, n))  # at n = 4096; reduceat over the columns took 2.8 s)
        for k, s in enumerate(starts):
            np.add.reduce(kt[s : s + b], axis=0, out=kpt[k])
        kp = np.ascontiguousarray(kpt.T)
        ac = np.add.reduceat(ring_areas(n)[:, None] * kp, starts, axis=0)
        ac = 0.5 * (ac + ac.T)
        for arr in (starts, kp, ac):
            arr.flags.writeable = False
        return starts, kp, ac

    return _cached(_coarse, (n, b), build)


class BalancingPreconditioner:
    """``M ~ (D + K)^{-1}``: Jacobi plus an exact coarse solve, balanced (two-level).

    With ``A = D + K``, the block indicator ``P`` (n x nc: blocks of ``coarse_block(n)``
    consecutive cells), ``W = diag(weights)``, the coarse matrix ``Ac = P^T W A P`` and
    ``Q = P Ac^{-1} P^T W``,

        M = Q + (I - Q A) J (I - A Q),        J = diag(1 / (D + K_ii)).

    ``M`` is self-adjoint and positive definite in the inner product ``<a, b> = sum w a b``
    in which the core's conjugate gradients run (``A`` is). The coarse space takes the smooth
    modes, whose eigenvalues the first-kind operator K makes ~n times larger than the
    diagonal: Jacobi alone leaves them to CG (iterations growing like sqrt(n)); an additive
    coarse correction (``J + Q``) does not help here, since it adds to those large
    eigenvalues instead of removing them; the balancing form projects them out. ``A P`` is
    ``K P`` (built once per n) plus ``D P``, so an application costs O(n nc), no product with
    K.

    Measured at n = 256 (paper surface 1, alpha = 1e-4, 1e-3, 1e-2, 0.1; Newton steps / CG
    iterations): Jacobi alone 6/92, 9/87, 8/61, 6/23; this preconditioner with blocks of 4
    cells 7/38, 6/33, 6/29, 5/11. Per-step exact inverses of the loaded core's block
    ``(K + D)_cc`` reach 7-14 CG iterations but cost O(m^3) per step; a shifted core block
    (the line contact's choice) 9-42.
    """

    __slots__ = ("_op", "_w", "_minv", "_b", "_ap", "_apt", "_chol", "_scale")

    def __init__(self, op: RingKernelOperator, D: ArrayLike) -> None:
        D = np.ascontiguousarray(D, dtype=np.float64)
        n = op.n
        b = coarse_block(n)
        starts, kp, ac_hat = _coarse_parts(n, b)
        w = op.weights
        self._op, self._w, self._b = op, w, b
        self._minv = 1.0 / (D + op.diagonal)
        ap = np.ascontiguousarray(op._scale * kp)
        ap[np.arange(n), np.arange(n) // b] += D
        ac = (op._scale * op.dr * op.dr) * ac_hat
        ac[np.diag_indices_from(ac)] += np.add.reduceat(w * D, starts)
        self._ap = ap
        self._apt = np.ascontiguousarray(ap.T)
        self._chol, self._scale = _coarse_factor(ac)

    def __call__(self, y: np.ndarray) -> np.ndarray:
        out = np.empty_like(self._minv)
        _balance(y, self._w, self._minv, self._ap, self._apt, self._chol, self._scale, self._b, out)
        self._op.convolutions += 1
        self._op.circulant_solves += 1
        return out
