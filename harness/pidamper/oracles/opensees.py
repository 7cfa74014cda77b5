"""OpenSees as the structural peer: the yielding shear building built with OpenSeesPy, and the one
way this package loads OpenSeesPy.

Loading: the Linux wheel (`openseespylinux`) bundles libblas and liblapack in its `lib` folder, but
its liblapack does not find the bundled libblas, so `import openseespy.opensees` fails with
"libblas.so.3: cannot open shared object file" unless that folder is on LD_LIBRARY_PATH.  `load()`
loads the bundled libraries first (ctypes, RTLD_GLOBAL), then imports OpenSeesPy: nobody is asked to
set LD_LIBRARY_PATH.  Where OpenSeesPy is missing or cannot load, `OpenSeesMissing` says what is
missing and how to install it (`pip install -e .[opensees]`).

The building (`shear_building`): nodes 0 (the ground, fixed) to N on one line (ndm = ndf = 1),
lumped masses, each storey a zeroLength element with `Steel01(Fy, k, b)` (default isotropic
hardening parameters: none), or `Elastic(k)` where Fy = 0, P-Delta as a parallel zeroLength with
`Elastic(-P_k / h_k)`; classical modal damping by `modalDamping` on the modes of K - K_G (the eigen
analysis before any load); the ground motion as `UniformExcitation` of a `Path` series that is the
held staircase an FMU input sees (two points at each jump); Newmark average acceleration, Newton,
NormDispIncr.  Relative displacements, as the FMUs report them.
"""
import ctypes
import glob
import importlib.util
import os

_OPS = None


class OpenSeesMissing(ImportError):
    """OpenSeesPy is not installed, or its bundled libraries cannot be loaded."""


def load():
    """The `openseespy.opensees` module, its bundled BLAS / LAPACK loaded first (once)."""
    global _OPS
    if _OPS is not None:
        return _OPS
    spec = importlib.util.find_spec("openseespylinux")
    if spec is not None and spec.submodule_search_locations:
        lib = os.path.join(list(spec.submodule_search_locations)[0], "lib")
        for name in ("libgfortran.so*", "libquadmath.so*", "libgomp.so*", "libblas.so*", "liblapack.so*"):
            for path in sorted(glob.glob(os.path.join(lib, name))):
                try:
                    ctypes.CDLL(path, mode=ctypes.RTLD_GLOBAL)
                except OSError as err:
                    raise OpenSeesMissing(f"OpenSeesPy's bundled library {path} cannot be loaded: {err}") from None
    try:
        import openseespy.opensees as ops
    except (ImportError, RuntimeError) as err:
        raise OpenSeesMissing(f"OpenSeesPy is needed here but cannot be imported ({err}): install it with "
                              "`pip install -e .[opensees]` (the `opensees` extra)") from None
    _OPS = ops
    return ops


def staircase(samples, dt):
    """(times, values) of the held ground motion: sample i holds on [i dt, (i + 1) dt), two points at
    each jump (OpenSees `Path` interpolates linearly between its points)."""
    times, values = [0.0], [float(samples[0])]
    for i in range(1, len(samples)):
        t = i * dt
        times += [t, t]
        values += [float(samples[i - 1]), float(samples[i])]
    times.append(len(samples) * dt)
    values.append(float(samples[-1]))
    return times, values


def shear_building(masses, stiffnesses, yield_forces, ratios, heights, zeta, p_delta=False, g=9.81):
    """Build the yielding shear building in a fresh OpenSees domain (see the module doc); returns
    the `ops` module."""
    ops = load()
    n = len(masses)
    ops.wipe()
    ops.model("basic", "-ndm", 1, "-ndf", 1)
    ops.node(0, 0.0)
    ops.fix(0, 1)
    for k in range(1, n + 1):
        ops.node(k, 0.0)
        ops.mass(k, float(masses[k - 1]))
    for k in range(1, n + 1):
        fy, kk, b = float(yield_forces[k - 1]), float(stiffnesses[k - 1]), float(ratios[k - 1])
        if fy > 0.0:
            ops.uniaxialMaterial("Steel01", k, fy, kk, b)
        else:
            ops.uniaxialMaterial("Elastic", k, kk)
        ops.element("zeroLength", k, k - 1, k, "-mat", k, "-dir", 1)
        if p_delta:
            gravity = g * sum(masses[k - 1:])
            ops.uniaxialMaterial("Elastic", 100 + k, -gravity / float(heights[k - 1]))
            ops.element("zeroLength", 100 + k, k - 1, k, "-mat", 100 + k, "-dir", 1)
    ops.eigen("-fullGenLapack", n)
    ops.modalDamping(float(zeta))
    return ops


def run_building(model, samples, dt_record, dt, stop_time, floors=None):
    """Drive a shear_building with the held ground motion `samples` (interval dt_record) at the
    analysis step dt up to stop_time; returns (times, displacements of `floors` (default: all)
    relative to the ground) at every dt_record instant.  dt must divide dt_record."""
    ops = load()
    n = len(model["masses"]) if isinstance(model, dict) else model
    floors = list(range(1, n + 1)) if floors is None else floors
    times, values = staircase(samples, dt_record)
    ops.timeSeries("Path", 1, "-time", *times, "-values", *values)
    ops.pattern("UniformExcitation", 1, 1, "-accel", 1)
    ops.constraints("Plain")
    ops.numberer("Plain")
    ops.system("FullGeneral")
    ops.test("NormDispIncr", 1e-13, 50)
    ops.algorithm("Newton")
    ops.integrator("Newmark", 0.5, 0.25)
    ops.analysis("Transient")
    per = int(round(dt_record / dt))
    steps = int(round(stop_time / dt_record))
    out_t, out_x = [0.0], [[0.0] * len(floors)]
    for i in range(steps):
        for _ in range(per):
            if ops.analyze(1, dt) != 0:
                raise ArithmeticError(f"OpenSees did not converge at t = {ops.getTime()!r} s (dt = {dt!r})")
        out_t.append((i + 1) * dt_record)
        out_x.append([ops.nodeDisp(k, 1) for k in floors])
    return out_t, out_x
