"""The numbers and figures of docs/validation.md that ``fastline validate`` does not print itself.

    python docs/validation_study.py grid       # alpha = 1: the same surfaces at 4 and 8 points
                                               # per shortest wavelength (paired), ~3 min
    python docs/validation_study.py bandwidth  # GW and Persson against q1/q0, BEM at q1/q0 = 8
    python docs/validation_study.py lattice    # BEM surfaces' h_rms and slope vs the spectrum's
    python docs/validation_study.py sphere     # the rough sphere (Greenwood-Tripp) with each law
    python docs/validation_study.py figures    # the figures, from the CSVs in docs/img

The line-contact and flat-contact tables come from ``fastline validate`` runs (their commands are
in docs/validation.md); ``figures`` reads their CSVs from docs/img.
"""

from __future__ import annotations

import math
import os
import sys
import time

import numpy as np

import fastline as fl
from fastline import bem
from fastline.bem._profile import central_peak
from fastline.io import read_csv, write_csv

HERE = os.path.dirname(os.path.abspath(__file__))
IMG = os.path.join(HERE, "img")
E_STAR, RADIUS = 10e6, 32.8e-3
Q0 = 2.0 * math.pi / 40e-6
MODELS = ("yang-persson-energy", "yang-persson-printed", "wang-mueser", "greenwood-williamson")
ALPHAS = ("0.1", "0.55", "1", "2.3", "10")


def paper_like(ratio=32.0):
    """The paper-like narrow-band surface (docs/validation.md): H 0.8, h_rms 0.5 um,
    q0 = 2 pi/40 um, no roll-off."""
    return fl.SelfAffinePSD(0.5e-6, 0.8, Q0, Q0, ratio * Q0)


def load_for(psd, alpha):
    return math.pi * E_STAR * psd.h_rms / (4.0 * alpha)


# ----------------------------------------------------------------------------------------------
# grid convergence: the same surfaces on a grid twice as fine
# ----------------------------------------------------------------------------------------------
def upsample(h, factor):
    """The band-limited surface ``h`` sampled ``factor`` times finer on the same cell (the
    cell-centre grid of fastline.bem.Grid: the first fine centre lies (factor - 1)/(2 factor)
    of a coarse cell before the first coarse one)."""
    nx, ny = h.shape
    H = np.fft.fft2(h)
    kx = np.fft.fftfreq(nx) * nx
    ky = np.fft.fftfreq(ny) * ny
    shift = (factor - 1) / (2.0 * factor)  # in coarse cells
    H = H * np.exp(-2j * np.pi * shift * (kx[:, None] / nx + ky[None, :] / ny))
    F = np.zeros((factor * nx, factor * ny), dtype=complex)
    ix = np.concatenate([np.arange(nx // 2), np.arange(factor * nx - nx // 2, factor * nx)])
    iy = np.concatenate([np.arange(ny // 2), np.arange(factor * ny - ny // 2, factor * ny)])
    F[np.ix_(ix, iy)] = H
    return np.real(np.fft.ifft2(F)) * factor * factor


def solve(scene, grid, heights):
    kappa = bem.image_curvature(scene.E_star, scene.load, scene.radius, grid.lx)
    gap = bem.cylinder_gap(grid, scene.radius, kappa) - heights
    res = bem.solve_contact(
        gap, grid, scene.E_star, scene.load * grid.ly, tol=scene.tol, max_iter=scene.max_iter
    )
    return res.pressure.mean(axis=1), res


def profile_stats(x, p, dx, p0_hertz):
    m0 = p.sum()
    xc = np.dot(x, p) / m0
    s = math.sqrt(np.dot((x - xc) ** 2, p) / m0 + dx * dx / 12.0)
    return central_peak(x - xc, p, s) / p0_hertz, s


def grid_study(realizations=3):
    psd = paper_like()
    scene = bem.line_contact_scene(psd, E_STAR, RADIUS, load_for(psd, 1.0))
    g = scene.grid
    fine = bem.Grid(2 * g.nx, 2 * g.ny, g.dx / 2, g.dy / 2)
    p0_h = scene.hertz()[0]
    rows, profiles = [], {4: [], 8: []}
    for k, seed in enumerate(np.random.SeedSequence(0).spawn(realizations)):
        h = bem.random_surface(psd, g, seed).heights
        hf = upsample(h, 2)
        # the fine surface restricted to the coarse band is the coarse one (round trip)
        back = np.fft.fft2(hf)
        assert abs(np.std(hf) / np.std(h) - 1.0) < 1e-12, "upsampling changed the surface"
        del back
        for ppw, grid, heights in ((4, g, h), (8, fine, hf)):
            t = time.perf_counter()
            p, res = solve(scene, grid, heights)
            p0r, s = profile_stats(grid.x, p, grid.dx, p0_h)
            profiles[ppw].append((grid.x, p))
            rows.append(
                (k, ppw, p0r, s, res.contact_fraction, res.iterations, time.perf_counter() - t)
            )
            print(
                f"realisation {k}, {ppw} points: p0/p0H {p0r:.4f}, s {s:.5g} m, contact "
                f"{res.contact_fraction:.4f}, {res.iterations} CCG, {rows[-1][-1]:.1f} s",
                flush=True,
            )
    write_csv(
        os.path.join(IMG, "validation_grid.csv"),
        [
            "realization",
            "points_per_wavelength",
            "p0_ratio",
            "s_m",
            "contact_fraction",
            "ccg_iterations",
            "seconds",
        ],
        rows,
        {
            "scene": "paper-like, alpha = 1",
            "grid_4": f"{g.nx} x {g.ny}",
            "grid_8": f"{fine.nx} x {fine.ny}",
        },
        title="BEM grid convergence: the same surfaces at 4 and 8 points per 2 pi/q1",
    )
    # paired differences and the mean profiles' statistics
    r = np.array(rows)
    d_p0 = r[r[:, 1] == 8, 2] - r[r[:, 1] == 4, 2]
    d_s = r[r[:, 1] == 8, 3] / r[r[:, 1] == 4, 3] - 1.0
    se = lambda a: a.std(ddof=1) / math.sqrt(a.size)  # noqa: E731
    print(
        f"paired 8 - 4 points: p0/p0H {d_p0.mean():+.4f} +- {se(d_p0):.4f}, "
        f"s {100 * d_s.mean():+.2f}% +- {100 * se(d_s):.2f}%"
    )
    for ppw in (4, 8):
        x = profiles[ppw][0][0]
        p = np.mean([pp for _, pp in profiles[ppw]], axis=0)
        p0r, s = profile_stats(x, p, x[1] - x[0], p0_h)
        print(f"mean profile, {ppw} points: p0/p0H {p0r:.4f}, s {s:.5g} m")


# ----------------------------------------------------------------------------------------------
# bandwidth: GW depends on q1, Persson hardly
# ----------------------------------------------------------------------------------------------
def bandwidth_study(realizations=8):
    rows = []
    for ratio in (8, 32, 128, 512):
        psd = paper_like(ratio)
        st = fl.SummitStatistics.from_psd(psd)
        f = load_for(psd, 1.0)
        row = [ratio, st.alpha, st.density, st.radius, st.height_std, st.height_mean]
        for law in (fl.PerssonTheory(psd, E_STAR), fl.GreenwoodWilliamsonLaw.from_psd(psd, E_STAR)):
            if isinstance(law, fl.PerssonTheory):
                lc = fl.LineContact(psd, E_STAR, RADIUS, theory=law, warn=False)
            else:
                lc = fl.LineContact(psd, E_STAR, RADIUS, model=law, warn=False)
            r = lc.solve(f)
            row += [r.p0_ratio, r.s]
        rows.append(row)
        print(
            f"q1/q0 {ratio}: Nayak alpha {st.alpha:.4g}, Persson p0/p0H {row[6]:.4f} s "
            f"{row[7]:.4g}, GW p0/p0H {row[8]:.4f} s {row[9]:.4g}",
            flush=True,
        )
    write_csv(
        os.path.join(IMG, "validation_bandwidth.csv"),
        [
            "q1_over_q0",
            "nayak_alpha",
            "summit_density_per_m2",
            "summit_radius_m",
            "summit_std_m",
            "summit_mean_m",
            "persson_p0_ratio",
            "persson_s_m",
            "gw_p0_ratio",
            "gw_s_m",
        ],
        rows,
        {"scene": "paper-like spectrum with q1 varied, alpha = 1"},
        title="GW and Persson line contacts against the bandwidth q1/q0",
    )


# ----------------------------------------------------------------------------------------------
# the BEM's lattice spectrum against the continuum one
# ----------------------------------------------------------------------------------------------
def lattice_study():
    """The random-phase surfaces of a periodic cell hold only the modes of its lattice; each mode
    carries the mean of the spectrum over its cell, normalised to the spectrum's h_rms
    (fastline.bem.surface). Their h_rms and rms slope against the spectrum's."""
    psd = paper_like()
    scene = bem.line_contact_scene(psd, E_STAR, RADIUS, load_for(psd, 1.0))
    grids = (
        ("line, alpha = 1", scene.grid),
        ("flat, 2 periods", bem.spectral_grid(psd, periods=2)),
        ("flat, 4 periods", bem.spectral_grid(psd, periods=4)),
    )
    for name, grid in grids:
        surf = bem.random_surface(psd, grid, 0)
        print(
            f"{name}: {grid.nx} x {grid.ny} cells, surface / spectrum: h_rms "
            f"{surf.h_rms / psd.h_rms:.5f}, rms slope {surf.rms_slope / psd.rms_slope:.5f}"
        )


# ----------------------------------------------------------------------------------------------
# the rough sphere
# ----------------------------------------------------------------------------------------------
def sphere_figure():
    from matplotlib.figure import Figure

    from fastline.reports.plotting import save_figure

    psd = paper_like()
    fig = Figure(figsize=(5.6, 3.8))
    fig.subplots_adjust(left=0.13, right=0.66, bottom=0.15, top=0.96)
    ax = fig.add_subplot()
    a = math.sqrt(RADIUS * psd.h_rms)  # alpha = h_rms / delta = 1, delta = a^2 / R
    load = 4.0 * E_STAR * a**3 / (3.0 * RADIUS)
    laws = {
        "yang-persson-energy": fl.PerssonTheory(psd, E_STAR),
        "greenwood-williamson": fl.GreenwoodWilliamsonLaw.from_psd(psd, E_STAR),
    }
    for k, (name, law) in enumerate(laws.items()):
        kw = {"theory": law} if isinstance(law, fl.PerssonTheory) else {"model": law}
        r = fl.PointContact(psd, E_STAR, RADIUS, warn=False, **kw).solve(load)
        x, p = r.diameter_profile()
        ax.plot(
            x * 1e3,
            p / 1e3,
            ["-", ":"][k],
            color=f"C{[0, 3][k]}",
            label=f"{name}\n$\\alpha$ = {r.alpha:.2g}, $p_0/p_{{0,H}}$ = {r.p0_ratio:.2f}",
        )
        print(f"sphere {name}: alpha {r.alpha:.3g}, p0/p0H {r.p0_ratio:.4f}, s {r.s:.4g} m")
    hz = fl.hertz_point_contact(E_STAR, RADIUS, load)
    xs = np.linspace(-2 * hz.a, 2 * hz.a, 801)
    ax.plot(xs * 1e3, hz.pressure(np.abs(xs)) / 1e3, "--", color="k", lw=1, label="Hertz (smooth)")
    ax.set_xlim(-0.25, 0.25)
    ax.set_ylim(0, None)
    ax.set_xlabel(r"$x$ along a diameter (mm)")
    ax.set_ylabel(r"nominal pressure $p$ (kPa)")
    ax.legend(loc="upper left", bbox_to_anchor=(1.02, 1.0), fontsize=8, frameon=False)
    save_figure(fig, os.path.join(IMG, "validation_sphere.png"))


# ----------------------------------------------------------------------------------------------
# figures from the CSVs of the fastline validate runs
# ----------------------------------------------------------------------------------------------
def figures():
    from matplotlib.figure import Figure

    from fastline.reports.plotting import save_figure

    shown = ("0.1", "1", "10")
    fig = Figure(figsize=(11.0, 3.6))
    fig.subplots_adjust(left=0.06, right=0.83, bottom=0.15, top=0.95, wspace=0.25)
    axes = fig.subplots(1, len(shown))
    for ax, a in zip(axes, shown, strict=True):
        meta, cols = read_csv(os.path.join(IMG, f"validation_alpha_{a}.csv"))
        x = cols["x_m"] * 1e3
        p, e = cols["p_bem_Pa"] / 1e3, 2 * cols["p_bem_se_Pa"] / 1e3
        ax.fill_between(x, p - e, p + e, color="0.8", lw=0, label="BEM ± 2 s.e.")
        n = meta["realizations"]
        ax.plot(x, p, "-", color="k", lw=1, label=r"BEM $\bar p$")
        for k, m in enumerate(MODELS):
            ax.plot(
                x,
                cols[f"p_{m.replace('-', '_')}_Pa"] / 1e3,
                ["-", "--", "-.", ":"][k],
                color=f"C{k}",
                lw=1.3,
                label=m,
            )
        s = float(meta["bem_s_m"].split()[0])
        ax.set_xlim(-3.2 * s * 1e3, 3.2 * s * 1e3)
        ax.set_ylim(0, None)
        ax.set_xlabel(r"$x$ (mm)")
        ax.text(
            0.03,
            0.96,
            rf"$\alpha$ = {a}" + f"\n{n} surfaces",
            transform=ax.transAxes,
            va="top",
            fontsize=9,
        )
    axes[0].set_ylabel(r"nominal pressure $p$ (kPa)")
    axes[-1].legend(loc="upper left", bbox_to_anchor=(1.03, 1.0), fontsize=8, frameon=False)
    save_figure(fig, os.path.join(IMG, "validation_profiles.png"))
    print("wrote validation_profiles.png")


def table():
    """The markdown table of the line-contact runs (printed; docs/validation.md holds it)."""
    print("| alpha | | p0/p0_H | s (um) | w/s |")
    print("|---|---|---|---|---|")
    for a in ALPHAS:
        meta, _ = read_csv(os.path.join(IMG, f"validation_alpha_{a}.csv"))
        bem_v = {
            k: [float(t) for t in meta[f"bem_{k}"].split(" +- ")]
            for k in ("p0_ratio", "s_m", "w_over_s")
        }
        b = bem_v
        print(
            f"| {a} | BEM | {b['p0_ratio'][0]:.3f} ± {b['p0_ratio'][1]:.3f} | "
            f"{1e6 * b['s_m'][0]:.1f} ± {1e6 * b['s_m'][1]:.1f} | "
            f"{b['w_over_s'][0]:.2f} ± {b['w_over_s'][1]:.2f} |"
        )
        for m in MODELS:
            cells = []
            for key, scale, fmt in (
                ("p0_ratio", 1, ".3f"),
                ("s_m", 1e6, ".1f"),
                ("w_over_s", 1, ".2f"),
            ):
                v = float(meta[f"{m.replace('-', '_')}_{key}"])
                z = (v - b[key][0]) / b[key][1]
                cells.append(f"{scale * v:{fmt}} ({100 * (v / b[key][0] - 1):+.0f}%, z {z:+.1f})")
            print(f"| | {m} | " + " | ".join(cells) + " |")


if __name__ == "__main__":
    parts = {
        "grid": grid_study,
        "bandwidth": bandwidth_study,
        "lattice": lattice_study,
        "sphere": sphere_figure,
        "figures": figures,
        "table": table,
    }
    for name in sys.argv[1:] or ["figures"]:
        parts[name]()
