"""Each compiled kernel is compiled once: callers pass consistently typed arguments.

A kernel called with an int where it was first called with a float (or a non-contiguous, a
read-only or a differently typed tuple argument) is compiled a second time, which costs a
fresh process 0.1-10 s of CPU (the line contact's Newton kernel alone ~2.5 s) and a second
cache entry. The scenes below run in a fresh interpreter (sharing the on-disk Numba cache of
the test run, so this is ~1 s once the cache is warm) through the paths a first user meets:
a Persson and an exponential solve at two grid sizes, and a (compiled) sweep with polynomial
predictions and a long step that starts cold.
"""

from __future__ import annotations

import json
import subprocess
import sys

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
