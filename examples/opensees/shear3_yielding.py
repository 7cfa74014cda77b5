"""The 3-storey shear building with yielding storeys and P-Delta in OpenSees (what our
DampedShearBuilding3 models with storey[k].Fy, storey[k].b, p_delta = 1): Steel01 storeys
(Fy 6e5, 5e5, 3e5 N, b = 0.02), the gravity above each storey through a parallel negative spring
-P/h (h = 3 m; P includes the particle's 15 t on the roof, which the unit models), 2 % classical
modal damping from the elastic modes of K - K_G.  It builds the structure only:

    pidamper cosim --opensees examples/opensees/shear3_yielding.py --node 3 \\
        --ground-motion examples/opensees/pulse.csv --scale 2 --step 0.0025 --stop-time 5 \\
        -p m=15000 -p L1=0.0626 -p d=0.02 -p e=0.5
"""
import openseespy.opensees as ops

MASSES = (1e5, 1e5, 1e5)
STIFFNESSES = (8e7, 8e7, 8e7)
YIELD = (6e5, 5e5, 3e5)
B, H, ZETA, G = 0.02, 3.0, 0.02, 9.81
CARRIED = (0.0, 0.0, 15000.0)  # the particle's mass on its floor: its weight loads the storeys

ops.wipe()
ops.model("basic", "-ndm", 1, "-ndf", 1)
ops.node(0, 0.0)
ops.fix(0, 1)
for k in range(1, 4):
    ops.node(k, 0.0)
    ops.mass(k, MASSES[k - 1])
    ops.uniaxialMaterial("Steel01", k, YIELD[k - 1], STIFFNESSES[k - 1], B)
    ops.element("zeroLength", k, k - 1, k, "-mat", k, "-dir", 1)
    gravity = G * sum(m + c for m, c in zip(MASSES[k - 1:], CARRIED[k - 1:]))
    ops.uniaxialMaterial("Elastic", 100 + k, -gravity / H)
    ops.element("zeroLength", 100 + k, k - 1, k, "-mat", 100 + k, "-dir", 1)
ops.eigen("-fullGenLapack", 3)
ops.modalDamping(ZETA)
