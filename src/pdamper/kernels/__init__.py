"""Compiled kernels (numba only): the contact law at a contact, force loops, neighbour search,
integrators, the drive and the coupled structure, sample recording.

Kernels take a few typed bundles of arrays (:mod:`.bundles`) and floats; they know nothing of
parameter dataclasses, files or Dask. All numba settings live in :mod:`pdamper.jit`.

Where things are: the contact law applied to one contact (history, normal force and damping,
friction, dissipated power) in :mod:`.contact`; the loops over pairs, the floor and the other
walls in :mod:`.forces`; Verlet lists in :mod:`.neighbours`; :mod:`.verlet` and :mod:`.gear`;
the container's motion in :mod:`.drive` and :mod:`.structure`; what a sample writes in
:mod:`.record`.
"""
