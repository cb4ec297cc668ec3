"""The progress display as an observer (kind ``progress``). See README.md beside this file."""
