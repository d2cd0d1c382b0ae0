"""The scenes of Tiwari & Persson, section 3, and the data behind their Figs. 2-5.

This module is the single definition of the paper's scene (surfaces, modulus, radius, loads):
the ``fastline paper`` command, the tests, ``bench/`` and ``docs/make_reproduction.py`` import it.

Scene (paper section 3): a rigid cylinder of radius ``R = 1 cm`` on an elastic half-space with
``E* = 1.33 GPa``; three self-affine spectra with roll-off between ``q0 = 1e3 1/m`` and
``qr = 1e4 1/m`` (surface 1: h_rms = 10 µm, H = 0.8; surface 2: 10 µm, H = 1.0; surface 3:
1 µm, H = 0.8); loads per unit length from 1e3 to 1.5e6 N/m. The paper does not state the
large-wavenumber cut-off q1; fastline uses 1e9 1/m by default (docs/reproduction.md shows how
little the reported numbers move with it).

The sphere versions (:func:`sphere_paper_data`, ``fastline paper --geometry sphere``) keep the
scene (E*, R = 1 cm as the sphere's radius, the three spectra) and choose the loads F [N] per
surface so that alpha = h_rms / delta (delta = a^2 / R) runs log-spaced over
:data:`SPHERE_ALPHA_RANGE` (:func:`sphere_load_for_alpha`), the same alphas for the three
surfaces. The paper has no point-contact sweep; the smallest alphas need contacts wider than
the half-space assumption allows (a > 0.1 R below alpha = h_rms / (0.01 R): 0.1 for surfaces 1
and 2, 0.01 for surface 3), which the diagnostics report.

SI units throughout: m, 1/m, Pa, N/m (N for a sphere).

Reference: A. Tiwari and B.N.J. Persson, *Cylinder-flat contact mechanics with surface
roughness*.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import ArrayLike

if TYPE_CHECKING:  # annotations only: the solvers load on first use
    from fastline.variants import Variant, VariantName

__all__ = [
    "E_STAR",
    "RADIUS",
    "Q0",
    "QR",
    "Q1",
    "FIG3_LOAD",
    "LOAD_RANGE",
    "SURFACES",
    "PaperSurface",
    "PaperData",
    "surfaces",
    "load_for_alpha",
    "paper_loads",
    "paper_data",
    "SPHERE_ALPHA_RANGE",
    "SPHERE_FIG3_ALPHA",
    "sphere_load_for_alpha",
    "sphere_paper_data",
]

#: effective modulus E* of the paper's scene [Pa]
E_STAR = 1.33e9
#: cylinder radius R [m]
RADIUS = 0.01
#: roll-off band of the spectra: smallest wavenumber q0 and roll-off wavenumber qr [1/m]
Q0, QR = 1e3, 1e4
#: large-wavenumber cut-off [1/m] (not stated in the paper; fastline's default)
Q1 = 1e9
#: load of the paper's Fig. 3 [N/m]
FIG3_LOAD = 1e4
#: smallest and largest load of the sweeps of Figs. 4-5 [N/m]
LOAD_RANGE = (1e3, 1.5e6)
#: alphas covered by the sphere versions of Figs. 4-5 (log-spaced)
SPHERE_ALPHA_RANGE = (1e-3, 1e3)
#: alpha of the sphere version of Fig. 3 (surface 1)
SPHERE_FIG3_ALPHA = 1.0
#: (label, h_rms [m], Hurst exponent) of the paper's three surfaces
SURFACES = (
    ("surface 1", 10e-6, 0.8),
    ("surface 2", 10e-6, 1.0),
    ("surface 3", 1e-6, 0.8),
)


def surfaces(q1: float = Q1) -> tuple:
    """The paper's three spectra as :class:`~fastline.SelfAffinePSD` (surface 1, 2, 3)."""
    from fastline.spectra import SelfAffinePSD

    return tuple(SelfAffinePSD(h, H, Q0, QR, q1) for _label, h, H in SURFACES)


def load_for_alpha(
    alpha: ArrayLike, h_rms: float = 10e-6, E_star: float = E_STAR
) -> float | np.ndarray:
    """Load per unit length f_N [N/m] that gives ``alpha = h_rms / delta``.

    With the Hertz penetration ``delta = 4 f_N / (pi E*)`` (paper eq. 9),
    ``f_N = (pi/4) h_rms E* / alpha``. Works on arrays of alpha.
    """
    return math.pi / 4.0 * h_rms * E_star / np.asarray(alpha, dtype=np.float64)[()]


def paper_loads(num: int = 40) -> np.ndarray:
    """``num`` loads log-spaced over the paper's range 1e3 ... 1.5e6 N/m."""
    return np.geomspace(LOAD_RANGE[0], LOAD_RANGE[1], num)


@dataclass
class PaperSurface:
    """One surface of the paper and its load sweep.

    Attributes
    ----------
    label : str
        ``"surface 1"`` ... ``"surface 3"``.
    h_rms, hurst : float
        rms roughness in m and Hurst exponent.
    psd : SelfAffinePSD
        The spectrum.
    theory : PerssonTheory
        Its Persson theory at E* and gamma.
    gamma_u : float
        ``u0 / h_rms`` of the exponential law from that theory (paper eq. 10).
    results : list of LineContactResult
        One solve per load, in increasing load.
    """

    label: str
    h_rms: float
    hurst: float
    psd: object
    theory: object
    gamma_u: float
    results: list = field(default_factory=list)


@dataclass
class PaperData:
    """Everything behind the paper's Figs. 2-5 (see :func:`paper_data`).

    Attributes
    ----------
    surfaces : list of PaperSurface
        Figs. 2, 4 and 5.
    fig3 : LineContactResult
        Surface 1 at ``FIG3_LOAD`` (Fig. 3).
    loads : ndarray
        The loads of the sweeps in N/m.
    q1, gamma : float
        Cut-off in 1/m and the theory's gamma.
    n : int
        Grid points of every solve.
    """

    surfaces: list
    fig3: object
    loads: np.ndarray
    q1: float
    gamma: float
    n: int

    @property
    def results(self) -> list:
        """Every solve of the sweeps and Fig. 3, in one list."""
        return [r for s in self.surfaces for r in s.results] + [self.fig3]


def paper_data(
    q1: float = Q1,
    loads: int = 40,
    n: int = 1024,
    gamma: float = 0.45,
    progress: Callable[[str], None] | None = None,
    variant: VariantName | Variant = "yang-persson-energy",
    **solve_options: Any,
) -> PaperData:
    """Solve the scenes behind the paper's Figs. 2-5 (no plotting, no files, no warnings).

    Parameters
    ----------
    q1 : float
        Large-wavenumber cut-off of the three spectra in 1/m.
    loads : int
        Loads per surface, log-spaced over 1e3 ... 1.5e6 N/m.
    n : int
        Grid points of each solve.
    gamma : float
        Yang-Persson parameter of the theory, in (0, 1].
    progress : callable, optional
        Called with the surface label after each solve (e.g. a progress bar's update).
    variant : str
        Variant of the theory (:mod:`fastline.variants`).
    **solve_options
        Passed on to :func:`~fastline.solve_line_contact` (e.g. ``max_iter``, ``hardness``).

    Returns
    -------
    PaperData
        The validity warnings of the solves are not emitted; they are in each result's
        ``diagnostics`` (see :func:`fastline.diagnostics.warn_once`).
    """
    from fastline.line_contact import solve_line_contact
    from fastline.persson import PerssonTheory

    kw = {**solve_options, "warn": False}
    fN = paper_loads(loads)
    out = []
    for (label, h, H), psd in zip(SURFACES, surfaces(q1), strict=True):
        th = PerssonTheory(psd, E_STAR, gamma=gamma, variant=variant)
        surf = PaperSurface(label, h, H, psd, th, th.exponential_fit().gamma_u)
        for f in fN:
            r = solve_line_contact(psd, E_STAR, RADIUS, float(f), n=n, theory=th, **kw)
            surf.results.append(r)
            if progress is not None:
                progress(label)
        out.append(surf)
    s1 = out[0]
    fig3 = solve_line_contact(s1.psd, E_STAR, RADIUS, FIG3_LOAD, n=n, theory=s1.theory, **kw)
    return PaperData(surfaces=out, fig3=fig3, loads=fN, q1=q1, gamma=gamma, n=n)


# ----------------------------------------------------------------------------------------------
# the sphere versions
# ----------------------------------------------------------------------------------------------
def sphere_load_for_alpha(
    alpha: ArrayLike, h_rms: float = 10e-6, E_star: float = E_STAR, radius: float = RADIUS
) -> float | np.ndarray:
    """Load F [N] on a sphere that gives ``alpha = h_rms / delta``.

    With the Hertz penetration ``delta = a^2 / R`` and ``a^3 = 3 F R / (4 E*)``,
    ``F = (4/3) E* R^(1/2) delta^(3/2)``, ``delta = h_rms / alpha``. Works on arrays of alpha.
    """
    delta = h_rms / np.asarray(alpha, dtype=np.float64)
    return (4.0 / 3.0 * E_star * math.sqrt(radius) * delta**1.5)[()]


def sphere_paper_data(
    q1: float = Q1,
    loads: int = 40,
    n: int = 512,
    gamma: float = 0.45,
    progress: Callable[[str], None] | None = None,
    variant: VariantName | Variant = "yang-persson-energy",
    **solve_options: Any,
) -> PaperData:
    """Solve the sphere versions of the paper's Figs. 3-5 (no plotting, no files, no warnings).

    Each surface is swept (:meth:`~fastline.PointContact.sweep`, continuation) over ``loads``
    loads F [N] chosen by :func:`sphere_load_for_alpha` so that alpha is log-spaced over
    :data:`SPHERE_ALPHA_RANGE`; ``fig3`` is surface 1 at alpha = :data:`SPHERE_FIG3_ALPHA`.

    Parameters
    ----------
    q1 : float
        Large-wavenumber cut-off of the three spectra in 1/m.
    loads : int
        Loads per surface.
    n : int
        Cells of each solve (central disc and rings).
    gamma : float
        Yang-Persson parameter of the theory, in (0, 1].
    progress : callable, optional
        Called with the surface label after each solve.
    variant : str
        Variant of the theory (:mod:`fastline.variants`).
    **solve_options
        Passed on to :class:`~fastline.PointContact` (e.g. ``max_iter``, ``hardness``).

    Returns
    -------
    PaperData
        ``loads`` holds the alphas' loads of surface 1 in N (each surface has its own: see the
        results' ``load``); the validity warnings are in each result's ``diagnostics``.
    """
    from fastline.persson import PerssonTheory
    from fastline.point_contact import PointContact

    kw = {**solve_options, "warn": False}
    alphas = np.geomspace(SPHERE_ALPHA_RANGE[0], SPHERE_ALPHA_RANGE[1], loads)
    out = []
    for (label, h, H), psd in zip(SURFACES, surfaces(q1), strict=True):
        th = PerssonTheory(psd, E_STAR, gamma=gamma, variant=variant)
        surf = PaperSurface(label, h, H, psd, th, th.exponential_fit().gamma_u)
        model = PointContact(psd, E_STAR, RADIUS, n=n, theory=th, **kw)
        tick = None if progress is None else (lambda lab=label: progress(lab))
        surf.results = model.sweep(sphere_load_for_alpha(alphas, h), progress=tick)
        out.append(surf)
    s1 = out[0]
    model = PointContact(s1.psd, E_STAR, RADIUS, n=n, theory=s1.theory, **kw)
    fig3 = model.solve(float(sphere_load_for_alpha(SPHERE_FIG3_ALPHA, s1.h_rms)))
    fN = sphere_load_for_alpha(alphas, SURFACES[0][1])
    return PaperData(surfaces=out, fig3=fig3, loads=fN, q1=q1, gamma=gamma, n=n)
