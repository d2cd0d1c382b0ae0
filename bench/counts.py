"""Convolutions and warm time per solve over alpha and n (surface 1): ``python -m bench.counts``.

Prints a markdown table of ``convolutions / best-of-5 ms`` for n = 512, 1024, 2048, 8192 and the
benchmark's alphas (default method, tol 1e-8). Counts are exact on any machine; times are not.
"""

from __future__ import annotations

import time

import fastline as fl
from bench.conftest import ALPHAS, E_STAR, RADIUS, load_for_alpha, surfaces

NS = (512, 1024, 2048, 8192)


def main():
    psd = surfaces()[0]
    th = fl.PerssonTheory(psd, E_STAR)
    print("| n | " + " | ".join(f"{a:g}" for a in ALPHAS) + " |")
    print("|---" * (len(ALPHAS) + 1) + "|")
    for n in NS:
        row = []
        for a in ALPHAS:
            args = (psd, E_STAR, RADIUS, load_for_alpha(a))
            res = fl.solve_line_contact(*args, n=n, theory=th, warn=False)
            best = float("inf")
            for _ in range(5):
                t = time.perf_counter()
                fl.solve_line_contact(*args, n=n, theory=th, warn=False)
                best = min(best, time.perf_counter() - t)
            row.append(f"{res.convolutions} / {best * 1e3:.1f}")
        print(f"| {n} | " + " | ".join(row) + " |")


if __name__ == "__main__":
    main()
