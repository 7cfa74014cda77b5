"""Hunt and fill (Vamvatsikos & Cornell 2002) against synthetic IDAs whose collapse intensity is
known: it is bracketed to the stated tolerance within 10 runs, the curve below it is filled, a
record that never collapses gets no capacity."""
import numpy as np
import pytest

from pidamper.assessment.ida import hunt_and_fill


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


def test_bad_arguments_are_named():
    with pytest.raises(ValueError, match="first = 0.0, step = 0.1"):
        hunt_and_fill(lambda im: (True, 0.0), first=0.0, step=0.1)
