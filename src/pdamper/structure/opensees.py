"""A structure given as an OpenSeesPy model (``[structure] opensees = "frame.py"``).

The file builds the model as an engineer writes it -- ``ops.model``, nodes, ``ops.fix``, masses,
materials, elements, ``ops.rayleigh`` -- and runs no analysis; ``damper_node = N`` (or
``damper_nodes = [..]``, a damper at each) names where the containers sit and ``dof`` (1: x) the
direction they move with. pdamper runs the file in a child process (:mod:`._opensees_worker`),
under a time limit, with its output captured: a file that raises, loops, prints or names a node
the model lacks gives one line, and nothing of pdamper's is written.

**Linear use** (``coupling = "tight"``, the default of a linear model): the model's mass,
stiffness and damping matrices (OpenSees' ``GimmeMCK`` integrator with a full system,
``ops.printA``), the dofs without mass condensed out statically (Guyan: exact for the static
shapes, and Rayleigh damping ``alpha M + beta K`` stays ``alpha M* + beta K*``), become pdamper's
own FE structure (:class:`~pdamper.structure.ModalStructure`: modes, fields, response, transient,
design). The dofs are the equations with mass, labelled by their node (``"node/dof"`` for a dof
other than ``dof``).

**Co-simulation** (``coupling = "opensees"``, the default of a nonlinear model -- a material other
than ``Elastic``, a nonlinear transformation or element): OpenSees advances the structure with its
own integrator (Newmark's average acceleration, Newton iterations) and materials, pdamper's DEM
advances the beds, a coupling step at a time (:class:`OpenSeesBackend`, :mod:`pdamper.cosim`). The
linearised modes (from the initial tangent) still give the time step, the bare structure's
numbers and the dofs; the bare response is OpenSees' own run without the beds.

The trap worth knowing: a ``zeroLength`` element takes no part in ``ops.rayleigh``'s
stiffness-proportional damping unless it is given ``'-doRayleigh', 1``; pdamper warns when the
model's damping is not proportional (its modal projection not diagonal).
"""

from __future__ import annotations

import dataclasses
import hashlib
import math
import os
import pickle
import select
import signal
import struct
import subprocess
import sys
import tempfile
import time
import warnings
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..errors import InputError, SimulationError, checked_file, resolved, shown, shown_path
from ..excitation import register_drive
from ..schema import config_keys, param
from .modal import ModalStructure
from .matrices import modes_from_matrices

__all__ = ["OpenSeesStructure", "OpenSeesModel", "OpenSeesBackend", "read_model", "available", "BUILD_TIMEOUT",
           "STEP_TIMEOUT", "COUPLINGS"]

#: Longest a model file may take to build [s] (a file that loops is stopped there).
BUILD_TIMEOUT = 60.0
#: Longest one coupling step of OpenSees may take [s].
STEP_TIMEOUT = 60.0
#: ``[structure] coupling``: "auto" (tight for a linear model, opensees for a nonlinear one),
#: "tight" (the model's matrices as pdamper's own structure; a nonlinear model linearised),
#: "opensees" (co-simulated: OpenSees advances the structure).
COUPLINGS = ("auto", "tight", "opensees")
#: The damping's modal projection is called not proportional above this off-diagonal ratio.
NONPROPORTIONAL = 1e-6
_WORKER = Path(__file__).with_name("_opensees_worker.py")


def _log_tail(path: Path, lines: int = 40) -> list[str]:
    """The last lines the child wrote (the user's prints, OpenSees' warnings), without OpenSees'
    own sign-off."""
    try:
        text = path.read_text(errors="replace")
    except OSError:
        return []
    out = [ln.strip() for ln in text.splitlines() if ln.strip() and "Process 0 Terminating" not in ln]
    return out[-lines:]


def _warning(lines: list[str]) -> str:
    """OpenSees' last warning (its messages go to stderr; its Python exception says only 'See stderr
    output')."""
    for ln in reversed(lines):
        if "WARNING" in ln or "ERROR" in ln or "error" in ln.lower():
            return ln
    return lines[-1] if lines else ""


def _bundled_libraries() -> str | None:
    """The folder of the shared libraries (BLAS, LAPACK, gfortran) that openseespy's Linux wheel ships
    beside its module but does not put on its load path; None where there is none."""
    import importlib.util

    try:
        spec = importlib.util.find_spec("openseespylinux")
    except (ImportError, ValueError):
        return None
    if spec is None or not spec.submodule_search_locations:
        return None
    lib = Path(list(spec.submodule_search_locations)[0]) / "lib"
    return str(lib) if lib.is_dir() else None


class _Worker:
    """One child process running :mod:`._opensees_worker`: requests and replies over two pipes, its
    output in a log file, each request under a time limit (the child is killed past it)."""

    def __init__(self, label: str, cwd: Path):
        self.label = label
        fd, name = tempfile.mkstemp(prefix="pdamper-opensees-", suffix=".log")
        self.log = Path(name)
        to_child_r, self._w = os.pipe()
        self._r, from_child_w = os.pipe()
        env = dict(os.environ, PYTHONUNBUFFERED="1", OMP_NUM_THREADS="1")
        libs = _bundled_libraries()
        if libs is not None:  # the wheel's own BLAS and LAPACK, where the system has none
            env["LD_LIBRARY_PATH"] = os.pathsep.join(p for p in (env.get("LD_LIBRARY_PATH"), libs) if p)
        try:
            self.proc = subprocess.Popen([sys.executable, str(_WORKER), str(to_child_r), str(from_child_w), name],
                                         pass_fds=(to_child_r, from_child_w), stdin=subprocess.DEVNULL, stdout=fd,
                                         stderr=fd, cwd=str(cwd), env=env, start_new_session=True)
        finally:
            os.close(fd)
            os.close(to_child_r)
            os.close(from_child_w)

    def request(self, msg, timeout: float, what: str):
        """The reply's data to ``msg``; raises InputError (the file, OpenSees missing), SimulationError
        (a step that did not converge) or, past ``timeout`` [s] or when the child dies, InputError with
        what it said last."""
        data = pickle.dumps(msg, protocol=pickle.HIGHEST_PROTOCOL)
        try:
            os.write(self._w, struct.pack("<I", len(data)) + data)
        except OSError:
            self._died(what)
        head = self._read(4, timeout, what)
        (n,) = struct.unpack("<I", head)
        reply = pickle.loads(self._read(n, timeout, what))
        if reply[0] == "ok":
            return reply[1]
        kind, text = reply[1], reply[2]
        if kind == "missing":
            raise InputError(f"{self.label} needs openseespy, which cannot be loaded here ({text}); install it with "
                             "pip install 'pdamper[opensees]'")
        if text.endswith("See stderr output"):
            said = _warning(_log_tail(self.log))
            text = text[: -len("See stderr output")].rstrip(": ") + (f": OpenSees says {said!r}" if said else "")
        if kind == "converge":
            raise SimulationError(text)
        if kind == "raised":
            raise InputError(f"{self.label}: {what} raised {text}")
        raise InputError(f"{self.label}: {text}")

    def _read(self, n: int, timeout: float, what: str) -> bytes:
        out = b""
        end = time.monotonic() + timeout
        while len(out) < n:
            left = end - time.monotonic()
            ready = select.select([self._r], [], [], max(left, 0.0))[0] if left > 0 else []
            if not ready:
                self.kill()
                raise InputError(f"{self.label}: {what} took longer than {timeout:g} s and was stopped (does the "
                                 "model file loop, or wait for input?)")
            chunk = os.read(self._r, n - len(out))
            if not chunk:
                self._died(what)
            out += chunk
        return out

    def _died(self, what: str):
        self.proc.wait(timeout=5)
        said = _warning(_log_tail(self.log))
        code = self.proc.returncode
        how = f"signal {-code}" if code is not None and code < 0 else f"exit status {code}"
        self._cleanup()
        raise InputError(f"{self.label}: OpenSees stopped during {what} ({how})" + (f"; it said {said!r}" if said else ""))

    def kill(self) -> None:
        if self.proc.poll() is None:
            try:
                os.killpg(self.proc.pid, signal.SIGKILL)
            except (ProcessLookupError, PermissionError):
                self.proc.kill()
            self.proc.wait()
        self._cleanup()

    def close(self) -> None:
        if self.proc.poll() is None:
            try:
                data = pickle.dumps(("close",))
                os.write(self._w, struct.pack("<I", len(data)) + data)
                self.proc.wait(timeout=10)
            except (OSError, subprocess.TimeoutExpired):
                pass
        self.kill()

    def _cleanup(self) -> None:
        for fd in (self._r, self._w):
            try:
                os.close(fd)
            except OSError:
                pass
        self._r = self._w = -1
        try:
            self.log.unlink()
        except OSError:
            pass

    def __del__(self):
        try:
            self.kill()
        except Exception:  # interpreter shutdown: nothing left to tidy
            pass


_AVAILABLE: dict = {}


def available() -> str | None:
    """None when openseespy loads here (tried once, in a child process), else why not (one line)."""
    if "reason" not in _AVAILABLE:
        w = _Worker("structure.opensees", Path.cwd())
        try:
            w.request(("hello",), BUILD_TIMEOUT, "loading openseespy")
            _AVAILABLE["reason"] = None
        except InputError as exc:
            _AVAILABLE["reason"] = str(exc)
        finally:
            w.close()
    return _AVAILABLE["reason"]


@dataclass(frozen=True)
class OpenSeesModel:
    """What pdamper reads of an OpenSees model file: M, K, C over the model's equations [SI], the
    equations of each node (``equations[node][dof - 1]``, -1 where fixed), why the model is
    nonlinear (empty: linear) and its ``ops.rayleigh`` calls."""

    path: str
    M: np.ndarray
    K: np.ndarray
    C: np.ndarray
    equations: dict
    nonlinear: tuple
    rayleigh: tuple

    def rayleigh_shortfall(self) -> float:
        """How far C is from the Rayleigh damping the model's last ``ops.rayleigh(alpha, beta_K,
        beta_Kinit, beta_Kcomm)`` asks for, alpha M + (beta_K + beta_Kinit + beta_Kcomm) K at rest
        (the largest entry of the difference over the largest of that C); 0 without ops.rayleigh."""
        if not self.rayleigh:
            return 0.0
        a, bk, bi, bc = (list(self.rayleigh[-1]) + [0.0] * 4)[:4]
        want = a * self.M + (bk + bi + bc) * self.K
        scale = float(np.max(np.abs(want)))
        return float(np.max(np.abs(self.C - want)) / scale) if scale > 0 else 0.0

    def condensed(self, dof: int):
        """(M, K, C, labels, equations): the equations with mass kept, the others condensed out
        statically (Guyan, T = [I; -K_ss^-1 K_sm]); ``labels`` the node of each kept equation
        (``"node/d"`` when it is not along ``dof``), ``equations`` their equation numbers."""
        m = np.diag(self.M)
        keep = np.flatnonzero(np.abs(m) > 0)
        rest = np.flatnonzero(~(np.abs(m) > 0))
        if keep.size == 0:
            raise InputError(f"structure.opensees = {shown_path(self.path)!r}: the model has no mass (ops.mass); pdamper needs "
                             "the masses of its floors")
        T = np.eye(self.M.shape[0])[:, keep]
        if rest.size:
            Kss = self.K[np.ix_(rest, rest)]
            try:
                T[rest] = -np.linalg.solve(Kss, self.K[np.ix_(rest, keep)])
            except np.linalg.LinAlgError:
                raise InputError(f"structure.opensees = {shown_path(self.path)!r}: the dofs without mass are not held by any "
                                 "stiffness (a mechanism); fix them or give them mass") from None
        owner = {}
        for node, eqs in self.equations.items():
            for d, e in enumerate(eqs):
                if e >= 0:
                    owner[e] = (node, d + 1)
        labels = [owner[e][0] if owner[e][1] == dof else f"{owner[e][0]}/{owner[e][1]}" for e in keep]
        return T.T @ self.M @ T, T.T @ self.K @ T, T.T @ self.C @ T, labels, keep


_MODELS: dict = {}


def read_model(path, *, dof: int = 1, damper_nodes=(), force_nodes=(), response_nodes=(), keys=None,
               timeout: float = BUILD_TIMEOUT) -> OpenSeesModel:
    """The :class:`OpenSeesModel` of the model file ``path`` (run in a child process under
    ``timeout`` [s]): the nodes named must exist and move along ``dof``, the damper nodes have mass
    there. Cached by the file's contents and the nodes asked about."""
    label = f"structure.opensees = {shown_path(path)!r}"
    try:
        p = checked_file(resolved(path), "model file (the Python file that builds the OpenSees model)")
        content = p.read_bytes()
    except InputError as exc:
        raise InputError(f"{label}: {exc}") from None
    except OSError as exc:
        raise InputError(f"{label}: cannot read it: {exc.strerror or exc}") from None
    keys = keys or {"damper": "damper_node", "force": "force_node", "response": "response_node"}
    options = {"dof": int(dof), "damper_nodes": [int(n) for n in damper_nodes],
               "force_nodes": [int(n) for n in force_nodes], "response_nodes": [int(n) for n in response_nodes],
               "keys": keys}
    key = (str(p), hashlib.sha1(content).hexdigest(), repr(sorted(options.items())))
    if key not in _MODELS:
        w = _Worker(label, p.parent)
        try:
            info = w.request(("model", str(p), options), timeout, "building the model")
        finally:
            w.close()
        if not info["finite"]:
            raise InputError(f"{label}: the model's mass or stiffness matrix has NaN or infinite entries")
        _MODELS[key] = OpenSeesModel(path=str(path), M=info["M"], K=info["K"], C=info["C"],
                                     equations=info["equations"], nonlinear=tuple(info["nonlinear"]),
                                     rayleigh=tuple(tuple(r) for r in info["rayleigh"]))
    return _MODELS[key]


@dataclass(frozen=True, kw_only=True)
class _OpenSees:
    """The OpenSees structure's own fields (first in the written config)."""

    opensees: str | None = param(None, kind="custom")
    damper_node: int | None = param(None, kind="whole")
    damper_nodes: tuple | None = param(None, kind="whole", many=True)
    force_node: int | None = param(None, kind="whole")
    response_node: int | None = param(None, kind="whole")
    dof: int = param(1, kind="whole")
    coupling: str = param("auto", kind="text", choices=COUPLINGS)


#: The modal structure's keys an OpenSees structure does not take (the model gives them).
_NOT_OURS = ("modes", "matrices", "damper_dof", "force_dof", "response_dof", "rayleigh", "rayleigh_modes",
             "rayleigh_ratios")


@register_drive
@dataclass(frozen=True, kw_only=True)
class OpenSeesStructure(ModalStructure, _OpenSees):
    """The container rides on a structure given as an OpenSeesPy model file (module docstring).

    Parameters (beside the shared ones of :class:`~pdamper.structure.StructureBase`)
    ----------
    opensees : the Python file that builds the model (relative to the config file).
    damper_node, damper_nodes : the node the container sits on, or the nodes (a damper at each).
    force_node, response_node : where the harmonic force acts and the response is read (default the
        first damper node).
    dof : the nodes' dof the containers move with (1: x).
    coupling : "auto", "tight" or "opensees" (:data:`COUPLINGS`).
    modes_kept, damping_ratio : as for FE matrices (``damping_ratio`` only for a model without
        damping of its own).
    """

    kind: str = param("opensees", kind="tag")
    config_marks = ("opensees",)
    damper_points_key = ("node", "damper_nodes")
    config_label = "an OpenSees model"
    config_summary = "opensees = 'frame.py' (an OpenSees model)"

    @classmethod
    def table_keys(cls) -> tuple:
        """The keys of an ``opensees`` table (not those the model gives: modes, matrices, dofs,
        Rayleigh damping)."""
        return config_keys(cls, drop=_NOT_OURS) + tuple(cls.config_extra_keys)

    @classmethod
    def config_read_extra(cls, table: dict, base_dir) -> dict:
        """``opensees`` made absolute (relative to the config file)."""
        kw = {"load": table["load"]} if "load" in table else {}
        if "opensees" in table:
            v = table["opensees"]
            if not isinstance(v, str) or not v.strip():
                raise InputError(f"[structure] opensees = {shown(v)}; give the path of the Python file that builds the "
                                 "OpenSees model, e.g. opensees = 'frame.py'")
            kw["opensees"] = str(resolved(v, base_dir))  # a name the system refuses: read_model says so
        return kw

    def config_extra(self) -> dict:
        return {"opensees": str(self.opensees)}

    def __post_init__(self):
        self._prepare()
        given = [k for k in _NOT_OURS if getattr(self, k)]
        if given:
            raise InputError(f"structure.{given[0]} does not apply to an OpenSees model (the model file gives its "
                             "masses, stiffness, damping and nodes); name the nodes with damper_node, force_node, "
                             "response_node")
        if not self.opensees:
            raise InputError("structure.opensees is missing: give the Python file that builds the model")
        if self.coupling not in COUPLINGS:
            raise InputError(f"structure.coupling = {shown(self.coupling)}; choose one of "
                             + ", ".join(repr(c) for c in COUPLINGS))
        d = self.dof
        if isinstance(d, bool) or not isinstance(d, int) or not 1 <= d <= 6:
            raise InputError(f"structure.dof = {shown(d)}; give the nodes' dof the containers move with, 1 to 6 (1: x)")
        nodes = self.damper_node_tags
        model = read_model(self.opensees, dof=d, damper_nodes=nodes,
                           force_nodes=[self.force_node] if self.force_node is not None else [],
                           response_nodes=[self.response_node] if self.response_node is not None else [],
                           keys={"damper": "damper_nodes" if self.damper_nodes is not None else "damper_node",
                                 "force": "force_node", "response": "response_node"})
        object.__setattr__(self, "_model", model)
        M, K, C, labels, eqs = model.condensed(d)
        where = {e: i for i, e in enumerate(eqs)}

        def index(node):
            return where[model.equations[node][d - 1]]

        force = index(self.force_node) if self.force_node is not None else index(nodes[0])
        resp = index(self.response_node) if self.response_node is not None else index(nodes[0])
        own_damping = bool(np.any(C != 0))
        if self.damping_ratio is not None and own_damping:
            raise InputError("structure.damping_ratio: the OpenSees model has damping of its own (ops.rayleigh); "
                             "leave damping_ratio out, or take ops.rayleigh out of the model")
        dofs = {"damper_dof": [index(n) for n in nodes], "force_dof": force, "response_dof": resp,
                "damper_key": "damper_nodes" if self.damper_nodes is not None else "damper_node"}
        # the model's damping (none: undamped), or damping_ratio for a model without damping of its own
        data = modes_from_matrices(self, {"M": M, "K": K, "C": None if self.damping_ratio is not None else C}, dofs,
                                   labels)
        short = model.rayleigh_shortfall()
        if short > NONPROPORTIONAL:
            a, bk, bi, bc = (list(model.rayleigh[-1]) + [0.0] * 4)[:4]
            warnings.warn(f"structure.opensees = {shown_path(self.opensees)!r}: the model's damping is not the Rayleigh damping "
                          f"ops.rayleigh({a:g}, {bk:g}, {bi:g}, {bc:g}) asks for (C differs from alpha M + beta K by "
                          f"{short:.2g} of it): some elements take no part in it; a zeroLength element takes part "
                          "in the stiffness-proportional damping only with '-doRayleigh', 1", stacklevel=2)
        elif data["nonproportional"] > NONPROPORTIONAL:
            warnings.warn(f"structure.opensees = {shown_path(self.opensees)!r}: the model's damping is not proportional (its "
                          f"modal projection's off-diagonal terms reach {data['nonproportional']:.2g} of the "
                          "diagonal's); pdamper keeps each mode's own damping. A zeroLength element takes part in "
                          "ops.rayleigh's stiffness-proportional damping only with '-doRayleigh', 1", stacklevel=2)
        self._set_modal(data, "modes_kept")
        if self.coupling == "opensees" and self.load is None and (self.force_amplitude > 0 or self.displacement):
            raise InputError("structure.coupling = 'opensees': the co-simulation runs a load in time ([load]: a "
                             "ground acceleration or a force history); a harmonic force or a free decay runs with "
                             "coupling = 'tight' (the model's matrices)")

    @property
    def damper_node_tags(self) -> list[int]:
        """The damper nodes (``damper_node`` or ``damper_nodes``)."""
        if self.damper_node is not None and self.damper_nodes is not None:
            raise InputError("structure.damper_node and damper_nodes are both given; give one (damper_nodes = "
                             "[3, 2] for a damper at each)")
        v = self.damper_nodes if self.damper_nodes is not None else self.damper_node
        if v is None:
            raise InputError("structure.damper_node is missing: give the node the container sits on (or "
                             "damper_nodes = [3, 2], a damper at each)")
        nodes = list(v) if isinstance(v, (list, tuple)) else [v]
        for n in nodes:
            if isinstance(n, bool) or not isinstance(n, int):
                raise InputError(f"structure.damper_node{'s' if len(nodes) > 1 else ''} = {shown(v)}; give node tags "
                                 "(whole numbers)")
        return nodes

    def at_damper(self, k: int):
        """The model with its damper node ``k`` as its one damper."""
        nodes = self.damper_node_tags
        if not 0 <= k < len(nodes):
            raise InputError(f"damper point {k + 1}: the model has {len(nodes)} damper node{'s' if len(nodes) > 1 else ''}")
        return dataclasses.replace(self, damper_node=nodes[k], damper_nodes=None)

    @property
    def nonlinear(self) -> tuple:
        """Why the model is nonlinear (its materials, transformations, elements); empty: linear."""
        return self._model.nonlinear

    @property
    def cosimulated(self) -> bool:
        """OpenSees advances the structure: ``coupling = "opensees"``, or "auto" on a nonlinear model."""
        return self.coupling == "opensees" or (self.coupling == "auto" and bool(self.nonlinear))

    def backend(self, step: float, duration: float, points, masses):
        """Co-simulated: :class:`OpenSeesBackend` (OpenSees steps the model); else pdamper's linear modes."""
        if not self.cosimulated:
            return super().backend(step, duration, points, masses)
        return OpenSeesBackend(self, step=step, duration=duration, points=points, masses=masses)

    def structure_summary(self) -> dict:
        out = super().structure_summary()
        out.update(opensees=str(self.opensees), damper_nodes=self.damper_node_tags, dof=self.dof,
                   coupling="opensees" if self.cosimulated else "tight",
                   nonlinear=list(self.nonlinear), damping_nonproportional=float(self._modal["nonproportional"]))
        return out

    def describe(self) -> str:
        how = "co-simulated" if self.cosimulated else "linear"
        return (f"OpenSees model {Path(self.opensees).name} ({how}, {self.n_modes} modes from "
                f"{self.mode_frequencies[0]:.4g} Hz), dampers at node{'s' if self.damper_count > 1 else ''} "
                f"{', '.join(map(str, self.damper_node_tags))}, {self._forced_words()}")


class OpenSeesBackend:
    """The structure advanced by OpenSees a coupling step at a time (the structure backend protocol,
    :mod:`pdamper.structure.backend`): the model built afresh in a child process with the empty
    containers' masses added at the damper nodes, the load as a ``Path`` series on the coupling
    step (a ground acceleration as ``UniformExcitation`` along ``dof``: the responses are relative to
    the ground), Newmark's average acceleration with Newton iterations (:mod:`._opensees_worker`)."""

    def __init__(self, structure: OpenSeesStructure, *, step: float, duration: float, points, masses):
        from .backend import Motion, ground_motion

        self.s = structure
        self.step = float(step)
        self.n_steps = int(math.floor(duration / step + 1e-9))
        nodes = structure.damper_node_tags
        self.points = list(points)
        self.nodes = [nodes[p] for p in self.points]
        load = structure.load
        t = np.arange(self.n_steps + 2) * self.step
        opts = {"dof": structure.dof, "step": self.step, "damper_nodes": self.nodes,
                "added_masses": [(nodes[p], float(sum(m for q, m in zip(self.points, masses) if q == p)))
                                 for p in sorted(set(self.points))]}
        self.ground = bool(load is not None and load.ground)
        if load is not None:
            entry = {"values": load.values(t).tolist(), "ground": self.ground}
            if not self.ground:
                node = structure.force_node if structure.force_node is not None else nodes[0]
                entry["nodes"] = [(node, 1.0)]
                if getattr(load, "influence", None) is not None or getattr(load, "participation", None) is not None:
                    raise InputError("[load] influence / participation: the co-simulation applies a force at the "
                                     "force node (structure.force_node)")
            opts["load"] = entry
        labels, _ = structure.dof_shapes()
        self.labels = list(labels)
        # the dofs' labels: a node (along dof) or "node/d"
        opts["recorded"] = [(lb, structure.dof) if isinstance(lb, int) else tuple(int(v) for v in lb.split("/"))
                            for lb in self.labels]
        resp = structure.response_node if structure.response_node is not None else nodes[0]
        self._response = self.labels.index(resp) if resp in self.labels else None
        self._g = ground_motion(load, t) if self.ground else None
        self._motion = Motion
        self.worker = _Worker(f"structure.opensees = {shown_path(structure.opensees)!r}", Path(structure.opensees).parent)
        try:
            self._state = self.worker.request(("session", str(structure.opensees), opts), BUILD_TIMEOUT,
                                              "building the model")
        except BaseException:
            self.worker.kill()
            raise
        self.k = 0

    def _wrap(self, st, k):
        g = (self._g[0][k], self._g[1][k], self._g[2][k]) if self._g is not None else (0.0, 0.0, 0.0)
        dofs = np.array(st["dofs_x"])
        return self._motion(t=k * self.step, x=np.array(st["x"]), v=np.array(st["v"]), a=np.array(st["a"]),
                            ground=g, dofs=dofs, dofs_velocity=np.array(st["dofs_v"]),
                            response=float(dofs[self._response]) if self._response is not None else math.nan)

    def start(self):
        """The state at t = 0."""
        return self._wrap(self._state, 0)

    def advance(self, forces):
        """One coupling step with the beds' wall forces ``forces`` [N] (on the spheres, along the
        drive: the structure feels minus them, held over the step); the state at its end."""
        f = [-float(x) for x in forces]
        try:
            st = self.worker.request(("step", f), STEP_TIMEOUT, f"the step to t = {(self.k + 1) * self.step:.6g} s")
        except BaseException:
            self.worker.kill()
            raise
        self.k += 1
        return self._wrap(st, self.k)

    def close(self) -> None:
        self.worker.close()

    #: the structure's own ledger is not known (its materials' hysteresis stays in OpenSees)
    ledger = None
