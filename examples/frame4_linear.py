"""A bench-scale 4-storey shear frame as an OpenSeesPy model (pdamper: [structure] opensees = "frame4_linear.py").

One node per floor along x (ndm = 1, ndf = 1), the ground node fixed, a zeroLength spring per storey
of elastic stiffness k_i, Rayleigh damping of 2 % at the first and third modes. A model file builds
the model only: no analysis, no load pattern (pdamper applies the [load] and runs the analysis).

The trap: a zeroLength element takes part in ops.rayleigh's stiffness-proportional damping only
with '-doRayleigh', 1; without it the storeys are damped by the mass-proportional part alone
(pdamper warns that the damping is not proportional).

frame4_yield.py is the same frame with storeys that yield (Steel01).
"""

import math

import openseespy.opensees as ops

MASSES = [3.0, 3.0, 3.0, 2.5]              # kg per floor, the roof last
STIFFNESS = [4400.0, 4000.0, 3400.0, 2600.0]  # N/m per storey, the ground storey first

ops.wipe()
ops.model("basic", "-ndm", 1, "-ndf", 1)
ops.node(0, 0.0)
ops.fix(0, 1)
for i, (m, k) in enumerate(zip(MASSES, STIFFNESS), start=1):
    ops.node(i, 0.0)
    ops.mass(i, m)
    ops.uniaxialMaterial("Elastic", i, k)
    ops.element("zeroLength", i, i - 1, i, "-mat", i, "-dir", 1, "-doRayleigh", 1)

# Rayleigh damping, 2 % at modes 1 and 3 (their frequencies from the same masses and springs)
w1, w3 = 2 * math.pi * 2.078, 2 * math.pi * 8.205
zeta = 0.02
alpha = 2 * zeta * w1 * w3 / (w1 + w3)
beta = 2 * zeta / (w1 + w3)
ops.rayleigh(alpha, 0.0, 0.0, beta)
