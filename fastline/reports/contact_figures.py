"""Figures of contact results: C(q), p(x) (or p along a sphere's diameter), w/s and
p0/p0_Hertz against alpha (log axis), one load sweep or several by label.

Units: SI, with mm and MPa for profiles.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from typing import TYPE_CHECKING, Literal, TypeAlias

import numpy as np
from numpy.typing import ArrayLike

from fastline._lib.validate import real_array
from fastline.contact import plot_profile
from fastline.reports.figures import (
    figure_and_axes,
    legend_above,
    log_axis,
    no_outside_legend,
)
from fastline.theory.limits import (
    WS_GAUSSIAN,
    WS_HERTZ,
    WS_HERTZ_SPHERE,
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


def _is_point(result) -> bool:
    """A point-contact result (it knows its Hertz radius)."""
    return hasattr(result, "hertz_radius")


def _ws_limits(values, hertz: float | None = None) -> tuple[float, float]:
    """y range of a w/s panel: the data and both reference values, with a margin."""
    hertz = WS_HERTZ if hertz is None else hertz
    v = np.asarray([x for x in values if math.isfinite(x)] or [WS_GAUSSIAN])
    lo, hi = min(v.min(), WS_GAUSSIAN), max(v.max(), hertz)
    pad = 0.1 * (hi - lo)  # room for the reference lines' labels
    return lo - pad, hi + pad


#: a marker per series, open (a series never hides another drawn after it)
_MARKERS = ("o", "s", "^", "D", "v", "P", "X", "*")


def _style(k: int, count: int) -> dict:
    """Line and marker of series ``k`` of ``count``: its colour and its own open marker, each
    series drawn over the next ones with a thinner line and a smaller marker, so that series
    on the same points all show (nested markers, the lines as stripes)."""
    return dict(
        color=f"C{k % 10}", marker=_MARKERS[k % len(_MARKERS)], ms=3.5 + 1.5 * k, mfc="none",
        mew=1.0, lw=1.0 + 0.9 * k, zorder=2.5 + count - k,
    )  # fmt: skip


def _data_label(label, rs) -> str:
    """A series' legend entry: its label, or for an unnamed sweep its model."""
    return label if label is not None else f"rough ({rs[0].model})"


def _x_values(rs, x: str) -> np.ndarray:
    if x not in ("alpha", "load"):
        raise ValueError(f"x must be 'alpha' or 'load', got {x!r}")
    return np.array([getattr(r, x) for r in rs])


def _x_axis(ax, series: dict, x: str) -> None:
    """Label the x axis (log); against the load, alpha on a secondary axis on top when every
    series has the same alpha(load) (a power law: alpha ~ 1/f_N for a cylinder, F^(-2/3) for a
    sphere)."""
    log_axis(ax.xaxis)
    if x == "alpha":
        ax.set_xlabel(_ALPHA_LABEL)
        return
    first = next(iter(series.values()))[0]
    unit = getattr(first, "LOAD_UNIT", "N/m")
    symbol = "F" if unit == "N" else r"f_\mathrm{N}"
    ax.set_xlabel(f"load ${symbol}$ ({unit})")
    fits = {_alpha_law(rs) for rs in series.values()}
    if len(fits) != 1 or None in fits:
        return
    c, k = fits.pop()

    def power(c, k):  # matplotlib also maps 0 and negative view limits: keep them finite
        return lambda v: c * np.clip(np.abs(v), 1e-30, 1e30) ** k

    top = ax.secondary_xaxis("top", functions=(power(c, k), power(c ** (-1.0 / k), 1.0 / k)))
    top.set_xlabel(_ALPHA_LABEL, fontsize=9)
    top.tick_params(labelsize=8)


def _alpha_law(rs) -> tuple[float, float] | None:
    """``(c, k)`` of ``alpha = c load^k`` through a sweep's results (rounded to 9 digits, so
    that sweeps of one scene compare equal); None without two distinct loads."""
    f = np.array([r.load for r in rs])
    a = np.array([r.alpha for r in rs])
    ok = np.isfinite(a) & (a > 0) & (f > 0)
    if len(np.unique(f[ok])) < 2:
        return None
    k, lnc = np.polyfit(np.log(f[ok]), np.log(a[ok]), 1)
    return float(f"{math.exp(lnc):.9g}"), float(f"{k:.9g}")


def plot_w_over_s(
    results: Sweeps, *, x: Literal["alpha", "load"] = "alpha", ax: Axes | None = None
) -> Figure:
    """w/s against alpha (or the load) on a log axis, with the Hertz and Gaussian values.

    Parameters
    ----------
    results : sequence of LineContactResult, or mapping of label -> sequence
        One or several load sweeps (paper Fig. 4); point-contact results (the sphere's
        version, with its Hertz value sqrt(15)).
    x : {"alpha", "load"}
        The x axis: alpha (the paper's), or the load (N/m, N) with alpha on a secondary axis.
    ax : matplotlib Axes, optional
    """
    series = _series(results)
    point = all(_is_point(r) for rs in series.values() for r in rs)
    hertz, hertz_text = WS_HERTZ, r"Hertz: $2\sqrt{3}$ = 3.464"
    if point:
        hertz, hertz_text = WS_HERTZ_SPHERE, r"Hertz sphere: $\sqrt{15}$ = 3.873"
    fig, ax, own = figure_and_axes(ax)
    allv = []
    for k, (label, rs) in enumerate(series.items()):
        rs = _sorted(rs)
        ws = [r.w_over_s for r in rs]
        allv += ws
        ax.semilogx(_x_values(rs, x), ws, **_style(k, len(series)), label=_data_label(label, rs))
    ax.set_ylim(*_ws_limits(allv, hertz))
    # reference lines labelled outside the band between them, where w/s usually lies: Hertz
    # above its line on the right (large alpha), Gaussian below its line on the left
    right, left = (0.98, 0.02) if x == "alpha" else (0.02, 0.98)  # the load runs the other way
    for y, ls, text, xt, dy, va in (
        (hertz, "--", hertz_text, right, 2, "bottom"),
        (WS_GAUSSIAN, ":", r"Gaussian: $2\sqrt{2\ln 2}$ = 2.355", left, -2, "top"),
    ):
        ax.axhline(y, ls=ls, color="k", lw=0.8)
        ax.annotate(
            text, (xt, y), xycoords=("axes fraction", "data"), xytext=(0, dy),
            textcoords="offset points", ha="right" if xt > 0.5 else "left", va=va, fontsize=8,
        )  # fmt: skip
    _x_axis(ax, series, x)
    ax.set_ylabel(_WS_LABEL)
    if any(k is not None for k in series):
        legend_above(ax, own)
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
    x: Literal["alpha", "load"] = "alpha",
    ax: Axes | None = None,
) -> Figure:
    """p0/p0_Hertz against alpha (or the load), with the Gaussian asymptote (paper eq. 14).

    Parameters
    ----------
    results : sequence of LineContactResult, or mapping of label -> sequence
        One or several load sweeps (paper Fig. 5); point-contact results (the sphere's
        version).
    gamma_u : float or mapping of label -> float, optional
        ``u0 / h_rms`` of each series; when given, eq. 14 ``(pi / (8 gamma_u alpha))^(1/2)`` is
        drawn (dashed, in the series' colour; for a sphere its analogue ``1 / (3 gamma_u
        alpha)``, :func:`fastline.theory.limits.p0_ratio_gaussian_sphere`) where it lies within
        the axes, and listed in the legend only then. The y range follows the data, not the
        asymptote (which grows without bound at small alpha).
    x : {"alpha", "load"}
        The x axis: alpha (the paper's), or the load (N/m, N) with alpha on a secondary axis.
    ax : matplotlib Axes, optional
    """
    series = {k: _sorted(v) for k, v in _series(results).items()}
    asymptote, name = p0_ratio_gaussian, "eq. 14"
    point = all(_is_point(r) for rs in series.values() for r in rs)
    if point:
        asymptote, name = p0_ratio_gaussian_sphere, r"$1/(3\gamma_u\alpha)$"
    fig, ax, own = figure_and_axes(ax)
    ratios = np.array([r.p0_ratio for rs in series.values() for r in rs], dtype=float)
    top, bottom = max(1.0, float(np.nanmax(ratios))), min(1.0, float(np.nanmin(ratios)))
    lo, hi = (0.5 * bottom, 2.0 * top) if point else (0.0, 1.15 * top)
    for k, (label, rs) in enumerate(series.items()):
        style = _style(k, len(series))
        pr = [r.p0_ratio for r in rs]
        ax.semilogx(_x_values(rs, x), pr, **style, label=_data_label(label, rs))
        gu = _gamma_u_for(gamma_u, label)
        a = np.array([r.alpha for r in rs])
        if gu is None or not np.all(a > 0):
            continue
        aa = np.geomspace(a.min(), a.max(), 200)
        yy = asymptote(aa, gu)
        seen = (yy >= lo) & (yy <= hi)
        if seen.any():  # an asymptote off the axes is neither drawn nor listed
            law = _alpha_law(rs) if x == "load" else (1.0, 1.0)  # alpha = c load^k
            if law is None:  # one load: no line to draw
                continue
            xx = (aa / law[0]) ** (1.0 / law[1])
            text = f"{name}, $\\gamma_u$ = {gu:.3f}"
            ax.semilogx(xx[seen], yy[seen], "--", color=style["color"], lw=0.9, label=text)
    ax.axhline(1.0, color="k", lw=0.6, label="Hertz")
    if point:  # p0 falls like 1/alpha: a log axis, on which the asymptote is a straight line
        ax.set_yscale("log")
        log_axis(ax.yaxis)
    ax.set_ylim(lo, hi)
    _x_axis(ax, series, x)
    ax.set_ylabel(_P0_LABEL)
    legend_above(ax, own)
    return fig


def plot_sweep(
    results: Sweeps,
    *,
    gamma_u: float | Mapping[str, float] | None = None,
    x: Literal["alpha", "load"] = "load",
) -> Figure:
    """Two panels of a load sweep: w/s and p0/p0_Hertz against the load (alpha on a secondary
    axis on top) or against alpha; one legend below both.

    Parameters
    ----------
    results : sequence of LineContactResult, or mapping of label -> sequence
    gamma_u : float or mapping, optional
        For the eq. 14 curve (see :func:`plot_p0_ratio`).
    x : {"load", "alpha"}
        The x axis of both panels (see :func:`plot_w_over_s`).

    Returns
    -------
    matplotlib.figure.Figure
    """
    fig, _, _ = figure_and_axes(None, size=(10.0, 4.3))
    fig.clear()
    fig.subplots_adjust(left=0.07, right=0.98, bottom=0.2, top=0.86, wspace=0.25)
    ax1, ax2 = fig.subplots(1, 2)
    plot_w_over_s(results, x=x, ax=ax1)
    plot_p0_ratio(results, gamma_u=gamma_u, x=x, ax=ax2)
    entries: dict = {}
    for ax in (ax1, ax2):
        if ax.get_legend() is not None:
            ax.get_legend().remove()
        for h, label in zip(*ax.get_legend_handles_labels(), strict=True):
            entries.setdefault(label, h)
    fig.legend(
        list(entries.values()), list(entries), loc="lower center", ncol=min(4, len(entries)),
        fontsize=8, frameon=False, bbox_to_anchor=(0.5, 0.0),
    )  # fmt: skip
    return fig
