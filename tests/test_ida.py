"""Hunt and fill (Vamvatsikos & Cornell 2002) against synthetic IDAs whose collapse intensity is
known: it is bracketed to the stated tolerance within 10 runs, the curve below it is filled, a
record that never collapses gets no capacity."""
import math
import numpy as np
import pytest

from pidamper.assessment.ida import Trace, at_level, hunt_and_fill, leave_one_out


@pytest.mark.parametrize("capacity", np.linspace(0.25, 1.2, 12))
def test_the_collapse_intensity_is_bracketed_to_the_tolerance(capacity):
    calls = []

    def run(im):
        calls.append(im)
        return im >= capacity, im / capacity * 0.02  # drift ratio grows to 2 % at collapse

    trace = hunt_and_fill(run, first=0.1, step=0.1, increment=0.1, tolerance=0.05, max_runs=10)
    assert trace.collapsed and len(calls) <= 10
    assert trace.lo < capacity <= trace.hi
    assert (trace.hi - trace.lo) <= 0.05 * trace.lo
    assert abs(trace.capacity - capacity) <= 0.025 * capacity
    assert [im for im, _ in trace.curve()] == sorted(im for im in calls if im < capacity)


def test_runs_left_fill_the_curve_below_collapse():
    """With runs to spare after the bracket, each halves the widest gap of the curve below collapse."""
    run = lambda im: (im >= 0.3, im)
    bracketed = hunt_and_fill(run, first=0.1, step=0.1, increment=0.1, tolerance=0.1, max_runs=10)
    used = next(k for k in range(2, 11)
                if hunt_and_fill(run, first=0.1, step=0.1, increment=0.1, tolerance=0.1, max_runs=k).hi is not None
                and (lambda t: t.hi - t.lo <= 0.1 * t.lo)(hunt_and_fill(run, first=0.1, step=0.1, increment=0.1,
                                                                       tolerance=0.1, max_runs=k)))
    before = hunt_and_fill(run, first=0.1, step=0.1, increment=0.1, tolerance=0.1, max_runs=used)
    widest = lambda t: np.diff([0.0] + [im for im, _ in t.curve()]).max()
    assert len(bracketed.runs) == 10 and used < 10
    assert all(im < bracketed.lo or im == bracketed.lo for im, c, _ in bracketed.runs[used:] if not c)
    assert widest(bracketed) <= 0.5 * widest(before) + 1e-12


def test_a_record_that_never_collapses_has_no_capacity():
    trace = hunt_and_fill(lambda im: (False, im), first=0.1, step=0.1, max_runs=10)
    assert not trace.collapsed and trace.capacity is None and len(trace.runs) == 10


def linear_trace(capacity=3.0):
    """Hunt and fill on a record whose demands are linear in the intensity up to its collapse."""
    def run(im):
        return im >= capacity, {"PID-1": 0.01 * im, "PFA-1": 4.0 * im + 0.0, "impacts": 10 * im, "collapsed": 0,
                                "t_end": 30.0}
    return hunt_and_fill(run, first=0.25, step=0.75, increment=0.5, tolerance=0.05, max_runs=10)


@pytest.mark.parametrize("level", [0.1, 0.25, 0.4, 0.63, 1.37, 2.5])
def test_stripe_demands_are_read_off_the_ida_curve(level):
    """Below the collapse intensity every demand of a linear IDA curve is recovered exactly (the
    curve from (0, 0), linear between runs); the flags say whether a run was there."""
    trace = linear_trace()
    found, collapsed, exact = at_level(trace, level)
    assert not collapsed and exact == any(im == level for im, _, _ in trace.runs)
    assert found["PID-1"] == pytest.approx(0.01 * level, rel=1e-12)
    assert found["PFA-1"] == pytest.approx(4.0 * level, rel=1e-12) and found["impacts"] == pytest.approx(10 * level)
    assert found["t_end"] == 30.0 and found["collapsed"] == 0  # how the run ended: never interpolated


def test_at_and_above_the_capacity_a_stripe_takes_the_collapsing_run():
    trace = linear_trace()
    lowest = min(im for im, c, _ in trace.runs if c)
    for level in (trace.capacity, lowest, 5.0, 50.0):
        found, collapsed, exact = at_level(trace, level)
        assert collapsed and found["PID-1"] == pytest.approx(0.01 * lowest) and exact == (level == lowest)
    # between the highest standing run and the capacity (half a bracket): that run's demands
    found, collapsed, _ = at_level(trace, 0.5 * (trace.lo + trace.capacity))
    assert not collapsed and found["PID-1"] == pytest.approx(0.01 * trace.lo)


def test_leaving_a_run_out_measures_the_reading_between_runs():
    """On a linear IDA curve every interior run is read back exactly from the others; on a curved one
    (demand ~ im^2) the error is the chord's, known in closed form."""
    assert leave_one_out([linear_trace()], ("PID-", "PFA-")) == {"PID-": (0.0, 0.0), "PFA-": (0.0, 0.0)}
    curved = Trace([(1.0, False, {"PID-1": 1.0}), (2.0, False, {"PID-1": 4.0}), (3.0, False, {"PID-1": 9.0}),
                    (4.0, True, {"PID-1": 0.1})], 3.0, 4.0)
    assert leave_one_out([curved], ("PID-",))["PID-"] == pytest.approx((0.25, 0.25))  # (1 + 9) / 2 = 5 against 4


def test_a_record_never_traced_up_to_a_stripe_has_no_demands_there():
    trace = hunt_and_fill(lambda im: (False, {"PID-1": im}), first=0.1, step=0.1, increment=0.0, max_runs=3)
    assert at_level(trace, 0.3)[0]["PID-1"] == pytest.approx(0.3) and at_level(trace, 0.31) is None
    assert at_level(Trace([(0.2, True, {"PID-1": 0.1})], 0.0, 0.2), 0.05) is None  # collapsed at its first run


def test_bad_arguments_are_named():
    with pytest.raises(ValueError, match="first = 0.0, step = 0.1"):
        hunt_and_fill(lambda im: (True, 0.0), first=0.0, step=0.1)


def test_a_yielding_buildings_ida_brackets_its_collapse(tmp_path, fmu_dir):
    """assess.run_ida_task on DampedShearBuilding1 (one storey, no post-yield stiffness, P-Delta: it
    collapses):
    the trace's bracket is confirmed by independent runs just below (standing) and at its top
    (collapsed); below collapse the drift ratio grows with the intensity; every run at most 6."""
    import json
    import math

    from pidamper import run
    from pidamper.assessment import assess
    from pidamper.assessment import demands
    from pidamper.assessment.ida import Trace
    from pidamper.forcing import Forcing

    study_file = tmp_path / "ida.toml"
    study_file.write_text("""
[study]
name = "ida"
[building]
storeys = 1
floor_m = 1.0e5
storey_k = 8.0e7
storey_height = 3.0
p_delta = 1
storey_Fy = 2.0e5
storey_b = 0.0
collapse_drift = 0.05
zeta_s = 0.02
fidelity = "damped"
[configurations.bare]
mu = 0.0
d = 100.0
[intensity]
measure = "PGA"
levels = [0.1, 0.2]
[damage_states]
DS1 = 0.01
[hazard]
k0 = 1e-3
k = 2.0
[suite]
generator = "kanai-tajimi"
count = 2
duration = 6.0
dt = 0.01
pga = 1.0
omega_g = 15.6
zeta_g = 0.6
""")
    study = assess.load(study_file)
    study.ida = {"first": 0.1, "step": 0.1, "increment": 0.1, "tolerance": 0.1, "max_runs": 6}
    record = study.records[0]
    row = assess.run_ida_task(assess.ida_tasks(study)[0])
    trace = Trace([tuple(r) for r in json.loads(row["runs"])], row["lo"], row["hi"])
    assert trace.collapsed and len(trace.runs) <= 6 and row["capacity"] == trace.capacity
    values = assess.start_values({**study.building, **study.configurations["bare"]})
    own = study.intensity(record)

    def collapses(im):  # the record and its free-vibration tail, as the IDA runs it
        times, ground = demands.with_tail(im / own * record.accel, record.dt, study.period)
        signal = Forcing("record", {}, table=(times, ground), target="a_g")
        return "collapsed" in run(values, signal, stop_time=round(times[-1], 6), output_interval=record.dt).meta

    assert collapses(trace.hi) and not collapses(trace.lo)
    curve = [(im, found["PID-1"]) for im, found in trace.curve()]
    assert all(b[1] >= a[1] for a, b in zip(curve, curve[1:])) and math.isfinite(curve[-1][1])


ELASTIC_STUDY = """
[study]
name = "elastic-ida"
[building]
storeys = 2
floor_m = 1.0e5
storey_k = 8.0e7
storey_height = 3.0
p_delta = 1
zeta_s = 0.02
fidelity = "damped"
[configurations.bare]
mu = 0.0
d = 100.0
[intensity]
measure = "Sa"
levels = [0.15, 0.3]
[damage_states]
DS1 = 0.001
[hazard]
k0 = 1e-3
k = 2.0
[ida]
first = 0.2
step = 0.2
max_runs = 3
stripes = "interpolate"
[suite]
generator = "kanai-tajimi"
count = 2
duration = 4.0
dt = 0.01
pga = 1.0
omega_g = 15.6
zeta_g = 0.6
"""


def test_interpolated_stripes_agree_with_runs_of_an_elastic_building(tmp_path, fmu_dir):
    """An elastic building (with P-Delta) answers in proportion to the record's scale: its IDA curve
    is straight, so the stripes read off it (between runs, and from (0, 0) below the first) agree
    with separate runs of each record scaled to the stripe (the same record and tail, run apart)."""
    from pidamper.assessment import assess, demands

    path = tmp_path / "elastic.toml"
    path.write_text(ELASTIC_STUDY)
    study = assess.load(path)
    assert study.ida["stripes"] == "interpolate"
    rows = assess.stripe_rows(study, assess.run_ida(study, tmp_path / "out", workers=1, progress=False))
    assert len(rows) == 2 * 2 and all(r["interpolated"] == 1 and r["collapsed"] == 0 for r in rows)
    values = assess.start_values({**study.building, **study.configurations["bare"]})
    for row in rows:
        record = study.records[row["record_index"]]
        direct = demands.run_demands(values, row["factor"] * record.accel, record.dt, study.period)
        for key in ("PID-1", "PID-2", "PFA-1", "PFA-2", "PFV-2"):
            assert row[key] == pytest.approx(direct[key], rel=1e-9), key
        assert row["factor"] == pytest.approx(row["level"] / study.intensity(record), rel=1e-15)


def test_a_hunt_that_cannot_reach_the_top_stripe_is_refused(tmp_path):
    from pidamper.assessment import assess

    path = tmp_path / "short.toml"
    path.write_text(ELASTIC_STUDY.replace("levels = [0.15, 0.3]", "levels = [0.15, 3.0]"))
    with pytest.raises(assess.StudyError, match=r"ida.max_runs = 3 .*reach 0.7 only"):
        assess.load(path)


def test_collapse_fragility_from_capacities_is_scipys_lognormal_mle():
    """Uncensored: scipy.stats.lognorm.fit (floc = 0) on the same capacities; censored (records
    that never collapsed): an independent maximisation of the censored likelihood (scipy's
    minimize on the (median, beta) form), and the censored median lies above the uncensored one."""
    from scipy import optimize, stats

    from pidamper.assessment.fragility import FragilityError, fit_capacities

    rng = np.random.default_rng(3)
    capacities = np.exp(rng.normal(np.log(1.2), 0.4, 30))
    fit = fit_capacities(capacities)
    s, _, scale = stats.lognorm.fit(capacities, floc=0.0)
    assert fit.theta == pytest.approx(scale, rel=1e-6) and fit.beta == pytest.approx(s, rel=1e-6)
    censored = [2.5, 2.5, 2.5]
    both = fit_capacities(capacities, censored)

    def nll(p):
        theta, beta = p
        return -(stats.lognorm.logpdf(capacities, beta, scale=theta).sum()
                 + stats.lognorm.logsf(censored, beta, scale=theta).sum())

    ref = optimize.minimize(nll, [1.0, 0.5], method="Powell", bounds=[(1e-3, 10.0), (1e-3, 5.0)],
                            options={"xtol": 1e-10, "ftol": 1e-13})
    assert both.theta == pytest.approx(ref.x[0], rel=1e-5) and both.beta == pytest.approx(ref.x[1], rel=1e-5)
    assert both.theta > fit.theta and both.censored == 3 and both.n == 33
    with pytest.raises(FragilityError, match="two distinct ones or more"):
        fit_capacities([1.0])


def test_p695_capacities_are_those_of_the_set_scaled_collectively():
    """A record scaled with the set to level L (factor L / median IM, as assess.tasks scales a FEMA
    P-695 set) reaches its own IDA capacity at L = capacity x median / its IM: the capacities the
    margin's S_CT is fitted to; the losses keep each record's own."""
    from types import SimpleNamespace

    from pidamper.assessment import assess

    ims, own = [1.0, 2.0, 4.0], [2.0, 2.0, 3.0]
    traces = [{"record_index": i, "configuration": "bare", "im_record": im, "capacity": c, "lo": 0.95 * c}
              for i, (im, c) in enumerate(zip(ims, own))]
    study = SimpleNamespace(configurations={"bare": {}}, levels=[1.0, 2.0], beta_m=0.0)
    collective = assess.ida_collapse(study, traces, collective=True)["bare"].capacities
    assert list(assess.ida_collapse(study, traces)["bare"].capacities) == own
    for im, c, level in zip(ims, own, collective):
        assert (level / np.median(ims)) * im == pytest.approx(c, rel=1e-15)  # its own Sa at that level
    assert list(collective) == pytest.approx([4.0, 2.0, 1.5])


def test_stripe_runs_take_the_ida_s_runs_where_they_fall_on_a_stripe(tmp_path, fmu_dir):
    """stripes = "run": at 0.2 (the hunt's first intensity) each record's stripe row is its IDA run,
    the same numbers a separate run of the stripe task gives (bit for bit) with no CPU of its own;
    at 0.3 (no IDA run there) the stripe is run."""
    from pidamper.assessment import assess

    path = tmp_path / "elastic.toml"
    path.write_text(ELASTIC_STUDY.replace('stripes = "interpolate"', 'stripes = "run"').replace(
        "levels = [0.15, 0.3]", "levels = [0.2, 0.3]"))
    study = assess.load(path)
    traces = assess.run_ida(study, tmp_path / "out", workers=1, progress=False)
    rows = assess.run_study(study, tmp_path / "out", workers=1, progress=False, traces=traces)
    tasks = {t["key"]: t for t in assess.tasks(study)}
    assert [r["level"] for r in rows] == [0.2, 0.3, 0.2, 0.3]
    for row in rows:
        taken = not math.isfinite(row["cpu_s"])
        assert taken == (row["level"] == 0.2)
        if taken:
            direct = assess.run_task(tasks[row["key"]])
            for key in ("drift_ratio", "floor_accel", "PID-1", "PID-2", "PFA-2", "RID-1", "collapsed", "t_end"):
                assert row[key] == direct[key], key
    ran = (tmp_path / "out" / "runs.csv").read_text().splitlines()
    assert len(ran) == 1 + 2  # the two records at 0.3 only


def test_interpolated_stripes_are_refused_beyond_their_leave_one_out_bound():
    """A curve bent between runs: the run at 0.4 read off its neighbours (0.006 for 0.008) is 25 %
    off, so a bound of 0.2 refuses the interpolation, naming ida.loo_limit and PID; 0.3 accepts."""
    from pidamper.assessment import assess

    runs = [[0.2, False, {"PID-1": 0.002, "PFA-1": 1.0}], [0.4, False, {"PID-1": 0.008, "PFA-1": 2.0}],
            [0.6, False, {"PID-1": 0.01, "PFA-1": 3.0}], [0.8, True, {"PID-1": 0.1, "PFA-1": 4.0}]]
    traces = [{"runs": runs, "lo": 0.6, "hi": 0.8}]

    class Study:
        source, ida = "study.toml", {"loo_limit": 0.2}

    with pytest.raises(assess.StudyError, match=r"ida\.loo_limit = 0\.2 is not allowed: .*read PID within 25\.0%"):
        assess.check_interpolation(Study, traces)
    Study.ida = {"loo_limit": 0.3}
    assess.check_interpolation(Study, traces)
