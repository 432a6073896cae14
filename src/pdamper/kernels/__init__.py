"""Compiled kernels (numba only): neighbour search, contact forces, integrators.

Kernels take plain arrays and floats; they know nothing of dataclasses, files or Dask.
All numba settings live in :mod:`pdamper.kernels.jit`.
"""
