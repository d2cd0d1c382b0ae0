"""Tables of docs/accuracy.md: ``python -m bench.accuracy`` (about two minutes on 2 cores).

1. observed convergence orders of each measure (paper surfaces, alpha 1e-3..1e3, n >= 256);
2. the estimate of ``accuracy=`` against the true error (reference: n = 32768, tol 1e-11 on
   the default domain), per surface, accuracies 1e-2, 1e-4, 1e-6; and its range over the
   paper's surfaces and campaign-like scenes at accuracies 1e-2..1e-6 (reference n = 65536);
3. the cost of ``accuracy=1e-4`` against the default n = 1024: convolutions, FFT work (cells x
   convolutions) and warm wall time (best of interleaved calls, same run);
4. the needle-shaped scene of docs/accuracy.md (the peak spans 2.8 cells at n = 256).

Counts are exact on any machine; times are not (the ratio of interleaved calls is the figure).
"""

from __future__ import annotations

import math
import statistics
import time
import warnings

import fastline as fl
from bench.conftest import E_STAR, RADIUS, load_for_alpha, surfaces
from fastline.contact import resolution

ALPHAS = (1e-3, 1e-2, 0.1, 1.0, 10.0, 100.0, 1e3)
ORDER_NS = (256, 512, 1024, 2048, 4096)
REF_N = 32768
NEEDLE = (
    fl.SelfAffinePSD(
        4.0219591928945736e-08, 1.0, 232.4997741925926, 232.4997741925926, 71888266.82459533
    ),
    402830.3189795967,
    0.002352259458219232,
    0.00015701517536695204,
)


def observed_orders() -> dict[str, list[float]]:
    """log2 of the ratio of successive differences, per measure, over every scene and n."""
    out: dict[str, list[float]] = {k: [] for k in ("p0", "p0_hi", "s", "fwhm", "fwhm_hi")}
    for psd in surfaces():
        for alpha in ALPHAS:
            load = load_for_alpha(alpha, psd.h_rms)
            half = fl.LineContact(psd, E_STAR, RADIUS)._grid(load).half_width
            runs = [
                fl.solve_line_contact(
                    psd, E_STAR, RADIUS, load, n=n, half_width=half, tol=1e-11, warn=False
                )
                for n in ORDER_NS
            ]
            vals = {
                "p0": [r.p0 for r in runs],
                "p0_hi": [resolution.peak_quartic(r.pressure) for r in runs],
                "s": [r.s for r in runs],
                "fwhm": [r.fwhm for r in runs],
                "fwhm_hi": [
                    resolution.fwhm_cubic(r.pressure, r.dx, resolution.peak_quartic(r.pressure))
                    for r in runs
                ],
            }
            for key, v in vals.items():
                for a, b, c in zip(v, v[1:], v[2:], strict=False):
                    # differences below 1e-9 relative are round-off, not discretisation
                    if abs(b - c) > 1e-9 * abs(c) and abs(a - b) > 1e-9 * abs(c):
                        out[key].append(math.log2(abs((a - b) / (b - c))))
    return out


def estimate_table(psd, accuracies=(1e-2, 1e-4, 1e-6)):
    rows = []
    for alpha in ALPHAS:
        load = load_for_alpha(alpha, psd.h_rms)
        ref = fl.LineContact(psd, E_STAR, RADIUS, n=REF_N, tol=1e-11, warn=False).solve(load)
        for acc in accuracies:
            res = fl.LineContact(psd, E_STAR, RADIUS, accuracy=acc, warn=False).solve(load)
            e = res.error_estimate
            true = {q: abs(getattr(res, q) / getattr(ref, q) - 1.0) for q in ("p0", "s")}
            true["w_over_s"] = abs(res.w_over_s / ref.w_over_s - 1.0)
            rows.append((alpha, acc, e, true))
    return rows


def campaign_scenes():
    """The paper's surfaces at alpha 1e-3..1e3, O-rings and low-H, wide-band scenes."""
    out = {}
    for k, psd in enumerate(surfaces()):
        for alpha in ALPHAS:
            out[f"surface {k + 1}, alpha {alpha:g}"] = (
                psd,
                E_STAR,
                RADIUS,
                load_for_alpha(alpha, psd.h_rms),
            )
    o_ring = fl.SelfAffinePSD(0.3e-6, 0.85, q0=5e4, qr=5e5, q1=1e9)
    e_o_ring = fl.effective_modulus(10e6, 0.5, 210e9, 0.3)
    for load in (10.0, 100.0, 1000.0):
        out[f"O-ring {load:g} N/m"] = (o_ring, e_o_ring, 1.5e-3, load)
    low_h = fl.SelfAffinePSD(10e-6, 0.3, 1e3, 1e3, 1e9)
    for alpha in (3.0, 300.0):
        out[f"low H, alpha {alpha:g}"] = (
            low_h,
            E_STAR,
            RADIUS,
            math.pi / 4 * low_h.h_rms * E_STAR / alpha,
        )
    return out


def summary(accuracies=(1e-2, 1e-3, 1e-4, 1e-5, 1e-6)):
    """Range of estimate / true error (errors above 1 % of the accuracy and 3e-8, the
    reference's own) and the largest true error / accuracy, over every scene and accuracy."""
    ratios, worst = [], 0.0
    for psd, E, R, load in campaign_scenes().values():
        half = fl.LineContact(psd, E, R)._grid(load).half_width
        ref = fl.LineContact(psd, E, R, n=65536, half_width=1.25 * half, tol=1e-11, warn=False)
        ref = ref.solve(load)
        for acc in accuracies:
            res = fl.LineContact(psd, E, R, accuracy=acc, warn=False).solve(load)
            for q in ("p0", "s", "w_over_s"):
                true = abs(getattr(res, q) / getattr(ref, q) - 1.0)
                worst = max(worst, true / acc)
                if true > max(1e-2 * acc, 3e-8):
                    ratios.append(getattr(res.error_estimate, q) / true)
    return min(ratios), max(ratios), len(ratios), worst


def best_interleaved(fa, fb, repeat=40):
    fa(), fb()
    ta = tb = math.inf
    for _ in range(repeat):
        t = time.perf_counter()
        fa()
        ta = min(ta, time.perf_counter() - t)
        t = time.perf_counter()
        fb()
        tb = min(tb, time.perf_counter() - t)
    return ta, tb


def cost_table(psd, accuracy=1e-4):
    default = fl.LineContact(psd, E_STAR, RADIUS, warn=False)
    accurate = fl.LineContact(psd, E_STAR, RADIUS, accuracy=accuracy, warn=False)
    rows = []
    for alpha in ALPHAS:
        load = load_for_alpha(alpha, psd.h_rms)
        rd, ra = default.solve(load), accurate.solve(load)
        td, ta = best_interleaved(
            lambda load=load: default.solve(load), lambda load=load: accurate.solve(load)
        )
        rows.append((alpha, rd, ra, td, ta))
    return rows


def main():
    warnings.simplefilter("ignore")
    print("## Observed orders (log2 of successive difference ratios, n = 256..4096)\n")
    print("| measure | triples | median | 10-90 % range | min..max |")
    print("|---|---|---|---|---|")
    names = {
        "p0": "p0, parabola (reported)",
        "p0_hi": "p0, quartic",
        "s": "s, cell-exact (reported)",
        "fwhm": "FWHM, linear crossings (reported)",
        "fwhm_hi": "FWHM, cubic crossings",
    }
    for key, vals in observed_orders().items():
        vals = sorted(vals)
        q10, q90 = vals[len(vals) // 10], vals[(9 * len(vals)) // 10]
        print(
            f"| {names[key]} | {len(vals)} | {statistics.median(vals):.2f} | "
            f"{q10:.2f}..{q90:.2f} | {vals[0]:.2f}..{vals[-1]:.2f} |"
        )

    for k, psd in enumerate(surfaces()):
        print(f"\n## Estimate vs true error, surface {k + 1} (reference n = {REF_N})\n")
        print("| alpha | accuracy | n | p0 est / true | s est / true | w/s est / true |")
        print("|---|---|---|---|---|---|")
        for alpha, acc, e, true in estimate_table(psd):
            cells = " | ".join(
                f"{getattr(e, q):.1e} / {true[q]:.1e}" for q in ("p0", "s", "w_over_s")
            )
            print(f"| {alpha:g} | {acc:g} | {e.n} | {cells} |")

    lo, hi, count, worst = summary()
    print(
        f"\nAll scenes, accuracy 1e-2..1e-6: estimate / true error {lo:.2f}..{hi:.2f} over "
        f"{count} comparisons; largest true error / accuracy {worst:.2f}"
    )

    for k, psd in enumerate(surfaces()):
        print(f"\n## Cost of accuracy=1e-4 against n = 1024, surface {k + 1}\n")
        print(
            "| alpha | n=1024: conv. | accuracy=1e-4: grids (cells/conv.) | conv. | "
            "FFT work ratio | time n=1024 | time accuracy | time ratio |"
        )
        print("|---|---|---|---|---|---|---|---|")
        for alpha, rd, ra, td, ta in cost_table(psd):
            e = ra.error_estimate
            grids = ", ".join(f"{n}/{c}" for n, c, _ in e.levels)
            work = e.fft_work / (1024 * rd.convolutions)
            print(
                f"| {alpha:g} | {rd.convolutions} | {grids} | {ra.convolutions} | {work:.2f} | "
                f"{td * 1e3:.2f} ms | {ta * 1e3:.2f} ms | {ta / td:.2f} |"
            )

    print("\n## Needle-shaped scene\n")
    psd, E, R, f = NEEDLE
    ref = fl.LineContact(psd, E, R, n=131072, tol=1e-11, warn=False).solve(f)
    lc = fl.LineContact(psd, E, R, n=256, warn=False)
    res = lc.solve(f)
    est = lc.estimate_error(res)
    print(
        f"- n = 256: p0 off by {abs(res.p0 / ref.p0 - 1):.2%}, estimate {est.p0:.2%} "
        f"(companion n = {est.companion_n}, FWHM over {est.fwhm_cells:.2g} cells)"
    )
    for acc in (1e-2, 1e-3, 1e-4):
        r = fl.solve_line_contact(psd, E, R, f, accuracy=acc, warn=False)
        e = r.error_estimate
        true = max(abs(getattr(r, q) / getattr(ref, q) - 1.0) for q in ("p0", "s", "w_over_s"))
        grids = ", ".join(str(n) for n, _, _ in e.levels)
        print(
            f"- accuracy = {acc:g}: n = {e.n} (grids {grids}), largest true error {true:.1e}, "
            f"estimate {e.worst:.1e}"
        )


if __name__ == "__main__":
    main()
