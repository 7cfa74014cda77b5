# Types for the compiled build of shear_motion.py (Cython, pure-Python mode): the sums of the
# elastic building's hot loops in C doubles, and ShearPiece as a typed class whose modes step in C
# (ShearMotion stays a Python class).  Each sum starts from 0.0 and adds left to right, as CPython's
# sum(); no FMA (the build's flags).
import cython

from .building cimport ShearBuilding
from .modal cimport _matrix_sum
from .oscillator cimport DampedOscillator
from .peaks cimport Peaks, Piece


@cython.locals(out=list, row=list, k=cython.Py_ssize_t, r=cython.Py_ssize_t, total=cython.double,
               a=cython.double, b=cython.double)
cpdef list combine(list phi, q, Py_ssize_t n)

@cython.locals(out=list, row=list, k=cython.Py_ssize_t, r=cython.Py_ssize_t, total=cython.double, p=cython.double,
               mk=cython.double, xk=cython.double)
cpdef list project(list phi, m, x, Py_ssize_t n)

@cython.locals(out=list, k=cython.Py_ssize_t, j=cython.Py_ssize_t, total=cython.double, c=cython.double,
               vj=cython.double, kk=cython.double, xj=cython.double, f=cython.double, mk=cython.double)
cpdef list accelerations(forces, K, C, m, x, v, Py_ssize_t n)

@cython.locals(r=cython.Py_ssize_t, total=cython.double, p=cython.double, a=cython.double, b=cython.double)
cpdef double load_work(list loads, list q0, list q1, Py_ssize_t n) except? -1.0

@cython.locals(out=list, k=cython.Py_ssize_t, r=cython.Py_ssize_t, total=cython.double, p=cython.double,
               f=cython.double, mk=cython.double)
cpdef list modal_loads(phi, m, forces, double ground, Py_ssize_t n)

@cython.locals(floors=list, drifts=list, bounds=list, row=list, below=list, w_r=list, k=cython.Py_ssize_t,
               j=cython.Py_ssize_t, r=cython.Py_ssize_t, total=cython.double, p=cython.double, a=cython.double,
               w=cython.double)
cpdef tuple piece_bounds(list phi, list amps, list powers, Py_ssize_t n, Py_ssize_t floor_order,
                         Py_ssize_t drift_order)

@cython.locals(out=list, j=cython.Py_ssize_t, r=cython.Py_ssize_t, total=cython.double, p=cython.double,
               d=cython.double)
cpdef list floor_derivatives(row, q, Py_ssize_t lo, Py_ssize_t hi)


@cython.locals(phi=list, x=list, v=list, out=list, heights=list, stiffnesses=list, net=list, masses=list,
               springs=list, k=cython.Py_ssize_t, kinetic=cython.double, strain=cython.double, xk=cython.double,
               vk=cython.double, mk=cython.double, nk=cython.double, hk=cython.double, sk=cython.double,
               d=cython.double, energy=cython.double)
cpdef list elastic_observables(ShearBuilding b, list q, list qd, forces, Peaks peaks, double energy0, double work_in, Py_ssize_t n)


cdef class ShearMotion


cdef class ShearPiece(Piece):
    cdef public ShearMotion motion
    cdef public double tau

    cpdef tuple start(self)

    cpdef dict derivatives(self, double s, dict floors)

    @cython.locals(out=list, mode=DampedOscillator, q=cython.double, q1=cython.double, c=cython.double,
                   k=cython.double, levels=list)
    cpdef list _modal(self, double s, Py_ssize_t orders)

    @cython.locals(q0=list, q1=list, q2=list, mode=DampedOscillator, q=cython.double, qd=cython.double,
                   c=cython.double, k=cython.double)
    cpdef tuple first(self)

    @cython.locals(m=ShearMotion, mode=DampedOscillator, amps=list)
    cpdef tuple bounds(self, Py_ssize_t floor_order, Py_ssize_t drift_order)


cdef class ShearMotion:
    cdef public ShearBuilding b
    cdef public Py_ssize_t n
    cdef public double t, work_in, energy0
    cdef public list q, qd, modes, powers
    cdef public Peaks peaks
    cdef public bint still

    @cython.locals(q=list, qd=list, r=cython.Py_ssize_t, mode=DampedOscillator)
    cpdef _free(self, double tau, list loads, double ground)

    @cython.locals(b=ShearBuilding, n=cython.Py_ssize_t, phi=list, m=list, loads=list, t=cython.double, q0=list,
                   r=cython.Py_ssize_t, before=cython.double)
    cpdef advance(self, t_end, forces, ground=*, impulses=*)
