"""What every figure of :mod:`fastline.reports.plotting` shares: a figure with fixed margins
(:func:`figure_and_axes`), log axes labelled 10ⁿ, legends outside the data, and writing a
figure to a file (:func:`save_figure`).

matplotlib is imported only when a figure is made (install it with the ``plot`` extra).
"""

from __future__ import annotations

import math
import os
from typing import TYPE_CHECKING, Literal

if TYPE_CHECKING:  # annotations only: matplotlib loads on first use
    from matplotlib.figure import Figure

__all__ = ["FORMATS", "DEFAULT_DPI", "figure_format", "save_figure"]

#: file formats :func:`save_figure` writes
FORMATS = ("png", "pdf", "svg")
#: resolution of raster (PNG) figures in dots per inch
DEFAULT_DPI = 150
_PANEL = (5.6, 3.8)  # inches: one panel with a legend on its right
_ABOVE_WIDTH = 5.0  # inches: one panel with its legend above


def figure_and_axes(ax, size=_PANEL):
    """(figure, axes, own): the given axes' figure, or a new one with fixed margins (``own``
    True: made here, its layout ours to change)."""
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


def log_axis(axis) -> None:
    """Major ticks at powers of ten labelled 10ⁿ (Unicode superscripts); minor ticks unlabelled.

    Left to matplotlib's own labels when the axis spans fewer than two powers of ten.
    """
    from matplotlib.ticker import FuncFormatter, NullFormatter  # optional: the plot extra

    lo, hi = sorted(axis.get_view_interval())
    if lo <= 0.0 or math.floor(math.log10(hi)) - math.ceil(math.log10(lo)) < 1:
        return
    axis.set_major_formatter(FuncFormatter(_power_of_ten))
    axis.set_minor_formatter(NullFormatter())


def outside_legend(ax) -> None:
    """Legend outside the axes, on the right (never over the data)."""
    ax.legend(loc="upper left", bbox_to_anchor=(1.02, 1.0), fontsize=8, frameon=False)


def legend_above(ax, own: bool, ncol: int = 2) -> None:
    """Legend in ``ncol`` columns above the axes, as wide as they are (never over the data, no
    empty margin beside them); a figure made here (``own``) gets the axes the full width and
    the legend's rows their height on top."""
    handles, labels = ax.get_legend_handles_labels()
    if not handles:
        return
    ncol = min(ncol, len(handles))
    ax.legend(
        loc="lower left", bbox_to_anchor=(0.0, 1.02, 1.0, 0.1), mode="expand", ncol=ncol,
        fontsize=8, frameon=False, borderaxespad=0.0,
    )  # fmt: skip
    fig = ax.figure
    if own and len(fig.axes) == 1:
        rows = math.ceil(len(handles) / ncol)
        height = _PANEL[1] + 0.18 * rows
        fig.set_size_inches(_ABOVE_WIDTH, height)
        fig.subplots_adjust(left=0.14, right=0.96, top=1.0 - (0.12 + 0.19 * rows) / height)


def no_outside_legend(fig, ax, own: bool) -> None:
    """Give the right margin back to the axes of a figure made here without an outer legend."""
    if own and len(fig.axes) == 1:
        fig.subplots_adjust(left=0.19, right=0.96)
        fig.set_size_inches(4.6, fig.get_size_inches()[1])


def figure_format(path: str | os.PathLike, format: str | None = None) -> str:
    """The format :func:`save_figure` writes to ``path``: ``format``, else the extension's,
    else PNG (no extension). A ValueError naming the file when its extension is not one of
    :data:`FORMATS` (``out.jpg`` would hold PNG bytes) or contradicts ``format``."""
    path = os.fspath(path)
    if format is not None and format not in FORMATS:
        raise ValueError(f"format must be one of {FORMATS}, got {format!r}")
    ext = os.path.splitext(path)[1].lower().lstrip(".")
    if ext and ext not in FORMATS:
        raise ValueError(
            f"cannot write {path}: figures are written as {', '.join(FORMATS)}, not .{ext} "
            f"(name the file .png, .pdf or .svg)"
        )
    if ext and format is not None and ext != format:
        raise ValueError(f"cannot write {path}: its extension .{ext} contradicts format {format}")
    return format or ext or "png"


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
        Default: from the file extension (PNG without one). A path whose extension names
        another format (``.jpg``) is refused (:func:`figure_format`).
    dpi : float, optional
        Resolution of PNG output (default 150).
    """
    path = os.fspath(path)
    format = figure_format(path, format)
    if dpi is not None and not (isinstance(dpi, int | float) and 10 <= dpi <= 2400):
        raise ValueError(f"dpi must be a number in [10, 2400], got {dpi!r}")
    meta = {"png": {"Software": "fastline"}, "pdf": {"Creator": "fastline"}}
    meta["svg"] = {"Creator": "fastline"}
    try:
        fig.savefig(path, format=format, dpi=dpi or DEFAULT_DPI, metadata=meta[format])
    except OSError as e:
        raise ValueError(f"cannot write {path}: {e.strerror}") from None
    return path
