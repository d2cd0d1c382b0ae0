"""Regenerate docs/performance.md and docs/img/perf_*.png: ``python -m bench.report``.

Every number in the report is measured by this script; the page is never edited by hand.
Timings are the best of a few repeats after a warm-up call (Numba compiled, FFTW planned).
"""

from __future__ import annotations

import datetime
import math
import os
import platform
import sys
import time
import warnings
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import fastline as fl  # noqa: E402
from bench import baseline as bl  # noqa: E402
from bench import coldstart, core, hard  # noqa: E402
from bench.conftest import (  # noqa: E402
    ALPHAS,
    E_STAR,
    PICARD_CAP,
    RADIUS,
    SWEEP_LOADS,
    load_for_alpha,
    surfaces,
)
from bench.test_bench_startup import STAGES, cold_and_warm  # noqa: E402
from fastline.contact.line import solve_line_contact  # noqa: E402

ROOT = Path(__file__).resolve().parent.parent
DOCS = ROOT / "docs"
IMG = DOCS / "img"
ERR_ALPHAS = (1e-3, 1e-2, 0.1, 1.0, 10.0)
NS = (128, 256, 512, 1024, 2048, 4096)
TOLS = (1e-4, 1e-6, 1e-8)
BASE_NS = (64, 128, 256)


def best_time(fn, *args, repeat=5, min_total=0.05, **kw):
    """Best wall time of one call (after one warm-up call); the warm-up's result is returned."""
    out = fn(*args, **kw)
    best = math.inf
    t_all = time.perf_counter()
    k = 0
    while k < repeat or (time.perf_counter() - t_all < min_total and k < 2000):
        t = time.perf_counter()
        fn(*args, **kw)
        best = min(best, time.perf_counter() - t)
        k += 1
    return best, out


def versions():
    import numba
    import pyfftw
    import scipy

    return {
        "python": platform.python_version(),
        "numpy": np.__version__,
        "numba": numba.__version__,
        "scipy": scipy.__version__,
        "pyfftw": pyfftw.__version__,
        "fastline": fl.__version__,
    }


def cpu_name():
    try:
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            if line.startswith("model name"):
                return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return platform.processor() or "unknown"


def rel(a, b):
    return abs(a / b - 1.0)


def main():
    warnings.simplefilter("ignore")
    IMG.mkdir(parents=True, exist_ok=True)
    t_start = time.perf_counter()
    psd = surfaces()[0]
    th = fl.PerssonTheory(psd, E_STAR)
    kw = dict(theory=th, warn=False)

    # ---- micro: table build, pressure(u), convolution --------------------------------------
    micro = {}
    probe_p = np.geomspace(1e-7 * E_STAR, 0.5 * E_STAR, 200)
    ref_u = fl.PerssonTheory(psd, E_STAR, rtol=1e-9).separation(probe_p)
    for rtol in (1e-4, 1e-6, 1e-8):
        # this shared machine has slow spells of ~1 s: take the best over 1.5 s of calls
        t, built = best_time(fl.PerssonTheory, psd, E_STAR, rtol=rtol, repeat=10, min_total=1.5)
        micro[f"build_{rtol:g}"] = t
        # speed against error: the table u(p) and the inverse p(u) against the rtol 1e-9 quadrature
        micro[f"err_u_{rtol:g}"] = float(np.max(rel(built.separation_table(probe_p)[0], ref_u)))
        micro[f"err_p_{rtol:g}"] = float(np.max(rel(built.pressure(ref_u), probe_p)))
    u = np.geomspace(1e-3, 10.0, 100_000) * th.exponential_fit().u0
    micro["pressure_1e5"] = best_time(th.pressure, u, repeat=100, min_total=1.5)[0]
    # noise-proof companion: the same array through NumPy's exp, best of as many calls
    micro["np_exp_1e5"] = best_time(np.exp, u, repeat=100, min_total=1.5)[0]
    for n in (512, 2048, 8192):
        op = fl.LogKernelOperator(n, 1e-5, E_STAR)
        pv = np.random.default_rng(0).random(n)
        micro[f"conv_{n}"] = best_time(op.apply, pv, repeat=50)[0]

    # ---- (b) convolutions per alpha, newton vs picard ---------------------------------------
    conv = {}
    for a in ALPHAS:
        f = load_for_alpha(a)
        for m in ("newton", "picard"):
            extra = {"max_iter": PICARD_CAP} if m == "picard" else {}
            rep = 1 if m == "picard" else 5
            t, r = best_time(
                solve_line_contact, psd, E_STAR, RADIUS, f, method=m, repeat=rep, **kw, **extra
            )
            conv[(a, m)] = (r.convolutions, r.converged, r.residual, t, r.diagnostics)
    t_default = conv[(1e-2, "newton")][3]
    t_default_all = {a: conv[(a, "newton")][3] for a in ALPHAS}

    # ---- paper sweep ------------------------------------------------------------------------
    pairs = [(s, fl.PerssonTheory(s, E_STAR)) for s in surfaces()]

    def sweep():
        return [
            solve_line_contact(s, E_STAR, RADIUS, float(f), theory=t_, warn=False)
            for s, t_ in pairs
            for f in SWEEP_LOADS
        ]

    t_sweep, sw = best_time(sweep, repeat=3, min_total=0.0)
    sweep_conv = sum(r.converged for r in sw)

    # ---- (a) error vs time ------------------------------------------------------------------
    refs = {}
    for a in ERR_ALPHAS:
        refs[a] = solve_line_contact(
            psd, E_STAR, RADIUS, load_for_alpha(a), n=16384, tol=1e-10, **kw
        )
    acc = {}
    for a in ERR_ALPHAS:
        f = load_for_alpha(a)
        for n in NS:
            for tol in TOLS:
                t, r = best_time(
                    solve_line_contact, psd, E_STAR, RADIUS, f, n=n, tol=tol, repeat=3, **kw
                )
                acc[(a, n, tol)] = (
                    t,
                    rel(r.p0_ratio, refs[a].p0_ratio),
                    rel(r.w_over_s, refs[a].w_over_s),
                )

    # ---- (c) time vs n ----------------------------------------------------------------------
    scal_ns = (256, 512, 1024, 2048, 4096, 8192, 16384)
    scal, scal_conv = {}, {}
    for a in (1e-2, 1.0, 100.0):
        runs = [
            best_time(
                solve_line_contact, psd, E_STAR, RADIUS, load_for_alpha(a), n=n, repeat=3, **kw
            )
            for n in scal_ns
        ]
        scal[a] = [t for t, _ in runs]
        scal_conv[a] = [r.convolutions for _, r in runs]
    fit = slice(2, 6)  # n = 1024 .. 8192
    expo = {a: float(np.polyfit(np.log(scal_ns[fit]), np.log(scal[a][fit]), 1)[0]) for a in scal}
    last = {a: math.log(scal[a][-1] / scal[a][-2]) / math.log(2.0) for a in scal}

    # ---- (d) baseline at matched error ------------------------------------------------------
    bpsd = bl.SelfAffine(10e-6, 0.8, 1e3, 1e4, 1e9)
    t0 = time.perf_counter()
    table = bl.SeparationTable(bpsd, E_STAR)
    t_base_table = time.perf_counter() - t0
    base = {}
    for a in ERR_ALPHAS:
        f = load_for_alpha(a)
        for n in BASE_NS:
            tb, b = best_time(bl.solve, table, E_STAR, RADIUS, f, n=n, repeat=3)
            tf, r = best_time(solve_line_contact, psd, E_STAR, RADIUS, f, n=n, repeat=5, **kw)
            ref = refs[a]
            base[(a, n)] = dict(
                tb=tb,
                tf=tf,
                eb=max(rel(b.p0_ratio, ref.p0_ratio), rel(b.w_over_s, ref.w_over_s)),
                ef=max(rel(r.p0_ratio, ref.p0_ratio), rel(r.w_over_s, ref.w_over_s)),
                ok=b.converged,
            )

    # ---- (e) fresh process --------------------------------------------------------------------
    startup = cold_and_warm()
    cold, warm, p0r, staged = startup.cold, startup.warm, startup.p_warm, startup.staged
    floor, floor_exit = startup.floor

    # ---- (f) the core's targets: counts over n, FFT share, sweeps, threads -------------------
    core_m = core.measure()
    hard_rows = hard.measure()

    # ---- figures ------------------------------------------------------------------------------
    cmap = plt.get_cmap("viridis")
    fig, axes = plt.subplots(1, 2, figsize=(11, 5.0))
    for k, a in enumerate(ERR_ALPHAS):
        col = cmap(k / (len(ERR_ALPHAS) - 1))
        for tol, mk in zip(TOLS, ("o", "s", "^"), strict=True):
            ts = [acc[(a, n, tol)][0] * 1e3 for n in NS]
            for ax, j in zip(axes, (1, 2), strict=True):
                es = [max(acc[(a, n, tol)][j], 1e-16) for n in NS]
                ax.loglog(
                    ts,
                    es,
                    mk + "-",
                    color=col,
                    ms=4,
                    lw=1,
                    label=f"alpha={a:g}" if tol == 1e-8 else None,
                )
    for ax, what in zip(axes, ("p0 ratio", "w/s"), strict=True):
        ax.set_xlabel("time per solve [ms]")
        ax.set_ylabel(f"relative error of {what}")
        ax.grid(True, which="both", alpha=0.3)
    handles, labels = axes[0].get_legend_handles_labels()
    fig.legend(  # below the panels: no corner of them is free of data
        handles,
        labels,
        loc="lower center",
        ncol=len(labels),
        fontsize=8,
        title="n = 128..4096 along each line; marker: o tol 1e-4, s 1e-6, ^ 1e-8",
        title_fontsize=8,
    )
    fig.tight_layout(rect=(0.0, 0.12, 1.0, 1.0))
    fig.savefig(IMG / "perf_error_vs_time.png", dpi=110)
    plt.close(fig)

    fig, ax = plt.subplots(figsize=(6.5, 4.3))
    for m, col in (("newton", "C0"), ("picard", "C3")):
        cs = [conv[(a, m)][0] for a in ALPHAS]
        ok = [conv[(a, m)][1] for a in ALPHAS]
        ax.loglog(ALPHAS, cs, "-", color=col, label=m)
        ax.loglog(
            [a for a, o in zip(ALPHAS, ok, strict=True) if o],
            [c for c, o in zip(cs, ok, strict=True) if o],
            "o",
            color=col,
        )
        bad = [(a, c) for a, c, o in zip(ALPHAS, cs, ok, strict=True) if not o]
        if bad:
            ax.loglog(
                *zip(*bad, strict=True),
                "x",
                color=col,
                ms=9,
                mew=2,
                label=f"{m}: not converged (cap {PICARD_CAP} sweeps)",
            )
    ax.axhline(100, color="gray", ls="--", lw=1, label="target 100")
    ax.set_xlabel("alpha = h_rms / delta")
    ax.set_ylabel("FFT convolutions per solve")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(IMG / "perf_convolutions.png", dpi=110)
    plt.close(fig)

    fig, ax = plt.subplots(figsize=(6.5, 4.3))
    for a in scal:
        ax.loglog(scal_ns, np.array(scal[a]) * 1e3, "o-", label=f"alpha={a:g}: slope {expo[a]:.2f}")
    ax.set_xlabel("grid points n")
    ax.set_ylabel("time per solve [ms] (tol 1e-8)")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8, title="fitted exponent (1024 <= n <= 8192)", title_fontsize=8)
    fig.tight_layout()
    fig.savefig(IMG / "perf_time_vs_n.png", dpi=110)
    plt.close(fig)

    fig, ax = plt.subplots(figsize=(8.5, 4.3))
    for k, a in enumerate(ERR_ALPHAS):
        col = cmap(k / (len(ERR_ALPHAS) - 1))
        ax.loglog(
            [base[(a, n)]["tf"] * 1e3 for n in BASE_NS],
            [base[(a, n)]["ef"] for n in BASE_NS],
            "o-",
            color=col,
            label=f"fastline, alpha={a:g}",
        )
        ax.loglog(
            [base[(a, n)]["tb"] * 1e3 for n in BASE_NS],
            [base[(a, n)]["eb"] for n in BASE_NS],
            "s--",
            color=col,
            mfc="none",
            label=f"SciPy baseline, alpha={a:g}",
        )
    ax.set_xlabel("time per solve [ms]")
    ax.set_ylabel("max rel. error of p0 ratio, w/s")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(  # beside the axes: the data fill every corner
        fontsize=7,
        title=f"n = {', '.join(map(str, BASE_NS))} along each line",
        title_fontsize=7,
        loc="upper left",
        bbox_to_anchor=(1.01, 1.0),
    )
    fig.tight_layout()
    fig.savefig(IMG / "perf_baseline.png", dpi=110)
    plt.close(fig)

    # ---- targets ------------------------------------------------------------------------------
    conv_max = max(conv[(a, "newton")][0] for a in ALPHAS if a >= 1e-3)
    conv_worst = max((a for a in ALPHAS if a >= 1e-3), key=lambda a: conv[(a, "newton")][0])
    t_solve_max = max(t_default_all.values())
    targets = [
        (
            "<= 100 convolutions per solve, every alpha >= 1e-3 (default method)",
            conv_max,
            100,
            f"max {conv_max} (alpha={conv_worst:g})",
        ),
        (
            "warm solve <= 10 ms at default settings (worst alpha)",
            t_solve_max * 1e3,
            10,
            f"{t_solve_max * 1e3:.2f} ms (alpha=1e-2: {t_default * 1e3:.2f} ms)",
        ),
        ("paper sweep (3 x 25 loads) <= 1 s warm", t_sweep, 1.0, f"{t_sweep:.3f} s"),
        (
            "Persson table build <= 5 ms warm (rtol 1e-6, default)",
            micro["build_1e-06"] * 1e3,
            5,
            f"{micro['build_1e-06'] * 1e3:.2f} ms",
        ),
        (
            "pressure(u) on 1e5 points <= 1 ms warm",
            micro["pressure_1e5"] * 1e3,
            1,
            f"{micro['pressure_1e5'] * 1e3:.3f} ms",
        ),
    ]

    # ---- markdown -----------------------------------------------------------------------------
    v = versions()
    L = []
    L.append("# Performance\n")
    L.append("_Generated by `python -m bench.report`; do not edit by hand._\n")
    L.append(f"- Date: {datetime.datetime.now(datetime.timezone.utc):%Y-%m-%d %H:%M UTC}")
    L.append(f"- Machine: {platform.platform()}, {cpu_name()}, {os.cpu_count()} CPUs")
    L.append("- Versions: " + ", ".join(f"{k} {val}" for k, val in v.items()))
    L.append(
        f"- Scene: E* = {E_STAR:g} Pa, R = {RADIUS:g} m, surface 1 (h_rms 10 um, H 0.8, "
        "q0 1e3, qr 1e4, q1 1e9 1/m) unless stated; f_N = (pi/4) h_rms E*/alpha. "
        "Defaults: method newton, n 1024, tol 1e-8, table rtol 1e-6."
    )
    L.append("- Report runtime: {RUNTIME} s. Timings: best of several warm calls.\n")

    L.append("## Standing targets: solve, table and lookup speed\n")
    L.append("| target | measured | met? | margin |")
    L.append("|---|---|---|---|")
    for name, val, lim, txt in targets:
        ok = val <= lim
        margin = f"{lim / val:.1f}x under" if ok else f"{val / lim:.2f}x over"
        L.append(f"| {name} | {txt} | {'yes' if ok else '**no**'} | {margin} |")
    L.append("")

    L.append("## Standing targets: speed at the limit and sweeps\n")
    L.append("| target | measured | met? | margin |")
    L.append("|---|---|---|---|")
    for name, val, lim, txt in core.targets(core_m, cold, warm):
        ok = val <= lim
        margin = f"{lim / val:.1f}x under" if ok else f"{val / lim:.2f}x over"
        L.append(f"| {name} | {txt} | {'yes' if ok else '**no**'} | {margin} |")
    L.append("")
    L.extend(core.markdown(core_m))
    L.extend(hard.markdown(hard_rows))

    L.append("## Convolutions per solve (n = 1024, tol = 1e-8)\n")
    L.append(
        f"Picard is capped at {PICARD_CAP} sweeps; `no` marks a solve that did not converge.\n"
    )
    L.append(
        "Newton's count is every FFT convolution of length 2n: products with K plus the "
        "preconditioner's circulant solves (in brackets: K products + circulant solves).\n"
    )
    L.append("| alpha | newton conv. | newton ms | picard conv. | picard converged | picard ms |")
    L.append("|---|---|---|---|---|---|")
    for a in ALPHAS:
        cn, okn, _, tn, dn = conv[(a, "newton")]
        cp, okp, rp, tp, _ = conv[(a, "picard")]
        split = f"{dn['k_applications']} + {dn['circulant_solves']}"
        L.append(
            f"| {a:g} | {cn} ({split}){'' if okn else ' (no)'} | {tn * 1e3:.2f} | {cp} | "
            f"{'yes' if okp else f'no (residual {rp:.1e})'} | {tp * 1e3:.1f} |"
        )
    L.append("\n![convolutions](img/perf_convolutions.png)\n")

    L.append("## Building blocks\n")
    L.append("| operation | time |")
    L.append("|---|---|")
    for rtol in (1e-4, 1e-6, 1e-8):
        L.append(
            f"| PerssonTheory build, rtol {rtol:g} | {micro[f'build_{rtol:g}'] * 1e3:.2f} ms "
            f"(max rel. error, 1e-7 E* <= p <= 0.5 E*: table u(p) "
            f"{micro[f'err_u_{rtol:g}']:.1e}, p(u) {micro[f'err_p_{rtol:g}']:.1e}) |"
        )
    L.append(
        f"| pressure(u), 1e5 points | {micro['pressure_1e5'] * 1e3:.3f} ms "
        f"({micro['pressure_1e5'] / micro['np_exp_1e5']:.2f}x `np.exp` of the same array, "
        f"{micro['np_exp_1e5'] * 1e3:.3f} ms) |"
    )
    for n in (512, 2048, 8192):
        L.append(f"| one convolution, n = {n} | {micro[f'conv_{n}'] * 1e6:.1f} us |")
    L.append(
        f"| paper sweep, 3 surfaces x 25 loads (1e3..1.5e6 N/m) | {t_sweep:.3f} s "
        f"({sweep_conv}/75 converged) |"
    )
    L.append("")

    L.append("## Error vs time\n")
    L.append(
        "Relative error of p0/p0_Hertz and w/s against a converged n = 16384, tol = 1e-10 solve, "
        f"for n in {NS} and tol in {TOLS}. The error is set by n (discretisation), "
        "not by tol, for tol <= 1e-6.\n"
    )
    L.append("![error vs time](img/perf_error_vs_time.png)\n")
    L.append("| alpha | n | time ms (tol 1e-8) | err p0 ratio | err w/s |")
    L.append("|---|---|---|---|---|")
    for a in ERR_ALPHAS:
        for n in NS:
            t, e1, e2 = acc[(a, n, 1e-8)]
            L.append(f"| {a:g} | {n} | {t * 1e3:.2f} | {e1:.1e} | {e2:.1e} |")
    L.append("")

    L.append("## Time vs n\n")
    L.append(
        "Fitted exponent of time ~ n^k over 1024 <= n <= 8192: "
        + ", ".join(f"alpha {a:g}: k = {expo[a]:.2f}" for a in expo)
        + ". Local exponent from n = 8192 to 16384: "
        + ", ".join(f"alpha {a:g}: {last[a]:.2f}" for a in last)
        + ". Convolutions per solve for n = "
        + ", ".join(map(str, scal_ns))
        + ": "
        + "; ".join(f"alpha {a:g}: " + ", ".join(map(str, scal_conv[a])) for a in scal_conv)
        + " (a local exponent well above the growth of the count times n log n means time "
        "outside the FFTs).\n"
    )
    L.append("![time vs n](img/perf_time_vs_n.png)\n")

    L.append("## Speed-up over a NumPy/SciPy baseline at matched error\n")
    L.append(
        "`bench/baseline.py`: dense influence matrix (same cell-integrated log kernel), "
        "Persson u(p) "
        "by `scipy.integrate.quad` over q (F from `exp1` + `quad`) tabulated on 48 pressures and "
        "spline-interpolated, and `scipy.optimize.root` (hybr, analytic Jacobian) on ln p and u1. "
        "Both codes solve the same discrete problem at the same n, so they reach the same error; "
        "the speed-up is the ratio of solve times. The baseline's one-off u(p) table took "
        f"{t_base_table:.2f} s (fastline: {micro['build_1e-06'] * 1e3:.1f} ms), not included "
        "below.\n"
    )
    L.append("| alpha | n | baseline ms | fastline ms | speed-up | err baseline | err fastline |")
    L.append("|---|---|---|---|---|---|---|")
    for a in ERR_ALPHAS:
        for n in BASE_NS:
            d = base[(a, n)]
            L.append(
                f"| {a:g} | {n} | {d['tb'] * 1e3:.2f}{'' if d['ok'] else ' (not conv.)'} | "
                f"{d['tf'] * 1e3:.2f} | {d['tb'] / d['tf']:.1f}x | {d['eb']:.1e} | {d['ef']:.1e} |"
            )
    sp = {n: [base[(a, n)]["tb"] / base[(a, n)]["tf"] for a in ERR_ALPHAS] for n in BASE_NS}
    L.append(
        "\nSpeed-up range per n: "
        + "; ".join(f"n={n}: {min(s):.1f}x-{max(s):.1f}x" for n, s in sp.items())
        + ". The dense baseline costs O(n^3) per Jacobian factorisation, so the gap widens "
        "with n; fastline's default n = 1024 is out of the baseline's practical range.\n"
    )
    L.append("![baseline](img/perf_baseline.png)\n")

    L.append("## Fresh process: time to a first answer\n")
    L.append(
        '`python -c "import fastline; ...; print(p0_ratio)"` in a new interpreter '
        f"(p0 ratio {p0r:.6g} at f_N = 1e4 N/m):\n"
    )
    L.append(
        "Times from the start of the process to the printed answer; in brackets, to the "
        "process's exit, which adds Numba's and LLVM's teardown (after the answer: a seal code "
        "that embeds fastline pays it once, when it ends).\n"
    )
    L.append(f"- cold (empty NUMBA_CACHE_DIR): {cold:.2f} s ({startup.cold_exit:.2f} s)")
    L.append(
        f"- warm (same cache dir, median of 5 fresh interpreters): {warm:.2f} s "
        f"({startup.warm_exit:.2f} s)"
    )
    L.append(
        f"- the floor, a trivial cached Numba function in a fresh interpreter (median of 5): "
        f"{floor:.2f} s ({floor_exit:.2f} s); fastline's first answer costs "
        f"{warm - floor:+.2f} s on top\n"
    )
    L.append(
        "Where a warm start goes (median of 5 fresh interpreters, a clock read after each "
        "stage; the stages before fastline's own are the floor any Numba package pays here):\n"
    )
    L.append("| stage | s | share |")
    L.append("|---|---|---|")
    for name, dt in zip(STAGES, staged, strict=True):
        L.append(f"| {name} | {dt:.3f} | {dt / sum(staged):.0%} |")
    L.append(f"| total | {sum(staged):.3f} | |\n")
    L.append(
        "The time to the answer also holds the interpreter's start (~0.03 s); the exit adds "
        "Numba's and LLVM's teardown, the same for the trivial program as for fastline.\n"
    )
    L += coldstart.markdown(coldstart.main(["--runs", "5"]))

    runtime = time.perf_counter() - t_start
    text = "\n".join(L).replace("{RUNTIME}", f"{runtime:.0f}")
    old = (DOCS / "performance.md").read_text()  # the BEM section is bench.bem_scaling's: kept
    text += old[old.find("\n<!-- bem-section") :] if "<!-- bem-section" in old else ""
    (DOCS / "performance.md").write_text(text)
    print(text)


if __name__ == "__main__":
    sys.exit(main())
