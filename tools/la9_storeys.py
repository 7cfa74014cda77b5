"""The SAC Los Angeles 9-storey frame as a shear building of deteriorating storeys, calibrated to the
frame's two pushovers (pidamper.assessment.shear_calibration), checked against them, and written
out: the study's [building] fields and the page docs/buildings/la9.md with its figures.

    python tools/la9_frame.py --out studies/la9/frame-pushover.json      # the frame (openseespy)
    python tools/la9_storeys.py studies/la9/frame-pushover.json studies/la9/shear-building.toml docs/buildings

Each storey's residual strength (0.4), ultimate drift ratio (0.2) and cyclic deterioration come from
the frame's beam hinges (Lignos and Krawinkler 2011, as tools/la9_frame.py gives them): the storey's
Lamda [m] is the mean of the hinge Lamda [rad] of the beams at its floor and ceiling times its height.
"""
import json
import math
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
import la9_frame  # noqa: E402  (its tables and hinge laws; nothing is run)

from pidamper.assessment import deteriorating_pushover, shear_calibration  # noqa: E402
from pidamper_physics import Params  # noqa: E402

G = 9.81  # m/s2, as the frame model's gravity
RESIDUAL, ULTIMATE = 0.4, 0.2  # the beam hinges' Mr / My and theta_u [rad]


def storey_lamda():
    """Per storey the mean LK 2011 Lamda [rad] of the beams at its floor and its ceiling."""
    lam = [la9_frame.beam_hinge(la9_frame.section(name), la9_frame.BAY)["lam"] for name in la9_frame.BEAMS]
    return [0.5 * (lam[k] + lam[k + 1]) for k in range(len(lam) - 1)]  # beams of levels 1 (ground) .. 10


def calibrated(frame):
    """(Storeys, the study's [building] per-storey fields) of the frame's pushovers."""
    masses, heights = np.array(frame["masses"]), np.array(frame["storey_heights"])
    above = G * np.cumsum(masses[::-1])[::-1]
    pushovers = [(frame[key]["storey_shear"], frame[key]["storey_drift"]) for key in ("steps", "steps_roof_load")]
    storeys = shear_calibration.calibrate(pushovers, above, heights)
    return storeys, shear_calibration.imk_fields(storeys, heights, RESIDUAL, ULTIMATE, storey_lamda())


def params(frame, fields):
    """pidamper_physics.Params of the shear building (P-Delta on, no damper)."""
    n = len(frame["masses"])
    imk = [{name[len("storey_"):]: fields[name][k] for name in fields if name not in ("storey_k", "storey_Fy")}
           for k in range(n)]
    return Params(storeys=n, floor_m=frame["masses"], storey_k=fields["storey_k"], storey_h=frame["storey_heights"],
                  storey_Fy=fields["storey_Fy"], storey_law=1, storey_imk=imk, p_delta=1, g=G, mu=0.0, d=100.0)


def toml_block(frame, fields):
    lines = ["storeys = 9", "storey_law = 1", "p_delta = 1",
             f"floor_m = [{', '.join(f'{m:.6g}' for m in frame['masses'])}]",
             f"storey_height = [{', '.join(f'{h:g}' for h in frame['storey_heights'])}]"]
    lines += [f"{name} = [{', '.join(f'{v:.6g}' for v in values)}]" for name, values in fields.items()]
    return "\n".join(lines) + "\n"


def plot(frame, storeys, fields, push, folder):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    weight = G * sum(frame["masses"])
    height = sum(frame["storey_heights"])
    fig, ax = plt.subplots(figsize=(6.4, 4.0))
    for key, label in (("steps", "frame, first-mode loads"), ("steps_roof_load", "frame, roof load")):
        ax.plot(100 * np.array(frame[key]["roof_drift"]), np.array(frame[key]["base_shear"]) / weight, label=label)
    ax.plot(100 * push.roof / height, push.base_shear / weight, "k--", label="shear building, first-mode loads")
    ax.set(xlabel="roof drift ratio [%]", ylabel="base shear / W", title="SAC LA9 frame and its shear building")
    ax.legend()
    fig.tight_layout()
    fig.savefig(folder / "la9-pushover.png", dpi=110)
    plt.close(fig)
    masses, heights = np.array(frame["masses"]), np.array(frame["storey_heights"])
    above = G * np.cumsum(masses[::-1])[::-1]
    fig, axes = plt.subplots(3, 3, figsize=(9.6, 8.0), sharex=True)
    for k, ax in enumerate(axes.flat):
        for key, style in (("steps", "C0"), ("steps_roof_load", "C1")):
            r = shear_calibration.resistances(frame[key]["storey_shear"], frame[key]["storey_drift"], above,
                                              heights)[:, k]
            u = np.array(frame[key]["storey_drift"])[:, k]
            _, u0 = shear_calibration.elastic_line(u, r)
            ax.plot(100 * (u - u0) / heights[k], r / 1e6, style, lw=1)
        s, res = storeys[k], fields["storey_FresFy_pos"][k]
        uy, um = s.fy / s.ke, s.fy / s.ke + s.dp
        ur = um + s.dpc * (1 - res / s.fmax_fy)
        u = np.array([0, uy, um, ur, ULTIMATE * heights[k]])
        f = np.array([0, s.fy, s.fmax_fy * s.fy, res * s.fy, res * s.fy])
        ax.plot(100 * u / heights[k], f / 1e6, "k--", lw=1)
        ax.set_title(f"storey {k + 1} ({s.basis})", fontsize=9)
        ax.set_xlim(0, 10)
    for ax in axes[-1]:
        ax.set_xlabel("storey drift ratio [%]")
    for ax in axes[:, 0]:
        ax.set_ylabel("resistance [MN]")
    fig.suptitle("storey resistance without P-Delta: frame (first-mode blue, roof load orange), backbone (dashed)")
    fig.tight_layout()
    fig.savefig(folder / "la9-storeys.png", dpi=110)
    plt.close(fig)


def softening(frame):
    """The storeys (1..N) that soften in the frame's first-mode pushover."""
    masses, heights = np.array(frame["masses"]), np.array(frame["storey_heights"])
    r = shear_calibration.resistances(frame["steps"]["storey_shear"], frame["steps"]["storey_drift"],
                                      G * np.cumsum(masses[::-1])[::-1], heights)
    u = np.array(frame["steps"]["storey_drift"])
    return [k + 1 for k in range(u.shape[1]) if shear_calibration.storey(u[:, k], r[:, k]).basis == "softened"]


def page(frame, storeys, fields, p, push, command):
    periods = [2 * math.pi / w for w in p.building.omegas[:3]]
    weight = G * sum(frame["masses"])
    height = sum(frame["storey_heights"])
    lines = ["# The SAC Los Angeles 9-storey building as a shear building", "",
             f"Written by `{command}`; the frame by `python tools/la9_frame.py --out studies/la9/frame-pushover.json` "
             f"(its docstring gives the model: members, hinges, gravity and their sources; {frame['opensees']}).", "",
             "The frame: one north-south perimeter moment frame of the SAC LA9 building (FEMA-355C, Appendix B; the "
             "benchmark building of Ohtori, Christenson, Spencer and Dyke 2004) in OpenSees, elastic members with "
             "deteriorating end hinges (Lignos and Krawinkler 2011 for the beams, Lignos et al. 2019 for the columns), "
             "a leaning column carrying the gravity load off the frame, P-Delta. It is pushed twice: with lateral "
             "loads in proportion to the first mode, and with a load at the roof alone (the same shear in every "
             "storey, so that the upper storeys, which the first mode's loads never take to their capacity, yield).",
             "", "The shear building: one degree of freedom per floor, the frame's floor masses, each storey an "
             "IMKBilin storey (`storey_law = 1`, P-Delta from the weight above) calibrated by "
             "`pidamper.assessment.shear_calibration` (its docstring gives the rules).", "",
             "## Periods", "", "| | T1 [s] | T2 [s] | T3 [s] |", "|---|---:|---:|---:|",
             "| Ohtori et al. 2004 (published) | " + " | ".join(f"{t:.3f}" for t in frame["ohtori_periods"]) + " |",
             "| the frame, no gravity | " + " | ".join(f"{t:.3f}" for t in frame["periods"]) + " |",
             "| the frame, after gravity, P-Delta | " + " | ".join(f"{t:.3f}" for t in frame["periods_after_gravity"])
             + " |",
             "| the shear building, P-Delta | " + " | ".join(f"{t:.3f}" for t in periods) + " |", "",
             "The shear building has the frame's first period; its higher ones are shorter (a shear building "
             "has no flexural mode shapes).", "",
             "## Pushover", "", "![pushover](la9-pushover.png)", "",
             f"Peak base shear: frame {max(frame['steps']['base_shear']) / weight:.3f} W, shear building "
             f"{push.v_max / weight:.3f} W (W = {weight / 1e6:.2f} MN, one frame's share of the building). "
             f"The shear building's curve ends where it has lost 20 % of its peak, at roof drift "
             f"{100 * push.delta_u / height:.2f} % ({push.limit}); storey {push.critical} softens. Under the same "
             f"loads the frame's storeys {', '.join(map(str, softening(frame)))} soften together: a shear building "
             "has no columns running through its floors to spread a mechanism over several storeys, so its curve "
             "falls sooner past the peak (a conservative idealisation for collapse).", "",
             "![storeys](la9-storeys.png)", "",
             "## The storeys", "", "| storey | h [m] | Ke [MN/m] | Fy [MN] | Fmax/Fy | dp/h | dpc/h | Fres/Fy | "
             "Lamda [m] | from |", "|---:|---:|---:|---:|---:|---:|---:|---:|---:|---|"]
    for k, s in enumerate(storeys):
        h = frame["storey_heights"][k]
        lines.append(f"| {k + 1} | {h:g} | {s.ke / 1e6:.4g} | {s.fy / 1e6:.4g} | {s.fmax_fy:.3g} | {s.dp / h:.4f} | "
                     f"{s.dpc / h:.3f} | {fields['storey_FresFy_pos'][k]:.3g} | {fields['storey_LamdaS'][k]:.3g} | "
                     f"{s.basis} |")
    lines += ["", "`from`: softened, the storey went past its peak in one of the pushovers (its own capping, "
              "post-capping and, where it reached one, residual plateau); yielded, it yielded and unloaded (the "
              "capping and post-capping drift ratios of the softened storeys, their median). The residual strength "
              "where the pushovers did not reach it (0.4 Fy) and the ultimate drift ratio (0.2): the beam hinges'.",
              ""]
    return "\n".join(lines)


def main(source, target, folder):
    frame = json.loads(Path(source).read_text())
    storeys, fields = calibrated(frame)
    p = params(frame, fields)
    push = deteriorating_pushover.pushover(list(frame["masses"]), p.imk, frame["storey_heights"], True, G)
    Path(target).write_text(f"# the [building] fields of the SAC LA9 shear building: "
                            f"python tools/la9_storeys.py {' '.join(sys.argv[1:])}\n" + toml_block(frame, fields))
    folder = Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    plot(frame, storeys, fields, push, folder)
    command = "python tools/la9_storeys.py " + " ".join(sys.argv[1:])
    (folder / "la9.md").write_text(page(frame, storeys, fields, p, push, command))
    print(toml_block(frame, fields))
    print(f"T1 {2 * math.pi / p.building.w_1:.4f} s; V_max/W {push.v_max / (G * sum(frame['masses'])):.4f}")


if __name__ == "__main__":
    main(*sys.argv[1:4])
