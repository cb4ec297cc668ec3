"""Snapshots of the fields (observer kind ``snapshots``). See README.md beside this file."""
