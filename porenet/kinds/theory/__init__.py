"""The theory's prediction as a classifier (kind ``theory``). See README.md beside this file."""
