"""Built-in solids."""
