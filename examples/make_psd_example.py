"""Write examples/psd_example.txt: a small, synthetic "measured" spectrum for the docs.

A self-affine spectrum with roll-off (h_rms 2 µm, H = 0.85, q0 = 2e3, qr = 2e4, q1 = 1e8 1/m)
tabulated at 48 log-spaced wavenumbers, with seeded 10 % log-normal scatter such as a
measured (averaged) spectrum has. Two columns: q [1/m], C(q) [m^4] (Persson's isotropic
convention, h_rms^2 = 2 pi int q C dq). Run from the repository root:

    python examples/make_psd_example.py
"""

import os

import numpy as np

import fastline as fl

HERE = os.path.dirname(os.path.abspath(__file__))


def main() -> None:
    psd = fl.SelfAffinePSD(2e-6, 0.85, 2e3, 2e4, 1e8)
    q = np.geomspace(2e3, 1e8, 48)
    rng = np.random.default_rng(20260101)
    C = psd(q) * np.exp(0.1 * rng.standard_normal(q.size))
    C[-1] = psd(q[-1] * (1 - 1e-12))  # the last point sits on the cut-off
    lines = [
        "# synthetic measured spectrum (examples/make_psd_example.py): self-affine with roll-off,",
        "# h_rms 2 um, H 0.85, q0 2e3, qr 2e4, q1 1e8 1/m, 10 % seeded log-normal scatter",
        "# q [1/m]   C(q) [m^4]",
    ]
    lines += [f"{a:.6e} {b:.6e}" for a, b in zip(q, C, strict=True)]
    with open(os.path.join(HERE, "psd_example.txt"), "w", encoding="utf-8") as fh:
        fh.write("\n".join(lines) + "\n")


if __name__ == "__main__":
    main()
