"""A random campaign of point contacts: ``python -m bench.point_campaign [--scenes N] [--seed S]
[--alpha LO HI]``.

A robustness probe of the sphere's Newton solver, beside :mod:`bench.campaign` (the cylinder):
self-affine spectra with H in [0.3, 1], q0 in [1, 1e4] 1/m, qr / q0 up to 10^1.5, q1 / qr in
[10, 1e6], h_rms in [1e-8, 1e-4] m; E* in [1e6, 10^11.5] Pa, R in [1e-5, 1] m; log10 alpha
uniform in [LO, HI] (default 3..5, where 39 of 600 scenes of seed 1 once stopped with "line
search failed"); n one of 128, 256, 512; every fourth scene with the exponential law, the
others Persson's. Loads outside the accepted range are skipped. Prints the scenes solved,
their total and largest operator applications, and every scene that did not converge or
raised, as a call that reproduces it. The scenes depend on the seed only.
"""

from __future__ import annotations

import argparse
import math
import warnings

import numpy as np

import fastline as fl

NS = (128, 256, 512)


def scenes(count: int, seed: int, alpha_range: tuple[float, float]):
    """``(psd, E*, R, F, n, model)`` of the campaign, drawn from ``seed``."""
    rng = np.random.default_rng(seed)
    for k in range(count):
        hurst = rng.uniform(0.3, 1.0)
        q0 = 10 ** rng.uniform(0, 4)
        qr = q0 * 10 ** rng.uniform(0, 1.5)
        q1 = qr * 10 ** rng.uniform(1, 6)
        h_rms = 10 ** rng.uniform(-8, -4)
        e_star = 10 ** rng.uniform(6, 11.5)
        radius = 10 ** rng.uniform(-5, 0)
        alpha = 10 ** rng.uniform(*alpha_range)
        n = int(rng.choice(NS))
        model = "exponential" if k % 4 == 0 else "persson"
        a = math.sqrt(radius * h_rms / alpha)  # Hertz radius of delta = h_rms / alpha
        load = 4.0 * e_star * a**3 / (3.0 * radius)
        yield fl.SelfAffinePSD(h_rms, hurst, q0, qr, q1), e_star, radius, load, n, model


def run(count: int, seed: int, alpha_range: tuple[float, float]) -> None:
    total = largest = solved = 0
    failed = []
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        for k, (psd, e_star, radius, load, n, model) in enumerate(scenes(count, seed, alpha_range)):
            scene = f"{psd!r}, {e_star!r}, {radius!r}, {load!r}, n={n}, model={model!r}"
            try:
                res = fl.solve_point_contact(
                    psd, e_star, radius, load, n=n, model=model, warn=False
                )
            except ValueError as exc:
                if "load must lie" in str(exc):
                    continue  # outside the accepted loads: not a scene
                failed.append(f"scene {k}: ValueError: {exc}")
                continue
            solved += 1
            total += res.convolutions
            largest = max(largest, res.convolutions)
            if not res.converged:
                failed.append(f"scene {k}: fl.solve_point_contact({scene}): {res.message}")
    print(f"{solved} scenes solved, {total} operator applications (at most {largest} in one)")
    print(f"{len(failed)} did not converge or raised")
    for line in failed:
        print(line)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--scenes", type=int, default=600)
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--alpha", type=float, nargs=2, default=(3.0, 5.0), metavar=("LO", "HI"))
    args = parser.parse_args()
    run(args.scenes, args.seed, tuple(args.alpha))


if __name__ == "__main__":
    main()
