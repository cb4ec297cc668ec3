"""The frictional solid's kernels: contact laws with a tangential force, the multigrid solver
of the grid and the sparse direct solver with free rotations."""
