"""One place for the Numba settings of every compiled kernel in fastline.

Every kernel is decorated with ``@numba.njit(**JIT)``:

* ``cache`` - compiled machine code is kept on disk next to the sources (or under
  ``NUMBA_CACHE_DIR``), so only the first call in the first process pays the compilation
  (a few seconds for the whole package). Set the environment variable
  ``FASTLINE_NUMBA_CACHE=0`` before importing fastline to switch the on-disk cache off, e.g. on
  a read-only file system or when many processes start at once on a shared network drive.
  Processes of a pool share the cache safely (Numba writes its index atomically; the test
  suite runs a ``ProcessPoolExecutor`` with the cache on).
* ``nogil`` - kernels release the GIL, so threads solving different scenes run in parallel.
* ``fastmath`` - one conservative set: FMA contraction, reciprocal and signed-zero freedom;
  never ``nnan``/``ninf``, so NaN and inf checks inside kernels keep working.
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
"""

from __future__ import annotations

import os

__all__ = ["JIT", "CACHE_ENV"]

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
