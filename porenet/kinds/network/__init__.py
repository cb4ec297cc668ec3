"""Imported pore networks (kind ``network``). See README.md beside this file."""
