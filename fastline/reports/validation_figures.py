"""Figures of the theory against the boundary-element method
(:mod:`fastline.reports.validation`): the profiles of a cylinder or a sphere, and the
separation and effective gap of a flat contact against the nominal pressure.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING

import numpy as np

from fastline.reports.figures import figure_and_axes, log_axis, outside_legend
from fastline.theory.limits import hertz_line_contact, hertz_point_contact

if TYPE_CHECKING:  # annotations only: matplotlib and the validation load on first use
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

    from fastline.reports.validation import FlatValidation, ProfileValidation

__all__ = ["plot_validation", "plot_flat_validation", "LAW_STYLES"]


def _pressure_unit(p_max: float) -> tuple[float, str]:
    return (1e3, "kPa") if p_max < 1e6 else (1e6, "MPa")


def _pressure_axis(ax) -> None:
    """Log pressure axis labelled at 1, 2, 5 times powers of ten (often less than two decades)."""
    from matplotlib.ticker import FuncFormatter, LogLocator, NullFormatter  # optional: plot extra

    ax.set_xscale("log")
    ax.set_xlabel(r"nominal pressure $p$ (Pa)")
    lo, hi = sorted(ax.get_xlim())
    if hi / lo >= 100.0:  # two decades or more: powers of ten
        log_axis(ax.xaxis)
        return
    ax.xaxis.set_major_locator(LogLocator(subs=(1.0, 2.0, 5.0)))
    ax.xaxis.set_major_formatter(FuncFormatter(lambda v, _pos: f"{v:g}"))
    ax.xaxis.set_minor_formatter(NullFormatter())


#: per law, in the order drawn: line style, width, marker (open), so that laws whose profiles
#: coincide still show: the first is widest at the bottom, each later one narrower on top, with
#: markers at staggered places along the line
LAW_STYLES = (
    ("-", 2.8, None),
    ("--", 2.0, "o"),
    ("-.", 1.5, "s"),
    (":", 1.3, "^"),
    ("-", 1.1, "D"),
)
_MARK_STEP = 0.09  # markers every 9 % of the axes' diagonal, staggered by law


def _law_style(k: int, laws: int) -> dict:
    """Line keywords of the k-th of ``laws`` laws (:data:`LAW_STYLES`)."""
    style, width, marker = LAW_STYLES[k % len(LAW_STYLES)]
    kw = {"ls": style, "lw": width, "color": f"C{k}", "zorder": 3 + k}
    if marker is not None:
        start = 0.02 + _MARK_STEP * k / max(laws, 1)
        kw |= {"marker": marker, "ms": 4.5, "mfc": "white", "mew": 1.0}
        kw["markevery"] = (start, _MARK_STEP)
    return kw


def _narrow_note(ax, e) -> None:
    """Say on the figure that the contact is too narrow to compare widths, and why."""
    scene = e.scene
    why = []
    if scene.psd is not None and e.contact_width < 2.0 * np.pi / scene.psd.q0:
        lam = 2.0 * np.pi / scene.psd.q0
        why.append(rf"$W$ = {e.contact_width * 1e3:.3g} mm < $2\pi/q_0$ = {lam * 1e3:.3g} mm")
    cells = e.contact_width / scene.grid.dx
    if cells < 10:
        why.append(f"{cells:.3g} cells across")
    ax.set_title(
        "BEM contact too narrow to compare widths: " + ", ".join(why),
        fontsize=7.5,
        color="C3",
        loc="left",
    )


def plot_validation(validation: ProfileValidation, *, ax: Axes | None = None) -> Figure:
    """Theory against BEM for a cylinder or a sphere
    (:func:`fastline.reports.validation.validate_line_contact`,
    :func:`~fastline.reports.validation.validate_point_contact`): the BEM ensemble ``p_bar(x)``
    (sphere: ``p_bar(r)`` over rings) with a band of two standard errors, each model's profile
    (:data:`LAW_STYLES`: every law visible where they coincide) and the Hertz profile; a title
    in red when the contact is too narrow to compare widths.

    Parameters
    ----------
    validation : fastline.reports.validation.LineValidation or PointValidation
    ax : matplotlib Axes, optional
    """
    fig, ax, own = figure_and_axes(ax, size=(6.0, 3.8))
    if own:  # the legend's longest entry ("greenwood-williamson") ends at 96 % of the width
        fig.subplots_adjust(left=0.11, right=0.66, top=0.9 if validation.ensemble.narrow else 0.96)
    e = validation.ensemble
    scale, unit = _pressure_unit(max(e.p0, e.p0_hertz))
    x = e.coordinate * 1e3
    band = 2.0 * e.pressure_error
    ax.fill_between(
        x, (e.pressure - band) / scale, (e.pressure + band) / scale, color="0.8", lw=0,
        label="BEM ± 2 s.e.", zorder=1,
    )  # fmt: skip
    label = rf"BEM $\bar p$ ({e.realizations} surfaces)"
    ax.plot(x, e.pressure / scale, "-", color="k", lw=1.1, label=label, zorder=10)
    sphere = validation.geometry == "sphere"
    laws = len(validation.results)
    for k, (name, r) in enumerate(validation.results.items()):
        coord = r.r if sphere else r.x
        ax.plot(coord * 1e3, r.pressure / scale, label=name, **_law_style(k, laws))
    scene = e.scene
    hertz = hertz_point_contact if sphere else hertz_line_contact
    hz = hertz(scene.E_star, scene.radius, scene.load)
    half = 1.3 * max(hz.a, 2.5 * e.s)
    xs = np.linspace(0.0 if sphere else -half, half, 801)
    ax.plot(xs * 1e3, hz.pressure(xs) / scale, ":", color="0.45", lw=1, label="Hertz (smooth)",
            zorder=2)  # fmt: skip
    ax.set_xlim(xs[0] * 1e3, half * 1e3)
    ax.set_ylim(0.0, None)
    ax.set_xlabel(r"$r$ (mm)" if sphere else r"$x$ (mm)")
    ax.set_ylabel(rf"nominal pressure $p$ ({unit})")
    ax.text(0.02, 0.97, rf"$\alpha$ = {e.alpha:.3g}", transform=ax.transAxes, va="top", fontsize=8)
    if e.narrow:
        _narrow_note(ax, e)
    outside_legend(ax)
    return fig


def plot_flat_validation(
    validation: FlatValidation, *, axes: Sequence[Axes] | None = None
) -> Figure:
    """Theory against BEM for a flat contact
    (:func:`fastline.reports.validation.validate_flat_contact`): mean separation u(p) of each
    model against the BEM mean gap (left), the critical-junction gap u_c against the BEM's
    Reynolds effective gap (right; with a calibrated law also its hydraulic gap g(p)); BEM
    points with two standard errors.

    Parameters
    ----------
    validation : fastline.reports.validation.FlatValidation
    axes : pair of matplotlib Axes, optional
    """
    if axes is None:
        fig, _, _ = figure_and_axes(None, size=(9.0, 3.6))
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
    if v.hydraulic_gap:  # a calibrated law: its hydraulic gap g(p)
        k, (name, law) = len(v.laws) - 1, list(v.laws.items())[-1]
        g = law.hydraulic_gap(pp) if p.size > 1 else [d.theory for d in v.hydraulic_gap]
        a1.plot(pp, np.asarray(g) * 1e6, "-" if p.size > 1 else "D", color=f"C{k}",
                label=f"$g$ ({name})")  # fmt: skip
    for ax in axes:
        _pressure_axis(ax)
    a0.set_ylabel(r"mean separation $\bar u$ ($\mu$m)")
    a1.set_ylabel(r"effective gap ($\mu$m)")
    a1.set_ylim(0.0, None)
    a0.set_ylim(0.0, None)
    a0.legend(loc="lower left", fontsize=7, frameon=False)  # the curves fall to the right
    outside_legend(a1)
    return fig
