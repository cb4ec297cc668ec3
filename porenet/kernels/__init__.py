"""Pure numerical kernels on arrays: no classes with state, no configs, no I/O."""
