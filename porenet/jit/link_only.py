"""Kernels that only other kernels call are compiled for linking only.

Numba compiles every jitted function into a *library* of its own: it optimises the function's
module with everything it calls linked in, then generates machine code for it. A kernel called
from another kernel is linked into its caller as LLVM IR, and the caller's library is optimised
and compiled again with it inside; so in a call tree of depth ``d`` the innermost loops are
optimised ``d + 1`` times and compiled to machine code ``d + 1`` times, although only the
machine code of the outermost function (the one Python calls) is ever run. On a first viscous
run that repetition was about a third of the compile time (docs/performance.md, "First run").

:class:`LinkOnlyLibrary` is the library of a kernel that only kernels call (the ``_callee``
twin of :mod:`porenet.jit.jit`): it links its callees' IR as numba does, but neither
optimises its module as a whole nor generates its machine code; its caller, which links it,
does both, once, for the whole tree. The library still enters numba's execution engine, with
only the kernel's *environment* (the global through which numba's runtime reaches a function's
Python-level data), so that everything numba does with a compiled function (set its
environment, cache it on disk as object code plus IR for linking, load it from the cache) works
unchanged. :data:`PIPELINE` is the numba compiler pipeline (numba's default one with one pass
added) that gives a kernel this library; :mod:`porenet.jit.jit` passes it as
``pipeline_class`` to the twins.

What this relies on in numba beyond its public API (``pipeline_class``, compiler passes):
``JITCodeLibrary`` and its attributes ``_linking_libraries``, ``_final_module``,
``_reload_init``, ``_get_module_for_linking``, ``_raise_if_finalized``,
``_finalize_dynamic_globals``, ``_verify_declare_only_symbols``, ``enable_object_caching``,
``_get_compiled_object``, ``_codegen`` (``_add_module``, ``_engine.finalize_object``,
``_create_empty_module``), the mark ``CPUCodeLibrary`` puts on a module for its object-cache
hooks (:data:`_MARK`), the pass state's ``library``, ``targetctx`` and ``func_id``, and the
dispatcher's ``get_call_template`` and ``get_overload`` (rebound by :mod:`porenet.jit.jit`).
Tested with numba up to the bound in pyproject.toml.

When it is not used (all three cases are safe; none changes what a kernel computes):

* **Switched off**, ``PORENET_LINK_ONLY=0`` in the environment: :data:`PIPELINE` is None and
  nothing is patched: :mod:`porenet.jit.jit` makes every kernel a plain ``numba.njit``
  dispatcher (no twin, no rebound method), exactly numba's default compilation.
* **Unavailable**, numba lacks one of the class-level internals :func:`_build` checks on
  import (a method, the mark read by the object-cache hook, the dispatcher's methods): the same
  as switched off, with the notice below.
* **Failed at compile time**: anything else that differs (an instance attribute renamed, a
  method whose signature changed, the mark no longer read) raises inside the pass or
  :meth:`LinkOnlyLibrary.finalize`. That exception switches link-only off for the rest of the
  process (:func:`active` is then False, and the pass leaves every later library to numba),
  logs the notice and is raised as :class:`LinkOnlyFailure`; the twin's ``get_call_template``
  in :mod:`porenet.jit.jit`, the only place that compiles a twin, catches it and compiles the
  twin again, now as numba does by default (still without CPython wrapper).

The notice is one ``logging`` warning per process, naming what failed and saying that kernels
compile as numba does by default (slower to compile, the same machine code up to the order in
which LLVM sees it).

Why a failed compilation is redone rather than finished: calling the base ``finalize`` on the
half-finalized library is safe only if the failure came before any change to it, and a method
whose signature changed fails after the callees were linked in or after the environment
entered the execution engine. Compiling again is safe wherever the failure came: the exception
leaves numba's ``Dispatcher.compile`` before the result is registered (``add_overload``,
``insert_user_function``) or cached (``save_overload``); :class:`LinkOnlyFailure` is not a
``TypingError``, so numba does not remember the failure; the new compilation starts from the
bytecode and names its symbols with a new unique id, so whatever the failed library left in the
engine is never referenced. Libraries finalized link-only before the failure are complete and
are linked by their callers like any library. A twin compiled after the failure is cached on
disk like any numba function; cache entries of either kind load in either mode. The cost is
one wasted compilation, once per process (``tests/unit/kernels/test_link_only_fallback.py``).
"""

from __future__ import annotations

import logging
import os
import weakref
from typing import Any

log = logging.getLogger(__name__)

#: Prefix of the names numba gives the global that holds a function's environment
#: (``numba.core.base.BaseContext.get_env_name``).
_ENV_PREFIX = "_ZN08NumbaEnv"

#: The attribute ``CPUCodeLibrary`` sets on an LLVM module to tell its object-cache hooks
#: which library the module's object code belongs to (``self._final_module.__library`` inside
#: that class, so name-mangled).
_MARK = "_CPUCodeLibrary__library"


class LinkOnlyFailure(Exception):
    """Link-only compilation failed on a numba internal and is now off in this process: the
    kernel being compiled must be compiled again (numba's default). Not a numba error, so that
    numba neither wraps nor remembers it."""


#: What made link-only compilation fail in this process (None while it has not).
_failed: str | None = None
_noticed = False


def _notice(what: str) -> None:
    """The one-line notice, once per process."""
    global _noticed
    if _noticed:
        return
    _noticed = True
    try:
        import numba

        version = numba.__version__
    except Exception:  # pragma: no cover
        version = "?"
    log.warning(
        "porenet: kernels compile as numba does by default (link-only compilation off with "
        "numba %s: %s)",
        version,
        what,
    )


def _fail(where: str, exc: BaseException) -> LinkOnlyFailure:
    """Switch link-only compilation off for the rest of the process; the exception to raise."""
    global _failed
    if _failed is None:
        _failed = f"{where}: {type(exc).__name__}: {exc}"
        _notice(_failed)
    return LinkOnlyFailure(_failed)


def _build() -> tuple[Any, Any, str | None]:
    """``(pipeline class, library class, None)``, or ``(None, None, what is missing)`` when
    numba's class-level internals differ from what link-only compilation needs."""
    from numba.core import codegen as nb_codegen
    from numba.core import compiler, dispatcher, typed_passes
    from numba.core.compiler_machinery import AnalysisPass, register_pass

    library_base = nb_codegen.JITCodeLibrary
    needed = (
        "finalize",
        "_finalize_dynamic_globals",
        "_verify_declare_only_symbols",
        "_get_module_for_linking",
        "_raise_if_finalized",
        "enable_object_caching",
        "_get_compiled_object",
    )
    missing = [f"JITCodeLibrary.{name}" for name in needed if not hasattr(library_base, name)]
    missing += [
        f"Dispatcher.{name}"
        for name in ("get_call_template", "get_overload")
        if not hasattr(dispatcher.Dispatcher, name)
    ]
    hook = getattr(nb_codegen.CPUCodeLibrary, "_object_compiled_hook", None)
    if _MARK not in getattr(getattr(hook, "__code__", None), "co_names", ()):
        missing.append(f"the module mark {_MARK} read by CPUCodeLibrary._object_compiled_hook")
    if missing:
        return None, None, "missing " + ", ".join(missing)

    class LinkOnlyLibrary(library_base):  # type: ignore[misc, valid-type]
        """A numba library that links its callees and is neither optimised as a whole nor
        compiled to machine code (see the module's docstring). Only its environment globals
        enter the execution engine."""

        def finalize(self) -> None:
            try:
                self._finalize_link_only()
            except Exception as exc:
                raise _fail("finalize", exc) from exc

        def _finalize_link_only(self) -> None:
            nb_codegen.require_global_compiler_lock()
            self._raise_if_finalized()
            seen: set[int] = set()
            for library in self._linking_libraries:  # as CPUCodeLibrary.finalize links them
                if id(library) in seen:
                    continue
                seen.add(id(library))
                self._reload_init.update(library._reload_init)
                self._final_module.link_in(library._get_module_for_linking(), preserve=True)
            self._final_module.verify()
            self._finalize_dynamic_globals()
            self._verify_declare_only_symbols()
            environments = _environment_module(self)
            # the mark the object-cache hooks read, so that the environments' object code is
            # kept for the on-disk cache
            setattr(environments, _MARK, weakref.proxy(self))
            self._codegen._add_module(environments)
            self._codegen._engine.finalize_object()
            try:
                self._get_compiled_object()
            except (RuntimeError, ValueError) as exc:
                raise RuntimeError(f"the object-cache hooks did not read the mark {_MARK}") from exc
            self._finalized = True

    def _environment_module(library: Any) -> Any:
        """An LLVM module that defines only ``library``'s environment globals (null, as numba
        declares them: ``common`` linkage, filled in by ``set_env``)."""
        import llvmlite.binding as ll

        empty = str(library._codegen._create_empty_module(library.name + ".environments"))
        lines = [empty]
        for gv in library._final_module.global_variables:
            if gv.name.startswith(_ENV_PREFIX) and not gv.is_declaration:
                lines.append(f'@"{gv.name}" = common global i8* null')
        module = ll.parse_assembly("\n".join(lines))
        module.name = library.name + ".environments"
        return module

    @register_pass(mutates_CFG=False, analysis_only=True)
    class LinkOnlyLibraryPass(AnalysisPass):  # type: ignore[misc, valid-type]
        """Give the function a :class:`LinkOnlyLibrary` before numba's lowering makes it the
        default one (unless link-only compilation failed in this process: numba's library)."""

        _name = "porenet_link_only_library"

        def __init__(self) -> None:
            AnalysisPass.__init__(self)

        def run_pass(self, state: Any) -> bool:
            if _failed is not None:
                return False
            try:
                if state.library is None:
                    codegen = state.targetctx.codegen()
                    library = LinkOnlyLibrary(codegen, state.func_id.func_qualname)
                    library.enable_object_caching()
                    state.library = library
            except Exception as exc:
                raise _fail("pass", exc) from exc
            return False

    class LinkOnlyCompiler(compiler.CompilerBase):  # type: ignore[misc, valid-type]
        """Numba's default nopython pipeline, with :class:`LinkOnlyLibraryPass` after type
        inference."""

        def define_pipelines(self) -> list[Any]:
            pm = compiler.DefaultPassBuilder.define_nopython_pipeline(self.state)
            pm.add_pass_after(LinkOnlyLibraryPass, typed_passes.NopythonTypeInference)
            pm.finalize()
            return [pm]

    return LinkOnlyCompiler, LinkOnlyLibrary, None


def available() -> bool:
    """Whether kernels that only kernels call have twins compiled for linking only (False when
    switched off or unavailable; see :func:`active` for a failure at compile time)."""
    return PIPELINE is not None


def active() -> bool:
    """Whether new twins are compiled for linking only in this process: :func:`available` and
    no link-only compilation has failed."""
    return PIPELINE is not None and _failed is None


def _pipeline() -> tuple[Any, Any]:
    if os.environ.get("PORENET_LINK_ONLY", "1").strip() == "0":
        return None, None
    try:
        pipeline, library, missing = _build()
    except Exception as exc:  # a numba whose internals differ
        pipeline, library, missing = None, None, f"{type(exc).__name__}: {exc}"
    if missing is not None:
        _notice(missing)
    return pipeline, library


#: The numba compiler class for kernels that only kernels call, or None: switched off or
#: unavailable, every kernel is a plain numba dispatcher.
PIPELINE: Any
#: The library class :data:`PIPELINE` gives them (None with it).
LinkOnlyLibrary: Any
PIPELINE, LinkOnlyLibrary = _pipeline()
