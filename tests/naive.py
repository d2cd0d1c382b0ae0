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
from scipy.special import erf, exp1, roots_legendre


def universal_F(x0: float, gamma: float, b2: float | None = None) -> float:
    """F(x0) = int_{x0}^inf (1/x)[gamma + b2 erf(x)^2] exp(-x^2) dx, b2 = 3(1-gamma) by default
    (the printed bracket of fastline.theory.variants has b2 = 1 - gamma).

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
            epsrel=1e-13,  # 1e-14 is below quad's round-off for m >= 3 (IntegrationWarning)
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


def line_contact_hard(E_star, radius, load, n, half_width):
    """Hard contact of a smooth cylinder, dense: the contact set by enumeration.

    For a convex profile the discrete contact is a centred, symmetric run of cells. Try runs
    of growing length; on each, solve the bordered system ``K_AA p_A + u1 = -g_A``,
    ``dx sum(p_A) = load``; return ``x, p`` of the first with ``p >= 0`` and no penetration
    outside (``g + K p + u1 >= 0``).
    """
    dx = 2.0 * half_width / n
    x = (np.arange(n) - 0.5 * (n - 1)) * dx
    K = log_kernel_matrix(n, dx, E_star)
    g = x * x / (2.0 * radius)
    order = np.argsort(np.abs(x), kind="stable")
    for m in range(2 - n % 2, n + 1, 2):  # symmetric runs: odd n odd lengths, even n even
        idx = np.sort(order[:m])
        M = np.zeros((m + 1, m + 1))
        M[:m, :m] = K[np.ix_(idx, idx)]
        M[:m, m] = 1.0
        M[m, :m] = dx
        sol = np.linalg.solve(M, np.concatenate([-g[idx], [load]]))
        p = np.zeros(n)
        p[idx] = sol[:m]
        gap = g + K @ p + sol[m]
        if p.min() >= 0.0 and gap.min() >= -1e-12 * g.max():
            return x, p
    raise RuntimeError("no feasible contact set")


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


def flow_path_cells(gap):
    """The cells fastline.bem.flow keeps on the flow path, by breadth-first search over sets:
    every cluster (open cells joined across faces, periodic in y) that touches the inlet column
    or the outlet column, if one cluster touches both; else none."""
    nx, ny = gap.shape
    open_ = gap > 0.0
    label = -np.ones((nx, ny), dtype=int)
    clusters = []
    for i0 in range(nx):
        for j0 in range(ny):
            if label[i0, j0] >= 0:
                continue
            label[i0, j0] = len(clusters)
            members, todo = {(i0, j0)}, [(i0, j0)]
            while todo and open_[i0, j0]:
                i, j = todo.pop()
                for a, b in ((i - 1, j), (i + 1, j), (i, (j - 1) % ny), (i, (j + 1) % ny)):
                    if 0 <= a < nx and open_[a, b] and label[a, b] < 0:
                        label[a, b] = len(clusters)
                        members.add((a, b))
                        todo.append((a, b))
            clusters.append(members)
    inlet = {label[0, j] for j in range(ny) if open_[0, j]}
    outlet = {label[nx - 1, j] for j in range(ny) if open_[nx - 1, j]}
    keep = np.zeros((nx, ny), dtype=bool)
    if inlet & outlet:
        for k in inlet | outlet:
            for cell in clusters[k]:
                keep[cell] = True
    return keep


def five_point_apply(D, tx, ty, x):
    """``A x`` of the flow's five-point system (diagonal D, x faces tx, periodic y faces ty),
    cell by cell."""
    nx, ny = D.shape
    y = np.zeros((nx, ny))
    for i in range(nx):
        for j in range(ny):
            s = D[i, j] * x[i, j] - ty[i, (j - 1) % ny] * x[i, (j - 1) % ny]
            s -= ty[i, j] * x[i, (j + 1) % ny]
            if i > 0:
                s -= tx[i - 1, j] * x[i - 1, j]
            if i < nx - 1:
                s -= tx[i, j] * x[i + 1, j]
            y[i, j] = s
    return y


def gauss_seidel_sweep(D, tx, ty, b, x, backward):
    """One Gauss-Seidel sweep of the flow's five-point system in place on x, cell by cell in
    lexicographic order (or its reverse), periodic in y (fastline.bem.pcg_flow's smoother)."""
    nx, ny = D.shape
    cells = [(i, j) for i in range(nx) for j in range(ny)]
    for i, j in reversed(cells) if backward else cells:
        s = b[i, j] + ty[i, (j - 1) % ny] * x[i, (j - 1) % ny] + ty[i, j] * x[i, (j + 1) % ny]
        if i > 0:
            s += tx[i - 1, j] * x[i - 1, j]
        if i < nx - 1:
            s += tx[i, j] * x[i + 1, j]
        x[i, j] = s / D[i, j]


# ------------------------------------------------------------------------------------------------
# tabulated spectra (fast eta quadrature of fastline.theory.quadrature)
# ------------------------------------------------------------------------------------------------
_GL20 = roots_legendre(20)
_G_STEP = 1.0 / 64.0  # grid of G(x) on [0, 7]; beyond 7 erf(x)^2 = 1 to 1e-22
_G_TOP = 7.0


def _gauss20(f, a, b):
    """int_a^b f by 20-point Gauss-Legendre, vectorised over arrays a, b."""
    t, w = _GL20
    a = np.asarray(a, dtype=float)[..., None]
    b = np.asarray(b, dtype=float)[..., None]
    x = 0.5 * (a + b) + 0.5 * (b - a) * t
    return 0.5 * (b - a)[..., 0] * (f(x) @ w)


def _g_integrand(x):
    return erf(x) ** 2 * np.exp(-x * x) / x


@functools.cache
def _g_grid():
    """G(x) = int_x^inf erf^2 exp(-x^2)/x dx on the grid k/64, summed down from x = 7."""
    x = np.arange(0.0, _G_TOP + 0.5 * _G_STEP, _G_STEP)
    cells = _gauss20(_g_integrand, np.maximum(x[:-1], 1e-300), x[1:])
    G = np.concatenate([np.cumsum(cells[::-1])[::-1], [0.0]]) + exp1(_G_TOP**2) / 2.0
    return x, G


def universal_F_vec(x, gamma: float) -> np.ndarray:
    """F(x) of ``universal_F`` for an array: ``gamma E1(x^2)/2 + 3 (1 - gamma) G(x)``.

    G from the grid value above x plus a 20-point Gauss-Legendre integral up to it (relative
    error ~1e-15, checked against ``universal_F``); for x >= 7, ``G = E1(x^2)/2``.
    """
    x = np.asarray(x, dtype=float)
    grid, G_grid = _g_grid()
    G = exp1(np.maximum(x, _G_TOP) ** 2) / 2.0
    low = x < _G_TOP
    k = np.minimum((x[low] / _G_STEP).astype(int) + 1, grid.size - 1)
    G[low] = G_grid[k] + _gauss20(_g_integrand, np.maximum(x[low], 1e-300), grid[k])
    return gamma * exp1(x * x) / 2.0 + 3.0 * (1.0 - gamma) * G


def tabulated_nodes(qn, Cn, piece: float = 0.01, points: int = 8):
    """Nodes of ``int f(q) q^2 C(q) dq`` for the log-log interpolant of a table: the weights
    ``dm`` (of q^2 C dq) and ``w = A^(-1/2)`` at each node.

    Per table interval (zero intervals skipped): ``points``-point Gauss-Legendre per piece of
    at most ``piece`` in ln q, so every kink of C is a piece edge. On the interval the
    spectrum is ``C = C_i (q/q_i)^s`` and ``A(q) = A_i + pi C_i q_i^4 ((q/q_i)^(4+s) - 1)/(4+s)``
    (written with expm1, A_i summed over the intervals below). On the first live interval
    ``q = a + L tau^2`` with tau graded geometrically (ratio 0.3, 40 levels) removes
    ``w ~ (q - q0)^(-1/2)``; there ``ln(q/a)`` is taken as ``log1p(L tau^2 / a)`` so that A stays
    exact when ``q`` rounds to ``a``.
    """
    qn, Cn = np.asarray(qn, dtype=float), np.asarray(Cn, dtype=float)
    t_ref, w_ref = roots_legendre(points)
    nodes, weights, cumul = [], [], []
    A_start, first = 0.0, True
    for i in range(qn.size - 1):
        if Cn[i] <= 0.0 or Cn[i + 1] <= 0.0:
            continue
        a, b = qn[i], qn[i + 1]
        s = math.log(Cn[i + 1] / Cn[i]) / math.log(b / a)
        if first:
            edges = np.concatenate([[0.0], 0.3 ** np.arange(40, -1, -1)])
            ta, tb = edges[:-1, None], edges[1:, None]
            tau = (0.5 * (ta + tb) + 0.5 * (tb - ta) * t_ref).ravel()
            log_r = np.log1p((b - a) * tau**2 / a)
            dq = (0.5 * (tb - ta) * w_ref).ravel() * 2.0 * (b - a) * tau
            first = False
        else:
            n = max(1, math.ceil(math.log(b / a) / piece))
            e = math.log(b / a) * np.arange(n + 1) / n
            ea, eb = e[:-1, None], e[1:, None]
            log_r = (0.5 * (ea + eb) + 0.5 * (eb - ea) * t_ref).ravel()
            dq = (0.5 * (eb - ea) * w_ref).ravel() * a * np.exp(log_r)
        q = a * np.exp(log_r)
        e4 = 4.0 + s
        grow = log_r if e4 == 0.0 else np.expm1(e4 * log_r) / e4
        cumul.append(A_start + math.pi * Cn[i] * a**4 * grow)
        weights.append(dq * q * q * Cn[i] * np.exp(s * log_r))
        nodes.append(q)
        A_start += (
            math.pi
            * Cn[i]
            * a**4
            * (math.log(b / a) if e4 == 0.0 else math.expm1(e4 * math.log(b / a)) / e4)
        )
    return np.concatenate(weights), 1.0 / np.sqrt(np.concatenate(cumul))


def separation_tabulated(
    qn, Cn, E_star: float, p, gamma: float = 0.45, piece: float = 0.01, points: int = 8
):
    """u(p) (THEORY.md section 3) of the log-log interpolant of a table, array of pressures,
    on the nodes of ``tabulated_nodes``."""
    dm, w = tabulated_nodes(qn, Cn, piece, points)
    p = np.atleast_1d(np.asarray(p, dtype=float))
    out = np.empty(p.size)
    for k, pk in enumerate(p):
        x = w * pk / E_star
        live = x < 27.0
        out[k] = math.sqrt(math.pi) * np.sum(dm[live] * w[live] * universal_F_vec(x[live], gamma))
    return out


# ------------------------------------------------------------------------------------------------
# 1D spectra of isotropic surfaces (topography)
# ------------------------------------------------------------------------------------------------
def self_affine_1d(psd, k) -> np.ndarray:
    """The two-sided 1D spectrum of a ``SelfAffinePSD`` in closed form (Abel forward transform).

    ``C1D(k) = 2 int_k^inf C(q) q / sqrt(q^2 - k^2) dq`` (docs/theory.md section 2). The flat
    part gives ``2 C0 [sqrt(b^2 - k^2) - sqrt(a^2 - k^2)]`` over ``[a, b] = [max(q0, k),
    max(qr, k)]``; the power law ``C0 (q/qr)^(-2(1+H))`` on ``[max(qr, k), q1]`` gives, with
    ``u = k^2/q^2``, ``C0 qr^(2+2H) k^(-1-2H) [B(k^2/max(qr,k)^2) - B(k^2/q1^2)]`` where B is the
    incomplete beta function ``B(x; H + 1/2, 1/2)``. Zero for k >= q1.
    """
    from scipy.special import beta, betainc

    k = np.asarray(k, dtype=float)
    C0, H, q0, qr, q1 = psd.C0, psd.hurst, psd.q0, psd.qr, psd.q1
    a, b = np.maximum(q0, k), np.maximum(qr, k)
    flat = 2.0 * C0 * (np.sqrt(np.maximum(b * b - k * k, 0.0)) - np.sqrt(a * a - k * k))
    alpha = H + 0.5

    def incomplete(x):
        return betainc(alpha, 0.5, x) * beta(alpha, 0.5)

    with np.errstate(divide="ignore"):
        power = (
            C0 * qr ** (2 + 2 * H) * k ** (-1 - 2 * H)
            * (incomplete((k / b) ** 2) - incomplete(np.minimum(k / q1, 1.0) ** 2))
        )  # fmt: skip
    return np.where(k < q1, flat + power, 0.0)


def abel_forward_quad(psd, k: float, epsrel: float = 1e-12) -> float:
    """``C1D(k) = 2 int_k^q1 C(q) q / sqrt(q^2 - k^2) dq`` by quad, with ``q = k cosh(t)``
    (smooth integrand ``2 k C(k cosh t) cosh t``), split at the kinks of C."""
    cuts = [max(k, b) for b in psd.breakpoints()] + [psd.q1]
    t = sorted({math.acosh(c / k) for c in cuts if c >= k})
    total = 0.0
    for ta, tb in zip(t[:-1], t[1:], strict=False):
        total += quad(
            lambda x: 2.0 * k * float(psd(k * math.cosh(x))) * math.cosh(x),
            ta,
            tb,
            epsabs=0.0,
            epsrel=epsrel,
            limit=200,
        )[0]
    return total


def smooth_rolloff_pair(k, C0: float, qr: float, H: float):
    """A spectrum without kinks and its 1D transform, both in closed form:
    ``C(q) = C0 (1 + q^2/qr^2)^-(1+H)`` and, integrating over the other wavevector component
    (``C1D(k) = int C(sqrt(k^2 + y^2)) dy``),
    ``C1D(k) = C0 qr B(1/2, H + 1/2) (1 + k^2/qr^2)^-(H + 1/2)``."""
    from scipy.special import beta

    k = np.asarray(k, dtype=float)
    C = C0 * (1.0 + (k / qr) ** 2) ** (-(1.0 + H))
    C1D = C0 * qr * beta(0.5, H + 0.5) * (1.0 + (k / qr) ** 2) ** (-H - 0.5)
    return C, C1D


def periodogram_1d(h, dx: float, window) -> tuple[np.ndarray, np.ndarray]:
    """``C1D(k_m) = dx^2/(2 pi L) |sum_j w_j h_j exp(-i k_m x_j)|^2`` for m = 1..N//2, written as
    the explicit O(N^2) sum (x_j = j dx, L = N dx), for one profile."""
    h = np.asarray(h, dtype=float)
    n = h.size
    L = n * dx
    x = np.arange(n) * dx
    m = np.arange(1, n // 2 + 1)
    k = 2.0 * math.pi * m / L
    phase = np.exp(-1j * np.outer(k, x))
    return k, dx * dx / (2.0 * math.pi * L) * np.abs(phase @ (window * h)) ** 2


# ----------------------------------------------------------------------------------------------
# point contact (THEORY.md section 9): the ring kernel of Johnson eq. 3.96a
# ----------------------------------------------------------------------------------------------
def ring_kernel(r: float, rho: float) -> float:
    """(4/pi) rho/(r + rho) K(k), k = 2 sqrt(r rho)/(r + rho): displacement at r per unit
    pressure on the ring at rho (per unit rho), E* = 1. K is written with scipy's ``ellipkm1``
    of 1 - k^2 = ((r - rho)/(r + rho))^2, exact near the log singularity at rho = r."""
    from scipy.special import ellipkm1

    if rho == r:
        return 0.0  # the integrable singularity; never an interior quadrature node
    return 4.0 / math.pi * rho / (r + rho) * float(ellipkm1(((r - rho) / (r + rho)) ** 2))


def ring_cell_coefficient(i: int, j: int) -> float:
    """Displacement averaged over cell i per unit pressure on cell j, dr = 1, E* = 1.

    Cells: the disc r < 1/2 (j = 0) and the rings (j - 1/2, j + 1/2). Nested ``quad`` of the
    ring kernel, each integral split where the integrand is singular or kinked.
    """

    def edges(k):
        return (0.0 if k == 0 else k - 0.5), k + 0.5

    (a, b), (c, d) = edges(i), edges(j)

    def inner(r):
        cuts = [c, r, d] if c < r < d else [c, d]
        return sum(
            quad(lambda rho: ring_kernel(r, rho), lo, hi, epsabs=0.0, epsrel=1e-13, limit=200)[0]
            for lo, hi in zip(cuts[:-1], cuts[1:], strict=False)
        )

    cuts = sorted({a, b} | {x for x in (c, d) if a < x < b})
    total = sum(
        quad(lambda r: inner(r) * 2.0 * math.pi * r, lo, hi, epsabs=0.0, epsrel=1e-12, limit=200)[0]
        for lo, hi in zip(cuts[:-1], cuts[1:], strict=False)
    )
    return total / (math.pi * (b * b - a * a))


def point_contact_exponential(khat, E_star, radius, load, u0, beta, domain):
    """Point contact with the exponential law p = beta E* exp(-u/u0): dense matrix, scipy root.

    ``khat`` is the dimensionless ring matrix (checked against :func:`ring_cell_coefficient`
    in the tests); cells are the disc r < dr/2 and rings of width dr = domain / (n - 1/2).
    Unknowns v = ln p (n values) and u1; equations
    u0 ln(beta E*/p_i) = u1 + <r^2/2R>_i + (dr/E*) (khat p)_i and sum(w p) = load.
    Returns r, p.
    """
    from scipy.optimize import root

    n = khat.shape[0]
    dr = domain / (n - 0.5)
    e = np.concatenate([[0.0], (np.arange(n) + 0.5) * dr])
    w = math.pi * (e[1:] ** 2 - e[:-1] ** 2)
    g = (e[1:] ** 2 + e[:-1] ** 2) / (4.0 * radius)
    K = khat * (dr / E_star)
    r = np.arange(n) * dr
    s2 = radius * u0
    v0 = np.log(load / (2.0 * math.pi * s2)) - r * r / (2.0 * s2)

    def fun(z):
        v, u1 = z[:-1], z[-1]
        p = np.exp(v)
        res = u0 * (math.log(beta * E_star) - v) - u1 - g - K @ p
        return np.concatenate([res / u0, [w @ p / load - 1.0]])

    z0 = np.concatenate([v0, [u0 * math.log(beta * E_star / (load / (2 * math.pi * s2)))]])
    sol = root(fun, z0, method="hybr", tol=1e-13)
    if not sol.success:
        raise RuntimeError(sol.message)
    return r, np.exp(sol.x[:-1])


# ---- variants of the theory with the area correction (fastline.theory.variants, "wang-mueser") --
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
    recursion (fastline.theory.special): Phi(Y) = 1/x0^2 by brentq on the ODE's dense output,
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


# ---- Greenwood-Williamson (fastline.theory.asperity) --------------------------------------------
def gw_integral(u, n, mean, std):
    """int_u^inf (z - u)^n phi_s(z) dz for Gaussian summit heights (mean, std), by quad in z
    (split at the peak of the integrand; the Gaussian factor scaled out beyond 8 std)."""
    t = (u - mean) / std
    shift = 0.5 * t * t if t > 0.0 else 0.0  # returned integral is multiplied by exp(-shift)

    def f(z):
        s = (z - mean) / std
        return (z - u) ** n * math.exp(shift - 0.5 * s * s) / (std * math.sqrt(2.0 * math.pi))

    top = max(u, mean) + 40.0 * std
    peak = max(u, mean)
    parts = [(u, peak), (peak, peak + 5 * std), (peak + 5 * std, top)]
    val = sum(quad(f, a, b, epsabs=0.0, epsrel=1e-13, limit=200)[0] for a, b in parts if b > a)
    return val, shift


def gw_pressure(u, density, radius, std, mean, E_star):
    """Greenwood-Williamson nominal pressure (4/3) eta E* sqrt(beta) int (z - u)^1.5 phi_s dz,
    returned as ln p (Pa)."""
    val, shift = gw_integral(u, 1.5, mean, std)
    return math.log(4.0 / 3.0 * density * E_star * math.sqrt(radius) * val) - shift


def gw_area(u, density, radius, std, mean):
    """Greenwood-Williamson real area fraction pi eta beta int (z - u) phi_s dz."""
    val, shift = gw_integral(u, 1.0, mean, std)
    return math.pi * density * radius * val * math.exp(-shift)


# ----------------------------------------------------------------------------------------------
# leakage (THEORY.md 8.2): the area that leaves the apparent contact, weighted by u1
# ----------------------------------------------------------------------------------------------
def leaving_area_moment(psd, E_star, p, u1, zeta_a, epsrel=1e-10):
    """``int_{zeta_a}^{q1/q0} u1(zeta) (-dP/dzeta) dzeta`` by ``quad`` in ln zeta.

    ``P(zeta) = erf(y)``, ``y = p / (E* sqrt(A(zeta q0)))``, so
    ``-dP/d ln zeta = sqrt(pi) y exp(-y^2) q^4 C(q) / A(q)`` at ``q = zeta q0``; ``u1`` is a
    callable of (zeta, p). The interval is split at the kinks of C. By the area balance that
    defines u1, ``d(P u_bar)/dzeta = P' u1``, the result is ``P(zeta_a) u_bar(zeta_a)``.
    """
    q0 = psd.q0

    def integrand(lz):
        q = q0 * math.exp(lz)
        A = float(psd.cumulative(q))
        y = p / (E_star * math.sqrt(A))
        weight = math.sqrt(math.pi) * y * math.exp(-y * y) * q**4 * float(psd(q)) / A
        return float(u1(q / q0, p)) * weight if weight > 0.0 else 0.0

    lo, hi = math.log(zeta_a), math.log(psd.q1 / q0)
    cuts = [math.log(b / q0) for b in psd.breakpoints() if lo < math.log(b / q0) < hi]
    return quad(integrand, lo, hi, points=cuts or None, epsabs=0.0, epsrel=epsrel, limit=400)[0]


def peak_quartic(p):
    """Peak of the quartic through the five samples around the discrete maximum: NumPy's
    polyfit through the five points, then a dense scan of [-1, 1] cells refined by SciPy's
    bounded scalar minimisation (compare :func:`fastline.contact.resolution.peak_quartic`)."""
    from scipy.optimize import minimize_scalar

    i = int(np.argmax(p))
    t = np.arange(-2.0, 3.0)
    coef = np.polyfit(t, p[i - 2 : i + 3], 4)
    scan = np.linspace(-1.0, 1.0, 2001)
    t0 = scan[np.argmax(np.polyval(coef, scan))]
    lo, hi = max(-1.0, t0 - 1e-3), min(1.0, t0 + 1e-3)
    best = minimize_scalar(
        lambda s: -np.polyval(coef, s), bounds=(lo, hi), method="bounded", options={"xatol": 1e-13}
    )
    return max(float(p[i]), float(-best.fun))


def fwhm_cubic(p, dx, p0):
    """Width between the outermost crossings of p0/2 of the cubic through four samples around
    each crossing cell (nodes k-1..k+2 for the cell [k, k+1]), each crossing found by SciPy's
    brentq on that cubic (compare :func:`fastline.contact.resolution.fwhm_cubic`)."""
    from scipy.optimize import brentq

    half = 0.5 * p0
    above = np.nonzero(p >= half)[0]
    i, j = int(above[0]), int(above[-1])

    def crossing(k):  # the crossing in [k, k+1], in cells from 0
        nodes = np.arange(k - 1, k + 3, dtype=float)
        coef = np.polyfit(nodes, p[k - 1 : k + 3], 3)
        return brentq(lambda t: np.polyval(coef, t) - half, k, k + 1, xtol=1e-14)

    return (crossing(j) - crossing(i - 1)) * dx


def cell_mean_spectrum(psd, qx: float, qy: float, dqx: float, dqy: float) -> float:
    """Mean of the isotropic ``C(|q|)`` over the lattice cell ``[qx +- dqx/2] x [qy +- dqy/2]``
    by nested adaptive quadrature, split where ``|q|`` crosses the spectrum's breakpoints (the
    reference of the BEM surface generator's cell means, fastline.bem.surface)."""
    radii = psd.breakpoints()

    def inner(x):
        cuts = [s * math.sqrt(r * r - x * x) for r in radii if r > abs(x) for s in (-1, 1)]
        lo, hi = qy - 0.5 * dqy, qy + 0.5 * dqy
        pts = [c for c in cuts if lo < c < hi]
        f = lambda y: float(psd(math.hypot(x, y)))  # noqa: E731
        return quad(f, lo, hi, points=pts or None, epsabs=0.0, epsrel=1e-10, limit=200)[0]

    lo, hi = qx - 0.5 * dqx, qx + 0.5 * dqx
    pts = [s * r for r in radii for s in (-1, 1) if lo < s * r < hi]
    total = quad(inner, lo, hi, points=pts or None, epsabs=0.0, epsrel=1e-9, limit=200)[0]
    return total / (dqx * dqy)


# ---- profile measures (fastline.contact.model.peak / fwhm, compiled in fastline.contact.kernels) -
def peak_parabola(p):
    """Peak by the parabola through the three points around np.argmax (the maximum at an end)."""
    i = int(np.argmax(p))
    if 0 < i < p.size - 1:
        a, b, c = p[i - 1], p[i], p[i + 1]
        den = a - 2.0 * b + c
        if den < 0.0:
            return float(b - 0.25 * (a - c) * (0.5 * (a - c) / den))
    return float(p[i])


def fwhm_crossings(x, p, p0):
    """Width between the outermost cells with p >= p0/2, each end interpolated linearly to the
    crossing; NaN when the half maximum is reached at an end of the grid."""
    above = np.nonzero(p >= 0.5 * p0)[0]
    i, j = above[0], above[-1]
    if i == 0 or j == p.size - 1:
        return float("nan")
    xl = np.interp(0.5 * p0, [p[i - 1], p[i]], [x[i - 1], x[i]])
    xr = np.interp(0.5 * p0, [p[j + 1], p[j]], [x[j + 1], x[j]])
    return float(xr - xl)


def coarse_operator(
    D: np.ndarray, K: np.ndarray, edges: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """Dense ``H P`` (n x nc) and ``P`` of the two-level preconditioner's coarse space:
    ``H = diag(D) + K``, ``P[i, k] = 1`` for the cells ``edges[k] <= i < edges[k + 1]``."""
    n, nc = D.size, edges.size - 1
    P = np.zeros((n, nc))
    for k in range(nc):
        P[edges[k] : edges[k + 1], k] = 1.0
    return (np.diag(D) + K) @ P, P


# ----------------------------------------------------------------------------------------------
# leakage (THEORY.md 8.4, read radially): rings in series around a point contact's orifice
# ----------------------------------------------------------------------------------------------
def radial_leak_rate(r, u_c, r_in, pressure_drop, viscosity):
    """``Q = dP / int_{r_in}^{r_out} dr 12 eta / (2 pi r u_c(r)^3)``, u_c constant on the cells
    centred at r (edges halfway, clipped at 0), the integral by SciPy's quad cell by cell (no
    logarithm in closed form: an independent route from :func:`fastline.leak_rate_profile`)."""
    mid = 0.5 * (r[1:] + r[:-1])
    edges = np.maximum(np.concatenate([[2 * r[0] - mid[0]], mid, [2 * r[-1] - mid[-1]]]), 0.0)
    total = 0.0
    for k in range(r.size):
        lo, hi = max(edges[k], r_in), edges[k + 1]
        if hi <= lo or not math.isfinite(u_c[k]):
            continue
        c = 12.0 * viscosity / (2.0 * math.pi * u_c[k] ** 3)
        total += quad(lambda s, c=c: c / s, lo, hi, epsabs=0.0, epsrel=1e-13)[0]
    return pressure_drop / total


def gaussian_profiles(c1d, n: int, dx: float, count: int, seed: int) -> np.ndarray:
    """``count`` periodic Gaussian profiles (count, n) of the two-sided 1D spectrum c1d(k):
    Fourier coefficients at ``k_m = 2 pi m / L`` (m = 1 .. n/2) with independent Gaussian real
    and imaginary parts of total variance ``E|F_m|^2 = 2 pi L C1D(k_m) / dx^2`` (the inverse of
    ``C1D = dx^2 / (2 pi L) |F|^2``; the Nyquist coefficient real), zero mean."""
    L = n * dx
    m = np.arange(n // 2 + 1)
    k = 2.0 * math.pi * np.maximum(m, 1) / L
    power = np.where(m > 0, 2.0 * math.pi * L * np.asarray(c1d(k)) / (dx * dx), 0.0)
    rng = np.random.default_rng(seed)
    z = rng.standard_normal((count, m.size)) + 1j * rng.standard_normal((count, m.size))
    z[:, -1] = z[:, -1].real * math.sqrt(2.0)  # real at Nyquist, the same variance
    return np.fft.irfft(z * np.sqrt(0.5 * power), n, axis=-1)


def fixed_gap_mean(u, pressures):
    """The ensemble's mean gap at each pressure, averaged at a fixed gap, by loops: for the
    mean gap u_k at pressure k, the mean over surfaces of the pressure each surface needs for
    u_k (linear in ln p between its own points, its end cells extended), then that curve read
    back at the pressures (linear in ln p, end cells extended)."""
    u = np.asarray(u, dtype=float)
    v = [math.log(p) for p in pressures]
    n_s, n_p = u.shape
    um = [sum(u[i, k] for i in range(n_s)) / n_s for k in range(n_p)]

    def cell(xs, x):  # the cell j of a monotone sequence xs holding x (end cells outside)
        for j in range(len(xs) - 1):
            if min(xs[j], xs[j + 1]) <= x <= max(xs[j], xs[j + 1]):
                return j
        return 0 if abs(x - xs[0]) < abs(x - xs[-1]) else len(xs) - 2

    def line(x0, y0, x1, y1, x):
        return y0 + (x - x0) * (y1 - y0) / (x1 - x0)

    P = []
    for k in range(n_p):
        total = 0.0
        for i in range(n_s):
            j = cell(list(u[i]), um[k])
            total += math.exp(line(u[i, j], v[j], u[i, j + 1], v[j + 1], um[k]))
        P.append(math.log(total / n_s))
    out = []
    for k in range(n_p):
        j = cell(P, v[k])
        out.append(line(P[j], um[j], P[j + 1], um[j + 1], v[k]))
    return np.array(out)
