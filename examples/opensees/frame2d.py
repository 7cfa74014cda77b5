"""A 3-storey, one-bay steel moment frame in 2D with concentrated plastic hinges: a structure our
FMUs cannot model.  Elastic beam-column members (E = 200 GPa; columns with a P-Delta transformation)
join at rotational hinges, bilinear in moment and rotation (Steel01: plastic moment Mp, 3 % hardening,
stiff elastic branch), at both ends of every beam and at the column bases.  Floors 6 m wide, 3.5 m
high; 60 t per floor lumped at the beam-column joints, the two joints of a floor tied horizontally
(equalDOF: a rigid floor, so the left joint carries the floor's whole horizontal mass); gravity
(300 kN per joint) applied first by a static analysis and held; 2 % classical modal damping.
Node 31 is the roof's left joint (the retained one).  It builds the structure only:

    pidamper cosim --opensees examples/opensees/frame2d.py --node 31 --dof 1 \\
        --ground-motion examples/opensees/northridge-mul009.csv --step 0.005 --stop-time 20 \\
        -p m=9000 -p L1=0.157 -p d=0.05 -p e=0.5
"""
import math

import openseespy.opensees as ops

E, H, W, FLOORS = 200e9, 3.5, 6.0, 3
COLUMN = {"A": 0.025, "I": 6.0e-4, "Mp": 1.3e6}
BEAM = {"A": 0.020, "I": 5.0e-4, "Mp": 0.9e6}
FLOOR_MASS, GRAVITY, ZETA, HARDENING = 60e3, 300e3, 0.02, 0.03


def hinge(tag, node_i, node_j, member, length, material):
    """A rotational spring between two coincident nodes: stiff elastic branch (20 x 6EI/L), plastic
    at the member's Mp; the translations held by stiff springs (so the only multi-point constraint
    is the floor's equalDOF: OpenSees's Transformation handler does not chain constraints)."""
    k = 20.0 * 6.0 * E * member["I"] / length
    ops.uniaxialMaterial("Steel01", material, member["Mp"], k, HARDENING * E * member["I"] / length / k)
    ops.element("zeroLength", tag, node_i, node_j, "-mat", RIGID, RIGID, material, "-dir", 1, 2, 3)


ops.wipe()
ops.model("basic", "-ndm", 2, "-ndf", 3)
RIGID = 9999
ops.uniaxialMaterial("Elastic", RIGID, 1e13)
ops.geomTransf("PDelta", 1)
ops.geomTransf("Linear", 2)
for line, x in enumerate((0.0, W), start=1):
    ops.node(line, x, 0.0)  # base, fixed
    ops.fix(line, 1, 1, 1)
    ops.node(100 + line, x, 0.0)  # column foot, above the base hinge
    hinge(100 + line, line, 100 + line, COLUMN, H, 100 + line)
    for floor in range(1, FLOORS + 1):
        joint = 10 * floor + line
        ops.node(joint, x, floor * H)
        ops.mass(joint, FLOOR_MASS / 2.0, 1e-6, 1e-6)
        below = 100 + line if floor == 1 else 10 * (floor - 1) + line
        ops.element("elasticBeamColumn", 200 + joint, below, joint, COLUMN["A"], E, COLUMN["I"], 1)
for floor in range(1, FLOORS + 1):
    left, right = 10 * floor + 1, 10 * floor + 2
    ends = (1000 + left, 1000 + right)  # the beam's own end nodes, hinged to the joints
    ops.node(ends[0], 0.0, floor * H)
    ops.node(ends[1], W, floor * H)
    hinge(300 + left, left, ends[0], BEAM, W, 300 + left)
    hinge(300 + right, right, ends[1], BEAM, W, 300 + right)
    ops.element("elasticBeamColumn", 400 + floor, ends[0], ends[1], BEAM["A"], E, BEAM["I"], 2)
    ops.equalDOF(left, right, 1)  # a rigid floor
# gravity, held
ops.timeSeries("Linear", 1)
ops.pattern("Plain", 1, 1)
for floor in range(1, FLOORS + 1):
    for line in (1, 2):
        ops.load(10 * floor + line, 0.0, -GRAVITY, 0.0)
ops.constraints("Transformation")
ops.numberer("RCM")
ops.system("FullGeneral")
ops.test("NormDispIncr", 1e-12, 20)
ops.algorithm("Newton")
ops.integrator("LoadControl", 0.1)
ops.analysis("Static")
ops.analyze(10)
ops.loadConst("-time", 0.0)
ops.wipeAnalysis()
# damping from the modes under gravity
ops.constraints("Transformation")
periods = [2.0 * math.pi / math.sqrt(lam) for lam in ops.eigen(3)]
ops.modalDamping(ZETA)
