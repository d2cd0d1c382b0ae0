"""The line-contact solver: nominal pressure p(x) under a cylinder (docs/theory.md section 4).

Equations (paper eqs. 3-4): unknown pressure ``p(x) > 0`` and rigid approach ``u1`` with

    u(x) = u1 + x^2/(2R) + (K p)(x),     u(x) = u_law(p(x)),     int p dx = f_N,

``K`` the plane-strain log kernel (:mod:`fastline.elastic`), ``u_law`` the model's separation.

Methods
-------
``method="newton"`` (default)
    Newton's method on ``v = ln p`` (p > 0 for free, 100+ decades from the centre to the edge
    without underflow) in the u(p) form ``r = u_law(p) - (u1 + x^2/2R + K p)``. With
    ``dp = p dv`` each step solves ``(D + K) dp + du1 = r``, ``sum(dp) = 0`` (the load is
    restored exactly by a log-sum-exp normalisation of v after the step), ``D = |du_law/dp|``:
    symmetric positive definite on zero-load increments (docs/theory.md section 4), solved by
    projected preconditioned conjugate gradients with K applied by FFT, to a
    relative accuracy that tightens as Newton converges (inexact Newton, Eisenstat-Walker
    forcing). The preconditioner inverts a circulant of K on the loaded core (where K
    dominates) and D + K00 elsewhere. A backtracking line search on ``||r||`` keeps it robust.
    Cost is counted in FFT convolutions of length 2n (K products and preconditioner solves).
``method="picard"``
    The plain damped fixed point ``p <- p_law(u1 + x^2/2R + K p)`` (damped in ln p), with u1
    re-solved each sweep so the force balance holds exactly. Kept for comparison: it slows down
    like ``1/alpha`` in the Hertz-like regime.
``model="hertz"``
    Smooth surfaces, hard contact: ``p >= 0``, gap ``>= 0``, ``p * gap = 0``, solved by a
    constrained conjugate gradient (the Polonsky-Keer scheme, Wear 231, 206 (1999)).
"""

from __future__ import annotations

import math
import warnings
from dataclasses import dataclass, field

import numpy as np

from fastline._validate import finite_scalar, integer, positive
from fastline.diagnostics import assess
from fastline.elastic import LogKernelOperator, log_reference_shift
from fastline.limits import gaussian_line_contact, hertz_line_contact
from fastline.models import ExponentialModel, PerssonModel
from fastline.persson import PerssonTheory
from fastline.spectra import PSD

__all__ = [
    "ConvergenceWarning",
    "LineContactResult",
    "solve_line_contact",
    "profile",
    "w_over_s",
    "p0_ratio",
]

MODELS = ("persson", "exponential", "hertz")
METHODS = ("newton", "picard")
DEFAULT_N = 1024
_MAX_NEWTON = 100
_MAX_PICARD_SWEEPS = 20000
_LN_TINY = math.log(1e-300)
ETA_MAX, ETA_FLOOR = 0.1, 1e-3  # inexact-Newton forcing term bounds
_MAX_CG = 400
#: largest change of ln p per Newton step where p > 1e-6 max(p) (2 cost 5% more convolutions
#: over 40 hard scenes and up to 1.7x more near alpha = 0.1; 8 keeps a guard against overflow)
_DV_MAX = 8.0
#: core block of the preconditioner: cells with |du/dp| < CORE_THETA * K00. Measured totals over
#: 20 hard scenes (4 surfaces x alpha 1e-4..0.1, n = 1024): 3 -> 1262, 6 -> 1277, 10 -> 1407
#: convolutions; at n = 8192, 10 did better (1738 vs 1873). 0.1 and 0.3 lost up to 2x at 1e-2.
CORE_THETA = 3.0
_CORE_MIN_CELLS = 8


class ConvergenceWarning(RuntimeWarning):
    """A solve stopped before reaching its tolerance (``converged=False``)."""


@dataclass
class LineContactResult:
    """The solution of one line-contact scene and what follows from it.

    Arrays are on the solver grid (cell centres). Units: m, Pa, N/m.

    Attributes
    ----------
    x : ndarray
        Grid coordinates in m (symmetric about 0).
    pressure : ndarray
        Nominal contact pressure p(x) in Pa.
    separation : ndarray
        Mean interfacial separation u(x) in m (the gap for ``model="hertz"``).
    real_area : ndarray or None
        Real contact area fraction P(q1, p(x)) from the Persson theory (1 inside and 0 outside
        the contact for ``model="hertz"``; None for the exponential model without a theory).
    p0 : float
        Peak pressure in Pa.
    s : float
        Standard deviation of p(x) about its centroid in m.
    fwhm : float
        Full width at half maximum in m.
    w_over_s, p0_ratio : float
        ``fwhm / s`` and ``p0 / p0_Hertz``.
    alpha, delta : float
        ``alpha = h_rms / delta`` and the Hertz penetration ``delta = 4 f_N / (pi E*)`` in m.
    u1 : float
        Rigid approach in m, with the logarithm's reference length R (a constant offset).
    converged : bool
        Whether the residual fell below ``tol``.
    iterations, convolutions : int
        Outer iterations (Newton steps, sweeps) and FFT convolutions of length 2n: applications
        of K plus the preconditioner's circulant solves (``diagnostics`` splits the two as
        ``k_applications`` and ``circulant_solves``).
    residual : float
        Final residual: max |u_law(p) - u1 - x^2/2R - K p| / u0 (for hertz: the
        complementarity error relative to delta).
    message : str
        What happened.
    """

    x: np.ndarray
    pressure: np.ndarray
    separation: np.ndarray
    real_area: np.ndarray | None
    p0: float
    s: float
    fwhm: float
    w_over_s: float
    p0_ratio: float
    alpha: float
    delta: float
    u1: float
    converged: bool
    iterations: int
    convolutions: int
    residual: float
    message: str
    model: str
    method: str
    load: float
    radius: float
    E_star: float
    dx: float
    force_error: float
    edge_pressure: float
    diagnostics: dict = field(default_factory=dict)

    def __repr__(self):
        return (
            f"LineContactResult(model={self.model!r}, alpha={self.alpha:.4g}, p0={self.p0:.6g} Pa,"
            f" w_over_s={self.w_over_s:.5g}, p0_ratio={self.p0_ratio:.5g}, "
            f"converged={self.converged}, convolutions={self.convolutions})"
        )


# ----------------------------------------------------------------------------------------------
# theory cache: seal codes call the solver thousands of times with the same spectrum
# ----------------------------------------------------------------------------------------------
_THEORIES: dict = {}


def _theory_for(psd: PSD, E_star: float, gamma: float) -> PerssonTheory:
    key = (id(psd), E_star, gamma)
    hit = _THEORIES.get(key)
    if hit is not None and hit[0] is psd:
        return hit[1]
    th = PerssonTheory(psd, E_star, gamma=gamma)
    if len(_THEORIES) >= 32:
        _THEORIES.pop(next(iter(_THEORIES)))
    _THEORIES[key] = (psd, th)
    return th


# ----------------------------------------------------------------------------------------------
# profile measures
# ----------------------------------------------------------------------------------------------
def _peak(x, p):
    """Peak value by a parabola through the three points around the discrete maximum."""
    i = int(np.argmax(p))
    if 0 < i < p.size - 1:
        a, b, c = p[i - 1], p[i], p[i + 1]
        den = a - 2.0 * b + c
        if den < 0.0:
            t = 0.5 * (a - c) / den
            return b - 0.25 * (a - c) * t
    return float(p[i])


def _fwhm(x, p, p0):
    """Width between the outermost half-maximum crossings (linear interpolation)."""
    half = 0.5 * p0
    above = np.nonzero(p >= half)[0]
    i, j = above[0], above[-1]
    if i == 0 or j == p.size - 1:
        return float("nan")
    xl = x[i - 1] + (half - p[i - 1]) * (x[i] - x[i - 1]) / (p[i] - p[i - 1])
    xr = x[j] + (half - p[j]) * (x[j + 1] - x[j]) / (p[j + 1] - p[j])
    return float(xr - xl)


def _std(x, p, dx):
    """Standard deviation of piecewise-constant p about its centroid (cell-exact)."""
    m0 = p.sum()
    xc = np.dot(x, p) / m0
    var = np.dot((x - xc) ** 2, p) / m0 + dx * dx / 12.0
    return math.sqrt(var)


# ----------------------------------------------------------------------------------------------
# Newton on v = ln p
# ----------------------------------------------------------------------------------------------
class _CorePreconditioner:
    """M^-1 ~ (D + K)^-1, block-diagonal (symmetric positive definite).

    * Loaded core, the cells from the first to the last with ``D < CORE_THETA * K00``: there
      the elastic compliance dominates and ``K`` restricted to the block is a Toeplitz matrix.
      It is replaced by the Strang circulant of ``K + median(D) I`` (size 2n, exact inverse by
      FFT; :meth:`fastline.elastic.LogKernelOperator.circulant_inverse`). This flattens the
      log kernel's spread of eigenvalues (~n on the core) that Jacobi leaves to CG.
    * Elsewhere, Jacobi ``1/(D + K00)``: where ``D >> K00`` the rows are nearly decoupled.

    Each application of the core block costs one FFT convolution (counted). Measured at n =
    1024 (surface 1): CG steps per Newton step fall from 13-25 to 3-8 for alpha <= 1e-2.
    """

    def __init__(self, op, D):
        self.minv = 1.0 / (D + op.diagonal)
        core = np.flatnonzero(D < CORE_THETA * op.diagonal)
        self.core = None
        if core.size >= _CORE_MIN_CELLS:
            i0, i1 = int(core[0]), int(core[-1]) + 1
            self.core = slice(i0, i1)
            self.cinv = op.circulant_inverse(float(np.median(D[i0:i1])))

    def __call__(self, y):
        out = self.minv * y
        if self.core is not None:
            self.cinv.apply(y[self.core], out[self.core])
        return out


def _projected_pcg(op, D, rhs, prec, rtol, maxit):
    """Solve (D + K) dp + du1 = rhs, sum(dp) = 0 by projected PCG.

    The projection keeps every search direction at zero net load, so CG works on the subspace
    where D + K is positive definite; du1 is the multiplier. (The load itself is restored
    exactly by the log-sum-exp normalisation after the step, so the increment carries none.)
    Returns dp, du1, iterations.
    """
    m1 = prec(np.ones_like(rhs))
    sm = m1.sum()
    dp = np.zeros_like(rhs)
    res = rhs.copy()

    def proj(y):
        my = prec(y)
        lam = my.sum() / sm
        return my - lam * m1, lam

    z, lam = proj(res)
    rz = np.dot(res, z)
    rz0 = rz
    d = z.copy()
    it = 0
    while it < maxit and rz > rtol * rtol * rz0 and rz > 0.0:
        Hd = D * d + op.apply(d)
        a = rz / np.dot(d, Hd)
        dp += a * d
        res -= a * Hd
        z, lam = proj(res)
        rz_new = np.dot(res, z)
        d = z + (rz_new / rz) * d
        rz = rz_new
        it += 1
    return dp, lam, it


def _normalise(v, f_N, dx):
    """Shift v so that sum(exp(v)) dx = f_N exactly (log-sum-exp)."""
    vmax = v.max()
    return v + (math.log(f_N / dx) - (vmax + math.log(np.exp(v - vmax).sum())))


def _pressure_of(v):
    """exp(v), flushed to 0 below 1e-300 Pa (subnormals only slow the arithmetic down)."""
    return np.where(v > _LN_TINY, np.exp(np.maximum(v, _LN_TINY)), 0.0)


def _forcing(res, res_prev, eta_prev, tol):
    """Relative accuracy of the inner linear solve (inexact Newton).

    Eisenstat & Walker's choice 2 (SIAM J. Sci. Comput. 17, 16 (1996)): loose while the residual
    falls slowly, tight when Newton converges fast; never tighter than ``ETA_FLOOR`` nor than
    what is needed to reach ``tol`` in this step. Against a fixed 1e-2 it saved 5% of the
    convolutions over 40 hard scenes at n = 1024 (total 1565 -> 1487, worst 99 -> 90).
    """
    if math.isnan(res_prev):
        eta = ETA_MAX
    else:
        eta = 0.9 * (res / res_prev) ** 2  # Eisenstat-Walker choice 2
        if 0.9 * eta_prev**2 > 0.1:
            eta = max(eta, 0.9 * eta_prev**2)
    return min(ETA_MAX, max(eta, ETA_FLOOR, 0.5 * tol / res))


def _newton(model, op, g, f_N, dx, v, u_ref, tol, max_iter):
    p = _pressure_of(v)
    U, dU = model.u_and_slope(v)
    Kp = op.apply(p)
    u1 = np.dot(p, U - g - Kp) / p.sum()
    r = U - u1 - g - Kp
    phi = np.linalg.norm(r)
    it = 0
    cg_total = 0
    res_prev = eta = math.nan
    while True:
        res = float(np.max(np.abs(r))) / u_ref
        if res < tol:
            message = f"converged: residual {res:.2e} < tol {tol:.1e} after {it} Newton steps"
            return v, u1, r, res, True, it, message, {"cg_iterations": cg_total}
        if it >= max_iter:
            message = f"not converged: residual {res:.2e} after {it} Newton steps (max_iter)"
            return v, u1, r, res, False, it, message, {"cg_iterations": cg_total}
        it += 1
        psafe = np.maximum(p, 1e-300)
        absdU = np.maximum(-dU, 1e-300 * u_ref)
        D = np.minimum(absdU / psafe, 1e300)
        eta = _forcing(res, res_prev, eta, tol)
        res_prev = res
        prec = _CorePreconditioner(op, D)
        dp, du1, cg_its = _projected_pcg(op, D, r, prec, eta, _MAX_CG)
        cg_total += cg_its
        dv = dp / psafe
        # backtracking line search on ||r||
        # limit the change of ln p where the pressure matters (elsewhere u_law is ~linear in v)
        core = p > 1e-6 * p.max()
        t = min(1.0, _DV_MAX / max(1e-300, float(np.max(np.abs(dv[core])))))
        for _ in range(30):
            v_new = _normalise(v + t * dv, f_N, dx)
            p_new = _pressure_of(v_new)
            U_new, dU_new = model.u_and_slope(v_new)
            Kp_new = op.apply(p_new)
            u1_new = u1 + t * du1
            r_new = U_new - u1_new - g - Kp_new
            phi_new = np.linalg.norm(r_new)
            if phi_new < (1.0 - 1e-4 * t) * phi or t < 1e-6:
                break
            t *= 0.5
        v, p, U, dU, Kp, u1, r, phi = v_new, p_new, U_new, dU_new, Kp_new, u1_new, r_new, phi_new


# ----------------------------------------------------------------------------------------------
# plain damped fixed point (for comparison)
# ----------------------------------------------------------------------------------------------
def _solve_u1(model, base, f_N, dx, u1):
    """u1 such that sum(p_law(u1 + base)) dx = f_N (monotone; Newton on ln of the load)."""
    target = math.log(f_N / dx)
    for _ in range(200):
        with np.errstate(over="ignore"):
            p = model.pressure(u1 + base)
            tot = p.sum()
        if not math.isfinite(tot):
            u1 += 10.0 * model.u0
            continue
        if tot <= 0.0:
            u1 -= 10.0 * model.u0
            continue
        # d ln(sum p)/du1 = sum(dp/du)/sum(p); dp/du = p / (du/dv)
        _, dU = model.u_and_slope(np.log(np.maximum(p, 1e-300)))
        slope = np.sum((p / tot) / dU)
        step = (math.log(tot) - target) / slope
        u1 -= step
        if abs(step) < 1e-14 * model.u0:
            break
    return u1


def _picard(model, op, g, f_N, dx, v, u_ref, tol, max_iter, omega=0.5):
    """Damped fixed point in ln p; the damping halves whenever the residual grows (and recovers
    slowly while it falls), which keeps the plain loop from blowing up in the stiff regime."""
    p = np.exp(v)
    U, _ = model.u_and_slope(v)
    Kp = op.apply(p)
    u1 = np.dot(p, U - g - Kp) / p.sum()
    res_old = math.inf
    for it in range(1, max_iter + 1):
        base = g + Kp
        u1 = _solve_u1(model, base, f_N, dx, u1)
        v_law = np.log(np.maximum(model.pressure(u1 + base), 1e-300))
        v_new = _normalise((1.0 - omega) * v + omega * v_law, f_N, dx)
        p_new = np.exp(v_new)
        Kp_new = op.apply(p_new)
        U, _ = model.u_and_slope(v_new)
        r = U - u1 - g - Kp_new
        res = float(np.max(np.abs(r))) / u_ref
        if res > res_old and omega > 1e-6:
            omega *= 0.5  # reject the sweep, retry with more damping
            continue
        v, p, Kp, res_old = v_new, p_new, Kp_new, res
        omega = min(0.5, 1.2 * omega)
        if res < tol:
            msg = f"converged: residual {res:.2e} < tol {tol:.1e} after {it} sweeps"
            return v, u1, r, res, True, it, msg, {"damping": omega}
    msg = f"not converged: residual {res_old:.2e} after {max_iter} sweeps (max_iter)"
    return v, u1, r, res_old, False, max_iter, msg, {"damping": omega}


# ----------------------------------------------------------------------------------------------
# hard contact (smooth surfaces)
# ----------------------------------------------------------------------------------------------
def _hertz_cg(op, g, f_N, dx, delta, tol, max_iter):
    """Constrained conjugate gradient for hard frictionless contact (Polonsky & Keer 1999)."""
    n = g.size
    # start: uniform pressure on the central third of the domain (inside the Hertz width)
    p = np.where(np.abs(np.arange(n) - 0.5 * (n - 1)) <= n / 6.0, 1.0, 0.0)
    p *= f_N / (p.sum() * dx)
    d = np.zeros(n)
    G_old = 1.0
    restart = True
    it = 0
    while it < max_iter:
        it += 1
        h = g + op.apply(p)
        c = p > 0.0
        hbar = h[c].mean()
        r = np.where(c, h - hbar, 0.0)
        G = np.dot(r, r)
        d = np.where(c, r + (0.0 if restart else G / G_old) * d, 0.0)
        G_old = G
        t = op.apply(d)
        t = np.where(c, t - t[c].mean(), 0.0)
        td = np.dot(t, d)
        tau = np.dot(r, d) / td if td > 0.0 else 0.0
        p_old = p
        p = np.maximum(p - tau * d, 0.0)
        entering = (~c) & (h - hbar < 0.0)
        restart = bool(np.any(entering))
        p = np.where(entering, p - tau * (h - hbar), p)
        p *= f_N / (p.sum() * dx)
        change = np.abs(p - p_old).sum() * dx / f_N
        if change < tol:
            break
    h = g + op.apply(p)
    c = p > 0.0
    u1 = -h[c].mean()
    gap = h + u1
    err = max(float(np.max(np.abs(gap[c]))), float(max(0.0, -gap.min()))) / delta
    converged = change < tol
    msg = (
        f"{'converged' if converged else 'not converged'}: pressure change {change:.2e} "
        f"(tol {tol:.1e}) after {it} iterations"
    )
    return p, u1, gap, err, converged, it, msg


# ----------------------------------------------------------------------------------------------
# public API
# ----------------------------------------------------------------------------------------------
def solve_line_contact(
    psd: PSD | None,
    E_star,
    radius,
    load,
    *,
    model: str = "persson",
    method: str = "newton",
    n: int = DEFAULT_N,
    half_width=None,
    tol: float = 1e-8,
    max_iter: int | None = None,
    gamma: float = 0.45,
    u0=None,
    beta=None,
    theory: PerssonTheory | None = None,
    hardness=None,
    warn: bool = True,
) -> LineContactResult:
    """Solve for the nominal pressure under a rigid cylinder on a rough elastic half-space.

    Parameters
    ----------
    psd : PSD or None
        Combined roughness spectrum; None only with ``model="hertz"`` (smooth surfaces).
    E_star : float
        Effective modulus in Pa (paper eq. 1).
    radius : float
        Cylinder radius R in m.
    load : float
        Normal load per unit length f_N in N/m.
    model : {"persson", "exponential", "hertz"}
        p(u) relation: full Persson theory, the exponential law (paper eq. 5, u0 and beta from
        the theory unless given), or hard contact of smooth surfaces.
    method : {"newton", "picard"}
        Accelerated Newton-Krylov (default) or the plain damped fixed point.
    n : int
        Grid points (>= 16); default 1024.
    half_width : float, optional
        Half-width of the computational domain in m; default ``1.25 a + 8 s`` with the Hertz
        half-width ``a`` and the Gaussian width ``s = sqrt(R u0)``.
    tol : float
        Residual tolerance (separation mismatch in units of u0; for hertz the relative pressure
        change), in (0, 1e-2].
    max_iter : int, optional
        Newton steps / fixed-point sweeps allowed (defaults 100 / 20000).
    gamma : float
        Yang-Persson parameter of the theory, in (0, 1].
    u0, beta : float, optional
        Exponential-law parameters for ``model="exponential"`` (m, dimensionless).
    theory : PerssonTheory, optional
        A prebuilt theory (must match psd and E_star); otherwise one is built and cached.
    hardness : float, optional
        Indentation hardness of the softer solid in Pa: the diagnostics warn when the elastic
        mean asperity pressure h' E*/2 exceeds it (plastic flow of asperities likely).
    warn : bool
        Emit a ``ConvergenceWarning`` when the solve does not converge, and the diagnostics'
        ``ValidityWarning`` s, one per cause (see :func:`fastline.diagnostics.assess`).

    Returns
    -------
    LineContactResult
    """
    E_star = positive("E_star", E_star, "Pa")
    radius = positive("radius", radius, "m")
    load = positive("load", load, "N/m")
    if model not in MODELS:
        raise ValueError(f"model must be one of {MODELS}, got {model!r}")
    if method not in METHODS:
        raise ValueError(f"method must be one of {METHODS}, got {method!r}")
    n = integer("n", n, 16)
    tol = finite_scalar("tol", tol)
    if not 0.0 < tol <= 1e-2:
        raise ValueError(f"tol must lie in (0, 1e-2], got {tol!r}")
    if max_iter is not None:
        max_iter = integer("max_iter", max_iter, 1)
    if psd is None and model != "hertz":
        raise ValueError(f"psd must be a PSD for model={model!r} (None is allowed for 'hertz')")
    if psd is not None and not isinstance(psd, PSD):
        raise ValueError(f"psd must be a fastline PSD or None, got {type(psd).__name__}")

    hz = hertz_line_contact(E_star, radius, load)
    delta, a = hz.delta, hz.a
    h_rms = psd.h_rms if psd is not None else 0.0
    alpha = h_rms / delta

    if model == "hertz":
        mdl = None
        u_ref = delta
        s_g = 0.0
    else:
        if theory is None:
            theory = _theory_for(psd, E_star, finite_scalar("gamma", gamma))
        elif theory.psd is not psd or theory.E_star != E_star:
            raise ValueError("theory must be built for the same psd and E_star")
        if model == "persson":
            mdl = PerssonModel(theory)
        else:
            fit = theory.exponential_fit()
            u0v = fit.u0 if u0 is None else positive("u0", u0, "m")
            bv = fit.beta if beta is None else positive("beta", beta)
            mdl = ExponentialModel(u0v, bv, E_star, theory)
        u_ref = mdl.u0
        s_g = math.sqrt(radius * mdl.u0)

    if half_width is None:
        half_width = 1.25 * a + 8.0 * s_g
    else:
        half_width = positive("half_width", half_width, "m")
    dx = 2.0 * half_width / n
    x = (np.arange(n) - 0.5 * (n - 1)) * dx
    g = x * x / (2.0 * radius)
    op = LogKernelOperator(n, dx, E_star)

    if model == "hertz":
        p, u1, sep, res, ok, it, msg = _hertz_cg(op, g, load, dx, delta, tol, max_iter or 10 * n)
        real = (p > 0.0).astype(float)
        extra = {}
    else:
        # initial guess: Hertz and Gaussian profiles blended in log space
        gs = gaussian_line_contact(mdl.u0, radius, load)
        wg = alpha / (alpha + 0.3)
        with np.errstate(divide="ignore"):
            lh = np.log(1.0 - wg) + np.log(hz.p0) + 0.5 * np.log(np.maximum(1 - (x / a) ** 2, 0))
        lg = math.log(wg) + math.log(gs.p0) - x * x / (2.0 * gs.s**2)
        v = _normalise(np.logaddexp(lh, lg), load, dx)
        if method == "newton":
            out = _newton(mdl, op, g, load, dx, v, u_ref, tol, max_iter or _MAX_NEWTON)
        else:
            out = _picard(mdl, op, g, load, dx, v, u_ref, tol, max_iter or _MAX_PICARD_SWEEPS)
        v, u1, r, res, ok, it, msg, extra = out
        p = np.exp(v)
        sep = mdl.u_and_slope(v)[0]
        real = mdl.real_area(p)

    p0 = _peak(x, p)
    s = _std(x, p, dx)
    w = _fwhm(x, p, p0)
    force_error = abs(p.sum() * dx - load) / load
    edge = float(max(p[0], p[-1]) / p0)
    u1_R = u1 + log_reference_shift(load, dx, E_star, radius)
    if not ok and warn:
        warnings.warn(f"fastline: {msg}", ConvergenceWarning, stacklevel=2)
    result = LineContactResult(
        x=x,
        pressure=p,
        separation=sep,
        real_area=real,
        p0=p0,
        s=s,
        fwhm=w,
        w_over_s=w / s,
        p0_ratio=p0 / hz.p0,
        alpha=alpha,
        delta=delta,
        u1=u1_R,
        converged=bool(ok),
        iterations=int(it),
        convolutions=int(op.convolutions),
        residual=float(res),
        message=msg,
        model=model,
        method=method,
        load=load,
        radius=radius,
        E_star=E_star,
        dx=dx,
        force_error=force_error,
        edge_pressure=edge,
        diagnostics={
            "n": n,
            "domain_half_width": half_width,
            "k_applications": op.convolutions - op.circulant_solves,
            "circulant_solves": op.circulant_solves,
            **extra,
        },
    )
    result.diagnostics.update(assess(result, theory, hardness, warn=warn))
    return result


def profile(psd, E_star, radius, load, **kwargs):
    """Pressure profile ``(x [m], p [Pa])`` of one scene (see :func:`solve_line_contact`)."""
    res = solve_line_contact(psd, E_star, radius, load, **kwargs)
    return res.x, res.pressure


def _per_load(attr, psd, E_star, radius, load, kwargs):
    loads = np.asarray(load, dtype=np.float64)
    if loads.ndim == 0:
        return getattr(solve_line_contact(psd, E_star, radius, float(loads), **kwargs), attr)
    out = np.empty(loads.shape)
    for i, f in np.ndenumerate(loads):
        out[i] = getattr(solve_line_contact(psd, E_star, radius, float(f), **kwargs), attr)
    return out


def w_over_s(psd, E_star, radius, load, **kwargs):
    """FWHM-to-standard-deviation ratio w/s; a float, or an array for an array of loads."""
    return _per_load("w_over_s", psd, E_star, radius, load, kwargs)


def p0_ratio(psd, E_star, radius, load, **kwargs):
    """Peak-pressure ratio p0(rough)/p0(Hertz); a float, or an array for an array of loads."""
    return _per_load("p0_ratio", psd, E_star, radius, load, kwargs)
