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
import os
from collections.abc import Callable, Iterable
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any, Literal

import numpy as np
from numpy.typing import ArrayLike

from fastline._lib.validate import real_array
from fastline.contact.line import solve_line_contact
from fastline.contact.point import PointContact
from fastline.io import scene_metadata, sweep_rows, write_csv
from fastline.reports import plotting
from fastline.theory.limits import (
    hertz_line_contact,
    hertz_point_contact,
    p0_ratio_gaussian,
    p0_ratio_gaussian_sphere,
)
from fastline.theory.persson import PerssonTheory
from fastline.theory.spectra import SelfAffinePSD
from fastline.theory.variants import DEFAULT_VARIANT, get_variant

if TYPE_CHECKING:  # annotations only
    from fastline.theory.variants import Variant, VariantName

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
    "write_files",
    "write_sphere_files",
]

_Format = Literal["png", "pdf", "svg"]

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
    return tuple(SelfAffinePSD(h, H, Q0, QR, q1) for _label, h, H in SURFACES)


def load_for_alpha(
    alpha: ArrayLike, h_rms: float = 10e-6, E_star: float = E_STAR
) -> float | np.ndarray:
    """Load per unit length f_N [N/m] that gives ``alpha = h_rms / delta``.

    With the Hertz penetration ``delta = 4 f_N / (pi E*)`` (paper eq. 9),
    ``f_N = (pi/4) h_rms E* / alpha``. Works on arrays of alpha.
    """
    return math.pi / 4.0 * h_rms * E_star / real_array("alpha", alpha)[()]


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
    variant : str
        Name of the theory's variant (:mod:`fastline.theory.variants`).
    """

    surfaces: list
    fig3: object
    loads: np.ndarray
    q1: float
    gamma: float
    n: int
    variant: str = "yang-persson-energy"

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
        Variant of the theory (:mod:`fastline.theory.variants`).
    **solve_options
        Passed on to :func:`~fastline.solve_line_contact` (e.g. ``max_iter``, ``hardness``).

    Returns
    -------
    PaperData
        The validity warnings of the solves are not emitted; they are in each result's
        ``diagnostics`` (see :func:`fastline.contact.diagnostics.warn_once`).
    """
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
    name = get_variant(variant).name
    return PaperData(surfaces=out, fig3=fig3, loads=fN, q1=q1, gamma=gamma, n=n, variant=name)


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
    delta = h_rms / real_array("alpha", alpha)
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
        Variant of the theory (:mod:`fastline.theory.variants`).
    **solve_options
        Passed on to :class:`~fastline.PointContact` (e.g. ``max_iter``, ``hardness``).

    Returns
    -------
    PaperData
        ``loads`` holds the alphas' loads of surface 1 in N (each surface has its own: see the
        results' ``load``); the validity warnings are in each result's ``diagnostics``.
    """
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
    name = get_variant(variant).name
    return PaperData(surfaces=out, fig3=fig3, loads=fN, q1=q1, gamma=gamma, n=n, variant=name)


# ----------------------------------------------------------------------------------------------
# files: the figures and the CSV tables behind them
# ----------------------------------------------------------------------------------------------
def write_files(
    data: PaperData,
    out: str | os.PathLike,
    *,
    format: _Format | None = None,
    dpi: float | None = None,
) -> list[str]:
    """Write the paper's Figs. 2-5 and the CSV table behind each into the directory ``out``.

    Files (figures in ``format``, PNG by default): ``fig2_psd`` (C(q) of surfaces 1-3 at 400
    log-spaced q from q0 to q1), ``fig3_profile`` (p(x) of surface 1 at :data:`FIG3_LOAD`, rough
    and Hertz), ``fig4_ws`` and ``fig5_p0ratio`` (the load sweeps: alpha, p0, p0 ratio, s, w, w/s
    and the Gaussian asymptote of paper eq. 14, one row per surface and load). Each CSV's
    header records the scene (:func:`fastline.io.scene_metadata`: E*, R, gamma, n, the
    variant when not the default, q0, qr, q1 and the surfaces).

    Parameters
    ----------
    data : PaperData
        From :func:`paper_data`.
    out : str or path-like
        Existing, writable directory.
    format : {"png", "pdf", "svg"}, optional
        Figure format (default PNG).
    dpi : float, optional
        Resolution of PNG figures (default: :func:`fastline.reports.plotting.save_figure`'s).

    Returns
    -------
    list of str
        The names of the files written (relative to ``out``), in the order written.
    """
    files, surfs, meta = _Files(out, format, dpi), data.surfaces, _files_metadata(data)
    q = np.geomspace(Q0, data.q1, 400)
    cols = [s.psd(q) for s in surfs]
    header = ["q_1_per_m", "C1_m4", "C2_m4", "C3_m4"]
    files.csv("fig2_psd", header, zip(q, *cols, strict=True), meta, "Fig. 2: C(q) of surfaces 1-3")
    files.figure("fig2_psd", plotting.plot_psd({_surface_label(s): s.psd for s in surfs}))

    r3 = data.fig3
    hz = hertz_line_contact(E_STAR, RADIUS, FIG3_LOAD)
    files.csv(
        "fig3_profile",
        ["x_m", "p_rough_Pa", "p_hertz_Pa"],
        zip(r3.x, r3.pressure, hz.pressure(r3.x), strict=True),
        {**meta, "load_N_per_m": FIG3_LOAD, "alpha": r3.alpha},
        "Fig. 3: p(x) of surface 1, rough and smooth (Hertz)",
    )
    files.figure("fig3_profile", plotting.plot_profile(r3, label="rough (surface 1)"))

    title = "Figs. 4-5: load sweeps 1e3..1.5e6 N/m (log-spaced)"
    _sweep_files(files, ("fig4_ws", "fig5_p0ratio"), data, _line_sweep_table(surfs), meta, title)
    return files.written


def _line_sweep_table(surfs: list[PaperSurface]) -> tuple[list, list]:
    """Header and rows of the tables of Figs. 4-5: one row per surface and load, with the
    Gaussian asymptote of paper eq. 14."""
    header = ["surface", "h_rms_m", "hurst", "load_N_per_m", "alpha", "p0_Pa", "p0_ratio", "s_m"]
    header += ["w_m", "w_over_s", "converged", "gamma_u", "p0_ratio_eq14"]
    rows = []
    for i, s in enumerate(surfs):
        for row in sweep_rows(s.results):
            eq14 = float(p0_ratio_gaussian(row[1], s.gamma_u))
            rows.append((str(i + 1), s.h_rms, s.hurst, *row[:7], row[7], s.gamma_u, eq14))
    return header, rows


def write_sphere_files(
    data: PaperData,
    out: str | os.PathLike,
    *,
    format: _Format | None = None,
    dpi: float | None = None,
) -> list[str]:
    """Write the sphere versions of the paper's Figs. 3-5 and their CSV tables into ``out``.

    Files (figures in ``format``, PNG by default): ``fig3_profile_sphere`` (p(r) of surface 1
    at alpha = :data:`SPHERE_FIG3_ALPHA`, rough and Hertz), ``fig4_ws_sphere`` and
    ``fig5_p0ratio_sphere`` (the sweeps over :data:`SPHERE_ALPHA_RANGE`, with the Gaussian
    asymptote 1/(3 gamma_u alpha), :func:`fastline.theory.limits.p0_ratio_gaussian_sphere`). The CSV
    headers record the scene as :func:`write_files` does, with ``geometry: sphere``.

    Parameters
    ----------
    data : PaperData
        From :func:`sphere_paper_data`.
    out : str or path-like
        Existing, writable directory.
    format : {"png", "pdf", "svg"}, optional
        Figure format (default PNG).
    dpi : float, optional
        Resolution of PNG figures.

    Returns
    -------
    list of str
        The names of the files written (relative to ``out``), in the order written.
    """
    files, meta = _Files(out, format, dpi), _files_metadata(data, geometry="sphere")
    r3 = data.fig3
    hz = hertz_point_contact(E_STAR, RADIUS, r3.load)
    files.csv(
        "fig3_profile_sphere",
        ["r_m", "p_rough_Pa", "p_hertz_Pa"],
        zip(r3.r, r3.pressure, hz.pressure(r3.r), strict=True),
        {**meta, "load_N": r3.load, "alpha": r3.alpha},
        "Sphere version of Fig. 3: p(r) of surface 1, rough and smooth (Hertz)",
    )
    files.figure("fig3_profile_sphere", plotting.plot_profile(r3, label="rough (surface 1)"))

    lo, hi = SPHERE_ALPHA_RANGE
    title = (
        f"Sphere versions of Figs. 4-5: loads F [N] per surface with alpha log-spaced over "
        f"{lo:g}..{hi:g} (F = (4/3) E* R^(1/2) (h_rms/alpha)^(3/2)); p0_ratio_gaussian = "
        "1/(3 gamma_u alpha)"
    )
    names = ("fig4_ws_sphere", "fig5_p0ratio_sphere")
    _sweep_files(files, names, data, _sphere_sweep_table(data.surfaces), meta, title)
    return files.written


def _sphere_sweep_table(surfs: list[PaperSurface]) -> tuple[list, list]:
    """Header and rows of the tables of the sphere versions of Figs. 4-5: one row per surface
    and load, with the Gaussian asymptote 1/(3 gamma_u alpha)."""
    header = ["surface", "h_rms_m", "hurst", "load_N", "alpha", "p0_Pa", "p0_ratio", "s_m"]
    header += ["w_m", "w_over_s", "converged", "gamma_u", "p0_ratio_gaussian"]
    rows = []
    for i, s in enumerate(surfs):
        for row in sweep_rows(s.results):
            gauss = float(p0_ratio_gaussian_sphere(row[1], s.gamma_u))
            rows.append((str(i + 1), s.h_rms, s.hurst, *row, s.gamma_u, gauss))
    return header, rows


class _Files:
    """Writes into the directory ``out`` and keeps the names written, in order."""

    def __init__(self, out: str | os.PathLike, format: _Format | None, dpi: float | None) -> None:
        self.out, self.format, self.dpi = out, format, dpi
        self.written: list[str] = []

    def _path(self, name: str) -> str:
        self.written.append(name)
        return os.path.join(self.out, name)

    def csv(self, name: str, header: list, rows: Iterable, meta: dict, title: str) -> None:
        write_csv(self._path(f"{name}.csv"), header, rows, meta, title=title)

    def figure(self, name: str, fig: Any) -> None:
        path = self._path(f"{name}.{self.format or 'png'}")
        plotting.save_figure(fig, path, format=self.format, dpi=self.dpi)


def _sweep_files(
    files: _Files,
    names: tuple[str, str],
    data: PaperData,
    table: tuple[list, list],
    meta: dict,
    title: str,
) -> None:
    """The two sweep tables (the same rows in each CSV), then Figs. 4 (w/s) and 5 (p0 ratio)."""
    fig4, fig5 = names
    header, rows = table
    files.csv(fig4, header, rows, meta, title)
    files.csv(fig5, header, rows, meta, title)
    series = {s.label: s.results for s in data.surfaces}
    files.figure(fig4, plotting.plot_w_over_s(series))
    gamma_u = {s.label: s.gamma_u for s in data.surfaces}
    files.figure(fig5, plotting.plot_p0_ratio(series, gamma_u=gamma_u))


def _files_metadata(data: PaperData, **geometry: str) -> dict:
    """The header of every CSV: the scene without a single spectrum, then the three surfaces."""
    variant = {} if data.variant == DEFAULT_VARIANT else {"variant": data.variant}
    meta = scene_metadata(
        None, E_STAR, RADIUS, model="persson", gamma=data.gamma, n=data.n, **variant
    )
    meta.pop("spectrum")
    meta.update(**geometry, q0_1_per_m=Q0, qr_1_per_m=QR, q1_1_per_m=data.q1)
    for s in data.surfaces:
        meta[s.label.replace(" ", "_")] = f"h_rms {s.h_rms:g} m, H {s.hurst:g}"
    return meta


def _surface_label(s: PaperSurface) -> str:
    return f"{s.label}: $h_\\mathrm{{rms}}$ = {s.h_rms * 1e6:g} µm, $H$ = {s.hurst:g}"
