"""Resolution by accuracy: the grid chosen for a wanted relative error, and error estimates.

``LineContact(..., accuracy=1e-4)`` solves each load on a sequence of grids over one domain
until the estimated relative error of p0, s and w/s is below the accuracy asked for; every
result then carries an :class:`ErrorEstimate` (``result.error_estimate``). For a result solved
on a fixed grid, :meth:`fastline.LineContact.estimate_error` gives the same estimate on demand.

How the error is estimated (measured in docs/accuracy.md, which has the tables):

* **Discretisation** - Richardson extrapolation (L. F. Richardson, Phil. Trans. R. Soc. A 210,
  307 (1911), doi:10.1098/rsta.1911.0009) from the result and a *companion* solve with half
  the cells on the same domain. The discrete solution converges at order 2 in the cell width
  h: p0, s and the FWHM measured exactly on the discrete solution fall by 4.00 +- 0.03 per
  halving of h from 256 cells on, over the paper's surfaces at alpha 1e-3..1e3. Then
  ``Q_h - Q = (Q_2h - Q_h) / 3`` to leading order.
* **Measurement** - the reported p0 (a parabola through the three points around the maximum)
  and FWHM (linear interpolation of the half-maximum crossings) add an interpolation error to
  that of the solution. For the FWHM it depends on where the crossing falls inside its cell
  and jumps from one grid to the next (observed "orders" -2.6..9.7): Richardson on the reported
  FWHM is off by up to 100x. So each measure is also taken to higher order on the same
  solution (the peak of the quartic through five points, the crossings of the cubic through
  four) and the estimate is ``(Q_h - Q_h^hi) + (Q_2h^hi - Q_h^hi) / 3``: interpolation error
  from the solution itself, discretisation error by Richardson on the smooth part.
* **Domain truncation** - the load left outside the domain, from the edge pressures and the
  decay of the tails (:func:`truncation_errors`; measured within 0.44-1.3 of the true effect).
* **Solver** - the final residual (separation mismatch in units of u0, i.e. the error in
  ln p).

The total for each quantity is ``|measurement + discretisation + truncation| + solver`` (the
signed parts can cancel: a domain cut short lowers s, the grid's Sheppard term raises it).
With ``accuracy=`` 1e-2..1e-6 on the paper's surfaces (alpha 1e-3..1e3) and campaign-like
scenes (O-rings, low-H wide-band spectra) the estimate is 0.82-1.54 times the true error (250
comparisons, errors above 1 % of the accuracy; tests/test_resolution.py holds a factor 3). It
is an estimate of the error, not a bound; ``accuracy=`` therefore accepts a grid when the
estimate is below ``accuracy / ACCEPT_MARGIN``: the largest true error was 0.49 accuracy.

The accuracy loop (:func:`solve_to_accuracy`): the domain half-width is ``1.25 a + c sqrt(R
u0)`` with ``c`` set by the accuracy (edge pressure about a tenth of it; the default domain
uses c = 8, good for 1e-13), the first grid is predicted from the Hertz and Gaussian widths,
each further grid from the order-2 estimate. Grids have ``2^k`` or ``3 2^k`` cells (FFT sizes).
Each grid's result is solved from cold (so it equals a plain solve on that grid, bit for bit);
its companion starts from it; when the cell count doubled, the previous result is the
companion. Where a grid under-resolved the peak (the a-priori widths were far off: a needle, a
full-contact core), an accepted grid is confirmed by one twice as fine.
"""

from __future__ import annotations

import math
import warnings
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

import numba
import numpy as np

from fastline._lib.jit import JIT
from fastline._lib.validate import finite_scalar
from fastline.contact.diagnostics import RESOLUTION_CELLS
from fastline.contact.model import fwhm, peak, std
from fastline.errors import AccuracyWarning
from fastline.theory.limits import hertz_line_contact

if TYPE_CHECKING:  # pragma: no cover
    from fastline.contact.line import LineContact, LineContactResult

__all__ = [
    "ACCURACY_RANGE",
    "ACCEPT_MARGIN",
    "AccuracyWarning",
    "ErrorEstimate",
    "estimate_error",
    "solve_to_accuracy",
    "sweep_to_accuracy",
]

#: relative accuracies accepted by ``accuracy=``: below 1e-8 the solver tolerance and the
#: theory's table (rtol 1e-6 in u, common to every grid) dominate what a finer grid can give
ACCURACY_RANGE = (1e-8, 0.1)
#: a grid is accepted when every estimate is below accuracy / ACCEPT_MARGIN: the estimate is
#: centred on the true error (measured ratio estimate/true 0.82-1.54, module docstring), so a
#: margin of 2 keeps the true error below the accuracy asked for (largest measured: 0.49)
ACCEPT_MARGIN = 2.0
#: order of convergence of the discrete solution in the cell width (measured: 4.00 +- 0.03 per
#: halving for p0, s and the high-order FWHM, paper surfaces, alpha 1e-3..1e3, n >= 256)
ORDER = 2
#: fewest cells across the FWHM of a grid whose estimate is trusted: its companion then has
#: RESOLUTION_CELLS (8), where the paper's scenes are in the asymptotic range
RESOLVED_CELLS = 2.0 * RESOLUTION_CELLS
#: share of the wanted accuracy left to domain truncation when the domain is sized
TRUNCATION_SHARE = 0.1
#: the domain is widened when the truncation estimate exceeds this share of the wanted accuracy
WIDEN_SHARE = 0.25
#: a-priori error model of the first grid (only the first: later grids follow the estimate):
#: relative error ~ C (h/s)^2, s = sqrt((a/2)^2 + R u0) from the Hertz and Gaussian limits and
#: C = PRIOR_C sqrt(1 + PRIOR_EDGE a / sqrt(R u0)). Fitted to the smallest grids that met
#: accuracies 1e-4..1e-6 on the paper's surfaces: C ~ 0.06 Gaussian-like, 0.09 at alpha 0.1,
#: 0.15 at 0.01, 0.2-0.25 at 1e-3 (the contact edge sets the error there)
PRIOR_C, PRIOR_EDGE = 0.06, 0.25
#: fewest cells of an accepted grid (its companion has half): with 64-128 cells the companion of
#: a Hertz-like scene is pre-asymptotic (estimates off by up to 26x at alpha 1e-3, n = 128)
MIN_N = 256
#: most cells the accuracy loop tries (~130 MB of working arrays)
MAX_N = 2**18
#: most grids solved per load (the loop refines at most 8x per step)
MAX_LEVELS = 12
#: the largest refinement factor per step (a pre-asymptotic estimate can ask for far more)
MAX_STEP = 8.0


@dataclass(frozen=True)
class ErrorEstimate:
    """Estimated relative errors of a line-contact result, and how they were obtained.

    Attributes
    ----------
    p0, s, fwhm, w_over_s : float
        Estimated relative error of each quantity (>= 0): ``|measurement + discretisation +
        truncation| + solver`` (module docstring).
    signed : dict
        The measurement and discretisation part with its sign, per quantity:
        ``Q_result - Q_exact ~ signed[q] * Q_result`` (so ``Q / (1 + signed[q])`` is a
        Richardson-corrected value).
    truncation : dict
        The domain-truncation part per quantity, signed like ``signed``
        (:func:`truncation_errors`).
    solver : float
        The largest final residual of the two solves (separation mismatch / u0).
    n, companion_n : int
        Cells of the result and of its companion solve (``n // 2``, or ``2 n`` when the result
        itself is too coarse to trust a coarser companion).
    half_width : float
        Domain half-width of both solves in m.
    fwhm_cells : float
        Cells across the FWHM of the result; below :data:`RESOLVED_CELLS` the estimate is less
        reliable (its companion is pre-asymptotic).
    levels : tuple of (int, int, bool)
        Every solve made for this result, in order: (cells, FFT convolutions, converged).
    accuracy : float or None
        The accuracy asked for (None for an on-demand estimate).
    met : bool or None
        Whether the estimate met ``accuracy / ACCEPT_MARGIN`` on a resolved grid with both
        solves converged (None for an on-demand estimate).
    method : str
        How the estimate was obtained, in words.
    """

    p0: float
    s: float
    fwhm: float
    w_over_s: float
    signed: dict = field(repr=False)
    truncation: dict = field(repr=False)
    solver: float
    n: int
    companion_n: int
    half_width: float
    fwhm_cells: float
    levels: tuple = field(repr=False)
    accuracy: float | None = None
    met: bool | None = None
    method: str = field(default="", repr=False)

    @property
    def worst(self) -> float:
        """The largest estimated relative error of p0, s and w/s (what ``accuracy=`` holds)."""
        return max(self.p0, self.s, self.w_over_s)

    @property
    def fft_work(self) -> int:
        """Cells times convolutions summed over every solve (a machine-independent cost: one
        convolution of 2n points costs about n log n)."""
        return sum(n * c for n, c, _ in self.levels)


def check_accuracy(accuracy) -> float | None:
    """``accuracy`` as a float in :data:`ACCURACY_RANGE`, or None."""
    if accuracy is None:
        return None
    value = finite_scalar("accuracy", accuracy)
    lo, hi = ACCURACY_RANGE
    if not lo <= value <= hi:
        raise ValueError(
            f"accuracy must lie in [{lo:g}, {hi:g}] (relative error of p0, s and w/s), "
            f"got {accuracy!r}"
        )
    return value


# ----------------------------------------------------------------------------------------------
# high-order measures of one discrete profile (the reported ones are in line_contact)
# ----------------------------------------------------------------------------------------------
@numba.njit(**JIT)
def _quartic(c, t):
    """Value and first two derivatives of ``c0 + c1 t + ... + c4 t^4``."""
    q = c[0] + t * (c[1] + t * (c[2] + t * (c[3] + t * c[4])))
    d1 = c[1] + t * (2.0 * c[2] + t * (3.0 * c[3] + t * 4.0 * c[4]))
    d2 = 2.0 * c[2] + t * (6.0 * c[3] + t * 12.0 * c[4])
    return q, d1, d2


@numba.njit(**JIT)
def _peak_quartic(p):
    """Peak of the quartic through the five points around the discrete maximum, by Newton's
    method on its slope from the parabola's vertex, kept within one cell of the maximum."""
    i = np.argmax(p)
    if i < 2 or i > p.size - 3:
        return p[i]
    a, b, f0, d, e = p[i - 2], p[i - 1], p[i], p[i + 1], p[i + 2]
    c = np.empty(5)  # exact interpolation at t = -2..2 (cells from the maximum)
    c[0] = f0
    c[1] = (a - 8.0 * b + 8.0 * d - e) / 12.0
    c[2] = (-a + 16.0 * b - 30.0 * f0 + 16.0 * d - e) / 24.0
    c[3] = (-a + 2.0 * b - 2.0 * d + e) / 12.0
    c[4] = (a - 4.0 * b + 6.0 * f0 - 4.0 * d + e) / 24.0
    if c[2] >= 0.0:
        return f0
    t = min(1.0, max(-1.0, -c[1] / (2.0 * c[2])))
    for _ in range(30):
        _, d1, d2 = _quartic(c, t)
        if d2 >= 0.0:
            break
        t_new = min(1.0, max(-1.0, t - d1 / d2))
        if abs(t_new - t) < 1e-14:
            t = t_new
            break
        t = t_new
    return max(f0, _quartic(c, t)[0])


@numba.njit(**JIT)
def _cubic_crossing(p, level, k):
    """Offset t in [0, 1] (cells from k) where the cubic through four points around cells k
    and k+1 (which bracket ``level``) crosses it: Newton's method kept inside the bracket."""
    lo = min(max(k - 1, 0), p.size - 4)
    f0, f1 = p[k] - level, p[k + 1] - level
    a, b = 0.0, 1.0
    t = f0 / (f0 - f1)  # the linear crossing
    for _ in range(40):
        g = -level
        dg = 0.0
        for j in range(4):  # Lagrange basis on the nodes lo-k .. lo-k+3
            tj = float(lo + j - k)
            den = 1.0
            prod = 1.0
            dprod = 0.0
            for m in range(4):
                if m != j:
                    tm = float(lo + m - k)
                    den *= tj - tm
                    dprod = dprod * (t - tm) + prod
                    prod *= t - tm
            g += p[lo + j] * prod / den
            dg += p[lo + j] * dprod / den
        if g == 0.0:
            break
        if (g < 0.0) == (f0 < 0.0):
            a = t
        else:
            b = t
        t_new = t - g / dg if dg != 0.0 else 0.5 * (a + b)
        if not a < t_new < b:
            t_new = 0.5 * (a + b)
        if abs(t_new - t) < 1e-14:
            return t_new
        t = t_new
    return t


@numba.njit(**JIT)
def _fwhm_cubic(p, dx, p0):
    """Width (m) between the outermost crossings of ``p0 / 2`` of the cubic interpolant;
    NaN when a crossing lies in an end cell (as for the reported FWHM)."""
    half = 0.5 * p0
    n = p.size
    i = 0
    while i < n and p[i] < half:
        i += 1
    j = n - 1
    while j > 0 and p[j] < half:
        j -= 1
    if n < 4 or i == 0 or i >= n or j == n - 1:
        return np.nan
    left = (i - 1) + _cubic_crossing(p, half, i - 1)
    right = j + _cubic_crossing(p, half, j)
    return (right - left) * dx


def peak_quartic(p: np.ndarray) -> float:
    """Peak value of the quartic through the five points around the discrete maximum of ``p``
    (the maximum itself when it lies within two cells of an end)."""
    return float(_peak_quartic(np.ascontiguousarray(p, dtype=np.float64)))


def fwhm_cubic(p: np.ndarray, dx: float, p0: float) -> float:
    """Width in m between the outermost crossings of ``p0 / 2`` of the cubic interpolant of
    ``p`` on cells of width ``dx`` (NaN when a crossing lies in an end cell)."""
    return float(_fwhm_cubic(np.ascontiguousarray(p, dtype=np.float64), float(dx), float(p0)))


def _measures(res: LineContactResult) -> dict[str, float]:
    """Reported and high-order measures of one result."""
    p0_hi = peak_quartic(res.pressure)
    return {
        "p0": res.p0,
        "p0_hi": p0_hi,
        "s": res.s,
        "fwhm": res.fwhm,
        "fwhm_hi": fwhm_cubic(res.pressure, res.dx, p0_hi),
    }


# ----------------------------------------------------------------------------------------------
# the estimate from a result and its companion
# ----------------------------------------------------------------------------------------------
def signed_errors(res: LineContactResult, comp: LineContactResult) -> dict[str, float]:
    """Measurement plus discretisation error of each quantity of ``res``, relative and signed.

    ``comp`` is the same scene on the same domain with another cell width (coarser or finer).
    For an order-2 error ``Q_h = Q + C h^2``, ``Q_h - Q = (Q_h - Q_k) / (1 - (k/h)^2)``.
    """
    mr, mc = _measures(res), _measures(comp)
    k = 1.0 / (1.0 - (comp.dx / res.dx) ** ORDER)
    p0 = (mr["p0"] - mr["p0_hi"] + k * (mr["p0_hi"] - mc["p0_hi"])) / mr["p0"]
    s = k * (mr["s"] - mc["s"]) / mr["s"]
    fwhm = (mr["fwhm"] - mr["fwhm_hi"] + k * (mr["fwhm_hi"] - mc["fwhm_hi"])) / mr["fwhm"]
    return {"p0": float(p0), "s": float(s), "fwhm": float(fwhm), "w_over_s": float(fwhm - s)}


def truncation_errors(res: LineContactResult) -> dict[str, float]:
    """Relative errors from the load the domain leaves out, per quantity, signed like
    :attr:`ErrorEstimate.signed` (``Q_result - Q_exact ~ value * Q_result``).

    The tail beyond each edge decays over ``L = dx / ln(p_1 / p_0)`` (the two outermost cells), so
    the load left out is ``m = (p_left L_left + p_right L_right) / f_N``. That load is carried
    inside instead: p0 and the FWHM rise by about m, s falls by ``ms = m (H^2/s^2 - 1) / 2`` (the
    load missing at the edge H carried H^2 of variance), w/s rises by ``m + ms``. Measured against
    wider domains (edge at 2-5 sqrt(R u0)) on the paper's surface 1 at alpha 0.1, 1 and 100, an
    O-ring and the needle scene of docs/accuracy.md: signs as stated, p0 0.44-0.96 m, s 0.89-1.11
    ms, w/s 0.8-1.3 (m + ms); the FWHM 0.01-1.0 m. A profile that does not decay at an edge gives
    inf (the domain cuts the contact).
    """
    p, dx = res.pressure, res.dx

    def tail(edge: float, inner: float) -> float:
        if edge <= 0.0:
            return 0.0
        return edge * dx / math.log(inner / edge) if inner > edge else math.inf

    m = (tail(p[0], p[1]) + tail(p[-1], p[-2])) / (p.sum() * dx)
    half_width = 0.5 * p.size * dx
    ms = m * max(1.0, 0.5 * (half_width * half_width / (res.s * res.s) - 1.0))
    m, ms = float(m), float(ms)
    return {"p0": m, "s": -ms, "fwhm": m, "w_over_s": m + ms}


def _estimate(res, comp, levels, accuracy=None) -> ErrorEstimate:
    signed = signed_errors(res, comp)
    trunc = truncation_errors(res)
    solver = max(float(res.residual), float(comp.residual))
    total = {q: abs(v + trunc[q]) + solver for q, v in signed.items()}
    total = {q: (float(v) if math.isfinite(v) else math.inf) for q, v in total.items()}
    cells = res.fwhm / res.dx if math.isfinite(res.fwhm) else 0.0
    n, nc = res.x.size, comp.x.size
    half_width = 0.5 * n * res.dx
    method = (
        f"Richardson (order {ORDER}) from n = {n} and a companion solve with n = {nc} on the "
        f"same domain (half-width {half_width:.4g} m); p0 and FWHM: interpolation error of the "
        "reported measures from the quartic peak and cubic crossings of the same solution; "
        f"truncation: load outside the domain {trunc['p0']:.2g} f_N; solver: residual "
        f"{solver:.2g}; FWHM over {cells:.3g} cells"
    )
    met = None
    if accuracy is not None:
        ok = res.converged and comp.converged and cells >= RESOLVED_CELLS
        met = bool(
            ok and max(total["p0"], total["s"], total["w_over_s"]) <= accuracy / ACCEPT_MARGIN
        )
    return ErrorEstimate(
        p0=total["p0"],
        s=total["s"],
        fwhm=total["fwhm"],
        w_over_s=total["w_over_s"],
        signed=signed,
        truncation=trunc,
        solver=solver,
        n=n,
        companion_n=nc,
        half_width=half_width,
        fwhm_cells=cells,
        levels=tuple(levels),
        accuracy=accuracy,
        met=met,
        method=method,
    )


# ----------------------------------------------------------------------------------------------
# grids
# ----------------------------------------------------------------------------------------------
def grid_size(n: float) -> int:
    """The smallest cell count ``2^k`` or ``3 2^k`` (k >= 4) that is at least ``n``."""
    k = max(4, math.ceil(math.log2(max(n, 1.0))))
    best = 2**k
    if k >= 5 and 3 * 2 ** (k - 2) >= n:
        best = 3 * 2 ** (k - 2)
    return best


def domain_half_width(model: LineContact, load: float, target: float) -> float:
    """``1.25 a + c sqrt(R u0)`` with the edge pressure ``~exp(-c^2/2)`` a tenth of ``target``
    (c = 8, the default domain, at most)."""
    a = hertz_line_contact(model.E_star, model.radius, load).a
    c = min(8.0, math.sqrt(2.0 * math.log(1.0 / (TRUNCATION_SHARE * target))))
    return 1.25 * a + c * math.sqrt(model.radius * model.law.u0)


def predicted_n(model: LineContact, load: float, half_width: float, target: float) -> int:
    """Cells for ``target`` by the a-priori model (:data:`PRIOR_C`; the first grid only)."""
    a = hertz_line_contact(model.E_star, model.radius, load).a
    gauss = math.sqrt(model.radius * model.law.u0)
    s = math.hypot(0.5 * a, gauss)
    coef = PRIOR_C * math.sqrt(1.0 + PRIOR_EDGE * a / gauss)
    return grid_size(max(MIN_N, 2.0 * half_width / (s * math.sqrt(target / coef))))


def _refined_n(res, est: ErrorEstimate, target: float) -> int:
    """Cells for the next grid: the order-2 estimate scaled to the target, enough cells across
    the FWHM, at least one size up and at most MAX_STEP times more."""
    n = res.x.size
    disc = max(abs(est.signed[q]) for q in ("p0", "s", "w_over_s"))
    budget = max(target - max(map(abs, est.truncation.values())) - est.solver, 0.25 * target)
    factor = 1.1 * math.sqrt(disc / budget) if math.isfinite(disc) else MAX_STEP
    if est.fwhm_cells < RESOLVED_CELLS:
        cells = est.fwhm_cells if est.fwhm_cells > 0 else 1.0
        factor = max(factor, 1.1 * RESOLVED_CELLS / cells)
    factor = min(max(factor, 1.0), MAX_STEP)
    return grid_size(max(n * factor, n + 1))


# ----------------------------------------------------------------------------------------------
# the accuracy loop
# ----------------------------------------------------------------------------------------------
@dataclass
class _Profile:
    """The measures of a companion solve (no separation, real area or diagnostics)."""

    x: np.ndarray
    dx: float
    pressure: np.ndarray
    p0: float
    s: float
    fwhm: float
    residual: float
    converged: bool
    edge_pressure: float


class _Levels:
    """The solves made for one load, logged as (cells, convolutions, converged).

    A *result* is a full solve from cold (the same as ``LineContact(n=n, half_width=...)``
    gives, bit for bit); its *companion* is a light solve of the same load, warm from the
    result restricted to the companion's grid, that keeps only the measures.
    """

    def __init__(self, model: LineContact, load: float, tol: float):
        self.model, self.load, self.tol = model, load, tol
        self.log: list[tuple[int, int, bool]] = []

    def _model(self, n: int, half_width: float) -> LineContact:
        level = self.model._with_grid(n, half_width)
        level.tol = self.tol
        return level

    def result(self, n: int, half_width: float, start=None) -> LineContactResult:
        res = self._model(n, half_width).solve(self.load, initial=start)
        self.log.append((n, res.convolutions, res.converged))
        return res

    def companion(self, n: int, half_width: float, start: LineContactResult) -> _Profile:
        level = self._model(n, half_width)
        grid = level._grid(self.load)
        out = level._run(grid, level._rescaled_start(grid, start))
        if not out.converged:  # the start misled Newton: from cold
            out = level._run(grid, None)
        self.log.append((n, grid.disc.op.convolutions, bool(out.converged)))
        p, x, dx = out.pressure, grid.x, grid.dx
        p0 = peak(p)
        return _Profile(
            x=x,
            dx=dx,
            pressure=p,
            p0=p0,
            s=std(x, p, dx),
            fwhm=fwhm(x, p, p0),
            residual=float(out.residual),
            converged=bool(out.converged),
            edge_pressure=float(max(p[0], p[-1]) / p0),
        )


def _widened(model: LineContact, half_width: float) -> float:
    return max(half_width + 1.5 * math.sqrt(model.radius * model.law.u0), 1.1 * half_width)


def _level_tol(model: LineContact, target: float) -> float:
    """Solver tolerance of every grid: the model's, or tighter so that the solver's error
    (~ the residual in ln p) stays a thousandth of the target."""
    return min(model.tol, 1e-3 * target)


def solve_to_accuracy(
    model: LineContact,
    load: float,
    initial: LineContactResult | None = None,
    warn: bool | None = None,
) -> LineContactResult:
    """Solve ``load`` (N/m) on grids refined until the error estimate meets
    ``model.accuracy``; the result of the last grid, with ``error_estimate`` set.

    ``model.n`` (when given by the user) is the first grid tried; ``model.half_width`` (when
    given) the first domain, widened when the truncation estimate asks for it. ``initial``
    starts the first grid. ``result.convolutions`` counts every solve made;
    ``error_estimate.levels`` lists them.
    """
    warn = model.warn if warn is None else warn
    target = model.accuracy / ACCEPT_MARGIN
    half = model.half_width or domain_half_width(model, load, target)
    n = grid_size(max(model._n_given or predicted_n(model, load, half, target), MIN_N))
    n = min(n, MAX_N)
    levels = _Levels(model, load, _level_tol(model, target))
    res = levels.result(n, half, initial)
    comp = levels.companion(n // 2, half, res)
    suspect = False  # a grid under-resolved the peak: the a-priori widths were far off
    pending = None  # an estimate met on a suspect scene, to be confirmed by the next grid
    while True:
        est = _estimate(res, comp, levels.log, model.accuracy)
        suspect = suspect or est.fwhm_cells < RESOLVED_CELLS
        if pending is not None and est.met and _consistent(pending, est, target):
            break
        pending = None
        if (est.met and not suspect) or len(levels.log) >= MAX_LEVELS:
            break
        if est.solver > target:  # the solver's residual: no finer grid reduces it
            break
        if est.met:  # confirm on twice the cells: the estimate must fall as h^2
            pending, n_new = est, 2 * n
        elif max(map(abs, est.truncation.values())) > WIDEN_SHARE * target or not math.isfinite(
            est.worst
        ):
            wider = _widened(model, half)
            n, half = grid_size(n * wider / half), wider  # the same cell width
            res = levels.result(n, half)
            comp = levels.companion(n // 2, half, res)
            continue
        else:
            n_new = _refined_n(res, est, target)
        if n_new > MAX_N:
            break
        previous, res = res, levels.result(n_new, half)
        comp = previous if n_new == 2 * n else levels.companion(n_new // 2, half, res)
        n = n_new
    return _finish(model, res, est, levels.log, warn)


def _consistent(coarse: ErrorEstimate, fine: ErrorEstimate, target: float) -> bool:
    """Whether the estimate fell as h^2 (within a factor 2: by 2 to 8 for a halved cell width)
    in every quantity where it was not already negligible (below a tenth of the target)."""
    h_ratio = (fine.half_width / fine.n) / (coarse.half_width / coarse.n)
    for q in ("p0", "s", "w_over_s"):
        before, after = abs(coarse.signed[q]), abs(fine.signed[q])
        if before > 0.1 * target and not 0.5 <= before * h_ratio**ORDER / max(after, 1e-300) <= 2:
            return False
    return True


def _finish(model, res, est, log, warn) -> LineContactResult:
    res.error_estimate = est
    res.convolutions = sum(c for _, c, _ in log)
    if warn:
        model._warn_sweep([res])
        if not est.met:
            warnings.warn(f"fastline: {_not_met(est)}", AccuracyWarning, stacklevel=4)
    return res


def _not_met(est: ErrorEstimate) -> str:
    text = (
        f"accuracy {est.accuracy:g} not reached: estimated error {est.worst:.2g} (p0 {est.p0:.2g},"
        f" s {est.s:.2g}, w/s {est.w_over_s:.2g}; a grid is accepted below accuracy/"
        f"{ACCEPT_MARGIN:g}) with n = {est.n}, FWHM over {est.fwhm_cells:.3g} cells; "
    )
    if est.solver > est.accuracy / ACCEPT_MARGIN:
        return text + (
            f"the solver's residual {est.solver:.2g} alone exceeds accuracy/{ACCEPT_MARGIN:g} "
            "and no finer grid reduces it (a solve that did not converge, or a tolerance "
            "raised to the round-off floor: see result.message)"
        )
    return text + f"the loop stops at {MAX_LEVELS} grids or n = {MAX_N}"


def sweep_to_accuracy(
    model: LineContact, loads: np.ndarray, progress: Callable[[], object] | None = None
) -> list[LineContactResult]:
    """:func:`solve_to_accuracy` for each load; warnings once per cause for the whole list."""
    out = []
    for load in loads:
        out.append(solve_to_accuracy(model, float(load), warn=False))
        if progress is not None:
            progress()
    if model.warn:
        model._warn_sweep(out)
        missed = [r for r in out if not r.error_estimate.met]
        if missed:
            worst = max(missed, key=lambda r: r.error_estimate.worst)
            loads_text = ", ".join(f"{r.load:.4g}" for r in missed)
            warnings.warn(
                f"fastline: {_not_met(worst.error_estimate)} [{len(missed)} of {len(out)} "
                f"loads: {loads_text} N/m]",
                AccuracyWarning,
                stacklevel=3,
            )
    return out


def estimate_error(model: LineContact, result: LineContactResult) -> ErrorEstimate:
    """Error estimate of a result solved on a fixed grid by ``model`` (one companion solve).

    The companion has half the cells on the same domain, warm from the result; when the result
    itself has fewer than :data:`RESOLVED_CELLS` across its FWHM (or fewer than 32 cells), a
    coarser companion would be far from the asymptotic range, and the companion has twice the
    cells instead. Sets ``result.error_estimate`` and returns it.
    """
    n = result.x.size
    half = 0.5 * n * result.dx
    cells = result.fwhm / result.dx if math.isfinite(result.fwhm) else 0.0
    finer = cells < RESOLVED_CELLS or n < 32 or n % 2
    levels = _Levels(model, result.load, model.tol)
    levels.log.append((n, result.convolutions, result.converged))
    comp = levels.companion(2 * n if finer else n // 2, half, result)
    est = _estimate(result, comp, levels.log)
    result.error_estimate = est
    return est


def check_result(model: LineContact, result) -> None:
    """``result`` must be a LineContactResult of ``model``'s scene (for :func:`estimate_error`)."""
    if not isinstance(result, model.result_type):
        raise TypeError(f"result must be a LineContactResult, got {type(result).__name__}")
    same = (result.E_star, result.radius, result.model) == (model.E_star, model.radius, model.model)
    if not same:
        raise ValueError(
            "result must come from this model (same E_star, radius and law): got "
            f"E_star={result.E_star!r}, radius={result.radius!r}, model={result.model!r}"
        )
    alpha = model._alpha(result.delta)  # h_rms / delta of the model's spectrum (NaN: none)
    same_alpha = math.isclose(alpha, result.alpha, rel_tol=1e-9) or (
        math.isnan(alpha) and math.isnan(result.alpha)
    )
    theirs, ours = result.theory, model.theory
    same_theory = theirs is None or ours is None or theirs is ours
    if not same_theory:
        same_theory = (theirs.gamma, theirs.variant) == (ours.gamma, ours.variant)
    if not (same_alpha and same_theory):
        raise ValueError(
            "result must come from this model (same spectrum, gamma and variant): its alpha "
            f"is {result.alpha:.6g}, this model's at its load {alpha:.6g}"
        )
