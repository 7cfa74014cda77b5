# The compiled build's bodies of _clist's sums (see _clist.py), inlined where a module cimports them:
# the lists' items read in place (borrowed, no per-item index check: the lengths are checked once),
# a float or complex item read from its object, anything else converted as Python would; the same
# products and additions in the same order as the plain bodies, so the same bits.
from cpython.object cimport PyObject
from cpython.list cimport PyList_GET_ITEM, PyList_GET_SIZE

cdef extern from "Python.h":
    ctypedef struct Py_complex:
        double real
        double imag
    ctypedef struct PyComplexObject:
        Py_complex cval
    bint PyFloat_CheckExact(PyObject *)
    bint PyComplex_CheckExact(PyObject *)
    double PyFloat_AS_DOUBLE(PyObject *)
    double PyFloat_AsDouble(PyObject *) except? -1.0
    Py_complex PyComplex_AsCComplex(PyObject *) except *


cdef inline double _real(PyObject *o) except? -1.0:
    """A float item's value; any other real number converted as arithmetic converts it (an int),
    anything else refused (TypeError)."""
    if PyFloat_CheckExact(o):
        return PyFloat_AS_DOUBLE(o)
    return PyFloat_AsDouble(o)


cdef inline Py_complex _converted(PyObject *o) except *:
    """Any item but a complex: converted as arithmetic converts it (a float x is (x, 0.0)), anything
    else refused (TypeError)."""
    return PyComplex_AsCComplex(o)


cdef inline int _lengths(list a, Py_ssize_t need) except -1:
    """Refuse None or a list shorter than `need` (as indexing it would)."""
    if a is None:
        raise TypeError("'NoneType' object is not subscriptable")
    if PyList_GET_SIZE(a) < need:
        raise IndexError("list index out of range")
    return 0


cdef inline double dot(list a, list b) except? -1.0:
    cdef Py_ssize_t k, n
    cdef double s = 0.0
    _lengths(a, 0)
    n = PyList_GET_SIZE(a)
    _lengths(b, n)
    for k in range(n):
        s += _real(PyList_GET_ITEM(a, k)) * _real(PyList_GET_ITEM(b, k))
    return s


cdef inline double weighted_real(list weight, list row, list eta) except? -1.0:
    cdef Py_ssize_t k, n
    cdef double s = 0.0, w
    cdef Py_complex v, e
    cdef PyObject *o
    _lengths(eta, 0)
    n = PyList_GET_SIZE(eta)
    _lengths(weight, n)
    _lengths(row, n)
    for k in range(n):
        w = _real(PyList_GET_ITEM(weight, k))
        o = PyList_GET_ITEM(row, k)
        v = (<PyComplexObject *>o).cval if PyComplex_CheckExact(o) else _converted(o)
        o = PyList_GET_ITEM(eta, k)
        e = (<PyComplexObject *>o).cval if PyComplex_CheckExact(o) else _converted(o)
        s += w * (v.real * e.real - v.imag * e.imag)
    return s


cdef inline double real_dot(list row, list eta) except? -1.0:
    cdef Py_ssize_t k, n
    cdef double s = 0.0
    cdef Py_complex v, e
    cdef PyObject *o
    _lengths(row, 0)
    n = PyList_GET_SIZE(row)
    _lengths(eta, n)
    for k in range(n):
        o = PyList_GET_ITEM(row, k)
        v = (<PyComplexObject *>o).cval if PyComplex_CheckExact(o) else _converted(o)
        o = PyList_GET_ITEM(eta, k)
        e = (<PyComplexObject *>o).cval if PyComplex_CheckExact(o) else _converted(o)
        s += v.real * e.real - v.imag * e.imag
    return s


cdef inline list real_dots(list row, list levels, Py_ssize_t lo, Py_ssize_t hi):
    # each sum on its own pass: the same sums, in the same order, as the plain body's single pass
    return [real_dot(row, levels[j]) for j in range(lo, hi)]


cdef inline double complex complex_dot(list w, x, Py_ssize_t offset, Py_ssize_t n) except *:
    cdef Py_ssize_t i
    cdef double sr = 0.0, si = 0.0, xi
    cdef Py_complex wi
    cdef PyObject *o
    cdef double complex s
    cdef list xs = x if type(x) is list else list(x)  # (a tuple of loads)
    if offset < 0 or n < 0:
        raise IndexError("list index out of range")
    _lengths(w, offset + n)
    _lengths(xs, n)
    for i in range(n):
        o = PyList_GET_ITEM(w, offset + i)
        wi = (<PyComplexObject *>o).cval if PyComplex_CheckExact(o) else _converted(o)
        xi = _real(PyList_GET_ITEM(xs, i))
        sr += wi.real * xi - wi.imag * 0.0  # (wi) (xi, 0.0) as CPython multiplies them
        si += wi.real * 0.0 + wi.imag * xi
    s.real = sr
    s.imag = si
    return s
