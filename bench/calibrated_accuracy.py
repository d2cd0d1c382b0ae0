"""Where a calibrated law gains or loses accuracy on the narrow-band cylinder scene of
docs/validation.md ("A calibrated law on the paper-like scene"): the cylinder BEM computed once
and cached, then any number of laws compared against it at theory speed.

    python -m bench.calibrated_accuracy reference --cache DIR --alphas 1 3 10 --realizations 40
    python -m bench.calibrated_accuracy flat --out flat.npz [--periods 4] [--realizations 8] \
        [--p-min 2 --p-max 1e5 --pressures 24] [--seed 0]
    python -m bench.calibrated_accuracy plot --cache DIR --law law.npz --out fig.png
    python -m bench.calibrated_accuracy compare --cache DIR --law law.npz [law2.npz ...] \
        [--flat flat.npz flat_a.npz+flat_b.npz ...] [--alphas 1 3 10]

``reference``: the cylinder BEM ensemble (:func:`fastline.bem.run_ensemble`, the page's grid:
2 longest wavelengths along the axis, 4 cells per 2 pi/q1, seed 0) at each alpha, pickled to
``DIR/bem_alpha{alpha}_n{realizations}.pkl`` (an existing file is kept). ``flat``: flat-contact
BEM u(p) of ``--realizations`` surfaces carried from pressure to pressure as
:func:`fastline.calibrate` carries them (warm starts, the same seeds), contact only (no flow):
per surface the mean gap, the contact fraction and the mean gap over the open cells. ``compare``:
for each law file its :class:`fastline.CalibratedLaw` and the :class:`fastline.TabulatedLaw` of
its own points, for each flat file the TabulatedLaw of its mean u(p) and the jackknife error of
p0 and s over its surfaces (with ``--fixed-gap`` also the law of the surfaces' mean pressure
at a fixed mean gap: :func:`_fixed_gap`); Persson's law and the Greenwood-Williamson law
beside; p0, s and w/s against the cached references of each alpha pooled (relative and in BEM
standard errors).
``plot``: each cached reference's p_bar(x) (± 2 standard errors) against the first law's.
"""

from __future__ import annotations

import argparse
import concurrent.futures as cf
import glob
import math
import os
import pickle
import time

import numpy as np

import fastline as fl
from bench.calibrated_validation import E_STAR, PSD, RADIUS, load_of
from fastline import bem
from fastline.bem.compare import compare_line_contact
from fastline.theory.asperity import GreenwoodWilliamsonLaw


def cmd_reference(args) -> None:
    os.makedirs(args.cache, exist_ok=True)
    for a in args.alphas:
        name = f"bem_alpha{a:g}_n{args.realizations}" + (f"_seed{args.seed}" if args.seed else "")
        out = os.path.join(args.cache, name + ".pkl")
        if os.path.exists(out):
            continue
        scene = bem.line_contact_scene(PSD, E_STAR, RADIUS, load_of(a), periods=2.0)
        t0 = time.perf_counter()
        ens = bem.run_ensemble(
            scene, args.realizations, args.seed, workers=args.workers, progress=False
        )
        with open(out, "wb") as f:
            pickle.dump(ens, f)
        print(f"alpha {a:g}: {args.realizations} surfaces, {time.perf_counter() - t0:.0f} s, "
              f"grid {scene.grid.nx} x {scene.grid.ny}, {ens.iterations.sum()} CCG iterations; "
              f"p0/p0_H {ens.p0_ratio:.4f} +- {ens.p0_ratio_error:.4f}, s {ens.s * 1e6:.2f} +- "
              f"{ens.s_error * 1e6:.2f} um, w/s {ens.w_over_s:.3f} +- {ens.w_over_s_error:.3f}; "
              f"load average {os.getloadavg()}", flush=True)  # fmt: skip


def _flat_surface(job) -> np.ndarray:
    """(mean gap [m], contact fraction, mean open gap [m], CCG iterations) per pressure."""
    seed, periods, pressures = job
    grid = bem.spectral_grid(PSD, points_per_wavelength=4.0, periods=periods)
    g0 = -bem.random_surface(PSD, grid, seed).heights
    out = np.zeros((4, pressures.size))
    warm = None
    for i, p in enumerate(pressures):
        r = bem.solve_contact(g0, grid, E_STAR, float(p) * grid.lx * grid.ly, p_init=warm)
        if i + 1 < pressures.size:
            warm = np.maximum(r.pressure, 0.0) * (pressures[i + 1] / p)
        out[:, i] = (r.gap.mean(), r.contact_fraction, r.gap[r.gap > 0.0].mean(), r.iterations)
    return out


def cmd_flat(args) -> None:
    p = np.geomspace(args.p_min, args.p_max, args.pressures)
    seeds = np.random.SeedSequence(args.seed).spawn(args.realizations)
    t0 = time.perf_counter()
    with cf.ProcessPoolExecutor(args.workers) as ex:
        runs = np.array(list(ex.map(_flat_surface, [(s, args.periods, p) for s in seeds])))
    np.savez(args.out, p=p, u=runs[:, 0], area=runs[:, 1], u_open=runs[:, 2], periods=args.periods)
    print(f"{args.out}: {args.realizations} surfaces x {p.size} pressures, periods "
          f"{args.periods:g}, {time.perf_counter() - t0:.0f} s, {runs[:, 3].sum():.0f} CCG "
          f"iterations, load average {os.getloadavg()}")  # fmt: skip
    u, e = runs[:, 0].mean(0), runs[:, 0].std(0, ddof=1) / math.sqrt(len(runs))
    for k in range(p.size):
        print(f"  p {p[k]:9.4g} Pa: u {u[k] * 1e6:.4f} +- {e[k] * 1e6:.4f} um, "
              f"A/A0 {runs[:, 1, k].mean():.3e}, open-cell mean gap / u - 1 "
              f"{runs[:, 2, k].mean() / u[k] - 1:+.2e}")  # fmt: skip


def _references(cache, by_seed: bool = False) -> dict:
    """alpha -> the cached ensembles (one per seed: the largest of each seed; by_seed: a dict
    seed -> ensemble)."""
    out: dict = {}
    for path in sorted(glob.glob(os.path.join(cache, "bem_alpha*_n*.pkl"))):
        with open(path, "rb") as f:
            e = pickle.load(f)
        seed = path.rsplit("_seed", 1)[1][:-4] if "_seed" in path else "0"
        d = out.setdefault(round(PSD.h_rms / e.delta, 6), {})
        if seed not in d or e.realizations > d[seed].realizations:
            d[seed] = e
    return {a: list(d.values()) for a, d in out.items()} if not by_seed else out


def _pooled(ensembles) -> dict:
    """name -> (value, standard error) of p0, s and w/s over independent ensembles (weights:
    their realisations)."""
    n = np.array([e.realizations for e in ensembles], dtype=float)
    out = {}
    for name in ("p0", "s", "w_over_s"):
        v = np.array([getattr(e, name) for e in ensembles])
        se = np.array([getattr(e, name + "_error") for e in ensembles])
        out[name] = (float(n @ v / n.sum()), float(np.sqrt(((n * se) ** 2).sum()) / n.sum()))
    return out


def _solve(law, alpha):
    return fl.LineContact(PSD, E_STAR, RADIUS, model=law, n=1024, warn=False).solve(load_of(alpha))


def _fixed_gap(u: np.ndarray, p: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(u_k, p_bar_k): the surfaces' mean gap at each pressure and the mean over surfaces of
    the pressure each surface needs for that gap (its own u(p), linear in ln p, extended with
    its end slopes): the ensemble's mean pressure at a fixed mean gap."""
    v = np.log(p)
    um = u.mean(0)
    out = []
    for ui in u:
        x, y = ui[::-1], v[::-1]
        lv = np.interp(um, x, y)
        lo, hi = um < x[0], um > x[-1]
        lv[lo] = y[0] + (um[lo] - x[0]) * (y[1] - y[0]) / (x[1] - x[0])
        lv[hi] = y[-1] + (um[hi] - x[-1]) * (y[-1] - y[-2]) / (x[-1] - x[-2])
        out.append(np.exp(lv))
    return um, np.mean(out, axis=0)


def _flat_table(u, p, fixed_gap) -> fl.TabulatedLaw:
    return fl.TabulatedLaw(*_fixed_gap(u, p)) if fixed_gap else fl.TabulatedLaw(u.mean(0), p)


def _flat_laws(path, fixed_gap=False) -> tuple[str, fl.TabulatedLaw, list]:
    """The TabulatedLaw of a flat file's mean u(p) and its jackknife laws (one surface out);
    ``a.npz+b.npz`` pools the surfaces of files of the same pressures."""
    files = [np.load(f) for f in path.split("+")]
    u, p = np.concatenate([d["u"] for d in files]), files[0]["p"]
    n = u.shape[0]
    jack = [_flat_table(np.delete(u, k, axis=0), p, fixed_gap) for k in range(n)]
    name = "flat " + "+".join(os.path.basename(f) for f in path.split("+"))
    name += ", mean p at fixed u" if fixed_gap else ""
    return name, _flat_table(u, p, fixed_gap), jack


def _row(name, r, ensembles, jack_err=None) -> str:
    """One law's p0, s and w/s against the (pooled) reference, and its chi2/bin (one
    reference) or the mean of the references' (several)."""
    comps = [compare_line_contact(r, e) for e in ensembles]
    pooled = _pooled(ensembles)
    cells = []
    for stat in ("p0", "s", "w_over_s"):
        theory = getattr(comps[0], stat).theory
        v, se = pooled[stat]
        cells.append(f"{100 * (theory / v - 1):+.1f} % (z {(theory - v) / se:+.1f})")
    chi2 = np.mean([c.chi2_per_bin for c in comps])
    extra = ""
    if jack_err is not None:
        extra = f" | ±{100 * jack_err[0]:.1f} % / ±{100 * jack_err[1]:.1f} %"
    return f"| | {name} | {' | '.join(cells)} | {chi2:.2f}{extra} |"


def _reference_rows(a, ensembles) -> list[str]:
    rows = []
    for e in ensembles:
        rows.append(
            f"| {a:g} | BEM, {e.realizations} surfaces | p0/p0_H {e.p0_ratio:.3f} ± "
            f"{e.p0_ratio_error:.3f} | {e.s * 1e6:.1f} ± {e.s_error * 1e6:.1f} µm | "
            f"{e.w_over_s:.2f} ± {e.w_over_s_error:.2f} | | |"
        )
    if len(ensembles) > 1:
        pooled = _pooled(ensembles)
        (p0, p0e), (sv, se), (ws, wse) = pooled["p0"], pooled["s"], pooled["w_over_s"]
        ph = ensembles[0].p0_hertz
        n = sum(e.realizations for e in ensembles)
        rows.append(
            f"| {a:g} | BEM, pooled {n} surfaces | p0/p0_H {p0 / ph:.3f} ± {p0e / ph:.3f} | "
            f"{sv * 1e6:.1f} ± {se * 1e6:.1f} µm | {ws:.2f} ± {wse:.2f} | | |"
        )
    return rows


def cmd_compare(args) -> None:
    refs = _references(args.cache)
    laws: list = []
    for path in args.law:
        law = fl.CalibratedLaw.load(path, psd=PSD, E_star=E_STAR)
        tag = os.path.basename(path)
        laws.append((f"calibrated {tag}", law, None))
        table = fl.TabulatedLaw(law.points.u, law.points.p)
        laws.append(("TabulatedLaw of its points", table, None))
    for path in args.flat or []:
        laws.append(_flat_laws(path))
        if args.fixed_gap:
            laws.append(_flat_laws(path, fixed_gap=True))
    laws.append(("persson (yang-persson-energy)", "persson", None))
    laws.append(("greenwood-williamson", GreenwoodWilliamsonLaw.from_psd(PSD, E_STAR), None))
    print("| alpha | law | p0 | s | w/s | chi2/bin | calibration's own error of p0 / s |")
    print("|---|---|---|---|---|---|---|")
    for a in args.alphas:
        e = refs.get(round(a, 6))
        if e is None:
            print(f"| {a:g} | no cached reference in {args.cache} | | | | | |")
            continue
        print("\n".join(_reference_rows(a, e)))
        for name, law, jack in laws:
            r = _solve(law, a)
            err = None
            if jack:
                js = np.array([(x.p0, x.s) for x in (_solve(j, a) for j in jack)])
                n = len(jack)
                err = np.sqrt((n - 1) * js.var(axis=0)) / np.array([r.p0, r.s])
            print(_row(name, r, e, err), flush=True)


def cmd_plot(args) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    refs = _references(args.cache, by_seed=True)
    law = fl.CalibratedLaw.load(args.law[0], psd=PSD, E_star=E_STAR)
    cols = min(3, len(args.alphas))
    rows = -(-len(args.alphas) // cols)
    fig, axs = plt.subplots(rows, cols, figsize=(4.4 * cols, 3.5 * rows), squeeze=False)
    for ax in axs.flat[len(args.alphas) :]:
        ax.set_axis_off()
    for ax, a in zip(axs.flat, args.alphas, strict=False):
        r = _solve(law, a)
        top = 0.0
        for k, (seed, e) in enumerate(sorted(refs[round(a, 6)].items())):
            colour = ("k", "tab:blue", "tab:green")[k % 3]
            x, p, pe = e.coordinate * 1e6, e.pressure / 1e3, e.pressure_error / 1e3
            ax.fill_between(x, p - 2 * pe, p + 2 * pe, color=colour, alpha=0.15, lw=0)
            ratio = f"{e.p0_ratio:.2f} ± {e.p0_ratio_error:.2f}"
            label = f"BEM seed {seed}, {e.realizations} surfaces: {ratio}"
            ax.plot(x, p, ".-", color=colour, ms=2.5, lw=0.8, label=label)
            top = max(top, float(np.max(p + 2 * pe)))
        theory = compare_line_contact(r, e).theory_pressure / 1e3
        ax.plot(
            x, theory, color="tab:red", lw=1.6, label=f"calibrated law: {r.p0 / e.p0_hertz:.2f}"
        )
        ax.set_xlim(-3.5 * r.s * 1e6, 3.5 * r.s * 1e6)
        ax.set_ylim(0.0, 1.4 * top)
        ax.set_xlabel("x (µm)")
        ax.set_ylabel("nominal pressure p̄ (kPa)")
        ax.set_title(f"alpha = {a:g}", fontsize=10)
        ax.legend(
            fontsize=7.5, loc="upper left", title="p0/p0_H", title_fontsize=7.5, frameon=False
        )
    fig.tight_layout()
    fig.savefig(args.out, dpi=110)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    sub = ap.add_subparsers(dest="cmd", required=True)
    r = sub.add_parser("reference")
    r.add_argument("--cache", required=True)
    r.add_argument("--alphas", type=float, nargs="+", default=[1.0, 3.0, 10.0])
    r.add_argument("--realizations", type=int, default=40)
    r.add_argument("--seed", type=int, default=0)
    r.add_argument("--workers", type=int, default=2)
    f = sub.add_parser("flat")
    f.add_argument("--out", required=True)
    f.add_argument("--periods", type=float, default=4.0)
    f.add_argument("--realizations", type=int, default=8)
    f.add_argument("--p-min", type=float, default=2.0)
    f.add_argument("--p-max", type=float, default=1e5)
    f.add_argument("--pressures", type=int, default=24)
    f.add_argument("--seed", type=int, default=0)
    f.add_argument("--workers", type=int, default=2)
    c = sub.add_parser("compare")
    c.add_argument("--cache", required=True)
    c.add_argument("--law", nargs="*", default=[])
    c.add_argument("--flat", nargs="*", default=[])
    c.add_argument("--alphas", type=float, nargs="+", default=[1.0, 3.0, 10.0])
    c.add_argument("--fixed-gap", action="store_true")
    g = sub.add_parser("plot")
    g.add_argument("--cache", required=True)
    g.add_argument("--law", nargs=1, required=True)
    g.add_argument("--out", required=True)
    g.add_argument("--alphas", type=float, nargs="+", default=[1.0, 3.0, 10.0])
    args = ap.parse_args()
    cmds = {"reference": cmd_reference, "flat": cmd_flat, "compare": cmd_compare, "plot": cmd_plot}
    cmds[args.cmd](args)


if __name__ == "__main__":
    main()
