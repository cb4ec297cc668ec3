"""Built-in fluids."""
