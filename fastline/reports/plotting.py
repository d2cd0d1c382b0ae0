"""Figures of line-contact results: C(q), p(x), w/s and p0/p0_Hertz against alpha, leak rates.

Each function draws into a given matplotlib ``Axes`` (``ax=``) or makes its own
:class:`matplotlib.figure.Figure` (no pyplot, no global backend change) and returns the figure.
matplotlib is imported only when a figure is made (install it with the ``plot`` extra).

Conventions: alpha on a log axis, SI units with mm and MPa for profiles, no titles (captions
belong to the document), reference lines labelled, legends outside the data.

>>> import fastline as fl                                              # doctest: +SKIP
>>> res = [fl.solve_line_contact(psd, 1.33e9, 0.01, f) for f in (1e3, 1e4, 1e5)]
>>> fig = fl.plotting.plot_sweep(res)
>>> fl.plotting.save_figure(fig, "sweep.pdf")
"""

from __future__ import annotations

import math
import os
from collections.abc import Mapping, Sequence
from typing import TYPE_CHECKING, Literal, TypeAlias

import numpy as np
from numpy.typing import ArrayLike

from fastline._lib.validate import real_array

if TYPE_CHECKING:  # annotations only: matplotlib and the solvers load on first use
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

    from fastline.contact.line import LineContactResult
    from fastline.contact.point import PointContactResult
    from fastline.leakage.flow import LeakResult
    from fastline.reports.validation import FlatValidation, ProfileValidation
    from fastline.surfaces.scan import ScanSpectrum
    from fastline.theory.spectra import PSD

    ContactResult: TypeAlias = LineContactResult | PointContactResult
    #: one load sweep, or several by label
    Sweeps: TypeAlias = Sequence[ContactResult] | Mapping[str, Sequence[ContactResult]]

__all__ = [
    "FORMATS",
    "plot_psd",
    "plot_profile",
    "plot_w_over_s",
    "plot_p0_ratio",
    "plot_sweep",
    "plot_leak",
    "plot_leak_sweep",
    "plot_validation",
    "plot_flat_validation",
    "plot_measured_psd",
    "save_figure",
]

#: file formats :func:`save_figure` writes
FORMATS = ("png", "pdf", "svg")
#: resolution of raster (PNG) figures in dots per inch
DEFAULT_DPI = 150
_ALPHA_LABEL = r"$\alpha = h_\mathrm{rms}/\delta$"
_WS_LABEL = r"$w/s$ (FWHM / standard deviation)"
_P0_LABEL = r"$p_0/p_{0,\mathrm{Hertz}}$"
_PANEL = (5.6, 3.8)  # inches: one panel with a legend on its right
#: lower end of the critical-gap axis of :func:`plot_leak` (m): narrower gaps (below an atom's
#: size, a closed seal for any practical purpose; they reach 1e-60 m near sealing) run off it
GAP_FLOOR = 1e-12


def _figure(ax, size=_PANEL):
    """(figure, axes): the given axes' figure, or a new one with fixed margins."""
    if ax is not None:
        return ax.figure, ax, False
    try:
        from matplotlib.figure import Figure
    except ImportError:
        raise ImportError(
            'plotting needs matplotlib: pip install matplotlib (the "plot" extra of '
            "fastline-contact)"
        ) from None
    fig = Figure(figsize=size)
    # fixed margins (no tight/constrained layout pass: each costs a full draw); the right
    # margin holds the legend
    fig.subplots_adjust(left=0.13, right=0.66, bottom=0.15, top=0.96)
    return fig, fig.add_subplot(), True


_SUPERSCRIPT = str.maketrans(
    "-0123456789", "\u207b\u2070\u00b9\u00b2\u00b3\u2074\u2075\u2076\u2077\u2078\u2079"
)


def _power_of_ten(value, _pos=None) -> str:
    """Tick label ``10⁻³`` in plain Unicode: a log axis without mathtext tick labels (their
    parsing took 0.37 s of the ~1 s spent on the paper's four figures)."""
    if value <= 0.0:
        return ""
    e = math.log10(value)
    return "10" + str(round(e)).translate(_SUPERSCRIPT) if abs(e - round(e)) < 1e-9 else ""


def _log_axis(axis) -> None:
    """Major ticks at powers of ten labelled 10ⁿ (Unicode superscripts); minor ticks unlabelled.

    Left to matplotlib's own labels when the axis spans fewer than two powers of ten.
    """
    from matplotlib.ticker import FuncFormatter, NullFormatter

    lo, hi = sorted(axis.get_view_interval())
    if lo <= 0.0 or math.floor(math.log10(hi)) - math.ceil(math.log10(lo)) < 1:
        return
    axis.set_major_formatter(FuncFormatter(_power_of_ten))
    axis.set_minor_formatter(NullFormatter())


def _series(results) -> dict:
    """label -> list of results, from a list of results or a mapping of lists."""
    if isinstance(results, Mapping):
        return {str(k): list(v) for k, v in results.items()}
    results = list(results)
    if not results:
        raise ValueError("results must hold at least one LineContactResult")
    return {None: results}


def _legend(ax) -> None:
    """Legend outside the axes, on the right (never over the data)."""
    ax.legend(loc="upper left", bbox_to_anchor=(1.02, 1.0), fontsize=8, frameon=False)


def _no_outside_legend(fig, ax, own: bool) -> None:
    """Give the right margin back to the axes of a figure made here without an outer legend."""
    if own and len(fig.axes) == 1:
        fig.subplots_adjust(left=0.19, right=0.96)
        fig.set_size_inches(4.6, fig.get_size_inches()[1])


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
    fig, ax, own = _figure(ax)
    for label, psd in psds.items():
        C = psd(q)
        live = C > 0.0
        ax.loglog(q[live], C[live], label=label)
    _log_axis(ax.xaxis)
    _log_axis(ax.yaxis)
    ax.set_xlabel(r"wavenumber $q$ (1/m)")
    ax.set_ylabel(r"$C(q)$ (m$^4$)")
    if any(k is not None for k in psds):
        # spectra fall from top left to bottom right: the lower left corner is free
        ax.legend(loc="lower left", fontsize=8, frameon=False)
    _no_outside_legend(fig, ax, own)
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
    from fastline.theory.limits import hertz_line_contact

    if _is_point(result):
        return _plot_point_profile(result, hertz, label, ax)
    fig, ax, _ = _figure(ax)
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
    _legend(ax)
    return fig


def _is_point(result) -> bool:
    """A point-contact result (it knows its Hertz radius)."""
    return hasattr(result, "hertz_radius")


def _plot_point_profile(result, hertz, label, ax):
    """:func:`plot_profile` of a point contact: p along a diameter, the Hertz sphere dashed."""
    from matplotlib.ticker import MaxNLocator

    from fastline.theory.limits import hertz_point_contact

    fig, ax, _ = _figure(ax)
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
    _legend(ax)
    return fig


def _ws_limits(values, hertz: float | None = None) -> tuple[float, float]:
    """y range of a w/s panel: the data and both reference values, with a margin."""
    from fastline.theory.limits import WS_GAUSSIAN, WS_HERTZ

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
    from fastline.theory.limits import WS_GAUSSIAN, WS_HERTZ, WS_HERTZ_SPHERE

    series = _series(results)
    point = all(_is_point(r) for rs in series.values() for r in rs)
    hertz, hertz_text = WS_HERTZ, r"Hertz: $2\sqrt{3}$ = 3.464"
    if point:
        hertz, hertz_text = WS_HERTZ_SPHERE, r"Hertz sphere: $\sqrt{15}$ = 3.873"
    fig, ax, own = _figure(ax)
    allv = []
    for label, rs in series.items():
        rs = _sorted(rs)
        a = [r.alpha for r in rs]
        ws = [r.w_over_s for r in rs]
        allv += ws
        ax.semilogx(a, ws, "o-", ms=3, lw=1.2, label=label)
    ax.set_ylim(*_ws_limits(allv, hertz))
    _log_axis(ax.xaxis)
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
        _legend(ax)
    else:
        _no_outside_legend(fig, ax, own)
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
    from fastline.theory.limits import p0_ratio_gaussian, p0_ratio_gaussian_sphere

    series = _series(results)
    asymptote, name = p0_ratio_gaussian, "eq. 14"
    point = all(_is_point(r) for rs in series.values() for r in rs)
    if point:
        asymptote, name = p0_ratio_gaussian_sphere, r"$1/(3\gamma_u\alpha)$"
    fig, ax, _ = _figure(ax)
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
        _log_axis(ax.yaxis)
    else:
        ax.set_ylim(0.0, 1.15 * top)
    _log_axis(ax.xaxis)
    ax.set_xlabel(_ALPHA_LABEL)
    ax.set_ylabel(_P0_LABEL)
    _legend(ax)
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
    fig, _, _ = _figure(None, size=(10.0, 3.8))
    fig.clear()
    fig.subplots_adjust(left=0.07, right=0.83, bottom=0.15, top=0.96, wspace=0.28)
    ax1, ax2 = fig.subplots(1, 2)
    plot_w_over_s(results, ax=ax1)
    plot_p0_ratio(results, gamma_u=gamma_u, ax=ax2)
    if ax1.get_legend() is not None:  # one legend (the right panel's) is enough
        ax1.get_legend().remove()
    return fig


def _cell_edges(x: np.ndarray) -> np.ndarray:
    """Edges of the strips centred at x: halfway between centres, the end cells symmetric (the
    strips of :func:`fastline.leak_rate_profile`)."""
    mid = 0.5 * (x[1:] + x[:-1])
    return np.concatenate([[2.0 * x[0] - mid[0]], mid, [2.0 * x[-1] - mid[-1]]])


def _leak_window(leak) -> tuple[float, float]:
    """x range (m) of a leak figure: where p >= 1e-3 max(p), widened by 15 % on each side."""
    x, p = leak.x, leak.pressure
    inside = x[p >= 1e-3 * p.max()]
    pad = 0.15 * max(inside[-1] - inside[0], x[1] - x[0])
    return max(inside[0] - pad, x[0]), min(inside[-1] + pad, x[-1])


def _leak_band(leak) -> tuple[float, float, str]:
    """(lo, hi, label) in m of the region a leak is decided in: the sealed strips when sealed,
    else the central 90 % of the flow resistance."""
    edges = _cell_edges(leak.x)
    if leak.sealed:
        k = np.flatnonzero(leak.sealed_strips)
        label = f"sealed: $P(q_1, p) \\geq {leak.threshold:g}$"
        return edges[k[0]], edges[k[-1] + 1], label
    cum = np.concatenate([[0.0], leak.cumulative_share])
    lo, hi = np.interp([0.05, 0.95], cum, edges)
    return lo, hi, f"90% of the flow resistance ({(hi - lo) * 1e6:.3g} µm wide)"


def plot_leak(leak: LeakResult, *, axes: Sequence[Axes] | None = None) -> Figure:
    """Where a seal leaks: p(x) above, the critical gap u_c(x) below (log axis), sharing x.

    The region holding the central 90% of the flow resistance (or, when sealed, the sealed
    strips) is shaded in both panels; dotted lines mark the FWHM of p. Gaps below
    :data:`GAP_FLOOR` (1e-12 m) run off the bottom of the u_c axis; sealed strips (u_c = 0)
    leave a gap in the line.

    Parameters
    ----------
    leak : LeakResult
        From :func:`fastline.leak_rate` (or :func:`fastline.leak_rate_profile`).
    axes : pair of matplotlib Axes, optional
        (top, bottom) to draw into; default a new figure.

    Returns
    -------
    matplotlib.figure.Figure
    """
    if axes is None:
        fig, _, _ = _figure(None, size=(5.6, 5.2))
        fig.clear()
        fig.subplots_adjust(left=0.15, right=0.96, bottom=0.11, top=0.88, hspace=0.08)
        top, bottom = fig.subplots(2, 1, sharex=True)
    else:
        top, bottom = axes
        fig = top.figure
    x_mm = leak.x * 1e3
    top.plot(x_mm, leak.pressure / 1e6, "-", color="C0")
    top.set_ylim(0.0, 1.1 * leak.pressure.max() / 1e6)
    top.set_ylabel(r"nominal pressure $p$ (MPa)")
    # 0 in sealed strips, inf where p = 0: gaps in the line, not a segment across them
    shown = np.isfinite(leak.u_c) & (leak.u_c > 0.0)
    bottom.semilogy(x_mm, np.where(shown, leak.u_c, np.nan), "-", color="C3")
    bottom.set_ylabel(r"critical gap $u_c$ (m)")
    radial = leak.inner_radius is not None
    bottom.set_xlabel(r"$r$ (mm)" if radial else r"$x$ (mm)")
    lo, hi, text = _leak_band(leak)
    half = leak.x[leak.pressure >= 0.5 * leak.pressure.max()]
    width = "half width at half maximum" if radial else "FWHM"
    fwhm = f"{width} of $p$ ({leak.share_in_fwhm:.1%} of the resistance inside)"
    marks = (half[-1],) if radial else (half[0], half[-1])  # radial: the half width only
    for k, ax in enumerate((top, bottom)):
        color = "C3" if leak.sealed else "C2"
        ax.axvspan(lo * 1e3, hi * 1e3, color=color, alpha=0.15, lw=0, label=text if k else None)
        for j, xf in enumerate(marks):
            lab = fwhm if (k == 0 and j == 0) else None
            ax.axvline(xf * 1e3, ls=":", color="k", lw=0.8, label=lab)
        if radial:
            lab = "orifice (the fluid enters at its edge)" if k == 0 else None
            ax.axvspan(0.0, leak.inner_radius * 1e3, color="0.6", alpha=0.4, lw=0, label=lab)
    window = _leak_window(leak)
    bottom.set_xlim(window[0] * 1e3, window[1] * 1e3)
    seen = shown & (leak.x >= window[0]) & (leak.x <= window[1])
    if seen.any():
        u = leak.u_c[seen]
        bottom.set_ylim(max(0.5 * u.min(), GAP_FLOOR), 2.0 * u.max())
    _log_axis(bottom.yaxis)
    handles = top.get_legend_handles_labels()
    more = bottom.get_legend_handles_labels()
    # above the top panel, off the data
    top.legend(
        handles[0] + more[0], handles[1] + more[1], loc="lower left", bbox_to_anchor=(0.0, 1.01),
        ncols=1, fontsize=8, frameon=False, borderaxespad=0.0,
    )  # fmt: skip
    return fig


def plot_leak_sweep(
    loads: ArrayLike,
    leaks: Sequence[LeakResult],
    *,
    label: str | None = None,
    ax: Axes | None = None,
) -> Figure:
    """Leak rate Q against load on log-log axes: how much squeeze stops the leak.

    Sealed loads (Q = 0, not on a log axis) are marked by triangles at the bottom of the axes
    with the sealed range shaded; loads whose solve did not converge are circled in red.

    Parameters
    ----------
    loads : array_like
        Loads per unit length f_N in N/m (e.g. ``[r.load for r in results]``); for radial flow
        out of a point contact (``leaks[0].inner_radius`` set), the total loads F in N.
    leaks : sequence of LeakResult
        Their leak rates, in the same order.
    label : str, optional
        Legend entry of the curve (e.g. the pressure drop when comparing several).
    ax : matplotlib Axes, optional

    Returns
    -------
    matplotlib.figure.Figure
    """
    f = real_array("loads", loads)
    leaks = list(leaks)
    if f.ndim != 1 or f.size != len(leaks) or f.size == 0:
        raise ValueError(
            f"loads and leaks must be non-empty and of the same length, got {f.size} loads "
            f"and {len(leaks)} leak results"
        )
    order = np.argsort(f)
    f = f[order]
    leaks = [leaks[i] for i in order]
    Q = np.array([k.Q for k in leaks])
    sealed = np.array([k.sealed for k in leaks])
    bad = ~np.array([k.converged for k in leaks])
    fig, ax, own = _figure(ax)
    ax.loglog(f[~sealed], Q[~sealed], "o-", ms=3, lw=1.2, color="C0", label=label)
    if np.any(~sealed):
        q_lo, q_hi = Q[~sealed].min(), Q[~sealed].max()
        ax.set_ylim(q_lo / 10.0, q_hi * 10.0)
    from matplotlib.transforms import blended_transform_factory

    at_bottom = blended_transform_factory(ax.transData, ax.transAxes)  # x data, y axes fraction
    if sealed.any():
        ax.axvspan(f[sealed].min(), f.max(), color="0.9", lw=0, zorder=0)
        ax.plot(
            f[sealed], np.zeros(sealed.sum()), "v", color="k", ms=5, transform=at_bottom,
            clip_on=False, label="sealed ($Q$ = 0)",
        )  # fmt: skip
    circle = dict(ls="none", marker="o", mfc="none", mec="r", ms=8, clip_on=False)
    if (bad & ~sealed).any():
        ax.plot(f[bad & ~sealed], Q[bad & ~sealed], label="not converged", **circle)
    if (bad & sealed).any():
        label = None if (bad & ~sealed).any() else "not converged"
        ax.plot(f[bad & sealed], np.zeros((bad & sealed).sum()), transform=at_bottom, **circle,
                label=label)  # fmt: skip
    pad = (f[-1] / f[0]) ** 0.03 if f[-1] > f[0] else 1.5
    ax.set_xlim(f[0] / pad, f[-1] * pad)
    _log_axis(ax.xaxis)
    _log_axis(ax.yaxis)
    radial = leaks[0].inner_radius is not None  # a point contact: the load on the sphere
    ax.set_xlabel(r"load $F$ (N)" if radial else r"load per unit length $f_N$ (N/m)")
    ax.set_ylabel(r"leak rate $Q$ (m$^3$/s)")
    ax.grid(True, which="major", alpha=0.3)
    if ax.get_legend_handles_labels()[1]:
        _legend(ax)
        if own:  # short legend entries: a narrower right margin than _figure's
            fig.set_size_inches(5.0, fig.get_size_inches()[1])
            fig.subplots_adjust(left=0.17, right=0.71)
    else:
        _no_outside_legend(fig, ax, own)
    return fig


def _pressure_unit(p_max: float) -> tuple[float, str]:
    return (1e3, "kPa") if p_max < 1e6 else (1e6, "MPa")


def _pressure_axis(ax) -> None:
    """Log pressure axis labelled at 1, 2, 5 times powers of ten (often less than two decades)."""
    from matplotlib.ticker import FuncFormatter, LogLocator, NullFormatter

    ax.set_xscale("log")
    ax.set_xlabel(r"nominal pressure $p$ (Pa)")
    lo, hi = sorted(ax.get_xlim())
    if hi / lo >= 100.0:  # two decades or more: powers of ten
        _log_axis(ax.xaxis)
        return
    ax.xaxis.set_major_locator(LogLocator(subs=(1.0, 2.0, 5.0)))
    ax.xaxis.set_major_formatter(FuncFormatter(lambda v, _pos: f"{v:g}"))
    ax.xaxis.set_minor_formatter(NullFormatter())


def plot_validation(validation: ProfileValidation, *, ax: Axes | None = None) -> Figure:
    """Theory against BEM for a cylinder or a sphere
    (:func:`fastline.reports.validation.validate_line_contact`,
    :func:`~fastline.reports.validation.validate_point_contact`): the BEM ensemble ``p_bar(x)`` (sphere:
    ``p_bar(r)`` over rings) with a band of two standard errors, each model's profile and the
    Hertz profile.

    Parameters
    ----------
    validation : fastline.reports.validation.LineValidation or PointValidation
    ax : matplotlib Axes, optional
    """
    from fastline.theory.limits import hertz_line_contact, hertz_point_contact

    fig, ax, _ = _figure(ax)
    e = validation.ensemble
    scale, unit = _pressure_unit(max(e.p0, e.p0_hertz))
    x = e.coordinate * 1e3
    band = 2.0 * e.pressure_error
    ax.fill_between(
        x,
        (e.pressure - band) / scale,
        (e.pressure + band) / scale,
        color="0.75",
        lw=0,
        label="BEM ± 2 s.e.",
    )
    ax.plot(
        x,
        e.pressure / scale,
        "-",
        color="k",
        lw=1.2,
        label=rf"BEM $\bar p$ ({e.realizations} surfaces)",
    )
    sphere = validation.geometry == "sphere"
    styles = ["-", "--", "-.", ":"]
    for k, (name, r) in enumerate(validation.results.items()):
        coord = r.r if sphere else r.x
        ax.plot(coord * 1e3, r.pressure / scale, styles[k % 4], color=f"C{k}", lw=1.2, label=name)
    scene = e.scene
    hertz = hertz_point_contact if sphere else hertz_line_contact
    hz = hertz(scene.E_star, scene.radius, scene.load)
    half = 1.3 * max(hz.a, 2.5 * e.s)
    xs = np.linspace(0.0 if sphere else -half, half, 801)
    ax.plot(xs * 1e3, hz.pressure(xs) / scale, ":", color="0.4", lw=1, label="Hertz (smooth)")
    ax.set_xlim(xs[0] * 1e3, half * 1e3)
    ax.set_ylim(0.0, None)
    ax.set_xlabel(r"$r$ (mm)" if sphere else r"$x$ (mm)")
    ax.set_ylabel(rf"nominal pressure $p$ ({unit})")
    ax.text(0.02, 0.97, rf"$\alpha$ = {e.alpha:.3g}", transform=ax.transAxes, va="top", fontsize=8)
    _legend(ax)
    return fig


def plot_flat_validation(
    validation: FlatValidation, *, axes: Sequence[Axes] | None = None
) -> Figure:
    """Theory against BEM for a flat contact (:func:`fastline.reports.validation.validate_flat_contact`):
    mean separation u(p) of each model against the BEM mean gap (left), the critical-junction
    gap u_c against the BEM's Reynolds effective gap (right); BEM points with two standard
    errors.

    Parameters
    ----------
    validation : fastline.reports.validation.FlatValidation
    axes : pair of matplotlib Axes, optional
    """
    if axes is None:
        fig, _, _ = _figure(None, size=(9.0, 3.6))
        fig.clear()
        fig.subplots_adjust(left=0.08, right=0.78, bottom=0.15, top=0.96, wspace=0.3)
        axes = fig.subplots(1, 2)
    else:
        fig = axes[0].figure
    v = validation
    p = v.pressures
    pp = np.geomspace(p.min() / 1.5, p.max() * 1.5, 100) if p.size > 1 else p
    a0, a1 = axes
    gap = np.array([e.mean_gap for e in v.ensembles])
    gap_e = np.array([e.mean_gap_error for e in v.ensembles])
    a0.errorbar(p, gap * 1e6, 2e6 * gap_e, fmt="o", color="k", ms=4, capsize=2, label="BEM")
    for k, (name, law) in enumerate(v.laws.items()):
        u, _ = law.separation_and_slope(np.log(pp))
        a0.plot(pp, u * 1e6, "-" if p.size > 1 else "s", color=f"C{k}", label=name)
    eff = np.array([e.effective_gap for e in v.ensembles])
    eff_e = np.array([e.effective_gap_error for e in v.ensembles])
    a1.errorbar(p, eff * 1e6, 2e6 * eff_e, fmt="o", color="k", ms=4, capsize=2, label="BEM")
    theory = v.laws.get(v.model)
    th = theory.theory if theory is not None else None
    for k, t in enumerate(v.critical_gap):
        if th is not None and p.size > 1:
            uc = th.critical_gap(pp, threshold=t).u_c
            a1.plot(pp, uc * 1e6, ["-", "--"][k % 2], color="C3", label=rf"$u_c$, threshold {t:g}")
        else:
            uc = [d.theory for d in v.critical_gap[t]]
            a1.plot(p, np.asarray(uc) * 1e6, "s", color=f"C{3 + k}", label=rf"$u_c$ ({t:g})")
    for ax in axes:
        _pressure_axis(ax)
    a0.set_ylabel(r"mean separation $\bar u$ ($\mu$m)")
    a1.set_ylabel(r"effective gap ($\mu$m)")
    a1.set_ylim(0.0, None)
    a0.set_ylim(0.0, None)
    a0.legend(loc="upper right", fontsize=7, frameon=False)
    _legend(a1)
    return fig


def _times_ten(value: float) -> str:
    """``2.7e4`` as mathtext ``2.7\\times10^{4}``."""
    e = math.floor(math.log10(value))
    m = value / 10.0**e
    return f"${m:.2g}\\times10^{{{e}}}$"


def _shade_outside(ax, lo, hi, span, label) -> None:
    """Light grey over the parts of ``span`` (the data's k range) outside [lo, hi]."""
    for a, b in ((span[0], lo), (hi, span[1])):
        if b > a * (1 + 1e-9):
            ax.axvspan(a, b, color="0.88", lw=0, zorder=0, label=label)
            label = None


def _c1d_panel(ax, scan) -> None:
    k, C = scan.raw
    live = C > 0.0
    ax.loglog(k[live], C[live], ".", ms=1.5, color="0.6", label="every Fourier mode")
    s = scan.spectrum
    ax.loglog(s.k, s.C1D, "o", ms=3, color="C0", label="averaged, usable range")
    _shade_outside(ax, *scan.q_range, (k[0], k[-1]), "outside the usable range")
    ax.set_xlim(k[0] / 1.1, k[-1] * 1.1)
    _log_axis(ax.xaxis)
    _log_axis(ax.yaxis)
    ax.set_xlabel(r"wavenumber $k$ (1/m)")
    ax.set_ylabel(r"$C_\mathrm{1D}(k)$ (m$^3$)")
    _corner_legend(ax)


def _corner_legend(ax) -> None:
    """Legend in the free lower left corner of a falling spectrum, on white so that the shaded
    bands' own swatches show over the shading."""
    ax.legend(loc="lower left", fontsize=8, frameon=True, framealpha=1.0, edgecolor="none")


def _c_panel(ax, scan) -> None:
    fit, measured, table = scan.fit, scan.measured, scan.psd
    lo = measured.q0
    if scan.kind == "map":
        q, C = scan.raw
        live = C > 0.0
        ax.loglog(q[live], C[live], ".", ms=2.5, color="0.6", label="ring averages, all rings")
        # above the range the continuation's own shading says what is there
        top = q[-1] if scan.extended_from is None else scan.q_range[1]
        _shade_outside(ax, *scan.q_range, (q[0], top), "outside the usable range")
        lo = q[0]
        what = "ring averages, usable range"
    else:
        what = "inverse Abel transform"
    ax.loglog(measured.q, measured.C, "o", ms=3, color="C0", label=what)
    qf = np.geomspace(fit.psd.q0, min(fit.psd.q1, measured.q1) * (1 - 1e-12), 200)  # the data's
    label = f"fit: $H$ = {fit.hurst:.2f}, $q_r$ = {_times_ten(fit.qr)} 1/m"
    ax.loglog(qf, fit.psd(qf), "-", color="C1", lw=1.2, label=label)
    hi = max(table.q1, measured.q1)
    if scan.extended_from is not None:
        top = table.q > scan.extended_from * (1 - 1e-12)
        ax.loglog(table.q[top], table.C[top], "--", color="C2", lw=1.2,
                  label=r"continued to $q_1$ (assumed)")  # fmt: skip
        ax.axvspan(scan.extended_from, table.q1, color="C2", alpha=0.08, lw=0, zorder=0)
    elif table.q1 < measured.q1:
        ax.axvline(table.q1, ls=":", color="k", lw=0.8, label=r"cut at $q_1$")
    ax.set_xlim(lo / 1.1, hi * 1.1)
    _log_axis(ax.xaxis)
    _log_axis(ax.yaxis)
    ax.set_xlabel(r"wavenumber $q$ (1/m)")
    ax.set_ylabel(r"$C(q)$ (m$^4$)")
    _corner_legend(ax)


def plot_measured_psd(scan: ScanSpectrum, *, axes: Axes | Sequence[Axes] | None = None) -> Figure:
    """The spectrum of a measured surface on log-log axes: what was measured, used and fitted.

    Profiles: two panels, the 1D spectrum C1D(k) (every Fourier mode in grey, averaged points
    over the usable range, the rest shaded) and the isotropic C(q) from the exact inverse Abel
    transform with the fitted self-affine model and, when the table was continued above the
    usable range, the continuation (dashed, shaded). Maps: the C(q) panel, with the ring
    averages over all full rings in grey.

    Parameters
    ----------
    scan : ScanSpectrum
        From :func:`fastline.surfaces.scan.analyse_scan`.
    axes : matplotlib Axes or pair of Axes, optional
        (C1D, C) axes for profiles, one Axes for a map; default a new figure.

    Returns
    -------
    matplotlib.figure.Figure
    """
    profiles = scan.kind != "map"
    if axes is None:
        fig, _, _ = _figure(None, size=(9.6, 3.8) if profiles else (4.8, 3.8))
        fig.clear()
        fig.subplots_adjust(left=0.09 if profiles else 0.17, right=0.98, bottom=0.15, top=0.96,
                            wspace=0.3)  # fmt: skip
        axes = fig.subplots(1, 2) if profiles else fig.subplots(1, 1)
    fig = (axes[0] if profiles else axes).figure
    if profiles:
        _c1d_panel(axes[0], scan)
        _c_panel(axes[1], scan)
    else:
        _c_panel(axes, scan)
    return fig


def save_figure(
    fig: Figure,
    path: str | os.PathLike,
    *,
    format: Literal["png", "pdf", "svg"] | None = None,
    dpi: float | None = None,
) -> str:
    """Write a figure to ``path`` (PNG, PDF or SVG) and return the path.

    Parameters
    ----------
    fig : matplotlib Figure
    path : str or path-like
    format : {"png", "pdf", "svg"}, optional
        Default: from the file extension, else PNG.
    dpi : float, optional
        Resolution of PNG output (default 150).
    """
    path = os.fspath(path)
    if format is None:
        ext = os.path.splitext(path)[1].lower().lstrip(".")
        format = ext if ext in FORMATS else "png"
    if format not in FORMATS:
        raise ValueError(f"format must be one of {FORMATS}, got {format!r}")
    if dpi is not None and not (isinstance(dpi, int | float) and 10 <= dpi <= 2400):
        raise ValueError(f"dpi must be a number in [10, 2400], got {dpi!r}")
    meta = {"png": {"Software": "fastline"}, "pdf": {"Creator": "fastline"}}
    meta["svg"] = {"Creator": "fastline"}
    try:
        fig.savefig(path, format=format, dpi=dpi or DEFAULT_DPI, metadata=meta[format])
    except OSError as e:
        raise ValueError(f"cannot write {path}: {e.strerror}") from None
    return path
