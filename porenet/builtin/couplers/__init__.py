"""Built-in couplers."""
