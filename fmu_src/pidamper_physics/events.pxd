# Types for the compiled build of events.py (Cython, pure-Python mode): the location loop in C doubles.
import cython
from libc cimport math as _libm

cdef double _INF

@cython.locals(root=cython.double)
cpdef double safe_step(double g, double g1, double b2) except? -1.0

cpdef tuple classify(double g1, double g2, double g3, double vres, double n2, double n3)

cpdef double resolution_speed(double g2, double n0, double n1, double n2) except? -1.0

@cython.locals(b2=cython.double, b3=cython.double, b4=cython.double)
cpdef double departure_step(Py_ssize_t order, double dk, double vres, tuple bounds) except? -1.0

@cython.locals(base=tuple, base0=cython.double, growth=cython.double, b2=cython.double, tau=cython.double,
               step=cython.double, near=cython.Py_ssize_t, n0=cython.double, i=cython.Py_ssize_t,
               g=cython.double, g1=cython.double, root=cython.double, s=cython.double, nxt=cython.double,
               scale=cython.double, away=cython.double, passes=cython.Py_ssize_t)
cpdef locate(seg, double tau_end, bint fresh=*)

@cython.locals(g=cython.double, g1=cython.double, g2=cython.double, g3=cython.double, n1=cython.double,
               n2=cython.double, n3=cython.double, vres=cython.double, order=cython.Py_ssize_t, dk=cython.double)
cpdef tuple _near_zero(seg, Py_ssize_t i, double tau, double tau_end, double n0, tuple base, double scale,
                       bint fresh)

@cython.locals(nxt=cython.double)
cpdef double _newton(seg, Py_ssize_t i, double tau, double g, double g1) except? -1.0
