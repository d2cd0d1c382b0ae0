"""Fingerprint every command-line output of fastline, to prove a refactoring changes none.

Record (run the fixed invocation list against one interpreter, write a JSON)::

    python -m bench.cli_outputs --python VENV/bin/python --examples TREE/examples --out result.json
                          [--workdir DIR] [--only NAME ...] [--timeout S]

Compare (exit 0: identical; 1: something differs, each difference printed with a diff)::

    python -m bench.cli_outputs --compare a.json b.json

List the invocations: ``python -m bench.cli_outputs --list``.

What is run
-----------
Each entry of ``INVOCATIONS`` runs as ``<python> -m fastline <args>`` in its own fresh
temporary directory, into which the files of ``--examples`` (``scan_example.txt``,
``psd_example.txt``, ``seal_scenes.csv``) and the entry's own small input files are copied
first; every path in the list is relative to that directory, so nothing depends on the tree.
An entry may have ``setup`` commands (other fastline invocations run first in the same
directory, e.g. ``psd --out`` writing the table a ``--psd`` then reads); their exit codes are
recorded too. Recorded per entry: the exit code, sha256 of stdout and of stderr, the (masked)
stdout/stderr texts themselves, and sha256 of every file in the directory afterwards that was
not there before or whose content changed (relative path -> hash). The wall time is stored but
never compared.

Before the list, one unrecorded warm-up process imports fastline and matplotlib.pyplot (so
matplotlib's one-off "building the font cache" message can not land in a recorded stderr).
The first run on a fresh install (or after any edit: fastline stamps its kernels with the mtime
of every module) also compiles Numba's kernels (minutes) - run twice, keep the second. The
cache lands next to the package's sources unless NUMBA_CACHE_DIR is set. Warm: ~75-90 s on 2
cores for the whole list.

Exit codes expected by the list (``expect``; a mismatch is flagged in the run's log, while
--compare compares only the two records): profile_not_converged 1, batch_mixed 1 (one scene
fails), sweep_bad_n 1 (a bad --n fails every scene of a sweep: a table of nan, exit 1, where
profile --n 8 gives exit 2), err_* 2.

Environment of every process (nothing else is inherited, except PATH, HOME, and
NUMBA_CACHE_DIR when set): MPLBACKEND=Agg, PYTHONHASHSEED=0, OMP_NUM_THREADS=1,
OPENBLAS_NUM_THREADS=1, MKL_NUM_THREADS=1, SOURCE_DATE_EPOCH=0, LC_ALL=C.UTF-8,
COLUMNS=100 (argparse wraps --help to the terminal width; fixed here), no TERM/tty (progress
bars stay off). Sweeps and batches pass --workers explicitly (the default depends on the CPU
count); one sweep uses --workers 2 to cover the process pool.

Normalisation (masks), applied to stdout, stderr and to every output file that decodes as
UTF-8 (CSV/text) before hashing; PNG files are hashed byte for byte, unmasked (no pdf/svg is
written: they embed dates):

1. ``<tmp>``: the invocation's temporary directory (its path and its realpath), e.g. the
   absolute psd paths in batch's result CSV and in "directory ... does not exist" errors.
2. ``<venv>`` / ``<pkg>``: sys.prefix of --python and the directory holding the imported
   fastline package (paths of tracebacks or warnings would otherwise differ between trees).
3. Wall-clock timings, number replaced by ``<t>``:
   - ``solved in 1.23 s`` / ``files in 0.12 s``              (fastline paper, both geometries)
   - ``BEM 1.9 s (0.96 s per realisation), theory 0.22 s``   (fastline validate, all modes)
   - ``; 0.47 s (21 scenes/s,``                               (fastline batch summary line)
4. ``<date>``: ``YYYY-MM-DD HH:MM:SS`` time stamps (the ``# written:`` line of
   fastline validate's CSV).

Standard library only.
"""

from __future__ import annotations

import argparse
import difflib
import hashlib
import json
import os
import re
import shutil
import subprocess
import sys
import tempfile
import time

# ---------------------------------------------------------------------------- invocations

MAT = "--E1 2.1e11 --nu1 0.3 --E2 5e6 --nu2 0.49"
SCAN = "--scan scan_example.txt --dx 1e-6 --units um --q1 1e9 --extend"
ORING = (
    "--h-rms 0.3e-6 --hurst 0.85 --q0 5e4 --qr 5e5 --q1 1e9 --E1 10e6 --nu1 0.5 --E2 210e9 "
    "--nu2 0.3"
)
FLUID = "--pressure-drop 1e4 --viscosity 1e-3"
BALL = f"--geometry sphere {ORING} --radius 10e-3 --inner-radius 20e-6 {FLUID}"

#: a scene table: a sphere, a Hertz and an exponential scene, and one out-of-range value (that
#: row fails, reported in its error column: exit 1)
MIXED_SCENES = """\
label,geometry,h_rms,hurst,q0,qr,q1,E_star,radius,load,model,n,variant
cyl,,1e-6,0.8,1e3,1e4,1e9,1.33e9,0.01,1e4,,128,
ball,sphere,1e-6,0.8,1e3,1e4,1e9,1.33e9,0.01,10,,64,yang-persson-printed
smooth,,1e-6,0.8,1e3,1e4,1e9,1.33e9,0.01,1e4,hertz,128,
expo,,1e-6,0.8,1e3,1e4,1e9,1.33e9,0.01,1e4,exponential,128,
badH,,1e-6,1.5,1e3,1e4,1e9,1.33e9,0.01,1e4,,128,
"""


def _inv(name, args, expect=0, setup=(), files=None):
    return {
        "name": name,
        "args": args.split() if isinstance(args, str) else list(args),
        "expect": expect,
        "setup": [s.split() for s in setup],
        "files": dict(files or {}),
    }


INVOCATIONS = [
    # --- help and version
    _inv("help", "--help"),
    _inv("version", "--version"),
    *(
        _inv(f"help_{c}", f"{c} --help")
        for c in ("profile", "sweep", "batch", "paper", "leak", "psd", "validate")
    ),
    # --- profile
    _inv("profile_defaults", "profile"),
    _inv(
        "profile_full",
        "profile --h-rms 10e-6 --hurst 0.8 --q1 1e9 --E-star 1.33e9 "
        "--radius 0.01 --load 1e4 --hardness 2e8 --n 256 --csv profile.csv --plot profile.png",
    ),
    _inv(
        "profile_psd",
        f"profile --psd psd_example.txt {MAT} --radius 2e-3 --load 500 --n 256 --csv profile.csv",
    ),
    _inv(
        "profile_psd_table",
        f"profile --psd psd_1e9.csv {MAT} --radius 0.01 --load 100 --n 256",
        setup=["psd scan_example.txt --dx 1e-6 --units um --q1 1e9 --extend --out psd_1e9.csv"],
    ),
    _inv(
        "profile_scan", f"profile {SCAN} {MAT} --radius 0.01 --load 100 --n 256 --csv profile.csv"
    ),
    _inv(
        "profile_sphere",
        "profile --geometry sphere --load 500 --E1 2.1e11 --nu1 0.3 --E2 7e10 "
        "--nu2 0.33 --n 128 --csv sphere.csv --plot sphere.png --dpi 60",
    ),
    _inv(
        "profile_hertz",
        "profile --model hertz --load 1e4 --n 256 --csv hertz.csv --plot hertz.png --dpi 60",
    ),
    _inv("profile_hertz_sphere", "profile --model hertz --geometry sphere --load 10 --n 128"),
    _inv(
        "profile_exponential",
        "profile --model exponential --h-rms 1e-6 --load 1e4 --n 256 --csv exp.csv",
    ),
    _inv(
        "profile_wang_mueser",
        "profile --variant wang-mueser --gamma 0.6 --h-rms 1e-6 --n 256 --plot wm.png --dpi 60",
    ),
    _inv("profile_not_converged", "profile --max-iter 1 --n 256", expect=1),
    # --- sweep
    _inv(
        "sweep_basic",
        "sweep --h-rms 1e-6 --loads-from 1e3 --loads-to 1e6 --loads-num 8 "
        "--n 128 --workers 1 --csv sweep.csv --plot sweep.png --dpi 60",
    ),
    _inv(
        "sweep_sphere",
        "sweep --geometry sphere --h-rms 1e-6 --n 128 --loads-num 6 "
        "--workers 1 --csv sweep.csv --plot sweep.png --dpi 60",
    ),
    _inv(
        "sweep_pool",
        "sweep --h-rms 1e-6 --n 128 --loads-num 16 --variant yang-persson-printed "
        "--workers 2 --chunksize 4",
    ),
    _inv("sweep_hertz", "sweep --model hertz --loads-num 5 --n 128 --workers 1 --csv sweep.csv"),
    _inv(
        "sweep_exponential",
        "sweep --model exponential --h-rms 1e-6 --loads-num 5 --n 128 --workers 1",
    ),
    # a bad value in a sweep fails every scene (table of nan, exit 1), unlike profile (exit 2)
    _inv("sweep_bad_n", "sweep --n 8 --loads-num 3 --workers 1", expect=1),
    _inv(
        "sweep_scan",
        f"sweep {SCAN} {MAT} --radius 0.01 --loads-from 30 --loads-to 3e3 "
        "--loads-num 5 --n 128 --workers 1 --csv sweep.csv",
    ),
    # --- batch
    _inv("batch_seal", "batch seal_scenes.csv --out seal_results.csv --workers 1"),
    _inv(
        "batch_mixed",
        "batch scenes.csv --out results.csv --workers 1",
        expect=1,
        files={"scenes.csv": MIXED_SCENES},
    ),
    # --- paper
    _inv("paper_cylinder", "paper --out figs --loads 4 --n 128 --dpi 60"),
    _inv("paper_sphere", "paper --geometry sphere --out figs --loads 4 --n 64 --dpi 60"),
    # --- leak
    _inv(
        "leak_oring",
        f"leak {ORING} --radius 1.5e-3 --load 300 {FLUID} --length 0.0785 "
        "--n 256 --csv leak.csv --plot leak.png --dpi 60",
    ),
    _inv(
        "leak_sweep",
        f"leak --sweep {ORING} --radius 1.5e-3 --loads-from 10 --loads-to 1e4 "
        f"--loads-num 6 {FLUID} --length 0.0785 --n 256 --csv leak_sweep.csv "
        "--plot leak_sweep.png --dpi 60",
    ),
    _inv("leak_sphere", f"leak {BALL} --load 0.2 --n 128 --csv ball.csv --plot ball.png --dpi 60"),
    _inv(
        "leak_sphere_sweep",
        f"leak --sweep {BALL} --loads-from 0.1 --loads-to 100 "
        "--loads-num 4 --n 128 --csv ball_sweep.csv",
    ),
    _inv(
        "leak_scan",
        f"leak {SCAN} {MAT} --radius 0.01 --load 100 {FLUID} --n 256 "
        "--threshold 0.415 --mean-free-path 70e-9",
    ),
    _inv(
        "leak_exponential",
        f"leak --model exponential {ORING} --radius 1.5e-3 --load 300 {FLUID} --n 256",
    ),
    # --- psd
    _inv("psd_scan", "psd scan_example.txt --dx 1e-6 --units um --out psd.csv --plot psd.png"),
    _inv(
        "psd_extend",
        "psd scan_example.txt --dx 1e-6 --units um --q1 1e9 --extend "
        "--out psd_1e9.csv --plot psd_1e9.png --dpi 60",
    ),
    _inv(
        "psd_options",
        "psd scan_example.txt --dx 1e-6 --units um --detrend parabola "
        "--window none --bins-per-decade 10 --q-range 2e4 auto --tip-radius 2e-6 --noise 1e-9",
    ),
    # --- validate (tiny: 2 realisations, 2 cells per shortest wavelength)
    _inv(
        "validate_line",
        "validate --realizations 2 --workers 1 --points-per-wavelength 2 "
        "--n 128 --csv validate.csv --plot validate.png --dpi 60",
    ),
    _inv(
        "validate_flat",
        "validate --leak --pressure 1e4 5e4 --all-variants --gw "
        "--realizations 2 --workers 1 --points-per-wavelength 2 --csv flat.csv",
    ),
    # --- error paths (exit 2, one "fastline: error:" line; argparse's own: usage + error)
    _inv("err_no_command", "", expect=2),
    _inv("err_negative_load", "profile --load -1e4", expect=2),
    _inv("err_missing_psd", "profile --psd missing.txt", expect=2),
    _inv("err_psd_with_hrms", "profile --psd psd_example.txt --h-rms 1e-6", expect=2),
    _inv("err_hertz_roughness", "profile --model hertz --h-rms 1e-6 --q1 1e8", expect=2),
    _inv("err_small_n", "profile --n 8", expect=2),
    _inv("err_csv_dir", "profile --csv nodir/p.csv", expect=2),
    _inv("err_leak_hertz", f"leak --model hertz {FLUID}", expect=2),
    _inv("err_leak_no_fluid", "leak --load 300", expect=2),
    _inv("err_leak_wang_mueser", f"leak --variant wang-mueser {FLUID}", expect=2),
    _inv("err_leak_sphere_hole", f"leak --geometry sphere {FLUID}", expect=2),
    _inv("err_psd_no_dx", "psd scan_example.txt", expect=2),
    _inv("err_psd_spectrum_file", "psd psd_example.txt", expect=2),
    _inv("err_batch_missing", "batch missing.csv --out r.csv --workers 1", expect=2),
    _inv("err_validate_one", "validate --realizations 1 --workers 1", expect=2),
]

# ---------------------------------------------------------------------------- masks

TIMING_MASKS = [
    (re.compile(r"\b(solved in|files in|BEM|theory) \d+(?:\.\d+)? s\b"), r"\1 <t> s"),
    (re.compile(r"\(\d+(?:\.\d+)? s per realisation\)"), "(<t> s per realisation)"),
    (re.compile(r"; \d+(?:\.\d+)? s \(\d+ scenes/s,"), "; <t> s (<t> scenes/s,"),
    (re.compile(r"\b\d{4}-\d\d-\d\d \d\d:\d\d:\d\d\b"), "<date>"),
]


def mask_text(text: str, paths: list[tuple[str, str]]) -> str:
    for path, token in paths:
        if path:
            text = text.replace(path, token)
    for rx, repl in TIMING_MASKS:
        text = rx.sub(repl, text)
    return text


def mask_bytes(data: bytes, paths) -> bytes:
    text = data.decode("utf-8", "surrogateescape")
    return mask_text(text, paths).encode("utf-8", "surrogateescape")


def sha(data: bytes) -> str:
    return hashlib.sha256(data).hexdigest()


# ---------------------------------------------------------------------------- record


def make_env() -> dict:
    env = {
        "PATH": os.environ.get("PATH", "/usr/bin:/bin"),
        "HOME": os.environ.get("HOME", "/tmp"),
        "MPLBACKEND": "Agg",
        "PYTHONHASHSEED": "0",
        "OMP_NUM_THREADS": "1",
        "OPENBLAS_NUM_THREADS": "1",
        "MKL_NUM_THREADS": "1",
        "SOURCE_DATE_EPOCH": "0",
        "LC_ALL": "C.UTF-8",
        "COLUMNS": "100",
    }
    if os.environ.get("NUMBA_CACHE_DIR"):
        env["NUMBA_CACHE_DIR"] = os.environ["NUMBA_CACHE_DIR"]
    return env


def snapshot(root: str) -> dict[str, str]:
    out = {}
    for dp, dn, fn in os.walk(root):
        dn.sort()
        for f in sorted(fn):
            p = os.path.join(dp, f)
            rel = os.path.relpath(p, root)
            with open(p, "rb") as fh:
                out[rel] = fh.read()
    return out


def run_one(inv, python, examples, base, env, sys_paths, timeout):
    work = tempfile.mkdtemp(prefix=f"{inv['name']}.", dir=base)
    for f in sorted(os.listdir(examples)):
        src = os.path.join(examples, f)
        if os.path.isfile(src) and not f.endswith(".py"):
            shutil.copy(src, os.path.join(work, f))
    for f, text in inv["files"].items():
        with open(os.path.join(work, f), "w") as fh:
            fh.write(text)
    paths = [(os.path.realpath(work), "<tmp>"), (work, "<tmp>")] + sys_paths
    rec = {"args": inv["args"], "expect": inv["expect"]}
    before = snapshot(work)  # the inputs: a file counts as output if new or changed
    t0 = time.perf_counter()
    setup_rc = []
    for s in inv["setup"]:
        p = subprocess.run(
            [python, "-m", "fastline", *s], cwd=work, env=env, capture_output=True, timeout=timeout
        )
        setup_rc.append(p.returncode)
    if setup_rc:
        rec["setup"] = [{"args": s, "rc": rc} for s, rc in zip(inv["setup"], setup_rc, strict=True)]
    try:
        p = subprocess.run(
            [python, "-m", "fastline", *inv["args"]],
            cwd=work,
            env=env,
            stdin=subprocess.DEVNULL,
            capture_output=True,
            timeout=timeout,
        )
        rc, out, err = p.returncode, p.stdout, p.stderr
    except subprocess.TimeoutExpired as e:
        rc, out, err = "timeout", e.stdout or b"", e.stderr or b""
    rec["seconds"] = round(time.perf_counter() - t0, 2)
    out, err = mask_bytes(out, paths), mask_bytes(err, paths)
    rec.update(
        rc=rc,
        stdout_sha256=sha(out),
        stderr_sha256=sha(err),
        stdout=out.decode("utf-8", "replace"),
        stderr=err.decode("utf-8", "replace"),
    )
    files = {}
    for rel, data in snapshot(work).items():
        if before.get(rel) == data:
            continue
        try:
            data.decode("utf-8")
            data = mask_bytes(data, paths)
        except UnicodeDecodeError:
            pass  # binary (PNG): as is
        files[rel] = sha(data)
    rec["files"] = files
    return rec, work


def record(args) -> int:
    python = os.path.abspath(args.python) if os.sep in args.python else args.python
    examples = os.path.abspath(args.examples)
    env = make_env()
    invs = INVOCATIONS
    if args.only:
        unknown = set(args.only) - {i["name"] for i in INVOCATIONS}
        if unknown:
            sys.exit(f"unknown invocation(s): {sorted(unknown)}")
        invs = [i for i in INVOCATIONS if i["name"] in args.only]
    # warm-up (unrecorded): matplotlib's font cache, fastline's import; where things live
    probe = subprocess.run(
        [
            python,
            "-c",
            "import sys, os, matplotlib.pyplot, fastline; "
            "print(sys.prefix); print(os.path.dirname(os.path.dirname(fastline.__file__))); "
            "print(getattr(fastline, '__version__', '?'))",
        ],
        env=env,
        capture_output=True,
        text=True,
        cwd=tempfile.gettempdir(),
    )
    if probe.returncode:
        sys.exit(f"cannot import fastline with {python}:\n{probe.stderr}")
    prefix, pkg_parent, version = probe.stdout.split("\n")[:3]
    sys_paths = [
        (pkg_parent, "<pkg>"),
        (os.path.realpath(pkg_parent), "<pkg>"),
        (prefix, "<venv>"),
        (os.path.realpath(prefix), "<venv>"),
    ]
    if args.workdir:
        os.makedirs(args.workdir, exist_ok=True)
        base = tempfile.mkdtemp(prefix="cli_outputs.", dir=args.workdir)
    else:
        base = tempfile.mkdtemp(prefix="cli_outputs.")
    result = {
        "meta": {
            "python": python,
            "fastline_version": version,
            "prefix": prefix,
            "package_parent": pkg_parent,
            "examples": examples,
        },
        "invocations": {},
    }
    t_all = time.perf_counter()
    unexpected = []
    try:
        for inv in invs:
            rec, _ = run_one(inv, python, examples, base, env, sys_paths, args.timeout)
            result["invocations"][inv["name"]] = rec
            flag = "" if rec["rc"] == inv["expect"] else f"  (UNEXPECTED, expected {inv['expect']})"
            bad_setup = [s for s in rec.get("setup", []) if s["rc"] != 0]
            if bad_setup:
                flag += f"  (setup exited {[s['rc'] for s in bad_setup]})"
            if flag:
                unexpected.append(inv["name"])
            print(
                f"{rec['seconds']:7.2f} s  rc={rec['rc']!s:<3} {inv['name']}"
                f"  files={len(rec['files'])}{flag}",
                flush=True,
            )
    finally:
        if not args.workdir:
            shutil.rmtree(base, ignore_errors=True)
    total = time.perf_counter() - t_all
    result["meta"]["seconds_total"] = round(total, 1)
    with open(args.out, "w") as fh:
        json.dump(result, fh, indent=1, sort_keys=True)
        fh.write("\n")
    print(
        f"{len(invs)} invocations in {total:.1f} s -> {args.out}"
        + (f"; outputs kept in {base}" if args.workdir else "")
    )
    if unexpected:
        print(f"unexpected exit codes: {', '.join(unexpected)}")
    return 0


# ---------------------------------------------------------------------------- compare


def compare(a_path: str, b_path: str, max_diff_lines: int = 40) -> int:
    with open(a_path) as fh:
        a = json.load(fh)["invocations"]
    with open(b_path) as fh:
        b = json.load(fh)["invocations"]
    ndiff = 0
    for name in sorted(set(a) - set(b)):
        print(f"{name}: only in {a_path}")
        ndiff += 1
    for name in sorted(set(b) - set(a)):
        print(f"{name}: only in {b_path}")
        ndiff += 1
    for name in [n for n in a if n in b]:
        ra, rb = a[name], b[name]
        problems = []
        if ra["args"] != rb["args"]:
            problems.append(f"args differ: {ra['args']} vs {rb['args']}")
        if ra["rc"] != rb["rc"]:
            problems.append(f"exit code {ra['rc']} -> {rb['rc']}")
        if ra.get("setup") != rb.get("setup"):
            problems.append(f"setup {ra.get('setup')} -> {rb.get('setup')}")
        diffs = []
        for stream in ("stdout", "stderr"):
            if ra[f"{stream}_sha256"] != rb[f"{stream}_sha256"]:
                problems.append(f"{stream} differs")
                d = list(
                    difflib.unified_diff(
                        ra[stream].splitlines(),
                        rb[stream].splitlines(),
                        f"a/{name}/{stream}",
                        f"b/{name}/{stream}",
                        lineterm="",
                        n=1,
                    )
                )
                if len(d) > max_diff_lines:
                    d = d[:max_diff_lines] + [f"... ({len(d) - max_diff_lines} more diff lines)"]
                diffs.extend(d)
        fa, fb = ra["files"], rb["files"]
        for f in sorted(set(fa) | set(fb)):
            if f not in fb:
                problems.append(f"file {f}: missing in b")
            elif f not in fa:
                problems.append(f"file {f}: new in b")
            elif fa[f] != fb[f]:
                problems.append(f"file {f}: content differs")
        if problems:
            ndiff += 1
            print(f"DIFF {name} ({' '.join(ra['args'])}):")
            for p in problems:
                print(f"    {p}")
            for line in diffs:
                print(f"      {line}")
    n = len(set(a) | set(b))
    if ndiff:
        print(f"{ndiff} of {n} invocations differ")
        return 1
    print(f"all {n} invocations identical")
    return 0


# ---------------------------------------------------------------------------- main


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--python", help="interpreter of the venv under test")
    ap.add_argument("--examples", help="directory of the example files (scan/psd/scenes)")
    ap.add_argument("--out", help="write the JSON record here")
    ap.add_argument(
        "--workdir",
        help="make the working directories under DIR and keep them "
        "(default: a temporary directory, removed afterwards)",
    )
    ap.add_argument("--only", nargs="+", metavar="NAME", help="run only these invocations")
    ap.add_argument("--timeout", type=float, default=600, help="per invocation [s] (600)")
    ap.add_argument("--compare", nargs=2, metavar=("A", "B"), help="compare two JSON records")
    ap.add_argument("--list", action="store_true", help="print the invocations and exit")
    args = ap.parse_args(argv)
    if args.list:
        for inv in INVOCATIONS:
            pre = "".join(f"[setup: fastline {' '.join(s)}] " for s in inv["setup"])
            extra = f" [+ file {', '.join(inv['files'])}]" if inv["files"] else ""
            print(
                f"{inv['name']:24} exit {inv['expect']}  {pre}fastline {' '.join(inv['args'])}"
                f"{extra}"
            )
        print(f"{len(INVOCATIONS)} invocations")
        return 0
    if args.compare:
        return compare(*args.compare)
    if not (args.python and args.out and args.examples):
        ap.error("--python, --examples and --out are needed to record (or --compare A B)")
    return record(args)


if __name__ == "__main__":
    sys.exit(main())
