"""A run logged to MCAP and Rerun while it goes, and the replay of an MCAP into Rerun.

The run is fmpy.simulate_fmu with a step_finished hook that takes each new row of
fmpy's recorder plus the FMU's per-step impact record, and hands blocks of rows
to both writers.  If the run fails half-way (an FMI error, bad input, Ctrl-C),
what was collected is written, a note says where and why it stopped, and both
files are closed so they read back up to the failure.
"""
import signal
import sys
import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from . import rerun_log
from ..running.fmu import find_fmu
from ..running.variants import storeys_of
from ..forcing import none
from .mcap_log import McapLog, read_floors, read_run
from .schema import IMPACT_DTYPE, STATE_DTYPE, STATE_FIELDS, floors_dtype, geometry, run_info
from ..running.simulation import FmuError, floor_columns, run

IMPACT_SLOTS = 16
INPUTS = ("F", "a_g")  # state columns that come from the forcing, not from the FMU
_SLOT_REALS = ("t", "v_rel_before", "v_rel_after", "energy_lost", "theta", "e", "force_peak", "pressure_peak",
               "duration")


@dataclass
class LoggedRun:
    result: object  # simulation.RunResult
    mcap: Path
    rrd: Path
    impacts_recorded: int
    impacts_unrecorded: int
    cpu_time: float  # s, the whole logged run


class Sinks:
    """The MCAP writer and the Rerun recording of one run, fed the same blocks."""

    def __init__(self, info, mcap_path=None, rrd_path=None, serve=False, connect=None):
        self.info = info
        self.mcap = McapLog(mcap_path, info) if mcap_path else None
        self.rec = None
        if rrd_path or serve or connect:
            self.rec = rerun_log.open_recording(info, rrd_path, serve, connect)
            rerun_log.log_start(self.rec, info)

    def write(self, states, impacts, floors=None):
        """A block of states and impacts, and of a building's floors (floors_dtype) if any."""
        if self.mcap:
            self.mcap.write(states, impacts, floors)
        if self.rec:
            rerun_log.log_block(self.rec, self.info, states, impacts, floors)

    def note(self, t, level, text):
        if self.mcap:
            self.mcap.note(t, level, text)
        if self.rec:
            rerun_log.log_note(self.rec, t, level, text)

    def flush(self):
        if self.mcap:
            self.mcap.flush()
        if self.rec:
            self.rec.flush()

    def close(self):
        if self.mcap:
            self.mcap.close()
        if self.rec:
            self.rec.flush()
            self.rec.disconnect()


class Collector:
    """step_finished hook: turns recorder rows and impact records into blocks."""

    def __init__(self, sinks, forcing, start_time, block):
        self.sinks, self.forcing, self.block = sinks, forcing, block
        self.done = 0  # recorder rows already taken
        self.states, self.impacts, self.floors = [], [], []
        self.floor_cols = []  # recorder columns of a building's floors (none without one)
        self.last_t = self.held_from = start_time
        self.recorded = self.unrecorded = 0
        self.vr = None

    def __call__(self, t, recorder):
        if self.vr is None:
            self._bind(recorder)
        rows = recorder.rows
        columns, states = self.columns, self.states
        for row in rows[self.done:]:
            states.append(tuple(row[i] for i in columns))
        if self.floor_cols:
            self.floors.extend([row[0]] + [row[i] for i in self.floor_cols] for row in rows[self.done:])
        self.done = len(rows)
        last = rows[-1]
        n = last[self.col_in_step]
        if n:
            self._take_impacts(recorder.fmu, n, last[self.col_impacts], last[0])
        self.last_t = last[0]
        if len(states) >= self.block:
            self.flush()
        return True

    def _bind(self, recorder):
        md = recorder.modelDescription
        vr = {v.name: v.valueReference for v in md.modelVariables}
        names = [c[0] for c in recorder.cols]
        self.columns = [names.index(f) for f in STATE_FIELDS if f not in INPUTS]
        self.col_in_step = names.index("impacts_in_step")
        self.col_impacts = names.index("impacts")
        self.storeys = storeys = sum(1 for n in names if n.startswith("floor[") and n.endswith("].x"))
        self.floor_cols = [names.index(n) for n in floor_columns(storeys)] if storeys else []
        self.vr_reals = [[vr[f"impact[{k + 1}].{f}"] for f in _SLOT_REALS] for k in range(IMPACT_SLOTS)]
        self.vr_sides = [vr[f"impact[{k + 1}].{f}"] for f in ("side", "plastic") for k in range(IMPACT_SLOTS)]
        self.vr = vr

    def _take_impacts(self, fmu, n, total, t_step):
        k = min(n, IMPACT_SLOTS)
        reals = fmu.getReal([v for slot in self.vr_reals[:k] for v in slot])
        ints = fmu.getInteger(self.vr_sides[:k] + self.vr_sides[IMPACT_SLOTS:IMPACT_SLOTS + k])
        first = total - n + 1
        nr = len(_SLOT_REALS)
        for j in range(k):
            self.impacts.append((reals[nr * j], ints[j], *reals[nr * j + 1:nr * j + nr], ints[k + j], first + j))
        self.recorded += k
        if n > k:
            self.unrecorded += n - k
            self.sinks.note(t_step, "warning",
                            f"{n - k} of the {n} impacts in the step ending at t = {t_step:.9g} s were counted "
                            f"but not recorded individually (the FMU records {IMPACT_SLOTS} per step)")

    def flush(self):
        if not self.states and not self.impacts:
            return
        states = np.zeros(len(self.states), dtype=STATE_DTYPE)
        if len(self.states):
            table = np.array(self.states, dtype=np.float64)
            for j, name in enumerate(f for f in STATE_FIELDS if f not in INPUTS):
                states[name] = table[:, j]
            # the input held over the step that ends at each row (the first row: at t0)
            held_from = np.concatenate([[self.held_from], states["time"][:-1]])
            states[self.forcing.target] = self.forcing.value(held_from)
            self.held_from = states["time"][-1]
        floors = None
        if self.floor_cols:
            n = self.storeys
            table = np.array(self.floors, dtype=np.float64).reshape(-1, 3 * n + 2)
            floors = np.zeros(len(table), dtype=floors_dtype(n))
            floors["time"], floors["base_shear"] = table[:, 0], table[:, -1]
            for j, name in enumerate(("x", "a", "drift")):
                floors[name] = table[:, 1 + j * n:1 + (j + 1) * n]
        self.sinks.write(states, np.array(self.impacts, dtype=IMPACT_DTYPE), floors)
        self.states, self.impacts, self.floors = [], [], []


class _CtrlC:
    """While active (main thread only), SIGINT sets `pressed` instead of raising."""

    def __init__(self):
        self.pressed = False
        self.previous = None

    def __enter__(self):
        try:
            self.previous = signal.signal(signal.SIGINT, self._press)
        except ValueError:  # not the main thread: leave SIGINT alone
            self.previous = None
        return self

    def _press(self, signum, frame):
        self.pressed = True

    def __exit__(self, *exc):
        if self.previous is not None:
            signal.signal(signal.SIGINT, self.previous)


def run_logged(parameters=None, forcing=None, stop_time=20.0, output_interval=0.01, out_dir="out", name="run",
               fmu=None, mcap=True, rrd=True, serve=False, connect=None, block=1000, start_time=0.0, topics=None,
               views=None, scene=None, after_collapse=False):
    """run() with the MCAP and the .rrd written into out_dir while it goes; `topics` and `views`
    choose the MCAP topics and the Rerun views (default: all); `scene` (name, source, description)
    is kept in the run's info; a building's collapse ends the run unless after_collapse (run())."""
    forcing = forcing or none()
    start_values = {**(parameters or {}), **forcing.start_values}
    path = find_fmu(fmu, storeys=storeys_of(start_values))  # DampedShearBuilding<N>.fmu for storeys = N
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    info = run_info(path, start_values, forcing, start_time, stop_time, output_interval, None)
    info["geometry"] = geometry(info["parameters"])
    info["log_block"] = block  # the replay logs in the same blocks
    info["scene"] = dict(scene or {})
    info["log"] = {"mcap_topics": list(topics) if topics else None, "rerun_views": list(views) if views else None}
    mcap_path = out / f"{name}.mcap" if mcap else None
    rrd_path = out / f"{name}.rrd" if rrd else None
    cpu = time.process_time()
    sinks = Sinks(info, mcap_path, rrd_path, serve, connect)
    collector = Collector(sinks, forcing, start_time, block)
    sinks.note(start_time, "info", f"run {info['recording_id']} started: forcing {forcing.kind} {forcing.args}")
    try:
        with _CtrlC() as ctrl_c:  # Ctrl-C ends the run between steps, never inside the FMU's Python
            result = run(parameters, forcing, stop_time, output_interval, fmu=path, start_time=start_time,
                         step_finished=lambda t, rec: collector(t, rec) and not ctrl_c.pressed,
                         extra_outputs=("impacts_in_step",),
                         on_warning=lambda t, text: sinks.note(t, "warning", text), after_collapse=after_collapse)
        if ctrl_c.pressed:
            raise KeyboardInterrupt(f"interrupted by the user at t = {collector.last_t:.9g} s")
    except BaseException as err:
        collector.flush()
        what = "interrupted" if isinstance(err, KeyboardInterrupt) else "failed"
        reason = str(err) or type(err).__name__
        sinks.note(collector.last_t, "error", f"run {what} after t = {collector.last_t:.9g} s: {reason}; "
                                              "the log holds everything up to there")
        sinks.close()
        if isinstance(err, FmuError):
            err.logs = (mcap_path, rrd_path)
        raise
    collector.flush()
    if "collapsed" in result.meta:
        sinks.note(result.meta["collapsed"], "warning", f"the building collapsed by t = {result.meta['collapsed']:.9g} "
                                                        "s: the run stops there")
    sinks.note(float(result.data["time"][-1]), "info",
               f"run complete: {int(result.data['impacts'][-1])} impacts, {collector.recorded} recorded "
               f"individually, {collector.unrecorded} not")
    sinks.close()
    return LoggedRun(result, mcap_path, rrd_path, collector.recorded, collector.unrecorded,
                     time.process_time() - cpu)


def replay(mcap_path, rrd_path=None, serve=False, connect=None):
    """Turn a run's MCAP into a Rerun recording with the same content as the live one: the
    same blocks (states in runs of the live run's block size, each with the impacts up to its
    last time) and notes, through the same logging function."""
    info, states, impacts, notes = read_run(mcap_path)
    floors = read_floors(mcap_path)
    block = info.get("log_block", 1000)
    sinks = Sinks(info, None, rrd_path, serve, connect)
    notes = sorted(notes, key=lambda note: note[0])
    n_note = j = 0
    for start in range(0, len(states), block):
        chunk = states[start:start + block]
        t_last = chunk["time"][-1]
        while n_note < len(notes) and notes[n_note][0] <= t_last:
            sinks.note(*notes[n_note])
            n_note += 1
        k = j + int(np.searchsorted(impacts["t"][j:], t_last, side="right"))
        sinks.write(chunk, impacts[j:k], None if floors is None else floors[start:start + block])
        j = k
    if j < len(impacts):
        sinks.write(states[:0], impacts[j:])
    for note in notes[n_note:]:
        sinks.note(*note)
    sinks.close()
    return info


def wait_for_viewers():
    """Keep a served recording up until Ctrl-C."""
    print("serving on rerun+http://127.0.0.1:9876/proxy; Ctrl-C to stop", file=sys.stderr)
    try:
        while True:
            time.sleep(1.0)
    except KeyboardInterrupt:
        return
