"""Write the shipped studies' performance models: studies/office-3-components.csv from the FEMA
P-58 Normative Quantity Estimation Tool's office quantities, and from it the same office as built
in seismic design category D (studies/office-3-components-sdc-d.csv).

    pip install normqtypact==0.2.0 openpyxl   # reads FEMA's tool (FEMA P-58-3, 2018), not in the extras
    python tools/office_components.py NQ.csv studies/office-3-components.csv
    python tools/office_components.py --sdc-d studies/office-3-components.csv studies/office-3-components-sdc-d.csv
    python tools/office_components.py --la9 studies/office-3-components-sdc-d.csv studies/office-9-components-sdc-d.csv

NQ.csv: the tool's pelicun component list for 3 storeys of 10,000 sq ft of OFFICE occupancy
(normqtypact's PurePythonNormQtyPact(...).Output_PelicunComponentDirectory; its __init__ needs
win32com: load normqtypact/python_core.py directly).  The quantities and blocks are scaled to the
study's floor area; contents (E.20.22: no repair consequence) and components whose library fragility
is incomplete (C.20.11.001a) are left out, roofing kept on the top storey only, the steel stair C.20.11.001b stands in for the latter;
the moment-frame connections come from the stated frame layout (STRUCTURE).

--sdc-d (SDC_D): each nonstructural component the tool gives with its SDC A-C fragility (unbraced,
unanchored, not seismically rated) takes the library's SDC D-F one of the same kind and size (braced,
anchored, seismically rated; where the library has no complete SDC D-F fragility of that kind, its
SDC C one, said in the comment); the roof tiles and the rooftop plant go on the roof (pelicun's
location "roof": the roof slab's floor acceleration); the gravity framing's shear tabs (GRAVITY) are
added.

--la9 (LA9): the same office per floor area, on the 9 storeys of 150 x 150 ft of the SAC Los Angeles
9-storey building (FEMA-355C, Appendix B): the first storey's components on floor 1, the middle
storey's on floors 2 to 8, the top storey's on floor 9, each quantity and its blocks scaled by the
floor area; the roof's by the roof area; the structure replaced by that building's frames and
gravity framing (LA9_STRUCTURE)."""
import csv
import sys

FLOOR_AREA_SQFT = 200.0 * 10.7639  # the study's 200 m2 per storey
TOOL_AREA_SQFT = 10000.0
LEFT_OUT = ("E.20.22", "C.20.11.001a")
ROOF = "B.30.11"  # roofing: the tool lists it per storey; only the top storey has a roof
#: two moment frames per direction, two bays each, per storey and direction: the four exterior
#: beam-column joints have a beam on one side, the two interior ones beams on both sides
STRUCTURE = (("B.10.35.001", "ea", "1--3", "1,2", 4, 4, "RBS connection, beam one side (2 frames x 2 exterior joints)"),
             ("B.10.35.011", "ea", "1--3", "1,2", 2, 2, "RBS connection, beams both sides (2 frames x 1 interior joint)"),
             ("C.20.11.001b", "ea", "1--3", "1,2", 1, 1, "prefabricated steel stair, one per storey"))


#: SDC A-C component -> the library's SDC D-F one (or SDC C where that is all it has), and why
SDC_D = {"C.30.32.001a": ("C.30.32.003a", "suspended ceiling, SDC D,E (Ip = 1.0), vertical and lateral support"),
         "D.20.21.011a": ("D.20.21.013a", "potable piping, SDC D, E or F"),
         "D.30.41.011a": ("D.30.41.011c", "HVAC ducting < 6 sq ft, SDC D, E or F"),
         "D.30.41.012a": ("D.30.41.012c", "HVAC ducting >= 6 sq ft, SDC D, E or F"),
         "D.30.41.031a": ("D.30.41.031b", "HVAC drops in suspended ceilings: SDC C (no complete SDC D-F fragility)"),
         "D.30.41.041a": ("D.30.41.041b", "VAV box: SDC C (no complete SDC D-F fragility)"),
         "D.40.11.021a": ("D.40.11.024a", "sprinkler mains and branches with designed bracing, SDC D, E or F"),
         "D.40.11.031a": ("D.40.11.033a", "sprinkler drops, SDC D, E or F"),
         "D.50.12.021a": ("D.50.12.023b", "low-voltage switchgear, hard anchored"),
         "D.50.12.013a": ("D.50.12.013c", "motor control centre, hard anchored"),
         "D.30.31.011a": ("D.30.31.013b", "chiller < 100 t, hard anchored"),
         "D.30.31.021a": ("D.30.31.023b", "cooling tower < 100 t, hard anchored"),
         "D.30.52.011a": ("D.30.52.013b", "air handling unit < 5000 CFM, hard anchored"),
         "C.30.34.001": ("C.30.34.002", "pendant lighting, seismically rated"),
         "C.30.27.001": ("C.30.27.002", "raised access floor, seismically rated")}
#: on the roof: the roof tiles and the rooftop plant of a low-rise office (packaged units)
ON_THE_ROOF = ("B.30.11.011", "D.30.31.013b", "D.30.31.023b", "D.30.52.013b")
#: the gravity framing per storey and direction (3 x 3 columns, two 7 m bays each way, the moment
#: frames on the perimeter): the interior girder line's two beams (4 ends) and one infill beam per
#: bay at mid-span (2 bays x 2 ends): 8 shear tabs
GRAVITY = ("B.10.31.001", "ea", "1--3", "1,2", 8, 8, "bolted shear tabs of the gravity framing (interior girder "
           "line 4 + infill beams 4, per direction)")


#: the SAC LA9 building (FEMA-355C, Appendix B: 5 x 5 bays of 30 ft, two perimeter moment frames of
#: 5 bays per direction, the last bay's beam pinned at the corner column, as tools/la9_frame.py models
#: it): per storey and direction 2 frames x (1 exterior joint with a beam on one side + 4 interior
#: joints with beams on both), welded connections other than RBS, ductile (post-Northridge: the frame
#: model's Lignos-Krawinkler hinges are those of such connections), beams of W30 or deeper at the
#: ceilings of storeys 1-7 (W36, W30) and W27 or shallower at those of storeys 8-9; its gravity framing:
#: 4 interior girder lines of 5 bays per direction, 2 shear tabs per girder, and the corner bays' pins
LA9 = {"storeys": 9, "floor_sqft": 150.0 * 150.0}
LA9_STRUCTURE = (("B.10.35.022", "ea", "1--7", "1,2", 2, 2, "welded moment connection other than RBS, beam one side, "
                  "beam >= W30 (2 frames x 1 exterior joint)"),
                 ("B.10.35.032", "ea", "1--7", "1,2", 8, 8, "welded moment connection other than RBS, beams both "
                  "sides, beam >= W30 (2 frames x 4 interior joints)"),
                 ("B.10.35.021", "ea", "8--9", "1,2", 2, 2, "welded moment connection other than RBS, beam one side, "
                  "beam <= W27 (2 frames x 1 exterior joint)"),
                 ("B.10.35.031", "ea", "8--9", "1,2", 8, 8, "welded moment connection other than RBS, beams both "
                  "sides, beam <= W27 (2 frames x 4 interior joints)"),
                 ("C.20.11.001b", "ea", "1--9", "1,2", 2, 2, "prefabricated steel stair, two per storey"),
                 ("B.10.31.001", "ea", "1--9", "1,2", 42, 42, "bolted shear tabs of the gravity framing (4 interior "
                  "girder lines x 5 bays x 2 ends, and the 2 corner bays' pinned ends, per direction)"))


def la9(source, target):
    """The SDC D office of `source` (3 storeys of FLOOR_AREA_SQFT) on the LA9 building (module doc)."""
    with open(source, newline="") as handle:
        rows = list(csv.DictReader(line for line in handle if not line.startswith("#")))
    n, scale = LA9["storeys"], LA9["floor_sqft"] / FLOOR_AREA_SQFT
    where = {"1": "1", "2": f"2--{n - 1}", "3": str(n), "roof": "roof"}
    with open(target, "w", newline="") as handle:
        handle.write(__doc__.replace("\n", "\n# ").join(["# ", "\n"]))
        out = csv.writer(handle)
        out.writerow(["ID", "Units", "Location", "Direction", "Theta_0", "Blocks", "Comment"])
        for r in rows:
            if r["Location"] not in where:  # the 3-storey structure: replaced below
                continue
            blocks = max(1, round(float(r["Blocks"]) * scale))
            out.writerow([r["ID"], r["Units"], where[r["Location"]], r["Direction"],
                          f"{float(r['Theta_0']) * scale:.4g}", blocks, r["Comment"]])
        for row in LA9_STRUCTURE:
            out.writerow(row)


def sdc_d(source, target):
    """The office of `source` as built in SDC D (module doc)."""
    with open(source, newline="") as handle:
        lines = [line for line in handle if not line.startswith("#")]
    rows = list(csv.DictReader(lines))
    with open(target, "w", newline="") as handle:
        handle.write(__doc__.replace("\n", "\n# ").join(["# ", "\n"]))
        out = csv.writer(handle)
        out.writerow(["ID", "Units", "Location", "Direction", "Theta_0", "Blocks", "Comment"])
        for r in rows:
            cid, why = SDC_D.get(r["ID"], (r["ID"], r["Comment"]))
            location = "roof" if cid in ON_THE_ROOF else r["Location"]
            comment = f"{why} (for {r['ID']})" if r["ID"] in SDC_D else why
            if location == "roof":
                comment += "; on the roof"
            out.writerow([cid, r["Units"], location, r["Direction"], r["Theta_0"], r["Blocks"], comment])
        out.writerow(GRAVITY)


def main(source, target):
    scale = FLOOR_AREA_SQFT / TOOL_AREA_SQFT
    with open(source, newline="", encoding="utf-8-sig") as handle:
        rows = [r for r in csv.DictReader(handle) if not r["ID"].startswith(LEFT_OUT)
                and not (r["ID"].startswith(ROOF) and r["Location"].strip() != "3")]
    with open(target, "w", newline="") as handle:
        handle.write(__doc__.replace("\n", "\n# ").join(["# ", "\n"]))
        out = csv.writer(handle)
        out.writerow(["ID", "Units", "Location", "Direction", "Theta_0", "Blocks", "Comment"])
        for r in rows:
            blocks = max(1, round(float(r["Blocks"]) * scale)) if r.get("Blocks") else 1
            out.writerow([r["ID"], r["Units"], r["Location"], r["Direction"].replace(" ", ""),
                          f"{float(r['Theta_0']) * scale:.4g}", blocks, "normative quantity, office"])
        for row in STRUCTURE:
            out.writerow(row)


if __name__ == "__main__":
    if sys.argv[1] == "--sdc-d":
        sdc_d(*sys.argv[2:4])
    elif sys.argv[1] == "--la9":
        la9(*sys.argv[2:4])
    else:
        main(*sys.argv[1:3])
