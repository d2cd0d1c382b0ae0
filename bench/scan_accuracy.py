"""Measured-surface defaults on seeded synthetic line scans with instrument noise.

Each case draws line scans from a known isotropic self-affine spectrum (Persson's convention),
cuts a non-periodic piece out of a four times longer periodic profile, adds a tilt and white
instrument noise of a given fraction of the surface's h_rms, writes it as one column in
micrometres and analyses it with :func:`fastline.surfaces.analyse_scan` at its defaults. It
prints, per case, the fitted H (with its standard error), q_r, h_rms of the fitted model and
the rms slope of the usable range against the truth, and the usable range's upper end against
the wavenumber where the true spectrum meets the noise.

Beside each case, the Cramer-Rao bounds of H and ln q_r (:func:`bound`): the least standard
deviations any unbiased estimate can reach on that scan, using every Fourier mode up to the
Nyquist wavenumber with the noise level known to be white but not its size; and, summed over
the cases, how many would fall within the targets (H within 0.05, q_r within 25 %) at those
bounds, beside how many did.

Run: ``python -m bench.scan_accuracy`` (``--profiles 8`` for eight parallel scans per case,
``--coverage 50`` for the coverage of +-2 standard errors over 50 seeded repeats, ``--modes 64``
for a roll-off 64 Fourier modes of the scan up instead of 16).
"""

from __future__ import annotations

import argparse
import math
import os
import tempfile
import warnings

import numpy as np

import fastline as fl
from fastline.surfaces import analyse_scan

#: (H, q_r given, noise as a fraction of h_rms, dx in m, points)
CASES = [
    (H, roll, noise, dx, n)
    for H in (0.3, 0.5, 0.8, 1.0)
    for roll in (True, False)
    for noise, dx, n in ((0.003, 1e-6, 8192), (0.01, 2e-7, 16384), (0.03, 5e-8, 4096))
]


def c1d_self_affine(psd: fl.SelfAffinePSD, k: np.ndarray) -> np.ndarray:
    """Two-sided 1D spectrum (m^3) of a self-affine isotropic spectrum, the forward Abel
    transform ``C1D = 2 int_k^q1 C(q) q / sqrt(q^2 - k^2) dq`` evaluated in closed form."""
    from scipy.special import beta, betainc

    C0, H, q0, qr, q1 = psd.C0, psd.hurst, psd.q0, psd.qr, psd.q1
    a, b = np.maximum(q0, k), np.maximum(qr, k)
    flat = 2.0 * C0 * (np.sqrt(np.maximum(b * b - k * k, 0.0)) - np.sqrt(a * a - k * k))
    al = H + 0.5
    inc = lambda x: betainc(al, 0.5, x) * beta(al, 0.5)  # noqa: E731
    power = (
        C0
        * qr ** (2 + 2 * H)
        * k ** (-1 - 2 * H)
        * (inc((k / b) ** 2) - inc(np.minimum(k / q1, 1.0) ** 2))
    )
    return np.where(k < q1, flat + power, 0.0)


#: the roll-off lies this many Fourier modes of the scan up (``--modes``)
ROLLOFF_MODES = {"modes": 16.0}


def truth(H: float, roll: bool, dx: float, n: int) -> fl.SelfAffinePSD:
    """The surface: 1 um rms over [2 pi / (4 L), 100 x Nyquist], q_r ROLLOFF_MODES modes up
    (16 by default, or none)."""
    L = n * dx
    q0 = 2.0 * math.pi / (4.0 * L)
    qr = ROLLOFF_MODES["modes"] * 2.0 * math.pi / L if roll else q0
    return fl.SelfAffinePSD(1e-6, H, q0, qr, 100.0 * math.pi / dx)


def scans(psd, dx: float, n: int, count: int, noise: float, seed: int):
    """(noisy scans (count, n) in m, noise-free ones): pieces of periodic profiles 4 n long,
    tilted, with white noise of rms ``noise`` times the rms of the detrended noise-free scans
    (the roughness the instrument sees)."""
    N = 4 * n
    m = np.arange(N // 2 + 1)
    k = 2.0 * math.pi * np.maximum(m, 1) / (N * dx)
    power = np.where(m > 0, 2.0 * math.pi * N * dx * c1d_self_affine(psd, k) / (dx * dx), 0.0)
    rng = np.random.default_rng(seed)
    z = rng.standard_normal((count, m.size)) + 1j * rng.standard_normal((count, m.size))
    z[:, -1] = z[:, -1].real * math.sqrt(2.0)
    h = np.fft.irfft(z * np.sqrt(0.5 * power), N, axis=-1)[:, :n]
    t = np.arange(n) * dx
    slope, offset = np.polyfit(t, h.T, 1)
    rms = math.sqrt(float(np.mean((h - slope[:, None] * t - offset[:, None]) ** 2)))
    h = h + 3e-4 * t
    return h + noise * rms * rng.standard_normal(h.shape), h


def bound(psd: fl.SelfAffinePSD, roll: bool, dx: float, n: int, profiles: int, sigma: float):
    """(sigma_H, sigma_ln_qr): the Cramer-Rao bounds for ``profiles`` Hann-windowed scans of n
    points (dx in m) of the surface ``psd`` with white noise of rms ``sigma`` (m). The Fisher
    information of the Whittle likelihood, ``sum_k (d ln S / d theta)(d ln S / d theta)^T``
    over the modes ``k = 2 pi j / (n dx)``, ``j = 1 .. n/2``, each counted as 18/35 of an
    independent value (Hann), with ``S = C1D(k) + sigma^2 dx / (2 pi)`` and theta the scale,
    H, ln q_r (with a roll-off) and the noise level (NaN for ln q_r without a roll-off)."""
    k = 2.0 * math.pi * np.arange(1, n // 2 + 1) / (n * dx)
    floor = sigma**2 * dx / (2.0 * math.pi)

    def ln_s(theta):
        scale, H, xr, noise = theta
        qr = math.exp(xr) if roll else psd.q0
        c1d = c1d_self_affine(fl.SelfAffinePSD(psd.h_rms, H, psd.q0, qr, psd.q1), k)
        return np.log(math.exp(scale) * c1d + math.exp(noise) * floor)

    theta = np.array([0.0, psd.hurst, math.log(psd.qr), 0.0])
    free = [0, 1, 3] + ([2] if roll else [])
    step = 1e-5
    # central differences, one-sided below H = 1 (the model's bound)
    centre = theta - np.eye(4)[1] * step if psd.hurst + step > 1.0 else theta
    J = np.column_stack(
        [(ln_s(centre + d) - ln_s(centre - d)) / (2.0 * step) for d in np.eye(4)[free] * step]
    )
    cov = np.linalg.inv(J.T @ J * profiles * 18.0 / 35.0)
    return math.sqrt(cov[1, 1]), math.sqrt(cov[3, 3]) if roll else math.nan


def _band(psd: fl.SelfAffinePSD, lo: float, hi: float) -> fl.TabulatedPSD:
    """The true spectrum restricted to the usable range [lo, hi] (1/m), densely tabulated."""
    q = np.geomspace(lo, hi, 4000)
    return fl.TabulatedPSD(q, psd(q))


def analyse(case, seed: int, profiles: int = 1, folder: str | None = None) -> dict:
    """One case, one seed: analyse_scan of the noisy scans (written in um) at its defaults."""
    H, roll, noise, dx, n = case
    psd = truth(H, roll, dx, n)
    h, clean = scans(psd, dx, n, profiles, noise, seed)
    folder = folder or tempfile.mkdtemp()
    path = os.path.join(folder, f"scan{seed}.npy")
    np.save(path, (h[0] if profiles == 1 else h) / 1e-6)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", fl.topography.TopographyWarning)
        scan = analyse_scan(path, dx=dx, unit="um")
        f, (lo, hi) = scan.fit, scan.q_range
        np.save(path, (clean[0] if profiles == 1 else clean) / 1e-6)
        ref = analyse_scan(path, dx=dx, unit="um", q_range=(lo, hi))  # the same without noise
    band = _band(psd, lo, hi)
    crb_H, crb_qr = bound(psd, roll, dx, n, profiles, float(np.std(h - clean)))
    return {
        "crb_H": crb_H,
        "crb_qr": crb_qr,
        "h_rms_vs_clean": f.h_rms / ref.fit.h_rms,
        "slope_vs_clean": scan.measured.rms_slope / ref.measured.rms_slope,
        "data_h_rms_vs_clean": scan.spectrum.h_rms / ref.spectrum.h_rms,
        "H": f.hurst,
        "H_err": f.hurst_err,
        "H_bound": f.hurst_at_bound,
        "qr": f.qr / psd.qr if roll else math.nan,
        "qr_unresolved": f.qr_at_bound,
        "qr_uncertain": f.qr_uncertain,
        "qr_interval": (f.qr_interval[0] / psd.qr, f.qr_interval[1] / psd.qr),
        "h_rms": f.h_rms / band.h_rms,
        "slope": scan.measured.rms_slope / band.rms_slope,
        "hi": hi,
        "rule": scan.limits["high"],
        "meets": _meets_noise(psd, dx, float(np.std(h - clean))),
    }


def _meets_noise(psd, dx: float, sigma: float) -> float:
    """The wavenumber (1/m) where the true C1D meets the white-noise level of rms sigma (m;
    nan: it does not)."""
    k = np.geomspace(psd.qr * 1.01, math.pi / dx, 400)
    level = sigma**2 * dx / (2.0 * math.pi)
    below = np.flatnonzero(c1d_self_affine(psd, k) < level)
    return float(k[below[0]]) if below.size else math.nan


def table(profiles: int) -> list[dict]:
    """Every case once (seed = its index): the rows of the printed table."""
    rows = []
    for i, case in enumerate(CASES):
        r = analyse(case, seed=i, profiles=profiles)
        rows.append({"case": case, **r})
    return rows


def coverage(case, repeats: int, profiles: int = 1) -> tuple[float, float, float, float]:
    """(share of repeats with |H - H_true| <= 2 H_err, mean H, std of H, share whose q_r
    interval holds the truth (NaN without roll-off)) over seeded repeats (an H held at its
    bound 1 counts when the truth is 1)."""
    inside, hs, qr_inside = [], [], []
    folder = tempfile.mkdtemp()
    for seed in range(repeats):
        r = analyse(case, seed=1000 + seed, profiles=profiles, folder=folder)
        hs.append(r["H"])
        exact = r["H_bound"] and abs(r["H"] - case[0]) < 1e-9
        inside.append(exact or abs(r["H"] - case[0]) <= 2.0 * r["H_err"])
        lo, hi = r["qr_interval"]
        qr_inside.append(lo <= 1.0 + 1e-9 and 1.0 - 1e-9 <= hi)
    qr_share = float(np.mean(qr_inside)) if case[1] else math.nan
    return float(np.mean(inside)), float(np.mean(hs)), float(np.std(hs, ddof=1)), qr_share


def figure(path: str) -> None:
    """docs/img/noisy_scan_psd.png: one profile (H 0.8, a roll-off, 1 % noise) analysed at the
    defaults, its spectrum with the noise floor found and the range cut below it."""
    case = (0.8, True, 0.01, 2e-7, 16384)
    H, roll, noise, dx, n = case
    h, _ = scans(truth(H, roll, dx, n), dx, n, 1, noise, seed=13)
    folder = tempfile.mkdtemp()
    path_scan = os.path.join(folder, "noisy_scan.npy")
    np.save(path_scan, h[0] / 1e-6)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", fl.topography.TopographyWarning)
        scan = analyse_scan(path_scan, dx=dx, unit="um")
    print(scan.summary())
    fl.plotting.plot_measured_psd(scan).savefig(path, dpi=110)


def _qr_text(r: dict) -> str:
    """q_r against the truth with its interval, and what the fit said of it."""
    said = "unresolved" if r["qr_unresolved"] else "uncertain" if r["qr_uncertain"] else "measured"
    if not r["case"][1]:
        return f"{'none':<21}{said if r['qr_unresolved'] else 'FITTED':<9}"
    lo, hi = r["qr_interval"]
    return f"{r['qr']:4.2f} [{lo:4.2f}, {hi:5.2f}]{'':5}{said:<9}"


def _row(r: dict) -> str:
    H, roll, noise, dx, n = r["case"]
    z = abs(r["H"] - H) / r["H_err"] if r["H_err"] > 0 else 0.0
    return (
        f"{H:<4} {'yes' if roll else 'no':<4} {noise:<5.1%}  {dx:<7.0e} {n:<6d} | "
        f"{r['H']:.3f} +- {r['H_err']:.3f} {z:4.1f} | {_qr_text(r)} | {r['h_rms']:5.3f} "
        f"{r['slope']:5.3f}         | {r['h_rms_vs_clean']:5.3f} {r['slope_vs_clean']:5.3f}  | "
        f"{r['hi']:9.3g} {r['rule']:<17} | {r['meets']:<8.3g} | {r['crb_H']:.3f} "
        f"{r['crb_qr']:.3f}"
    )


def _qr_counts(rows: list[dict]) -> None:
    """The roll-off cases in counts: within 25 %, interval covering the truth, said uncertain
    or unresolved, and confident but wrong (neither said, yet off by more than 25 %)."""
    roll = [r for r in rows if r["case"][1]]
    within = sum(abs(r["qr"] - 1.0) <= 0.25 for r in roll)
    covers = sum(
        r["qr_interval"][0] <= 1.0 + 1e-9 and 1.0 - 1e-9 <= r["qr_interval"][1] for r in roll
    )
    said = sum(r["qr_uncertain"] for r in roll)
    wrong = sum(abs(r["qr"] - 1.0) > 0.25 and not r["qr_uncertain"] for r in roll)
    print(
        f"q_r, {len(roll)} roll-off cases: within 25 % {within}; interval covers the truth "
        f"{covers}; said uncertain or unresolved {said}; confident and off by > 25 % {wrong}"
    )


def _bound_counts(rows: list[dict]) -> None:
    """Cases within the targets against the number expected at the Cramer-Rao bounds (each
    estimate Gaussian about the truth with the bound's deviation)."""
    H_in = sum(abs(r["H"] - r["case"][0]) <= 0.05 for r in rows)
    H_expected = sum(math.erf(0.05 / (r["crb_H"] * math.sqrt(2.0))) for r in rows)
    roll = [r for r in rows if r["case"][1]]
    qr_in = sum(abs(r["qr"] - 1.0) <= 0.25 for r in roll)

    def within_25(s):
        cdf = lambda x: 0.5 * (1.0 + math.erf(x / (s * math.sqrt(2.0))))  # noqa: E731
        return cdf(math.log(1.25)) - cdf(math.log(0.75))

    qr_expected = sum(within_25(r["crb_qr"]) for r in roll)
    print(
        f"at the Cramer-Rao bounds: H within 0.05 expected in {H_expected:.1f} of {len(rows)} "
        f"(measured {H_in}); q_r within 25 % expected in {qr_expected:.1f} of {len(roll)} "
        f"(measured {qr_in})"
    )


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--profiles", type=int, default=1, help="parallel scans per case")
    parser.add_argument("--coverage", type=int, default=0, help="repeats for the coverage")
    parser.add_argument("--figure", metavar="PNG", help="only draw the docs' noisy-scan figure")
    parser.add_argument("--modes", type=float, default=16.0, help="roll-off: Fourier modes up")
    args = parser.parse_args(argv)
    ROLLOFF_MODES["modes"] = args.modes
    if args.figure:
        figure(args.figure)
        return
    print(
        "H    q_r  noise  dx      N      | H fit (+-err)    |z| | q_r/true [interval]  said     "
        "| h_rms, slope / true | / noise-free | top of range (1/m), rule    | C1D meets "
        "noise | CRB H, ln q_r"
    )
    rows = table(args.profiles)
    for r in rows:
        print(_row(r))
    _qr_counts(rows)
    _bound_counts(rows)
    if args.coverage:
        for case in ((0.8, True, 0.01, 1e-6, 4096), (0.5, False, 0.03, 1e-6, 4096)):
            share, mean, std, qr_share = coverage(case, args.coverage, args.profiles)
            print(
                f"coverage {case}: {share:.0%} of {args.coverage} within +-2 errors; "
                f"H {mean:.3f} +- {std:.3f} (scatter); q_r interval holds the truth in "
                f"{qr_share:.0%}"
            )


if __name__ == "__main__":
    main()
