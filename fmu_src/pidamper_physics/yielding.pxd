# Types for the compiled build of yielding.py (Cython, pure-Python mode): the storeys' guards over a
# piece as a typed class, its loops in C doubles.
import cython

from .modal cimport Modes, Motion, _dot3
from .peaks cimport Peaks, Piece
from .stepping cimport same_bits, same_floats
from .storeys cimport Hysteresis


cdef class StoreyGuards:
    cdef public Motion motion
    cdef public list guards
    cdef public tuple bounds, noise
    cdef public double growth
    cdef public bint clear
    cdef public Py_ssize_t n, first, last, orders
    cdef public list floors, drift_bounds
    cdef public double span

    @cython.locals(modes=Modes)
    cpdef _start(self, list guards, Motion motion, double T, Py_ssize_t n, Py_ssize_t orders)

    @cython.locals(b2=cython.double, b3=cython.double, b4=cython.double, n0=cython.double, n1=cython.double,
                   n2=cython.double, n3=cython.double, kept=list, i=cython.Py_ssize_t, order=cython.Py_ssize_t,
                   coef=cython.double, offset=cython.double, c=cython.double, di=list, bi=list, own=cython.double,
                   least=cython.double, d0=cython.double, d1=cython.double, d2=cython.double, e1=cython.double,
                   e2=cython.double, e3=cython.double, e4=cython.double, tol=cython.double, guard=tuple,
                   first=cython.Py_ssize_t, last=cython.Py_ssize_t, orders=cython.Py_ssize_t)
    cpdef _keep(self, guards, list bd, list start, double T, double growth)

    @cython.locals(lo=cython.Py_ssize_t, floors=list)
    cpdef list _drifts(self, double tau, Py_ssize_t orders, Py_ssize_t first=*, last=*)

    @cython.locals(d=list, out=list, guard=tuple, i=cython.Py_ssize_t, order=cython.Py_ssize_t, coef=cython.double,
                   offset=cython.double, di=list, first=cython.Py_ssize_t)
    cpdef list values(self, double tau)

    @cython.locals(guard=tuple, i=cython.Py_ssize_t, order=cython.Py_ssize_t, coef=cython.double,
                   offset=cython.double, di=list)
    cpdef tuple guard(self, double tau, Py_ssize_t index)

    @cython.locals(guard=tuple, i=cython.Py_ssize_t, order=cython.Py_ssize_t, coef=cython.double,
                   offset=cython.double, di=list)
    cpdef tuple derivs(self, double tau, Py_ssize_t index)



cdef class RegimePiece(Piece):
    cdef public Motion motion
    cdef public Py_ssize_t n
    cdef public double tau
    cdef public StoreyGuards guards

    @cython.locals(d=list, n=cython.Py_ssize_t, k=cython.Py_ssize_t)
    cpdef tuple start(self)

    @cython.locals(d=list, n=cython.Py_ssize_t, k=cython.Py_ssize_t)
    cpdef tuple first(self)

    @cython.locals(motion=Motion, n=cython.Py_ssize_t, tau=cython.double, guards=StoreyGuards, drifts=list)
    cpdef tuple bounds(self, Py_ssize_t floor_order, Py_ssize_t drift_order)

    cpdef dict derivatives(self, double s, dict floors)


cdef class YieldingMotion:
    cdef public object b, frozen, track, on_collapse
    cdef public Py_ssize_t n, pieces
    cdef public double t, work_in, viscous, energy0, _max_span
    cdef public list x, v, _c
    cdef public Hysteresis storeys
    cdef public bint fresh
    cdef public Peaks peaks
    cdef public dict _systems
    cdef public tuple _regime, _held, _booked, _restored, _dampings

    @cython.locals(booked=tuple)
    cpdef tuple _booking(self)

    @cython.locals(booked=tuple)
    cpdef list _drifts_now(self)

    @cython.locals(booked=tuple, kept=tuple, C=list, n=cython.Py_ssize_t, v=list, r=list, out=list,
                   i=cython.Py_ssize_t, j=cython.Py_ssize_t, row=list, damping=cython.double)
    cpdef list _restoring(self)

    @cython.locals(span=cython.double, tau=cython.double, motion=Motion, guards=StoreyGuards, event=tuple)
    cpdef _run(self, double t_stop, forces, double ground)

    @cython.locals(held=tuple)
    cpdef list _loads(self, forces, double ground)

    @cython.locals(n=cython.Py_ssize_t, booked=tuple, x0=list, x1=list, d0=list, d1=list, e0=cython.double,
                   e1=cython.double, z=list, work=cython.double, masses=list, k=cython.Py_ssize_t,
                   hysteretic=cython.double)
    cpdef _move(self, Motion motion, double tau, forces, double ground, StoreyGuards guards)

@cython.locals(out=list, k=cython.Py_ssize_t, j=cython.Py_ssize_t, a=list, b=list)
cpdef list _differences(list d, Py_ssize_t first, Py_ssize_t orders)

