"""Figures of contact results: C(q), p(x) (or p along a sphere's diameter), w/s and
p0/p0_Hertz against alpha (log axis), one load sweep or several by label.

Units: SI, with mm and MPa for profiles.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from typing import TYPE_CHECKING, TypeAlias

import numpy as np
from numpy.typing import ArrayLike

from fastline._lib.validate import real_array
from fastline.reports.figures import (
    figure_and_axes,
    log_axis,
    no_outside_legend,
    outside_legend,
)
from fastline.theory.limits import (
    WS_GAUSSIAN,
    WS_HERTZ,
    WS_HERTZ_SPHERE,
    hertz_line_contact,
    hertz_point_contact,
    p0_ratio_gaussian,
    p0_ratio_gaussian_sphere,
)

if TYPE_CHECKING:  # annotations only: matplotlib and the solvers load on first use
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

    from fastline.contact.line import LineContactResult
    from fastline.contact.point import PointContactResult
    from fastline.theory.spectra import PSD

    ContactResult: TypeAlias = LineContactResult | PointContactResult
    #: one load sweep, or several by label
    Sweeps: TypeAlias = Sequence[ContactResult] | Mapping[str, Sequence[ContactResult]]

__all__ = ["plot_psd", "plot_profile", "plot_w_over_s", "plot_p0_ratio", "plot_sweep"]

_ALPHA_LABEL = r"$\alpha = h_\mathrm{rms}/\delta$"
_WS_LABEL = r"$w/s$ (FWHM / standard deviation)"
_P0_LABEL = r"$p_0/p_{0,\mathrm{Hertz}}$"


def _series(results) -> dict:
    """label -> list of results, from a list of results or a mapping of lists."""
    if isinstance(results, Mapping):
        return {str(k): list(v) for k, v in results.items()}
    results = list(results)
    if not results:
        raise ValueError("results must hold at least one LineContactResult")
    return {None: results}


def _sorted(results):
    return sorted(results, key=lambda r: r.alpha)


def plot_psd(
    psds: PSD | Mapping[str, PSD], *, q: ArrayLike | None = None, ax: Axes | None = None
) -> Figure:
    """Power spectra C(q) on log-log axes.

    Parameters
    ----------
    psds : PSD or mapping of label -> PSD
        Spectra to draw.
    q : array_like, optional
        Wavenumbers in 1/m; default 400 log-spaced points over the spectra's range.
    ax : matplotlib Axes, optional
    """
    if not isinstance(psds, Mapping):
        psds = {None: psds}
    if q is None:
        lo = min(p.q0 for p in psds.values())
        hi = max(p.q1 for p in psds.values())
        q = np.geomspace(lo, hi, 400)
    q = real_array("q", q)  # before the figure: a bad q leaves none open
    fig, ax, own = figure_and_axes(ax)
    for label, psd in psds.items():
        C = psd(q)
        live = C > 0.0
        ax.loglog(q[live], C[live], label=label)
    log_axis(ax.xaxis)
    log_axis(ax.yaxis)
    ax.set_xlabel(r"wavenumber $q$ (1/m)")
    ax.set_ylabel(r"$C(q)$ (m$^4$)")
    if any(k is not None for k in psds):
        # spectra fall from top left to bottom right: the lower left corner is free
        ax.legend(loc="lower left", fontsize=8, frameon=False)
    no_outside_legend(fig, ax, own)
    return fig


def plot_profile(
    result: ContactResult,
    *,
    hertz: bool = True,
    label: str | None = None,
    ax: Axes | None = None,
) -> Figure:
    """Pressure profile p(x) of one result, with the smooth (Hertz) profile at the same load.

    A point contact's profile is drawn along a diameter, with the Hertz sphere.

    Parameters
    ----------
    result : LineContactResult or PointContactResult
    hertz : bool
        Also draw the Hertz profile (paper eq. 6) at the same E*, R and load.
    label : str, optional
        Legend entry of the rough profile (default: its model and alpha).
    ax : matplotlib Axes, optional
    """
    if _is_point(result):
        return _plot_point_profile(result, hertz, label, ax)
    fig, ax, _ = figure_and_axes(ax)
    x_mm = result.x * 1e3
    if label is None:
        label = f"{result.model}, $\\alpha$ = {result.alpha:.3g}"
    ax.plot(x_mm, result.pressure / 1e6, "-", color="C0", label=label)
    hz = hertz_line_contact(result.E_star, result.radius, result.load)
    if hertz:
        ax.plot(x_mm, hz.pressure(result.x) / 1e6, "--", color="k", lw=1, label="Hertz (smooth)")
    half = 1.3 * max(hz.a if hertz else 0.0, 2.5 * result.s)
    ax.set_xlim(-half * 1e3, half * 1e3)
    ax.set_ylim(0.0, None)
    ax.set_xlabel(r"$x$ (mm)")
    ax.set_ylabel(r"nominal pressure $p$ (MPa)")
    outside_legend(ax)
    return fig


def _is_point(result) -> bool:
    """A point-contact result (it knows its Hertz radius)."""
    return hasattr(result, "hertz_radius")


def _plot_point_profile(result, hertz, label, ax):
    """:func:`plot_profile` of a point contact: p along a diameter, the Hertz sphere dashed."""
    from matplotlib.ticker import MaxNLocator  # optional: the plot extra

    fig, ax, _ = figure_and_axes(ax)
    x, p = result.diameter_profile()
    if label is None:
        label = f"{result.model}, $\\alpha$ = {result.alpha:.3g}"
    ax.plot(x * 1e3, p / 1e6, "-", color="C0", label=label)
    hz = hertz_point_contact(result.E_star, result.radius, result.load)
    if hertz:
        ax.plot(x * 1e3, hz.pressure(x) / 1e6, "--", color="k", lw=1, label="Hertz (smooth)")
    half = 1.3 * max(hz.a if hertz else 0.0, 2.5 * result.s)
    ax.set_xlim(-half * 1e3, half * 1e3)
    ax.xaxis.set_major_locator(MaxNLocator(nbins=6, symmetric=True))
    ax.set_ylim(0.0, None)
    ax.set_xlabel(r"position along a diameter $x$ (mm)")
    ax.set_ylabel(r"nominal pressure $p$ (MPa)")
    outside_legend(ax)
    return fig


def _ws_limits(values, hertz: float | None = None) -> tuple[float, float]:
    """y range of a w/s panel: the data and both reference values, with a margin."""
    hertz = WS_HERTZ if hertz is None else hertz
    v = np.asarray([x for x in values if math.isfinite(x)] or [WS_GAUSSIAN])
    lo, hi = min(v.min(), WS_GAUSSIAN), max(v.max(), hertz)
    pad = 0.07 * (hi - lo)  # room for the reference lines' labels
    return lo - pad, hi + pad


def plot_w_over_s(results: Sweeps, *, ax: Axes | None = None) -> Figure:
    """w/s against alpha (log axis) with the Hertz and Gaussian values labelled.

    Parameters
    ----------
    results : sequence of LineContactResult, or mapping of label -> sequence
        One or several load sweeps (paper Fig. 4); point-contact results (the sphere's
        version, with its Hertz value sqrt(15)).
    ax : matplotlib Axes, optional
    """
    series = _series(results)
    point = all(_is_point(r) for rs in series.values() for r in rs)
    hertz, hertz_text = WS_HERTZ, r"Hertz: $2\sqrt{3}$ = 3.464"
    if point:
        hertz, hertz_text = WS_HERTZ_SPHERE, r"Hertz sphere: $\sqrt{15}$ = 3.873"
    fig, ax, own = figure_and_axes(ax)
    allv = []
    for label, rs in series.items():
        rs = _sorted(rs)
        a = [r.alpha for r in rs]
        ws = [r.w_over_s for r in rs]
        allv += ws
        ax.semilogx(a, ws, "o-", ms=3, lw=1.2, label=label)
    ax.set_ylim(*_ws_limits(allv, hertz))
    log_axis(ax.xaxis)
    # reference lines labelled outside the band between them, where w/s usually lies: Hertz
    # above its line on the right (large alpha), Gaussian below its line on the left
    for y, ls, text, x, ha, dy, va in (
        (hertz, "--", hertz_text, 0.98, "right", 2, "bottom"),
        (WS_GAUSSIAN, ":", r"Gaussian: $2\sqrt{2\ln 2}$ = 2.355", 0.02, "left", -2, "top"),
    ):
        ax.axhline(y, ls=ls, color="k", lw=0.8)
        ax.annotate(
            text, (x, y), xycoords=("axes fraction", "data"), xytext=(0, dy),
            textcoords="offset points", ha=ha, va=va, fontsize=8,
        )  # fmt: skip
    ax.set_xlabel(_ALPHA_LABEL)
    ax.set_ylabel(_WS_LABEL)
    if any(k is not None for k in series):
        outside_legend(ax)
    else:
        no_outside_legend(fig, ax, own)
    return fig


def _gamma_u_for(gamma_u, label):
    if isinstance(gamma_u, Mapping):
        return gamma_u.get(label)
    return gamma_u


def plot_p0_ratio(
    results: Sweeps,
    *,
    gamma_u: float | Mapping[str, float] | None = None,
    ax: Axes | None = None,
) -> Figure:
    """p0/p0_Hertz against alpha (log axis), with the Gaussian asymptote (paper eq. 14).

    Parameters
    ----------
    results : sequence of LineContactResult, or mapping of label -> sequence
        One or several load sweeps (paper Fig. 5); point-contact results (the sphere's
        version).
    gamma_u : float or mapping of label -> float, optional
        ``u0 / h_rms`` of each series; when given, eq. 14 ``(pi / (8 gamma_u alpha))^(1/2)`` is
        drawn (dashed, in the series' colour; for a sphere its analogue ``1 / (3 gamma_u
        alpha)``, :func:`fastline.theory.limits.p0_ratio_gaussian_sphere`). The y range follows the
        data, not the asymptote (which grows without bound at small alpha).
    ax : matplotlib Axes, optional
    """
    series = _series(results)
    asymptote, name = p0_ratio_gaussian, "eq. 14"
    point = all(_is_point(r) for rs in series.values() for r in rs)
    if point:
        asymptote, name = p0_ratio_gaussian_sphere, r"$1/(3\gamma_u\alpha)$"
    fig, ax, _ = figure_and_axes(ax)
    top, bottom = 1.0, 1.0
    for k, (label, rs) in enumerate(series.items()):
        rs = _sorted(rs)
        a = np.array([r.alpha for r in rs])
        pr = np.array([r.p0_ratio for r in rs])
        top = max(top, float(np.nanmax(pr)))
        bottom = min(bottom, float(np.nanmin(pr)))
        color = f"C{k % 10}"
        ax.semilogx(a, pr, "o-", ms=3, lw=1.2, color=color, label=label)
        gu = _gamma_u_for(gamma_u, label)
        if gu is not None and np.all(a > 0):
            aa = np.geomspace(a.min(), a.max(), 200)
            ax.semilogx(
                aa,
                asymptote(aa, gu),
                "--",
                color=color,
                lw=0.9,
                label=f"{name}, $\\gamma_u$ = {gu:.3f}",
            )
    ax.axhline(1.0, color="k", lw=0.6, label="Hertz")
    if point:  # p0 falls like 1/alpha: a log axis, on which the asymptote is a straight line
        ax.set_yscale("log")
        ax.set_ylim(0.5 * bottom, 2.0 * top)
        log_axis(ax.yaxis)
    else:
        ax.set_ylim(0.0, 1.15 * top)
    log_axis(ax.xaxis)
    ax.set_xlabel(_ALPHA_LABEL)
    ax.set_ylabel(_P0_LABEL)
    outside_legend(ax)
    return fig


def plot_sweep(results: Sweeps, *, gamma_u: float | Mapping[str, float] | None = None) -> Figure:
    """Two panels of a load sweep: w/s and p0/p0_Hertz against alpha.

    Parameters
    ----------
    results : sequence of LineContactResult, or mapping of label -> sequence
    gamma_u : float or mapping, optional
        For the eq. 14 curve (see :func:`plot_p0_ratio`).

    Returns
    -------
    matplotlib.figure.Figure
    """
    fig, _, _ = figure_and_axes(None, size=(10.0, 3.8))
    fig.clear()
    fig.subplots_adjust(left=0.07, right=0.83, bottom=0.15, top=0.96, wspace=0.28)
    ax1, ax2 = fig.subplots(1, 2)
    plot_w_over_s(results, ax=ax1)
    plot_p0_ratio(results, gamma_u=gamma_u, ax=ax2)
    if ax1.get_legend() is not None:  # one legend (the right panel's) is enough
        ax1.get_legend().remove()
    return fig
