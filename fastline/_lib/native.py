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
  with the tuple ``args`` and returns its result of the given Numba type.
"""

from __future__ import annotations

from numba import types
from numba.core import cgutils, errors
from numba.extending import intrinsic

__all__ = ["native_address", "caller"]


def native_address(kernel, argtypes: tuple, return_type) -> int:
    """The address of ``kernel``'s machine code for ``argtypes`` (Numba types), compiled or
    loaded from the on-disk cache as a call would. Raises ``TypeError`` if it does not return
    ``return_type`` (what :func:`caller` declared) and ``RuntimeError`` if Numba has no
    address for it."""
    argtypes = tuple(argtypes)
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
    def call(typingctx, address, args):
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
