"""The damper unit on a shear building, co-simulated: PendulumImpactDamperUnit.fmu + ShearBuilding.fmu.

The coupled system (names as in the FMUs): the unit hangs from floor j of the building;

    building.floor[j].a  ->  unit.a_s         (absolute acceleration of the attachment)
    unit.F_s             ->  building.F[j]    (mean force of the unit on the floor over the step)
    unit.J_s, unit.t_J   ->  building.J[j], building.t_J[j]      (impulse-aware coupling only)

Masters (each returns a `Run`: floor displacements on the communication grid, impacts, wall time):

- `gauss_seidel(scenario, h, mode)`: fmpy's FMU2Slave driven directly.  At each step it reads
  floor[j].a (absolute, with the F[j] the building received for the previous step: direct
  feedthrough), steps the unit with it held, passes F_s to F[j] (and, impulse-aware, J_s, t_J to
  J[j], t_J[j]), then steps the building over the same interval.  Modes (MODES):
  "mean": the unit runs with impulse_aware = 0; F_s carries the impacts' impulses spread over the
  step, and the attachment's share of each impulse reaches the unit through the next floor[j].a.
  "impulse": the unit runs with impulse_aware = 1; F_s is the smooth force only, the building
  applies J_s at t_J (the step's momentum and its first moment kept), and the unit applies the
  attachment's share J/M_s in its own frame at the impact (floor[j].a, an instantaneous
  acceleration, never carries an impulse).
  "impulse-extrapolated": as "impulse", but the unit's a_s is the linear extrapolation of the
  attachment's smooth mean acceleration over the last two steps (from floor[j].v and J_s / M_s)
  instead of the held floor[j].a: the master's input extrapolation that the second order needs.
  Both held-floor[j].a modes are first order: the unit sees the attachment's acceleration held
  from the step's start, computed with the previous step's mean force (a lag of about h); the
  impulse-aware inputs remove the impacts' share of the error, not that lag.
- `physics_gauss_seidel(scenario, h, mode)`: the same master on the physics classes directly (no
  FMI), for tests: it reproduces `gauss_seidel` bit for bit.
- `libcosim_jacobi(scenario, h, impulse_aware)`: the same system in libcosim (libcosimpy), loaded
  from the OSP system structure this module writes; its fixed-step algorithm steps both FMUs in
  parallel on the outputs of the previous step (Jacobi): the unit's a_s is a step older than in
  Gauss-Seidel and F_s reaches the building a step late (impulse-aware: J_s with a t_J in the
  past, which the building applies at the step's start).

`reference(scenario, times)` is the exact monolithic solution the measurements compare with: the
physics core's building level (Damper with storeys, issue 14 part 1) when it is there, else an
independent event-driven integration (`ivp_reference`: scipy DOP853 at rtol 1e-12 with its own
impact law).  `export_system(out_dir, scenario)` writes the SSP files and the OSP system
structures beside the FMUs.
"""
import math
import shutil
import tempfile
import time
import zipfile
from dataclasses import dataclass, field, replace
from pathlib import Path
from xml.sax.saxutils import quoteattr

import numpy as np

UNIT = "PendulumImpactDamperUnit"
BUILDING = "ShearBuilding"
SYSTEM = "DamperOnBuilding"


# ---- the coupled system's parameters ----------------------------------------------------------

@dataclass(frozen=True)
class Scenario:
    """A building with the damper unit on floor `damper_floor` (1..storeys; 0 = the top floor, as in
    the monolithic model's Params), excited by a ground
    acceleration pulse `pulse` [m/s2] over [0, pulse_time) [s], from rest.

    The particle is given as in the monolithic model: m = mu * (building mass), w1 = FR * w_1 (the
    building's first natural frequency), L1 = g / w1^2; M_s = the damper floor's mass.  Defaults:
    the convergence benchmark's case (3 storeys of 1e5 kg and 8e7 N/m: T1 = 0.499 s; 2 % modal
    damping; a 6 t particle at the top, w1 = w_1 / 2, d = 2 cm, e = 0.5; 2 m/s2 for half a
    period): 20 impacts in 5 s, every one well separated (no chatter, no sticking)."""

    storeys: int = 3
    floor_m: tuple = (1e5,) * 10  # per floor / storey, 1 first; entries beyond `storeys` are ignored
    storey_k: tuple = (8e7,) * 10
    zeta_s: float = 0.02
    damper_floor: int = 0
    mu: float = 0.02
    FR: float = 0.5
    g: float = 9.81
    d: float = 0.02
    e: float = 0.5
    zeta_p: float = 0.0
    pulse: float = 2.0
    pulse_time: float = 0.25
    stop_time: float = 5.0

    @property
    def building(self):
        from pidamper_physics.shear_motion import make_building

        return make_building(list(self.floor_m[:self.storeys]), list(self.storey_k[:self.storeys]), self.zeta_s)

    @property
    def floor(self):
        """Number (1-based) of the damper floor."""
        if not 0 <= self.damper_floor <= self.storeys:
            raise ValueError(f"damper_floor = {self.damper_floor!r} is not allowed: 0 (the top) or 1..storeys")
        return self.damper_floor or self.storeys

    @property
    def j(self):
        """Index (0-based) of the damper floor."""
        return self.floor - 1

    @property
    def m(self):
        return self.mu * sum(self.floor_m[:self.storeys])

    @property
    def M_s(self):
        return self.floor_m[self.j]

    @property
    def w1(self):
        return self.FR * self.building.w_1

    @property
    def L1(self):
        return self.g / self.w1 ** 2

    def building_values(self):
        values = {"storeys": self.storeys, "zeta_s": self.zeta_s}
        for k in range(self.storeys):
            values[f"floor[{k + 1}].m"] = self.floor_m[k]
            values[f"storey[{k + 1}].k"] = self.storey_k[k]
        return values

    def unit_values(self, impulse_aware=False):
        return {"m": self.m, "M_s": self.M_s, "L1": self.L1, "g": self.g, "d": self.d, "e": self.e,
                "zeta_p": self.zeta_p, "impulse_aware": int(bool(impulse_aware))}

    def ground(self, t, h):
        """a_g held over the step [t, t + h]: the pulse's mean over it (exact where the pulse's end
        is a communication point, and its impulse always kept)."""
        if h <= 0.0:
            return self.pulse if t < self.pulse_time else 0.0
        return self.pulse * max(0.0, min(t + h, self.pulse_time) - t) / h

    def steps(self, h):
        n = int(round(self.stop_time / h))
        if abs(n * h - self.stop_time) > 1e-9 * self.stop_time:
            raise ValueError(f"step {h!r} is not allowed: it must divide stop_time = {self.stop_time!r}")
        return n


@dataclass
class Run:
    """A co-simulation's result on its communication grid."""

    master: str
    h: float
    time: np.ndarray
    x: np.ndarray          # floor displacements [m], one row per communication point, one column per floor
    r: np.ndarray          # the unit's r [m]
    impacts: int
    wall: float            # s, wall time of the stepping loop (instantiation excluded)
    notes: list = field(default_factory=list)

    def at(self, times):
        """Rows of x at `times` (points of the grid)."""
        index = np.rint(np.asarray(times) / self.h).astype(int)
        if np.max(np.abs(index * self.h - np.asarray(times))) > 1e-9 * max(1.0, float(np.max(times))):
            raise ValueError(f"times are not points of the grid of step {self.h}")
        return self.x[index]


# ---- the FMUs ---------------------------------------------------------------------------------

def component_fmus(folder=None):
    """{name: path} of ShearBuilding.fmu and PendulumImpactDamperUnit.fmu: `folder` if given, else
    dist/ of the source checkout, rebuilt (all FMUs, in a fresh process) when missing or stale."""
    import fmpy

    from build_fmu import expected_guid

    from .fmu import build_fmu, default_fmu_path

    if folder is not None:
        paths = {name: Path(folder) / f"{name}.fmu" for name in (BUILDING, UNIT)}
        missing = [str(p) for p in paths.values() if not p.is_file()]
        if missing:
            raise FileNotFoundError(f"{', '.join(missing)}: no such file (build them with: python -m build_fmu)")
        return paths
    dist = default_fmu_path().parent
    paths = {name: dist / f"{name}.fmu" for name in (BUILDING, UNIT)}

    def current(name):
        try:
            return fmpy.read_model_description(str(paths[name])).guid == expected_guid(model=name)
        except Exception:
            return False

    if not all(current(name) for name in paths):
        build_fmu(dist)
    return paths


def _slave(path, name, values, messages):
    """One initialised FMU instance whose messages go to the list `messages`."""
    from .instance import FmuInstance

    return FmuInstance(path, values, instance_name=name, logger=lambda status, text: messages.append(text))


#: the Gauss-Seidel masters: name -> (impulse-aware coupling, extrapolated a_s)
MODES = {"mean": (False, False), "impulse": (True, False), "impulse-extrapolated": (True, True)}
LABELS = {"mean": "Gauss-Seidel mean force", "impulse": "Gauss-Seidel impulse-aware",
          "impulse-extrapolated": "Gauss-Seidel impulse-aware, extrapolated a_s",
          "libcosim": "libcosim Jacobi mean force", "libcosim-impulse": "libcosim Jacobi impulse-aware"}


class _MeanAcceleration:
    """a_s for the coming step as the linear extrapolation of the attachment's smooth mean
    absolute acceleration over the last two steps, (v_j(t_n) - v_j(t_n-1) - J/M_s) / h + a_g (the
    impulse's jump taken out: the impulse-aware unit applies it itself); the held floor[j].a until
    two steps are known.  Second order where the acceleration is smooth (see the module doc)."""

    def __init__(self, M_s):
        self.M_s = M_s
        self.means = []

    def value(self, a_now):
        means = self.means
        if not means:
            return a_now
        return means[-1] if len(means) < 2 else 2.0 * means[-1] - means[-2]

    def step_done(self, v_before, v_after, impulse, ground, h):
        self.means = self.means[-1:] + [(v_after - v_before - impulse / self.M_s) / h + ground]


def gauss_seidel(scn, h, mode="mean", fmus=None):
    """The Gauss-Seidel master on the two FMUs with fmpy's FMU2Slave (see the module doc);
    mode: one of MODES."""
    impulse_aware, extrapolate = MODES[mode]
    fmus = fmus or component_fmus()
    messages = []
    n = scn.steps(h)
    j = scn.floor
    building = _slave(fmus[BUILDING], "building", scn.building_values(), messages)
    unit = _slave(fmus[UNIT], "unit", scn.unit_values(impulse_aware), messages)
    try:
        b, u = building.fmu, unit.fmu
        vr_a = building.vr(f"floor[{j}].a")
        vr_in = building.vr(f"F[{j}]", "a_g") + (building.vr(f"J[{j}]", f"t_J[{j}]") if impulse_aware else [])
        vr_x = building.vr(*(f"floor[{k + 1}].x" for k in range(scn.storeys)), f"floor[{j}].v")
        vr_as = unit.vr("a_s")
        vr_out = unit.vr("F_s", "J_s", "t_J", "r")
        x = np.zeros((n + 1, scn.storeys))
        r = np.zeros(n + 1)
        means = _MeanAcceleration(scn.M_s) if extrapolate else None
        v_j = 0.0
        start = time.perf_counter()
        for k in range(n):
            t = k * h
            a_s = b.getReal(vr_a)
            if means is not None:
                a_s = [means.value(a_s[0])]
            u.setReal(vr_as, a_s)
            u.doStep(t, h)
            F_s, J_s, t_J, r[k + 1] = u.getReal(vr_out)
            ground = scn.ground(t, h)
            b.setReal(vr_in, [F_s, ground, J_s, t_J] if impulse_aware else [F_s, ground])
            b.doStep(t, h)
            *x[k + 1], v_next = b.getReal(vr_x)
            if means is not None:
                means.step_done(v_j, v_next, J_s, ground, h)
            v_j = v_next
        wall = time.perf_counter() - start
        impacts = u.getInteger(unit.vr("impacts"))[0]
    finally:
        unit.close()
        building.close()
    return Run(LABELS[mode], h, np.arange(n + 1) * h, x, r, impacts, wall, messages)


def physics_gauss_seidel(scn, h, mode="mean"):
    """The Gauss-Seidel master on the physics classes (ShearMotion, DamperUnit) directly: the
    FMUs' arithmetic without FMI (their adapters add nothing), for tests and quick studies.
    Returns (Run, the DamperUnit, the ShearMotion) at the end."""
    from pidamper_physics.shear_motion import ShearMotion
    from pidamper_physics.unit import DamperUnit

    impulse_aware, extrapolate = MODES[mode]
    n = scn.steps(h)
    j = scn.j
    building = ShearMotion(scn.building)
    unit = DamperUnit(**scn.unit_values(impulse_aware))
    unit.bound_work()
    forces = [0.0] * scn.storeys
    x = np.zeros((n + 1, scn.storeys))
    r = np.zeros(n + 1)
    means = _MeanAcceleration(scn.M_s) if extrapolate else None
    start = time.perf_counter()
    for k in range(n):
        t = k * h
        xs, vs = building.floors()
        a_s = building.absolute_accelerations(forces, xs, vs)[j]
        if means is not None:
            a_s = means.value(a_s)
        unit.advance(t + h, a_s)
        forces = [0.0] * scn.storeys
        forces[j] = unit.F_s
        kicks = [(unit.t_J, j, unit.J_s)] if impulse_aware and unit.J_s != 0.0 else ()
        ground = scn.ground(t, h)
        building.advance(t + h, forces, ground, kicks)
        x[k + 1], v_next = building.floors()
        if means is not None:
            means.step_done(vs[j], v_next[j], unit.J_s, ground, h)
        r[k + 1] = unit.r
    wall = time.perf_counter() - start
    return Run("physics " + LABELS[mode], h, np.arange(n + 1) * h, x, r, unit.impacts, wall), unit, building


def libcosim_jacobi(scn, h, impulse_aware=False, fmus=None):
    """The system in libcosim (libcosimpy), from the OSP system structure: its fixed-step
    algorithm (Jacobi); a_g driven through an override manipulator, floors read by an observer."""
    from libcosimpy.CosimExecution import CosimExecution
    from libcosimpy.CosimLogging import CosimLogLevel, log_output_level
    from libcosimpy.CosimManipulator import CosimManipulator
    from libcosimpy.CosimObserver import CosimObserver

    fmus = fmus or component_fmus()
    log_output_level(CosimLogLevel.ERROR)
    n = scn.steps(h)
    step_ns = int(round(h * 1e9))
    if abs(step_ns * 1e-9 - h) > 1e-12 * h:
        raise ValueError(f"step {h!r} is not allowed in libcosim: a whole number of nanoseconds")
    with tempfile.TemporaryDirectory(prefix="pidamper_osp_") as tmp:
        for path in fmus.values():
            shutil.copy2(path, Path(tmp) / Path(path).name)
        config = write_osp(Path(tmp) / "OspSystemStructure.xml", scn, impulse_aware, h)
        ex = CosimExecution.from_osp_config_file(str(config))
        b = ex.slave_index_from_instance_name("building")
        u = ex.slave_index_from_instance_name("unit")
        vr_b = {v.name.decode(): v.reference for v in ex.slave_variables(b)}
        vr_u = {v.name.decode(): v.reference for v in ex.slave_variables(u)}
        manipulator = CosimManipulator.create_override()
        ex.add_manipulator(manipulator=manipulator)
        observer = CosimObserver.create_last_value()
        ex.add_observer(observer=observer)
        vr_x = [vr_b[f"floor[{k + 1}].x"] for k in range(scn.storeys)]
        x = np.zeros((n + 1, scn.storeys))
        r = np.zeros(n + 1)
        start = time.perf_counter()
        for k in range(n):
            manipulator.slave_real_values(b, [vr_b["a_g"]], [scn.ground(k * h, h)])
            if not ex.step():
                raise RuntimeError(f"libcosim stopped at step {k} (t = {k * h} s)")
            x[k + 1] = observer.last_real_values(b, vr_x)
            r[k + 1] = observer.last_real_values(u, [vr_u["r"]])[0]
        wall = time.perf_counter() - start
        impacts = observer.last_integer_values(u, [vr_u["impacts"]])[0]
        del ex
    return Run(LABELS["libcosim-impulse" if impulse_aware else "libcosim"], h, np.arange(n + 1) * h, x, r, impacts,
               wall)


def refusal(fmu, values=None, inputs=None, steps=2, h=0.01):
    """Instantiate `fmu` with the start `values`, set `inputs` after initialization and take
    `steps` steps of h: the FMU's messages (str) if a call was refused, else None.  Run it through
    pidamper.isolated (a child process), as the other refusal checks."""
    from fmpy.fmi1 import FMICallException

    messages = []
    try:
        slave = _slave(fmu, "checked", values or {}, messages)
    except FMICallException as err:
        return "\n".join(messages) + f"\nstatus {err.status}"
    try:
        for name, value in (inputs or {}).items():
            slave.fmu.setReal(slave.vr(name), [value])
        for k in range(steps):
            slave.fmu.doStep(k * h, h)
    except FMICallException as err:
        return "\n".join(messages) + f"\nstatus {err.status}"
    finally:
        slave.close()
    return None


def refusals(cases):
    """[refusal(fmu, values, inputs) for each case]: for pidamper.isolated (JSON in and out)."""
    return [refusal(fmu, values, inputs) for fmu, values, inputs in cases]


# ---- the exact monolithic reference -------------------------------------------------------------

def reference(scn, times):
    """Floor displacements [m] at `times` (rows) of the exact monolithic model: THE function the
    measurements compare with.  The physics core's building level (Damper with storeys, when it
    accepts the scenario), else `ivp_reference`.  Returns (x, source)."""
    from pidamper_physics import ParameterError

    try:
        return monolithic_reference(scn, times), "monolithic core (Damper with storeys)"
    except (ImportError, TypeError, AttributeError, NotImplementedError, ParameterError) as err:
        return ivp_reference(scn, times), (f"independent event-driven integration (scipy DOP853, rtol 1e-12; the "
                                           f"core's building level is not usable here: {err})")


def monolithic_reference(scn, times):
    """Floor displacements at `times` by the physics core (Params(storeys=...) + Damper.floors())."""
    from pidamper_physics import Damper, Params

    params = Params(mu=scn.mu, FR=scn.FR, g=scn.g, d=scn.d, e=scn.e, zeta_s=scn.zeta_s, zeta_p=scn.zeta_p,
                    fidelity=1 if (scn.zeta_s or scn.zeta_p) else 0, storeys=scn.storeys,
                    damper_floor=scn.damper_floor, floor_m=list(scn.floor_m), storey_k=list(scn.storey_k))
    core = Damper(params)
    out = []
    for t in times:
        if core.t < scn.pulse_time < t:
            core.advance(scn.pulse_time, 0.0, scn.pulse)
        core.advance(t, 0.0, scn.pulse if t <= scn.pulse_time else 0.0)
        out.append(list(core.floors()[0]))
    return np.array(out)


def ivp_reference(scn, times, rtol=1e-12):
    """Floor displacements at `times` by an independent event-driven integration of the
    monolithic model: DOP853 (rtol 1e-12) between impacts, impacts located as events and resolved
    by the two-body Newton law between floor j and the particle (momentum exchanged with floor j
    only).  Refuses a scenario that chatters (it has no sticking rule)."""
    from scipy.integrate import solve_ivp

    b = scn.building
    n, j = b.n, scn.j
    M, K, C = np.array(b.masses), np.array(b.K), np.array(b.C)
    m, w1, d, e = scn.m, scn.w1, scn.d, scn.e
    cp = 2.0 * scn.zeta_p * w1
    mj = M[j]
    mu = m * mj / (m + mj)

    def rhs(t, z, ag):
        x, v, r, rd = z[:n], z[n:2 * n], z[2 * n], z[2 * n + 1]
        f = -(C @ v) - (K @ x)
        f[j] += m * (w1 * w1 * r + cp * rd)
        absolute = f / M
        return np.concatenate([v, absolute - ag, [rd, -w1 * w1 * r - cp * rd - absolute[j]]])

    def stop_plus(t, z, ag):
        return z[2 * n] - d

    def stop_minus(t, z, ag):
        return z[2 * n] + d

    stop_plus.terminal = stop_minus.terminal = True
    stop_plus.direction, stop_minus.direction = 1.0, -1.0
    atol = np.concatenate([np.full(2 * n, 1e-15), [1e-15, 1e-14]])
    pieces = []
    z = np.zeros(2 * n + 2)
    t = 0.0
    t_end = float(np.max(times))
    impacts = 0
    for t_to, ag in ((min(scn.pulse_time, t_end), scn.pulse), (t_end, 0.0)):
        while t < t_to:
            sol = solve_ivp(rhs, (t, t_to), z, method="DOP853", rtol=rtol, atol=atol, args=(ag,),
                            events=(stop_plus, stop_minus), dense_output=True)
            if sol.status == -1:
                raise RuntimeError(f"reference integration failed at t = {t}: {sol.message}")
            pieces.append((t, sol.t[-1], sol.sol))
            t, z = sol.t[-1], sol.y[:, -1].copy()
            if sol.status == 1:  # an impact
                side = 1.0 if len(sol.t_events[0]) else -1.0
                w = z[2 * n + 1]
                if abs(w) < 1e-6:
                    raise RuntimeError(f"the reference has no sticking rule: a grazing or chattering impact at "
                                       f"t = {t} (approach speed {w!r} m/s)")
                J = mu * (1.0 + e) * w
                z[n + j] += J / mj
                z[2 * n + 1] = -e * w
                z[2 * n] = side * d
                impacts += 1
    out = np.zeros((len(times), n))
    for i, tq in enumerate(times):
        for t0, t1, sol in pieces:
            if t0 <= tq <= t1 and t1 > t0:
                out[i] = sol(tq)[:n]
                break
        else:
            out[i] = 0.0 if tq <= 0.0 else pieces[-1][2](pieces[-1][1])[:n]
    ivp_reference.impacts = impacts
    return out


def error(run, scn, grid=0.01, ref=None):
    """max |x_k(t) - x_ref,k(t)| / max |x_ref| over the floors and the points t of a `grid` [s]
    common to every step compared (the relative error of the displacement history)."""
    times = np.arange(1, int(round(scn.stop_time / grid)) + 1) * grid
    if ref is None:
        ref, _ = reference(scn, times)
    return float(np.max(np.abs(run.at(times) - ref)) / np.max(np.abs(ref)))


# ---- SSP and OSP system structures --------------------------------------------------------------

def _connections(scn, impulse_aware):
    j = scn.floor
    pairs = [("building", f"floor[{j}].a", "unit", "a_s"), ("unit", "F_s", "building", f"F[{j}]")]
    if impulse_aware:
        pairs += [("unit", "J_s", "building", f"J[{j}]"), ("unit", "t_J", "building", f"t_J[{j}]")]
    return pairs


def write_osp(path, scn, impulse_aware=False, h=0.001, fmu_dir="."):
    """OspSystemStructure.xml (libcosim) of the coupled system at `path`; the FMUs are found in
    `fmu_dir` relative to it."""
    def initial(values, fmi_types):
        rows = []
        for name, value in values.items():
            kind = fmi_types.get(name, "Real")
            text = repr(int(value)) if kind == "Integer" else repr(float(value))
            rows.append(f'        <InitialValue variable={quoteattr(name)}><{kind} value="{text}"/></InitialValue>')
        return "\n".join(rows)

    integers = {"storeys": "Integer", "impulse_aware": "Integer"}
    connections = "\n".join(
        f'    <VariableConnection><Variable simulator="{a}" name={quoteattr(va)}/>'
        f'<Variable simulator="{b}" name={quoteattr(vb)}/></VariableConnection>'
        for a, va, b, vb in _connections(scn, impulse_aware))
    text = f"""<?xml version="1.0" encoding="UTF-8"?>
<!-- {SYSTEM}: the pendulum impact damper unit on floor {scn.floor} of a shear building
     ({'impulse-aware' if impulse_aware else 'mean-force'} coupling); written by pidamper.cosim -->
<OspSystemStructure xmlns="http://opensimulationplatform.com/MSMI/OSPSystemStructure" version="0.1">
  <StartTime>0.0</StartTime>
  <BaseStepSize>{h!r}</BaseStepSize>
  <Algorithm>fixedStep</Algorithm>
  <Simulators>
    <Simulator name="building" source="{fmu_dir}/{BUILDING}.fmu">
      <InitialValues>
{initial(scn.building_values(), integers)}
      </InitialValues>
    </Simulator>
    <Simulator name="unit" source="{fmu_dir}/{UNIT}.fmu">
      <InitialValues>
{initial(scn.unit_values(impulse_aware), integers)}
      </InitialValues>
    </Simulator>
  </Simulators>
  <Connections>
{connections}
  </Connections>
</OspSystemStructure>
"""
    Path(path).write_text(text)
    return Path(path)


def ssd_text(scn, impulse_aware=False, h=0.001):
    """SystemStructure.ssd (SSP 1.0) of the coupled system, the FMUs under resources/."""
    def connectors(rows):
        return "\n".join(f'          <ssd:Connector name={quoteattr(name)} kind="{kind}"><ssc:Real/></ssd:Connector>'
                         for name, kind in rows)

    def parameters(values):
        rows = []
        for name, value in values.items():
            typed = (f'<ssv:Integer value="{int(value)}"/>' if name in ("storeys", "impulse_aware")
                     else f'<ssv:Real value="{float(value)!r}"/>')
            rows.append(f'                  <ssv:Parameter name={quoteattr(name)}>{typed}</ssv:Parameter>')
        return "\n".join(rows)

    def binding(name, values):
        return f"""        <ssd:ParameterBindings>
          <ssd:ParameterBinding>
            <ssd:ParameterValues>
              <ssv:ParameterSet version="1.0" name="{name}">
                <ssv:Parameters>
{parameters(values)}
                </ssv:Parameters>
              </ssv:ParameterSet>
            </ssd:ParameterValues>
          </ssd:ParameterBinding>
        </ssd:ParameterBindings>"""

    j = scn.floor
    b_rows = [(f"floor[{j}].a", "output"), (f"F[{j}]", "input"), ("a_g", "input")]
    u_rows = [("a_s", "input"), ("F_s", "output")]
    if impulse_aware:
        b_rows += [(f"J[{j}]", "input"), (f"t_J[{j}]", "input")]
        u_rows += [("J_s", "output"), ("t_J", "output")]
    b_rows += [(f"floor[{k + 1}].x", "output") for k in range(scn.storeys)]
    u_rows += [("r", "output")]
    connections = "\n".join(
        f'      <ssd:Connection startElement="{a}" startConnector={quoteattr(va)} endElement="{b}" '
        f'endConnector={quoteattr(vb)}/>' for a, va, b, vb in _connections(scn, impulse_aware))
    mode = "impulse-aware" if impulse_aware else "mean-force"
    return f"""<?xml version="1.0" encoding="UTF-8"?>
<ssd:SystemStructureDescription xmlns:ssd="http://ssp-standard.org/SSP1/SystemStructureDescription"
    xmlns:ssc="http://ssp-standard.org/SSP1/SystemStructureCommon"
    xmlns:ssv="http://ssp-standard.org/SSP1/SystemStructureParameterValues"
    xmlns:osp="http://opensimulationplatform.com/SSP/OSPAnnotations"
    version="1.0" name="{SYSTEM}"
    description="pendulum impact damper unit on floor {j} of a shear building, {mode} coupling">
  <ssd:System name="{SYSTEM}">
    <ssd:Elements>
      <ssd:Component name="building" type="application/x-fmu-sharedlibrary" source="resources/{BUILDING}.fmu">
        <ssd:Connectors>
{connectors(b_rows)}
        </ssd:Connectors>
{binding("building", scn.building_values())}
      </ssd:Component>
      <ssd:Component name="unit" type="application/x-fmu-sharedlibrary" source="resources/{UNIT}.fmu">
        <ssd:Connectors>
{connectors(u_rows)}
        </ssd:Connectors>
{binding("unit", scn.unit_values(impulse_aware))}
      </ssd:Component>
    </ssd:Elements>
    <ssd:Connections>
{connections}
    </ssd:Connections>
  </ssd:System>
  <ssd:DefaultExperiment startTime="0.0" stopTime="{scn.stop_time!r}">
    <ssd:Annotations>
      <ssc:Annotation type="com.opensimulationplatform">
        <osp:Algorithm><osp:FixedStepAlgorithm baseStepSize="{h!r}"/></osp:Algorithm>
      </ssc:Annotation>
    </ssd:Annotations>
  </ssd:DefaultExperiment>
</ssd:SystemStructureDescription>
"""


def write_ssp(path, scn, fmus, impulse_aware=False, h=0.001):
    """An .ssp archive: SystemStructure.ssd and the two FMUs under resources/."""
    with zipfile.ZipFile(path, "w", zipfile.ZIP_DEFLATED) as z:
        z.writestr("SystemStructure.ssd", ssd_text(scn, impulse_aware, h))
        for name in (BUILDING, UNIT):
            z.write(fmus[name], f"resources/{name}.fmu")
    return Path(path)


def export_system(out_dir, scn=None, fmus=None, h=0.001):
    """Write the coupled system beside the FMUs in out_dir: DamperOnBuilding.ssp (mean force),
    DamperOnBuilding-impulse.ssp, OspSystemStructure.xml (mean force) and
    OspSystemStructure-impulse.xml (libcosim).  Returns the paths."""
    scn = scn or Scenario()
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    fmus = fmus or component_fmus()
    for name, path in fmus.items():
        if Path(path).resolve() != (out / f"{name}.fmu").resolve():
            shutil.copy2(path, out / f"{name}.fmu")
    return [write_ssp(out / f"{SYSTEM}.ssp", scn, fmus, False, h),
            write_ssp(out / f"{SYSTEM}-impulse.ssp", scn, fmus, True, h),
            write_osp(out / "OspSystemStructure.xml", scn, False, h),
            write_osp(out / "OspSystemStructure-impulse.xml", scn, True, h)]


# ---- command line -------------------------------------------------------------------------------

def add_arguments(parser):
    parser.add_argument("--step", type=float, action="append",
                        help="communication step [s] (repeatable; default 0.001); must divide the horizon")
    parser.add_argument("--stop-time", type=float, help="horizon [s] (default 5)")
    parser.add_argument("--master", action="append", choices=tuple(LABELS),
                        help="which masters to run (repeatable; default: mean, impulse, impulse-extrapolated: fmpy "
                             "Gauss-Seidel; libcosim, libcosim-impulse: libcosim's Jacobi)")
    parser.add_argument("--fmu-dir", help="folder with ShearBuilding.fmu and PendulumImpactDamperUnit.fmu "
                                          "(default: dist/, built when stale)")
    parser.add_argument("--export", metavar="DIR", help="also write the SSP files and the OSP system structures "
                                                        "(and a copy of the FMUs) into DIR")
    parser.add_argument("--no-reference", action="store_true", help="do not compute the monolithic reference")
    parser.add_argument("-p", "--param", action="append", default=[], metavar="NAME=VALUE",
                        help="scenario field, e.g. -p e=0.8 -p pulse=3 (fields of pidamper.cosim.Scenario)")


def scenario_from(params, stop_time=None):
    scn = Scenario()
    scalars = [k for k in Scenario.__dataclass_fields__ if k not in ("floor_m", "storey_k")]
    fields = {}
    for text in params:
        name, sep, value = text.partition("=")
        if not sep or name not in scalars:
            raise ValueError(f"-p {text!r} is not allowed: NAME=VALUE with NAME a scalar field of Scenario "
                             f"({', '.join(scalars)})")
        kind = type(getattr(scn, name))
        try:
            fields[name] = kind(value)
        except ValueError:
            raise ValueError(f"-p {text!r} is not allowed: {value!r} is not a {kind.__name__}") from None
    if stop_time is not None:
        fields["stop_time"] = stop_time
    return replace(scn, **fields)


def cli_main(argv=None):
    """pidamper cosim [options]: run the coupled system (see add_arguments); exit status."""
    import argparse
    import sys

    parser = argparse.ArgumentParser(
        prog="pidamper cosim",
        description="Co-simulate PendulumImpactDamperUnit.fmu on ShearBuilding.fmu (Gauss-Seidel with fmpy, or "
                    "libcosim's Jacobi) and compare with the exact monolithic model; --export writes the SSP files "
                    "and OSP system structures.")
    add_arguments(parser)
    args = parser.parse_args(argv)
    try:
        return main(args)
    except (ValueError, FileNotFoundError, RuntimeError) as err:
        print(f"pidamper cosim: error: {err}", file=sys.stderr)
        return 2


def main(args):
    scn = scenario_from(args.param, args.stop_time)
    fmus = component_fmus(args.fmu_dir)
    if args.export:
        for path in export_system(args.export, scn, fmus):
            print(f"wrote {path}")
    steps = args.step or [0.001]
    masters = args.master or list(MODES)
    grid = max(steps)
    ref, source = (None, None)
    if not args.no_reference:
        times = np.arange(1, int(round(scn.stop_time / grid)) + 1) * grid
        ref, source = reference(scn, times)
        print(f"reference: {source}")
    print(f"{'master':46s} {'step [s]':>10s} {'impacts':>8s} {'wall [s]':>9s} {'max|x_top| [m]':>15s} "
          f"{'error':>10s}")
    for h in steps:
        for master in masters:
            if master in ("libcosim", "libcosim-impulse"):
                run = libcosim_jacobi(scn, h, master == "libcosim-impulse", fmus)
            else:
                run = gauss_seidel(scn, h, master, fmus)
            err = error(run, scn, grid, ref) if ref is not None else math.nan
            print(f"{run.master:46s} {h:10.3g} {run.impacts:8d} {run.wall:9.3f} {np.max(np.abs(run.x[:, -1])):15.6g} "
                  f"{err:10.3e}")
            for text in run.notes:
                print(f"  FMU: {text}")
    return 0
