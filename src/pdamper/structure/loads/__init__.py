"""Loads on a structure, one module a kind behind one protocol (:mod:`.base`), read from a
``[load]`` section (docs/config.md, docs/structure.md):

=====================  ======================================================================
``harmonic``           :class:`HarmonicLoad`: F0 sin(2 pi f t), the structure's own force
``force_history``      :class:`ForceHistory`: a force-time file or lists at the force point
``ground_acceleration``:class:`GroundAcceleration`: an accelerogram (CSV or PEER .AT2), every
                       dof through the mass matrix, displacements relative to the ground
``random``             :class:`RandomLoad`: a stationary Gaussian force or ground acceleration
                       of a PSD (band-limited white noise or Kanai-Tajimi), seeded
``stepped_sine``       :class:`SteppedSine`: a sine at frequencies in turn, the state carried
=====================  ======================================================================
"""

from .base import LOADS, LoadBase, SampledLoad, register_load
from .harmonic import HarmonicLoad
from .force_history import ForceHistory
from .ground import GroundAcceleration
from .random import RandomLoad
from .stepped_sine import SteppedSine

__all__ = ["LOADS", "LoadBase", "SampledLoad", "register_load", "HarmonicLoad", "ForceHistory",
           "GroundAcceleration", "RandomLoad", "SteppedSine"]
