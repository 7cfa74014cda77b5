# Types for the compiled build of stepping.py (Cython, pure-Python mode): EventDriven as a typed
# class, so the event loop reads the clock and the mode from C fields rather than an instance dict.
# Fields a caller or a saved state may give any number type (t, t_lo, mode, side, fresh, impacts)
# stay Python objects, so both builds keep what they were given; the loop's own locals are C doubles.
import cython

from .events cimport classify, locate, resolution_speed


cpdef bint same_bits(double a, double b)

@cython.locals(i=cython.Py_ssize_t)
cpdef bint same_floats(a, b) except -1


cdef class EventDriven:
    cdef dict __dict__  # models keep their own attributes (and tests may replace a method on an instance)
    cdef public object x, v, y, u  # the state a segment-free flight starts from (a model's own: Damper's)
    cdef public object t, t_lo, mode, side, fresh, impacts, pieces, max_pieces, _coaster
    cdef public double _max_span, _clearance
    cdef public bint _may_coast, _passes_through, still, halted

    @cython.locals(cap=cython.double, pieces=cython.Py_ssize_t, horizon=cython.double, span=cython.double,
                   tau=cython.double, guard=cython.Py_ssize_t, rest=cython.bint, still=cython.bint)
    cpdef _run(self, t_end, loads, observe=*)

    cpdef _resting(self, loads)

    cpdef _segment(self, loads, double span)

    cpdef _move(self, seg, double tau, t_end, loads, observe)

    cpdef _coast(self, state, double tau, t_end)

    @cython.locals(t=cython.double, s=cython.double, b=cython.double, lo=cython.double, t_new=cython.double,
                   end=cython.double)
    cpdef tuple _tick(self, double tau, t_end)
