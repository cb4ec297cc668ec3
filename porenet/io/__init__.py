"""Run files (HDF5). Import is lazy about h5py: it loads only when a file is written or read."""

from porenet.io.runfile import FORMAT_VERSION, read_run, write_run

__all__ = ["FORMAT_VERSION", "read_run", "write_run"]
