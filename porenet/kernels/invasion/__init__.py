"""Invasion percolation: the precomputed sequence with and without trapping, the online variant for
deformable media, and the bitmap priority queue they share."""
