"""The figure of a measured surface's spectrum (:func:`fastline.surfaces.scan.analyse_scan`):
what was measured, used and fitted, on log-log axes.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import TYPE_CHECKING

import numpy as np

from fastline.reports.figures import figure_and_axes, log_axis

if TYPE_CHECKING:  # annotations only: matplotlib and the scan load on first use
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

    from fastline.surfaces.scan import ScanSpectrum

__all__ = ["plot_measured_psd"]


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
    if s.noise_floor > 0.0:
        sigma = math.sqrt(s.noise_floor * 2.0 * math.pi / s.dx)
        ax.axhline(s.noise_floor, ls="--", color="C3", lw=1.0,
                   label=f"noise floor found: rms {_times_ten(sigma)} m")  # fmt: skip
    _shade_outside(ax, *scan.q_range, (k[0], k[-1]), "outside the usable range")
    ax.set_xlim(k[0] / 1.1, k[-1] * 1.1)
    log_axis(ax.xaxis)
    log_axis(ax.yaxis)
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
    if fit.qr_at_bound:
        label = f"fit: $H$ = {fit.hurst:.2f}, $q_r$ not resolved"
    elif fit.qr_uncertain:  # its interval at two standard errors, wider than 25 % either way
        lo, hi = fit.qr_interval
        label += f"\n($q_r$ uncertain: {_times_ten(lo)}-{_times_ten(hi)} 1/m)"
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
    log_axis(ax.xaxis)
    log_axis(ax.yaxis)
    ax.set_xlabel(r"wavenumber $q$ (1/m)")
    ax.set_ylabel(r"$C(q)$ (m$^4$)")
    _corner_legend(ax)


def plot_measured_psd(scan: ScanSpectrum, *, axes: Axes | Sequence[Axes] | None = None) -> Figure:
    """The spectrum of a measured surface on log-log axes: what was measured, used and fitted.

    Profiles: two panels, the 1D spectrum C1D(k) (every Fourier mode in grey, averaged points
    over the usable range, the rest shaded, the instrument's white-noise level found in the
    data dashed) and the isotropic C(q) from the exact inverse Abel
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
        fig, _, _ = figure_and_axes(None, size=(9.6, 3.8) if profiles else (4.8, 3.8))
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
