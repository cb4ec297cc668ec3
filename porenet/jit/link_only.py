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
``_reload_init``, ``_finalize_dynamic_globals``, ``_verify_declare_only_symbols``, ``_codegen``
(``_add_module``, ``_engine``, ``_create_empty_module``) and the way ``CPUCodeLibrary`` marks a
module with its library for the object-cache hooks. :func:`available` checks them when the
module is imported; if numba lacks any, :data:`PIPELINE` is None and every kernel is compiled
as numba does by default (slower to compile, the same machine code).
``PORENET_LINK_ONLY=0`` in the environment also switches it off, for comparing the two.
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


def _build() -> Any:
    """The pipeline class, or None when numba's internals differ from what it needs."""
    from numba.core import codegen as nb_codegen
    from numba.core import compiler, typed_passes
    from numba.core.compiler_machinery import AnalysisPass, register_pass

    library_base = nb_codegen.JITCodeLibrary
    needed = (
        "_finalize_dynamic_globals",
        "_verify_declare_only_symbols",
        "_get_module_for_linking",
        "_raise_if_finalized",
        "enable_object_caching",
    )
    if not all(hasattr(library_base, name) for name in needed):
        return None

    class LinkOnlyLibrary(library_base):  # type: ignore[misc, valid-type]
        """A numba library that links its callees and is neither optimised as a whole nor
        compiled to machine code (see the module's docstring). Only its environment globals
        enter the execution engine."""

        def finalize(self) -> None:
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
            # the mark CPUCodeLibrary puts on its module, read by the object-cache hooks
            # (name-mangled inside that class), so that the environments' object code is kept
            # for the on-disk cache
            environments._CPUCodeLibrary__library = weakref.proxy(self)
            self._codegen._add_module(environments)
            self._codegen._engine.finalize_object()
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
        default one."""

        _name = "porenet_link_only_library"

        def __init__(self) -> None:
            AnalysisPass.__init__(self)

        def run_pass(self, state: Any) -> bool:
            if state.library is None:
                library = LinkOnlyLibrary(state.targetctx.codegen(), state.func_id.func_qualname)
                library.enable_object_caching()
                state.library = library
            return False

    class LinkOnlyCompiler(compiler.CompilerBase):  # type: ignore[misc, valid-type]
        """Numba's default nopython pipeline, with :class:`LinkOnlyLibraryPass` after type
        inference."""

        def define_pipelines(self) -> list[Any]:
            pm = compiler.DefaultPassBuilder.define_nopython_pipeline(self.state)
            pm.add_pass_after(LinkOnlyLibraryPass, typed_passes.NopythonTypeInference)
            pm.finalize()
            return [pm]

    return LinkOnlyCompiler


def available() -> bool:
    """Whether kernels that only kernels call are compiled for linking only."""
    return PIPELINE is not None


def _pipeline() -> Any:
    if os.environ.get("PORENET_LINK_ONLY", "1").strip() == "0":
        return None
    try:
        return _build()
    except Exception as exc:  # pragma: no cover - a numba whose internals differ
        log.info("kernels compiled as numba does by default (%s)", exc)
        return None


#: The numba compiler class for kernels that only kernels call, or None (numba's default).
PIPELINE: Any = _pipeline()
