"""The fluid-solid coupler (kind ``pressure-aperture``). See README.md beside this file."""
