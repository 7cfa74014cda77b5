# Types for the compiled build of level_model.py (Cython, pure-Python mode): LevelModel as a typed base
# class, so Damper's loop calls a level's segments and energy in C (a level written in Python, such as
# the modal, nonlinear and building levels, overrides them as usual and is called as before).  An
# instance __dict__ keeps the levels' own attributes; the arguments stay Python objects (the state
# keeps what it was given).
import cython


cdef class LevelModel:
    cdef dict __dict__
    cdef public object p

    cpdef flight(self, x, v, y, u, fc, psi, T, always_bound=*)

    cpdef stick(self, x, v, side, fc, psi, T)

    cpdef energy(self, x, v, y, u)
