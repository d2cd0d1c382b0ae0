"""The Persson q-integrals of a tabulated spectrum at a cost independent of the table size.

A :class:`~fastline.theory.spectra.TabulatedPSD` is a power law on each interval ``[q_i, q_i+1]``
(log-log interpolation). A measured periodogram has 10^4-10^5 such intervals with kinks of
order one at every node, so a quadrature that follows the kinks (panels per interval) costs
time in proportion to the table. This module builds instead a Gauss rule of about 300 nodes
whose error does not depend on the table at all.

The change of variable
----------------------
With ``A(q) = pi int_{q0}^q q'^3 C dq'`` and ``w = A^(-1/2)``, the separation integral is
(docs/theory.md, section 3)

    u(p) = sqrt(pi) int w F(w p / E*) q^2 C dq = sqrt(pi) int F(exp(-eta) p / E*) d nu(eta),

with ``eta = -ln w = ln(A) / 2`` and the positive measure ``d nu = w q^2 C dq``. Everything
rough about the table (noise, kinks) sits in ``nu``; the integrand ``F(exp(-eta) p/E*)`` is
one smooth universal function of ``eta``, for every table. (In ``ln q`` it would not be:
``A(q)`` of a noisy table is itself rough, a random walk of relative size ~1e-3.)

The rule
--------
1. *Exact interval moments* (:func:`interval_moments`, once per table). For ``dM = q^2 C dq``
   on one power-law interval the mass ``M``, the extent ``dA`` and the mean ``A_bar`` of A
   have closed forms. In the variable A the density ``dM/dA = 1/(pi q)`` varies by only the
   factor ``q_i/q_i+1`` across the interval, however steep C is, so the interval's
   contribution to ``int phi(eta) d nu`` is ``M [phi w](A_bar) + (dA^2/24) [phi w]''(A_bar)``
   up to terms of relative size ``(dA/A)^3 dt``: stored as ``eta_bar``, ``nu_bar`` and the
   spread ``r = (dA/A_bar)^2 / 96``.
2. *Bins* (:func:`_accumulate`). The eta axis is cut into panels, and each panel into equal
   bins. The table is split exactly at every bin edge (a split point on a power law is
   another node of the same power law), so each piece lies in one bin and has
   ``dA/A <= 2 x (bin width)``; the bin's first four moments in eta follow from the pieces to
   second order. From them, a two-point Gauss rule per bin (exact for cubics).
3. *Panels* (:func:`_panel_rules`). The two-point rules of a panel's bins form a discrete
   positive measure; its n-point Gauss rule (Stieltjes recurrence and Golub-Welsch
   eigenproblem) has positive weights, nodes inside the panel, and integrates polynomials of
   degree ``2n - 1`` against that measure exactly.

The error is therefore bounded by the error of polynomial approximation of F on the panels
(degree ``2n - 1``) and on the bins (degree 3), neither of which knows the table; tests hold
it against a per-interval reference on smooth, chi-squared-noisy and linearly spaced
periodogram tables of up to 10^5 points. The panel layout: equal panels over the eta range
carrying all but 1e-3 of nu, three times wider ones below it down to where 1e-13 of nu
remains (the rest is dropped), and panels graded geometrically (ratio 0.3) towards
``eta(q1)``, where the integrand piles up at high pressure (width ``1/(2 x1^2)`` in eta, with
``x1 = w(q1) p / E*`` up to 12).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numba
import numpy as np

from fastline._lib.jit import JIT

if TYPE_CHECKING:
    from fastline.theory.spectra import TabulatedPSD

__all__ = ["EtaRule", "interval_moments", "tabulated_quadrature"]

_TOP_WIDTH = 0.5  # eta width of the graded zone below eta(q1)
_TOP_RATIO = 0.3  # ratio of successive graded panels
_LOW_FACTOR = 3.0  # panels below the bulk are this many times wider
_BULK_MASS = 1e-3  # fraction of nu below the bulk panels
_TAIL_MASS = 1e-13  # fraction of nu dropped below the lowest panel
_SERIES = 0.02  # |z| below which expm1(z)/z is summed as a series (error < 2e-14)
_C2, _C3, _C4, _C5, _C6 = (1.0 / math.factorial(n) for n in range(2, 7))


@dataclass(frozen=True)
class EtaRule:
    """Sizes of the eta quadrature of a tabulated spectrum (see the module docstring)."""

    order: int  # Gauss nodes per bulk panel
    edge_order: int  # nodes per panel below the bulk and in the graded top zone
    width: float  # bulk panel width in eta = ln(A)/2
    bins: int  # two-point bins per panel
    top_levels: int  # graded panels towards eta(q1)


# ----------------------------------------------------------------------------------------------
# exact moments of one power-law piece
# ----------------------------------------------------------------------------------------------
@numba.njit(**JIT, inline="always")
def _expm1_over(z, ez):
    """``(exp(z) - 1) / z`` given ``ez = exp(z)`` (a ratio of table values, no exp needed)."""
    if abs(z) < _SERIES:
        return 1.0 + z * (_C2 + z * (_C3 + z * (_C4 + z * (_C5 + z * _C6))))
    return (ez - 1.0) / z


@numba.njit(**JIT, inline="always")
def _first_moment(z, ez):
    """``int_0^1 u exp(z u) du`` given ``ez = exp(z)``."""
    if abs(z) < _SERIES:
        return 0.5 + z * (1.0 / 3.0 + z * (1.0 / 8.0 + z * (1.0 / 30.0 + z / 144.0)))
    return (ez * (z - 1.0) + 1.0) / (z * z)


@numba.njit(**JIT)
def _power_piece(qa, Ca, rq, rc, dt, s):
    """Moments of ``C = Ca (q/qa)^s`` on ``[qa, qa rq]``, ``rc = C(end)/Ca``, ``dt = ln rq``.

    Returns ``int q C dq``, ``M = int q^2 C dq``, ``int q^3 C dq`` and ``theta``, the mean of
    ``(A - A_start)/dA`` under ``dM`` (1/2 for a uniform density in A).
    """
    b = (3.0 + s) * dt
    eps = b + dt
    eb = rc * rq * rq * rq  # exp(b)
    E1 = _expm1_over(b - dt, eb / rq)
    Eb = _expm1_over(b, eb)
    Ee = _expm1_over(eps, eb * rq)
    q2 = qa * qa
    m1 = Ca * q2 * dt * E1
    M = Ca * q2 * qa * dt * Eb
    m3 = Ca * q2 * q2 * dt * Ee
    if abs(eps) >= 1e-6:
        theta = (_expm1_over(eps + b, eb * eb * rq) - Eb) / (eps * Ee * Eb)
    else:  # A linear in ln q: the mean of u under exp(b u)
        theta = _first_moment(b, eb) / Eb
    if not 0.0 <= theta <= 1.0:  # overflow of exp(2 b) on absurdly steep pieces
        theta = 1.0 if b > 0.0 else 0.0
    return m1, M, m3, theta


@numba.njit(**JIT)
def _interval_kernel(table, cum1, cum3, eta, nu, spread, cum_nu):
    """Per interval i: the running ``int_q0^q_i q^k C dq`` (k = 1, 3; node i) and the
    ``eta_bar, nu_bar, spread`` of step 1 with the running sum of ``nu_bar``.

    ``table = (q, C, dt, slope, live)``: the log-log table, q (1/m) and C (m^4) at the nodes,
    per interval ``ln(q_{i+1}/q_i)``, the slope ``d ln C / d ln q`` and whether it carries
    mass (bool)."""
    q, C, dt, slope, live = table
    cum1[0] = cum3[0] = 0.0
    total = 0.0
    for i in range(q.shape[0] - 1):
        if live[i]:
            a, M, b, theta = _power_piece(
                q[i], C[i], q[i + 1] / q[i], C[i + 1] / C[i], dt[i], slope[i]
            )
            A = math.pi * cum3[i]
            dA = math.pi * b
            Abar = A + theta * dA
            eta[i] = 0.5 * math.log(Abar)
            nu[i] = M / math.sqrt(Abar)
            x = dA / Abar
            spread[i] = x * x * (1.0 / 96.0)
        else:
            a = b = nu[i] = spread[i] = 0.0
            eta[i] = -math.inf
        cum1[i + 1] = cum1[i] + a
        cum3[i + 1] = cum3[i] + b
        total += nu[i]
        cum_nu[i] = total


def interval_moments(
    q: np.ndarray, C: np.ndarray, dt: np.ndarray, slope: np.ndarray, live: np.ndarray
) -> tuple[np.ndarray, np.ndarray, tuple[np.ndarray, ...]]:
    """Exact per-interval moments of a log-log table (step 1 of the module docstring).

    Returns the cumulative moments ``int_q0^q_i q^k C dq`` at the nodes for k = 1, 3, and the
    measure data ``eta_bar, nu_bar, spread, cumsum(nu_bar)`` per interval (zero mass on dead
    intervals).
    """
    n = q.size
    out = [np.empty(n), np.empty(n)] + [np.empty(n - 1) for _ in range(4)]
    _interval_kernel((q, C, dt, slope, live), *out)
    return out[0], out[1], tuple(out[2:])


# ----------------------------------------------------------------------------------------------
# bins and panels
# ----------------------------------------------------------------------------------------------
@numba.njit(**JIT)
def _add(mu, edges, inv_hb, nbins, pan, e, v, r):
    """Second-order moments (bin units, about the bin centre) of one piece into its bin."""
    ih = inv_hb[pan]
    z = (e - edges[pan]) * ih
    k = min(max(int(z), 0), nbins - 1)
    d = z - k - 0.5
    d2 = d * d
    r1 = r * ih
    r2 = r1 * ih
    mu[pan, k, 0] += v * (1.0 + 3.0 * r)
    mu[pan, k, 1] += v * (d + 3.0 * r * d - 4.0 * r1)
    mu[pan, k, 2] += v * (d2 + 3.0 * r * d2 - 8.0 * r1 * d + 2.0 * r2)
    mu[pan, k, 3] += v * (d2 * d + 3.0 * r * d2 * d - 12.0 * r1 * d2 + 6.0 * r2 * d)


@numba.njit(**JIT)
def _accumulate(table, A, measure, S, edges, inv_hb, mu):
    """Bin moments of nu (step 2): whole intervals from their stored moments, intervals that
    hold a split point ``S`` (sorted, A at the bin edges) piece by piece.

    ``table = (q, C, dt, slope, live)`` as in :func:`_interval_kernel`; ``A``: ``pi int q^3 C
    dq`` at the nodes (dimensionless); ``measure = (eta, nu, spread)``: the per-interval
    ``eta_bar, nu_bar, spread`` of step 1 (:func:`interval_moments`)."""
    q, C, dt, slope, live = table
    eta, nu, spread = measure
    npan = edges.shape[0] - 1
    nbins = mu.shape[1]
    top = edges[npan]
    nS = S.shape[0]
    k = 0
    pan = 0
    for i in range(q.shape[0] - 1):
        if not live[i] or A[i + 1] <= S[0]:
            continue
        Aa, Ab = A[i], A[i + 1]
        while k < nS and S[k] <= Aa:
            k += 1
        if k > 0 and (k == nS or S[k] >= Ab):  # no split inside: stored moments
            e = eta[i]
            if e < top:
                while edges[pan + 1] <= e:
                    pan += 1
                _add(mu, edges, inv_hb, nbins, pan, e, nu[i], spread[i])
            continue
        s = slope[i]
        e4 = 4.0 + s
        scale = math.pi * C[i] * q[i] ** 4
        A_lo, lr_lo = Aa, 0.0
        while True:
            last = not (k < nS and S[k] < Ab)
            if last:
                A_hi, lr_hi = Ab, dt[i]
            else:  # invert A on the power law: A - Aa = scale (exp(e4 lr) - 1) / e4
                A_hi = S[k]
                X = (A_hi - Aa) / scale
                lr_hi = X if abs(e4) < 1e-12 else math.log1p(e4 * X) / e4
                k += 1
            if A_lo >= S[0] * (1.0 - 1e-14):  # below S[0]: the dropped tail
                d = lr_hi - lr_lo
                qa = q[i] * math.exp(lr_lo)
                Ca = C[i] * math.exp(s * lr_lo)
                _, M, b, theta = _power_piece(qa, Ca, math.exp(d), math.exp(s * d), d, s)
                dA = math.pi * b
                Abar = A_lo + theta * dA
                e = 0.5 * math.log(Abar)
                if e < top:
                    while edges[pan + 1] <= e:
                        pan += 1
                    x = dA / Abar
                    _add(mu, edges, inv_hb, nbins, pan, e, M / math.sqrt(Abar), x * x / 96.0)
            if last:
                break
            A_lo, lr_lo = A_hi, lr_hi


@numba.njit(**JIT)
def _bin_rules(mu, xs, ws):
    """Two-point Gauss rule of each bin from its four moments; nodes in panel units [-1, 1].

    The nodes are the roots of ``y^2 - (k3/v) y - v`` (y about the bin's mean, variance v,
    third central moment k3); both weights are positive. A bin of zero variance is one node.
    """
    nbins = mu.shape[0]
    c = 0
    for k in range(nbins):
        m0 = mu[k, 0]
        if m0 <= 0.0:
            continue
        m = mu[k, 1] / m0
        var = mu[k, 2] / m0 - m * m
        centre = (2.0 * k + 1.0) / nbins - 1.0
        unit = 2.0 / nbins
        if var <= 1e-14:
            xs[c] = centre + m * unit
            ws[c] = m0
            c += 1
            continue
        a = (mu[k, 3] / m0 - 3.0 * m * mu[k, 2] / m0 + 2.0 * m * m * m) / var
        root = math.sqrt(a * a + 4.0 * var)
        y1, y2 = 0.5 * (a - root), 0.5 * (a + root)
        xs[c] = centre + (m + y1) * unit
        ws[c] = m0 * y2 / (y2 - y1)
        xs[c + 1] = centre + (m + y2) * unit
        ws[c + 1] = -m0 * y1 / (y2 - y1)
        c += 2
    return c


@numba.njit(**JIT)
def _gauss_rule(x, w, n, nodes, weights):
    """n-point Gauss rule of the discrete positive measure ``sum w_i delta(x - x_i)``.

    Orthonormal Stieltjes (Lanczos) recurrence for the Jacobi matrix, then Golub-Welsch: the
    nodes are its eigenvalues, the weights the total mass times the squared first components
    of the eigenvectors. Stops early (fewer nodes) when the measure has fewer support points.
    Returns the number of nodes.
    """
    K = x.shape[0]
    total = 0.0
    for i in range(K):
        total += w[i]
    if K == 0 or total <= 0.0:
        return 0
    n = min(n, K)
    cur = np.full(K, 1.0 / math.sqrt(total))
    prev = np.zeros(K)
    alpha = np.zeros(n)
    beta = np.zeros(n)
    m = n
    for j in range(n):
        a = 0.0
        for i in range(K):
            a += w[i] * x[i] * cur[i] * cur[i]
        alpha[j] = a
        if j == n - 1:
            break
        norm = 0.0
        for i in range(K):
            prev[i] = (x[i] - a) * cur[i] - beta[j] * prev[i]
            norm += w[i] * prev[i] * prev[i]
        b = math.sqrt(norm)
        if b < 1e-12:
            m = j + 1
            break
        beta[j + 1] = b
        for i in range(K):
            t = prev[i] / b
            prev[i] = cur[i]
            cur[i] = t
    J = np.zeros((m, m))
    for j in range(m):
        J[j, j] = alpha[j]
        if j + 1 < m:
            J[j, j + 1] = J[j + 1, j] = beta[j + 1]
    ev, V = np.linalg.eigh(J)
    for j in range(m):
        nodes[j] = ev[j]
        weights[j] = total * V[0, j] * V[0, j]
    return m


@numba.njit(**JIT)
def _panel_rules(mu, edges, orders, eta_out, nu_out):
    """Step 3: each panel's Gauss rule from its bins' two-point rules. Returns the count."""
    npan, nbins = mu.shape[0], mu.shape[1]
    xs, ws = np.empty(2 * nbins), np.empty(2 * nbins)
    nmax = 0
    for p in range(npan):
        nmax = max(nmax, orders[p])
    nodes, weights = np.empty(nmax), np.empty(nmax)
    c = 0
    for p in range(npan):
        kb = _bin_rules(mu[p], xs, ws)
        m = _gauss_rule(xs[:kb], ws[:kb], orders[p], nodes, weights)
        half = 0.5 * (edges[p + 1] - edges[p])
        for j in range(m):
            eta_out[c] = edges[p] + (nodes[j] + 1.0) * half
            nu_out[c] = weights[j]
            c += 1
    return c


# ----------------------------------------------------------------------------------------------
# driver
# ----------------------------------------------------------------------------------------------
def _layout(eta, cum, eta1, rule: EtaRule):
    """Panel edges in eta and Gauss orders (module docstring), from the stored per-interval
    ``eta_bar`` and the cumulative ``nu_bar`` (which locate the bulk and the tail of nu)."""
    first = int(np.searchsorted(cum, 0.0, side="right"))  # the first live interval

    def eta_at(fraction):
        j = int(np.searchsorted(cum, fraction * cum[-1]))
        if j <= first:  # inside the first interval nu ~ exp(eta): an exponential tail
            return float(eta[first]) - 1.0 + math.log(max(fraction * cum[-1] / cum[first], 1e-300))
        return float(eta[j])

    top = eta1 - _TOP_WIDTH
    bulk_lo = min(eta_at(_BULK_MASS), top - rule.width)
    nb = math.ceil((top - bulk_lo) / rule.width - 1e-9)
    bulk = top - rule.width * np.arange(nb, 0, -1)
    wide = _LOW_FACTOR * rule.width
    nl = max(0, math.ceil((bulk[0] - eta_at(_TAIL_MASS)) / wide - 1e-9))
    low = bulk[0] - wide * np.arange(nl, 0, -1)
    graded = eta1 - _TOP_WIDTH * _TOP_RATIO ** np.arange(rule.top_levels + 1)
    edges = np.concatenate([low, bulk, graded, [eta1]])
    orders = np.full(edges.size - 1, rule.edge_order, dtype=np.int64)
    orders[nl : nl + nb] = rule.order
    return edges, orders


def _q_of_cumulative(psd, A):
    """q where the table's cumulative ``A(q)`` takes the values A (inverse of ``cumulative``)."""
    A_nodes = math.pi * psd._cum[3]
    i = np.clip(np.searchsorted(A_nodes, A, side="right") - 1, 0, psd.q.size - 2)
    e4 = 4.0 + psd._slope[i]
    X = (A - A_nodes[i]) / (math.pi * psd.C[i] * psd.q[i] ** 4)
    flat = np.abs(e4) < 1e-12
    lr = np.where(flat, X, np.log1p(np.where(flat, 0.0, e4) * X) / np.where(flat, 1.0, e4))
    return psd.q[i] * np.exp(lr)


def tabulated_quadrature(
    psd: TabulatedPSD, rule: EtaRule
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Nodes ``q_j``, weights ``dm_j`` of ``int f(q) q^2 C(q) dq`` and ``A(q_j)``, increasing q.

    The weights integrate ``f = w F(w p / E*)`` for every p to the accuracy the rule is sized
    for (module docstring); ``A`` is exact at the nodes (``w_j = exp(-eta_j)``).
    """
    eta, nu, spread, cum = psd._measure
    A_nodes = math.pi * psd._cum[3]
    eta1 = 0.5 * math.log(A_nodes[-1])
    edges, orders = _layout(eta, cum, eta1, rule)
    frac = np.arange(rule.bins) / rule.bins
    cuts = np.append((edges[:-1, None] + np.diff(edges)[:, None] * frac).ravel(), eta1)
    mu = np.zeros((edges.size - 1, rule.bins, 4))
    table = (psd.q, psd.C, psd._dt, psd._slope, psd._live)
    _accumulate(
        table, A_nodes, (eta, nu, spread), np.exp(2.0 * cuts), edges, rule.bins / np.diff(edges), mu
    )
    eta_j, nu_j = np.empty(int(orders.sum())), np.empty(int(orders.sum()))
    n = _panel_rules(mu, edges, orders, eta_j, nu_j)
    eta_j, nu_j = eta_j[:n], nu_j[:n]
    order = np.argsort(eta_j)
    eta_j, nu_j = eta_j[order], nu_j[order]
    A = np.exp(2.0 * eta_j)
    return _q_of_cumulative(psd, A), nu_j * np.exp(eta_j), A
