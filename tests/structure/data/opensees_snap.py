# An OpenSees model that does not converge: a spring whose post-yield stiffness is negative (Steel01, b = -1.5)
# on a light mass (tests/structure/test_opensees.py).
import openseespy.opensees as ops
ops.wipe()
ops.model("basic", "-ndm", 1, "-ndf", 1)
ops.node(0, 0.0); ops.fix(0, 1)
ops.node(1, 0.0); ops.mass(1, 0.05)
ops.uniaxialMaterial("Steel01", 1, 10.0, 4400.0, -1.5)
ops.element("zeroLength", 1, 0, 1, "-mat", 1, "-dir", 1)
