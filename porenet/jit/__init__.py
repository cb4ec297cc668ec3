"""The kernel machinery: numba compilation (:mod:`~porenet.jit.jit`, link-only libraries in
:mod:`~porenet.jit.link_only`), compile notices (:mod:`~porenet.jit.compilation`), thread
choice (:mod:`~porenet.jit.threads`) and the warm-up runner of ``porenet compile``
(:mod:`~porenet.jit.warmup`), which asks each kind for its warm-ups."""
