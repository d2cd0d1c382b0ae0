"""The inverse Abel transform from a 1D to the isotropic 2D roughness spectrum (private).

For an isotropic surface (docs/theory.md section 2; Persson's conventions, SI)

    C1D(k) = 2 int_k^inf C(q) q / sqrt(q^2 - k^2) dq,
    C(q)   = -(1/pi) int_q^inf C1D'(k) / sqrt(k^2 - q^2) dk.

Representation of the data: between its points, ``ln C1D`` is the cubic Hermite polynomial in
``ln k`` through the two end values with slopes from the parabola through each point and its
neighbours, limited as Fritsch & Carlson (SIAM J. Numer. Anal. 17, 238 (1980)) so that the
interpolant never leaves the range of its two end values: noise in a measured C1D can tilt the
pieces, never make them overshoot, and ``C1D'`` is continuous. (Straight pieces in log-log,
i.e. power laws, would make ``C1D'`` jump at every point; their round-trip error on smooth
spectra converges like h^1.5 against h^2.5 here.)

The singularity: on each piece the substitution ``k = q cosh(theta)`` gives
``dk / sqrt(k^2 - q^2) = d theta`` exactly, so the piece contributes ``int C1D'(q cosh theta)
d theta`` with a smooth, bounded integrand even on the piece that starts at ``k = q``.
Gauss-Legendre with 8 nodes per part integrates it, the piece cut into
``ceil((|slope| + 1) d theta)`` parts (relative error per piece ~1e-12).

The tail: beyond the last point C1D may continue as ``C1D_n (k/k_n)^s`` (s < -1), which
contributes ``-(s C1D_n / (pi q)) (q/k_n)^s (1/2) B(q^2/k_n^2; (1 - s)/2, 1/2)`` in closed form
(B the incomplete beta function, from ``u = q^2/k^2``).
"""

from __future__ import annotations

import math

import numba
import numpy as np

from fastline._lib.jit import JIT

__all__ = ["inverse_abel", "hermite_slopes"]

_T8, _W8 = np.polynomial.legendre.leggauss(8)
_T8 = np.ascontiguousarray(0.5 * (_T8 + 1.0))
_W8 = np.ascontiguousarray(0.5 * _W8)
_LN2 = math.log(2.0)


def hermite_slopes(u: np.ndarray, v: np.ndarray) -> np.ndarray:
    """Node slopes ``dv/du``: the parabola through each point and its neighbours (one-sided at
    the ends), set to 0 at local extrema and capped at three times the smaller adjacent secant
    (Fritsch-Carlson), which keeps each Hermite piece monotone between its end values."""
    h = np.diff(u)
    d = np.diff(v) / h
    if u.size == 2:
        return np.array([d[0], d[0]])
    m = np.empty_like(v)
    m[1:-1] = (h[1:] * d[:-1] + h[:-1] * d[1:]) / (h[:-1] + h[1:])
    m[0] = ((2.0 * h[0] + h[1]) * d[0] - h[0] * d[1]) / (h[0] + h[1])
    m[-1] = ((2.0 * h[-1] + h[-2]) * d[-1] - h[-1] * d[-2]) / (h[-1] + h[-2])
    left = np.concatenate([[d[0]], d])
    right = np.concatenate([d, [d[-1]]])
    cap = 3.0 * np.minimum(np.abs(left), np.abs(right))
    return np.where(left * right > 0.0, np.sign(left) * np.minimum(np.abs(m), cap), 0.0)


@numba.njit(**JIT)
def _piece(lq, piece, ta, tb, t_ref, w_ref):
    """``int_ta^tb C1D'(q cosh theta) d theta`` on one Hermite piece (``t`` in [0, 1]:
    ``ln C1D = v0 + h t (m0 + t (c2 + t c3))``, ``ln k = u0 + h t``), ``lq = ln q``.
    ``piece = (u0, h, v0, m0, c2, c3)``: ln k (k in 1/m) at the piece's start and the piece's
    width in ln k, ln C1D (C1D in m^3) at its start and the cubic's coefficients (slopes d ln
    C1D / d ln k, dimensionless); ``t_ref, w_ref``: the Gauss rule on [0, 1]."""
    u0, h, v0, m0, c2, c3 = piece
    steep = max(abs(m0), abs(m0 + 2.0 * c2 + 3.0 * c3)) + 1.0
    n = max(1, int(math.ceil(steep * (tb - ta))))
    width = (tb - ta) / n
    acc = 0.0
    for part in range(n):
        a = ta + part * width
        for g in range(t_ref.shape[0]):
            theta = a + width * t_ref[g]
            lc = theta + math.log1p(math.exp(-2.0 * theta)) - _LN2  # ln cosh
            t = (lq + lc - u0) / h
            lnC = v0 + h * t * (m0 + t * (c2 + t * c3))
            slope = m0 + t * (2.0 * c2 + 3.0 * c3 * t)  # d ln C1D / d ln k
            acc += w_ref[g] * math.exp(lnC - lq - lc) * slope  # C1D' = C1D slope / k
    return acc * width


@numba.njit(**JIT)
def _inverse_kernel(u, v, m, out):
    """``-(1/pi) sum`` of the piece integrals above ``q = k_i``, for every i (no tail)."""
    n = u.shape[0]
    for i in range(n):
        lq = u[i]
        acc = 0.0
        ta = 0.0
        for j in range(i, n - 1):
            h = u[j + 1] - u[j]
            d = (v[j + 1] - v[j]) / h
            tb = math.acosh(math.exp(u[j + 1] - lq))
            c2 = 3.0 * d - 2.0 * m[j] - m[j + 1]
            c3 = m[j] + m[j + 1] - 2.0 * d
            acc += _piece(lq, (u[j], h, v[j], m[j], c2, c3), ta, tb, _T8, _W8)
            ta = tb
        out[i] = -acc / math.pi


def inverse_abel(k: np.ndarray, C1D: np.ndarray, tail_slope: float | None) -> np.ndarray:
    """C(q) at ``q = k_i`` (all i) from C1D > 0 at increasing points k (no checks).

    ``tail_slope``: C1D continues beyond ``k[-1]`` as ``C1D[-1] (k/k[-1])^tail_slope``
    (< -1), or None for ``C1D = 0`` there (a band-limited surface).
    """
    u = np.ascontiguousarray(np.log(k), dtype=np.float64)
    v = np.ascontiguousarray(np.log(C1D), dtype=np.float64)
    m = np.ascontiguousarray(hermite_slopes(u, v))
    out = np.empty_like(u)
    _inverse_kernel(u, v, m, out)
    if tail_slope is not None:
        from scipy.special import beta, betainc  # here: SciPy's import costs ~0.2 s

        s = float(tail_slope)
        a = 0.5 * (1.0 - s)
        ratio = np.exp(u - u[-1])  # q / k_n
        part = 0.5 * betainc(a, 0.5, ratio * ratio) * beta(a, 0.5)
        out -= s * C1D[-1] * ratio**s * part / (math.pi * np.exp(u))
    return out
