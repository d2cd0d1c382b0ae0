"""Each compiled kernel is compiled once: callers pass consistently typed arguments.

A kernel called with an int where it was first called with a float (or a non-contiguous, a
read-only or a differently typed tuple argument) is compiled a second time, which costs a
fresh process 0.1-10 s of CPU (the line contact's Newton kernel alone ~2.5 s) and a second
cache entry. The scenes below run in a fresh interpreter (sharing the on-disk Numba cache of
the test run, so this is ~1 s once the cache is warm) through the paths a first user meets:
a Persson and an exponential solve at two grid sizes, and a (compiled) sweep with polynomial
predictions and a long step that starts cold.

The tests after those hold Numba's on-disk cache as users meet it: a copy of the package's
sources is compiled once (one small group of kernels) and must load every kernel when copied
to another path, compile again, and say so once, on another CPU, and compile again after any
module is edited; ``fastline compile`` fills the cache of every group so that a second run
compiles nothing."""

from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys
from pathlib import Path

import numba
import numpy as np
import pytest

import fastline as fl
from fastline.elastic.pcg import call_system

SCRIPT = """
import gc, json
from numba.core.registry import CPUDispatcher
import fastline as fl
from fastline.contact.line import solve_line_contact

psd = fl.SelfAffinePSD(10e-6, 0.8, 1e3, 1e4, 1e9)
solve_line_contact(psd, 1.33e9, 0.01, 1.0e4, warn=False)
solve_line_contact(psd, 1.33e9, 0.01, 3.0e5, n=256, warn=False)
solve_line_contact(psd, 1.33e9, 0.01, 1.0e4, model="exponential", n=256, warn=False)
lc = fl.LineContact(psd, 1.33e9, 0.01, n=256, warn=False)
lc.sweep([1.0e4, 1.1e4, 1.2e4, 1.3e4, 4.0e4])  # polynomial steps, then a long (cold) step
sigs = {
    f"{d.py_func.__module__}.{d.py_func.__qualname__}": [str(s) for s in d.signatures]
    for d in gc.get_objects()
    if isinstance(d, CPUDispatcher) and d.py_func.__module__.startswith("fastline")
}
print(json.dumps(sigs))
"""

#: kernels the scenes above must reach (the check below would pass vacuously without them)
REACHED = (
    "fastline.contact.line_newton.newton_line",
    "fastline.elastic.pcg.solve_newton_system",
    "fastline.contact.line_sweep.sweep_line",
    "fastline.contact.kernels.line_measures",
)


def test_first_solves_compile_each_kernel_once():
    out = subprocess.run(
        [sys.executable, "-c", SCRIPT], capture_output=True, text=True, check=True, timeout=600
    )
    sigs = json.loads(out.stdout.strip().splitlines()[-1])
    for name in REACHED:
        assert sigs.get(name), f"{name} was not compiled by the scenes"
    twice = {name: s for name, s in sigs.items() if len(s) > 1}
    assert not twice, f"kernels compiled for more than one signature: {twice}"


# --- the compiled kernels' cache: carried with a copied installation, refused where it does not
# --- apply (another CPU, an edited source), and the notice of a compilation

#: the group of kernels these tests compile: the Persson tables' (6 kernels, ~2.5 s of CPU)
GROUP = "theory tables"


def _group_run(package_parent, extra_env=None, prelude=""):
    """Run GROUP's scenes in a fresh interpreter that imports the fastline under
    ``package_parent`` with its in-tree cache; returns ``(kernels compiled, stderr)``."""
    from fastline._lib.warmup import COUNTER, GROUPS, REPORT

    env = dict(os.environ, PYTHONPATH=str(package_parent))
    for name in ("NUMBA_CACHE_DIR", "FASTLINE_NUMBA_CACHE", "NUMBA_CPU_NAME"):
        env.pop(name, None)
    env.update(extra_env or {})
    check = f"\nassert fl.__file__.startswith({str(package_parent)!r}), fl.__file__\n"
    out = subprocess.run(
        [sys.executable, "-c", prelude + COUNTER + check + GROUPS[GROUP] + REPORT],
        capture_output=True,
        text=True,
        env=env,
        cwd=str(package_parent),
        timeout=600,
    )
    assert out.returncode == 0, out.stderr
    return json.loads(out.stdout.strip().splitlines()[-1])["compiled"], out.stderr


@pytest.fixture(scope="module")
def installed(tmp_path_factory):
    """A copy of the package's sources (no cache), its group compiled once: the parent dir."""
    parent = tmp_path_factory.mktemp("install") / "a"
    shutil.copytree(
        os.path.dirname(fl.__file__),
        parent / "fastline",
        ignore=shutil.ignore_patterns("__pycache__", "*.nbi", "*.nbc"),
    )
    compiled, err = _group_run(parent)
    assert compiled >= 3, "the group compiled too few kernels for the checks to mean anything"
    assert err.count("fastline: compiling the solver") == 1, err
    return parent


@pytest.mark.slow
def test_a_copied_installation_loads_its_kernels(installed, tmp_path):
    """A fresh process of a copy at another path (as a container layer or an install with pip's
    ``--target`` makes, all files rewritten with new times) compiles nothing, and is silent."""
    moved = tmp_path / "elsewhere"
    shutil.copytree(installed, moved, copy_function=shutil.copy)  # new times, another path
    compiled, err = _group_run(moved)
    assert compiled == 0 and "compiling" not in err, err


@pytest.mark.slow
def test_another_cpu_compiles_and_says_so_once(installed):
    """The cache does not serve another CPU (Numba keys it by the CPU's name): the kernels
    compile, and the notice says so once, naming why."""
    compiled, err = _group_run(installed, {"NUMBA_CPU_NAME": "generic"})
    assert compiled > 0
    assert err.count("fastline: compiling the solver") == 1, err
    assert "another CPU" in err


@pytest.mark.slow
def test_a_content_change_invalidates_the_cache(installed, tmp_path):
    """Any edited module (here one whose kernels the group does not define) recompiles every
    kernel; a library user who silenced the ``fastline`` logger sees no notice."""
    edited = tmp_path / "edited"
    shutil.copytree(installed, edited)
    with open(edited / "fastline" / "contact" / "kernels.py", "a") as f:
        f.write("\n# an edit\n")
    silence = "import logging\nlogging.getLogger('fastline').setLevel(logging.ERROR)\n"
    compiled, err = _group_run(edited, prelude=silence)
    assert compiled > 0 and "compiling" not in err, err


@pytest.mark.slow
def test_compile_builds_every_group_then_nothing_compiles():
    """``fl.compile_kernels`` (``fastline compile``) fills the cache of every group; run again,
    each group's fresh process loads all of its kernels (0 compiled)."""
    first = fl.compile_kernels()
    assert [r.error for r in first] == [""] * len(first)
    again = fl.compile_kernels()
    assert {r.name: r.compiled for r in again} == {r.name: 0 for r in first}


# --- kernels called by address, compiled in a second process

#: in a fresh interpreter with an empty cache: compile a small kernel in a second process, then
#: ask for its address; prints whether a process started, the compilations this process made,
#: whether the cache then serves the kernel, and whether a second request starts nothing
ELSEWHERE = """
import sys, numba, numpy as np
from numba.core import event
from fastline._lib.native import cache_serves, compile_elsewhere, native_address
from fastline.contact.kernels import largest
compiled = []
class Count(event.Listener):
    def on_start(self, e): compiled.append(e.data["dispatcher"].py_func.__name__)
    def on_end(self, e): pass
event.register("numba:compile", Count())
argtypes = (numba.typeof(np.empty(3)), numba.float64)
served_before = cache_serves(largest, argtypes)
there = "import numpy as np\\nfrom fastline.contact.kernels import largest as f\\n"
there += "f(np.empty(3), 0.0)"
started = compile_elsewhere(largest, argtypes, there, sys.argv[1])
address = native_address(largest, argtypes, numba.float64)
again = compile_elsewhere(largest, argtypes, there, sys.argv[1])
print(served_before, started, compiled, cache_serves(largest, argtypes), address > 0, again)
"""


@pytest.mark.skipif((os.cpu_count() or 1) < 2, reason="a second process only with 2+ CPUs")
def test_a_kernel_compiled_in_a_second_process_is_loaded_not_compiled(tmp_path):
    """With an empty cache, :func:`compile_elsewhere` starts a process that compiles the kernel
    into the cache; :func:`native_address` waits for it and loads the kernel: this process
    compiles nothing. Once loaded, no second process starts."""
    parent = os.path.dirname(os.path.dirname(fl.__file__))
    env = dict(os.environ, NUMBA_CACHE_DIR=str(tmp_path))
    for name in ("FASTLINE_NUMBA_CACHE", "FASTLINE_PARALLEL_COMPILE"):
        env.pop(name, None)
    out = subprocess.run(
        [sys.executable, "-c", ELSEWHERE, parent],
        capture_output=True,
        text=True,
        env=env,
        cwd=parent,
        timeout=300,
    )
    assert out.returncode == 0, out.stderr
    assert out.stdout.split() == ["False", "True", "[]", "True", "True", "False"], out.stdout


def test_call_by_address_refuses_other_array_layouts():
    """The Newton kernel's call of the Newton-system solver by address is typed against the
    argument types the solver is compiled for: a strided work array is a typing error, not a
    call with the wrong memory layout."""

    @numba.njit
    def calls(a):
        return call_system(0, (a, a, a, a, a, a[::2], a, a, a))

    with pytest.raises(numba.core.errors.TypingError, match="call_system"):
        calls(np.empty(4))


def test_compile_command_refuses_bad_jobs():
    res = subprocess.run(
        [sys.executable, "-m", "fastline", "compile", "--jobs", "0"],
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert res.returncode == 2 and "--jobs" in res.stderr and "Traceback" not in res.stderr
    with pytest.raises(ValueError, match="groups"):
        fl.compile_kernels(groups=["no such group"])


def test_compile_children_import_the_installation_that_asked(tmp_path, monkeypatch):
    """``fastline compile`` started in a directory that holds another ``fastline`` (a source
    checkout beside an installed copy) compiles the installation it was called from: its child
    interpreters must not pick up the working directory's package first."""
    from fastline._lib.warmup import child_script

    decoy = tmp_path / "fastline"
    decoy.mkdir()
    (decoy / "__init__.py").write_text("raise ImportError('the decoy package was imported')\n")
    body = "import fastline\nprint(fastline.__file__)\n"
    out = subprocess.run(
        [sys.executable, "-c", child_script(body)],
        capture_output=True,
        text=True,
        cwd=str(tmp_path),
        timeout=120,
    )
    assert out.returncode == 0, out.stderr
    assert Path(out.stdout.strip()) == Path(fl.__file__)
