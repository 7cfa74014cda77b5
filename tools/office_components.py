"""Write the shipped study's performance model (studies/office-3-components.csv) from the FEMA
P-58 Normative Quantity Estimation Tool's office quantities.

    pip install normqtypact==0.2.0 openpyxl   # reads FEMA's tool (FEMA P-58-3, 2018), not in the extras
    python tools/office_components.py NQ.csv studies/office-3-components.csv

NQ.csv: the tool's pelicun component list for 3 storeys of 10,000 sq ft of OFFICE occupancy
(normqtypact's PurePythonNormQtyPact(...).Output_PelicunComponentDirectory; its __init__ needs
win32com: load normqtypact/python_core.py directly).  The quantities and blocks are scaled to the
study's floor area; contents (E.20.22: no repair consequence) and components whose library fragility
is incomplete (C.20.11.001a) are left out, roofing kept on the top storey only, the steel stair C.20.11.001b stands in for the latter;
the moment-frame connections come from the stated frame layout (STRUCTURE)."""
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
    main(*sys.argv[1:3])
