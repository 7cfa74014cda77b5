# Types for the compiled build of levels.py (Cython, pure-Python mode): the linear level's energy,
# read at every piece, in C doubles (the level classes stay Python classes).
import cython

from .segments cimport LinearParams


@cython.locals(M=cython.double, m=cython.double, w2=cython.double, w1=cython.double)
cpdef double _linear_energy(LinearParams p, double x, double v, double y, double u) except? -1.0
