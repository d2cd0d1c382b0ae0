"""One compiled kernel calling another through its machine-code address.

When a Numba kernel calls another, Numba links the callee's LLVM code into the caller's and
optimises and compiles it there again: the callee is compiled once for itself and once more
inside every kernel that calls it, and the caller cannot be compiled before its callee. A call
through an address avoids both: the callee is compiled (or loaded from the on-disk cache) on its
own, the caller gets its address as an argument (an int64, never baked into the cached machine
code) and calls it with Numba's own calling convention (:func:`caller`), exceptions
propagated as in a direct call. The two can then be compiled independently, even in two
processes at once.

* :func:`native_address` - compile a kernel for given argument types (or load it from the
  cache) and return the address of its machine code;
* :func:`caller` - an intrinsic ``call(address, args)`` that calls the kernel at ``address``
  with the tuple ``args`` and returns its result of the given Numba type;
* :func:`compile_elsewhere` - when the on-disk cache does not hold such a kernel
  (:func:`cache_serves`), compile it in a second Python process meanwhile, into the cache, so
  that :func:`native_address` then loads it instead of compiling it (on a machine with more
  than one core, with the cache on; ``FASTLINE_PARALLEL_COMPILE=0`` switches it off).
"""

from __future__ import annotations

import os
import subprocess
import sys
import threading

from numba import typeof, types
from numba.core import cgutils, errors
from numba.extending import intrinsic

__all__ = [
    "native_address",
    "caller",
    "cache_serves",
    "compile_elsewhere",
    "compile_meanwhile",
    "PARALLEL_ENV",
]

#: environment variable that switches compiling in a second process off when set to 0/false/no/off
PARALLEL_ENV = "FASTLINE_PARALLEL_COMPILE"
#: most seconds :func:`native_address` waits for a second process before it compiles itself
WAIT_SECONDS = 600
#: (kernel, argument types) -> the process compiling it (:func:`compile_elsewhere`)
_elsewhere: dict = {}
_lock = threading.Lock()


def native_address(kernel, argtypes: tuple, return_type) -> int:
    """The address of ``kernel``'s machine code for ``argtypes`` (Numba types), compiled or
    loaded from the on-disk cache as a call would. Raises ``TypeError`` if it does not return
    ``return_type`` (what :func:`caller` declared) and ``RuntimeError`` if Numba has no
    address for it."""
    argtypes = tuple(argtypes)
    with _lock:
        proc = _elsewhere.get((kernel, argtypes))
    if proc is not None:  # compiled there, into the cache: wait, then load it from the cache
        try:
            proc.wait(WAIT_SECONDS)
        except subprocess.TimeoutExpired:  # pragma: no cover - a stuck process: compile here
            proc.kill()
        with _lock:  # after the wait: other threads asking meanwhile wait for it too
            _elsewhere.pop((kernel, argtypes), None)
    kernel.compile(argtypes)
    result = kernel.overloads[argtypes]
    if result.signature.return_type != return_type:
        raise TypeError(
            f"{kernel.py_func.__qualname__} returns {result.signature.return_type}, "
            f"not {return_type}"
        )
    address = result.library.get_pointer_to_function(result.fndesc.llvm_func_name)
    if not address:  # pragma: no cover - a Numba release with another code library
        raise RuntimeError(f"no machine code address for {kernel.py_func.__qualname__}")
    return address


def caller(return_type, argtypes_check=None):
    """An intrinsic ``call(address, args)``: call the compiled kernel at ``address``
    (:func:`native_address`) with the arguments in the tuple ``args``; it returns
    ``return_type``. ``argtypes_check(types) -> str``: optional, a message when the argument
    types are not those the kernel is compiled for (a typing error then)."""

    @intrinsic
    def call(typingctx: object, address: types.Type, args: types.Type) -> tuple | None:
        if not isinstance(address, types.Integer) or not isinstance(args, types.BaseTuple):
            return None
        argtys = list(args.types)
        if argtypes_check is not None:
            problem = argtypes_check(argtys)
            if problem:
                raise errors.TypingError(problem)

        def codegen(context, builder, signature, llargs):
            fnty = context.call_conv.get_function_type(return_type, argtys)
            fn = builder.inttoptr(llargs[0], fnty.as_pointer())
            values = cgutils.unpack_tuple(builder, llargs[1], len(argtys))
            status, out = context.call_conv.call_function(builder, fn, return_type, argtys, values)
            with cgutils.if_unlikely(builder, status.is_error):
                context.call_conv.return_status_propagate(builder, status)
            return out

        return return_type(address, args), codegen

    return call


def cache_serves(kernel, argtypes: tuple) -> bool:
    """Whether Numba's on-disk cache holds ``kernel`` compiled for ``argtypes`` on this machine
    (its index has the entry; True when the cache is off or this cannot be told, so that
    nothing more is done than a call would do). Reads Numba's private cache index, about 1 ms."""
    try:
        cache = kernel._cache
        key = cache._index_key(tuple(argtypes), kernel.targetctx.codegen())
        return key in cache._cache_file._load_index()
    except Exception:  # the cache off (a NullCache), or another Numba release's layout
        return True


def _parallel_allowed() -> bool:
    if os.environ.get(PARALLEL_ENV, "1").strip().lower() in ("0", "false", "no", "off"):
        return False
    cpus = len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else os.cpu_count()
    name = os.path.basename(sys.executable or "").lower()
    return (cpus or 1) > 1 and name.startswith(("python", "pypy"))


def compile_elsewhere(kernel, argtypes: tuple, statement: str, package_parent: str) -> bool:
    """Compile ``kernel`` for ``argtypes`` into the on-disk cache in a second process, now, if
    the cache does not hold it (:func:`cache_serves`) and more than one CPU is usable: run
    ``statement`` (Python that compiles it, e.g. by a call) in a new interpreter that imports
    the fastline under ``package_parent``, with this process's environment (so the same
    ``NUMBA_CACHE_DIR``). :func:`native_address` waits for it and loads the kernel from the
    cache. Returns whether a process was started."""
    argtypes = tuple(argtypes)
    with _lock:
        if (kernel, argtypes) in _elsewhere or kernel.overloads.get(argtypes) is not None:
            return False
        if not _parallel_allowed() or cache_serves(kernel, argtypes):
            return False
        env = dict(os.environ)
        env[PARALLEL_ENV] = "0"  # the helper compiles only what it is asked to
        env["PYTHONPATH"] = os.pathsep.join(
            p for p in (package_parent, env.get("PYTHONPATH", "")) if p
        )
        _elsewhere[(kernel, argtypes)] = subprocess.Popen(
            # the path set first in the script: ``-c`` puts the working directory ahead of
            # PYTHONPATH, where another fastline (a source checkout) may lie
            [
                sys.executable,
                "-c",
                f"import sys\nsys.path.insert(0, {package_parent!r})\n{statement}",
            ],
            env=env,
            stdin=subprocess.DEVNULL,
            stdout=subprocess.DEVNULL,
            stderr=subprocess.DEVNULL,
        )
        return True


def compile_meanwhile(kernel, args: tuple) -> None:
    """While a second process compiles a kernel that :func:`native_address` will wait for,
    compile ``kernel`` (the one that calls it by address) for the types of the values ``args``
    now, without calling it, so that the two compile at once; nothing when no process runs."""
    if _elsewhere:
        kernel.compile(tuple(typeof(a) for a in args))
