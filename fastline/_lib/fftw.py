"""FFTW called from compiled code: real transforms of length 2n for the line contact's kernels.

The solver's inner loop (one conjugate-gradient iteration: two FFT convolutions and a few vector
operations) is compiled as a whole, so the FFTs must be callable from Numba code. pyFFTW (a
dependency) ships the FFTW library (``pyfftw.libs`` in its wheels) or links a system FFTW; this
module loads that same library with ctypes, makes the plans and exposes

* ``AVAILABLE`` - whether an FFTW library with the needed symbols was found;
* :func:`acquire` / :func:`release` - ``(r2c, c2r, plan_forward, plan_backward)`` addresses
  (int64) for one length, pinned while a kernel runs (plans are LRU-bounded);
* :func:`execute` - an intrinsic that calls ``fftw_execute_dft_r2c`` / ``_c2r`` (new-array
  execute) at such an address from ``@njit`` code.

Function and plan addresses are passed to the kernels as integers, never baked into the compiled
code, so the kernels stay cacheable across processes (library addresses change with ASLR).
FFTW's new-array execute functions are thread-safe; planning is not, and happens under a lock.
Plans use ``FFTW_ESTIMATE`` (deterministic: the same results in every process) on 64-byte
aligned buffers, and the kernels execute them on buffers aligned the same way
(:func:`aligned_buffers`). If no library is found, fastline falls back to pyFFTW's Python
interface (same results to round-off, slower).

FFT normalisation: FFTW's transforms are unnormalised; the kernels fold the factor ``1/(2n)``
into the spectra they multiply by.
"""

from __future__ import annotations

import ctypes
import ctypes.util
import glob
import importlib.util
import os
import sys
import threading
from collections import OrderedDict
from collections.abc import Iterator

import numba
import numpy as np
from llvmlite import ir
from numba import types
from numba.extending import intrinsic

from fastline._lib.jit import JIT

__all__ = [
    "AVAILABLE",
    "acquire",
    "release",
    "execute",
    "aligned_buffers",
    "aligned_views",
    "aligned_size",
    "ALIGN_PAD",
    "library_path",
]

_FFTW_ESTIMATE = 1 << 6
#: byte alignment of the buffers the plans are made on and executed with (AVX-512 safe)
ALIGN = 64


def _candidates() -> Iterator[str]:
    """Paths of the FFTW double-precision library, most specific first. A generator: the
    system search (``ctypes.util.find_library`` runs ``ldconfig``, ~40 ms) only happens when
    pyFFTW's own copy is not found."""
    spec = importlib.util.find_spec("pyfftw")
    if spec is not None and spec.submodule_search_locations:
        pkg = spec.submodule_search_locations[0]
        site = os.path.dirname(pkg)
        patterns = [
            os.path.join(site, "pyfftw.libs", "libfftw3-*.so*"),  # Linux wheels (auditwheel)
            os.path.join(pkg, ".dylibs", "libfftw3.*dylib"),  # macOS wheels (delocate)
            os.path.join(pkg, "libfftw3-3.dll"),  # Windows wheels
            os.path.join(site, "pyfftw.libs", "libfftw3-3*.dll"),
        ]
        for pattern in patterns:
            yield from sorted(p for p in glob.glob(pattern) if "_omp" not in p)
    for name in ("fftw3", "fftw3-3"):
        found = ctypes.util.find_library(name)
        if found:
            yield found


def _load():
    for path in _candidates():
        try:
            lib = ctypes.CDLL(path)
            for name in ("fftw_execute_dft_r2c", "fftw_execute_dft_c2r", "fftw_plan_dft_r2c_1d"):
                getattr(lib, name)
        except (OSError, AttributeError):
            continue
        return lib, path
    return None, None


_lib, library_path = (None, None) if os.environ.get("FASTLINE_PURE_PYFFTW") else _load()
#: whether the compiled FFT path can be used (``FASTLINE_PURE_PYFFTW=1`` forces the fallback)
AVAILABLE = _lib is not None
if AVAILABLE:
    _vp = ctypes.c_void_p
    for _name in ("fftw_plan_dft_r2c_1d", "fftw_plan_dft_c2r_1d"):
        getattr(_lib, _name).restype = _vp
        getattr(_lib, _name).argtypes = [ctypes.c_int, _vp, _vp, ctypes.c_uint]
    _lib.fftw_destroy_plan.restype = None
    _lib.fftw_destroy_plan.argtypes = [_vp]
    _R2C = ctypes.cast(_lib.fftw_execute_dft_r2c, _vp).value
    _C2R = ctypes.cast(_lib.fftw_execute_dft_c2r, _vp).value

_plan_lock = threading.Lock()
#: transform lengths whose plans are kept when not in use (least recently used out); a plan in
#: use by a kernel in any thread is never destroyed. An FFTW_ESTIMATE plan of length N holds
#: ~60 KB at N ~ 2000 (measured as RSS over 300 lengths).
PLANS_KEPT = 16
#: N -> [r2c, c2r, forward plan, backward plan, number of kernels using it now]
_plans: OrderedDict[int, list] = OrderedDict()


def aligned_empty(size: int, dtype=np.float64) -> np.ndarray:
    """An uninitialised 1-D array whose data start on an ``ALIGN``-byte boundary."""
    item = np.dtype(dtype).itemsize
    raw = np.empty(size + ALIGN // item, dtype=dtype)
    skip = (-raw.ctypes.data % ALIGN) // item
    return raw[skip : skip + size]


def _make(N: int) -> list:
    a = aligned_empty(N)
    c = aligned_empty(N // 2 + 1, np.complex128)
    pf = _lib.fftw_plan_dft_r2c_1d(N, a.ctypes.data, c.ctypes.data, _FFTW_ESTIMATE)
    pb = _lib.fftw_plan_dft_c2r_1d(N, c.ctypes.data, a.ctypes.data, _FFTW_ESTIMATE)
    if not pf or not pb:  # pragma: no cover - FFTW refused a plan
        raise RuntimeError(f"FFTW could not plan a real transform of length {N}")
    return [_R2C, _C2R, pf, pb, 0]


def acquire(N: int) -> tuple[int, int, int, int]:
    """``(r2c, c2r, forward plan, backward plan)`` addresses for real transforms of length N,
    pinned until :func:`release` (call it in a ``finally``). Planning and the bookkeeping
    happen under a lock: FFTW's planner is not thread-safe, its execute functions are."""
    with _plan_lock:
        entry = _plans.get(N)
        if entry is None:
            entry = _plans[N] = _make(N)
        entry[4] += 1
        _plans.move_to_end(N)
        if len(_plans) > PLANS_KEPT:
            _evict()
        return entry[0], entry[1], entry[2], entry[3]


def release(N: int) -> None:
    """Unpin the plans of length N (see :func:`acquire`)."""
    with _plan_lock:
        _plans[N][4] -= 1
        if len(_plans) > PLANS_KEPT:
            _evict()


def _evict() -> None:
    """Destroy the least recently used plans not in use, beyond ``PLANS_KEPT`` (lock held)."""
    for N in list(_plans):
        if len(_plans) <= PLANS_KEPT:
            break
        entry = _plans[N]
        if entry[4] == 0:
            _lib.fftw_destroy_plan(entry[2])
            _lib.fftw_destroy_plan(entry[3])
            del _plans[N]


@intrinsic
def execute(typingctx, fn, plan, src, dst):
    """``fn(plan, src, dst)`` for an FFTW new-array execute function at address ``fn``
    (all four arguments int64: function, plan and the two data addresses)."""
    sig = types.void(fn, plan, src, dst)

    def codegen(context, builder, signature, args):
        fn_addr, plan_addr, src_addr, dst_addr = args
        vp = ir.IntType(8).as_pointer()
        fnty = ir.FunctionType(ir.VoidType(), [vp, vp, vp])
        fptr = builder.inttoptr(fn_addr, fnty.as_pointer())
        builder.call(
            fptr,
            [
                builder.inttoptr(plan_addr, vp),
                builder.inttoptr(src_addr, vp),
                builder.inttoptr(dst_addr, vp),
            ],
        )
        return context.get_dummy_value()

    return sig, codegen


#: float64 elements :func:`aligned_views` needs beyond ``2 N`` for transforms of length N (``N``
#: real, ``N + 2`` for the complex half spectrum, up to 16 to reach the alignment of each)
ALIGN_PAD = 2 + 16


def aligned_size(N: int) -> int:
    """float64 elements :func:`aligned_views` needs for transforms of length N."""
    return 2 * N + ALIGN_PAD


@numba.njit(**JIT)
def aligned_views(raw, N):
    """A real buffer of length N and one of length N + 2 for the N/2 + 1 complex values as
    interleaved (real, imaginary) pairs (FFTW's layout), both 64-byte aligned views into
    ``raw`` (float64, at least :func:`aligned_size` ``(N)`` elements), for executing the plans
    of :func:`acquire` from compiled code (no complex dtype needed)."""
    off = (-raw.ctypes.data % 64) // 8
    off2 = off + N + (-N % 8)
    return raw[off : off + N], raw[off2 : off2 + N + 2]


@numba.njit(**JIT)
def aligned_buffers(N):
    """:func:`aligned_views` on a new allocation."""
    return aligned_views(np.empty(N + (N + 2) + 16), N)


if __name__ == "__main__":  # pragma: no cover - a quick check of the set-up
    print(AVAILABLE, library_path, file=sys.stderr)
