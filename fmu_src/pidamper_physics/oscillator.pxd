# Types for the compiled build of oscillator.py (Cython, pure-Python mode): the undamped closed form
# (the pendulum's linear level) and the damped one (a building's modes, the unit's particle) as typed
# classes in C doubles; their methods return C tuples (structs of doubles) to typed callers, Python
# tuples to Python ones.
import cython
from libc cimport math as _libm


cdef class Oscillator:
    cdef public double w, ww, xe, A, B, R, x0, v0, wa, a, om, sp, cp, hs, hd

    cpdef _init(self, double w, double x0, double v0, double c, double a, double om, double psi)

    @cython.locals(h=cython.double, sh=cython.double, s=cython.double, omc=cython.double, v0=cython.double)
    cpdef (double, double, double, double) state(self, double tau)

    @cython.locals(xh=cython.double, R=cython.double, xe=cython.double, x0=cython.double,
                   spread=cython.double)
    cpdef (double, double) reach(self, double T)

    @cython.locals(x=cython.double, v=cython.double, sf=cython.double, cf=cython.double, ww=cython.double,
                   a=cython.double)
    cpdef (double, double, double, double, double, double) derivs(self, double tau)

    @cython.locals(w=cython.double, hs=cython.double, u=cython.double, ss=cython.double, cs=cython.double,
                   sd=cython.double, cd=cython.double, s=cython.double, co=cython.double, so=cython.double,
                   coo=cython.double, sinc=cython.double, dc=cython.double, ds=cython.double, a=cython.double,
                   sp=cython.double, cp=cython.double, om=cython.double, hw=cython.double, omc=cython.double,
                   v0=cython.double, x=cython.double, v=cython.double)
    cpdef (double, double, double, double) _forced(self, double tau)

    @cython.locals(a=cython.double, w=cython.double, om=cython.double, gap=cython.double, xh=cython.double,
                   vh=cython.double)
    cpdef (double, double) harmonic_bounds(self, double T)

    @cython.locals(w=cython.double, ww=cython.double, a=cython.double, R=cython.double, om=cython.double,
                   xh=cython.double, vh=cython.double, p0=cython.double, p1=cython.double, p2=cython.double,
                   p3=cython.double, p4=cython.double, p5=cython.double, p6=cython.double)
    cpdef (double, double, double, double, double, double, double) bounds(self, double T)


@cython.locals(osc=Oscillator)
cpdef Oscillator oscillator(double w, double x0, double v0, double c, double a, double om, double psi)


cdef class DampedOscillator:
    cdef public double w, ww, s, wd, p, q0, v0, a, b, k

    @cython.locals(ww=cython.double, s=cython.double, wd=cython.double, a=cython.double)
    cpdef start(self, double q0, double v0, double p)

    @cython.locals(s=cython.double, v0=cython.double, half=cython.double, sh=cython.double, sn=cython.double,
                   omc=cython.double, ec_m1=cython.double, es=cython.double, em1=cython.double)
    cpdef (double, double) at(self, double tau)
