"""Drive the physics core of one source tree over the equivalence cases and print every value.

Run as `PYTHONPATH=TREE/fmu_src python tools/core_cases.py [--perturb-mu]` (tools/equivalence.py does it for the
merge-base tree and the new one): it imports `pidamper_physics` from that tree only, steps each case
with the public API (Damper, DamperUnit, ShearMotion, yielding.building_motion) and prints one JSON object
{case: [[value, ...] per step]} with every float as its repr, so that two trees can be compared bit
for bit.  It relies on nothing but the constructors, advance(), observables(), get_state() and
set_state() that both trees share.
"""
import json
import math
import sys

from pidamper_physics.damper import Damper
from pidamper_physics.params import Params
from pidamper_physics.unit import DamperUnit
from pidamper_physics.shear_motion import ShearMotion

H = 0.01  # communication step [s]


def pendulum_cases():
    """(name, params, start angles, steps, force(t) [N], ground(t) [m/s2])."""
    w2 = math.sqrt(9.81)
    res = 0.0981
    cases = []
    for level, label in ((0, "linear"), (1, "damped"), (2, "coupled"), (3, "nonlinear")):
        z = {"zeta_s": 0.01, "zeta_p": 0.02} if level else {}
        if level >= 2:  # the particle swings with its pivot: a tighter gap gives impacts
            z["d"] = 0.02
        cases.append((f"free-{label}", dict(fidelity=level, **z), (0.0, 0.7 * w2, 0.0, 0.0), 800, None, None))
        cases.append((f"resonance-{label}", dict(fidelity=level, mu=0.02, **z), (0.0, 0.0, 0.0, 0.0), 1500,
                      lambda t: res * math.sin(w2 * t), None))
    cases.append(("builtin-harmonic", dict(mu=0.02, F0=0.0981, Omega=w2), (0.0, 0.0, 0.0, 0.0), 1500, None, None))
    cases.append(("chatter-stick", dict(mu=0.5, e=0.6, FR=1.5, d=0.02), (0.0, 0.0, 0.0, 0.0), 1500,
                  lambda t: 2.0 * math.sin(0.7 * w2 * t), None))
    cases.append(("angle-form", dict(contact_form=1, d_angle=0.1, FR=2.0), (0.0, 0.7 * w2, 0.0, 0.0), 800,
                  None, None))
    cases.append(("base-excitation", dict(fidelity=1, zeta_s=0.02, mu=0.05), (0.0, 0.0, 0.0, 0.0), 1500, None,
                  lambda t: 1.5 * math.sin(2.7 * t) * math.exp(-0.1 * t)))
    for n in (1, 3, 10):
        for level in (0, 1):
            z = {"zeta_s": 0.05, "zeta_p": 0.01} if level else {}
            cases.append((f"building-{n}-level{level}", dict(storeys=n, fidelity=level, mu=0.03, FR=1.0, d=0.01 if n > 1 else 0.002,
                                                               **z),
                          (0.0, 0.0, 0.0, 0.0), 600, None, lambda t: 3.0 * math.sin(6.0 * t) * math.exp(-0.2 * t)))
    yielding = dict(storeys=3, floor_m=[1e5] * 3, storey_k=[8e7] * 3, fidelity=1, p_delta=1,
                    storey_Fy=[8e5, 7e5, 5e5], storey_b=[0.02] * 3, mu=0.05, FR=0.95, d=0.02, e=0.5)
    for zeta in (0.02, 0.1):  # storeys that yield and unload, with P-Delta, the damper impacting
        cases.append((f"yielding-3-zeta{zeta}", dict(yielding, zeta_s=zeta), (0.0, 0.0, 0.0, 0.0), 600, None,
                      lambda t: 4.0 * math.sin(6.0 * t) * math.exp(-0.2 * t)))
    return cases


def run_damper(params, start, steps, force, ground):
    d = Damper(Params(**params), *start)
    rows = []
    saved = None
    for k in range(1, steps + 1):
        t = k * H
        f = force((k - 1) * H) if force else 0.0
        a = ground((k - 1) * H) if ground else 0.0
        d.advance(t, f, a)
        row = list(d.observables(f, a)) + [d.t, d.impacts, d.dissipated, d.work_in, d.energy, d.mode, d.side]
        if params.get("storeys"):
            xs, acc, drifts, shear = d.building_outputs(f, a)
            row += list(xs) + list(acc) + list(drifts) + [shear]
        rows.append(row)
        if k == steps // 3:
            saved = json.loads(json.dumps(d.get_state()))
    # restore mid-run and step again: the rerun must equal the first run
    d.set_state(saved)
    for k in range(steps // 3 + 1, steps + 1):
        f = force((k - 1) * H) if force else 0.0
        a = ground((k - 1) * H) if ground else 0.0
        d.advance(k * H, f, a)
    rows.append(list(d.observables(0.0, 0.0)) + [d.t, d.impacts, d.dissipated])
    return rows


def unit_cases():
    return [(f"unit-aware{mode}-e{e}", dict(impulse_aware=mode, e=e, zeta_p=z), 2000)
            for mode in (0, 1) for e, z in ((0.5, 0.0), (0.8, 0.03))]


def bare_cases():
    """(name, yield forces [N], ground(t) [m/s2], impulses at step k: [(t offset, floor, J)], steps):
    the bare yielding 3-storey building with P-Delta (yielding.building_motion): yielding and
    unloading under a pulse, floor impulses, and a collapse."""
    pulse = lambda amplitude: (lambda t: amplitude if 0.5 <= t < 0.8 else 0.0)
    return [("bare-yielding-pulse", [6e5, 5e5, 3e5], pulse(2.0), {}, 600),
            ("bare-yielding-kicks", [6e5, 5e5, 3e5], lambda t: 3.0 * math.sin(6.0 * t) * math.exp(-0.2 * t),
             {40: [(0.004, 2, 3e4)], 41: [(0.0, 0, -2e4), (0.01, 1, 1e4)], 200: [(0.005, 2, -5e4)]}, 600),
            ("bare-yielding-collapse", [3e5, 2.5e5, 1.5e5], pulse(6.0), {}, 300)]


def run_bare(yield_forces, ground, kicks, steps):
    from pidamper_physics.yielding import building_motion
    m = building_motion([1e5] * 3, [8e7] * 3, [3.0] * 3, 0.02, yield_forces, [0.02] * 3, 1)
    rows, saved = [], None
    zero = [0.0] * 3
    for k in range(1, steps + 1):
        a = ground((k - 1) * H)
        m.advance(k * H, zero, a, [((k - 1) * H + dt, f, j) for dt, f, j in kicks.get(k, ())])
        x, v = m.floors()
        pk = m.peaks
        rows.append(x + v + m.absolute_accelerations(zero) + m.storey_forces() + m.plastic_drifts()
                    + list(pk.drift) + list(pk.velocity) + list(pk.acceleration)
                    + [m.t, m.energy(), m.base_shear(), m.hysteretic, m.viscous, m.work_in, m.collapsed,
                       m.storeys.events, m.pieces])
        if k == steps // 3:
            saved = json.loads(json.dumps(m.get_state()))
    m.set_state(saved)
    for k in range(steps // 3 + 1, steps + 1):
        m.advance(k * H, zero, ground((k - 1) * H), [((k - 1) * H + dt, f, j) for dt, f, j in kicks.get(k, ())])
    x, v = m.floors()
    rows.append(x + v + [m.t, m.energy(), m.hysteretic, m.viscous, m.work_in])
    return rows


def run_unit_with_building(params, steps):
    """The unit on floor 3 of a bare 3-storey building, Gauss-Seidel with the unit's mean force
    (and, impulse-aware, its impulses) passed to the building: the physics of the two FMUs."""
    from pidamper_physics.building import ShearBuilding
    b = ShearBuilding([1e5] * 3, [8e7] * 3, 0.02)
    s = ShearMotion(b)
    u = DamperUnit(M_s=1e5, **params)
    rows = []
    a_s = 0.0
    for k in range(1, steps + 1):
        t = k * H
        ag = 3.0 * math.sin(6.0 * (k - 1) * H)
        u.advance(t, a_s)
        kicks = [(u.t_J, 2, u.J_s)] if params["impulse_aware"] else []
        s.advance(t, [0.0, 0.0, u.F_s], ag, kicks)
        a_s = s.absolute_accelerations([0.0, 0.0, u.F_s])[2] + 3.0 * math.sin(6.0 * k * H)
        xs, vs = s.floors()
        rows.append([u.r, u.rd, u.F_s, u.J_s, u.t_J, u.impacts, u.dissipated, u.mode, u.side] + list(xs) + list(vs))
        if k == steps // 2:
            saved = json.loads(json.dumps(u.get_state()))
    u.set_state(saved)
    rows.append([u.r, u.rd, u.impacts])
    return rows


def main():
    """Every case's values as JSON; with --perturb-mu, mu is one ulp larger in the pendulum cases
    (the conditioning of each case: how far one ulp of one input moves its outputs)."""
    out = {}
    for name, params, start, steps, force, ground in pendulum_cases():
        if "--perturb-mu" in sys.argv:
            params = dict(params, mu=Params(**params).mu * (1.0 + 2.0 ** -52))
        try:
            out[name] = run_damper(params, start, steps, force, ground)
        except Exception as err:  # a refusal is an outcome to compare too
            out[name] = f"{type(err).__name__}: {err}"
    for name, params, steps in unit_cases():
        try:
            out[name] = run_unit_with_building(params, steps)
        except Exception as err:
            out[name] = f"{type(err).__name__}: {err}"
    for name, yield_forces, ground, kicks, steps in bare_cases():
        try:
            out[name] = run_bare(yield_forces, ground, kicks, steps)
        except Exception as err:
            out[name] = f"{type(err).__name__}: {err}"
    json.dump({k: v if isinstance(v, str) else [[repr(x) for x in row] for row in v] for k, v in out.items()},
              sys.stdout)


if __name__ == "__main__":
    main()
