"""The JIT decorator used by porenet's kernels, and two low-level helpers for them.

Numba compiles each kernel once per machine and caches the machine code on disk
(``cache=True``), so only the first run after installation pays the compilation (a few
seconds); later processes load the cache. If numba cannot be imported the kernels still run,
as plain (slow) Python, and a warning says so.

:func:`prefetch` asks the CPU to start loading ``array[index]`` into the cache without waiting
for it (a no-op without numba), and :func:`trailing_zeros` is the hardware count of trailing
zero bits of a non-zero 64-bit word (a de Bruijn multiplication where numba's intrinsic is
missing). Use them inside kernels.

Calls between kernels: each kernel is two numba dispatchers of the same function, the one
Python calls (with numba's CPython wrapper, which converts Python objects to machine types)
and a twin that other kernels call, without it and compiled for linking only
(:mod:`porenet.jit.link_only`): a kernel tree is optimised and compiled to machine code
once, at the kernel Python calls (docs/architecture.md). No kernel has numba's C-callable
wrapper (porenet passes no kernel as a first-class function). With link-only compilation
switched off (``PORENET_LINK_ONLY=0``) or unavailable (a numba without the internals it
needs), a kernel is a plain ``numba.njit(**options)`` dispatcher: no twin, nothing rebound.
:func:`variant` compiles a kernel with capability switches off (:data:`THREADS`, and the
viscous model's ``LISTS`` and ``WINDOWS``), for a run that cannot use the code they guard.

Threads: :func:`pjit` compiles a kernel whose ``prange`` loops run on several threads,
:func:`serial_and_parallel` one loop both ways (callers pick by ``THREADS and``
:func:`threaded_box`), and
:func:`set_threads` / :func:`threads` set and read how many threads they use (the results do
not depend on it; docs/architecture.md).
"""

from __future__ import annotations

import logging
from collections.abc import Callable
from types import FunctionType
from typing import Any

import numpy as np

log = logging.getLogger(__name__)

try:
    import numba

    HAVE_NUMBA = True
    # Start numba's threading layer now. A cached kernel that calls a parallel one does not
    # start it when it is loaded from the on-disk cache (numba issue #8578, open): its first
    # call would then crash the process.
    numba.get_num_threads()
    from porenet.jit import link_only
except ImportError:  # pragma: no cover - numba is a core dependency
    numba = None
    HAVE_NUMBA = False
    log.warning("numba is not importable: porenet's kernels run as plain Python (slow)")


def njit(
    func: Callable[..., Any] | None = None, *, helper: bool = False, reassociate: bool = False
) -> Any:
    """``numba.njit(cache=True, nogil=True)`` when numba is available, else identity.

    ``@njit(helper=True)`` marks a small helper that takes arrays but allocates nothing: it is
    compiled without numba's reference counting (``_nrt=False``). Called from a loop, such a
    helper that writes into its array arguments sometimes is not optimised into its caller
    and costs ~16 ns per call instead of ~0.2 ns; without reference counting it never did in
    our measurements (``tests/benchmarks/bench_numba_helpers.py``, where renaming the
    parameters alone switches the slow case on and off).

    ``reassociate=True`` lets the compiler reorder floating-point sums (``fastmath`` flags
    ``reassoc`` and ``nsz`` only: no fused multiply-add, no assumptions about NaN or
    infinity), which is what lets a loop with a running sum use SIMD instructions. The sums
    then differ from the sequential ones in the last bits; use it only for reductions whose
    order carries no meaning.
    """
    if func is None:
        return lambda f: njit(f, helper=helper, reassociate=reassociate)
    if not HAVE_NUMBA:
        return func
    options: dict[str, Any] = {"cache": True, "nogil": True}
    if helper:
        options["_nrt"] = False
    if reassociate:
        options["fastmath"] = {"reassoc", "nsz"}
    return _kernel(func, options)


#: Options of the twin that kernels call: no CPython wrapper (the C-callable one, for passing
#: a kernel to numba's first-class function types, which porenet does not use, is left out of
#: every kernel: ``no_cfunc_wrapper``).
_CALLEE_ONLY = {"no_cpython_wrapper": True}


def _kernel(func: Callable[..., Any], options: dict[str, Any]) -> Any:
    """``numba.njit(**options)(func)``, whose calls from other kernels go to a twin compiled
    without numba's wrappers, for linking only (see the module's docstring) and for plain
    argument types (:func:`_without_literal_variants`). Python calls the returned dispatcher
    as usual. Without :data:`porenet.jit.link_only.PIPELINE` (switched off or unavailable) the
    plain dispatcher, untouched.

    How: numba types a call from a kernel by asking the callee's dispatcher for a call
    template (``get_call_template``, which compiles it for the argument types) and lowers it
    through the dispatcher's ``get_overload``; both are routed to the twin, a dispatcher of
    its own under the name ``<name>_callee``, so that its on-disk cache entry (keyed by the
    function's name, not by the options) never serves a Python call, which would need the
    wrapper (calling a function compiled without it from Python crashes the process)."""
    python_side = numba.njit(**options)(func)
    _OPTIONS[id(python_side)] = (python_side, options)
    if link_only.PIPELINE is None:
        return python_side
    callee_options = dict(options, **_CALLEE_ONLY, pipeline_class=link_only.PIPELINE)
    callee = numba.njit(**callee_options)(_twin(func, "_callee"))
    python_side.get_call_template = _without_literal_variants(
        _compiled_again_on_failure(callee.get_call_template)
    )
    python_side.get_overload = callee.get_overload
    return python_side


def _compiled_again_on_failure(get_call_template: Callable[[Any, Any], Any]) -> Any:
    """A twin's ``get_call_template`` (the only call that compiles a twin) that compiles it
    again when link-only compilation failed on a numba internal
    (:class:`porenet.jit.link_only.LinkOnlyFailure`): link-only compilation is then off in
    this process, so the second compilation is numba's default one, and the failed one left
    nothing numba uses (:mod:`porenet.jit.link_only` says why)."""

    def compiled(args: Any, kws: Any) -> Any:
        try:
            return get_call_template(args, kws)
        except link_only.LinkOnlyFailure:
            return get_call_template(args, kws)

    return compiled


#: id of each kernel's dispatcher -> (the dispatcher, its numba options), for :func:`variant`
_OPTIONS: dict[int, tuple[Any, dict[str, Any]]] = {}
#: (id of a kernel, the switches off) -> its variant (the kernel itself if it reads none)
_VARIANTS: dict[tuple[int, tuple[str, ...]], Any] = {}


def _twin(
    func: Callable[..., Any], suffix: str, namespace: dict[str, Any] | None = None
) -> Callable[..., Any]:
    """A copy of the Python function ``func`` (same code, closure and, unless ``namespace`` is
    given, globals) named ``func.__name__ + suffix``: numba caches each under its own name."""
    twin = FunctionType(
        func.__code__, func.__globals__ if namespace is None else namespace,
        func.__name__ + suffix, func.__defaults__, func.__closure__,
    )  # fmt: skip
    twin.__qualname__ = func.__qualname__ + suffix
    twin.__module__ = func.__module__
    twin.__doc__ = func.__doc__
    twin.__annotations__ = dict(func.__annotations__)
    twin.__kwdefaults__ = func.__kwdefaults__
    return twin


def _without_literal_variants(specialise: Callable[[Any, Any], Any]) -> Callable[[Any, Any], Any]:
    """A dispatcher's ``get_call_template`` that compiles for its arguments' plain types when a
    kernel calls it with constants: numba would compile one variant per literal value
    (``f(.., True)`` and ``f(.., False)``, ``f(0, ..)`` and ``f(n, ..)``), each with all its
    callees: 22 of the 169 compilations of a first viscous run, ~10 % of its compile time, for
    the same bits (docs/performance.md, "First run"). No kernel relies on a literal argument.
    Signed integer scalars narrower than 64 bits are widened likewise (the call converts
    them)."""
    from numba.core import types

    def plain(arg: Any) -> Any:
        arg = types.unliteral(arg)
        if isinstance(arg, types.Integer) and arg.signed and arg.bitwidth < 64:
            return types.int64  # one variant for int32 and int64 scalars (a safe widening)
        return arg

    def get_call_template(args: Any, kws: Any) -> Any:
        return specialise(tuple(plain(a) for a in args), {k: plain(v) for k, v in kws.items()})

    return get_call_template


#: Boxes of at least this many pores are swept by several threads; below, starting them
#: costs more than they save (the crossover is near 64 x 64 pores on 2 threads:
#: ``python tests/benchmarks/bench_threads.py``, docs/performance.md).
PARALLEL_MIN = 4096


@njit(helper=True)
def threaded_box(box: np.ndarray) -> bool:
    """Whether the box (rows ``[box[0], box[1])``, columns ``[box[2], box[3])``) has
    :data:`PARALLEL_MIN` pores or more: its row loops then run on several threads."""
    return (box[1] - box[0]) * (box[3] - box[2]) >= PARALLEL_MIN


#: ``numba.prange`` (a loop whose iterations may run on several threads), ``range`` without
#: numba.
prange = numba.prange if HAVE_NUMBA else range


def pjit(func: Callable[..., Any]) -> Any:
    """``numba.njit(parallel=True, cache=True, nogil=True)`` when numba is available, else
    identity: a kernel whose ``prange`` loops run on up to :func:`threads` threads. Its
    iterations must write disjoint data, and any sum over them is done afterwards, in a fixed
    order (per-iteration partial sums), so that the result does not depend on the number of
    threads to the last bit."""
    if not HAVE_NUMBA:
        return func
    return _kernel(func, {"parallel": True, "cache": True, "nogil": True, "no_cfunc_wrapper": True})


def serial_and_parallel(func: Callable[..., Any]) -> tuple[Any, Any]:
    """Two compilations of one kernel whose loop is a ``prange``: ``(serial, parallel)``, the
    first an ordinary :func:`njit` kernel (numba runs ``prange`` as ``range`` there) for small
    inputs, where starting threads costs more than they save, the second a :func:`pjit` one
    (the same rules apply). Each is cached on disk under its own name. Callers pick the
    parallel one only ``if THREADS and threaded_box(box)`` (:data:`THREADS`)."""
    serial = njit(func)
    if not HAVE_NUMBA:
        return serial, serial
    return serial, pjit(_twin(func, "_parallel"))


#: A capability switch of the kernels (see :func:`variant`): code that only a run with
#: threads needs sits under ``if THREADS and ...``. True here, so the kernels as imported
#: have every capability.
THREADS = True


def variant(kernel: Any, **switches: bool) -> Any:
    """``kernel`` compiled with some capability switches off, for a run that cannot use
    them: ``variant(rkc_advance, THREADS=False)``. ``kernel`` itself if neither it nor a
    kernel it calls reads any of them.

    A switch is a module-level boolean that kernels read in branch conditions (``if THREADS
    and threaded_box(box): ...``): :data:`THREADS` here, ``LISTS`` and ``WINDOWS`` of
    :mod:`porenet.kinds.viscous.kernels.state`. Numba treats a global as a constant and drops a
    branch whose condition is a constant False before it types the code, so the kernels
    called only there are never compiled. Where the switch is off in a variant, the run must
    never need the branch (the caller's promise: e.g. no box of ``PARALLEL_MIN`` pores);
    the code that does run is the same, so the results are the same to the bit
    (``tests/verification/test_kernel_variants.py``), and a first run compiles less
    (docs/performance.md, "First run").

    How: a variant is a copy of the kernel's function (same code) whose globals map each
    switch to its value and each kernel it calls to that kernel's variant; numba compiles and
    caches it under ``<name>_without_<switches>``. Only callees named as globals of the
    kernel's module are seen (porenet's kernels call each other so)."""
    off = tuple(sorted(name for name, value in switches.items() if not value))
    if not HAVE_NUMBA or not off:
        return kernel
    key = (id(kernel), off)
    known = _VARIANTS.get(key)
    if known is not None:
        return known
    func = kernel.py_func
    substitutes: dict[str, Any] = {}
    for name in _global_names(func.__code__):
        value = func.__globals__.get(name)
        if name in off and isinstance(value, bool):
            substitutes[name] = False
        elif value is not None and value is not kernel and id(value) in _OPTIONS:
            callee = variant(value, **dict.fromkeys(off, False))
            if callee is not value:
                substitutes[name] = callee
    if not substitutes:
        _VARIANTS[key] = kernel
        return kernel
    namespace = dict(func.__globals__)
    namespace.update(substitutes)
    suffix = "_without_" + "_".join(name.lower() for name in off)
    compiled = _kernel(_twin(func, suffix, namespace), _OPTIONS[id(kernel)][1])
    _VARIANTS[key] = compiled
    return compiled


def _global_names(code: Any) -> set[str]:
    """The names a code object (and the code objects nested in it) loads as globals or
    attributes (a superset of the globals it reads)."""
    names = set(code.co_names)
    for const in code.co_consts:
        if hasattr(const, "co_names"):
            names |= _global_names(const)
    return names


def set_threads(count: int | None) -> int:
    """Let the parallel kernels use ``count`` threads (None: every core numba sees), at least
    1 and at most numba's limit; returns the number set. Results do not depend on it."""
    if not HAVE_NUMBA:
        return 1
    limit = int(numba.config.NUMBA_NUM_THREADS)
    count = limit if count is None else max(1, min(int(count), limit))
    numba.set_num_threads(count)
    return count


def thread_limit() -> int:
    """The most threads the parallel kernels can use (numba's ``NUMBA_NUM_THREADS``)."""
    return int(numba.config.NUMBA_NUM_THREADS) if HAVE_NUMBA else 1


def threads() -> int:
    """The threads the parallel kernels use now."""
    return int(numba.get_num_threads()) if HAVE_NUMBA else 1


def _prefetch_py(array: np.ndarray, index: int) -> None:
    """Stand-in for :func:`prefetch` without numba: does nothing."""


_DEBRUIJN = np.uint64(0x03F79D71B4CB0A89)
_DEBRUIJN_TABLE = np.array(
    [
        0, 1, 48, 2, 57, 49, 28, 3, 61, 58, 50, 42, 38, 29, 17, 4,
        62, 55, 59, 36, 53, 51, 43, 22, 45, 39, 33, 30, 24, 18, 12, 5,
        63, 47, 56, 27, 60, 41, 37, 16, 54, 35, 52, 21, 44, 32, 23, 11,
        46, 26, 40, 15, 34, 20, 31, 10, 25, 14, 19, 9, 13, 8, 7, 6,
    ],
    dtype=np.uint64,
)  # fmt: skip


@njit
def _trailing_zeros_debruijn(word: np.uint64) -> np.uint64:
    """Stand-in for :func:`trailing_zeros` without numba's intrinsic: de Bruijn
    multiplication (``word`` must be non-zero)."""
    isolated = word & (~word + np.uint64(1))
    return _DEBRUIJN_TABLE[(isolated * _DEBRUIJN) >> np.uint64(58)]


prefetch: Callable[[np.ndarray, int], None] = _prefetch_py
trailing_zeros: Callable[[np.uint64], np.uint64] = _trailing_zeros_debruijn

if HAVE_NUMBA:
    from llvmlite import ir
    from numba.core import cgutils, types
    from numba.extending import intrinsic

    try:  # numba's count-trailing-zeros intrinsic (llvm.cttz), internal but long-standing
        from numba.cpython.unsafe.numbers import trailing_zeros as _numba_trailing_zeros
    except ImportError:  # pragma: no cover
        _numba_trailing_zeros = _trailing_zeros_debruijn

    @intrinsic
    def _prefetch_intrinsic(typingctx: Any, array: Any, index: Any) -> Any:
        """``prefetch(array, index)``: LLVM's ``llvm.prefetch`` (read, keep in all caches) of
        the element's address. Not bounds-checked, which is harmless: a prefetch never faults."""
        if not isinstance(array, types.Array) or not isinstance(index, types.Integer):
            return None

        def codegen(context: Any, builder: Any, signature: Any, args: Any) -> Any:
            ary = context.make_array(signature.args[0])(context, builder, args[0])
            address = builder.gep(ary.data, [args[1]])
            i8p = ir.IntType(8).as_pointer()
            i32 = ir.IntType(32)
            fnty = ir.FunctionType(ir.VoidType(), [i8p, i32, i32, i32])
            fn = cgutils.get_or_insert_function(builder.module, fnty, "llvm.prefetch.p0i8")
            builder.call(fn, [builder.bitcast(address, i8p), i32(0), i32(3), i32(1)])
            return context.get_dummy_value()

        return types.void(array, index), codegen

    prefetch = _prefetch_intrinsic
    trailing_zeros = _numba_trailing_zeros
