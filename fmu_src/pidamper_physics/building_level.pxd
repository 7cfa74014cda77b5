# Types for the compiled build of building_level.py (Cython, pure-Python mode): the modal sums it
# calls, cimported so that the compiled build calls them in C, and its outputs' loops in C doubles;
# its classes stay Python classes.
import cython

from .building cimport ShearBuilding
from .modal cimport _dot3, _dot_change, _dot_real, _matrix_sum, _total
from .peaks cimport Peaks


@cython.locals(out=list, i=cython.Py_ssize_t, load=cython.double)
cpdef list _relative_accelerations(list K, list C, list loads, list q, list dq, Py_ssize_t n)

@cython.locals(xs=list, vs=list, k=cython.Py_ssize_t)
cpdef tuple _all_floors(list others, Py_ssize_t j, Py_ssize_t n, x, v)

@cython.locals(out=list, drifts=list, ratios=list, k=cython.Py_ssize_t, a=cython.double, d=cython.double,
               h=cython.double)
cpdef tuple _floor_table(list xs, list acc, double ground, list heights, Py_ssize_t n)

@cython.locals(out=list, drifts=list, ratios=list, stiffnesses=list, k=cython.Py_ssize_t, s=cython.double,
               d=cython.double)
cpdef list _elastic_outputs(list xs, list vs, list acc, double ground, ShearBuilding b, Peaks peaks, Py_ssize_t n)
