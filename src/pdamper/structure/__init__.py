"""The structures a damper is put on: the models, their FE readers (and, to come, their loads and
responses).

A structure is a drive of the ``[structure]`` section (:class:`pdamper.excitation.DriveBase`):
the container rides on it, and the bed's force moves it (two-way coupled). Each model is one
module registered with :func:`pdamper.excitation.register_drive`; :mod:`pdamper.config` reads a
``[structure]`` table into the model whose keys it has (``mass``: one mode; ``modes`` or
``matrices``: several).

=====================  ======================================================================
:mod:`.base`           :class:`StructureBase`: the fields every structure has (the force, the
                       start, the direction) and the drive protocol's shared answers
:mod:`.sdof`           :class:`CoupledStructure`: one mode, mass M, stiffness K, damping ratio zeta
:mod:`.modal`          :class:`ModalStructure`: N modes, given as data or from FE matrices
:mod:`.matrices`       FE matrices: :func:`read_structure_matrices` (.npz, Matrix Market,
                       Harwell-Boeing), the modes of K phi = omega^2 M phi, the damping
                       (zeta, Rayleigh [alpha, beta] or zeta at two modes, a C matrix)
:mod:`.opensees`       :class:`OpenSeesStructure`: an OpenSeesPy model file, its matrices (linear
                       use) or OpenSees advancing it (co-simulation, :class:`OpenSeesBackend`)
:mod:`.backend`        the structure backend protocol a coupling step at a time, and
                       :class:`LinearBackend` (pdamper's own linear modes, exact between steps)
=====================  ======================================================================

The empty container's mass (``[container] mass``) moves with the structure: a run puts it at
the damper point (:meth:`~StructureBase.carrying`, through :attr:`pdamper.params.Case.running_drive`).
"""

from .base import StructureBase
from .sdof import CoupledStructure
from .modal import ModalStructure
from .matrices import read_structure_matrices, rayleigh_coefficients
from .opensees import OpenSeesStructure

__all__ = ["StructureBase", "CoupledStructure", "ModalStructure", "OpenSeesStructure", "read_structure_matrices",
           "rayleigh_coefficients"]
