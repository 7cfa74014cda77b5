# Types for the compiled build of modal.py (Cython, pure-Python mode): the per-mode loops of the
# closed form in C doubles and complex doubles.  Only +, -, * and .real on complex values are typed
# (they are CPython's operations to the bit: no contraction, -ffp-contract=off); divisions go
# through _quot, CPython's algorithm written out, exp through _exp, cmath's formula written out with
# libc's exp, sin and cos, and complex(re, im) through _ccomplex.parts.
import cython
from libc cimport math as _libm

from . cimport _ccomplex as _cx
from . cimport _clist as _cl

cdef double _INF

@cython.locals(a=cython.double, b=cython.double, el=cython.double)
cpdef double complex _exp(double complex z) except *

@cython.locals(a=cython.double, b=cython.double, e=cython.doublecomplex, em=cython.doublecomplex)
cpdef tuple exp_pair(double complex z)

@cython.locals(ea=cython.double, h=cython.double, omc=cython.double)
cdef double complex _expm1_near_zero(double a, double b) noexcept

@cython.locals(k=cython.Py_ssize_t, term=cython.doublecomplex, total=cython.doublecomplex)
cpdef double complex phi1(double complex w) except *

@cython.locals(a=cython.double, b=cython.double)
cpdef double complex _exp_lead(double complex z) except *

@cython.locals(w=cython.doublecomplex)
cpdef double complex _spread(double complex s, double complex lam, double tau, double complex es,
                             double complex el) except *

@cython.locals(a=cython.double, gap_p=cython.double, gap_m=cython.double, ga_p=cython.double, ga_m=cython.double,
               p_p=cython.double, p_m=cython.double, w=cython.double, j=cython.Py_ssize_t, q=cython.double,
               steady=cython.double, add_p=cython.double, add_m=cython.double, column=list)
cdef int _forced_bounds(list columns, Py_ssize_t k, double complex lam, double complex gp, double complex gm,
                        double om, list pk, double T, Py_ssize_t orders) except -1

@cython.locals(k=cython.Py_ssize_t, z=cython.doublecomplex, a=cython.double, b=cython.double,
               el=cython.doublecomplex, em=cython.doublecomplex, ea=cython.double, h=cython.double,
               omc=cython.double, e0=cython.doublecomplex, c=cython.doublecomplex)
cpdef list _free(list lams, list eta0, list shift, double tau)

@cython.locals(k=cython.Py_ssize_t, x=cython.doublecomplex, g=cython.doublecomplex)
cpdef list _plus_scaled(list d, list gamma, double s)

@cython.locals(k=cython.Py_ssize_t, lam=cython.doublecomplex, e=cython.doublecomplex, c=cython.doublecomplex)
cpdef list _rates(list lams, list eta, list shift)

cpdef double _weighted_real(list weight, list row, list eta) except? -1.0

cpdef double _real_dot(list row, list eta) except? -1.0

cpdef list _real_dots(list row, list levels, Py_ssize_t lo, Py_ssize_t hi)

cpdef double _dot_real(list a, list b) except? -1.0

@cython.locals(k=cython.Py_ssize_t, s=cython.double, x=cython.double)
cpdef double _total(list a) except? -1.0

@cython.locals(k=cython.Py_ssize_t, s=cython.double, x=cython.double, y=cython.double, z=cython.double)
cpdef double _dot3(list a, b, c) except? -1.0

@cython.locals(k=cython.Py_ssize_t, s=cython.double, x=cython.double, y=cython.double, z=cython.double)
cpdef double _dot_change(list a, x1, x0) except? -1.0

@cython.locals(i=cython.Py_ssize_t, j=cython.Py_ssize_t, s=cython.double, a=list, b=list, p=cython.double,
               q=cython.double, r=cython.double, w=cython.double)
cpdef double _matrix_sum(list A, x, B, v, Py_ssize_t n) except? -1.0

cpdef double complex _dot(list w, x, Py_ssize_t offset, Py_ssize_t n) except *

@cython.locals(ar=cython.double, ai=cython.double, br=cython.double, bi=cython.double, ratio=cython.double,
               denom=cython.double)
cpdef double complex _quot(double complex a, double complex b) except *


cdef class Modes:
    cdef public Py_ssize_t n
    cdef public list lam, weight, V, W, secular
    cdef public double fastest, growth_rate
    cdef dict _weighted, _complex, _difference, _drifts, _floors, _powers

    cpdef list weighted_complex(self, Py_ssize_t i)
    cpdef list weighted_difference(self, Py_ssize_t i, Py_ssize_t j)
    cpdef list weighted_drifts(self, Py_ssize_t n)
    cpdef list weighted_floors(self, Py_ssize_t n)
    cpdef list powers(self, Py_ssize_t orders)
    cpdef list weighted(self, Py_ssize_t i)


cdef class Motion:
    cdef public Modes modes
    cdef public list eta0, coef, steady, gp, gm, gamma, beta, secular
    cdef public double om, psi
    cdef public bint forced
    cdef public object _columns, _start
    cdef double _at, _levels_tau
    cdef list _eta, _levels_last

    @cython.locals(n=cython.Py_ssize_t, k=cython.Py_ssize_t, lams=list, w=list, lam=cython.doublecomplex,
                   eta0=cython.doublecomplex, c=cython.doublecomplex, gamma=cython.doublecomplex,
                   eip=cython.doublecomplex)
    cpdef _project(self, Modes modes, z0, b, f, double psi)

    @cython.locals(k=cython.Py_ssize_t, lams=list, gp=list, gm=list, sp=cython.doublecomplex,
                   e_plus=cython.doublecomplex, e_minus=cython.doublecomplex, lam=cython.doublecomplex,
                   el=cython.doublecomplex, o=cython.doublecomplex, g=cython.doublecomplex, h=cython.doublecomplex)
    cpdef list modal(self, double tau)

    @cython.locals(out=list, weight=list, m=Modes)
    cpdef list state(self, double tau, rows=*)

    @cython.locals(m=Modes, out=dict, levels=list, lo=cython.Py_ssize_t, hi=cython.Py_ssize_t, j=cython.Py_ssize_t,
                   row=list)
    cpdef dict derivatives(self, double tau, dict rows, Py_ssize_t orders=*)

    @cython.locals(m=Modes, i=cython.Py_ssize_t, levels=list, out=list)
    cpdef list component_derivatives(self, double tau, Py_ssize_t first, Py_ssize_t last, Py_ssize_t orders)

    @cython.locals(levels=list)
    cpdef list _levels_at(self, double tau, Py_ssize_t orders)

    @cython.locals(m=Modes, lams=list, levels=list, d=list, j=cython.Py_ssize_t, s=cython.double, c=cython.double)
    cpdef list _levels(self, double tau, Py_ssize_t orders)

    @cython.locals(a=cython.double)
    cpdef tuple load(self, double tau)

    @cython.locals(m=Modes, j=cython.Py_ssize_t, columns=list)
    cpdef list bounds(self, double T, Py_ssize_t orders=*, rows=*, vectors=*, weighted=*, Py_ssize_t first=*)

    @cython.locals(m=Modes)
    cpdef list rest(self, rows=*, vectors=*)

    @cython.locals(m=Modes, lams=list, count=cython.Py_ssize_t, k=cython.Py_ssize_t, j=cython.Py_ssize_t,
                   lam=cython.doublecomplex, a=cython.double, size=cython.double, grow=cython.double, powers=list,
                   pk=list, p=cython.double, columns=list)
    cpdef list _columns_over(self, double T, Py_ssize_t orders)
