"""The 3-D cubic lattice (kind ``cubic``). See README.md beside this file."""
