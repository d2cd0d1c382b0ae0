"""Figures of leak rates: where a seal leaks (p(x) above the critical gap u_c(x)) and the
leak rate against the load.

Units: SI, with mm and MPa for profiles.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike

from fastline._lib.validate import real_array
from fastline.reports.figures import (
    figure_and_axes,
    log_axis,
    no_outside_legend,
    outside_legend,
)

if TYPE_CHECKING:  # annotations only: matplotlib and the solvers load on first use
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

    from fastline.leakage.flow import LeakResult
    from fastline.leakage.seal import SealSweep

__all__ = ["GAP_FLOOR", "plot_leak", "plot_leak_sweep", "plot_seal"]

#: lower end of the critical-gap axis of :func:`plot_leak` (m): narrower gaps (below an atom's
#: size, a closed seal for any practical purpose; they reach 1e-60 m near sealing) run off it
GAP_FLOOR = 1e-12


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


def _runs(mask: np.ndarray, edges: np.ndarray) -> list[tuple[float, float]]:
    """(lo, hi) in m of each run of consecutive strips where ``mask`` holds."""
    steps = np.diff(np.concatenate([[0], mask.astype(np.int8), [0]]))
    starts, ends = np.flatnonzero(steps == 1), np.flatnonzero(steps == -1)
    return list(zip(edges[starts], edges[ends], strict=True))


def _leak_bands(leak) -> list[tuple[list[tuple[float, float]], str, str]]:
    """(spans in m, label, colour) of the regions a leak is decided in: when sealed, the strips
    the real contact area seals (it percolates) and those the gap floor seals, each cause its
    own; else the central 90 % of the flow resistance."""
    edges = _cell_edges(leak.x)
    if leak.sealed:
        floor = getattr(leak, "floor_strips", np.zeros(0, dtype=bool))
        if floor.shape != leak.sealed_strips.shape:  # a result made without the split
            floor = np.zeros(leak.sealed_strips.shape, dtype=bool)
        contact = leak.sealed_strips & ~floor
        bands = [
            (contact, f"sealed: $P(q_1, p) \\geq {leak.threshold:g}$ (contact percolates)", "C3"),
            (floor, f"sealed: gap below the molecular floor {leak.gap_floor:g} m", "C4"),
        ]
        return [(_runs(m, edges), text, c) for m, text, c in bands if m.any()]
    cum = np.concatenate([[0.0], leak.cumulative_share])
    lo, hi = np.interp([0.05, 0.95], cum, edges)
    return [([(lo, hi)], f"90% of the flow resistance ({(hi - lo) * 1e6:.3g} µm wide)", "C2")]


def plot_leak(leak: LeakResult, *, axes: Sequence[Axes] | None = None) -> Figure:
    """Where a seal leaks: p(x) above, the critical gap u_c(x) below (log axis), sharing x.

    The region holding the central 90% of the flow resistance (or, when sealed, the sealed
    strips: red where the real contact area percolates, purple where the gap is below the
    molecular floor ``leak.gap_floor``) is shaded in both panels; dotted lines mark the FWHM
    of p. Gaps below :data:`GAP_FLOOR` (1e-12 m) run off the bottom of the u_c axis; strips
    where the contact percolates (u_c = 0) leave a gap in the line.

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
    fig, top, bottom = _leak_axes(axes)
    x_mm = leak.x * 1e3
    top.plot(x_mm, leak.pressure / 1e6, "-", color="C0")
    top.set_ylim(0.0, 1.1 * leak.pressure.max() / 1e6)
    top.set_ylabel(r"nominal pressure $p$ (MPa)")
    # 0 in sealed strips, inf where p = 0: gaps in the line, not a segment across them
    shown = np.isfinite(leak.u_c) & (leak.u_c > 0.0)
    bottom.semilogy(x_mm, np.where(shown, leak.u_c, np.nan), "-", color="C3")
    medium = leak.method == "effective-medium"
    bottom.set_ylabel(r"effective gap $u_{eff}$ (m)" if medium else r"critical gap $u_c$ (m)")
    floor = getattr(leak, "gap_floor", 0.0)
    if floor > 0.0 and shown.any() and leak.u_c[shown].min() < 10.0 * floor:
        bottom.axhline(floor, ls="--", color="0.4", lw=0.8, label="molecular floor of the gap")
    radial = leak.inner_radius is not None
    bottom.set_xlabel(r"$r$ (mm)" if radial else r"$x$ (mm)")
    _mark_leak(top, bottom, leak)
    _gap_axis(bottom, leak, shown)
    handles = top.get_legend_handles_labels()
    more = bottom.get_legend_handles_labels()
    # above the top panel, off the data
    top.legend(
        handles[0] + more[0], handles[1] + more[1], loc="lower left", bbox_to_anchor=(0.0, 1.01),
        ncols=1, fontsize=8, frameon=False, borderaxespad=0.0,
    )  # fmt: skip
    if axes is None:  # room for the legend's lines (3 fit below the top at 0.88)
        fig.subplots_adjust(top=min(0.88, 0.97 - 0.03 * len(handles[1] + more[1])))
    return fig


def _leak_axes(axes: Sequence[Axes] | None) -> tuple[Figure, Axes, Axes]:
    """(figure, top, bottom) of :func:`plot_leak`: the given pair's figure, or a new one."""
    if axes is None:
        fig, _, _ = figure_and_axes(None, size=(5.6, 5.2))
        fig.clear()
        fig.subplots_adjust(left=0.15, right=0.96, bottom=0.11, top=0.88, hspace=0.08)
        top, bottom = fig.subplots(2, 1, sharex=True)
    else:
        top, bottom = axes
        fig = top.figure
    return fig, top, bottom


def _mark_leak(top: Axes, bottom: Axes, leak: LeakResult) -> None:
    """In both panels: the region the leak is decided in (shaded), the FWHM of p (dotted; a
    point contact: its half width) and a point contact's orifice."""
    radial = leak.inner_radius is not None
    half = leak.x[leak.pressure >= 0.5 * leak.pressure.max()]
    width = "half width at half maximum" if radial else "FWHM"
    fwhm = f"{width} of $p$"
    if not leak.sealed:  # a sealed contact's resistance is infinite: no share to state
        fwhm += f" ({leak.share_in_fwhm:.1%} of the resistance inside)"
    marks = (half[-1],) if radial else (half[0], half[-1])  # radial: the half width only
    for k, ax in enumerate((top, bottom)):
        for spans, text, color in _leak_bands(leak):
            for j, (lo, hi) in enumerate(spans):
                lab = text if (k and not j) else None
                ax.axvspan(lo * 1e3, hi * 1e3, color=color, alpha=0.15, lw=0, label=lab)
        for j, xf in enumerate(marks):
            lab = fwhm if (k == 0 and j == 0) else None
            ax.axvline(xf * 1e3, ls=":", color="k", lw=0.8, label=lab)
        if radial:
            lab = "orifice (the fluid enters at its edge)" if k == 0 else None
            ax.axvspan(0.0, leak.inner_radius * 1e3, color="0.6", alpha=0.4, lw=0, label=lab)


def _gap_axis(bottom: Axes, leak: LeakResult, shown: np.ndarray) -> None:
    """x range of both panels (:func:`_leak_window`) and the u_c axis over the gaps shown there
    (down to :data:`GAP_FLOOR` at most)."""
    window = _leak_window(leak)
    bottom.set_xlim(window[0] * 1e3, window[1] * 1e3)
    seen = shown & (leak.x >= window[0]) & (leak.x <= window[1])
    if seen.any():
        u = leak.u_c[seen]
        bottom.set_ylim(max(0.5 * u.min(), GAP_FLOOR), 2.0 * u.max())
    log_axis(bottom.yaxis)


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
    f, leaks = _by_load(loads, leaks)
    Q = np.array([k.Q for k in leaks])
    sealed = np.array([k.sealed for k in leaks])
    bad = ~np.array([k.converged for k in leaks])
    fig, ax, own = figure_and_axes(ax)
    ax.loglog(f[~sealed], Q[~sealed], "o-", ms=3, lw=1.2, color="C0", label=label)
    if np.any(~sealed):
        q_lo, q_hi = Q[~sealed].min(), Q[~sealed].max()
        ax.set_ylim(q_lo / 10.0, q_hi * 10.0)
    _mark_sealed_and_unconverged(ax, f, Q, sealed, bad)
    pad = (f[-1] / f[0]) ** 0.03 if f[-1] > f[0] else 1.5
    ax.set_xlim(f[0] / pad, f[-1] * pad)
    log_axis(ax.xaxis)
    log_axis(ax.yaxis)
    radial = leaks[0].inner_radius is not None  # a point contact: the load on the sphere
    ax.set_xlabel(r"load $F$ (N)" if radial else r"load per unit length $f_N$ (N/m)")
    ax.set_ylabel(r"leak rate $Q$ (m$^3$/s)")
    ax.grid(True, which="major", alpha=0.3)
    if ax.get_legend_handles_labels()[1]:
        outside_legend(ax)
        if own:  # short legend entries: a narrower right margin than figure_and_axes's
            fig.set_size_inches(5.0, fig.get_size_inches()[1])
            fig.subplots_adjust(left=0.17, right=0.71)
    else:
        no_outside_legend(fig, ax, own)
    return fig


def _by_load(loads: ArrayLike, leaks: Sequence[LeakResult]) -> tuple[np.ndarray, list]:
    """The loads (N/m or N) and their leak results, checked and in increasing load."""
    f = real_array("loads", loads)
    leaks = list(leaks)
    if f.ndim != 1 or f.size != len(leaks) or f.size == 0:
        raise ValueError(
            f"loads and leaks must be non-empty and of the same length, got {f.size} loads "
            f"and {len(leaks)} leak results"
        )
    order = np.argsort(f)
    return f[order], [leaks[i] for i in order]


def _mark_sealed_and_unconverged(ax, f, Q, sealed, bad) -> None:
    """Sealed loads as triangles at the bottom of the axes over a shaded range; unconverged
    loads circled in red (sealed ones at the bottom)."""
    from matplotlib.transforms import blended_transform_factory  # optional: the plot extra

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


def plot_seal(sweep: SealSweep, *, shown: Sequence[int] | None = None) -> Figure:
    """A seal under pressure: Q against dP (coupled and uncoupled, lift-off marked) on the
    left; contact pressure p_c and fluid pressure p_f at some pressure drops on the right,
    along x across a line contact, or along r out of a point contact's hole (shaded).

    Parameters
    ----------
    sweep : SealSweep
        From :func:`fastline.seal_leak`.
    shown : sequence of int, optional
        Indices of the pressure drops whose profiles are drawn; default the (up to) three
        largest that hold (not lifted off).

    Returns
    -------
    matplotlib.figure.Figure
    """
    fig, _, _ = figure_and_axes(None, size=(10.0, 4.2))
    fig.clear()
    left, right = fig.subplots(1, 2)
    fig.subplots_adjust(left=0.08, right=0.98, bottom=0.13, top=0.80, wspace=0.28)
    dP = sweep.pressure_drops
    ok = np.isfinite(sweep.Q) & (sweep.Q > 0.0)
    left.loglog(dP[ok], sweep.Q[ok], "o-", color="C0", ms=4, label="coupled (fluid pressure)")
    unc = sweep.uncoupled_Q > 0.0
    left.loglog(dP[unc], sweep.uncoupled_Q[unc], "s--", color="0.5", ms=3,
                label="uncoupled (dry contact)")  # fmt: skip
    if sweep.lift_off_pressure is not None:
        left.axvline(sweep.lift_off_pressure, color="C3", ls=":",
                     label=f"lift-off {sweep.lift_off_pressure:.3g} Pa")  # fmt: skip
    left.set_xlabel(r"pressure drop $\Delta P$ (Pa)")
    left.set_ylabel(r"leak rate $Q$ (m$^3$/s)")
    left.legend(loc="lower left", bbox_to_anchor=(0.0, 1.01), fontsize=8, frameon=False,
                borderaxespad=0.0)  # fmt: skip
    held = [k for k, r in enumerate(sweep.results) if not r.lifted_off]
    _seal_profiles(right, sweep, held[-3:] if shown is None else shown)  # the largest that hold
    return fig


def _seal_profiles(right, sweep: SealSweep, shown) -> None:
    """p_c and p_f of the pressure drops ``shown`` along x (line) or r (point, hole shaded)."""
    for j, k in enumerate(shown):
        r = sweep.results[k]
        c = f"C{j}"
        right.plot(r.x * 1e3, r.contact_pressure / 1e6, "-", color=c,
                   label=f"$p_c$, $\\Delta P$ = {r.pressure_drop:.3g} Pa")  # fmt: skip
        right.plot(r.x * 1e3, r.fluid_pressure / 1e6, "--", color=c,
                   label=f"$p_f$, $\\Delta P$ = {r.pressure_drop:.3g} Pa")  # fmt: skip
    point = getattr(sweep, "geometry", "line") == "point"
    if point:
        right.axvspan(0.0, sweep.inner_radius * 1e3, color="0.85", lw=0, label="hole")
    if shown:
        r = sweep.results[shown[0]]
        inside = r.x[r.contact_pressure >= 1e-3 * r.contact_pressure.max()]
        pad = 0.3 * (inside[-1] - inside[0])
        right.set_xlim(0.0 if point else (inside[0] - pad) * 1e3, (inside[-1] + pad) * 1e3)
    if shown or point:
        right.legend(loc="lower left", bbox_to_anchor=(0.0, 1.01), ncols=2, fontsize=8,
                     frameon=False, borderaxespad=0.0)  # fmt: skip
    right.set_xlabel(
        r"$r$ (mm), flow outwards from the hole" if point else r"$x$ (mm), flow from left to right"
    )
    right.set_ylabel("pressure (MPa)")
    right.set_ylim(bottom=0.0)
