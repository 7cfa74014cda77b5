# Types for the compiled build of segments.py (Cython, pure-Python mode): the linear level's free
# flight and ride as typed classes in C doubles (Outside stays a Python subclass of Flight).
import cython
from libc cimport math as _libm

from .oscillator cimport Oscillator, oscillator


cdef double _TOL, _RESOLUTION, _ABOVE, _UNDERFLOW

cpdef double noise_size(double swing, double reach, double D) except? -1.0

cdef class LinearParams:
    cdef public double w2, w1, D, cx, cy, Omega_acting, F0, M, Omega, mu, d, m, L2, L1

@cython.locals(w2=cython.double, w1=cython.double, ww2=cython.double, ww1=cython.double, a2=cython.double,
               b2=cython.double, a1=cython.double, b1=cython.double, D=cython.double, r2=cython.double,
               r1=cython.double, swing=cython.double, growth=cython.double, zmax=cython.double,
               h2=cython.double, h1=cython.double, sh2=cython.double, sh1=cython.double, s2=cython.double,
               s1=cython.double, o2=cython.double, o1=cython.double)
cpdef tuple coast(LinearParams p, double x, double v, double y, double u, double fx, double fy, double T)


cdef class Flight:
    cdef public Oscillator px, py
    cdef public double cx, cy, D, growth, w2, x0, v0, a2, b2, w1, y0, u0, a1, b1
    cdef public tuple bounds, noise, start
    cdef public bint clear, inline
    cdef public int sgn

    @cython.locals(a=cython.double, px=Oscillator, py=Oscillator, cx=cython.double, cy=cython.double,
                   D=cython.double, xh=cython.double, x_lo=cython.double, x_hi=cython.double,
                   y_lo=cython.double, y_hi=cython.double, zmax=cython.double, swing=cython.double,
                   tol=cython.double, n0=cython.double, _=cython.double, bx1=cython.double,
                   bx2=cython.double, bx3=cython.double, bx4=cython.double, by1=cython.double, by2=cython.double,
                   by3=cython.double, by4=cython.double)
    cpdef _init(self, LinearParams p, double x, double v, double y, double u, double fx, double fy, double psi, double T,
                bint always_bound)

    @cython.locals(x=cython.double, v=cython.double, y=cython.double, u=cython.double)
    cpdef tuple positions(self, double tau)

    @cython.locals(w2=cython.double, w1=cython.double, h2=cython.double, h1=cython.double, sh2=cython.double,
                   sh1=cython.double, s2=cython.double, s1=cython.double, o2=cython.double, o1=cython.double,
                   v=cython.double, u=cython.double, a2=cython.double, a1=cython.double)
    cpdef (double, double, double, double) _inline(self, double tau)

    @cython.locals(g=cython.double, dg=cython.double)
    cpdef (double, double) gap(self, double tau)

    @cython.locals(x=cython.double, v=cython.double, x2=cython.double, x3=cython.double, y=cython.double,
                   u=cython.double, y2=cython.double, y3=cython.double, cx=cython.double, cy=cython.double)
    cpdef (double, double, double, double) gap_derivs(self, double tau)

    @cython.locals(cx=cython.double, cy=cython.double, D=cython.double, x=cython.double, v=cython.double,
                   y=cython.double, u=cython.double, z=cython.double, dz=cython.double)
    cpdef tuple values(self, double tau)

    @cython.locals(z=cython.double, z1=cython.double, z2=cython.double, z3=cython.double)
    cpdef tuple derivs(self, double tau, Py_ssize_t i)


@cython.locals(seg=Flight)
cpdef Flight flight(LinearParams p, double x, double v, double y, double u, double fx, double fy, double psi, double T,
                    bint always_bound)


cdef class Stick:
    cdef public Oscillator osc
    cdef public int sgn
    cdef public double d, k, base, a, om, growth
    cdef public tuple bounds, noise
    cdef public bint clear

    @cython.locals(mu=cython.double, w1=cython.double, w2=cython.double, d=cython.double, ww1=cython.double,
                   big_w=cython.double, a=cython.double, c=cython.double, osc=Oscillator, k=cython.double,
                   _=cython.double, P0=cython.double, P1=cython.double, P2=cython.double, P3=cython.double,
                   P4=cython.double, aa=cython.double, om=cython.double, tol=cython.double, lo=cython.double,
                   hi=cython.double, size=cython.double, n0=cython.double, floor=cython.double)
    cpdef _init(self, LinearParams p, double x, double v, int sgn, double fx, double fy, double psi, double T)

    @cython.locals(x=cython.double, v=cython.double)
    cpdef tuple positions(self, double tau)

    @cython.locals(x=cython.double, v=cython.double, sf=cython.double, cf=cython.double, s=cython.double)
    cpdef tuple values(self, double tau)

    @cython.locals(x=cython.double, v=cython.double, x2=cython.double, x3=cython.double, sf=cython.double,
                   cf=cython.double, s=cython.double, k=cython.double, a=cython.double, om=cython.double)
    cpdef tuple derivs(self, double tau, Py_ssize_t i=*)


@cython.locals(seg=Stick)
cpdef Stick stick(LinearParams p, double x, double v, int sgn, double fx, double fy, double psi, double T)
