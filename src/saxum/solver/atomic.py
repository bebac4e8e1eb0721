"""Atomic operations on int64 array elements inside numba kernels, for threads that hand work
to each other within one parallel region (saxum.solver.nlgs.nlgs_2d_domains): numba has
none on the CPU, so these emit LLVM's atomic instructions (cmpxchg, load atomic acquire,
store atomic release: the C++11 memory model's, which LLVM maps to each processor).

A store with release order followed, in another thread, by a load with acquire order that
reads it makes every write before the store visible to every read after the load."""

import os

from llvmlite import ir
from numba import types
from numba.core import cgutils
from numba.extending import intrinsic

__all__ = ["claim", "load_acquire", "relax", "store_release"]


def _element(context, builder, aryty, ary, index, indexty):
    """Pointer to ary[index] (no bounds check: the callers index their own arrays)."""
    array = context.make_array(aryty)(context, builder, ary)
    index = context.cast(builder, index, indexty, types.intp)
    return cgutils.get_item_pointer(context, builder, aryty, array, [index])


def _int64_vector(ary, index) -> bool:
    return (isinstance(ary, types.Array) and ary.ndim == 1 and ary.dtype == types.int64
            and ary.mutable and isinstance(index, types.Integer))


@intrinsic
def load_acquire(typingctx, ary, index):
    """ary[index] (int64), read with acquire order."""
    if not _int64_vector(ary, index):
        return None

    def codegen(context, builder, sig, args):
        ptr = _element(context, builder, sig.args[0], args[0], args[1], sig.args[1])
        return builder.load_atomic(ptr, "acquire", 8)

    return types.int64(ary, index), codegen


@intrinsic
def store_release(typingctx, ary, index, value):
    """ary[index] = value (int64), written with release order."""
    if not (_int64_vector(ary, index) and isinstance(value, types.Integer)):
        return None

    def codegen(context, builder, sig, args):
        ptr = _element(context, builder, sig.args[0], args[0], args[1], sig.args[1])
        val = context.cast(builder, args[2], sig.args[2], types.int64)
        builder.store_atomic(val, ptr, "release", 8)
        return context.get_dummy_value()

    return types.void(ary, index, value), codegen


@intrinsic
def claim(typingctx, ary, index, expected, value):
    """Whether this thread set ary[index] from `expected` to `value` (int64, compare and
    exchange, acquire-release order): of threads that try the same change at once, exactly
    one succeeds."""
    if not (_int64_vector(ary, index) and isinstance(expected, types.Integer)
            and isinstance(value, types.Integer)):
        return None

    def codegen(context, builder, sig, args):
        ptr = _element(context, builder, sig.args[0], args[0], args[1], sig.args[1])
        old = context.cast(builder, args[2], sig.args[2], types.int64)
        new = context.cast(builder, args[3], sig.args[3], types.int64)
        pair = builder.cmpxchg(ptr, old, new, "acq_rel", "acquire")
        return builder.extract_value(pair, 1)

    return types.boolean(ary, index, expected, value), codegen


_POSIX = os.name == "posix"


@intrinsic
def relax(typingctx):
    """Lets another thread of this core run (POSIX sched_yield; nothing elsewhere): for a
    thread that has waited long for another, which may be waiting for a time slice."""

    def codegen(context, builder, sig, args):
        if _POSIX:
            fn = cgutils.get_or_insert_function(
                builder.module, ir.FunctionType(ir.IntType(32), []), "sched_yield")
            builder.call(fn, [])
        return context.get_dummy_value()

    return types.void(), codegen
