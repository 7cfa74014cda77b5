# Types for the compiled build of building_level.py (Cython, pure-Python mode): the modal sums it
# calls, cimported so that the compiled build calls them in C, its outputs' loops in C doubles, and
# the level model as a typed subclass of LevelModel (its fields in C, its hot methods called in C;
# the arguments stay Python objects, so the state keeps what it was given, as in the plain build).
import cython

from .building cimport ShearBuilding
from .level_model cimport LevelModel
from .modal_segments cimport ModalFlight
from .modal cimport _dot3, _dot_change, _dot_real, _matrix_sum, _total
from .peaks cimport Peaks
from .yielding cimport StoreyGuards
from .storeys cimport Hysteresis


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


cdef class BuildingModel(LevelModel):
    cdef public Py_ssize_t n, j
    cdef public double mu_j, _ground, _hysteretic
    cdef public list Kf, Cf, Kr, Cr, ride_masses, others, damping_now
    cdef public tuple free, ride
    cdef public Peaks peaks
    cdef public object storeys
    cdef dict _regimes, _held_kept
    cdef object _acc_key, _acc

    @cython.locals(storeys=Hysteresis, kept=tuple, held=list)
    cpdef _held(self, masses)

    @cython.locals(b=ShearBuilding, xs=list, vs=list)
    cpdef _decide(self, x, v)

    cpdef tuple floors(self, x, v)

    @cython.locals(b=ShearBuilding)
    cpdef follow(self, seg, double tau)

    @cython.locals(xs=list, vs=list, r=cython.double, kinetic=cython.double, b=ShearBuilding, m=cython.double,
                   w1=cython.double)
    cpdef energy(self, x, v, y, u)

    @cython.locals(b=list, i=cython.Py_ssize_t)
    cpdef list _loads(self, fc)

    @cython.locals(n=cython.Py_ssize_t, j=cython.Py_ssize_t, o=list, z0=list)
    cpdef flight(self, x, v, y, u, fc, psi, T, always_bound=*)

    @cython.locals(n=cython.Py_ssize_t, j=cython.Py_ssize_t, o=list, z0=list, b=list, mj=cython.double,
                   mr=cython.double, a=cython.double)
    cpdef stick(self, x, v, side, fc, psi, T)

    cpdef list _accelerations(self, x, v, y, u, side, f, ground)

    @cython.locals(n=cython.Py_ssize_t, j=cython.Py_ssize_t, xs=list, vs=list, K=list, C=list, loads=list,
                   q=list, dq=list, i=cython.Py_ssize_t, mj=cython.double)
    cpdef list _compute_accelerations(self, x, v, y, u, side, f, ground)

    cpdef acceleration(self, x, v, y, u, side, f, ground)

    cpdef tuple observables(self, x, v, y, u, side, f, ground)

    cpdef contact_accel(self, x, v, side, f, ground)

    @cython.locals(b=ShearBuilding, xs=list, vs=list, acc=list, out=list, drifts=list, ratios=list, pk=Peaks,
                   n=cython.Py_ssize_t)
    cpdef list building_observables(self, x, v, y, u, side, f, ground)


cdef class BuildingFlight(ModalFlight):
    cdef public double _tau
    cdef public list _z, start_floors, z0
    cdef Py_ssize_t _j, _n

    cpdef take_peaks(self, peaks, double tau, ground, guards=*)

    cpdef list state(self, double tau)

    cpdef list floors_at(self, double tau)

    @cython.locals(z=list, j=cython.Py_ssize_t, n=cython.Py_ssize_t)
    cpdef list others(self, double tau)

    @cython.locals(z=list, j=cython.Py_ssize_t, n=cython.Py_ssize_t)
    cpdef tuple positions(self, double tau)

    @cython.locals(j=cython.Py_ssize_t, n=cython.Py_ssize_t, x=cython.double, y=cython.double, v=cython.double,
                   u=cython.double, g=cython.double, dg=cython.double, D=cython.double)
    cpdef tuple values(self, double tau)


cdef class WithStoreys:
    cdef public object seg
    cdef public StoreyGuards storey
    cdef public Py_ssize_t contacts
    cdef public tuple bounds, noise
    cdef public double growth
    cdef public bint clear

    cpdef floors_at(self, double tau)

    cpdef positions(self, double tau)

    cpdef others(self, double tau)

    cpdef take_peaks(self, peaks, double tau, ground, guards=*)

    cpdef tuple values(self, double tau)

    cpdef tuple guard(self, double tau, Py_ssize_t i)

    cpdef tuple derivs(self, double tau, Py_ssize_t i)

@cython.locals(out=list, k=cython.Py_ssize_t, a=cython.double, b=cython.double)
cpdef tuple _larger(tuple p, tuple q)

@cython.locals(out=list, i=cython.Py_ssize_t, f=cython.double, m=cython.double)
cpdef list _per_floor(list forces, list masses)
