"""Measures of invasion patterns (MODEL.md section 7)."""
