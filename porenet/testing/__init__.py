"""Public helpers for testing porenet and its plugins."""
