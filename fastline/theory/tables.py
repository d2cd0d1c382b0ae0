"""The compiled tables of Persson's theory and the kernels that build and read them.

Table T1 holds ``ln u`` on a uniform grid of ``v = ln p`` (quintic Hermite with the exact
derivatives of the quadrature), table T2 ``v`` as a cubic Hermite polynomial in u on cells cut
from the bits of the float64 (one ``exp`` and no ``log`` per lookup); both continue with the
theory's own asymptotes below and above their grids. The construction and the accuracy are in
:mod:`fastline.theory.persson` (its module docstring, "Numerics"), which builds the tables with
the kernels here; :func:`solver_law` is the form the line contact's compiled Newton reads, and
:data:`PerssonTables` with :func:`pressure_at` and :func:`separation_at` the form for users'
own compiled code (:meth:`fastline.PerssonTheory.jit`). Units: p in Pa, u in m.
"""

from __future__ import annotations

import math
from collections import namedtuple

import numba
import numpy as np

from fastline._lib.jit import JIT
from fastline.theory.special import _F, _beta_area, _F_area, _Y_area

__all__ = ["PerssonTables", "pressure_at", "separation_at", "solver_law"]

_TWO_OVER_SQRT_PI = 2.0 / math.sqrt(math.pi)


# ----------------------------------------------------------------------------------------------
# compiled kernels
# ----------------------------------------------------------------------------------------------
@numba.njit(**JIT)
def _separation_kernel(p, s, W, gamma, c1, c2, c3, out):
    """u(p_i) = sum_j W_j F(s_j p_i); s_j = w(q_j)/E* decreasing in j."""
    for i in range(p.shape[0]):
        acc = 0.0
        for j in range(s.shape[0] - 1, -1, -1):
            x = s[j] * p[i]
            if x > 27.3:  # F underflows; all earlier nodes have larger x
                break
            acc += W[j] * _F(max(x, 1e-300), gamma, c1, c2, c3)
        out[i] = acc


@numba.njit(**JIT)
def _lnu_nodes(v, s, W, gamma, b2, coef, L, L1, L2):
    """ln u and its first two v-derivatives at v = ln p (exact, from the quadrature); the
    bracket of F is ``gamma + b2 erf(x)^2``, ``coef = (c1, c2, c3)`` F's coefficient arrays
    (:func:`fastline.theory.special.f_coefficients`, dimensionless)."""
    c1, c2, c3 = coef
    b3 = b2
    for i in range(v.shape[0]):
        p = math.exp(v[i])
        u = 0.0
        d1 = 0.0
        d2 = 0.0
        for j in range(s.shape[0] - 1, -1, -1):
            x = s[j] * p
            if x > 27.3:
                break
            e = math.exp(-x * x)
            er = math.erf(x)
            b = gamma + b3 * er * er
            u += W[j] * _F(max(x, 1e-300), gamma, c1, c2, c3)
            d1 -= W[j] * b * e
            d2 += W[j] * e * (2.0 * x * x * b - 2.0 * b3 * er * _TWO_OVER_SQRT_PI * x * e)
        if u > 0.0:
            L[i] = math.log(u)
            L1[i] = d1 / u
            L2[i] = d2 / u - L1[i] * L1[i]
        else:  # u underflowed (deep full contact): ln u = -inf, no slope
            L[i] = -math.inf
            L1[i] = L2[i] = 0.0


@numba.njit(**JIT)
def _separation_area(p, s, W, at, out):
    """:func:`_separation_kernel` for a variant with the area correction (F of
    :mod:`fastline.theory.special`, tables ``at``)."""
    for i in range(p.shape[0]):
        acc = 0.0
        for j in range(s.shape[0] - 1, -1, -1):
            x = s[j] * p[i]
            if x > 27.3:
                break
            acc += W[j] * _F_area(max(x, 1e-300), at)
        out[i] = acc


@numba.njit(**JIT)
def _lnu_nodes_area(v, s, W, at, correction, L, L1, L2):
    """:func:`_lnu_nodes` for a variant with the area correction: ``du/dv = -sum W beta`` and
    ``d2u/dv2 = -sum W beta x d ln(beta)/dx`` with ``beta = -x F'(x)``;
    ``correction = (s0, s2, s4)`` of S."""
    s0, s2, s4 = correction
    for i in range(v.shape[0]):
        p = math.exp(v[i])
        u = 0.0
        d1 = 0.0
        d2 = 0.0
        for j in range(s.shape[0] - 1, -1, -1):
            x = s[j] * p
            if x > 27.3:
                break
            x = max(x, 1e-300)
            beta, dlog = _beta_area(x, at, s0, s2, s4)
            u += W[j] * _F_area(x, at)
            d1 -= W[j] * beta
            d2 -= W[j] * beta * dlog
        if u > 0.0:
            L[i] = math.log(u)
            L1[i] = d1 / u
            L2[i] = d2 / u - L1[i] * L1[i]
        else:  # u underflowed (deep full contact): ln u = -inf, no slope
            L[i] = -math.inf
            L1[i] = L2[i] = 0.0


@numba.njit(**JIT)
def _area_fraction_vec(x, at, out):
    """``erf(Y(x))``: the contact area of a variant with the area correction."""
    for i in range(x.shape[0]):
        out[i] = math.erf(_Y_area(x[i], at)) if x[i] > 0.0 else 0.0


@numba.njit(**JIT)
def _quintic(t, h, f0, a0, b0, f1, a1, b1):
    """Quintic Hermite on [0, 1] (t) with values f, slopes a, curvatures b at both ends
    (slopes and curvatures per unit of the original variable, cell width h).
    Returns the value and the derivative per unit of the original variable."""
    t2 = t * t
    t3 = t2 * t
    t4 = t3 * t
    t5 = t4 * t
    h00 = 1.0 - 10.0 * t3 + 15.0 * t4 - 6.0 * t5
    h10 = t - 6.0 * t3 + 8.0 * t4 - 3.0 * t5
    h20 = 0.5 * (t2 - 3.0 * t3 + 3.0 * t4 - t5)
    h01 = 10.0 * t3 - 15.0 * t4 + 6.0 * t5
    h11 = -4.0 * t3 + 7.0 * t4 - 3.0 * t5
    h21 = 0.5 * (t3 - 2.0 * t4 + t5)
    g00 = -30.0 * t2 + 60.0 * t3 - 30.0 * t4
    g10 = 1.0 - 18.0 * t2 + 32.0 * t3 - 15.0 * t4
    g20 = 0.5 * (2.0 * t - 9.0 * t2 + 12.0 * t3 - 5.0 * t4)
    g01 = -g00
    g11 = -12.0 * t2 + 28.0 * t3 - 15.0 * t4
    g21 = 0.5 * (3.0 * t2 - 8.0 * t3 + 5.0 * t4)
    hh = h * h
    val = f0 * h00 + h * a0 * h10 + hh * b0 * h20 + f1 * h01 + h * a1 * h11 + hh * b1 * h21
    der = (f0 * g00 + f1 * g01) / h + a0 * g10 + h * b0 * g20 + a1 * g11 + h * b1 * g21
    return val, der


@numba.njit(**JIT)
def _lnu_table(v, v0, h, L, L1, L2, u0, kappa):
    """ln u(v) and d ln u / dv from table T1 with its two extensions."""
    n = L.shape[0]
    if v <= v0:  # exponential law: u = u_lo + u0 (v0 - v)
        u = math.exp(L[0]) + u0 * (v0 - v)
        return math.log(u), -u0 / u
    vhi = v0 + (n - 1) * h
    if v >= vhi:  # near full contact: ln u = L_hi - k (p^2 - p_hi^2) - m (v - v_hi)
        k, m = kappa[0], kappa[1]
        p2 = math.exp(2.0 * v)
        return L[n - 1] - k * (p2 - math.exp(2.0 * vhi)) - m * (v - vhi), -2.0 * k * p2 - m
    z = (v - v0) / h
    k = min(int(z), n - 2)
    return _quintic(z - k, h, L[k], L1[k], L2[k], L[k + 1], L1[k + 1], L2[k + 1])


@numba.njit(**JIT)
def _separation_and_slope(v, v0, h, L, L1, L2, u0, kappa, u, dudv):
    """u and du/dv at v = ln p, vectorised, from the Hermite data of T1 and its extensions
    (:meth:`PerssonTheory.separation_table`; the solvers use :func:`solver_law`)."""
    for i in range(v.shape[0]):
        lu, d = _lnu_table(v[i], v0, h, L, L1, L2, u0, kappa)
        u[i] = math.exp(lu)
        dudv[i] = u[i] * d


#: entries of the solver form's parameter vector (:func:`_solver_form`)
_SF_V0, _SF_INV_H, _SF_U0, _SF_U_LO, _SF_V_HI, _SF_L_HI, _SF_K, _SF_M, _SF_P2_HI = range(9)


def _solver_form(t1: tuple) -> tuple[np.ndarray, np.ndarray]:
    """Table T1 in the form the solvers evaluate: ``(prm, Cf)``.

    Each cell's quintic Hermite (:func:`_quintic`) rewritten in Horner form,
    ``ln u = sum_j Cf[6 k + j] t^j`` with ``t = (v - v_k)/h`` in [0, 1]: the same polynomial
    (1e-14 apart, round-off), evaluated with 5 multiply-adds for ln u and 4 for its slope
    instead of the 12 basis polynomials. ``prm`` holds the grid (v0, 1/h), the exponential law
    below it (u0, u(v0)) and the near-full-contact form above it (v_hi, ln u(v_hi), k, m,
    p_hi^2); :func:`solver_law` evaluates it.
    """
    v0, h, L, L1, L2, u0, kappa = t1
    f0, a0, b0 = L[:-1], h * L1[:-1], h * h * L2[:-1]  # value, slope, curvature per unit t
    f1, a1, b1 = L[1:], h * L1[1:], h * h * L2[1:]
    r0 = f1 - (f0 + a0 + 0.5 * b0)  # what c3..c5 must add at t = 1 to value, slope, curvature
    r1 = a1 - (a0 + b0)
    r2 = b1 - b0
    Cf = np.empty((L.size - 1, 6))
    Cf[:, 0], Cf[:, 1], Cf[:, 2] = f0, a0, 0.5 * b0
    Cf[:, 3] = 10.0 * r0 - 4.0 * r1 + 0.5 * r2
    Cf[:, 4] = -15.0 * r0 + 7.0 * r1 - r2
    Cf[:, 5] = 6.0 * r0 - 3.0 * r1 + 0.5 * r2
    v_hi = v0 + (L.size - 1) * h
    prm = np.array(
        [v0, 1.0 / h, u0, math.exp(L[0]), v_hi, L[-1], kappa[0], kappa[1], math.exp(2.0 * v_hi)]
    )
    return prm, Cf.ravel()


@numba.njit(**JIT)
def solver_law(v: np.ndarray, prm: tuple, Cf: np.ndarray, u: np.ndarray, dudv: np.ndarray) -> None:
    """u and du/dv at v = ln p, vectorised, from the solver form of T1 (:func:`_solver_form`).

    The branches of :func:`_lnu_table` on the same thresholds: below the table the exponential
    law directly in u (no exp, no log), inside one Horner evaluation and one exp, above it the
    near-full-contact form (two exps; cells in deep full contact only).
    """
    v0, inv_h, u0, u_lo = prm[_SF_V0], prm[_SF_INV_H], prm[_SF_U0], prm[_SF_U_LO]
    v_hi = prm[_SF_V_HI]
    last = Cf.shape[0] // 6 - 1
    for i in range(v.shape[0]):
        x = v[i]
        if x <= v0:
            u[i] = u_lo + u0 * (v0 - x)
            dudv[i] = -u0
        elif x < v_hi:
            z = (x - v0) * inv_h
            k = min(int(z), last)
            t = z - k
            c = 6 * k
            c1, c2, c3, c4, c5 = Cf[c + 1], Cf[c + 2], Cf[c + 3], Cf[c + 4], Cf[c + 5]
            lu = Cf[c] + t * (c1 + t * (c2 + t * (c3 + t * (c4 + t * c5))))
            d = (c1 + t * (2.0 * c2 + t * (3.0 * c3 + t * (4.0 * c4 + t * 5.0 * c5)))) * inv_h
            e = math.exp(lu)
            u[i] = e
            dudv[i] = e * d
        else:
            u[i], dudv[i] = _near_full_contact(x, prm)


@numba.njit(**JIT)
def _near_full_contact(v, prm):
    """u and du/dv above table T1: ``ln u = L_hi - k (p^2 - p_hi^2) - m (v - v_hi)``."""
    k, m = prm[_SF_K], prm[_SF_M]
    p2 = math.exp(2.0 * v)
    e = math.exp(prm[_SF_L_HI] - k * (p2 - prm[_SF_P2_HI]) - m * (v - prm[_SF_V_HI]))
    return e, e * (-2.0 * k * p2 - m)


@numba.njit(**JIT)
def _build_inverse(e0, logm, ncell, t1, V, V1):
    """Table T2: v and dv/du at the cell ends ``u = 2^e (1 + j/2^m)``, by inverting T1.

    ln u decreases along the T1 nodes, so one pointer walks the T1 cells while the T2 nodes are
    visited in increasing u (from the last T1 node backwards); Newton finishes inside a cell.
    Nodes beyond the low-pressure end of T1 take the exponential law. ``t1 = (v0, h, L, L1,
    L2, u0, kappa)``: table T1 (:attr:`PerssonTheory._t1`: v = ln p of its first node and its
    step, ln u (u in m) and its first two v-derivatives at the nodes, the exponential law's u0
    in m, the continuation above). Written: ``V`` (ln p) and ``V1`` (dv/du, 1/m) at the
    ``ncell + 1`` cell ends.
    """
    v0, h, L, L1, L2, u0, kappa = t1
    n = L.shape[0]
    m = 1 << logm
    k = n - 1  # T1 cell [k-1, k] brackets ln u
    lu_prev = d_prev = math.nan
    for j in range(ncell + 1):
        un = math.ldexp(1.0 + (j % m) / m, e0 + j // m)
        lu_t = math.log(un)
        if lu_t >= L[0]:
            V[j] = v0 - (un - math.exp(L[0])) / u0
            V1[j] = -1.0 / u0
            continue
        while k > 1 and L[k - 1] < lu_t:
            k -= 1
        lo, hi = v0 + (k - 1) * h, v0 + k * h
        if math.isnan(d_prev):
            vk = 0.5 * (lo + hi)
        else:  # predictor: tangent from the previous node (error ~ (ln 2 / 2^m)^2)
            vk = min(max(V[j - 1] + (lu_t - lu_prev) / d_prev, lo), hi)
        for _ in range(30):
            lu, d = _lnu_table(vk, v0, h, L, L1, L2, u0, kappa)
            step = (lu - lu_t) / d
            vk = min(max(vk - step, lo), hi)
            if abs(step) < 1e-12:  # d is then exact to ~1e-12 as well
                break
        V[j] = vk
        V1[j] = 1.0 / (un * d)
        lu_prev, d_prev = lu_t, d


@numba.njit(**JIT)
def _invert_t1(lu_target, v_start, t1):
    """v with ln u(v) = lu_target from T1, by safeguarded Newton from v_start (upwards)."""
    v0, h, L, L1, L2, u0, kappa = t1
    v = v_start
    for _ in range(60):
        lu, d = _lnu_table(v, v0, h, L, L1, L2, u0, kappa)
        step = (lu - lu_target) / d
        v -= max(min(step, 1.0), -1.0)
        if abs(step) < 1e-13:
            break
    return v


@numba.njit(**JIT)
def _t2_lookup(b, u, Cf, base, shift, inv_u0, u_lo, v_lo):
    """ln p(u) from table T2 (cubic per cell, Horner) or the exponential-law extension at large
    u, for one u > 0 whose float64 bits are ``b``; NaN where u lies below the table (near full
    contact), where the caller inverts T1 (:func:`_invert_t1`).

    A positive float64 ``u = 2^e (1 + f)`` has the bits ``(e + 1023) << 52 | f 2^52``, so the
    top bits shifted down by ``shift = 52 - m`` count the cells ``(e, floor(f 2^m))`` in order;
    ``base`` is the count of the first cell, and the remaining bits give t = frac(f 2^m).
    (The rare T1 branch is kept out of this function: inside it, it slowed the loop 20x.)
    """
    k = (b >> shift) - base
    if k >= Cf.shape[0]:
        return v_lo - (u - u_lo) * inv_u0
    if k < 0:
        return math.nan
    t = (b & ((np.int64(1) << shift) - 1)) * (1.0 / float(np.int64(1) << shift))
    return Cf[k, 0] + t * (Cf[k, 1] + t * (Cf[k, 2] + t * Cf[k, 3]))


@numba.njit(**JIT)
def _log_pressure_kernel(u, Cf, base, logm, inv_u0, u_lo, v_lo, v_first, t1, out):
    """ln p(u) for a contiguous float64 array of u > 0: T2 (:func:`_t2_lookup`), T1 below it.

    It returns ln p, not p: NumPy's vectorised (SIMD) ``exp`` over the whole array afterwards
    is several times faster than a scalar ``exp`` per point in this loop (0.08 vs 0.44 ms on
    1e5 points on the 2-core development machine).
    """
    bits = u.view(np.int64)
    shift = 52 - logm
    for i in range(u.shape[0]):
        lp = _t2_lookup(bits[i], u[i], Cf, base, shift, inv_u0, u_lo, v_lo)
        if lp != lp:
            lp = _invert_t1(math.log(u[i]), v_first, t1)
        out[i] = lp


def _log_pressure_from_table(u: np.ndarray, t2) -> np.ndarray:
    """ln p(u) for a contiguous float64 array of u > 0 (no checks)."""
    out = np.empty_like(u)
    _log_pressure_kernel(u, *t2, out)
    return out


def _pressure_from_table(u: np.ndarray, t2) -> np.ndarray:
    """p(u) for a contiguous float64 array of u > 0 (no checks)."""
    out = _log_pressure_from_table(u, t2)
    return np.exp(out, out=out)


# ----------------------------------------------------------------------------------------------
# the tables as a namedtuple, for users' own @njit code (theory.jit())
# ----------------------------------------------------------------------------------------------
#: Tables of a :class:`PerssonTheory` for compiled code (see :meth:`PerssonTheory.jit`).
PerssonTables = namedtuple(
    "PerssonTables",
    "v0 h L L1 L2 u0 kappa Cf base logm inv_u0 u_lo v_lo v_first",
)


@numba.njit(**JIT)
def _float_bits(u):
    """The IEEE-754 bits of a normal float64 u > 0 as int64 (those of subnormals come out
    negative, which sends them to the T1 branch as in the array kernel)."""
    m, e = math.frexp(u)  # u = m 2^e, m in [0.5, 1)
    return (np.int64(e + 1022) << 52) | np.int64((2.0 * m - 1.0) * 4503599627370496.0)


@numba.njit(inline="always", **JIT)
def pressure_at(tables: PerssonTables, u: float) -> float:
    """Nominal pressure p(u) in Pa for one separation u in m, callable from ``@njit`` code.

    ``tables`` is ``theory.jit()``. Same tables and arithmetic as
    :meth:`PerssonTheory.pressure` (relative accuracy ``rtol``). Returns ``inf`` for
    ``u <= 0`` (the full-contact limit) and NaN for NaN.
    """
    if not u > 0.0:
        return math.inf if u <= 0.0 else math.nan
    t = tables
    lp = _t2_lookup(_float_bits(u), u, t.Cf, t.base, 52 - t.logm, t.inv_u0, t.u_lo, t.v_lo)
    if lp != lp:
        lp = _log_pressure_near_contact(tables, u)
    return math.exp(lp)


@numba.njit(**JIT)
def _log_pressure_near_contact(tables, u):
    """ln p below table T2 (near full contact) by inverting T1; the rare branch of
    :func:`pressure_at`, a function of its own so that the common path stays small and fast."""
    t = tables
    return _invert_t1(math.log(u), t.v_first, (t.v0, t.h, t.L, t.L1, t.L2, t.u0, t.kappa))


@numba.njit(inline="always", **JIT)
def separation_at(tables: PerssonTables, p: float) -> float:
    """Mean separation u(p) in m for one nominal pressure p in Pa, callable from ``@njit`` code.

    ``tables`` is ``theory.jit()``. From table T1 (as :meth:`PerssonTheory.separation_table`);
    relative accuracy ``rtol`` against the direct quadrature :meth:`PerssonTheory.separation`.
    Returns ``inf`` for ``p <= 0`` and NaN for NaN.
    """
    if not p > 0.0:
        return math.inf if p <= 0.0 else math.nan
    t = tables
    lu, _ = _lnu_table(math.log(p), t.v0, t.h, t.L, t.L1, t.L2, t.u0, t.kappa)
    return math.exp(lu)


@numba.njit(**JIT)
def _erf_vec(x, out):
    for i in range(x.shape[0]):
        out[i] = math.erf(x[i])
