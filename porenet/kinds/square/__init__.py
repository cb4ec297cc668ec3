"""The paper's square lattice (kind ``square``). See README.md beside this file."""
