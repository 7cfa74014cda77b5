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
cpdef tuple chain(z, Py_ssize_t n, K, C, b, Py_ssize_t j, double a, double om, double s, double c, bint full=*)
