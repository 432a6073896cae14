"""The child process that runs a user's OpenSeesPy model (:mod:`pdamper.structure.opensees`).

Run as a script (``python _opensees_worker.py READ_FD WRITE_FD``), not imported: it needs the
standard library, numpy and openseespy only, so it starts in a fraction of a second and a model
file that raises, loops, prints or crashes OpenSees takes only this process with it. Its stdout
and stderr (the user's prints, OpenSees' warnings) go to a log file the parent reads back for
its messages. Requests and replies are pickled frames (a 4-byte length, then the pickle) on two
pipes:

``("model", path, options)``
    build the model (the file executed with ``ops`` as a recording proxy) and reply what pdamper
    needs of it: every node's equations, the masses, M, K and C over the equations (OpenSees'
    ``GimmeMCK`` integrator with a full system, ``printA``), whether the model is linear (and why
    not), the ``ops.rayleigh`` calls.
``("session", path, options)``
    build the model afresh for a co-simulation: the empty containers' masses added at the damper
    nodes, the load (``UniformExcitation`` along ``dof`` for a ground acceleration, a nodal force
    history otherwise) as a ``Path`` series on the coupling step, Newmark's average acceleration
    with Newton iterations; reply the state at t = 0.
``("step", forces)``
    the dampers' forces [N] on their nodes along ``dof`` for the next step; analyse one step
    (retrying with sub-steps and other algorithms when Newton does not converge); reply the
    damper nodes' and the recorded dofs' state at the step's end.
``("close",)``
    end.

A failure replies ``("error", kind, message)``: ``kind`` "model" (the file or the options are
wrong: the parent raises an InputError) or "converge" (a step failed: a SimulationError).
"""

import math
import os
import pickle
import struct
import sys
import traceback
import types

#: Analysis commands a model file may not call: pdamper sets up and runs the analysis itself.
_REFUSED = {"analyze": "runs an analysis", "analysis": "sets up an analysis", "integrator": "sets up an analysis",
            "algorithm": "sets up an analysis", "system": "sets up an analysis", "numberer": "sets up an analysis",
            "constraints": "sets up an analysis", "test": "sets up an analysis", "eigen": "runs an eigen analysis",
            "recorder": "writes files", "record": "writes files", "wipeAnalysis": "sets up an analysis",
            "pattern": "defines loads", "loadConst": "sets up an analysis", "database": "writes files",
            "logFile": "writes files", "printModel": "writes output", "reset": "changes the state",
            "setTime": "changes the state", "remove": "changes the model after it is built"}

#: Materials, sections and transformations whose response is linear; every other one makes the
#: model nonlinear (so it is co-simulated: OpenSees advances it with its own materials).
_LINEAR = {"uniaxialMaterial": {"Elastic"}, "nDMaterial": {"ElasticIsotropic", "ElasticOrthotropic"},
           "section": {"Elastic", "ElasticMembranePlateSection", "ElasticShear"},
           "geomTransf": {"Linear"}}
#: Elements that are linear when their materials and sections are.
_LINEAR_ELEMENTS = {"zeroLength", "zeroLengthSection", "twoNodeLink", "truss", "Truss", "trussSection",
                    "TrussSection", "elasticBeamColumn", "ElasticTimoshenkoBeam", "ElasticTimoshenkoBeam2d",
                    "forceBeamColumn", "dispBeamColumn", "nonlinearBeamColumn", "quad", "tri31", "stdBrick",
                    "bbarBrick", "ShellMITC4", "ShellDKGQ", "ShellNLDKGQ", "ElasticBeam2d", "ElasticBeam3d"}


class _Refused(Exception):
    pass


def _send(fd, obj):
    data = pickle.dumps(obj, protocol=pickle.HIGHEST_PROTOCOL)
    data = struct.pack("<I", len(data)) + data
    while data:
        n = os.write(fd, data)
        data = data[n:]


def _recv(fd):
    head = _read(fd, 4)
    if head is None:
        return None
    (n,) = struct.unpack("<I", head)
    return pickle.loads(_read(fd, n))


def _read(fd, n):
    out = b""
    while len(out) < n:
        chunk = os.read(fd, n - len(out))
        if not chunk:
            return None
        out += chunk
    return out


class _Proxy(types.ModuleType):
    """``openseespy.opensees`` as the model file sees it: every command passed on to OpenSees and
    noted (the materials, sections, transformations and elements a model is made of, its Rayleigh
    damping), the analysis commands refused."""

    def __init__(self, real):
        super().__init__("openseespy.opensees")
        self._real = real
        self.calls = []
        names = [n for n in dir(real) if not n.startswith("_")]
        self.__all__ = names
        for n in names:
            f = getattr(real, n)
            setattr(self, n, self._wrap(n, f) if callable(f) else f)

    def _wrap(self, name, f):
        def command(*args, **kw):
            if name in _REFUSED:
                raise _Refused(f"the model file calls ops.{name}(...), which {_REFUSED[name]}; a model file builds "
                               "the model only (nodes, fix, masses, materials, elements, ops.rayleigh): pdamper "
                               "applies the load and runs the analysis")
            self.calls.append((name, args))
            return f(*args, **kw)

        command.__name__ = name
        return command


def _compiled(path):
    """The model file's code (a syntax error raised before OpenSees is loaded)."""
    with open(path, "rb") as fh:
        source = fh.read()
    return compile(source, path, "exec")


def _build(path, real, code=None):
    """Execute the model file ``path`` (its ``code``) with the recording proxy as
    ``openseespy.opensees``; returns the proxy (its ``calls``)."""
    import openseespy

    code = _compiled(path) if code is None else code
    real.wipe()
    proxy = _Proxy(real)
    sys.modules["openseespy.opensees"] = proxy
    openseespy.opensees = proxy
    folder = os.path.dirname(os.path.abspath(path))
    if folder not in sys.path:
        sys.path.insert(0, folder)
    scope = {"__name__": "__pdamper_model__", "__file__": path}
    exec(code, scope)
    sys.modules["openseespy.opensees"] = real
    openseespy.opensees = real
    return proxy


def _nonlinear(calls):
    """Why the model is nonlinear (a list of words, e.g. "uniaxialMaterial Steel01 (tags 1, 2)");
    empty: linear."""
    found = {}
    for name, args in calls:
        if not args:
            continue
        kind = str(args[0])
        if (name in _LINEAR and kind not in _LINEAR[name]) or (name == "element" and kind not in _LINEAR_ELEMENTS):
            found.setdefault((name, kind), []).append(str(args[1]) if len(args) > 1 else "")
    out = []
    for (name, kind), tags in found.items():
        tags = [t for t in tags if t]
        out.append(f"{name} {kind}" + (f" (tag{'s' if len(tags) > 1 else ''} {', '.join(tags)})" if tags else ""))
    return out


def _equations(ops):
    """{node: [equation or -1 per dof]} after an analysis is set up."""
    return {int(n): [int(e) for e in ops.nodeDOFs(n)] for n in ops.getNodeTags()}


def _matrix(ops, m, c, k):
    import numpy as np

    ops.wipeAnalysis()
    ops.system("FullGeneral")
    ops.numberer("Plain")
    ops.constraints("Transformation")
    ops.algorithm("Linear")
    ops.integrator("GimmeMCK", float(m), float(c), float(k))
    ops.analysis("Transient")
    ops.analyze(1, 0.0)
    n = int(ops.systemSize())
    return np.array(ops.printA("-ret"), dtype=float).reshape(n, n)


def _check_nodes(ops, options, equations):
    """The damper, force and response nodes exist and move along ``dof``; the damper nodes have mass
    there. Returns the ndf of the damper nodes."""
    dof = options["dof"]
    nodes = sorted(equations)
    for role in ("damper", "force", "response"):
        for node in options.get(role + "_nodes", ()):
            key = options["keys"][role]
            if node not in equations:
                shown = ", ".join(map(str, nodes[:12])) + (", ..." if len(nodes) > 12 else "")
                raise _Refused(f"structure.{key} = {node}: the model has no node {node} (its nodes: {shown})")
            eqs = equations[node]
            if not 1 <= dof <= len(eqs):
                raise _Refused(f"structure.dof = {dof}: node {node} has {len(eqs)} dof{'s' if len(eqs) > 1 else ''} "
                               f"(1 to {len(eqs)}; 1 is x)")
            if eqs[dof - 1] < 0:
                raise _Refused(f"structure.{key} = {node}: its dof {dof} is fixed (or constrained to another "
                               "node's); give a node that moves along dof")
            if role == "damper":
                mass = ops.nodeMass(node, dof)
                if not mass > 0:
                    raise _Refused(f"structure.{key} = {node}: the node has no mass along dof {dof} "
                                   "(ops.mass); the damper sits on a floor or a mass of the model: give a node "
                                   "with mass")


def _model(path, options):
    code = _compiled(path)
    import numpy as np
    import openseespy.opensees as ops

    proxy = _build(path, ops, code)
    if not ops.getNodeTags():
        raise _Refused("the model file defines no nodes (ops.node)")
    M = _matrix(ops, 1.0, 0.0, 0.0)
    K = _matrix(ops, 0.0, 0.0, 1.0)
    C = _matrix(ops, 0.0, 1.0, 0.0)
    equations = _equations(ops)
    _check_nodes(ops, options, equations)
    rayleigh = [list(map(float, args)) for name, args in proxy.calls if name == "rayleigh"]
    return {"M": M, "K": K, "C": C, "equations": equations, "nonlinear": _nonlinear(proxy.calls),
            "rayleigh": rayleigh, "ndm": None, "finite": bool(np.all(np.isfinite(K)) and np.all(np.isfinite(M)))}


class _Session:
    """A model set up for the co-simulation (``("session", ...)``) and stepped by ``("step", ...)``."""

    def __init__(self, path, options):
        import openseespy.opensees as ops

        self.ops = ops
        _build(path, ops)
        self.o = options
        self.dof = int(options["dof"])
        # the empty containers' masses at the damper nodes, along dof
        for node, extra in options["added_masses"]:
            if extra:
                ndf = len(ops.nodeDisp(node))
                vals = [ops.nodeMass(node, d + 1) for d in range(ndf)]
                vals[self.dof - 1] += float(extra)
                ops.mass(node, *vals)
        ops.wipeAnalysis()
        self.ndf = {n: len(ops.nodeDisp(n)) for n in options["damper_nodes"]}
        step = float(options["step"])
        load = options.get("load")
        if load is not None:
            ops.timeSeries("Path", 1, "-dt", step, "-values", *[float(v) for v in load["values"]], "-factor", 1.0)
            if load["ground"]:
                ops.pattern("UniformExcitation", 1, self.dof, "-accel", 1)
            else:
                ops.pattern("Plain", 1, 1)
                for node, share in load["nodes"]:
                    ops.load(node, *self._unit(node, share))
        ops.timeSeries("Constant", 2)
        self.loads = 2
        for node, x0 in options.get("initial", ()):
            ops.setNodeDisp(node, self.dof, float(x0), "-commit")
        ops.constraints("Transformation")
        ops.numberer("RCM")
        ops.system("UmfPack")
        self.tolerance = float(options.get("tolerance", 1e-9))
        ops.test("NormDispIncr", self.tolerance, 30)
        ops.algorithm("Newton")
        ops.integrator("Newmark", 0.5, 0.25)
        ops.analysis("Transient")
        self.step = step
        self.t = 0.0
        self.has_pattern = False

    def _unit(self, node, value):
        n = len(self.ops.nodeDisp(node))
        v = [0.0] * n
        v[self.dof - 1] = float(value)
        return v

    def state(self):
        ops, d = self.ops, self.dof
        dn = self.o["damper_nodes"]
        rec = self.o["recorded"]
        return {"t": self.t,
                "x": [ops.nodeDisp(n, d) for n in dn], "v": [ops.nodeVel(n, d) for n in dn],
                "a": [ops.nodeAccel(n, d) for n in dn],
                "dofs_x": [ops.nodeDisp(n, k) for n, k in rec], "dofs_v": [ops.nodeVel(n, k) for n, k in rec]}

    def advance(self, forces):
        ops = self.ops
        if self.has_pattern:
            ops.remove("loadPattern", 2)
        ops.pattern("Plain", 2, self.loads)
        for node, f in zip(self.o["damper_nodes"], forces):
            ops.load(node, *self._unit(node, f))
        self.has_pattern = True
        if ops.analyze(1, self.step) != 0 and not self._retry():
            raise _NoConvergence(f"the OpenSees model did not converge in the step from t = {self.t:.6g} s to "
                                 f"{self.t + self.step:.6g} s (Newton, modified Newton from the initial tangent "
                                 f"and Newton with line search on 1/10 and 1/100 steps, NormDispIncr "
                                 f"{self.tolerance:g} m): the model fails there (a storey lost its strength?) or "
                                 "needs a smaller [structure] coupling_step")
        self.t += self.step
        return self.state()

    def _retry(self):
        """Sub-steps with other algorithms after Newton failed; True once the step is done."""
        ops = self.ops
        for algo, parts in ((("ModifiedNewton", "-initial"), 1), (("NewtonLineSearch",), 10),
                            (("NewtonLineSearch",), 100), (("ModifiedNewton", "-initial"), 100)):
            ops.algorithm(*algo)
            ops.test("NormDispIncr", self.tolerance, 100)
            done = 0
            while done < parts and ops.analyze(1, self.step / parts) == 0:
                done += 1
            ops.algorithm("Newton")
            ops.test("NormDispIncr", self.tolerance, 30)
            if done == parts:
                return True
            if done:  # part of the step done: the rest by the next algorithm is not started from t_n
                return False
        return False


class _NoConvergence(Exception):
    pass


def _orphaned(log):
    """The parent is gone: remove the log it would have removed."""
    if log:
        try:
            os.unlink(log)
        except OSError:
            pass


def _raised(exc, msg):
    """The reply to an exception the model file (or OpenSees under it) raised: its type, the line of
    the file, its last line of text."""
    tb = traceback.extract_tb(exc.__traceback__)
    where = [f for f in tb if len(msg) > 1 and f.filename == msg[1]]
    at = f" (line {where[-1].lineno})" if where else ""
    text = str(exc).strip().splitlines()
    return ("error", "raised", f"{type(exc).__name__}{at}: {text[-1] if text else ''}".rstrip(": "))


def main():
    rfd, wfd = int(sys.argv[1]), int(sys.argv[2])
    log = sys.argv[3] if len(sys.argv) > 3 else None
    session = None
    while True:
        msg = _recv(rfd)
        if msg is None:  # the parent is gone (killed): nothing to reply to, no one to read the log
            _orphaned(log)
            return
        if msg[0] == "close":
            return
        try:
            if msg[0] == "model":
                reply = ("ok", _model(msg[1], msg[2]))
            elif msg[0] == "session":
                session = _Session(msg[1], msg[2])
                reply = ("ok", session.state())
            elif msg[0] == "step":
                reply = ("ok", session.advance(msg[1]))
            elif msg[0] == "hello":
                import openseespy.opensees as ops  # noqa: F401  (is it there, does it load)

                reply = ("ok", None)
            else:
                reply = ("error", "model", f"unknown request {msg[0]!r}")
        except (ImportError, RuntimeError) as exc:
            if "openseespy" not in str(exc).lower() and "opensees" not in type(exc).__module__:
                reply = _raised(exc, msg)
            else:
                reply = ("error", "missing", f"{type(exc).__name__}: {exc}")
        except _NoConvergence as exc:
            reply = ("error", "converge", str(exc))
        except _Refused as exc:
            reply = ("error", "model", str(exc))
        except BaseException as exc:  # the user's file: anything it raises is its own, said in one line
            reply = _raised(exc, msg)
        sys.stdout.flush()
        sys.stderr.flush()
        try:
            _send(wfd, reply)
        except OSError:  # the parent died while this step ran
            _orphaned(log)
            return


if __name__ == "__main__":
    sys.path.pop(0)  # the package folder is not the user's
    main()
