"""Slow, readable reference implementations used by the tests.

Nothing here is fast or clever on purpose: each function writes the equation of docs/theory.md out
with SciPy ``quad`` so that the compiled kernels of fastline have an independent check.
"""

from __future__ import annotations

import functools
import math

import numpy as np
from scipy.integrate import quad, solve_ivp
from scipy.optimize import brentq
from scipy.special import erf, exp1


def universal_F(x0: float, gamma: float, b2: float | None = None) -> float:
    """F(x0) = int_{x0}^inf (1/x)[gamma + b2 erf(x)^2] exp(-x^2) dx, b2 = 3(1-gamma) by default
    (the printed bracket of fastline.variants has b2 = 1 - gamma).

    The gamma part is E1(x0^2)/2 (SciPy); the erf^2 part by quad on [x0, inf).
    """
    part_b = quad(
        lambda x: erf(x) ** 2 * math.exp(-x * x) / x,
        x0,
        np.inf,
        epsabs=0.0,
        epsrel=1e-13,
        limit=200,
    )[0]
    b2 = 3.0 * (1.0 - gamma) if b2 is None else b2
    return gamma * exp1(x0 * x0) / 2.0 + b2 * part_b


def separation(psd, E_star: float, p: float, gamma: float = 0.45, epsrel: float = 1e-10, F=None):
    """u(p) by a direct double integral (docs/theory.md section 3), one pressure at a time.

    The outer integral over q is split at the kinks of C(q) and at every decade; on the first
    interval the substitution q = q0 + L t^2 removes the (q - q0)^(-1/2) of w(q). ``F`` is the
    universal function (a callable of x0; default :func:`universal_F` at gamma).
    """
    if F is None:
        F = lambda x0: universal_F(x0, gamma)  # noqa: E731

    def A(q):
        return float(psd.cumulative(q))

    def integrand_q(q, A_q):
        if A_q <= 0.0:
            return 0.0
        w = 1.0 / math.sqrt(A_q)
        x0 = w * p / E_star
        if x0 > 27.0:
            return 0.0
        return q * q * float(psd(q)) * w * F(x0)

    q0, q1 = psd.q0, psd.q1
    cuts = [q0] + [b for b in psd.breakpoints() if q0 < b < q1] + [q1]
    edges = []
    for a, b in zip(cuts[:-1], cuts[1:], strict=False):
        n = max(1, math.ceil(math.log10(b / a)))
        edges.extend(list(np.geomspace(a, b, n + 1))[:-1])
    edges.append(q1)
    total = 0.0
    # first interval: q = q0 + L t^2; A(q0 + L t^2) integrated from q0 to avoid cancellation
    L = edges[1] - q0

    def first(t):
        if t == 0.0:
            return 0.0
        d = L * t * t
        A_q = math.pi * quad(lambda r: (q0 + r) ** 3 * float(psd(q0 + r)), 0.0, d)[0]
        return integrand_q(q0 + d, A_q) * 2.0 * L * t

    total += quad(first, 0.0, 1.0, epsabs=0.0, epsrel=epsrel, limit=400)[0]
    for a, b in zip(edges[1:-1], edges[2:], strict=False):
        total += quad(
            lambda lq: integrand_q(math.exp(lq), A(math.exp(lq))) * math.exp(lq),
            math.log(a),
            math.log(b),
            epsabs=0.0,
            epsrel=epsrel,
            limit=200,
        )[0]
    return math.sqrt(math.pi) * total


def log_kernel_matrix(n: int, dx: float, E_star: float) -> np.ndarray:
    """Dense plane-strain log-kernel matrix, cell-integrated, reference length dx.

    K_ij = -(2/(pi E*)) int_{cell j} ln(|x_i - x'|/dx) dx', written with quad per distance.
    """
    coeff = np.empty(n)
    for m in range(n):
        points = [0.0] if m == 0 else None
        val = quad(
            lambda t: math.log(abs(t)) if t != 0.0 else 0.0,
            m - 0.5,
            m + 0.5,
            points=points,
            epsabs=1e-14,
            epsrel=1e-14,
            limit=200,
        )[0]
        coeff[m] = -(2.0 / math.pi) * val * dx / E_star
    idx = np.arange(n)
    return coeff[np.abs(idx[:, None] - idx[None, :])]


def line_contact_exponential(E_star, radius, load, u0, beta, n, half_width):
    """Line contact with the exponential law p = beta E* exp(-u/u0), dense matrix, scipy root.

    Unknowns v = ln p (n values) and u1; equations u0 ln(beta E*/p_i) = u1 + x_i^2/2R + (K p)_i
    and sum(p) dx = load. Returns x, p.
    """
    from scipy.optimize import root

    dx = 2.0 * half_width / n
    x = (np.arange(n) - 0.5 * (n - 1)) * dx
    K = log_kernel_matrix(n, dx, E_star)
    g = x * x / (2.0 * radius)
    s = math.sqrt(radius * u0)
    v0 = np.log(load / (s * math.sqrt(2.0 * math.pi))) - x * x / (2.0 * s * s)

    def fun(z):
        v, u1 = z[:-1], z[-1]
        p = np.exp(v)
        r = u0 * (math.log(beta * E_star) - v) - u1 - g - K @ p
        return np.concatenate([r / u0, [p.sum() * dx / load - 1.0]])

    z0 = np.concatenate([v0, [u0 * math.log(beta * E_star / (load / s))]])
    sol = root(fun, z0, method="hybr", tol=1e-13)
    if not sol.success:
        raise RuntimeError(sol.message)
    return x, np.exp(sol.x[:-1])


# ----------------------------------------------------------------------------------------------
# leakage (THEORY.md section 8): the interface at magnification zeta
# ----------------------------------------------------------------------------------------------
def _band_integral(psd, a: float, integrand, epsrel: float) -> float:
    """``int_a^{q1} integrand(q, b) dq`` with ``b = pi int_a^q q'^3 C dq'`` (the moment of the
    roughness not resolved at magnification a/q0).

    Split at the kinks of C(q) and at every decade, as :func:`separation`; on the first interval
    ``q = a + L t^2`` removes the ``(q - a)^(-1/2)`` of ``w = b^(-1/2)`` and b is integrated from
    a directly (no cancellation in ``A(q) - A(a)``).
    """
    q1 = psd.q1
    cuts = [a] + [c for c in psd.breakpoints() if a < c < q1] + [q1]
    edges = []
    for lo, hi in zip(cuts[:-1], cuts[1:], strict=False):
        n = max(1, math.ceil(math.log10(hi / lo)))
        edges.extend(list(np.geomspace(lo, hi, n + 1))[:-1])
    edges.append(q1)
    B_a = float(psd.cumulative(a))
    L = edges[1] - a

    def first(t):
        if t == 0.0:
            return 0.0
        d = L * t * t
        b = math.pi * quad(lambda r: (a + r) ** 3 * float(psd(a + r)), 0.0, d, epsrel=1e-13)[0]
        return integrand(a + d, b) * 2.0 * L * t

    total = quad(first, 0.0, 1.0, epsabs=0.0, epsrel=epsrel, limit=400)[0]
    for lo, hi in zip(edges[1:-1], edges[2:], strict=False):
        total += quad(
            lambda lq: (
                integrand(math.exp(lq), float(psd.cumulative(math.exp(lq))) - B_a) * math.exp(lq)
            ),
            math.log(lo),
            math.log(hi),
            epsabs=0.0,
            epsrel=epsrel,
            limit=200,
        )[0]
    return total


def _apparent(psd, E_star, a, p):
    """P(a) = erf(w(a) p/E*), w(a) = A(a)^(-1/2), and its derivative dP/da."""
    B_a = float(psd.cumulative(a))
    if B_a <= 0.0:
        return 1.0, 0.0
    w0 = 1.0 / math.sqrt(B_a)
    y = w0 * p / E_star
    dB = math.pi * a**3 * float(psd(a))
    dP = -(1.0 / math.sqrt(math.pi)) * y * math.exp(-y * y) * w0 * w0 * dB
    return float(erf(y)), dP


def mean_separation(psd, E_star, zeta, p, gamma=0.45, epsrel=1e-10, b2=None):
    """u_bar(zeta, p) of THEORY.md 8.2 written out with quad: the Yang-Persson separation of the
    roughness from zeta q0 to q1 under the pressure p / P(zeta) (bracket gamma + b2 erf^2)."""
    a = zeta * psd.q0
    P, _ = _apparent(psd, E_star, a, p)
    s = p / (E_star * P)

    def integrand(q, b):
        if b <= 0.0:
            return 0.0
        w = 1.0 / math.sqrt(b)
        x = w * s
        if x > 27.0:
            return 0.0
        return q * q * float(psd(q)) * w * universal_F(x, gamma, b2)

    return math.sqrt(math.pi) * _band_integral(psd, a, integrand, epsrel)


def edge_separation(psd, E_star, zeta, p, gamma=0.45, epsrel=1e-10, b2=None):
    """u1(zeta) = u_bar + u_bar'(zeta) P(zeta)/P'(zeta) (THEORY.md 8.2), zeta > 1.

    The derivative is taken under the integral in the q variable (an independent route from the
    package's moment variable): with ``w = (A(q) - A(a))^(-1/2)``, ``x = w s``,
    ``s = p/(E* P(a))`` and ``beta(x) = gamma + 3 (1 - gamma) erf(x)^2`` (so ``x F'(x) =
    -beta e^(-x^2)``),

        du_bar/da = sqrt(pi) int q^2 C [w^3 A'(a)/2 (F - beta e^(-x^2))
                                         - w beta e^(-x^2) d ln s/da].
    """
    a = zeta * psd.q0
    P, dP = _apparent(psd, E_star, a, p)
    s = p / (E_star * P)
    dB = math.pi * a**3 * float(psd(a))
    dlns = -dP / P

    def integrand(q, b):
        if b <= 0.0:
            return 0.0
        w = 1.0 / math.sqrt(b)
        x = w * s
        if x > 27.0:
            return 0.0
        bracket_b2 = 3.0 * (1.0 - gamma) if b2 is None else b2
        e = math.exp(-x * x) * (gamma + bracket_b2 * erf(x) ** 2)
        F = universal_F(x, gamma, b2)
        return q * q * float(psd(q)) * (0.5 * w**3 * dB * (F - e) - w * e * dlns)

    du = math.sqrt(math.pi) * _band_integral(psd, a, integrand, epsrel)
    return mean_separation(psd, E_star, zeta, p, gamma, epsrel, b2) + du * P / dP


# ---- boundary-element references (fastline.bem) -----------------------------------------------
def boussinesq_cell(X: float, Y: float, dx: float, dy: float, E_star: float) -> float:
    """Displacement at (X, Y) of unit pressure on the cell |x| <= dx/2, |y| <= dy/2, by quadrature.

    u = (1/(pi E*)) int_cell dA / r (Boussinesq). The cell is cut into the four rectangles that
    have a corner at the field point; each is integrated in polar coordinates about that corner,
    int_0^{pi/2} rho_max(theta) d theta, so the 1/r singularity never meets the quadrature.
    """

    def corner_rect(a: float, b: float) -> float:
        # int over [0, a] x [0, b] of 1/r, a, b >= 0
        if a <= 0.0 or b <= 0.0:
            return 0.0
        split = math.atan2(b, a)
        f1 = quad(lambda t: a / math.cos(t), 0.0, split, epsabs=0.0, epsrel=1e-13)[0]
        f2 = quad(lambda t: b / math.sin(t), split, 0.5 * math.pi, epsabs=0.0, epsrel=1e-13)[0]
        return f1 + f2

    # int_{x0}^{x1} int_{y0}^{y1} as a signed sum of rectangles with a corner at the point
    total = 0.0
    for xa, sx in ((0.5 * dx - X, 1.0), (-0.5 * dx - X, -1.0)):
        for ya, sy in ((0.5 * dy - Y, 1.0), (-0.5 * dy - Y, -1.0)):
            sign = sx * sy * math.copysign(1.0, xa) * math.copysign(1.0, ya)
            total += sign * corner_rect(abs(xa), abs(ya))
    return total / (math.pi * E_star)


def reynolds_dense(gap, dx, dy, viscosity, pressure_drop):
    """Reynolds flow across x by loops and a dense solve (fastline.bem.flow's discretisation).

    Cells with gap > 0 conduct g^3/(12 eta); faces take the harmonic mean; inlet/outlet are half
    a cell from the first/last column; periodic in y. Cells not reachable from both inlet and
    outlet (breadth-first search) are dropped. Returns Q Lx / (Ly dP).
    """
    nx, ny = gap.shape
    c = gap**3 / (12.0 * viscosity)

    def face(a, b):
        return 0.0 if a + b == 0.0 else 2.0 * a * b / (a + b)

    def neighbours(i, j):
        out = []
        if i > 0:
            out.append((i - 1, j, face(c[i, j], c[i - 1, j]) * dy / dx))
        if i < nx - 1:
            out.append((i + 1, j, face(c[i, j], c[i + 1, j]) * dy / dx))
        for jj in ((j - 1) % ny, (j + 1) % ny):
            out.append((i, jj, face(c[i, j], c[i, jj]) * dx / dy))
        return [(a, b, t) for a, b, t in out if t > 0.0]

    def reach(starts):
        seen = set(s for s in starts if c[s] > 0.0)
        todo = list(seen)
        while todo:
            i, j = todo.pop()
            for a, b, _ in neighbours(i, j):
                if (a, b) not in seen:
                    seen.add((a, b))
                    todo.append((a, b))
        return seen

    active = reach([(0, j) for j in range(ny)]) & reach([(nx - 1, j) for j in range(ny)])
    if not active:
        return 0.0
    cells = sorted(active)
    index = {cell: k for k, cell in enumerate(cells)}
    A = np.zeros((len(cells), len(cells)))
    rhs = np.zeros(len(cells))
    for (i, j), k in index.items():
        for a, b, t in neighbours(i, j):
            if (a, b) in index:
                A[k, k] += t
                A[k, index[(a, b)]] -= t
        if i == 0:
            A[k, k] += 2.0 * c[i, j] * dy / dx
            rhs[k] += 2.0 * c[i, j] * dy / dx * pressure_drop
        if i == nx - 1:
            A[k, k] += 2.0 * c[i, j] * dy / dx
    P = np.linalg.solve(A, rhs)
    q = sum(
        2.0 * c[nx - 1, j] * dy / dx * P[index[(nx - 1, j)]]
        for j in range(ny)
        if (nx - 1, j) in index
    )
    return q * nx * dx / (ny * dy * pressure_drop)


# ---- variants of the theory with the area correction (fastline.variants, "wang-mueser") -------
def _s_poly(P, gamma, s2, s4):
    return gamma + s2 * P**2 + s4 * P**4


@functools.lru_cache(maxsize=4)
def _area_ode(gamma: float, s2: float, s4: float):
    """Dense solution in s = ln y of Phi(y) = int_y^inf 2 t^-3 / S(erf t) dt and of
    Fy(y) = int_y^inf b(erf t) exp(-t^2) Phi(t)^(1/2) dt, b = d/dP [P S], by one ODE solve
    downwards from y = 7 (Phi = 1/y^2, Fy = b(1) E1(y^2)/2 there)."""

    def b(P):
        return gamma + 3.0 * s2 * P**2 + 5.0 * s4 * P**4

    def rhs(s, z):
        y = math.exp(s)
        P = float(erf(y))
        return [
            -2.0 / (y * y * _s_poly(P, gamma, s2, s4)),
            -b(P) * math.exp(-y * y) * y * math.sqrt(z[0]),
        ]

    top = 7.0
    z0 = [top**-2, b(1.0) * float(exp1(top * top)) / 2.0]
    sol = solve_ivp(
        rhs,
        [math.log(top), math.log(1e-10)],
        z0,
        method="DOP853",
        rtol=1e-13,
        atol=1e-300,
        dense_output=True,
    )
    return sol.sol, b(1.0)


def area_functions(x0: float, gamma: float, s2: float, s4: float) -> tuple[float, float]:
    """(Y(x0), F(x0)) of a variant whose S(P) = gamma + s2 P^2 + s4 P^4 enters the contact-area
    recursion (fastline._special_area): Phi(Y) = 1/x0^2 by brentq on the ODE's dense output,
    F = Fy(Y). For x0 > 6.5, Y = x0 and F = b(1) E1(x0^2)/2."""
    dense, b1 = _area_ode(gamma, s2, s4)
    if x0 > 6.5:
        return x0, b1 * float(exp1(x0 * x0)) / 2.0
    s = brentq(
        lambda s: math.log(dense(s)[0]) + 2.0 * math.log(x0),
        math.log(1e-10),
        math.log(7.0),
        xtol=1e-15,
        rtol=1e-15,
    )
    return math.exp(s), float(dense(s)[1])


def area_recursion(psd, E_star, p, gamma, s2, s4, rtol=1e-12):
    """The contact-area recursion with the correction in it, solved as an ODE in ln q:
    ``dA/dq = S(P) pi q^3 C(q)``, ``P = erf(p / (E* sqrt(A)))`` (A = 2 V / E*^2, from 0 at q0),
    and the elastic energy ``U = (pi/2) E* int q^2 C P S dq``. Returns (P(q1, p), U(p))."""

    def rhs(lq, z):
        q = math.exp(lq)
        A = z[0]
        P = 1.0 if A <= 0.0 else float(erf(p / (E_star * math.sqrt(A))))
        S = _s_poly(P, gamma, s2, s4)
        C = float(psd(q))
        return [S * math.pi * q**4 * C, 0.5 * math.pi * E_star * q**3 * C * P * S]

    z = [0.0, 0.0]
    A1 = float(psd.cumulative(psd.q1))  # scales for the absolute tolerance (A starts at 0)
    atol = [1e-16 * A1, 1e-16 * E_star * A1 / psd.q1]
    cuts = [psd.q0] + [b for b in psd.breakpoints() if psd.q0 < b < psd.q1] + [psd.q1]
    for a, c in zip(cuts[:-1], cuts[1:], strict=False):
        sol = solve_ivp(rhs, [math.log(a), math.log(c)], z, method="DOP853", rtol=rtol, atol=atol)
        z = list(sol.y[:, -1])
    return float(erf(p / (E_star * math.sqrt(z[0])))), z[1]


def separation_from_energy(psd, E_star, p, gamma, s2, s4, epsrel=1e-9):
    """u(p) = int_p^inf dp'/p' dU/dp' from the energy of :func:`area_recursion`, written as
    ``u = (1/p) int_0^1 [U(p/t) - U(p)] dt`` (integration by parts; U(inf) is finite)."""
    U = lambda pp: area_recursion(psd, E_star, pp, gamma, s2, s4)[1]  # noqa: E731
    Up = U(p)
    val = quad(
        lambda t: U(p / t) - Up if t > 0.0 else 0.0, 0.0, 1.0, epsabs=0.0, epsrel=epsrel, limit=200
    )[0]
    return val / p
