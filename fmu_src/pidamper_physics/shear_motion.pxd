# Types for the compiled build of shear_motion.py (Cython, pure-Python mode): the sums of the
# elastic building's hot loops in C doubles, and ShearPiece as a typed class whose modes step in C
# (ShearMotion stays a Python class).  Each sum starts from 0.0 and adds left to right, as CPython's
# sum(); no FMA (the build's flags).
import cython

from .oscillator cimport DampedOscillator


@cython.locals(out=list, k=cython.Py_ssize_t, r=cython.Py_ssize_t, total=cython.double, a=cython.double,
               b=cython.double)
cpdef list combine(phi, q, Py_ssize_t n)

@cython.locals(out=list, k=cython.Py_ssize_t, j=cython.Py_ssize_t, total=cython.double, c=cython.double,
               vj=cython.double, kk=cython.double, xj=cython.double, f=cython.double, mk=cython.double)
cpdef list accelerations(forces, K, C, m, x, v, Py_ssize_t n)

@cython.locals(out=list, k=cython.Py_ssize_t, r=cython.Py_ssize_t, total=cython.double, p=cython.double,
               f=cython.double, mk=cython.double)
cpdef list modal_loads(phi, m, forces, double ground, Py_ssize_t n)

@cython.locals(floors=list, drifts=list, bounds=list, k=cython.Py_ssize_t, j=cython.Py_ssize_t,
               r=cython.Py_ssize_t, total=cython.double, p=cython.double, a=cython.double, w=cython.double)
cpdef tuple piece_bounds(phi, amps, powers, Py_ssize_t n, Py_ssize_t floor_order, Py_ssize_t drift_order)

@cython.locals(out=list, j=cython.Py_ssize_t, r=cython.Py_ssize_t, total=cython.double, p=cython.double,
               d=cython.double)
cpdef list floor_derivatives(row, q, Py_ssize_t lo, Py_ssize_t hi)


cdef class ShearPiece:
    cdef public object motion
    cdef public double tau

    @cython.locals(out=list, mode=DampedOscillator, q=cython.double, q1=cython.double, c=cython.double,
                   k=cython.double, levels=list)
    cpdef list _modal(self, double s, Py_ssize_t orders)
