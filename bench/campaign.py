"""A random campaign of line-contact scenes: ``python -m bench.campaign [--scenes N] [--seed S]``.

A robustness probe for changes to the solver, beside the count scenes of ``bench.count_grid``
(which are the hard ones we know): self-affine spectra with H in [0.3, 1], q0 in [1e2, 1e4]
1/m, qr / q0 up to 10^1.5, q1 / qr in [10, 1e6], h_rms in [1e-7, 10^-4.5] m; alpha log-uniform
in [1e-6, 1e4]; n one of 128, 512, 2048, 8192; every fourth scene with the exponential law, the
others Persson's. Prints the scenes solved, their total and largest FFT convolutions, and every
scene that did not converge or raised. The scenes depend on the seed only, so two checkouts
run one after the other compare like for like (counts are exact on any machine).
"""

from __future__ import annotations

import argparse
import math
import warnings

import numpy as np

import fastline as fl
from fastline.reports.paper import E_STAR, RADIUS, load_for_alpha

NS = (128, 512, 2048, 8192)


def scenes(count: int, seed: int):
    """``(psd, alpha, n, model)`` of the campaign, drawn from ``seed``."""
    rng = np.random.default_rng(seed)
    for k in range(count):
        hurst = rng.uniform(0.3, 1.0)
        q0 = 10 ** rng.uniform(2, 4)
        qr = q0 * 10 ** rng.uniform(0, 1.5)
        q1 = qr * 10 ** rng.uniform(1, 6)
        h_rms = 10 ** rng.uniform(-7, -4.5)
        alpha = 10 ** rng.uniform(-6, 4)
        n = int(rng.choice(NS))
        model = "exponential" if k % 4 == 0 else "persson"
        yield fl.SelfAffinePSD(h_rms, hurst, q0, qr, q1), alpha, n, model


def run(count: int, seed: int) -> None:
    total = largest = solved = 0
    failed = []
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        for k, (psd, alpha, n, model) in enumerate(scenes(count, seed)):
            load = load_for_alpha(alpha, psd.h_rms, E_STAR)
            try:
                res = fl.solve_line_contact(psd, E_STAR, RADIUS, load, n=n, model=model, warn=False)
            except Exception as exc:  # a probe: report it and go on
                failed.append(f"scene {k}: {type(exc).__name__}: {exc}")
                continue
            solved += 1
            total += res.convolutions
            largest = max(largest, res.convolutions)
            if not res.converged:
                failed.append(
                    f"scene {k}: log10 alpha {math.log10(alpha):.2f}, n {n}, {model}: {res.message}"
                )
    print(f"{solved} scenes solved, {total} convolutions (at most {largest} in one solve)")
    print(f"{len(failed)} not converged or raised" + (":" if failed else ""))
    for line in failed:
        print("  " + line)


if __name__ == "__main__":
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--scenes", type=int, default=240)
    ap.add_argument("--seed", type=int, default=2026)
    args = ap.parse_args()
    run(args.scenes, args.seed)
