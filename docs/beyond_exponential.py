"""Why w/s falls below the Gaussian value 2 sqrt(2 ln 2): the evidence for docs/theory.md §6.

Imported by docs/make_reproduction.py (figure ``img/ws_beyond_exponential.png`` and its CSV,
and the table of reproduction.md). The argument:

* With bulk deformation neglected, ``u(x) = u1 + x^2/(2R)`` (paper eq. 11), so the profile is
  ``p(x) = p_law(u1 + x^2/2R)``: its *shape* is that of ``ln p`` against ``u``, mapped through
  the parabola. The exponential law (``ln p`` linear in ``u``) gives a Gaussian, w/s = 2.355.
* The full Persson law has ``ln p`` rising faster than linearly as ``u`` falls once ``p`` nears
  and exceeds ``beta E*`` (the exponential law's ``p`` at ``u = 0``). Then the profile's top is
  sharper than a Gaussian's and w/s < 2.355, with no elastic deformation involved at all:
  ``rigid_ws(theory, p0)`` computes that w/s from the law alone (R cancels).
* The solver, with the elastic deformation, follows that curve where the deformation is small
  and the exponential model stays at or above 2.355 on the same scenes.
"""

from __future__ import annotations

import numpy as np

import fastline as fl

#: the campaign-like scene (low H, wide band without roll-off, soft solid): SI units
H_RMS, HURST, Q0, Q1 = 1e-6, 0.5, 1e3, 1e9
E_STAR, RADIUS = 1e7, 0.01
ALPHAS = (0.3, 0.5, 1.0, 2.0, 5.0, 10.0, 100.0, 1000.0)
N = 1024


def scene():
    psd = fl.SelfAffinePSD(H_RMS, HURST, Q0, Q0, Q1)
    return psd, fl.PerssonTheory(psd, E_STAR)


def rigid_ws(theory, p0: float, points: int = 20001) -> float:
    """w/s of ``p(x) = p_law(u(p0) + x^2/2)`` (no elastic deformation; R = 1 m, it cancels)."""
    u1 = float(theory.separation([p0])[0])
    u_half = float(theory.separation([0.5 * p0])[0])
    fwhm = 2.0 * np.sqrt(2.0 * (u_half - u1))
    # integrate out to where p < 1e-12 p0: u - u1 up to u(1e-12 p0) - u1
    x_max = np.sqrt(2.0 * (float(theory.separation([1e-12 * p0])[0]) - u1))
    x = np.linspace(0.0, x_max, points)
    p = theory.pressure(u1 + 0.5 * x * x)
    s = np.sqrt(np.trapezoid(x * x * p, x) / np.trapezoid(p, x))
    return float(fwhm / s)


def study() -> dict:
    """The law curves, the rigid w/s curve and solver sweeps of the scene."""
    psd, th = scene()
    fit = th.exponential_fit()
    pb = fit.beta * E_STAR
    p = np.geomspace(1e-4 * pb, 30.0 * pb, 300)
    u = th.separation(p)
    ratios = np.geomspace(1e-2, 20.0, 40)
    ws_rigid = np.array([rigid_ws(th, r * pb) for r in ratios])
    rows = []
    for a in ALPHAS:
        f = float(fl.paper.load_for_alpha(a, H_RMS, E_STAR))
        r = fl.solve_line_contact(psd, E_STAR, RADIUS, f, theory=th, n=N, warn=False)
        r4 = fl.solve_line_contact(psd, E_STAR, RADIUS, f, theory=th, n=4 * N, warn=False)
        e = fl.solve_line_contact(
            psd, E_STAR, RADIUS, f, theory=th, n=N, model="exponential", warn=False
        )
        rows.append(
            dict(
                alpha=a,
                load=f,
                p0_over_beta_E=r.p0 / pb,
                ws=r.w_over_s,
                ws_n4=r4.w_over_s,
                ws_exponential=e.w_over_s,
                ws_rigid=rigid_ws(th, r.p0),
                fwhm=r.fwhm,
                converged=r.converged and r4.converged and e.converged,
            )
        )
    return dict(psd=psd, theory=th, fit=fit, p=p, u=u, ratios=ratios, ws_rigid=ws_rigid, rows=rows)


def figure(data, path: str) -> None:
    """Two panels: ln p against u (law vs exponential), and w/s against p0/(beta E*)."""
    from matplotlib.figure import Figure

    fit, pb = data["fit"], data["fit"].beta * E_STAR
    fig = Figure(figsize=(10.0, 3.9))
    fig.subplots_adjust(left=0.07, right=0.98, bottom=0.15, top=0.96, wspace=0.3)
    ax1, ax2 = fig.subplots(1, 2)
    u_h = data["u"] / H_RMS
    ax1.plot(u_h, np.log(data["p"] / pb), "-", color="C0", label="full Persson $u(p)$")
    uu = np.linspace(0.0, u_h.max(), 50)
    ax1.plot(uu, -uu * H_RMS / fit.u0, "--", color="k", lw=1, label="exponential law, eq. 5")
    for row in data["rows"][:4]:
        ax1.axhline(np.log(row["p0_over_beta_E"]), color="0.6", lw=0.6, ls=":")
    ax1.annotate(
        r"$p_0$ of the sweeps ($\alpha$ = 0.3 ... 2)", (0.97, 0.97), xycoords="axes fraction",
        ha="right", va="top", fontsize=8, color="0.4",
    )  # fmt: skip
    ax1.set_xlabel(r"mean separation $u/h_\mathrm{rms}$")
    ax1.set_ylabel(r"$\ln(p/\beta E^*)$")
    ax1.set_xlim(0.0, u_h.max())
    ax1.legend(loc="lower left", fontsize=8, frameon=False)

    ax2.semilogx(
        data["ratios"], data["ws_rigid"], "-", color="C0", label="law alone (no bulk deformation)"
    )
    rows = data["rows"]
    x = [r["p0_over_beta_E"] for r in rows]
    ax2.semilogx(x, [r["ws"] for r in rows], "o", color="C1", ms=4, label="solver, full $u(p)$")
    ax2.semilogx(
        x, [r["ws_exponential"] for r in rows], "s", color="C2", ms=4, mfc="none",
        label="solver, exponential law",
    )  # fmt: skip
    ax2.axhline(fl.WS_GAUSSIAN, color="k", ls=":", lw=0.8)
    ax2.annotate(
        r"Gaussian: $2\sqrt{2\ln 2}$", (0.98, fl.WS_GAUSSIAN), xycoords=("axes fraction", "data"),
        xytext=(0, 2), textcoords="offset points", fontsize=8, ha="right",
    )  # fmt: skip
    ax2.set_xlabel(r"$p_0/\beta E^*$")
    ax2.set_ylabel(r"$w/s$")
    ax2.legend(loc="lower left", fontsize=8, frameon=False)
    fig.savefig(path, dpi=150, metadata={"Software": "fastline"})
