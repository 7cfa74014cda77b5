# Types for the compiled build of peaks.py (Cython, pure-Python mode): the running maxima as a typed
# class, the certification's cubics in C doubles.
import cython

cdef double REL, _TINY, _SURE
cdef Py_ssize_t _MAX_POINTS

@cython.locals(best=cython.double, sg=cython.double, c0=cython.double, c1=cython.double, c2=cython.double,
               top=cython.double, end=cython.double, disc=cython.double, s=cython.double)
cdef double _cubic_max(double f, double f1, double f2, double b3, double length) except? -1.0

@cython.locals(lo=cython.double, hi=cython.double, f=cython.double, f1=cython.double, f2=cython.double,
               s=cython.double)
cdef double _next(tuple ya, tuple yb, double length) except? -1.0


cdef class Piece:
    cpdef tuple start(self)
    cpdef tuple first(self)
    cpdef tuple bounds(self, Py_ssize_t floor_order, Py_ssize_t drift_order)
    cpdef dict derivatives(self, double s, dict floors)


cdef class Peaks:
    cdef public Py_ssize_t n
    cdef public list inv_h, drift, velocity, acceleration
    cdef public double v_ground
    cdef tuple _begun

    @cython.locals(n=cython.Py_ssize_t, k=cython.Py_ssize_t, i=cython.Py_ssize_t, ih=list, vg=cython.double,
                   h=cython.double, active=list, values=list, q=tuple, y=tuple, xk=cython.double, vk=cython.double,
                   ak=cython.double, jk=cython.double, sk=cython.double, xb=cython.double, vb=cython.double,
                   ab=cython.double, bound=cython.double)
    cpdef take(self, Piece piece, double tau, double a_g)

    @cython.locals(n=cython.Py_ssize_t, k=cython.Py_ssize_t, ih=list, vg=cython.double, drift=list, velocity=list,
                   acceleration=list, below=cython.bint, xb=cython.double, h=cython.double, xk=cython.double,
                   vk=cython.double, ak=cython.double, d=cython.double, u=cython.double, w=cython.double,
                   slope=cython.double, curve=cython.double, end=cython.double, b=list, db=list, bk=list,
                   more=tuple, vb=cython.double, half=cython.double, rate=cython.double, begun=tuple)
    cdef bint _stays_below(self, Piece piece, double tau, double a_g) except -1

    @cython.locals(top=list, old=cython.double)
    cdef _raise(self, Py_ssize_t kind, Py_ssize_t k, double f)

    @cython.locals(top=list, value=cython.double)
    cdef double _top(self, Py_ssize_t kind, Py_ssize_t k) except? -1.0

    @cython.locals(need=dict, ih=list, vg=cython.double, out=list, q=tuple, kind=cython.Py_ssize_t,
                   k=cython.Py_ssize_t, lo=cython.Py_ssize_t, ll=cython.Py_ssize_t, hi=cython.Py_ssize_t,
                   h=cython.double, f=cython.double, f1=cython.double, f2=cython.double, dk=list, dl=list,
                   u0=cython.double, u1=cython.double, u2=cython.double, u3=cython.double, u4=cython.double,
                   l0=cython.double, l1=cython.double, l2=cython.double)
    cpdef list _values(self, Piece piece, double s, double a_g, list active, dict need)

    cpdef dict _need(self, list active)

    @cython.locals(a=cython.double, b=cython.double, length=cython.double, worst=cython.Py_ssize_t, fb=list,
                   need=dict, kept=list)
    cpdef _scan(self, Piece piece, list active, list fa, double tau, double a_g)

    @cython.locals(kept=list, kept_values=list, i=cython.Py_ssize_t, q=tuple, y=tuple, b3=cython.double,
                   top=cython.double, f=cython.double, f1=cython.double, f2=cython.double)
    cpdef tuple _open(self, list active, list values, double rest)

    @cython.locals(worst=cython.Py_ssize_t, excess=cython.double, i=cython.Py_ssize_t, q=tuple, y=tuple,
                   yb=tuple, b3=cython.double, top=cython.double, f=cython.double, f1=cython.double,
                   f2=cython.double, over=cython.double)
    cpdef Py_ssize_t _worst(self, list active, list fa, list fb, double length) except? -2
