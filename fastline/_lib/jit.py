"""One place for the Numba settings of every compiled kernel in fastline.

Every kernel is decorated with ``@numba.njit(**JIT)``:

* ``cache`` - compiled machine code is kept on disk next to the sources (or under
  ``NUMBA_CACHE_DIR``), so only the first call in the first process pays the compilation
  (~25 s of CPU for the line solver, split between two processes on a machine with more
  than one core (:mod:`fastline._lib.native`), once per installation; ``fastline compile``
  pays it ahead of time, for every kernel, at once). Set the
  environment variable ``FASTLINE_NUMBA_CACHE=0`` before importing fastline to switch the
  on-disk cache off, e.g. on a read-only file system or when many processes start at once on
  a shared network drive. Processes of a pool share the cache safely (Numba writes its index
  atomically; the test suite runs a ``ProcessPoolExecutor`` with the cache on).
* ``nogil`` - kernels release the GIL, so threads solving different scenes run in parallel.
* ``fastmath`` - one conservative set: FMA contraction, reciprocal and signed-zero freedom;
  never ``nnan``/``ninf``, so NaN and inf checks inside kernels keep working. ``JIT_SUMS``
  adds ``reassoc`` for kernels that are nothing but sums of products (the coarse level's
  correlations, :func:`fastline.elastic.preconditioner._edge_correlations`): LLVM may then reorder
  their additions into vector lanes (2.6-2.9x faster there). Their results stay the same on
  every run of the same machine (the order is fixed when the kernel is compiled for its CPU,
  and Numba's cache is keyed by the CPU), but change in the last bits on a CPU with other
  vector widths - as FFTW's transforms already do.
* ``error_model="numpy"`` - a division by zero gives inf or NaN (as in NumPy) instead of a
  ``ZeroDivisionError`` path in every division; kernels guard their own divisions and the
  public functions validate their inputs. With it, and with element loops instead of slice
  assignments (whose shape-mismatch error message Numba compiles too), the first compilation
  of the line contact's Newton fell from 12.9 to 9.5 s of CPU (empty ``NUMBA_CACHE_DIR``).
* ``no_cfunc_wrapper`` - no C-callback wrapper per kernel (nothing passes a kernel as a
  first-class function): less to compile cold. The Python wrapper stays on every kernel, inner
  ones included: without it (``no_cpython_wrapper``) calling an inner kernel from Python, in a
  test, a benchmark or a REPL, crashes the interpreter, and the cold start gained less than
  this machine's noise (~1 s in 12).

Cache freshness: Numba keys a kernel's cached machine code by the source file that defines
it, but a kernel's code also holds every kernel it calls, compiled in, from other files: edit
``elastic/pcg.py`` and the cached ``newton_line`` of ``contact/line_newton.py`` would keep
running the old Newton-system solver. fastline's kernels are therefore stamped with the whole
package (:func:`package_stamp`: the relative path and the contents of every ``.py`` file), so
any change to any module recompiles them all. The stamp follows the contents only, not the
files' sizes, modification times or place: an installation copied elsewhere (a container
image layer, an install with pip's ``--target``, a shared network install) keeps its compiled
kernels.
Numba adds the CPU's name and features and the Numba and Python versions to each entry; where
those differ, the kernels are compiled anew.

The first compilation in a process (a cache miss: a fresh installation, another CPU, an
edited source, ``FASTLINE_NUMBA_CACHE=0``) is announced once, before it starts, by a message
of level WARNING on the logger ``"fastline"`` (:data:`NOTICE`; with no logging configured,
Python prints it on stderr). Silence it with
``logging.getLogger("fastline").setLevel(logging.ERROR)``. ``fastline compile`` (or
:func:`fastline.compile_kernels`) compiles every kernel ahead of time.
"""

from __future__ import annotations

import functools
import hashlib
import logging
import os

__all__ = ["JIT", "JIT_SUMS", "CACHE_ENV", "NOTICE", "package_stamp", "compile_notice_given"]

#: the package's directory (the parent of _lib): kernels defined below it get the package-wide stamp
_ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))

#: environment variable that switches the on-disk cache off when set to 0/false/no/off
CACHE_ENV = "FASTLINE_NUMBA_CACHE"


def _cache_enabled() -> bool:
    return os.environ.get(CACHE_ENV, "1").strip().lower() not in ("0", "false", "no", "off")


#: keyword arguments of ``numba.njit`` shared by every kernel of the package
JIT = dict(
    cache=_cache_enabled(),
    nogil=True,
    fastmath={"contract", "arcp", "nsz"},
    error_model="numpy",
    no_cfunc_wrapper=True,
)
#: :data:`JIT` with reassociation allowed: for kernels that only sum products (module docstring)
JIT_SUMS = dict(JIT, fastmath={"contract", "arcp", "nsz", "reassoc"})


@functools.cache
def package_stamp(root: str = _ROOT) -> str:
    """A digest of every ``.py`` file under ``root``: its path relative to ``root`` and its
    contents (not its size, modification time or absolute place, so that a copied installation
    keeps its cache). Computed once per process (~60 files, about 2 ms)."""
    digest = hashlib.sha256()
    for dirpath, dirnames, filenames in os.walk(root):
        dirnames[:] = sorted(d for d in dirnames if d != "__pycache__")
        for name in sorted(filenames):
            if name.endswith(".py"):
                path = os.path.join(dirpath, name)
                rel = os.path.relpath(path, root).replace(os.sep, "/")
                with open(path, "rb") as f:
                    body = hashlib.sha256(f.read()).hexdigest()
                digest.update(f"{rel}:{body};".encode())
    return digest.hexdigest()


class _PackageStampedLocator:
    """The cache locator Numba would choose for a kernel of fastline (same directory, same
    file names), with :func:`package_stamp` added to its source stamp (module docstring)."""

    def __init__(self, inner) -> None:
        self._inner = inner

    def __getattr__(self, name: str):
        return getattr(self._inner, name)

    def get_source_stamp(self):
        return (self._inner.get_source_stamp(), package_stamp())

    @classmethod
    def from_function(cls, py_func, py_file: str):
        if not os.path.abspath(py_file).startswith(_ROOT + os.sep):
            return None
        for other in _numba_locators():
            if other is not cls:
                found = other.from_function(py_func, py_file)
                if found is not None:
                    return cls(found)
        return None


def _numba_locators() -> list:
    from numba.core import caching

    impl = getattr(caching, "CacheImpl", None) or getattr(caching, "_CacheImpl", None)
    return impl._locator_classes if impl is not None else []


def _install_locator() -> None:
    """Put :class:`_PackageStampedLocator` first in Numba's list of cache locators (a class
    attribute of Numba's private ``CacheImpl``; if a Numba release renames it, kernels keep
    Numba's own per-file stamps)."""
    try:
        locators = _numba_locators()
    except ImportError:  # pragma: no cover - numba is a dependency
        return
    if locators is not None and _PackageStampedLocator not in locators:
        locators.insert(0, _PackageStampedLocator)


#: what the first compilation of a process says (logger ``"fastline"``, level WARNING)
NOTICE = (
    "fastline: compiling the solver for this machine, once: ~{seconds} s{why} "
    "(`fastline compile` does it ahead of time; docs/performance.md, cold start)"
)
#: seconds of the line contact's first compilation, the notice's estimate: ~25 s of CPU measured
#: on a loaded 2-core x86-64 machine by Numba's event API (``python -m bench.compile_profile``),
#: split between two processes on more than one core (the longer ~10-13 s), in one on one core
COMPILE_SECONDS = 15
_log = logging.getLogger("fastline")
_notice = {"given": False}


def compile_notice_given() -> bool:
    """Whether this process has announced a compilation (:data:`NOTICE`)."""
    return _notice["given"]


def _why(dispatcher) -> str:
    """`` (the compiled kernels found here ...)`` when this kernel has a cache index that did not
    serve this machine (another CPU, Numba, Python or source), else ``""``."""
    try:
        index = dispatcher._cache._cache_file._index_path  # Numba's private cache layout
    except AttributeError:
        return ""
    if not os.path.exists(index):
        return ""
    return " (the compiled kernels found were built for another CPU, Numba, Python or source)"


def _on_compile(dispatcher) -> None:
    """Announce the process's first compilation of a fastline kernel, once (module docstring)."""
    if _notice["given"] or not dispatcher.py_func.__module__.startswith("fastline."):
        return
    _notice["given"] = True
    _log.warning(NOTICE.format(seconds=COMPILE_SECONDS, why=_why(dispatcher)))


def _install_notice() -> None:
    """Listen to Numba's ``numba:compile`` event, which starts only on a cache miss."""
    from numba.core import event

    class _Notice(event.Listener):
        def on_start(self, ev) -> None:
            _on_compile(ev.data["dispatcher"])

        def on_end(self, ev) -> None:
            pass

    event.register("numba:compile", _Notice())


if JIT["cache"]:
    _install_locator()
_install_notice()
