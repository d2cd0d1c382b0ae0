"""The pressure profile of one result as a figure: ``result.plot()`` and
:func:`fastline.plotting.plot_profile` draw it here.

p(x) in MPa against x in mm (a sphere's along a diameter), with the smooth (Hertz) profile at
the same load dashed; the legend, above the axes, names the load and alpha. matplotlib is
imported only when a figure is made (the ``plot`` extra); no pyplot, no global backend change.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from fastline.theory.limits import hertz_line_contact, hertz_point_contact

if TYPE_CHECKING:  # annotations only: matplotlib loads on first use
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

    from fastline.contact.result import ContactResult

__all__ = ["plot_profile"]

#: inches: one profile panel, its legend above the axes
PROFILE_SIZE = (5.0, 3.9)


def _profile_axes(ax):
    """(figure, axes): the given axes' figure, or a new figure with the legend's room on top."""
    if ax is not None:
        return ax.figure, ax
    try:
        from matplotlib.figure import Figure
    except ImportError:
        raise ImportError(
            'plotting needs matplotlib: pip install matplotlib (the "plot" extra of '
            "fastline-contact)"
        ) from None
    fig = Figure(figsize=PROFILE_SIZE)
    fig.subplots_adjust(left=0.14, right=0.96, bottom=0.14, top=0.80)
    return fig, fig.add_subplot()


def scene_text(result, math: bool = True) -> str:
    """``f_N = 1e+04 N/m, alpha = 0.37`` (a sphere's load is F in N), as matplotlib's math
    text or as plain text (``math`` False)."""
    symbol = getattr(result, "LOAD_SYMBOL", "f_N")
    unit = getattr(result, "LOAD_UNIT", "N/m")
    if not math:
        return f"{symbol} = {result.load:.4g} {unit}, alpha = {result.alpha:.4g}"
    symbol = symbol.replace("f_N", "f_\\mathrm{N}")
    return f"${symbol}$ = {result.load:.3g} {unit}, $\\alpha$ = {result.alpha:.3g}"


def plot_profile(
    result: ContactResult, *, hertz: bool = True, label: str | None = None, ax: Axes | None = None
) -> Figure:
    """Pressure profile p(x) of one result, with the smooth (Hertz) profile at the same load.

    A point contact's profile is drawn along a diameter, with the Hertz sphere (paper eq. 6
    for a cylinder; K.L. Johnson, Contact Mechanics, 1985, section 4.2, for a sphere). The
    legend names the load and alpha.

    Parameters
    ----------
    result : LineContactResult or PointContactResult
    hertz : bool
        Also draw the Hertz profile at the same E*, R and load.
    label : str, optional
        Legend entry of the rough profile (default: its model).
    ax : matplotlib Axes, optional
    """
    from matplotlib.ticker import MaxNLocator  # optional: the plot extra

    fig, ax = _profile_axes(ax)
    point = hasattr(result, "hertz_radius")
    if point:
        x, p = result.diameter_profile()
        hz = hertz_point_contact(result.E_star, result.radius, result.load)
    else:
        x, p = result.x, result.pressure
        hz = hertz_line_contact(result.E_star, result.radius, result.load)
    ax.plot(x * 1e3, p / 1e6, "-", color="C0", label=label or f"rough ({result.model})")
    half = 1.3 * max(hz.a if hertz else 0.0, 2.5 * result.s)
    if hertz:  # on a fine grid of its own: its edges are sharp
        xh = np.linspace(-half, half, 1001)
        ax.plot(xh * 1e3, hz.pressure(xh) / 1e6, "--", color="k", lw=1, label="Hertz (smooth)")
    ax.set_xlim(-half * 1e3, half * 1e3)
    ax.xaxis.set_major_locator(MaxNLocator(nbins=6, symmetric=True, steps=[1, 2, 2.5, 5, 10]))
    ax.set_ylim(0.0, None)
    where = "position along a diameter $x$" if point else "$x$"
    ax.set_xlabel(f"{where} (mm)")
    ax.set_ylabel(r"nominal pressure $p$ (MPa)")
    ax.legend(
        loc="lower left", bbox_to_anchor=(0.0, 1.02, 1.0, 0.1), mode="expand", ncol=2,
        fontsize=8, frameon=False, title=scene_text(result), title_fontsize=8,
    )  # fmt: skip
    return fig
