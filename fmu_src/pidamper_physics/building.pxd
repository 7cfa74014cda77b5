# Types for the compiled build of building.py (Cython, pure-Python mode): ShearBuilding as a typed
# class, so that the modules stepping it read its matrices and lists from C fields, and the modal
# sums it calls, cimported so that the compiled build calls them in C.
import cython

from .modal cimport _dot3, _matrix_sum


cdef class ShearBuilding:
    cdef public Py_ssize_t n
    cdef public double zeta
    cdef public list masses, stiffnesses, heights, geometric, net, K, omegas, shapes, C, zetas
    cdef public Py_ssize_t damping
    cdef public object rayleigh
