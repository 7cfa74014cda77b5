"""OpenSees model of the SAC Los Angeles 9-storey pre-Northridge steel moment frame (one N-S perimeter
frame) and its first-mode static pushover, for calibrating a shear-building idealisation.

    python tools/la9_frame.py --out studies/la9/frame-pushover.json

Building: FEMA-355C (2000) Appendix B, LA 9-storey model building, = the nonlinear benchmark building
of Ohtori, Christenson, Spencer & Dyke (2004), J. Eng. Mech. 130(4) 366-385.  Units: N, m, kg, s.

Geometry: 5 bays of 9.15 m; basement 3.66 m, storey 1 (ground -> floor 2) 5.49 m, storeys 2-9 3.96 m.
The basement is modelled as in Ohtori 2004: column bases pinned at the basement level, the ground
level (floor 1) restrained horizontally (foundation walls).  Centreline model: no panel zones, no
column splices (a size change is made at the floor level of the storey it belongs to), no composite
action, no gravity-frame stiffness.  The right-hand end of the beams of the last bay is pinned (simple
connection at the corner column, as in the public OpenSees implementation of the benchmark,
github.com/siwalan/BenchmarkControlProblems, ninestory/tcl/model.tcl).

Member sizes (storey = column between the floor below and the floor above; beams by floor), as
FEMA-355C Table B-2 / Ohtori 2004 list them.  Source actually read: the public OpenSees implementation
of the benchmark (siwalan/BenchmarkControlProblems, ninestory/model.tcl + sectionData.tcl, column lists
{1 1 1 1 4 4 5 5 6 6} / {2 2 3 3 1 1 4 4 5 5}, beam list {7 7 7 8 8 8 8 9 10 11}); the FEMA-355C
table itself was not readable in the stored copies (only its Sec. B.1 text), so the agreement with it
rests on that implementation and on the sizes quoted in the brief:

    storey  exterior  interior  | floor  beam
    B       W14x370   W14x500   | 1 (ground) W36x160
    1       W14x370   W14x500   | 2      W36x160
    2       W14x370   W14x455   | 3      W36x160
    3       W14x370   W14x455   | 4-7    W36x135
    4-5     W14x283   W14x370   | 8      W30x99
    6-7     W14x257   W14x283   | 9      W27x84
    8-9     W14x233   W14x257   | roof   W24x68

Section properties: AISC Shapes Database (the AISC table in OpenSees' SteelWSection.tcl, F. McKenna);
h is taken as d - 2 tf (clear web depth without fillets, an approximation).

Material: E = 200 GPa; expected yield strengths FEMA-355C / Gupta & Krawinkler (1999) use for the
SAC models: A36 beams 49.2 ksi (339 MPa), A572 Gr 50 columns 57.6 ksi (397 MPa).  These two values
are quoted from memory of FEMA-355C Sec. 3 and were NOT verified against a public copy.

Hinges: elastic beam-columns (I scaled by (n+1)/n, n = 10) between zeroLength rotational springs
(OpenSees `Bilin`, the modified Ibarra-Medina-Krawinkler bilinear model, K = (n+1) 6EI/L, post-yield
ratio (Mc/My - 1) My / (theta_p K); Ibarra & Krawinkler 2005, Zareian & Medina 2010).  The newer
`IMKBilin` (and `IMKPeakOriented`) were tried first: with OpenSeesPy 3.7.1 Newton diverged at the
first beam yield in this model with every algorithm and step reduction tried, while Steel01 and `Bilin`
springs converge.  OpenSees prints a deprecation warning for `Bilin`; its monotonic backbone is the
same modified-IMK one.
  Beams, Lignos & Krawinkler (2011) J. Struct. Eng. 137(11), other-than-RBS, d >= 533 mm:
    theta_p  = 0.318 (h/tw)^-0.550 (bf/2tf)^-0.345 (Lb/ry)^-0.023 (L/d)^0.090 (d/533)^-0.330 (Fy/355)^-0.130
    theta_pc = 7.50  (h/tw)^-0.610 (bf/2tf)^-0.710 (Lb/ry)^-0.110 (d/533)^-0.161 (Fy/355)^-0.320
    Lambda   = 536   (h/tw)^-1.260 (bf/2tf)^-0.525 (Lb/ry)^-0.130 (Fy/355)^-0.291     (d in mm, Fy in MPa)
    My = 1.1 Zx Fy_exp, Mc/My = 1.1, Mr = 0.4 My, theta_u = 0.2 rad; L = shear span = half the span,
    Lb = half the span.  Equations as coded by Lignos' group in amaelkady/FM-2D src/Spring_IMK.tcl
    (note: OpenSees' SteelWSection.tcl uses d/tw in place of h/tw and the d < 533 mm set; not used).
  Columns, Lignos, Hartloper, Elkady, Deierlein & Hamburger (2019) J. Struct. Eng. 145(9), from the
    same FM-2D source: theta_p = 294 (h/tw)^-1.7 (Lb/ry)^-0.7 (1-p)^1.6 <= 0.2,
    theta_pc = 90 (h/tw)^-0.8 (Lb/ry)^-0.8 (1-p)^2.5 <= 0.3, p = Pg/Py (gravity, tributary estimate),
    My = 1.15 Zx Fy (1 - p/2) for p <= 0.2 else 1.15 (9/8) Zx Fy (1 - p),
    Mc/My = 12.5 (h/tw)^-0.2 (Lb/ry)^-0.4 (1-p)^0.4 in [1, 1.3], Mr = (0.5 - 0.4 p) My, theta_u 0.15.
    (The heavy W14 columns lie outside the calibration range in h/tw; the caps govern.)

Gravity and P-Delta: per-frame seismic masses (half the building's, Ohtori 2004: 1.01e6 kg floor 2,
9.89e5 kg floors 3-9, 1.07e6 kg roof).  Of each floor weight m g, FRAME_SHARE = 25 % (tributary floor
strip 150 ft x 17 ft + cladding, of the half-building) is a uniform load on that floor's frame beams;
75 % sits on a leaning column (elastic, PDelta, pinned, tied to the frame by equalDOF in x).  Frame
columns use PDelta transformation.  Horizontal masses at the frame joints (interior 1/5, exterior 1/10
of the floor mass).

Pushovers: lateral loads m_i phi_i (first mode; "steps") and a load at the roof alone ("steps_roof_load":
the same shear in every storey, so that the upper storeys yield) on the floors above ground, displacement control at the
roof, until the base shear has lost 40 % of its peak (or 20 % roof drift).  Storey shear = the applied
lateral load above the storey (includes the leaning column's P-Delta; base shear = storey-1 shear);
the sum of frame-column shears (leaning column excluded) is written as well.
"""
import argparse
from importlib.metadata import version
import json
import math
import os
import sys
import time

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "harness"))
from pidamper.oracles.opensees import load  # noqa: E402

IN, KSI, G = 0.0254, 6.894757e6, 9.81
E = 200e9
FY_BEAM, FY_COL = 49.2 * KSI, 57.6 * KSI
N_MOD = 10.0
FRAME_SHARE = 0.25
BAY = 9.15
H_BASEMENT = 3.66
STOREY_H = [5.49] + [3.96] * 8                      # storeys 1..9 (above ground)
MASSES = [5.05e5] + [4.945e5] * 7 + [5.35e5]          # floors 2..roof, one frame [kg]
OHTORI_FREQ = [0.443, 1.18, 2.05]                     # Hz, Ohtori et al. 2004
PIN_LAST_BAY = True
RIGID = 1                                             # material tag of the rigid zeroLength directions

# AISC Shapes Database: A [in2], d, bf, tw, tf [in], Ix [in4], Zx [in3], ry [in]
AISC = {
    "W14X500": (147.0, 19.6, 17.0, 2.19, 3.50, 8210, 1050, 4.43),
    "W14X455": (134.0, 19.0, 16.8, 2.02, 3.21, 7190, 936, 4.38),
    "W14X370": (109.0, 17.9, 16.5, 1.66, 2.66, 5440, 736, 4.27),
    "W14X283": (83.3, 16.7, 16.1, 1.29, 2.07, 3840, 542, 4.17),
    "W14X257": (75.6, 16.4, 16.0, 1.18, 1.89, 3400, 487, 4.13),
    "W14X233": (68.5, 16.0, 15.9, 1.07, 1.72, 3010, 436, 4.10),
    "W36X160": (47.0, 36.0, 12.0, 0.650, 1.02, 9760, 624, 2.50),
    "W36X135": (39.9, 35.6, 12.0, 0.600, 0.790, 7800, 509, 2.38),
    "W30X99": (29.0, 29.7, 10.5, 0.520, 0.670, 3990, 312, 2.10),
    "W27X84": (24.7, 26.7, 10.0, 0.460, 0.640, 2850, 244, 2.07),
    "W24X68": (20.1, 23.7, 8.97, 0.415, 0.585, 1830, 177, 1.87),
}
# storeys B, 1..9: (exterior, interior); beams on levels 1 (ground) .. 10 (roof)
COLUMNS = ([("W14X370", "W14X500")] * 2 + [("W14X370", "W14X455")] * 2 + [("W14X283", "W14X370")] * 2
           + [("W14X257", "W14X283")] * 2 + [("W14X233", "W14X257")] * 2)
BEAMS = ["W36X160"] * 3 + ["W36X135"] * 4 + ["W30X99", "W27X84", "W24X68"]


def section(name):
    """SI properties of a W section: dict with A [m2], d, bf, tw, tf, ry, h [m], I [m4], Z [m3]."""
    A, d, bf, tw, tf, Ix, Zx, ry = AISC[name]
    return dict(A=A * IN**2, d=d * IN, bf=bf * IN, tw=tw * IN, tf=tf * IN, I=Ix * IN**4, Z=Zx * IN**3,
                ry=ry * IN, h=(d - 2 * tf) * IN)


def beam_hinge(s, L):
    """IMK backbone of a beam hinge (Lignos & Krawinkler 2011, other-than-RBS, d >= 533 mm)."""
    htw, bftf, lbry = s["h"] / s["tw"], s["bf"] / (2 * s["tf"]), (L / 2) / s["ry"]
    dmm, fy = s["d"] * 1e3 / 533.0, FY_BEAM / 1e6 / 355.0
    tp = 0.318 * htw**-0.550 * bftf**-0.345 * lbry**-0.023 * ((L / 2) / s["d"])**0.090 * dmm**-0.330 * fy**-0.130
    tpc = 7.50 * htw**-0.610 * bftf**-0.710 * lbry**-0.110 * dmm**-0.161 * fy**-0.320
    lam = 536.0 * htw**-1.260 * bftf**-0.525 * lbry**-0.130 * fy**-0.291
    return dict(My=1.1 * s["Z"] * FY_BEAM, McMy=1.1, tp=tp, tpc=tpc, tu=0.2, res=0.4, lam=lam)


def column_hinge(s, L, p):
    """IMK backbone of a column hinge (Lignos et al. 2019), p = gravity axial load / (A Fy)."""
    htw, lbry = s["h"] / s["tw"], L / s["ry"]
    tp = min(294.0 * htw**-1.7 * lbry**-0.7 * (1 - p)**1.6, 0.2)
    tpc = min(90.0 * htw**-0.8 * lbry**-0.8 * (1 - p)**2.5, 0.3)
    lam = min(25500.0 * htw**-2.14 * lbry**-0.53 * (1 - p)**4.92, 3.0)
    Mp = s["Z"] * FY_COL
    My = 1.15 * Mp * (1 - p / 2) if p <= 0.2 else 1.15 * Mp * 9 / 8 * (1 - p)
    McMy = min(max(12.5 * htw**-0.2 * lbry**-0.4 * (1 - p)**0.4, 1.0), 1.3)
    return dict(My=My, McMy=McMy, tp=tp, tpc=tpc, tu=0.15, res=0.5 - 0.4 * p, lam=lam)


class Frame:
    """Builds the OpenSees domain; keeps node / element tags for recording."""

    def __init__(self, ops):
        self.ops, self.next_tag, self.hinges = ops, 10000, []
        self.y = [0.0, H_BASEMENT]
        for h in STOREY_H:
            self.y.append(self.y[-1] + h)
        self.w_beam = [0.0, 0.0] + [FRAME_SHARE * m * G / (5 * BAY) for m in MASSES]   # by level 0..10 [N/m]

    def tag(self):
        self.next_tag += 1
        return self.next_tag

    @staticmethod
    def joint(level, col):
        return 100 * level + col

    def spring(self, node, hinge, K, member, level):
        """A hinge node at `node`, joined by a zeroLength: rigid in x, y, Bilin in rotation (hinge=None: a
        pin).  Not equalDOF: with the Transformation handler the hinge nodes at the fixed ground joints
        were seen to slide, and DisplacementControl then failed."""
        ops, h = self.ops, hinge
        hn, ele = self.tag(), self.tag()
        ops.node(hn, *ops.nodeCoord(node))
        if h is None:
            ops.element("zeroLength", ele, node, hn, "-mat", RIGID, RIGID, "-dir", 1, 2)
            return hn
        mat = self.tag()
        a_s = (h["McMy"] - 1) * h["My"] / (h["tp"] * K)            # post-yield / elastic stiffness
        ops.uniaxialMaterial("Bilin", mat, K, a_s, a_s, h["My"], -h["My"], *[h["lam"]] * 4, 1.0, 1.0, 1.0, 1.0,
                             h["tp"], h["tp"], h["tpc"], h["tpc"], h["res"], h["res"], h["tu"], h["tu"], 1.0, 1.0)
        ops.element("zeroLength", ele, node, hn, "-mat", RIGID, RIGID, mat, "-dir", 1, 2, 6)
        self.hinges.append(dict(ele=ele, member=member, level=level, cap=h["My"] / K + h["tp"]))
        return hn

    def build(self):
        ops = self.ops
        ops.wipe()
        ops.model("basic", "-ndm", 2, "-ndf", 3)
        ops.geomTransf("PDelta", 1)
        ops.geomTransf("Linear", 2)
        ops.uniaxialMaterial("Elastic", RIGID, 1e13)                 # zeroLength translations [N/m]
        for lev, y in enumerate(self.y):
            for c in range(1, 7):
                ops.node(self.joint(lev, c), (c - 1) * BAY, y)
            if lev >= 1:
                ops.node(self.joint(lev, 7), 6 * BAY, y)              # leaning column
        for c in range(1, 7):
            ops.fix(self.joint(0, c), 1, 1, 0)                        # pinned basement bases
            ops.fix(self.joint(1, c), 1, 0, 0)                        # ground level restrained in x
        ops.fix(self.joint(1, 7), 1, 1, 0)
        for lev in range(2, 11):
            ops.equalDOF(self.joint(lev, 1), self.joint(lev, 7), 1)
        self.columns, self.lean = [], []
        # gravity axial load on columns by tributary beam length, storeys B..9
        P = [[sum(self.w_beam[l] * BAY * (0.5 if c in (1, 6) else 1.0) for l in range(s + 1, 11))
              for c in range(1, 7)] for s in range(10)]
        for s in range(10):
            L = self.y[s + 1] - self.y[s]
            sc = []
            for c in range(1, 7):
                sec = section(COLUMNS[s][0 if c in (1, 6) else 1])
                hinge = column_hinge(sec, L, P[s][c - 1] / (sec["A"] * FY_COL))
                K = (N_MOD + 1) * 6 * E * sec["I"] / L
                i = self.spring(self.joint(s, c), hinge, K, "column", s)
                j = self.spring(self.joint(s + 1, c), hinge, K, "column", s)
                ele = self.tag()
                ops.element("elasticBeamColumn", ele, i, j, sec["A"], E, sec["I"] * (N_MOD + 1) / N_MOD, 1)
                sc.append(ele)
            self.columns.append(sc)
            if s >= 1:
                ele = self.tag()
                ops.element("elasticBeamColumn", ele, self.joint(s, 7), self.joint(s + 1, 7), 1.0, E, 1e-7, 1)
                self.lean.append(ele)
        self.beams = []
        for lev in range(1, 11):
            sec = section(BEAMS[lev - 1])
            hinge = beam_hinge(sec, BAY)
            K = (N_MOD + 1) * 6 * E * sec["I"] / BAY
            for c in range(1, 6):
                i = self.spring(self.joint(lev, c), hinge, K, "beam", lev)
                pin = PIN_LAST_BAY and c == 5
                j = self.spring(self.joint(lev, c + 1), None if pin else hinge, K, "beam", lev)
                ele = self.tag()
                ops.element("elasticBeamColumn", ele, i, j, sec["A"], E, sec["I"] * (N_MOD + 1) / N_MOD, 2)
                self.beams.append((ele, lev))
        for k, m in enumerate(MASSES):
            for c in range(1, 7):
                share = 0.1 if c in (1, 6) else 0.2
                ops.mass(self.joint(k + 2, c), share * m, 0.0, 0.0)

    def gravity(self):
        """Frame share as uniform beam loads, the rest on the leaning column; 10 load steps, then held."""
        ops = self.ops
        ops.timeSeries("Linear", 1)
        ops.pattern("Plain", 1, 1)
        for ele, lev in self.beams:
            ops.eleLoad("-ele", ele, "-type", "-beamUniform", -self.w_beam[lev])
        for k, m in enumerate(MASSES):
            ops.load(self.joint(k + 2, 7), 0.0, -(1 - FRAME_SHARE) * m * G, 0.0)
        ops.constraints("Transformation")
        ops.numberer("RCM")
        ops.system("UmfPack")
        ops.test("NormDispIncr", 1e-8, 50)
        ops.algorithm("Newton")
        ops.integrator("LoadControl", 0.1)
        ops.analysis("Static")
        if ops.analyze(10) != 0:
            raise RuntimeError("gravity analysis failed")
        ops.loadConst("-time", 0.0)

    def eigen(self, n=3):
        """Periods [s] and the first mode's floor displacements (floors 2..roof, column line 1)."""
        lam = self.ops.eigen(n)
        phi = [self.ops.nodeEigenvector(self.joint(lev, 1), 1, 1) for lev in range(2, 11)]
        return [2 * math.pi / math.sqrt(v) for v in lam], phi

    def floor_disp(self):
        return [self.ops.nodeDisp(self.joint(lev, 1), 1) for lev in range(2, 11)]


def pushover(fr, weights, step, max_drift, stop_loss):
    """Displacement-controlled pushover under lateral loads in proportion to `weights` (floors 2..roof);
    returns per-step records."""
    ops = fr.ops
    F = [w / sum(weights) for w in weights]                      # unit total lateral load [N]
    ops.timeSeries("Linear", 2)
    ops.pattern("Plain", 2, 2)
    for k, f in enumerate(F):
        for c in range(1, 7):
            ops.load(fr.joint(k + 2, c), f * (0.1 if c in (1, 6) else 0.2), 0.0, 0.0)
    H = fr.y[-1] - fr.y[1]
    roof = fr.joint(10, 1)
    ops.wipeAnalysis()
    ops.constraints("Transformation")
    ops.numberer("RCM")
    ops.system("UmfPack")
    ops.test("NormDispIncr", 1e-7, 100)
    ops.algorithm("Newton")
    ops.integrator("DisplacementControl", roof, 1, step)
    ops.analysis("Static")
    fallbacks = [("Newton",), ("ModifiedNewton", "-initial"), ("KrylovNewton",), ("NewtonLineSearch", 0.8)]
    rec = dict(roof_drift=[], base_shear=[], storey_shear=[], storey_shear_frame_columns=[], storey_drift=[])
    vmax, loss = 0.0, 0.0
    while True:
        ok, du = -1, step
        for _ in range(4):                                       # quarter the step on failure
            for alg in fallbacks:
                ops.algorithm(*alg)
                ops.integrator("DisplacementControl", roof, 1, du)
                ok = ops.analyze(1)
                if ok == 0:
                    break
            if ok == 0:
                break
            du /= 4.0
        ops.algorithm("Newton")
        if ok != 0:
            print(f"pushover stopped: no convergence at roof drift {ops.nodeDisp(roof, 1) / H:.4f}")
            break
        lam = ops.getLoadFactor(2)
        u = fr.floor_disp()
        shear = [lam * sum(F[k:]) for k in range(9)]
        col = []
        for s in range(1, 10):
            col.append(-sum(ops.eleForce(e)[0] for e in fr.columns[s]))
        rec["roof_drift"].append(u[-1] / H)
        rec["base_shear"].append(shear[0])
        rec["storey_shear"].append(shear)
        rec["storey_shear_frame_columns"].append(col)
        rec["storey_drift"].append([u[0]] + [u[k] - u[k - 1] for k in range(1, 9)])
        vmax = max(vmax, shear[0])
        loss = 1 - shear[0] / vmax
        if loss >= stop_loss or u[-1] / H >= max_drift:
            break
    return rec


def hinge_summary(fr):
    """Per storey / floor: hinges whose rotation passed the capping point."""
    out = {}
    for h in fr.hinges:
        rot = abs(fr.ops.eleResponse(h["ele"], "deformation")[-1])
        key = f"{h['member']} {'storey' if h['member'] == 'column' else 'level'} {h['level']}"
        d = out.setdefault(key, dict(n=0, past_cap=0, max_rot=0.0))
        d["n"] += 1
        d["past_cap"] += rot > h["cap"]
        d["max_rot"] = max(d["max_rot"], rot)
    return out


def _rounded(rec, digits=7):
    """The records with every number to `digits` significant digits (the file stays small)."""
    r = lambda v: [r(x) for x in v] if isinstance(v, list) else float(f"{v:.{digits - 1}e}")  # noqa: E731
    return {k: r(v) for k, v in rec.items()}


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", default="studies/la9/frame-pushover.json")
    ap.add_argument("--step", type=float, default=0.002, help="roof displacement increment [m]")
    ap.add_argument("--max-drift", type=float, default=0.20, help="hard stop, roof drift ratio")
    ap.add_argument("--stop-loss", type=float, default=0.40, help="stop at this base-shear loss after peak")
    a = ap.parse_args()
    t0 = time.time()
    ops = load()
    fr = Frame(ops)
    fr.build()
    ops.constraints("Transformation")
    ops.numberer("RCM")
    ops.system("UmfPack")
    T0, _ = fr.eigen()
    fr.gravity()
    T, phi = fr.eigen()
    rec = pushover(fr, [m * p for m, p in zip(MASSES, phi)], a.step, a.max_drift, a.stop_loss)
    hs = hinge_summary(fr)
    fr = Frame(ops)  # the roof-load pushover, from a new frame: the same shear in every storey, so that
    fr.build()       # the upper storeys (whose capacity the first-mode pattern does not reach) yield
    fr.gravity()
    roof_rec = pushover(fr, [0.0] * 8 + [1.0], a.step, a.max_drift, a.stop_loss)
    W = sum(MASSES) * G
    V = rec["base_shear"]
    i_pk = max(range(len(V)), key=V.__getitem__)
    fall80 = next((rec["roof_drift"][i] for i in range(i_pk, len(V)) if V[i] <= 0.8 * V[i_pk]), None)
    d_pk, d_end = rec["storey_drift"][i_pk], rec["storey_drift"][-1]
    h = STOREY_H
    out = dict(
        opensees=f"openseespy {version('openseespy')}; static, Transformation constraints, UmfPack, "
                 f"NormDispIncr 1e-7, Newton with fallbacks, DisplacementControl at the roof, {a.step} m steps",
        source="FEMA-355C App. B LA 9-storey pre-Northridge; Ohtori et al. 2004 J. Eng. Mech. 130(4); "
               "hinges Lignos & Krawinkler 2011 (beams), Lignos et al. 2019 (columns)",
        model="2D centreline N-S perimeter frame, 5 bays, basement (pinned bases, ground restrained), "
              "elastic members + Bilin (modified IMK) end springs (n=10), PDelta, leaning column, no panel zones",
        periods=T0, periods_after_gravity=T, ohtori_periods=[1 / f for f in OHTORI_FREQ],
        heights=[y - fr.y[1] for y in fr.y[2:]], storey_heights=h, masses=MASSES,
        weights_on_frame_and_leaning=dict(frame_beams=[FRAME_SHARE * m * G for m in MASSES],
                                          leaning_column=[(1 - FRAME_SHARE) * m * G for m in MASSES]),
        W=W, mode1=[p / phi[-1] for p in phi],
        definitions="storey_shear = applied lateral load above the storey (leaning-column P-Delta "
                    "included); storey_shear_frame_columns = sum of frame column shears; drifts in m",
        steps=_rounded(rec), steps_roof_load=_rounded(roof_rec), hinges_at_end=hs)
    os.makedirs(os.path.dirname(os.path.abspath(a.out)), exist_ok=True)
    with open(a.out, "w") as f:
        json.dump(out, f)
    print(f"periods (bare)      T1..3 = {', '.join(f'{t:.3f}' for t in T0)} s")
    print(f"periods (gravity)   T1..3 = {', '.join(f'{t:.3f}' for t in T)} s")
    print(f"Ohtori 2004         T1..3 = {', '.join(f'{1 / x:.3f}' for x in OHTORI_FREQ)} s")
    print(f"W = {W / 1e6:.2f} MN; V_max/W = {V[i_pk] / W:.4f} at roof drift {rec['roof_drift'][i_pk]:.4f}")
    print(f"roof drift at 0.8 V_max (falling): {fall80}; last step: drift {rec['roof_drift'][-1]:.4f}, "
          f"V/V_max {V[-1] / V[i_pk]:.3f}, {len(V)} steps")
    print("storey drift ratio at peak / at end:")
    for s in range(9):
        print(f"  storey {s + 1}: {d_pk[s] / h[s]:.4f} / {d_end[s] / h[s]:.4f}")
    print("hinges past capping at end:", {k: v["past_cap"] for k, v in hs.items() if v["past_cap"]})
    print(f"wrote {a.out} in {time.time() - t0:.1f} s")


if __name__ == "__main__":
    main()
