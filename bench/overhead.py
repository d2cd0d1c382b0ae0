"""Per-call cost of a warm solve against fastline 0.1, in one process: ``python -m bench.overhead``.

fastline 0.1 (commit e4d0481, before the embedding API) is extracted from git into a temporary
directory and imported as ``fastline_v01`` next to the current package, so both are timed in the
same run on the same machine state. Reported: best-of-N wall time per warm solve of surface 1
at alpha = 1 (15 convolutions) and alpha = 0.01, n = 128 and 1024, for

* ``solve_line_contact`` of 0.1 (a theory cache lookup, fresh grid and operator each call),
* ``solve_line_contact`` now (builds a LineContact, shared theory),
* ``LineContact.solve`` now (the model reused),

and the ratios. Needs git and a checkout (not part of the installed package).
"""

from __future__ import annotations

import math
import pathlib
import subprocess
import sys
import tempfile
import time
from functools import partial

import fastline as fl

OLD_COMMIT = "e4d0481"
E_STAR, RADIUS = 1.33e9, 0.01


def _import_old(tmp: pathlib.Path):
    root = pathlib.Path(__file__).resolve().parents[1]
    files = subprocess.run(
        ["git", "-C", str(root), "ls-tree", "-r", "--name-only", OLD_COMMIT, "fastline"],
        capture_output=True,
        text=True,
        check=True,
    ).stdout.split()
    pkg = tmp / "fastline_v01"
    pkg.mkdir()
    for f in files:
        text = subprocess.run(
            ["git", "-C", str(root), "show", f"{OLD_COMMIT}:{f}"],
            capture_output=True,
            text=True,
            check=True,
        ).stdout
        (pkg / pathlib.Path(f).name).write_text(text.replace("fastline", "fastline_v01"))
    sys.path.insert(0, str(tmp))
    import fastline_v01

    return fastline_v01


def best(fn, repeat=200):
    fn()
    out = math.inf
    for _ in range(repeat):
        t = time.thread_time()  # CPU time of this thread: robust on a shared machine
        fn()
        out = min(out, time.thread_time() - t)
    return out


def main():
    with tempfile.TemporaryDirectory(prefix="fastline-v01-") as d:
        old = _import_old(pathlib.Path(d))
        psd_old = old.SelfAffinePSD(10e-6, 0.8, 1e3, 1e4, 1e9)
        psd = fl.SelfAffinePSD(10e-6, 0.8, 1e3, 1e4, 1e9)
        print(
            "| alpha | n | 0.1 solve_line_contact | solve_line_contact | LineContact.solve "
            "| 0.1 / LineContact.solve | convolutions 0.1 / now |"
        )
        print("|---|---|---|---|---|---|---|")
        for alpha in (1.0, 0.01):
            load = math.pi / 4.0 * psd.h_rms * E_STAR / alpha
            for n in (128, 1024):
                args = (E_STAR, RADIUS, load)
                lc = fl.LineContact(psd, *args[:2], n=n, warn=False)
                t_old = best(partial(old.solve_line_contact, psd_old, *args, n=n, warn=False))
                t_fn = best(partial(fl.solve_line_contact, psd, *args, n=n, warn=False))
                t_lc = best(partial(lc.solve, load))
                c_old = old.solve_line_contact(psd_old, *args, n=n, warn=False).convolutions
                c_new = lc.solve(load).convolutions
                print(
                    f"| {alpha:g} | {n} | {t_old * 1e3:.2f} ms | {t_fn * 1e3:.2f} ms | "
                    f"{t_lc * 1e3:.2f} ms | {t_old / t_lc:.2f} | {c_old} / {c_new} |"
                )


if __name__ == "__main__":
    main()
