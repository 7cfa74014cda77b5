# The compiled build's body of _ccomplex.parts (see _ccomplex.py): the C complex (re, im), inlined
# where a module cimports it; the same bits as CPython's complex(re, im), signed zeros included.
cdef inline double complex parts(double re, double im) noexcept:
    cdef double complex z
    z.real = re
    z.imag = im
    return z
