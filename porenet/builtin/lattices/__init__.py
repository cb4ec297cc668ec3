"""Built-in lattices."""
