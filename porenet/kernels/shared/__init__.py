"""Kernels every model uses: the pore graph, stable ranking, burst statistics, dense Cholesky
columns."""
