"""The 3-storey shear building of our DampedShearBuilding3 in OpenSees, elastic: floor masses
1e5 kg, storey stiffnesses 8e7 N/m, 2 % classical modal damping.  Nodes 0 (ground, fixed) to 3 (the
roof) on one line, one degree of freedom each.  It builds the structure only:

    pidamper cosim --opensees examples/opensees/shear3_elastic.py --node 3 --dof 1 \\
        --ground-motion examples/opensees/pulse.csv --step 0.0025 --stop-time 5 \\
        -p m=15000 -p L1=0.0619 -p d=0.02 -p e=0.5 --csv-out out/shear3.csv
"""
import openseespy.opensees as ops

MASSES = (1e5, 1e5, 1e5)
STIFFNESSES = (8e7, 8e7, 8e7)
ZETA = 0.02

ops.wipe()
ops.model("basic", "-ndm", 1, "-ndf", 1)
ops.node(0, 0.0)
ops.fix(0, 1)
for k, (m, stiffness) in enumerate(zip(MASSES, STIFFNESSES), start=1):
    ops.node(k, 0.0)
    ops.mass(k, m)
    ops.uniaxialMaterial("Elastic", k, stiffness)
    ops.element("zeroLength", k, k - 1, k, "-mat", k, "-dir", 1)
ops.eigen("-fullGenLapack", len(MASSES))
ops.modalDamping(ZETA)
