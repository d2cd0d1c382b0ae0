"""Accuracy and speed of the point contact: ``python -m bench.sphere_report``.

Prints the markdown tables of docs/sphere.md ("Accuracy" and "Performance"): the error of p0
and w/s against n, operator applications and solve times over alpha (with the line contact's
time in the same run for a machine-independent ratio), and the cost of one ring-operator
product against one FFT convolution of the line contact. Timings are the best of several calls
after a warm-up call; counts are exact on any machine.
"""

from __future__ import annotations

import math
import time
import warnings

import numpy as np

import fastline as fl
from bench.conftest import ALPHAS, E_STAR, RADIUS, load_for_alpha, surfaces
from fastline.reports.paper import sphere_load_for_alpha

ERR_ALPHAS = (1e-3, 1e-2, 0.1, 1.0, 10.0, 100.0)
ERR_NS = (128, 256, 512, 1024)
REF_N = 4096
SPEED_NS = (256, 512, 1024)


def best(fn, *args, repeat=7):
    fn(*args)
    out = math.inf
    for _ in range(repeat):
        t = time.perf_counter()
        fn(*args)
        out = min(out, time.perf_counter() - t)
    return out


def accuracy(psd, theory):
    print(f"Relative error against n = {REF_N} (surface 1, model persson, tol 1e-10):\n")
    print("| alpha | " + " | ".join(f"n = {n}: p0 ratio / w/s" for n in ERR_NS) + " |")
    print("|---" * (len(ERR_NS) + 1) + "|")
    for a in ERR_ALPHAS:
        f = float(sphere_load_for_alpha(a, psd.h_rms))
        kw = dict(theory=theory, tol=1e-10, warn=False)
        ref = fl.solve_point_contact(psd, E_STAR, RADIUS, f, n=REF_N, **kw)
        cells = []
        for n in ERR_NS:
            r = fl.solve_point_contact(psd, E_STAR, RADIUS, f, n=n, **kw)
            e1, e2 = r.p0_ratio / ref.p0_ratio - 1, r.w_over_s / ref.w_over_s - 1
            cells.append(f"{e1:.1e} / {e2:.1e}")
        print(f"| {a:g} | " + " | ".join(cells) + " |")
    print("\nHertz model against the closed forms (F = 10 N):\n")
    print("| n | p0 | w/s | rigid approach -u1 vs delta | L1 profile error |")
    print("|---|---|---|---|---|")
    hz = fl.hertz_point_contact(E_STAR, RADIUS, 10.0)
    for n in (64, 128, 256, 512, 1024, 2048):
        r = fl.solve_point_contact(None, E_STAR, RADIUS, 10.0, model="hertz", n=n, tol=1e-10)
        e = np.concatenate([[0.0], r.r + 0.5 * r.dr])
        out = 2 * math.pi * hz.a**2 * hz.p0 / 3 * np.maximum(1 - (e / hz.a) ** 2, 0) ** 1.5
        w = math.pi * (e[1:] ** 2 - e[:-1] ** 2)
        l1 = np.sum(np.abs(r.pressure * w - (out[:-1] - out[1:]))) / 10.0
        print(
            f"| {n} | {r.p0 / hz.p0 - 1:.1e} | {r.w_over_s / fl.WS_HERTZ_SPHERE - 1:.1e} | "
            f"{-r.u1 / hz.delta - 1:.1e} | {l1:.1e} |"
        )


def speed(psd, theory):
    print("\nOperator applications (products with K + preconditioner solves) and the best")
    print("time of a solve from the cold start, surface 1; last column: the line contact at")
    print("its default n = 1024 and the same alpha, same run:\n")
    print("| alpha | " + " | ".join(f"n = {n}" for n in SPEED_NS) + " | line n = 1024 |")
    print("|---" * (len(SPEED_NS) + 2) + "|")
    models = {n: fl.PointContact(psd, E_STAR, RADIUS, n=n, theory=theory, warn=False)
              for n in SPEED_NS}  # fmt: skip
    line = fl.LineContact(psd, E_STAR, RADIUS, theory=theory, warn=False)
    for a in ALPHAS:
        f = float(sphere_load_for_alpha(a, psd.h_rms))
        cells = []
        for n in SPEED_NS:
            r = models[n].solve(f)
            t = best(models[n].solve, f)
            cells.append(
                f"{r.convolutions} ({r.diagnostics['k_applications']} + "
                f"{r.diagnostics['preconditioner_solves']}) / {t * 1e3:.1f} ms"
            )
        fl_line = load_for_alpha(a)
        rl = line.solve(fl_line)
        tl = best(line.solve, fl_line)
        print(f"| {a:g} | " + " | ".join(cells) + f" | {rl.convolutions} / {tl * 1e3:.1f} ms |")


def products():
    print("\nOne product with the ring operator against one FFT convolution of the line")
    print("contact at the same n (best of 7 x 200 calls):\n")
    print("| n | ring product | line FFT convolution | ratio |")
    print("|---|---|---|---|")
    rng = np.random.default_rng(0)
    for n in (256, 512, 1024, 2048, 4096):
        ring, lin = fl.RingKernelOperator(n, 1e-6, E_STAR), fl.LogKernelOperator(n, 1e-6, E_STAR)
        p, out = rng.random(n), np.empty(n)

        def many(op, p=p, out=out):
            for _ in range(200):
                op.apply(p, out)

        tr, tl = best(many, ring) / 200, best(many, lin) / 200
        print(f"| {n} | {tr * 1e6:.1f} us | {tl * 1e6:.1f} us | {tr / tl:.1f} |")


def sweep_saving(psd, theory):
    model = fl.PointContact(psd, E_STAR, RADIUS, theory=theory, warn=False)
    loads = sphere_load_for_alpha(np.geomspace(1e-3, 1e3, 40), psd.h_rms)
    swept = sum(r.convolutions for r in model.sweep(loads))
    alone = sum(model.solve(float(f)).convolutions for f in loads)
    t_sweep = best(model.sweep, loads, repeat=3)
    print(f"\nSweep of 40 loads (alpha 1e-3..1e3, surface 1, n = 512): {swept} operator")
    print(f"applications with continuation, {alone} for independent solves; {t_sweep:.3f} s.")


def main():
    warnings.simplefilter("ignore")
    psd = surfaces()[0]
    theory = fl.PerssonTheory(psd, E_STAR)
    accuracy(psd, theory)
    speed(psd, theory)
    products()
    sweep_saving(psd, theory)


if __name__ == "__main__":
    main()
