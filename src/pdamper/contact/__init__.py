"""Contact laws, one file per literature model, and the registry of damping laws.

- :mod:`.hertz` -- Hertz elasticity shared by the normal laws: stiffness ``4/3 E* sqrt(R*)`` and
  elastic energy ``2/5 k delta^(5/2)``.
- :mod:`.hertz_gonthier` -- normal force, Hertz with Gonthier et al. (2004) damping, eq. (1);
  damping choices ``"calibrated"`` (default) and ``"gonthier"``.
- :mod:`.hertz_tsuji` -- normal force, Hertz with Tsuji et al. (1992) viscoelastic damping as
  LIGGGHTS' ``model hertz`` uses it; damping choice ``"tsuji"``.
- :mod:`.friction_tanh` -- regularised Coulomb friction, eq. (2) (tangential choice ``"tanh"``, default).
- :mod:`.tangential_spring` -- incremental tangential spring, Mindlin's stiffness, Coulomb cap
  (tangential choice ``"spring"``).
- :mod:`.cor_constant`, :mod:`.cor_table`, :mod:`.cor_thornton` -- coefficient of restitution laws.

A COR law is a Python object with ``restitution(speed)``; the kernels see every law as a table of
the damping law's coefficient over log-spaced impact speeds (:func:`.cor_table.tabulate_law`), so
one compiled kernel serves all COR laws. A damping law is a :class:`.damping.DampingLaw`, chosen
by name (``ContactModel.damping``) from :data:`DAMPING_LAWS`; each is compiled into its own
kernels. **A new damping law** is one file here plus one line in :data:`DAMPING_LAWS` (see
:mod:`.damping`). A tangential law is a :class:`.tangential.TangentialLaw`, chosen by name
(``ContactModel.tangential``) from :data:`TANGENTIAL_LAWS` and compiled the same way.
"""

import difflib

from . import friction_tanh, hertz_gonthier, hertz_tsuji, tangential_spring
from .cor_constant import ConstantRestitution
from .cor_table import TabulatedRestitution
from .cor_thornton import ThorntonRestitution
from .damping import DampingLaw
from .tangential import TangentialLaw
from .friction_tanh import DEFAULT_TAU
from .hertz import hertz_energy, hertz_stiffness
from .hertz_gonthier import contact_time, damping_parameter
from ..errors import InputError
from ..schema import check_keys, read_list, read_quantity

#: Damping law name -> :class:`~.damping.DampingLaw`: the registry of ``contact.damping``.
DAMPING_LAWS = {law.name: law for law in (*hertz_gonthier.LAWS, *hertz_tsuji.LAWS)}

#: The allowed values of ``contact.damping``, the default first.
DAMPING_CHOICES = tuple(DAMPING_LAWS)

#: Tangential law name -> :class:`~.tangential.TangentialLaw`: the registry of ``contact.tangential``.
TANGENTIAL_LAWS = {law.name: law for law in (friction_tanh.LAW, tangential_spring.LAW)}

#: The allowed values of ``contact.tangential``, the default first.
TANGENTIAL_CHOICES = tuple(TANGENTIAL_LAWS)

#: The keys of a restitution law's table in a config file, by law.
LAW_KEYS = {"constant": ("law", "value"), "table": ("law", "speeds", "values"), "thornton": ("law", "yield_pressure")}


def read_restitution(value, section: str, key: str = "restitution"):
    """A COR law as a config gives it: a number (constant) or a table ``{law = "constant" |
    "table" | "thornton", ...}``; a law object (anything with ``restitution``) as it is."""
    if hasattr(value, "restitution"):
        return value
    name = f"[{section}] {key}"
    try:
        return _law(value, section, key)
    except InputError as exc:
        msg = str(exc)
        if msg.startswith("["):
            raise
        if msg.startswith("restitution = ") and ": " in msg:
            raise InputError(f"{name} = {value!r}: {msg.split(': ', 1)[1]}") from None
        raise InputError(f"[{section}] {msg}") from None


def _law(value, section, key):
    name = f"[{section}] {key}"
    if isinstance(value, (bool, int, float, str)):
        return ConstantRestitution(value=_dimless(value, name))
    if not isinstance(value, dict):
        raise InputError(f"{name} = {value!r}: give a number such as 0.9 or a table "
                         "{law = 'table', speeds = [...], values = [...]} or {law = 'thornton', "
                         "yield_pressure = '1.5GPa'}")
    law = value.get("law")
    if law is None:
        raise InputError(f"{name}: the table needs law = 'constant', 'table' or 'thornton'")
    if law not in LAW_KEYS:
        near = difflib.get_close_matches(str(law), list(LAW_KEYS), n=1, cutoff=0.5)
        hint = f"did you mean {near[0]!r}? " if near else ""
        raise InputError(f"{name}: law = {law!r} is unknown; {hint}choose 'constant', 'table' or 'thornton'")
    sub = f"{section}.{key}"
    check_keys(value, sub, LAW_KEYS[law])
    for req in LAW_KEYS[law][1:]:
        if req not in value:
            raise InputError(f"{name}: law = {law!r} needs {req!r}")
    if law == "constant":
        return ConstantRestitution(value=_dimless(value["value"], f"[{sub}] value"))
    if law == "thornton":
        return ThorntonRestitution(yield_pressure=read_quantity(value["yield_pressure"], f"[{sub}] yield_pressure",
                                                                "pressure"))
    speeds = read_list(value["speeds"], f"[{sub}] speeds", "velocity")
    vals = value["values"]
    if not isinstance(vals, list):
        raise InputError(f"[{sub}] values = {vals!r} must be a list of numbers in (0, 1]")
    values = tuple(_dimless(v, f"[{sub}] values[{k}]") for k, v in enumerate(vals))
    return TabulatedRestitution(speeds=speeds, values=values)


def _dimless(value, label) -> float:
    if isinstance(value, bool) or isinstance(value, (dict, list)):
        raise InputError(f"{label} = {value!r} must be a number")
    return read_quantity(value, label, "dimensionless")

__all__ = [
    "ConstantRestitution",
    "TabulatedRestitution",
    "ThorntonRestitution",
    "DampingLaw",
    "DAMPING_LAWS",
    "DAMPING_CHOICES",
    "TangentialLaw",
    "TANGENTIAL_LAWS",
    "TANGENTIAL_CHOICES",
    "read_restitution",
    "contact_time",
    "hertz_stiffness",
    "hertz_energy",
    "damping_parameter",
    "DEFAULT_TAU",
]
