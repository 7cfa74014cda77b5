"""The master that steps an OpenSeesPy model and PendulumImpactDamperUnit FMUs on its nodes.

Gauss-Seidel with second-order coupling, communication step h, OpenSees substeps of h / substeps
(Newmark average acceleration, Newton):

1. each unit gets the attachment's absolute acceleration for the coming step: the linear
   extrapolation of the node's smooth mean absolute acceleration over the last two steps
   ((v(t_k) - v(t_k-1) - the impulse's jump) / h + the ground's held value), the node's own until
   two steps are known; the unit steps over [t, t + h] (impulse-aware: it reports its mean smooth
   force F_s and the impulse J_s at t_J);
2. OpenSees gets F_s as a nodal load held over the step (a Plain pattern per unit, re-made every
   step on one Constant series) and is analysed to t + h, split at each t_J, where the impulse
   jumps the attachment's velocity by M^-1 e J (`setNodeVel(..., '-commit')`);
3. Newmark carries the committed acceleration into the next step, and that acceleration belongs
   to the old loads and velocities: wherever they change (a new F_s, a new held ground value, a
   velocity jump) the committed accelerations are set to equilibrium with the new ones,
   a += M^-1 (dF - C dv) - iota da_g (`setNodeAccel(..., '-commit')`, `domainChange()`): without
   this the coupling is first order (physics notes).  M and C (mass and damping in OpenSees's
   equation numbering, whatever damping model the user chose: modalDamping, rayleigh) are read
   once from the analysis's own matrix A = K + (2/dt) C + (4/dt^2) M at three step sizes, from
   rest, before the ground motion is applied.

The ground motion is a UniformExcitation whose Path series is the staircase an FMU input sees:
the record's value at each communication point, held over the step (two points at each jump).
OpenSees reports motion relative to the ground; the units get absolute accelerations.
"""
import math
import time
from dataclasses import dataclass, field

import numpy as np

from ..oracles.opensees import load, staircase
from ..running.fmu import find_fmu
from ..running.instance import FmuInstance
from . import checks
from .checks import CouplingError

#: the unit's outputs recorded each step, by their FMU names
UNIT_OUTPUTS = ("F_s", "J_s", "t_J", "r", "r_dot", "impacts", "contact", "energy_dissipated", "impact_force_peak",
                "contact_pressure_peak", "impacts_plastic")
#: tags the master owns in the user's model (far from what a model file uses)
_GROUND_SERIES, _GROUND_PATTERN, _FORCE_SERIES, _FORCE_PATTERN = 910001, 910002, 910003, 910100


class OpenSeesFailure(RuntimeError):
    """OpenSees could not analyse a step (no convergence): the time and step are named."""


@dataclass
class Attachment:
    """A unit on `node`'s degree of freedom `dof` (1-based); `values` its FMU start values (m, L1,
    d, e, materials, ...); M_s the mass share its impact law uses (default: the apparent mass of
    the attachment, 1 / (M^-1)_jj: the node's mass plus what is constrained to move with it)."""

    node: int
    dof: int
    values: dict = field(default_factory=dict)
    M_s: float = None


@dataclass
class CosimResult:
    """time [s] (n + 1,), per attachment x, v, a_abs [m, m/s, m/s2] (relative displacement and
    velocity, absolute acceleration of the attachment's dof) and the unit's UNIT_OUTPUTS, rows at
    the communication points; cpu [s] of the loop (host included); warnings from the units."""

    time: np.ndarray
    nodes: list
    units: list
    cpu: float
    M_s: list
    warnings: list
    impulses: list  # (t_J, attachment index, J [N s], the attachment's velocity jump OpenSees shows [m/s])
    watched: np.ndarray = None  # (n + 1, len(watch), 2): x and a_abs of the watched degrees of freedom


def _equations(ops):
    """{equation: (node, dof)} of the analysis's numbering."""
    out = {}
    for tag in ops.getNodeTags():
        for dof, eq in enumerate(ops.nodeDOFs(tag), start=1):
            if eq >= 0:
                out[eq] = (tag, dof)
    return out


def _matrices(ops, steps=(0.01, 0.02, 0.04)):
    """(M, C) in equation numbering from the transient analysis's matrix at three step sizes
    (Newmark 1/2, 1/4: A = K + 2/dt C + 4/dt^2 M), taken from rest with no load: the state stays,
    the clock is set back to 0."""
    rows = []
    for dt in steps:
        if ops.analyze(1, dt) != 0:
            raise OpenSeesFailure(f"OpenSees could not take a step of {dt} s from rest with no load, so its mass "
                                  "and damping cannot be read: check the model (see OpenSees's output above)")
        A = np.array(ops.printA("-ret"), dtype=float)
        n = int(round(math.sqrt(A.size)))
        rows.append(A.reshape(n, n))
    ops.setTime(0.0)
    basis = np.array([[1.0, 2.0 / dt, 4.0 / dt ** 2] for dt in steps])
    K, C, M = np.einsum("ij,jkl->ikl", np.linalg.inv(basis), np.array(rows))
    scale = np.abs(M).max()
    M[np.abs(M) < 1e-12 * scale] = 0.0
    C[np.abs(C) < 1e-12 * max(np.abs(C).max(), 1e-300)] = 0.0
    return M, C


class Coupling:
    """The master (see the module doc) on the OpenSees domain the user built; `attachments` a list
    of Attachment, `ground` (samples at the communication points [m/s2]) or None, `direction` the
    degree of freedom the ground moves (1-based), h the communication step [s]."""

    def __init__(self, attachments, h, ground=None, direction=1, substeps=4, fmu=None, logger=None, watch=()):
        self.ops = ops = load()
        self.h, self.substeps = checks.positive("step", h), checks.count("substeps", substeps)
        self.direction = direction
        checks.on_model(ops, attachments, direction)
        tags = set(ops.getNodeTags())
        self.attachments = attachments
        self.watch = [tuple(w) for w in watch]  # (node, dof) recorded every step beside the attachments
        for node, dof in self.watch:
            if node not in tags:
                raise CouplingError(f"watch node = {node!r} is not allowed: the model has no such node")
        self._made = False
        self.done, self.stopped = 0, None  # steps done; while run() goes, stopped(text, t) (see there)
        self._analysis()
        M, C = _matrices(ops)
        eq = _equations(ops)
        self.mass_eqs = [i for i in range(len(M)) if M[i, i] > 0.0]
        index = {e: k for k, e in enumerate(self.mass_eqs)}
        Mm = M[np.ix_(self.mass_eqs, self.mass_eqs)]
        self.Minv = np.linalg.inv(Mm)
        self.C = C[np.ix_(self.mass_eqs, self.mass_eqs)]
        self.where = [eq[e] for e in self.mass_eqs]  # (node, dof) of each mass equation
        self.iota = np.array([1.0 if dof == direction else 0.0 for _, dof in self.where])
        self.slot, self.M_app = [], []
        for a in attachments:
            e = ops.nodeDOFs(a.node)[a.dof - 1]
            if e < 0 or e not in index:
                raise CouplingError(f"node = {a.node}, dof = {a.dof} is not allowed: that degree of freedom "
                                    f"{'is constrained' if e < 0 else 'carries no mass'}: attach the unit to a "
                                    "free degree of freedom with mass (the retained node of a constraint)")
            k = index[e]
            self.slot.append(k)
            self.M_app.append(1.0 / self.Minv[k, k])
        self.M_s = []
        for a, apparent in zip(attachments, self.M_app):
            M_s = apparent if a.M_s is None else a.M_s
            if not (isinstance(M_s, (int, float)) and math.isfinite(M_s) and M_s > 0.0):
                raise CouplingError(f"M_s = {M_s!r} is not allowed: a finite mass > 0 kg (default: the apparent "
                                    f"mass of node {a.node}, dof {a.dof}: {apparent!r} kg)")
            self.M_s.append(float(M_s))
        self.ground = None if ground is None else np.asarray(ground, dtype=float)
        if self.ground is not None:
            times, values = staircase(self.ground, h)
            ops.timeSeries("Path", _GROUND_SERIES, "-time", *times, "-values", *values)
            ops.pattern("UniformExcitation", _GROUND_PATTERN, direction, "-accel", _GROUND_SERIES)
        self.messages = []
        self._logger = logger
        fmu = fmu or find_fmu(model="PendulumImpactDamperUnit")
        self.units = []
        for i, (a, M_s) in enumerate(zip(attachments, self.M_s)):
            try:
                self.units.append(FmuInstance(fmu, {**a.values, "M_s": M_s, "impulse_aware": 1},
                                              instance_name=f"unit{i + 1}", logger=self._hear))
            except Exception as err:
                self.close()
                said = "; ".join(text for status, text in self.messages if status >= 3) or str(err)
                raise CouplingError(f"the unit on node {a.node}, dof {a.dof} refused its parameters: {said}") from None

    def _hear(self, status, text):
        self.messages.append((status, text))
        if self._logger is not None:
            self._logger(status, text)

    def _analysis(self):
        ops = self.ops
        ops.timeSeries("Constant", _FORCE_SERIES)
        self._set_forces([0.0] * len(self.attachments))
        ops.wipeAnalysis()
        ops.constraints("Transformation")
        ops.numberer("RCM")
        ops.system("FullGeneral")
        ops.test("NormDispIncr", 1e-12, 50)
        ops.algorithm("Newton")
        ops.integrator("Newmark", 0.5, 0.25)
        ops.analysis("Transient")

    def _set_forces(self, forces):
        ops = self.ops
        for i, (a, f) in enumerate(zip(self.attachments, forces)):
            tag = _FORCE_PATTERN + i
            if self._made:
                ops.remove("loadPattern", tag)
            ops.pattern("Plain", tag, _FORCE_SERIES)
            ndf = len(ops.nodeDisp(a.node))
            ops.load(a.node, *[f if d == a.dof else 0.0 for d in range(1, ndf + 1)])
        self._made = True

    def _accelerations(self):
        ops = self.ops
        return np.array([ops.nodeAccel(node, dof) for node, dof in self.where])

    def _set_accelerations(self, values):
        ops = self.ops
        for (node, dof), a in zip(self.where, values):
            ops.setNodeAccel(node, dof, float(a), "-commit")
        ops.domainChange()

    def _analyze(self, span):
        """OpenSees from its time to + span, in substeps no longer than h / substeps."""
        ops = self.ops
        n = max(1, int(math.ceil(span / (self.h / self.substeps) - 1e-9)))
        dt = span / n
        for _ in range(n):
            if ops.analyze(1, dt) != 0:
                raise OpenSeesFailure(f"OpenSees did not converge in the step from t = {ops.getTime()!r} s "
                                      f"(dt = {dt!r} s; see OpenSees's output above)")

    def run(self, stop_time, sink=None, block=500):
        """Co-simulate to stop_time [s] (a whole number of steps); returns a CosimResult.  sink (a
        log.CosimLog) gets the rows every `block` steps and, on a failure, those up to it and a note;
        while it goes, self.stopped(text, t) does that for a failure seen from outside (the process
        ending: exits.py)."""
        ops, h = self.ops, self.h
        n = checks.horizon(stop_time, h)
        if self.ground is not None and len(self.ground) < n:
            raise CouplingError(f"stop_time = {stop_time!r} is not allowed: the ground motion has "
                                f"{len(self.ground)} steps of {h!r} s")
        k_units = len(self.units)
        vr_in = [u.vr("a_s")[0] for u in self.units]
        vr_out = [u.vr(*(name for name in UNIT_OUTPUTS if u.vars[name].type == "Real")) for u in self.units]
        vr_int = [u.vr(*(name for name in UNIT_OUTPUTS if u.vars[name].type != "Real")) for u in self.units]
        reals = [name for name in UNIT_OUTPUTS if self.units[0].vars[name].type == "Real"]
        ints = [name for name in UNIT_OUTPUTS if self.units[0].vars[name].type != "Real"]
        order = [UNIT_OUTPUTS.index(name) for name in reals + ints]
        nodes = [np.zeros((n + 1, 3)) for _ in range(k_units)]
        self.watched = np.zeros((n + 1, len(self.watch), 2))
        units = [np.zeros((n + 1, len(UNIT_OUTPUTS))) for _ in range(k_units)]
        impulses = []
        means = [[] for _ in range(k_units)]
        v_then = [ops.nodeVel(a.node, a.dof) for a in self.attachments]
        for i, a in enumerate(self.attachments):
            nodes[i][0] = (ops.nodeDisp(a.node, a.dof), v_then[i], 0.0)
        start = time.process_time()
        written = [1, 0]  # rows and impulses handed to the sink

        def hand_on(upto):
            if sink is not None and upto > written[0]:
                rows = slice(written[0], upto)
                sink.write(np.arange(n + 1)[rows] * h, [x[rows] for x in nodes], [u[rows] for u in units],
                           impulses[written[1]:])
                written[:] = [upto, len(impulses)]

        def stopped(text, t):
            hand_on(self.done + 1)  # the steps completed before the failure
            if sink is not None:
                sink.note(t, f"the co-simulation stopped: {text}", "ERROR")

        if sink is not None:
            sink.write(np.zeros(1), [x[:1] for x in nodes], [u[:1] for u in units], [])
        self.stopped = stopped
        try:
            self._loop(n, nodes, units, impulses, means, v_then, vr_in, vr_out, vr_int, order, hand_on, block)
        except Exception as err:
            stopped(str(err), ops.getTime())
            raise
        finally:
            self.stopped = None
        hand_on(n + 1)
        cpu = time.process_time() - start
        warnings = [text for status, text in self.messages if status == 1]
        return CosimResult(np.arange(n + 1) * h, nodes, units, cpu, list(self.M_s), warnings, impulses, self.watched)

    def _loop(self, n, nodes, units, impulses, means, v_then, vr_in, vr_out, vr_int, order, hand_on, block):
        ops, h = self.ops, self.h
        forces = [0.0] * len(self.units)
        ground_then = 0.0  # the ground value the committed accelerations belong to (rest: none)
        self.done = 0
        for k in range(n):
            if k and k % block == 0:
                hand_on(k + 1)
            t = k * h
            g = float(self.ground[k]) if self.ground is not None else 0.0
            # 1. the units
            news = []
            for i, (u, a) in enumerate(zip(self.units, self.attachments)):
                m = means[i]
                if len(m) >= 2:
                    a_s = 2.0 * m[-1] - m[-2]
                elif m:
                    a_s = m[-1]
                else:
                    a_s = ops.nodeAccel(a.node, a.dof) - (g - ground_then) + g
                u.fmu.setReal([vr_in[i]], [a_s])
                u.do_step(t, h)
                values = list(u.fmu.getReal(vr_out[i])) + [float(x) for x in u.fmu.getInteger(vr_int[i])]
                row = [0.0] * len(UNIT_OUTPUTS)
                for j, value in zip(order, values):
                    row[j] = value
                units[i][k + 1] = row
                news.append(row)
            # 2. the new loads, and the committed accelerations set to equilibrium with them
            new_forces = [row[0] for row in news]
            self._set_forces(new_forces)
            dP = np.zeros(len(self.mass_eqs))
            for i, (f_new, f_old) in enumerate(zip(new_forces, forces)):
                dP[self.slot[i]] += f_new - f_old
            self._set_accelerations(self._accelerations() + self.Minv @ dP - self.iota * (g - ground_then))
            forces, ground_then = new_forces, g
            # 3. OpenSees over the step, split at the impulses
            kicks = sorted((row[2], i, row[1]) for i, row in enumerate(news) if row[1] != 0.0)
            now = t
            for t_J, i, J in kicks:
                t_J = min(max(t_J, t), t + h)
                if t_J > now:
                    self._analyze(t_J - now)
                    now = t_J
                self._kick(i, J, impulses, t_J)
            if t + h > now:
                self._analyze(t + h - now)
            # 4. the attachments' motion, and their mean absolute accelerations for the extrapolation
            for i, a in enumerate(self.attachments):
                v = ops.nodeVel(a.node, a.dof)
                J = news[i][1]
                means[i] = means[i][-1:] + [(v - v_then[i] - J / self.M_app[i]) / h + g]
                v_then[i] = v
                nodes[i][k + 1] = (ops.nodeDisp(a.node, a.dof), v, ops.nodeAccel(a.node, a.dof) + g)
            for j, (node, dof) in enumerate(self.watch):
                self.watched[k + 1, j] = (ops.nodeDisp(node, dof), ops.nodeAccel(node, dof) + g)
            self.done = k + 1

    def _kick(self, i, J, impulses, t_J):
        """The impulse J [N s] of unit i at t_J: the velocities jump by M^-1 e J, the committed
        accelerations by -M^-1 C dv."""
        ops = self.ops
        e = np.zeros(len(self.mass_eqs))
        e[self.slot[i]] = J
        dv = self.Minv @ e
        a = self.attachments[i]
        before = ops.nodeVel(a.node, a.dof)
        for (node, dof), jump in zip(self.where, dv):
            if jump != 0.0:
                ops.setNodeVel(node, dof, ops.nodeVel(node, dof) + float(jump), "-commit")
        self._set_accelerations(self._accelerations() - self.Minv @ (self.C @ dv))
        impulses.append((t_J, i, J, ops.nodeVel(a.node, a.dof) - before))

    def close(self):
        for u in self.units:
            u.close()
