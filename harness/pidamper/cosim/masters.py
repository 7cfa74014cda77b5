"""The co-simulation masters: Gauss-Seidel on fmpy (`gauss_seidel`), the same master on the physics
classes (`physics_gauss_seidel`) and libcosim's Jacobi (`libcosim_jacobi`); the component FMUs they load."""
import shutil
import tempfile
import time
from pathlib import Path

import numpy as np

from .components import component_instance, component_fmus
from .scenario import BUILDING, UNIT, Run
from .system_files import write_osp


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
    fmus = fmus or component_fmus(storeys=scn.storeys)
    messages = []
    n = scn.steps(h)
    j = scn.floor
    building = component_instance(fmus[BUILDING], "building", scn.building_values(), messages)
    unit = component_instance(fmus[UNIT], "unit", scn.unit_values(impulse_aware), messages)
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

    fmus = fmus or component_fmus(storeys=scn.storeys)
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
