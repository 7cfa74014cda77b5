# Types for the compiled build of storeys.py (Cython, pure-Python mode): the storey laws and the
# storeys' hysteretic state as typed classes, their per-storey arithmetic in C doubles.
import cython


cdef class Storeys:
    cdef public list k, Fy, geometric, flat, b, reach, yields
    cdef public Py_ssize_t n

    cpdef double tangent(self, Py_ssize_t i, long s) except? -1.0
    cpdef double offset(self, Py_ssize_t i, long s, double dp) except? -1.0

    @cython.locals(k=cython.double, b=cython.double)
    cpdef double force(self, Py_ssize_t i, double drift, double dp) except? -1.0

    @cython.locals(k=cython.double, b=cython.double, e=cython.double)
    cpdef double strain(self, Py_ssize_t i, double drift, double dp) except? -1.0


cdef class Hysteresis:
    cdef public Storeys law
    cdef public list heights, regime, dp
    cdef public double theta_c, w, hysteretic, collapse_time
    cdef public Py_ssize_t n
    cdef public object events, collapsed, collapse_reason, log, version
    cdef public tuple _guards

    cpdef list guards(self)

    @cython.locals(law=Storeys, n=cython.Py_ssize_t, regime=list, dp=list, c=list, i=cython.Py_ssize_t)
    cpdef list held(self)

    @cython.locals(law=Storeys, n=cython.Py_ssize_t, regime=list, dp=list, f=list, i=cython.Py_ssize_t)
    cpdef list restoring(self, list drifts)

    @cython.locals(s=cython.long)
    cpdef double plastic(self, Py_ssize_t i, double drift) except? -1.0

    @cython.locals(i=cython.Py_ssize_t)
    cpdef list forces(self, list drifts)

    @cython.locals(i=cython.Py_ssize_t)
    cpdef list zero_force_drifts(self, list drifts)

    @cython.locals(law=Storeys, e=cython.double, i=cython.Py_ssize_t, d=cython.double)
    cpdef double strain(self, list drifts) except? -1.0

    @cython.locals(law=Storeys, e=cython.double, regime=list, i=cython.Py_ssize_t, s=cython.long)
    cpdef double piece(self, list d0, list d1) except? -1.0
