"""Point contact: the nominal pressure p(r) under a sphere on a rough half-space (docs/sphere.md).

Equations (docs/sphere.md, "Equations"): unknown axisymmetric pressure ``p(r) > 0`` and the
separation ``u1`` the undeformed sphere would have at its apex, with

    u(r) = u1 + r^2/(2R) + (K p)(r),     u(r) = u_law(p(r)),     2 pi int p r dr = F,

``K`` the half-space's axisymmetric compliance (Johnson eq. 3.96a; :mod:`fastline.elastic.ring`)
and ``u_law`` the pressure law (:mod:`fastline.theory.laws`), the same as for the cylinder. What is
sphere-specific lives here: the grid of a central disc and rings, the cell-averaged gap, the
Hertz sphere, alpha, the profile measures (p0, s, FWHM along a diameter, the radii holding a
share of the load). The settings, the solve and sweep loop, the cold start and the
Newton-Krylov core are shared with the line contact (:mod:`fastline.contact.model`,
:mod:`fastline.contact.core`).

Definitions (docs/sphere.md): ``delta = a^2 / R`` (Hertz penetration), ``alpha = h_rms /
delta``; ``s^2 = int r^2 p dA / (2 F)``, the variance of p along one diameter direction, so that
the Gaussian limit ``p0 exp(-r^2 / (2 s^2))`` has ``s^2 = R u0`` and the Hertz sphere
``s = a / sqrt(5)``; ``w`` the FWHM along a diameter (``w/s = sqrt(15)`` for Hertz,
``2 sqrt(2 ln 2)`` for the Gaussian).

:class:`PointContact` is the reusable model; :func:`solve_point_contact` a one-call wrapper.
SI units: m, Pa, N (the load on the sphere; a cylinder's is per unit length, N/m).
"""

from __future__ import annotations

import copy
import math
from collections.abc import Callable, Iterable
from dataclasses import KW_ONLY, dataclass
from typing import Any, ClassVar

import numpy as np

from fastline.contact import core as _core
from fastline.contact.core import ConvergenceWarning, Discretisation, dot
from fastline.contact.model import (
    ContactModel,
    fwhm,
    log_pressure,
    peak,
)
from fastline.contact.result import ContactResult
from fastline.elastic.ring import MAX_N as _OPERATOR_MAX_N
from fastline.elastic.ring import RingKernelOperator, ring_edges
from fastline.theory.laws import PressureLaw
from fastline.theory.limits import HertzPointContact, gaussian_point_contact, hertz_point_contact
from fastline.theory.persson import PerssonTheory
from fastline.theory.spectra import PSD

__all__ = [
    "ConvergenceWarning",
    "PointContact",
    "PointContactResult",
    "solve_point_contact",
]

#: default number of cells (central disc + rings). Against n = 2048 the p0 ratio and w/s
#: are within 2e-5 over alpha = 1e-3..100 (paper surface 1; 1e-4 at n = 256), and a warm solve
#: takes 1-5 ms (docs/sphere.md, "Performance").
DEFAULT_N = 512
#: largest grid (the ring operator is a dense n x n matrix)
MAX_N = _OPERATOR_MAX_N
#: nested iteration: a cold Newton solve on more than ``NESTED_ABOVE`` cells starts from the
#: same load's solution on ``n // NESTED_FACTOR`` cells of the same domain (itself nested), as
#: the line contact does. A cold start at n = 3000-4096 took 100 Newton steps and more (over
#: 1,000 products with the dense operator, ~30 s) on a scene whose contact edge falls from
#: 0.3 p0 to 1e-3 p0 within a few cells, where the law turns from full contact to its tail;
#: from the solution on a quarter of the cells it takes 4-10 (docs/sphere.md, "Performance")
NESTED_ABOVE = 512
NESTED_FACTOR = 4
#: loads accepted, in units of E* R^2: the Hertz radius stays between ~1e-6 R and ~100 R
LOAD_RANGE = (1e-18, 1e6)


@dataclass(repr=False)  # the short repr of ContactResult, not every array
class PointContactResult(ContactResult):
    """The solution of one point-contact scene and what follows from it.

    Arrays are on the solver's cells (centres ``r_j = j dr``, the first a disc). Units: m, Pa,
    N. ``real_area`` and ``diagnostics`` of a solve are computed when first read (for
    ``diagnostics``, unless the model warns); the values are the same
    (:class:`fastline.contact.model.DeferredFields`).

    Attributes
    ----------
    r : ndarray
        Cell centres in m, from 0 (the axis) outwards.
    pressure : ndarray
        Nominal contact pressure p(r) in Pa (cell averages).
    separation : ndarray
        Mean interfacial separation u(r) in m (the gap for ``model="hertz"``).
    real_area : ndarray or None
        Real contact area fraction P(q1, p(r)) (1 inside and 0 outside the contact for
        ``model="hertz"``; None for a law that does not know it).
    p0 : float
        Peak (central) pressure in Pa.
    s : float
        ``sqrt(int r^2 p dA / (2 F))`` in m: the standard deviation of p along one diameter
        direction (cell-exact).
    fwhm : float
        Full width at half maximum along a diameter in m.
    w_over_s, p0_ratio : float
        ``fwhm / s`` (``sqrt(15)`` for Hertz, ``2 sqrt(2 ln 2)`` for a Gaussian) and
        ``p0 / p0_Hertz``.
    alpha, delta : float
        ``alpha = h_rms / delta`` and the Hertz penetration ``delta = a^2 / R`` in m.
    hertz_radius : float
        Hertz contact radius ``a = (3 F R / (4 E*))^(1/3)`` in m.
    u1 : float
        Separation in m that the undeformed sphere would have at its apex (minus the rigid
        approach; ``-delta`` for Hertz).
    converged : bool
        Whether the residual fell below ``tol``.
    iterations, convolutions : int
        Outer iterations (Newton steps, sweeps) and operator-like applications: products with
        the ring operator K plus preconditioner applications (``diagnostics`` splits them as
        ``k_applications`` and ``preconditioner_solves``).
    residual : float
        Final residual: max |u_law(p) - u1 - r^2/2R - K p| / u0 (for hertz: the
        complementarity error relative to delta).
    message : str
        What happened.
    model, method : str
        The law's name and the method (as for the line contact).
    load, radius, E_star, dr : float
        The scene (N, m, Pa) and the cell width (m).
    force_error : float
        ``|2 pi int p r dr - F| / F`` (the cells' sum, exact for the piecewise-constant p).
    edge_pressure : float
        Pressure at the domain edge relative to p0.
    diagnostics : dict
        Solver counts and the validity checks of :func:`fastline.contact.diagnostics.assess`.
    theory : PerssonTheory or None
        The theory the scene was solved with (None for hertz and for user laws).
    """

    #: how the diagnostics name the load and the contact's extent
    LOAD_SYMBOL: ClassVar[str] = "F"
    LOAD_UNIT: ClassVar[str] = "N"
    EXTENT_WORD: ClassVar[str] = "radius"

    _: KW_ONLY
    r: np.ndarray
    dr: float
    hertz_radius: float

    def diameter_profile(self) -> tuple[np.ndarray, np.ndarray]:
        """``(x [m], p [Pa])`` along a diameter: the profile mirrored about the axis."""
        return _diameter(self.r, self.pressure)

    def load_radius(self, fraction: float = 0.99) -> float:
        """Radius in m of the centred disc that carries ``fraction`` of the load.

        Exact for the piecewise-constant pressure (inside a cell the load grows linearly in
        r^2). ``fraction`` in (0, 1).
        """
        if not (isinstance(fraction, int | float) and 0.0 < fraction < 1.0):
            raise ValueError(f"fraction must lie in (0, 1), got {fraction!r}")
        e = ring_edges(self.r.size) * self.dr
        cell_loads = np.pi * (e[1:] - e[:-1]) * (e[1:] + e[:-1]) * self.pressure
        inner = np.concatenate([[0.0], np.cumsum(cell_loads)])
        target = fraction * inner[-1]
        j = min(int(np.searchsorted(inner, target, side="right")) - 1, self.r.size - 1)
        return float(math.sqrt(e[j] ** 2 + (target - inner[j]) / (np.pi * self.pressure[j])))

    def pressure_radius(self, level: float = 0.01) -> float:
        """Outermost radius in m where p falls to ``level * p0`` (linear interpolation between
        cell centres); NaN if p stays above it on the domain. ``level`` in (0, 1)."""
        if not (isinstance(level, int | float) and 0.0 < level < 1.0):
            raise ValueError(f"level must lie in (0, 1), got {level!r}")
        above = np.nonzero(self.pressure >= level * self.p0)[0]
        j = int(above[-1])
        if j == self.r.size - 1:
            return float("nan")
        p, r = self.pressure, self.r
        return float(r[j] + (level * self.p0 - p[j]) * (r[j + 1] - r[j]) / (p[j + 1] - p[j]))


# ----------------------------------------------------------------------------------------------
# the grid of one load and the profile measures
# ----------------------------------------------------------------------------------------------
@dataclass(frozen=True)
class _RingGrid:
    """Cells of one solve: centres (``x``, from 0), width, the domain radius (``half_width``,
    the name the shared machinery reads), the Hertz reference and the discretisation."""

    x: np.ndarray
    dr: float
    half_width: float
    hertz: HertzPointContact
    disc: Discretisation


def _build_grid(n: int, domain: float, radius: float, E_star: float, hz) -> _RingGrid:
    dr = domain / (n - 0.5)
    e = ring_edges(n) * dr
    op = RingKernelOperator(n, dr, E_star)  # fresh counters per solve (threads share nothing)
    gap = (e[1:] ** 2 + e[:-1] ** 2) / (4.0 * radius)  # cell average of r^2 / (2R)
    disc = Discretisation(gap, op.weights, op, hz.load)
    return _RingGrid(np.arange(n) * dr, dr, domain, hz, disc)


def _diameter(r: np.ndarray, p: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    return np.concatenate([-r[:0:-1], r]), np.concatenate([p[:0:-1], p])


def _radial_std(p: np.ndarray, dr: float, load: float) -> float:
    """``sqrt(int r^2 p dA / (2 F))`` of piecewise-constant p on the cells (exact per cell:
    ``int r^2 dA = pi (e_+^4 - e_-^4) / 2``)."""
    e = ring_edges(p.size) * dr
    e2 = e * e
    return math.sqrt(dot(p, 0.5 * np.pi * (e2[1:] - e2[:-1]) * (e2[1:] + e2[:-1])) / (2 * load))


def _rescaled_start(grid: _RingGrid, initial: PointContactResult) -> np.ndarray:
    """ln p of a neighbouring solution at the same relative radius in the domain (the default
    domain scales with the contact), interpolated onto this grid; the load is restored later."""
    ri = initial.r / ((initial.r.size - 0.5) * initial.dr)
    return np.interp(grid.x / grid.half_width, ri, log_pressure(initial))


class PointContact(ContactModel):
    """A reusable point-contact model: one spectrum, material, sphere and law, many loads.

    It owns what every solve reuses: the Persson theory and its tables, the pressure law, the
    grid policy and the solver settings; the ring operator's coefficients are shared per grid
    size by all models (:mod:`fastline.elastic.ring`). Safe to share between threads and
    picklable, like :class:`~fastline.LineContact`.

    Parameters
    ----------
    psd : PSD or None
        Combined roughness spectrum (m^4 vs 1/m). None only with ``model="hertz"`` or a user
        law (then alpha is reported as NaN).
    E_star : float
        Effective modulus in Pa (paper eq. 1), in [1, 1e13].
    radius : float
        Sphere radius R in m, in [1e-9, 1e3].
    model : {"persson", "exponential", "hertz"} or PressureLaw
        p(u) relation, as for :class:`~fastline.LineContact`.
    method : {"newton", "picard"}
        Newton-Krylov (default) or the plain damped fixed point (for comparison).
    gamma : float, optional
        Parameter gamma of the theory's correction S(P), in [0.05, 1] (default: the variant's
        own, 0.45; 5/9 for ``"wang-mueser"``).
    variant : str, optional
        Variant of the theory's u(p) (:mod:`fastline.theory.variants`, docs/theory.md):
        ``"yang-persson-energy"`` (None, the default), ``"yang-persson-printed"`` or
        ``"wang-mueser"``. Ignored for ``model="hertz"`` and for laws without a theory;
        with ``theory=`` it must name the theory's own variant (or be None).
    n : int
        Cells from the axis to the domain edge (a central disc and n - 1 rings), in
        [16, 4096] (default 512; the operator is a dense n x n matrix).
    domain_radius : float, optional
        Radius of the domain in m, the same for every load, at most 1e3 R and at least the
        Hertz radius ``a`` of each load solved; default per load ``1.25 a + 8 sqrt(R u0)``.
    tol : float
        Residual tolerance (separation mismatch in units of u0; hertz: relative pressure
        change), in (0, 1e-2].
    max_iter : int, optional
        Newton steps / fixed-point sweeps allowed (defaults 100 / 5000).
    u0, beta : float, optional
        Exponential-law parameters for ``model="exponential"`` (m, dimensionless); refused
        with another model, which would ignore them.
    theory : PerssonTheory, optional
        A prebuilt theory for ``psd`` and ``E_star`` (its gamma and variant are used).
    hardness : float, optional
        Indentation hardness of the softer solid in Pa, for the plasticity diagnostic.
    warn : bool
        Emit a ``ConvergenceWarning`` when a solve does not converge and the diagnostics'
        ``ValidityWarning`` s.

    Examples
    --------
    >>> import fastline as fl
    >>> psd = fl.SelfAffinePSD(5e-6, 0.8, 1e4, 1e5, 1e8)
    >>> E = fl.effective_modulus(210e9, 0.3, 70e9, 0.33)
    >>> pc = fl.PointContact(psd, E, radius=0.02, hardness=1e9)
    >>> res = pc.solve(500.0)  # N
    >>> 2 * res.load_radius(0.99)  # diameter holding 99 % of the load, m  # doctest: +SKIP
    >>> results = pc.sweep([1.0, 10.0, 100.0])  # continuation along the loads
    """

    RESULT = PointContactResult
    LOAD_UNIT = "N"
    LOAD_RANGE = LOAD_RANGE
    LOAD_SCALE_TEXT = "E* R^2"
    MAX_N = MAX_N
    N_NOTE = " (the ring operator is a dense n x n matrix: 8 n^2 bytes)"
    HERTZ_EXTENT_TEXT = "Hertz contact radius"
    #: the cold start's Hertz part is floored at 1e-50 of its peak outside the contact: the
    #: Gaussian part alone puts ln p there at ~ -1e4 in the Hertz-like regime (its p0 is
    #: 1/(3 gamma_u alpha) times Hertz's). Total operator applications of 24 cold solves (paper
    #: surfaces 1 and 3 and H = 0.3, alpha 1e-4..1e3, n = 512): 1237 without, 1106 with (floors
    #: 1e-30..1e-300 gave 1106-1136)
    COLD_FLOOR = 1e-100

    def __init__(
        self,
        psd: PSD | None,
        E_star: float,
        radius: float,
        *,
        model: str | PressureLaw = "persson",
        method: str = "newton",
        gamma: float | None = None,
        variant: str | None = None,
        n: int = DEFAULT_N,
        domain_radius: float | None = None,
        tol: float = 1e-8,
        max_iter: int | None = None,
        u0: float | None = None,
        beta: float | None = None,
        theory: PerssonTheory | None = None,
        hardness: float | None = None,
        warn: bool = True,
    ) -> None:
        self._check_settings(E_star, radius, method, n)
        self.domain_radius = self._check_extent("domain_radius", domain_radius)
        self._check_rest(
            psd, model, gamma, variant, tol, max_iter, u0, beta, theory, hardness, warn
        )

    def __repr__(self):
        return (
            f"PointContact({self.psd!r}, E_star={self.E_star!r}, radius={self.radius!r}, "
            f"model={self.model!r}, method={self.method!r}, n={self.n})"
        )

    # -- solving ------------------------------------------------------------------------------
    def solve(self, load: float, initial: PointContactResult | None = None) -> PointContactResult:
        """Solve one load F (N); ``initial`` is a neighbouring solution to start from.

        Stages: check the load, size the grid, make the initial guess, run the core method,
        measure the profile, run the diagnostics.
        """
        return self._solve(load, initial)

    def sweep(
        self, loads: Iterable[float], progress: Callable[[], object] | None = None
    ) -> list[PointContactResult]:
        """Solve a series of loads F (N) by continuation; results in the order given.

        As :meth:`fastline.LineContact.sweep`: increasing order, each solve started from a
        polynomial prediction in ln F of the earlier solutions, warnings once per cause naming
        the loads; ``progress`` is called after each solve.
        """
        return self._sweep(loads, self._check_progress(progress))

    # -- solve stages -------------------------------------------------------------------------
    def _load_scale(self) -> float:
        return self.E_star * self.radius * self.radius

    def _grid(self, load: float) -> _RingGrid:
        hz = hertz_point_contact(self.E_star, self.radius, load)
        domain = self._extent("domain_radius", self.domain_radius, hz, load)
        return _build_grid(self.n, domain, self.radius, self.E_star, hz)

    def _gaussian(self, load: float):
        return gaussian_point_contact(self._u0(), self.radius, load)

    def _rescaled_start(self, grid: _RingGrid, initial: PointContactResult) -> np.ndarray:
        return _rescaled_start(grid, initial)

    def _coarse_start(self, grid: _RingGrid, load: float) -> tuple[np.ndarray | None, dict | None]:
        """Nested iteration (:data:`NESTED_ABOVE`): the same load on ``n // NESTED_FACTOR``
        cells of this domain, interpolated in ln p (None if it did not converge); its work goes
        to ``diagnostics["nested_start"]`` (its operator applications are of size n / 4 and
        not counted in ``convolutions``)."""
        if self.n <= NESTED_ABOVE or self._law is None or self.method != "newton":
            return None, None
        coarse_model = self.__dict__.get("_nested")
        if coarse_model is None:  # made once; a race between threads makes two equal copies
            coarse_model = copy.copy(self)
            coarse_model.__dict__.pop("_nested", None)
            coarse_model.n, coarse_model.warn = self.n // NESTED_FACTOR, False
            self._nested = coarse_model
        cgrid = _build_grid(coarse_model.n, grid.half_width, self.radius, self.E_star, grid.hertz)
        cstart, counts = coarse_model._coarse_start(cgrid, load)
        coarse = coarse_model._solve_on(cgrid, cstart, False, counts)
        start = _rescaled_start(grid, coarse) if coarse.converged else None
        inner = (counts or {}).get("nested_start", {}).get("convolutions", 0)
        work = dict(
            n=coarse_model.n, convolutions=coarse.convolutions + inner, used=start is not None
        )
        return start, {"nested_start": work}

    def _result(self, grid: _RingGrid, out: _core.Outcome) -> PointContactResult:
        r, dr, hz = grid.x, grid.dr, grid.hertz
        p = out.pressure
        separation, real = self._separation_and_area(out)
        x, pd = _diameter(r, p)
        p0 = peak(pd)
        s = _radial_std(p, dr, hz.load)
        w = fwhm(x, pd, p0)
        op = grid.disc.op
        alpha = self._alpha(hz.delta)
        return PointContactResult(
            r=r,
            pressure=p,
            separation=separation,
            real_area=real,
            p0=p0,
            s=s,
            fwhm=w,
            w_over_s=w / s,
            p0_ratio=p0 / hz.p0,
            alpha=alpha,
            delta=hz.delta,
            hertz_radius=hz.a,
            u1=float(out.u1),
            converged=bool(out.converged),
            iterations=int(out.iterations),
            convolutions=int(op.convolutions),
            residual=float(out.residual),
            message=self._message(out, alpha),
            model=self.model,
            method=self.method,
            load=hz.load,
            radius=self.radius,
            E_star=self.E_star,
            dr=dr,
            force_error=abs(dot(op.weights, p) - hz.load) / hz.load,
            edge_pressure=float(p[-1] / p0),
            diagnostics={
                "n": self.n,
                "domain_radius": grid.half_width,
                "k_applications": op.convolutions - op.circulant_solves,
                "preconditioner_solves": op.circulant_solves,
                **out.info,
            },
            theory=self._theory,
        )


def solve_point_contact(
    psd: PSD | None, E_star: float, radius: float, load: float, **options: Any
) -> PointContactResult:
    """Solve for the nominal pressure under a rigid sphere on a rough elastic half-space.

    ``solve_point_contact(psd, E_star, radius, load, **options)`` is
    ``PointContact(psd, E_star, radius, **options).solve(load)``; the theory of a spectrum is
    built once and shared between calls while the spectrum object lives.

    Parameters
    ----------
    psd : PSD or None
        Combined roughness spectrum; None only with ``model="hertz"``.
    E_star : float
        Effective modulus in Pa (paper eq. 1).
    radius : float
        Sphere radius R in m.
    load : float
        Normal load F in N.
    **options
        Keyword options of :class:`PointContact` (model, method, gamma, variant, n,
        domain_radius, tol, max_iter, u0, beta, theory, hardness, warn).

    Returns
    -------
    PointContactResult
    """
    return PointContact(psd, E_star, radius, **options).solve(load)
