"""Convolutions over the 160 count scenes, and warm solve times: ``python -m bench.count_grid``.

The scenes of ``tests/test_solver.py::test_convolution_budget``: five hard surfaces (the paper's
three, H = 0.3, q1/q0 = 1e10) x the eight alphas 1e-4..1e3 of ``bench.conftest.ALPHAS`` x n =
256, 1024, 4096, 16384, default settings (tol 1e-8). Prints the maximum per n, the total and the
worst scenes; counts are exact on any machine. ``--times`` adds the warm solve time (best of 5)
of surface 1 at alpha 1e-4..1e3, n = 512, 1024, 4096, summed over the alphas, for same-run
comparisons of two checkouts (run each with its own venv, one after the other). ``--nested``
times the nested start from n/8 cells against cold starts on the same scenes at n = 4096-16384.
"""

from __future__ import annotations

import argparse
import time
import warnings

import fastline as fl
from fastline.reports.paper import E_STAR, RADIUS, load_for_alpha, surfaces

ALPHAS = (1e-4, 1e-3, 1e-2, 0.1, 1.0, 10.0, 100.0, 1e3)
NS = (256, 1024, 4096, 16384)
TIME_NS = (512, 1024, 4096)


def hard_surfaces() -> dict:
    """The five hard surfaces of the count test."""
    return {
        **dict(zip(("surface1", "surface2", "surface3"), surfaces(), strict=True)),
        "H0.3": fl.SelfAffinePSD(10e-6, 0.3, 1e3, 1e4, 1e9),
        "q1/q0=1e10": fl.SelfAffinePSD(10e-6, 0.8, 1e3, 1e4, 1e13),
    }


_THEORIES: dict = {}


def solve(psd, alpha, n):
    """One solve at default settings; the spectrum's theory is built once and reused."""
    if id(psd) not in _THEORIES:
        _THEORIES[id(psd)] = (psd, fl.PerssonTheory(psd, E_STAR))
    th = _THEORIES[id(psd)][1]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        load = load_for_alpha(alpha, psd.h_rms, E_STAR)
        return fl.solve_line_contact(psd, E_STAR, RADIUS, load, n=n, theory=th, warn=False)


def counts(ns=NS) -> None:
    rows = []
    for n in ns:
        for name, psd in hard_surfaces().items():
            for a in ALPHAS:
                res = solve(psd, a, n)
                its = [int(h[1]) for h in res.diagnostics["newton_history"]]
                start = res.diagnostics.get("nested_start")  # on n/8 cells, length n/4
                coarse = start["convolutions"] if start else 0
                rows.append((n, name, a, res.convolutions, res.converged, its, coarse))
    for n in ns:
        sel = [r for r in rows if r[0] == n]
        worst = max(sel, key=lambda r: r[3])
        print(
            f"n={n:6d}: max {worst[3]:3d} total {sum(r[3] for r in sel):5d}  "
            f"worst {worst[1]} alpha {worst[2]:g} CG/step {worst[5]}; nested start on n/8 "
            f"cells: max {max(r[6] for r in sel)} total {sum(r[6] for r in sel)}"
        )
    bad = [r for r in rows if not r[4]]
    print(f"all: max {max(r[3] for r in rows)} total {sum(r[3] for r in rows)}  unconverged {bad}")


def times() -> None:
    psd = surfaces()[0]
    for n in TIME_NS:
        tot = 0.0
        for a in ALPHAS:
            solve(psd, a, n)
            best = float("inf")
            for _ in range(5):
                t = time.perf_counter()
                solve(psd, a, n)
                best = min(best, time.perf_counter() - t)
            tot += best
        print(f"n={n:5d}: sum over 8 alphas of best-of-5 warm solve {tot * 1e3:8.2f} ms")


#: grids of the nested-iteration comparison (``--nested``)
NESTED_NS = (4096, 8192, 16384)


def nested_times() -> None:
    """The 40 count scenes per n, cold and nested (:data:`fastline.contact.line.NESTED_MIN_N`)
    interleaved in this process: the summed best CPU time of each, and the scenes where nesting
    cost more than 5 %."""
    import fastline.contact.line as lc_module

    default = lc_module.NESTED_MIN_N
    try:
        for n in NESTED_NS:
            total = {"cold": 0.0, "nested": 0.0}
            losses = []
            for name, psd in hard_surfaces().items():
                model = fl.LineContact(psd, E_STAR, RADIUS, n=n, warn=False)
                for a in ALPHAS:
                    load = load_for_alpha(a, psd.h_rms)
                    best = {"cold": float("inf"), "nested": float("inf")}
                    for mode in ("cold", "nested") * 3:
                        lc_module.NESTED_MIN_N = default if mode == "nested" else 2 * n
                        model.solve(load)
                        t = time.thread_time()
                        model.solve(load)
                        best[mode] = min(best[mode], time.thread_time() - t)
                    for mode, t in best.items():
                        total[mode] += t
                    if best["nested"] > 1.05 * best["cold"]:
                        losses.append(f"{name} alpha {a:g}: {best['nested'] / best['cold']:.2f}x")
            print(
                f"n={n:5d}: cold {total['cold'] * 1e3:7.1f} ms, nested {total['nested'] * 1e3:7.1f}"
                f" ms, ratio {total['nested'] / total['cold']:.2f}; losses > 5%: {losses}"
            )
    finally:
        lc_module.NESTED_MIN_N = default


if __name__ == "__main__":
    ap = argparse.ArgumentParser()
    ap.add_argument("--times", action="store_true")
    ap.add_argument("--nested", action="store_true", help="nested iteration against cold starts")
    ap.add_argument("--no-counts", action="store_true")
    args = ap.parse_args()
    if not args.no_counts:
        counts()
    if args.times:
        times()
    if args.nested:
        nested_times()
