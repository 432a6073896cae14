"""The GPU engine's kernels (numba-cuda): every case of a batch advanced together on one NVIDIA GPU,
one thread block per case.

Nothing here is imported by ``import pdamper``: :mod:`pdamper.engine.cuda` imports it when a run
asks for ``device = "cuda"``, and it needs numba-cuda (``pip install -e ".[gpu]"``).

The physics is the CPU kernels' own: the block calls the same compiled functions as
:func:`pdamper.kernels.forces.compute_forces` and Gear's implicit friction pass -- the contact law at a contact
(:func:`pdamper.kernels.contact.contact`, which dispatches on the damping law's marker), the
contact-point kinematics, :func:`~pdamper.kernels.contact.scatter`, the walls' signed distance
(:func:`pdamper.geometry.walls.wall_distance`), Hertz' stiffness and energy, the harmonic drive
(:func:`pdamper.kernels.drive.harmonic_motion`), Gear's ``corrected_friction`` -- compiled a second
time by numba-cuda for the GPU. Only the per-target dispatch glue of the damping law is registered twice (:mod:`.targets`).

- :mod:`.targets` -- the damping law's dispatch for the CUDA target.
- :mod:`.batch` -- the batch's bundles of arrays (a leading case axis on every array).
- :mod:`.verlet` -- velocity Verlet for a batch, and the device functions both kernels share
  (neighbour rows, the pairs' contact law, a sphere's force, a sample).
- :mod:`.gear` -- Gear's predictor-corrector for a batch, each case with its own adaptive step.
"""
