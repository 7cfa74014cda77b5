# Types for the compiled build of damper.py (Cython, pure-Python mode): Damper's stepping half
# (_Damper: advance, observables and the per-piece methods) as a typed subclass of stepping.EventDriven, so it
# reaches the state through C fields.  The fields stay Python objects, so the state keeps whatever
# numbers a caller or a saved state gave it, in both builds alike.  Damper itself stays a Python
# subclass: its methods (and _Damper's) can still be replaced on the class or on an instance.
import cython

from .level_model cimport LevelModel
from .stepping cimport EventDriven


cdef class _Damper(EventDriven):
    cdef public LevelModel model
    cdef public object p, energy, energy0, work_in, viscous, dissipated, e_applied
    cdef public object contacts, on_impact, on_collapse, _follow, _observables

    @cython.locals(x=cython.double, v=cython.double, y=cython.double, u=cython.double, e=cython.double,
                   w=cython.double, check=cython.double)
    cpdef bint _in_range(self) except -1

    cpdef _energy(self)

    @cython.locals(om=cython.double, phi=cython.double, t=cython.double, lo=cython.double)
    cpdef double _phase(self) except? -1.0

    cpdef _resting(self, fc)

    cpdef _applied(self, force)

    @cython.locals(model=LevelModel)
    cpdef _segment(self, fc, double horizon)

    cpdef _coast(self, state, double tau, t_end)

    cpdef _move(self, seg, double tau, t_end, fc, observe)
