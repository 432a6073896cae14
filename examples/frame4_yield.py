"""The 4-storey frame of frame4_linear.py with storeys that yield (pdamper: [structure] opensees = "frame4_yield.py").

Each storey spring is Steel01: the elastic stiffness k_i of frame4_linear.py, yield at a storey drift
of 6 mm (F_y = k_i 6 mm), 5 % strain hardening after. Nonlinear, so pdamper co-simulates it
(coupling = "auto"): OpenSees advances the frame with its own integrator and materials, pdamper's
DEM the beds, a coupling step at a time. Rayleigh damping on the initial stiffness
(betaKinit), so a yielded storey is not damped by its tangent.
"""

import math

import openseespy.opensees as ops

MASSES = [3.0, 3.0, 3.0, 2.5]
STIFFNESS = [4400.0, 4000.0, 3400.0, 2600.0]
YIELD_DRIFT = 0.006   # m
HARDENING = 0.05

ops.wipe()
ops.model("basic", "-ndm", 1, "-ndf", 1)
ops.node(0, 0.0)
ops.fix(0, 1)
for i, (m, k) in enumerate(zip(MASSES, STIFFNESS), start=1):
    ops.node(i, 0.0)
    ops.mass(i, m)
    ops.uniaxialMaterial("Steel01", i, k * YIELD_DRIFT, k, HARDENING)
    ops.element("zeroLength", i, i - 1, i, "-mat", i, "-dir", 1, "-doRayleigh", 1)

w1, w3 = 2 * math.pi * 2.078, 2 * math.pi * 8.205
zeta = 0.02
alpha = 2 * zeta * w1 * w3 / (w1 + w3)
beta = 2 * zeta / (w1 + w3)
ops.rayleigh(alpha, 0.0, beta, 0.0)
