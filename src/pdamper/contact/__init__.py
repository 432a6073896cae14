"""Contact laws, one file per literature model, and the registry of damping laws.

- :mod:`.hertz` -- Hertz elasticity shared by the normal laws: stiffness ``4/3 E* sqrt(R*)`` and
  elastic energy ``2/5 k delta^(5/2)``.
- :mod:`.hertz_gonthier` -- normal force, Hertz with Gonthier et al. (2004) damping, eq. (1);
  damping choices ``"calibrated"`` (default) and ``"gonthier"``.
- :mod:`.hertz_tsuji` -- normal force, Hertz with Tsuji et al. (1992) viscoelastic damping as
  LIGGGHTS' ``model hertz`` uses it; damping choice ``"tsuji"``.
- :mod:`.friction_tanh` -- regularised Coulomb friction, eq. (2).
- :mod:`.cor_constant`, :mod:`.cor_table`, :mod:`.cor_thornton` -- coefficient of restitution laws.

A COR law is a Python object with ``restitution(speed)``; the kernels see every law as a table of
the damping law's coefficient over log-spaced impact speeds (:func:`.cor_table.tabulate_law`), so
one compiled kernel serves all COR laws. A damping law is a :class:`.damping.DampingLaw`, chosen
by name (``ContactModel.damping``) from :data:`DAMPING_LAWS`; each is compiled into its own
kernels. **A new damping law** is one file here plus one line in :data:`DAMPING_LAWS` (see
:mod:`.damping`).
"""

from . import hertz_gonthier, hertz_tsuji
from .cor_constant import ConstantRestitution
from .cor_table import TabulatedRestitution
from .cor_thornton import ThorntonRestitution
from .damping import DampingLaw
from .friction_tanh import DEFAULT_TAU
from .hertz import hertz_energy, hertz_stiffness
from .hertz_gonthier import contact_time, damping_parameter

#: Damping law name -> :class:`~.damping.DampingLaw`: the registry of ``contact.damping``.
DAMPING_LAWS = {law.name: law for law in (*hertz_gonthier.LAWS, *hertz_tsuji.LAWS)}

#: The allowed values of ``contact.damping``, the default first.
DAMPING_CHOICES = tuple(DAMPING_LAWS)

__all__ = [
    "ConstantRestitution",
    "TabulatedRestitution",
    "ThorntonRestitution",
    "DampingLaw",
    "DAMPING_LAWS",
    "DAMPING_CHOICES",
    "contact_time",
    "hertz_stiffness",
    "hertz_energy",
    "damping_parameter",
    "DEFAULT_TAU",
]
