# Types for the compiled build of modal_segments.py (Cython, pure-Python mode): the free flight's
# guards as a typed class.
import cython

from .modal cimport Motion, _dot_real


cdef class ModalFlight:
    cdef public Motion motion
    cdef public object K, C, b, gap
    cdef public double f, om, D, growth
    cdef public tuple bounds, noise
    cdef public bint clear

    @cython.locals(rx=cython.double, ry=cython.double, x=cython.double, y=cython.double, v=cython.double,
                   u=cython.double, Bx=list, By=list, Bv=list, Bu=list, zmax=cython.double, size=cython.double,
                   n0=cython.double)
    cpdef _guard(self, list B, list rest, list start, double T, double D)

    @cython.locals(x=cython.double, y=cython.double, v=cython.double, u=cython.double)
    cpdef tuple positions(self, double tau)

    @cython.locals(x=cython.double, y=cython.double, v=cython.double, u=cython.double, g=cython.double,
                   dg=cython.double, D=cython.double)
    cpdef tuple values(self, double tau)
