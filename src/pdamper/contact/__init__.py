"""Contact laws, one file per literature model.

- :mod:`.hertz_gonthier` -- normal force, Hertz with Gonthier et al. (2004) damping, eq. (1).
- :mod:`.friction_tanh` -- regularised Coulomb friction, eq. (2).
- :mod:`.cor_constant`, :mod:`.cor_table`, :mod:`.cor_thornton` -- coefficient of restitution laws.

A COR law is a Python object with ``restitution(speed)``; the kernels see every law
as a table of epsilon over log-spaced impact speeds (:func:`.cor_table.tabulate_law`),
so one compiled kernel serves all laws.
"""

from .cor_constant import ConstantRestitution
from .cor_table import TabulatedRestitution
from .cor_thornton import ThorntonRestitution
from .hertz_gonthier import contact_time, hertz_stiffness, damping_parameter
from .friction_tanh import DEFAULT_TAU

__all__ = [
    "ConstantRestitution",
    "TabulatedRestitution",
    "ThorntonRestitution",
    "contact_time",
    "hertz_stiffness",
    "damping_parameter",
    "DEFAULT_TAU",
]
