# Types for the compiled build of modal.py (Cython, pure-Python mode): the per-mode loops of the
# closed form in C doubles and complex doubles.  Only +, -, * and .real on complex values are typed
# (they are CPython's operations to the bit: no contraction, -ffp-contract=off); divisions go
# through _quot, CPython's algorithm written out, and exp through cmath as in the plain build.
import cython

@cython.locals(k=cython.Py_ssize_t, z=cython.doublecomplex, a=cython.double, b=cython.double,
               el=cython.doublecomplex, em=cython.doublecomplex, ea=cython.double, h=cython.double,
               omc=cython.double, e0=cython.doublecomplex, c=cython.doublecomplex)
cpdef list _free(lams, eta0, shift, double tau)

@cython.locals(k=cython.Py_ssize_t, lam=cython.doublecomplex, e=cython.doublecomplex, c=cython.doublecomplex)
cpdef list _rates(lams, eta, shift)

@cython.locals(k=cython.Py_ssize_t, s=cython.double, w=cython.double, v=cython.doublecomplex,
               e=cython.doublecomplex)
cpdef double _weighted_real(weight, row, eta) except? -1.0

@cython.locals(k=cython.Py_ssize_t, s=cython.double, v=cython.doublecomplex, e=cython.doublecomplex)
cpdef double _real_dot(row, eta) except? -1.0

@cython.locals(k=cython.Py_ssize_t, s=cython.double, x=cython.double, y=cython.double)
cpdef double _dot_real(a, b) except? -1.0

@cython.locals(i=cython.Py_ssize_t, s=cython.doublecomplex)
cpdef double complex _dot(w, x, Py_ssize_t offset, Py_ssize_t n) except *

@cython.locals(ar=cython.double, ai=cython.double, br=cython.double, bi=cython.double, ratio=cython.double,
               denom=cython.double)
cpdef double complex _quot(double complex a, double complex b) except *
