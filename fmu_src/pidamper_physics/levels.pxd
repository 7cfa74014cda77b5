# Types for the compiled build of levels.py (Cython, pure-Python mode): the linear level as a typed class
# (its segments and energy called in C from Damper's loop, their parameters in C doubles); the other
# levels stay Python subclasses.
import cython

from .level_model cimport LevelModel
from .segments cimport LinearParams, Flight, Stick, flight, stick


cdef class _Displacements(LevelModel):
    cdef public LinearParams consts


cdef class LinearModel(_Displacements):
    cpdef flight(self, x, v, y, u, fc, psi, T, always_bound=*)

    cpdef stick(self, x, v, side, fc, psi, T)

    cpdef energy(self, x, v, y, u)

    @cython.locals(p=LinearParams, L2=cython.double, L1=cython.double, ww2=cython.double)
    cpdef tuple observables(self, x, v, y, u, side, f, ground)


@cython.locals(M=cython.double, m=cython.double, w2=cython.double, w1=cython.double)
cpdef double _linear_energy(LinearParams p, double x, double v, double y, double u) except? -1.0
