# Types for the compiled build of modal_segments.py (Cython, pure-Python mode): the free flight's
# guards as a typed class.
import cython

from .modal cimport Motion, _dot_real
from .peaks cimport Piece


cdef class ModalFlight:
    cdef public Motion motion
    cdef public object K, C, b, gap
    cdef public double f, om, D, growth
    cdef public tuple bounds, noise
    cdef public bint clear

    @cython.locals(rx=cython.double, ry=cython.double, x=cython.double, y=cython.double, v=cython.double,
                   u=cython.double, Bx=list, By=list, Bv=list, Bu=list, zmax=cython.double, size=cython.double,
                   n0=cython.double, tol=cython.double, x0=cython.double, x1=cython.double, x2=cython.double,
                   x3=cython.double, x4=cython.double, y0=cython.double, y1=cython.double, y2=cython.double,
                   y3=cython.double, y4=cython.double, v0=cython.double, v1=cython.double, v2=cython.double,
                   u0=cython.double, u1=cython.double, u2=cython.double)
    cpdef _guard(self, list B, list rest, list start, double T, double D)

    @cython.locals(x=cython.double, y=cython.double, v=cython.double, u=cython.double)
    cpdef tuple positions(self, double tau)

    @cython.locals(x=cython.double, y=cython.double, v=cython.double, u=cython.double, g=cython.double,
                   dg=cython.double, D=cython.double)
    cpdef tuple values(self, double tau)


@cython.locals(s=cython.double, i=cython.Py_ssize_t, a=cython.double, b=cython.double, c=cython.double,
               d=cython.double)
cpdef double _pair_dot(p, x, Py_ssize_t ox, q, y, Py_ssize_t oy, Py_ssize_t n) except? -1.0

@cython.locals(s=cython.double, i=cython.Py_ssize_t, a=cython.double, b=cython.double, c=cython.double,
               d=cython.double)
cpdef double _pair_dot_abs(p, z, q, Py_ssize_t n) except? -1.0

@cython.locals(s=cython.doublecomplex, i=cython.Py_ssize_t, a=cython.double, b=cython.doublecomplex,
               c=cython.double, d=cython.doublecomplex)
cpdef double complex _mode_row(p, q, V, Py_ssize_t n, Py_ssize_t k) except *

@cython.locals(rows=cython.Py_ssize_t, r=cython.Py_ssize_t, acc=list, jerk=list, snap=list)
cpdef tuple chain(z, Py_ssize_t n, K, C, b, Py_ssize_t j, double a, double om, double s, double c, bint full=*,
                  Py_ssize_t first=*)


cdef class ModalStick:
    cdef public Motion motion
    cdef public Py_ssize_t j, n
    cdef public double sgn, d, a, om, k0, growth, _tau
    cdef public object kx, kv, K, C, b
    cdef public tuple bounds, noise
    cdef public bint clear
    cdef public list _z, start_floors, z0

    cpdef list state(self, double tau)

    cpdef list floors_at(self, double tau)

    @cython.locals(z=list, j=cython.Py_ssize_t, n=cython.Py_ssize_t)
    cpdef list others(self, double tau)

    @cython.locals(z=list, x=cython.double, v=cython.double)
    cpdef tuple positions(self, double tau)

    cpdef tuple _chain(self, double tau)

    cpdef take_peaks(self, peaks, double tau, ground, guards=*)

    @cython.locals(x=list, v=list, acc=list, s=cython.double, c=cython.double, sg=cython.double, a=cython.double,
                   om=cython.double, n=cython.Py_ssize_t)
    cpdef tuple values(self, double tau)

    @cython.locals(x=list, v=list, acc=list, jerk=list, snap=list, s=cython.double, c=cython.double,
                   sg=cython.double, a=cython.double, n=cython.Py_ssize_t)
    cpdef tuple derivs(self, double tau, Py_ssize_t i=*)


cdef class ModalPiece(Piece):
    cdef public object seg, guards
    cdef public Py_ssize_t n, j, floors
    cdef public double a, tau

    cpdef tuple start(self)

    cpdef tuple first(self)

    @cython.locals(motion=Motion, drifts=list)
    cpdef tuple bounds(self, Py_ssize_t floor_order, Py_ssize_t drift_order)

    cpdef dict derivatives(self, double s, dict floors)
