"""Regenerate docs/img/leak_oring.png and .csv: the worked O-ring example of docs/leakage.md.

Run from the repository root: ``python docs/make_leakage_figure.py`` (needs matplotlib).
"""

from __future__ import annotations

import math
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import fastline as fl  # noqa: E402

OUT = Path(__file__).resolve().parent / "img"

# the scene of docs/leakage.md
E_STAR = fl.effective_modulus(10e6, 0.5, 210e9, 0.3)  # rubber on steel, Pa
PSD = fl.SelfAffinePSD(0.3e-6, 0.85, q0=5e4, qr=5e5, q1=1e9)  # the steel surface
RADIUS = 1.5e-3  # O-ring cross-section radius, m
LENGTH = math.pi * 25e-3  # seal length: O-ring of 25 mm mean diameter, m
DP, ETA = 1e4, 1e-3  # 0.1 bar of water
LOADS = np.geomspace(10.0, 1e4, 43)  # N/m
PROFILE_LOAD = 300.0  # N/m, the load of the right-hand panel


def sweep(theory):
    rows = []
    for f in LOADS:
        res = fl.solve_line_contact(PSD, E_STAR, RADIUS, f, theory=theory, n=1024, warn=False)
        leak = fl.leak_rate(res, DP, ETA, LENGTH, theory=theory, warn=False)
        rows.append((f, res.p0, leak.Q, leak.sealed, leak.share_in_fwhm))
    return np.array(rows, dtype=float)


def main():
    theory = fl.PerssonTheory(PSD, E_STAR)
    rows = sweep(theory)
    OUT.mkdir(exist_ok=True)
    np.savetxt(
        OUT / "leak_oring.csv",
        rows,
        delimiter=",",
        header="load_N_per_m,p0_Pa,leak_rate_m3_per_s,sealed,resistance_share_in_fwhm",
        comments="",
    )
    f_seal = rows[rows[:, 3] > 0, 0].min()

    fig, (ax, bx) = plt.subplots(1, 2, figsize=(10.0, 3.8), constrained_layout=True)
    leaking = rows[:, 3] == 0
    ax.loglog(rows[leaking, 0], rows[leaking, 2], "o-", ms=3, color="C0")
    ax.axvspan(f_seal, LOADS[-1], color="0.88", lw=0)
    ax.text(
        math.sqrt(f_seal * LOADS[-1]),
        1e-15,
        "sealed: $u_c < 1$ nm or $P(q_1, p) \\geq 0.42$",
        fontsize=9,
        ha="center",
        va="center",
        rotation=90,
    )
    ax.set_xlim(LOADS[0], LOADS[-1])
    ax.set_ylim(1e-22, 1e-9)
    ax.set_xlabel("load per unit length $f_N$ (N/m)")
    ax.set_ylabel("leak rate $Q$ (m$^3$/s)")
    ax.grid(True, which="major", alpha=0.3)

    res = fl.solve_line_contact(PSD, E_STAR, RADIUS, PROFILE_LOAD, theory=theory, warn=False)
    leak = fl.leak_rate(res, DP, ETA, LENGTH, theory=theory, warn=False)
    keep = np.abs(res.x) < 1.6 * res.fwhm
    xm = res.x[keep] * 1e3
    bx.plot(xm, res.pressure[keep] / 1e6, color="C0", label="$p(x)$")
    bx.set_xlabel("$x$ (mm)")
    bx.set_ylabel("nominal pressure $p$ (MPa)", color="C0")
    cx = bx.twinx()
    cx.semilogy(xm, leak.u_c[keep] * 1e9, color="C3", label="$u_c(x)$")
    cx.set_ylabel("critical gap $u_c$ (nm)", color="C3")
    cum = leak.cumulative_share[keep]
    lo, hi = np.interp([0.05, 0.95], cum, xm)
    bx.axvspan(lo, hi, color="C2", alpha=0.15, lw=0, label="90 % of the flow resistance")
    lines = bx.get_legend_handles_labels()
    more = cx.get_legend_handles_labels()
    bx.legend(
        lines[0] + more[0], lines[1] + more[1], loc="upper center", fontsize=8, framealpha=0.9
    )
    bx.set_ylim(0, 1.6 * res.p0 / 1e6)
    fig.savefig(OUT / "leak_oring.png", dpi=130)
    print(f"sealing load ~{f_seal:.0f} N/m; figure and CSV in {OUT}")


if __name__ == "__main__":
    main()
