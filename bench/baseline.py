"""The line-contact problem solved without fastline: NumPy/SciPy only, the way a capable user would.

* Roughness: the self-affine spectrum with roll-off written out (C0 from h_rms, closed-form A(q)).
* Persson u(p): ``scipy.integrate.quad`` over ln q of ``sqrt(pi) q^2 C w F(w p / E*)``, with the
  universal function ``F`` from ``scipy.special.exp1`` (gamma part) plus ``quad`` (erf^2 part,
  tabulated once on a log grid of x0 and spline-interpolated). u(p) is tabulated on a modest grid
  in ln p and interpolated by a cubic spline (linear extrapolation below the grid, where u(p) is
  the exponential law, linear in ln p).
* Elasticity: the dense influence matrix ``K_ij = (dx/E*) khat_|i-j|`` of the cell-integrated log
  kernel, ``khat_m = -(2/pi)[g(m+1/2) - g(m-1/2)]``, ``g(t) = t ln|t| - t``.
* Nonlinear system in ``v = ln p`` plus the force balance, solved by ``scipy.optimize.root``
  (MINPACK ``hybr``) with the analytic dense Jacobian.

Nothing here imports fastline; it is the reference point of the speed-up in docs/performance.md.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy.integrate import quad
from scipy.interpolate import CubicSpline
from scipy.linalg import toeplitz
from scipy.optimize import root
from scipy.special import erf, exp1


# -- spectrum ------------------------------------------------------------------------------------
@dataclass
class SelfAffine:
    h_rms: float
    H: float
    q0: float
    qr: float
    q1: float

    def __post_init__(self):
        q0, qr, q1, H = self.q0, self.qr, self.q1, self.H
        tail = qr ** (2 + 2 * H) * (qr ** (-2 * H) - q1 ** (-2 * H)) / (2 * H)
        self.C0 = self.h_rms**2 / (2 * math.pi * ((qr * qr - q0 * q0) / 2 + tail))

    def C(self, q):
        if q < self.qr:
            return self.C0
        return self.C0 * (q / self.qr) ** (-2 * (1 + self.H))

    def A(self, q):
        """pi int_{q0}^{q} q'^3 C dq'."""
        q0, qr, H, C0 = self.q0, self.qr, self.H, self.C0
        if q <= qr:
            return math.pi * C0 * (q**4 - q0**4) / 4
        a = math.pi * C0 * (qr**4 - q0**4) / 4
        if H == 1.0:
            return a + math.pi * C0 * qr**4 * math.log(q / qr)
        return a + math.pi * C0 * qr ** (2 + 2 * H) * (q ** (2 - 2 * H) - qr ** (2 - 2 * H)) / (
            2 - 2 * H
        )


# -- Persson u(p) --------------------------------------------------------------------------------
class UniversalF:
    """F(x0) = gamma E1(x0^2)/2 + 3(1-gamma) int_{x0}^inf erf(x)^2 exp(-x^2)/x dx."""

    def __init__(self, gamma, n=300):
        self.gamma = gamma
        lx = np.linspace(math.log(1e-8), math.log(6.0), n)
        b = [
            quad(lambda x: erf(x) ** 2 * math.exp(-x * x) / x, math.exp(t), np.inf, limit=200)[0]
            for t in lx
        ]
        self._b = CubicSpline(lx, b)
        self._b_small = b[0]  # the erf^2 part tends to a constant as x0 -> 0

    def __call__(self, x0):
        if x0 > 6.0:
            return 0.0 if x0 > 27.0 else self.gamma * exp1(x0 * x0) / 2
        part_b = self._b_small if x0 < 1e-8 else float(self._b(math.log(x0)))
        return self.gamma * exp1(x0 * x0) / 2 + 3 * (1 - self.gamma) * part_b


def separation(psd: SelfAffine, E_star, p, F):
    """u(p) = sqrt(pi) int dq q^2 C w F(w p/E*), quad over ln q split per decade."""

    def f(lq):
        q = math.exp(lq)
        A = psd.A(q)
        if A <= 0.0:
            return 0.0
        w = 1.0 / math.sqrt(A)
        return q**3 * psd.C(q) * w * F(w * p / E_star)

    cuts = np.unique(np.concatenate([np.geomspace(psd.q0, psd.q1, 13), [psd.qr]]))
    total = sum(
        quad(f, math.log(a), math.log(b), limit=100, epsrel=1e-8)[0]
        for a, b in zip(cuts[:-1], cuts[1:], strict=True)
    )
    return math.sqrt(math.pi) * total


class SeparationTable:
    """u(v), v = ln p: cubic spline on ``n`` points; linear (exponential law) below the grid."""

    def __init__(self, psd, E_star, gamma=0.45, n=48):
        self.F = UniversalF(gamma)
        # top: the interface is closed (P(q1, p) = erf(5)); bottom: deep in the exponential law
        w1 = 1.0 / math.sqrt(psd.A(psd.q1))
        v = np.linspace(math.log(1e-9 * E_star), math.log(5.0 * E_star / w1), n)
        u = np.array([separation(psd, E_star, math.exp(t), self.F) for t in v])
        self.v_lo, self.v_hi = v[0], v[-1]
        self.lnu = CubicSpline(v, np.log(u))  # ln u is smooth and well scaled
        self.u_lo = u[0]
        self.slope_lo = float(self.lnu(v[0], 1)) * u[0]  # du/dv at the low end (= -u0)
        self.u0 = -self.slope_lo

    def __call__(self, v):
        """u and du/dv."""
        v = np.asarray(v)
        vc = np.clip(v, self.v_lo, self.v_hi)
        lu = self.lnu(vc)
        u = np.exp(lu)
        du = u * self.lnu(vc, 1)
        low = v < self.v_lo
        u = np.where(low, self.u_lo + self.slope_lo * (v - self.v_lo), u)
        du = np.where(low, self.slope_lo, du)
        return u, du


# -- elasticity ----------------------------------------------------------------------------------
def influence_matrix(n, dx, E_star):
    m = np.arange(n, dtype=float)

    def g(t):
        t = np.abs(t)
        with np.errstate(divide="ignore", invalid="ignore"):
            return np.where(t > 0, t * np.log(t), 0.0) - t

    khat = -(2 / math.pi) * (g(m + 0.5) - g(m - 0.5) * np.sign(m - 0.5))
    # g is odd in t: g(-1/2) = -g(1/2), so m = 0 gives 2 g(1/2)
    return (dx / E_star) * toeplitz(khat)


# -- line contact --------------------------------------------------------------------------------
@dataclass
class BaselineResult:
    x: np.ndarray
    pressure: np.ndarray
    p0_ratio: float
    w_over_s: float
    converged: bool
    nfev: int
    residual: float


def _measures(x, p, dx, p0_hertz):
    i = int(np.argmax(p))
    a, b, c = p[i - 1], p[i], p[i + 1]
    den = a - 2 * b + c
    p0 = b - 0.25 * (a - c) * (0.5 * (a - c) / den) if den < 0 else b
    xc = np.dot(x, p) / p.sum()
    s = math.sqrt(np.dot((x - xc) ** 2, p) / p.sum() + dx * dx / 12)
    half = 0.5 * p0
    above = np.nonzero(p >= half)[0]
    i, j = above[0], above[-1]
    xl = x[i - 1] + (half - p[i - 1]) * dx / (p[i] - p[i - 1])
    xr = x[j] + (half - p[j]) * dx / (p[j + 1] - p[j])
    return p0 / p0_hertz, (xr - xl) / s


def solve(table: SeparationTable, E_star, radius, load, n=128, tol=1e-10):
    """Solve u_law(p) = u1 + x^2/2R + K p, sum p dx = f_N with scipy.optimize.root (hybr)."""
    delta = 4 * load / (math.pi * E_star)
    a = math.sqrt(radius * delta)
    p0h = math.sqrt(E_star * load / (math.pi * radius))
    u0 = table.u0
    sg = math.sqrt(radius * u0)
    L = 1.25 * a + 8 * sg
    dx = 2 * L / n
    x = (np.arange(n) - 0.5 * (n - 1)) * dx
    g = x * x / (2 * radius)
    K = influence_matrix(n, dx, E_star)
    # initial guess: Hertz and Gaussian profiles blended in log space
    alpha_ = table.u0 / 0.4 / delta
    wg = alpha_ / (alpha_ + 0.3)
    with np.errstate(divide="ignore"):
        lh = math.log(1 - wg) + math.log(p0h) + 0.5 * np.log(np.maximum(1 - (x / a) ** 2, 0))
    s_g = sg
    lg = math.log(wg) + math.log(load / (s_g * math.sqrt(2 * math.pi))) - x * x / (2 * s_g**2)
    v_init = np.logaddexp(lh, lg)
    v_init += math.log(load / dx) - np.log(np.exp(v_init).sum())
    p_init = np.exp(v_init)
    u_init, _ = table(v_init)
    u1_init = np.dot(p_init, u_init - g - K @ p_init) / p_init.sum()
    z0 = np.append(v_init, u1_init / u0)

    def fun(z):
        v, u1 = z[:-1], z[-1] * u0
        p = np.exp(v)
        u, _ = table(v)
        r = (u - u1 - g - K @ p) / u0
        return np.append(r, math.log(p.sum() * dx / load))

    def jac(z):
        v = z[:-1]
        p = np.exp(v)
        _, du = table(v)
        J = np.empty((n + 1, n + 1))
        J[:n, :n] = -(K * p[None, :]) / u0
        J[np.arange(n), np.arange(n)] += du / u0
        J[:n, n] = -1.0
        J[n, :n] = p / p.sum()
        J[n, n] = 0.0
        return J

    sol = root(fun, z0, jac=jac, method="hybr", tol=tol)
    res = float(np.max(np.abs(fun(sol.x)[:-1])))
    p = np.exp(sol.x[:-1])
    p0r, ws = _measures(x, p, dx, p0h)
    return BaselineResult(x, p, p0r, ws, bool(sol.success), int(sol.nfev), res)
