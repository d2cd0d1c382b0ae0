"""Command-line interface: ``fastline paper | profile | sweep`` (also ``python -m fastline``).

SI units throughout: lengths in m, wavenumbers in 1/m, spectra C(q) in m^4, pressures and
moduli in Pa, loads per unit cylinder length in N/m.
"""

from __future__ import annotations

import argparse
import math
import os
import sys
import time
import warnings

import numpy as np

PAPER_E_STAR = 1.33e9  # Pa
PAPER_RADIUS = 0.01  # m
PAPER_FIG3_LOAD = 1e4  # N/m
PAPER_LOADS = (1e3, 1.5e6)  # N/m
PAPER_Q0, PAPER_QR = 1e3, 1e4  # 1/m
#: (label, h_rms [m], Hurst exponent) of the paper's three surfaces
PAPER_SURFACES = (
    ("surface 1", 10e-6, 0.8),
    ("surface 2", 10e-6, 1.0),
    ("surface 3", 1e-6, 0.8),
)

DESCRIPTION = """\
fastline: nominal contact pressure of a rigid cylinder (radius R) pressed onto a randomly rough
elastic half-space, from Persson's contact theory (Tiwari & Persson, "Cylinder-flat contact
mechanics with surface roughness"). The roughness enters through its power spectrum C(q); the
result is the pressure profile p(x) across the contact line, its peak p0, width (standard
deviation s, full width at half maximum w) and how far it is from the smooth Hertz solution,
measured by alpha = h_rms / delta (delta = 4 f_N / (pi E*), the Hertz penetration).

SI units everywhere: m, 1/m, m^4, Pa, N/m (load per unit cylinder length)."""

EPILOG = """\
examples:
  fastline profile --h-rms 10e-6 --hurst 0.8 --load 1e4 --csv p.csv --plot p.png
  fastline profile --psd measured.txt --E1 2.1e11 --nu1 0.3 --E2 5e6 --nu2 0.49 --load 500
  fastline sweep --h-rms 1e-6 --loads-from 1e3 --loads-to 1e6 --loads-num 30 --csv sweep.csv
  fastline paper --out figs/"""


class CLIError(Exception):
    """A user error: reported as one line on stderr, exit status 2."""


class _Parser(argparse.ArgumentParser):
    """argparse that reports errors as a single line (no usage dump), exit status 2."""

    def error(self, message):  # noqa: D102
        raise CLIError(message)


# ----------------------------------------------------------------------------------------------
# option types
# ----------------------------------------------------------------------------------------------
def _number(text: str) -> float:
    try:
        v = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"not a number: {text!r}") from None
    if not math.isfinite(v):
        raise argparse.ArgumentTypeError(f"must be a finite number, got {text!r}")
    return v


def _positive(text: str) -> float:
    v = _number(text)
    if v <= 0.0:
        raise argparse.ArgumentTypeError(f"must be > 0, got {text!r}")
    return v


def _count(text: str) -> int:
    try:
        v = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"not an integer: {text!r}") from None
    if v < 1:
        raise argparse.ArgumentTypeError(f"must be >= 1, got {text!r}")
    return v


# ----------------------------------------------------------------------------------------------
# parser
# ----------------------------------------------------------------------------------------------
def _scene_options(parser: argparse.ArgumentParser, load: bool) -> None:
    g = parser.add_argument_group(
        "roughness spectrum",
        "Self-affine spectrum with roll-off: C(q) = C0 for q0 <= q < qr, C0 (q/qr)^(-2(1+H)) for "
        "qr <= q <= q1, normalised so that h_rms^2 = 2 pi int q C(q) dq (Persson's isotropic "
        "convention). Use the combined spectrum of both surfaces (C = C1 + C2). Defaults: the "
        "paper's surface 1.",
    )
    g.add_argument(
        "--h-rms",
        type=_positive,
        default=10e-6,
        metavar="M",
        help="rms roughness amplitude h_rms [m] (default 10e-6)",
    )
    g.add_argument(
        "--hurst",
        type=_number,
        default=0.8,
        metavar="H",
        help="Hurst exponent H [-], 0 < H <= 1 (default 0.8)",
    )
    g.add_argument(
        "--q0",
        type=_positive,
        default=PAPER_Q0,
        metavar="1/M",
        help="smallest wavenumber q0 [1/m] (default 1e3)",
    )
    g.add_argument(
        "--qr",
        type=_positive,
        default=PAPER_QR,
        metavar="1/M",
        help="roll-off wavenumber qr [1/m] (default 1e4)",
    )
    g.add_argument(
        "--q1",
        type=_positive,
        default=1e9,
        metavar="1/M",
        help="large-wavenumber cut-off q1 [1/m] (default 1e9)",
    )
    g.add_argument(
        "--psd",
        metavar="FILE",
        help="measured isotropic spectrum instead: two columns q [1/m] and C(q) "
        "[m^4], whitespace- or comma-separated, '#' starts a comment",
    )
    m = parser.add_argument_group(
        "material and geometry",
        "Give the effective modulus directly or the two solids' elastic constants "
        "(1/E* = (1-nu1^2)/E1 + (1-nu2^2)/E2).",
    )
    m.add_argument(
        "--E-star",
        type=_positive,
        metavar="PA",
        help="effective (plane-strain) modulus E* [Pa] (default 1.33e9 when no "
        "--E1/--nu1/--E2/--nu2 are given)",
    )
    m.add_argument("--E1", type=_positive, metavar="PA", help="Young's modulus of solid 1 [Pa]")
    m.add_argument("--nu1", type=_number, metavar="NU", help="Poisson ratio of solid 1 [-]")
    m.add_argument("--E2", type=_positive, metavar="PA", help="Young's modulus of solid 2 [Pa]")
    m.add_argument("--nu2", type=_number, metavar="NU", help="Poisson ratio of solid 2 [-]")
    m.add_argument(
        "--radius",
        type=_positive,
        default=PAPER_RADIUS,
        metavar="M",
        help="cylinder radius R [m] (default 0.01)",
    )
    if load:
        m.add_argument(
            "--load",
            type=_positive,
            default=PAPER_FIG3_LOAD,
            metavar="N/M",
            help="normal load per unit cylinder length f_N [N/m] (default 1e4)",
        )
    s = parser.add_argument_group("model and numerics")
    s.add_argument(
        "--model",
        choices=("persson", "exponential", "hertz"),
        default="persson",
        help="pressure-separation law: full Persson theory (default), its "
        "exponential approximation p = beta E* exp(-u/u0), or smooth Hertz "
        "contact",
    )
    s.add_argument(
        "--n",
        type=_count,
        default=1024,
        metavar="N",
        help="grid points across the contact (default 1024, at least 16)",
    )
    s.add_argument(
        "--hardness",
        type=_positive,
        metavar="PA",
        help="indentation hardness of the softer solid [Pa]: warns when the elastic "
        "mean asperity pressure h' E*/2 exceeds it (plastic flow likely)",
    )


def build_parser() -> argparse.ArgumentParser:
    fmt = argparse.RawDescriptionHelpFormatter
    parser = _Parser(prog="fastline", description=DESCRIPTION, epilog=EPILOG, formatter_class=fmt)
    from fastline import __version__

    parser.add_argument("--version", action="version", version=f"fastline {__version__}")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND")

    p = sub.add_parser(
        "paper",
        help="reproduce the paper's Figs. 2-5 (PNG + CSV each)",
        formatter_class=fmt,
        description="Reproduce Figs. 2-5 of Tiwari & Persson: C(q) of surfaces 1-3 (fig2_psd), "
        "p(x) rough vs Hertz at f_N = 1e4 N/m (fig3_profile), w/s vs log10 alpha (fig4_ws) and "
        "p0(rough)/p0(Hertz) vs log10 alpha with the Gaussian asymptote, eq. 14 (fig5_p0ratio). "
        "E* = 1.33 GPa, R = 1 cm, q0 = 1e3 1/m, qr = 1e4 1/m.",
    )
    p.add_argument("--out", required=True, metavar="DIR", help="output directory (created)")
    p.add_argument(
        "--loads",
        type=_count,
        default=40,
        metavar="N",
        help="loads per surface, log-spaced from 1e3 to 1.5e6 N/m (default 40)",
    )
    p.add_argument(
        "--q1",
        type=_positive,
        default=1e9,
        metavar="1/M",
        help="large-wavenumber cut-off q1 [1/m] (the paper does not state it; default 1e9)",
    )
    p.add_argument(
        "--n",
        type=_count,
        default=1024,
        metavar="N",
        help="grid points across the contact (default 1024)",
    )

    p = sub.add_parser(
        "profile",
        help="solve one scene: p(x), p0, widths, regime, diagnostics",
        formatter_class=fmt,
        description="Solve one cylinder-on-flat scene and print the peak pressure, widths, "
        "alpha, regime, validity diagnostics and solver convergence.",
    )
    _scene_options(p, load=True)
    p.add_argument("--csv", metavar="FILE", help="write x [m], p [Pa], u [m] columns to FILE")
    p.add_argument("--plot", metavar="FILE", help="write a PNG of p(x) with Hertz to FILE")

    p = sub.add_parser(
        "sweep",
        help="solve a log-spaced series of loads",
        formatter_class=fmt,
        description="Solve the scene for log-spaced loads and tabulate alpha, p0, p0 ratio, "
        "s, w and w/s.",
    )
    _scene_options(p, load=False)
    p.add_argument(
        "--loads-from",
        type=_positive,
        default=1e3,
        metavar="N/M",
        help="smallest load per unit length [N/m] (default 1e3)",
    )
    p.add_argument(
        "--loads-to",
        type=_positive,
        default=1.5e6,
        metavar="N/M",
        help="largest load per unit length [N/m] (default 1.5e6)",
    )
    p.add_argument(
        "--loads-num", type=_count, default=20, metavar="N", help="number of loads (default 20)"
    )
    p.add_argument(
        "--csv",
        metavar="FILE",
        help="write the table (load [N/m], alpha, p0 [Pa], p0_ratio, s [m], w [m], "
        "w_over_s, converged) to FILE",
    )
    p.add_argument("--plot", metavar="FILE", help="write a PNG of w/s and p0 ratio vs alpha")
    return parser


# ----------------------------------------------------------------------------------------------
# helpers
# ----------------------------------------------------------------------------------------------
def _pyplot():
    try:
        import matplotlib
    except ImportError:
        raise CLIError("plotting needs matplotlib: pip install fastline[plot]") from None
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt


def read_psd_file(path: str):
    """Read a two-column spectrum file (q [1/m], C [m^4]) into a TabulatedPSD."""
    import fastline as fl

    rows = []
    try:
        with open(path, encoding="utf-8") as fh:
            for k, line in enumerate(fh, 1):
                line = line.split("#", 1)[0].replace(",", " ").strip()
                if not line:
                    continue
                parts = line.split()
                if len(parts) != 2:
                    raise CLIError(f"{path}:{k}: expected two columns q [1/m] and C [m^4]")
                try:
                    rows.append((float(parts[0]), float(parts[1])))
                except ValueError:
                    raise CLIError(f"{path}:{k}: not a number in {line!r}") from None
    except OSError as e:
        raise CLIError(f"cannot read spectrum file {path}: {e.strerror}") from None
    if len(rows) < 2:
        raise CLIError(f"{path}: need at least two (q, C) rows")
    q, C = np.array(rows).T
    return fl.TabulatedPSD(q, C)


def _scene(args):
    """(psd, E_star) from the scene options."""
    import fastline as fl

    elastic = [args.E1, args.nu1, args.E2, args.nu2]
    if any(v is not None for v in elastic):
        if args.E_star is not None:
            raise CLIError("give either --E-star or --E1/--nu1/--E2/--nu2, not both")
        if any(v is None for v in elastic):
            raise CLIError("--E1, --nu1, --E2 and --nu2 must be given together")
        E_star = fl.effective_modulus(args.E1, args.nu1, args.E2, args.nu2)
    else:
        E_star = PAPER_E_STAR if args.E_star is None else args.E_star
    if args.psd is not None:
        psd = read_psd_file(args.psd)
    else:
        psd = fl.SelfAffinePSD(args.h_rms, args.hurst, args.q0, args.qr, args.q1)
    return psd, E_star


def _progress(i: int, n: int, label: str = "", width: int = 30) -> None:
    done = int(width * i / n)
    bar = "#" * done + "-" * (width - done)
    sys.stderr.write(f"\r[{bar}] {i}/{n} {label:<12}")
    if i == n:
        sys.stderr.write("\n")
    sys.stderr.flush()


def _write_csv(path: str, header: list[str], rows, comment: str = "") -> None:
    try:
        with open(path, "w", encoding="utf-8") as fh:
            for line in comment.splitlines():
                fh.write(f"# {line}\n")
            fh.write(",".join(header) + "\n")
            for row in rows:
                fh.write(",".join(_fmt(v) for v in row) + "\n")
    except OSError as e:
        raise CLIError(f"cannot write {path}: {e.strerror}") from None


def _fmt(v) -> str:
    if isinstance(v, (bool, np.bool_)):
        return str(int(v))
    if isinstance(v, str):
        return v
    return repr(float(v))


def _save(fig, path: str) -> None:
    try:
        fig.savefig(path, dpi=130)
    except OSError as e:
        raise CLIError(f"cannot write {path}: {e.strerror}") from None


def _solve(psd, E_star, radius, load, theory, model, n):
    from fastline.line_contact import solve_line_contact

    return solve_line_contact(
        psd, E_star, radius, load, model=model, n=n, theory=theory, warn=False
    )


def _theory(psd, E_star, model):
    from fastline.persson import PerssonTheory

    return PerssonTheory(psd, E_star)


def _print_warnings(msgs) -> None:
    for m in msgs:
        print(f"fastline: warning: {m}", file=sys.stderr)


# ----------------------------------------------------------------------------------------------
# commands
# ----------------------------------------------------------------------------------------------
def paper_data(q1: float = 1e9, loads: int = 40, n: int = 1024, progress: bool = True) -> dict:
    """Compute the data behind the paper's Figs. 2-5 (no plotting, no files).

    Returns a dict with ``surfaces`` (list of dicts: label, h_rms [m], hurst, psd, theory,
    gamma_u, rows) where each row is (load [N/m], alpha, p0 [Pa], p0_ratio, s [m], w [m],
    w_over_s, converged), plus ``fig3`` (x [m], p rough [Pa], p Hertz [Pa]) and ``loads``.
    """
    import fastline as fl

    E, R = PAPER_E_STAR, PAPER_RADIUS
    fN = np.logspace(math.log10(PAPER_LOADS[0]), math.log10(PAPER_LOADS[1]), loads)
    surfaces = []
    total, k = len(PAPER_SURFACES) * loads, 0
    for label, h, H in PAPER_SURFACES:
        psd = fl.SelfAffinePSD(h, H, PAPER_Q0, PAPER_QR, q1)
        th = fl.PerssonTheory(psd, E)
        rows = []
        for f in fN:
            r = _solve(psd, E, R, float(f), th, "persson", n)
            rows.append((float(f), r.alpha, r.p0, r.p0_ratio, r.s, r.fwhm, r.w_over_s, r.converged))
            k += 1
            if progress:
                _progress(k, total, label)
        surfaces.append(
            dict(
                label=label,
                h_rms=h,
                hurst=H,
                psd=psd,
                theory=th,
                gamma_u=th.exponential_fit().gamma_u,
                rows=rows,
            )
        )
    s1 = surfaces[0]
    r = _solve(s1["psd"], E, R, PAPER_FIG3_LOAD, s1["theory"], "persson", n)
    hz = fl.hertz_line_contact(E, R, PAPER_FIG3_LOAD)
    fig3 = dict(x=r.x, p=r.pressure, p_hertz=hz.pressure(r.x), result=r, hertz=hz)
    return dict(surfaces=surfaces, fig3=fig3, loads=fN, q1=q1, n=n)


def cmd_paper(args) -> int:
    plt = _pyplot()
    import fastline as fl

    try:
        os.makedirs(args.out, exist_ok=True)
    except OSError as e:
        raise CLIError(f"cannot create {args.out}: {e.strerror}") from None
    t0 = time.perf_counter()
    data = paper_data(q1=args.q1, loads=args.loads, n=args.n, progress=True)
    elapsed = time.perf_counter() - t0
    out = args.out
    surfs = data["surfaces"]
    scene = (
        f"E* = {PAPER_E_STAR:g} Pa, R = {PAPER_RADIUS:g} m, q0 = {PAPER_Q0:g} 1/m, "
        f"qr = {PAPER_QR:g} 1/m, q1 = {args.q1:g} 1/m, n = {args.n}"
    )
    styles = ("C0", "C1", "C2")

    # Fig. 2: spectra
    q = np.logspace(math.log10(PAPER_Q0), math.log10(args.q1), 400)
    Cs = [s["psd"](q) for s in surfs]
    _write_csv(
        os.path.join(out, "fig2_psd.csv"),
        ["q_1_per_m", "C1_m4", "C2_m4", "C3_m4"],
        zip(q, *Cs, strict=True),
        "Fig. 2: C(q) of surfaces 1-3\n" + scene,
    )
    fig, ax = plt.subplots(figsize=(5.5, 4.2))
    for s, C, c in zip(surfs, Cs, styles, strict=True):
        ax.plot(
            np.log10(q),
            np.log10(C),
            color=c,
            label=f"{s['label']}: h_rms = {s['h_rms'] * 1e6:g} µm, H = {s['hurst']:g}",
        )
    ax.set_xlabel("log10 q (1/m)")
    ax.set_ylabel("log10 C(q) (m$^4$)")
    ax.legend(fontsize=8)
    ax.set_title("Fig. 2: surface roughness power spectra", fontsize=10)
    fig.tight_layout()
    _save(fig, os.path.join(out, "fig2_psd.png"))
    plt.close(fig)

    # Fig. 3: profile
    f3 = data["fig3"]
    r3 = f3["result"]
    _write_csv(
        os.path.join(out, "fig3_profile.csv"),
        ["x_m", "p_rough_Pa", "p_hertz_Pa"],
        zip(f3["x"], f3["p"], f3["p_hertz"], strict=True),
        f"Fig. 3: surface 1, f_N = {PAPER_FIG3_LOAD:g} N/m, alpha = {r3.alpha:.6g}\n" + scene,
    )
    fig, ax = plt.subplots(figsize=(5.5, 4.2))
    ax.plot(f3["x"] * 1e3, f3["p"] / 1e6, "-", color="C0", label="rough (surface 1)")
    ax.plot(f3["x"] * 1e3, f3["p_hertz"] / 1e6, "--", color="k", label="Hertz (smooth)")
    lim = 1.3 * max(f3["hertz"].a, 2.5 * r3.s) * 1e3
    ax.set_xlim(-lim, lim)
    ax.set_xlabel("x (mm)")
    ax.set_ylabel("nominal pressure p (MPa)")
    ax.set_title(f"Fig. 3: f_N = {PAPER_FIG3_LOAD:g} N/m, alpha = {r3.alpha:.3g}", fontsize=10)
    ax.legend(fontsize=8)
    fig.tight_layout()
    _save(fig, os.path.join(out, "fig3_profile.png"))
    plt.close(fig)

    # Figs. 4-5: sweeps
    header = [
        "surface",
        "h_rms_m",
        "hurst",
        "load_N_per_m",
        "alpha",
        "log10_alpha",
        "p0_Pa",
        "p0_ratio",
        "s_m",
        "w_m",
        "w_over_s",
        "converged",
        "gamma_u",
        "p0_ratio_eq14",
    ]
    rows = []
    for i, s in enumerate(surfs):
        for f, a, p0, pr, sd, w, ws, ok in s["rows"]:
            eq14 = float(fl.p0_ratio_gaussian(a, s["gamma_u"]))
            rows.append(
                (
                    str(i + 1),
                    s["h_rms"],
                    s["hurst"],
                    f,
                    a,
                    math.log10(a),
                    p0,
                    pr,
                    sd,
                    w,
                    ws,
                    ok,
                    s["gamma_u"],
                    eq14,
                )
            )
    comment = "Figs. 4-5: load sweeps 1e3..1.5e6 N/m (log-spaced)\n" + scene
    _write_csv(os.path.join(out, "fig4_ws.csv"), header, rows, comment)
    _write_csv(os.path.join(out, "fig5_p0ratio.csv"), header, rows, comment)

    fig, ax = plt.subplots(figsize=(5.5, 4.2))
    for s, c in zip(surfs, styles, strict=True):
        a = np.array([r[1] for r in s["rows"]])
        ax.plot(np.log10(a), [r[6] for r in s["rows"]], "o-", ms=3, color=c, label=s["label"])
    ax.axhline(fl.WS_HERTZ, ls="--", color="k", lw=1)
    ax.axhline(fl.WS_GAUSSIAN, ls=":", color="k", lw=1)
    ax.set_ylim(2.25, 3.55)
    xl = ax.get_xlim()
    xm = 0.5 * (xl[0] + xl[1])
    ax.text(xm, fl.WS_HERTZ - 0.015, "Hertz: 2√3 = 3.464", fontsize=8, va="top", ha="center")
    ax.text(
        xm,
        fl.WS_GAUSSIAN - 0.015,
        "Gaussian: 2√(2 ln 2) = 2.355",
        fontsize=8,
        va="top",
        ha="center",
    )
    ax.set_xlabel("log10 alpha")
    ax.set_ylabel("w/s (FWHM / standard deviation)")
    ax.set_title("Fig. 4: width ratio vs alpha = h_rms/delta", fontsize=10)
    ax.legend(fontsize=8, loc="center left")
    fig.tight_layout()
    _save(fig, os.path.join(out, "fig4_ws.png"))
    plt.close(fig)

    fig, ax = plt.subplots(figsize=(5.5, 4.2))
    for s, c in zip(surfs, styles, strict=True):
        a = np.array([r[1] for r in s["rows"]])
        ax.plot(np.log10(a), [r[3] for r in s["rows"]], "o-", ms=3, color=c, label=s["label"])
        aa = np.logspace(math.log10(a.min()), math.log10(a.max()), 100)
        ax.plot(
            np.log10(aa),
            fl.p0_ratio_gaussian(aa, s["gamma_u"]),
            "--",
            color=c,
            lw=1,
            label=f"eq. 14, gamma_u = {s['gamma_u']:.3f}",
        )
    ax.axhline(1.0, color="k", lw=0.6)
    ax.set_ylim(0.0, 1.3)
    ax.set_xlabel("log10 alpha")
    ax.set_ylabel("p0(rough) / p0(Hertz)")
    ax.set_title("Fig. 5: peak pressure ratio vs alpha", fontsize=10)
    ax.legend(fontsize=7)
    fig.tight_layout()
    _save(fig, os.path.join(out, "fig5_p0ratio.png"))
    plt.close(fig)

    # summary
    print(f"fastline paper: {scene}; {args.loads} loads per surface, {elapsed:.2f} s")
    print(
        f"{'surface':<10}{'h_rms [m]':>11}{'H':>5}{'gamma_u':>9}{'alpha range':>22}"
        f"{'w/s range':>17}{'p0 ratio range':>18}{'not conv.':>10}"
    )
    for s in surfs:
        a = [r[1] for r in s["rows"]]
        ws = [r[6] for r in s["rows"]]
        pr = [r[3] for r in s["rows"]]
        bad = sum(not r[7] for r in s["rows"])
        print(
            f"{s['label']:<10}{s['h_rms']:>11.3g}{s['hurst']:>5.2g}{s['gamma_u']:>9.4f}"
            f"{min(a):>11.3g}-{max(a):<10.3g}{min(ws):>8.4f}-{max(ws):<8.4f}"
            f"{min(pr):>9.4f}-{max(pr):<8.4f}{bad:>10d}"
        )
    print(f"wrote fig2_psd, fig3_profile, fig4_ws, fig5_p0ratio (.png, .csv) to {out}")
    return 0


def _result_lines(r, diag) -> list[str]:
    lines = [
        f"model            {r.model} (method {r.method}, n = {r.diagnostics.get('n', '?')})",
        f"load f_N         {r.load:.6g} N/m",
        f"E*, R            {r.E_star:.6g} Pa, {r.radius:.6g} m",
        f"alpha            {r.alpha:.6g}   (h_rms / delta, delta = {r.delta:.6g} m)",
        f"regime           {diag['regime']}",
        f"peak pressure p0 {r.p0:.6g} Pa",
        f"p0 / p0(Hertz)   {r.p0_ratio:.6g}",
        f"std. dev. s      {r.s:.6g} m",
        f"FWHM w           {r.fwhm:.6g} m",
        f"w/s              {r.w_over_s:.6g}   (Hertz 3.464, Gaussian 2.355)",
    ]
    if diag.get("rms_slope") is not None:
        lines += [
            f"rms slope h'     {diag['rms_slope']:.6g}",
            f"h' E*/2          {diag['asperity_pressure']:.6g} Pa (elastic mean asperity pressure)",
            f"real area P(p0)  {diag['real_area_at_peak']:.6g} (fraction at the peak)",
        ]
    if diag.get("plastic_likely") is not None:
        lines.append(f"plastic likely   {'yes' if diag['plastic_likely'] else 'no'}")
    lines.append(f"half-width / R   {diag['half_width_over_radius']:.4g}")
    if "exponential_valid" in diag:
        lo, hi = diag["pressure_range_met"]
        vr = diag["exponential_valid_range"]
        lines.append(
            f"exp. law valid   {'yes' if diag['exponential_valid'] else 'NO'} (pressures met "
            f"{lo:.3g}-{hi:.3g} Pa; law within 5% in u up to {vr[1]:.3g} Pa)"
        )
    lines += [
        f"converged        {'yes' if r.converged else 'NO'} ({r.iterations} iterations, "
        f"{r.convolutions} FFT convolutions, residual {r.residual:.3g})",
        f"force error      {r.force_error:.3g} (relative); edge pressure {r.edge_pressure:.3g} p0",
    ]
    if r.message:
        lines.append(f"solver message   {r.message}")
    return lines


def cmd_profile(args) -> int:
    import fastline as fl
    from fastline.diagnostics import assess

    psd, E = _scene(args)
    th = _theory(psd, E, args.model) if args.model != "hertz" else None
    r = _solve(psd, E, args.radius, args.load, th, args.model, args.n)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        theory = th if th is not None else _theory(psd, E, args.model)
        diag = assess(r, theory=theory, hardness=args.hardness)
    print("\n".join(_result_lines(r, diag)))
    _print_warnings(str(w.message).removeprefix("fastline: ") for w in caught)
    if not r.converged:
        _print_warnings([f"the solve did not converge: {r.message}"])
    if args.csv:
        _write_csv(
            args.csv,
            ["x_m", "p_Pa", "u_m"],
            zip(r.x, r.pressure, r.separation, strict=True),
            f"fastline profile: model {r.model}, f_N = {r.load:g} N/m, E* = {E:g} Pa, "
            f"R = {args.radius:g} m, alpha = {r.alpha:.6g}",
        )
    if args.plot:
        plt = _pyplot()
        hz = fl.hertz_line_contact(E, args.radius, args.load)
        fig, ax = plt.subplots(figsize=(5.5, 4.2))
        ax.plot(r.x * 1e3, r.pressure / 1e6, "-", label=f"rough ({r.model})")
        ax.plot(r.x * 1e3, hz.pressure(r.x) / 1e6, "--", color="k", label="Hertz (smooth)")
        ax.set_xlabel("x (mm)")
        ax.set_ylabel("nominal pressure p (MPa)")
        ax.set_title(f"f_N = {r.load:g} N/m, alpha = {r.alpha:.3g}", fontsize=10)
        ax.legend(fontsize=8)
        fig.tight_layout()
        _save(fig, args.plot)
        plt.close(fig)
    return 0


def cmd_sweep(args) -> int:
    psd, E = _scene(args)
    if args.loads_to < args.loads_from:
        raise CLIError("--loads-to must be >= --loads-from")
    loads = np.logspace(math.log10(args.loads_from), math.log10(args.loads_to), args.loads_num)
    th = _theory(psd, E, args.model) if args.model != "hertz" else None
    rows = []
    for i, f in enumerate(loads):
        r = _solve(psd, E, args.radius, float(f), th, args.model, args.n)
        rows.append((float(f), r.alpha, r.p0, r.p0_ratio, r.s, r.fwhm, r.w_over_s, r.converged))
        _progress(i + 1, len(loads), "sweep")
    header = ["load_N_per_m", "alpha", "p0_Pa", "p0_ratio", "s_m", "w_m", "w_over_s", "converged"]
    print(
        f"{'load [N/m]':>12}{'alpha':>12}{'p0 [Pa]':>13}{'p0 ratio':>10}{'s [m]':>12}"
        f"{'w [m]':>12}{'w/s':>8}{'conv':>6}"
    )
    for f, a, p0, pr, sd, w, ws, ok in rows:
        print(
            f"{f:>12.4g}{a:>12.4g}{p0:>13.5g}{pr:>10.5f}{sd:>12.4g}{w:>12.4g}{ws:>8.4f}"
            f"{'yes' if ok else 'NO':>6}"
        )
    if args.csv:
        _write_csv(
            args.csv,
            header,
            rows,
            f"fastline sweep: model {args.model}, E* = {E:g} Pa, R = {args.radius:g} m",
        )
    if args.plot:
        plt = _pyplot()
        import fastline as fl

        a = np.log10([r[1] for r in rows])
        fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(9, 3.8))
        ax1.plot(a, [r[6] for r in rows], "o-", ms=3)
        ax1.axhline(fl.WS_HERTZ, ls="--", color="k", lw=1)
        ax1.axhline(fl.WS_GAUSSIAN, ls=":", color="k", lw=1)
        ax1.set_xlabel("log10 alpha")
        ax1.set_ylabel("w/s")
        ax2.plot(a, [r[3] for r in rows], "o-", ms=3)
        if th is not None:
            aa = np.logspace(a.min(), a.max(), 100)
            ax2.plot(
                np.log10(aa),
                fl.p0_ratio_gaussian(aa, th.exponential_fit().gamma_u),
                "--",
                color="k",
                lw=1,
                label="eq. 14",
            )
            ax2.legend(fontsize=8)
        ax2.set_xlabel("log10 alpha")
        ax2.set_ylabel("p0(rough) / p0(Hertz)")
        fig.tight_layout()
        _save(fig, args.plot)
        plt.close(fig)
    return 0


COMMANDS = {"paper": cmd_paper, "profile": cmd_profile, "sweep": cmd_sweep}


def main(argv=None) -> int:
    """Run the command line; returns the exit status (0 ok, 2 usage or input error)."""
    parser = build_parser()
    try:
        args = parser.parse_args(argv)
        if args.command is None:
            parser.print_help()
            return 2
        return COMMANDS[args.command](args)
    except CLIError as e:
        print(f"fastline: error: {e}", file=sys.stderr)
        return 2
    except ValueError as e:
        msg = " ".join(str(e).split())
        print(f"fastline: error: {msg}", file=sys.stderr)
        return 2


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
