"""Kernels that models of every kind use: the pore graph (:mod:`~porenet.kernels.graph`), stable
ranking (:mod:`~porenet.kernels.sorting`), burst statistics (:mod:`~porenet.kernels.bursts`),
dense Cholesky columns (:mod:`~porenet.kernels.dense`) and number parsing
(:mod:`~porenet.kernels.text`). Pure functions on arrays: no classes with state, no configs, no
I/O. A kind's own kernels live in its folder (``porenet/kinds/<kind>/kernels/``)."""
