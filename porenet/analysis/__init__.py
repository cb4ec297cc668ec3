"""Measures of invasion patterns (docs/model.md section 7)."""
