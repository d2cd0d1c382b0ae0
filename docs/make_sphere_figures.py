"""Regenerate the figures of docs/sphere.md: ``python docs/make_sphere_figures.py``.

* docs/img/sphere_experiment.png and .csv: the paper's indentation experiment (steel ball on
  sandblasted aluminium) with the assumed spectrum of docs/sphere.md;
* docs/img/sphere_fig4_ws.png, sphere_fig5_p0ratio.png: the sphere versions of Figs. 4-5
  (the same as ``fastline paper --geometry sphere``).

Run from the repository root (needs matplotlib).
"""

from __future__ import annotations

from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import fastline as fl  # noqa: E402
from fastline.reports import (
    paper,  # noqa: E402
    plotting,
)

OUT = Path(__file__).resolve().parent / "img"

# the experiment of the paper (its section 3, last figure) and the assumed aluminium surface
E_STAR = fl.effective_modulus(210e9, 0.3, 70e9, 0.33)  # steel on aluminium, Pa
RADIUS, LOAD = 0.02, 500.0  # m, N
PSD = fl.SelfAffinePSD(5e-6, 0.8, q0=1e4, qr=1e5, q1=1e8)  # assumed: grit-blasted aluminium
HARDNESS = 1e9  # Pa, aluminium (order of magnitude)
PAPER_DIAMETERS = {"Hertz (paper)": 0.9e-3, "deformed asperities (paper)": 1.5e-3}  # m


def experiment():
    res = fl.solve_point_contact(PSD, E_STAR, RADIUS, LOAD, hardness=HARDNESS, warn=False)
    hz = fl.hertz_point_contact(E_STAR, RADIUS, LOAD)
    np.savetxt(
        OUT / "sphere_experiment.csv",
        np.column_stack([res.r, res.pressure, hz.pressure(res.r)]),
        delimiter=",",
        header="r_m,p_rough_Pa,p_hertz_Pa",
        comments="",
    )
    fig, ax = plt.subplots(figsize=(8.0, 3.9))
    fig.subplots_adjust(left=0.09, right=0.6, bottom=0.15, top=0.96)
    x, p = res.diameter_profile()
    ax.plot(x * 1e3, p / 1e6, "-", color="C0", label=f"rough, $\\alpha$ = {res.alpha:.2f}")
    ax.plot(x * 1e3, hz.pressure(x) / 1e6, "--", color="k", lw=1, label="Hertz (smooth)")
    d99 = 2 * res.load_radius(0.99)
    ax.axvspan(-d99 / 2 * 1e3, d99 / 2 * 1e3, color="C0", alpha=0.12, lw=0,
               label=f"99% of the load: {d99 * 1e3:.2f} mm")  # fmt: skip
    for (text, d), ls in zip(PAPER_DIAMETERS.items(), (":", "-."), strict=True):
        for sign in (-1, 1):
            ax.axvline(sign * d / 2 * 1e3, color="C3", ls=ls, lw=1,
                       label=f"{text}: {d * 1e3:.1f} mm" if sign > 0 else None)  # fmt: skip
    ax.set_xlim(-1.2, 1.2)
    ax.set_ylim(0.0, None)
    ax.set_xlabel(r"position along a diameter $x$ (mm)")
    ax.set_ylabel(r"nominal pressure $p$ (MPa)")
    ax.legend(loc="upper left", bbox_to_anchor=(1.02, 1.0), fontsize=8, frameon=False)
    fig.savefig(OUT / "sphere_experiment.png", dpi=150)
    return res


def figs_4_5():
    data = paper.sphere_paper_data(loads=40)
    series = {s.label: s.results for s in data.surfaces}
    plotting.save_figure(plotting.plot_w_over_s(series), OUT / "sphere_fig4_ws.png")
    fig = plotting.plot_p0_ratio(series, gamma_u={s.label: s.gamma_u for s in data.surfaces})
    plotting.save_figure(fig, OUT / "sphere_fig5_p0ratio.png")


def main():
    OUT.mkdir(exist_ok=True)
    res = experiment()
    d = res.diagnostics
    print(
        f"alpha {res.alpha:.3f}, p0 {res.p0:.4g} Pa (ratio {res.p0_ratio:.3f}), w/s "
        f"{res.w_over_s:.3f}, Hertz diameter {2e3 * res.hertz_radius:.3f} mm, 99% load "
        f"diameter {2e3 * res.load_radius(0.99):.3f} mm, p = 1% p0 at diameter "
        f"{2e3 * res.pressure_radius(0.01):.3f} mm, h'E*/2 {d['asperity_pressure']:.3g} Pa"
    )
    figs_4_5()


if __name__ == "__main__":
    main()
