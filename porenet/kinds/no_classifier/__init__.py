"""No pattern analysis (classifier kind ``none``). See README.md beside this file."""
