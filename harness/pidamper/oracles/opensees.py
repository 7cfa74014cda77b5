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
import json
import os
import math

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


def available():
    """None when OpenSeesPy loads, else the OpenSeesMissing message (a JSON-able check)."""
    try:
        load()
    except OpenSeesMissing as err:
        return str(err)
    return None


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


def _floors(ops, masses):
    """A fresh 1-D domain: node 0 the fixed ground, nodes 1..N the floors with their masses [kg]."""
    ops.wipe()
    ops.model("basic", "-ndm", 1, "-ndf", 1)
    ops.node(0, 0.0)
    ops.fix(0, 1)
    for k, m in enumerate(masses, start=1):
        ops.node(k, 0.0)
        ops.mass(k, float(m))


def shear_building(masses, stiffnesses, yield_forces, ratios, heights, zeta, p_delta=False, g=9.81, carried=None,
                   damping="modal", imk=None):
    """Build the yielding shear building in a fresh OpenSees domain (see the module doc); returns
    the `ops` module.  carried: masses [kg] per floor whose weight the storeys carry beyond the
    floors' own (a damper's particle, modelled elsewhere), for P-Delta.  damping: "modal"
    (`modalDamping`), "rayleigh-initial" or "rayleigh-tangent" (`rayleigh` with betaKinit or betaK,
    zeta at the first mode and the min(3, N)-th; the P-Delta springs' stiffness included).  imk: per
    storey the 21 `IMKBilin` values (the command's order) of deteriorating storeys instead of Steel01."""
    ops = load()
    n = len(masses)
    weights = [m + (carried[k] if carried else 0.0) for k, m in enumerate(masses)]
    _floors(ops, masses)
    # a zeroLength element takes no Rayleigh damping unless asked (-doRayleigh 1)
    rayleigh = ("-doRayleigh", 1) if damping != "modal" else ()
    for k in range(1, n + 1):
        fy, kk, b = float(yield_forces[k - 1]), float(stiffnesses[k - 1]), float(ratios[k - 1])
        if imk is not None:
            ops.uniaxialMaterial("IMKBilin", k, *[float(v) for v in imk[k - 1]])
        elif fy > 0.0:
            ops.uniaxialMaterial("Steel01", k, fy, kk, b)
        else:
            ops.uniaxialMaterial("Elastic", k, kk)
        ops.element("zeroLength", k, k - 1, k, "-mat", k, "-dir", 1, *rayleigh)
        if p_delta:
            gravity = g * sum(weights[k - 1:])
            ops.uniaxialMaterial("Elastic", 100 + k, -gravity / float(heights[k - 1]))
            ops.element("zeroLength", 100 + k, k - 1, k, "-mat", 100 + k, "-dir", 1, *rayleigh)
    w2 = ops.eigen("-fullGenLapack", n)
    if damping == "modal":
        ops.modalDamping(float(zeta))
    else:
        w1, wj = math.sqrt(w2[0]), math.sqrt(w2[min(3, n) - 1])
        a0, a1 = 2.0 * zeta * w1 * wj / (w1 + wj), 2.0 * zeta / (w1 + wj)
        tangent = damping == "rayleigh-tangent"
        ops.rayleigh(a0, a1 if tangent else 0.0, 0.0 if tangent else a1, 0.0)
    return ops


def damped_shear_building(masses, stiffnesses, yield_forces, ratios, heights, zeta, p_delta, floor, m, w1, zeta_p,
                          d, Kh, xi, g=9.81, imk=None):
    """The yielding shear building with the pendulum damper as OpenSees models one: the particle a
    node of mass m [kg] hung from floor `floor` (0-based) by a spring m w1^2 with the dashpot
    2 zeta_p m w1 (`Elastic` with eta), the two stops `JankowskiImpact` gap elements (Hertz
    stiffness Kh [N/m^1.5], damping ratio xi, the gap d [m] each way).  The building's classical
    modal damping is assembled as a network of `Viscous` dashpots (node to node and node to ground)
    whose matrix is exactly C = M Phi diag(2 zeta w) Phi^T M of the building's elastic modes (K -
    K_G): `modalDamping` would damp the particle's modes as well.  imk: per storey the 21 `IMKBilin`
    values of deteriorating storeys instead of Steel01.  Returns `ops`; the particle is node PARTICLE."""
    import numpy as np
    import scipy.linalg

    ops = load()
    n = len(masses)
    carried = list(masses)
    carried[floor] += m
    loads = [g * sum(carried[k:]) for k in range(n)] if p_delta else [0.0] * n
    keff = [k - p / h for k, p, h in zip(stiffnesses, loads, heights)]
    D = np.eye(n) - np.eye(n, k=-1)
    Kmat, Mmat = D.T @ np.diag(keff) @ D, np.diag(masses)
    w2, phi = scipy.linalg.eigh(Kmat, Mmat)
    C = Mmat @ phi @ np.diag(2 * zeta * np.sqrt(w2)) @ phi.T @ Mmat
    _floors(ops, masses)
    ops.node(PARTICLE, 0.0)
    ops.mass(PARTICLE, float(m))
    tag = 1
    for k in range(1, n + 1):
        fy, kk, b = float(yield_forces[k - 1]), float(stiffnesses[k - 1]), float(ratios[k - 1])
        if imk is not None:
            ops.uniaxialMaterial("IMKBilin", tag, *[float(v) for v in imk[k - 1]])
        else:
            ops.uniaxialMaterial(*(("Steel01", tag, fy, kk, b) if fy > 0.0 else ("Elastic", tag, kk)))
        ops.element("zeroLength", tag, k - 1, k, "-mat", tag, "-dir", 1)
        tag += 1
        if p_delta:
            ops.uniaxialMaterial("Elastic", tag, -loads[k - 1] / float(heights[k - 1]))
            ops.element("zeroLength", tag, k - 1, k, "-mat", tag, "-dir", 1)
            tag += 1
    for i in range(n):  # the damping network: -C_ij between floors i, j; the row sum to the ground
        for j in range(i, n):
            c = float(C[i].sum()) if i == j else -float(C[i, j])
            if c != 0.0:
                ops.uniaxialMaterial("Viscous", tag, c, 1.0)
                ops.element("zeroLength", tag, 0 if i == j else i + 1, j + 1, "-mat", tag, "-dir", 1)
                tag += 1
    j = floor + 1
    ops.uniaxialMaterial("Elastic", tag, m * w1 * w1, 2.0 * zeta_p * m * w1)
    ops.element("zeroLength", tag, j, PARTICLE, "-mat", tag, "-dir", 1)
    tag += 1
    meff = m * masses[floor] / (m + masses[floor])
    for a, b in ((j, PARTICLE), (PARTICLE, j)):  # the stops: compression of b - a below -d
        ops.uniaxialMaterial("JankowskiImpact", tag, float(Kh), float(xi), float(meff), -float(d))
        ops.element("zeroLength", tag, a, b, "-mat", tag, "-dir", 1)
        tag += 1
    return ops


#: the particle's node of damped_shear_building
PARTICLE = 1000


def roof_history(masses, stiffnesses, yield_forces, ratios, heights, zeta, p_delta, samples, dt_record, dt,
                 stop_time, damping="modal", imk=None):
    """The roof's displacement [m] at every dt_record instant of a shear_building under the held
    ground motion `samples` (a JSON-able call for a child process: running.isolated)."""
    shear_building(masses, stiffnesses, yield_forces, ratios, heights, zeta, p_delta=p_delta, damping=damping,
                   imk=imk)
    _, x = run_building(len(masses), samples, dt_record, dt, stop_time, floors=[len(masses)])
    return [row[0] for row in x]


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
    if abs(per * dt - dt_record) > 1e-9 * dt_record:
        raise ValueError(f"dt = {dt!r} is not allowed: it must divide the record's interval {dt_record!r} s")
    steps = int(round(stop_time / dt_record))
    out_t, out_x = [0.0], [[0.0] * len(floors)]
    for i in range(steps):
        for _ in range(per):
            if ops.analyze(1, dt) != 0:
                raise ArithmeticError(f"OpenSees did not converge at t = {ops.getTime()!r} s (dt = {dt!r})")
        out_t.append((i + 1) * dt_record)
        out_x.append([ops.nodeDisp(k, 1) for k in floors])
    return out_t, out_x


def pushover_curve(masses, stiffnesses, yield_forces, ratios, heights, p_delta, pattern, roof_target, steps,
                   g=9.81):
    """OpenSees's static pushover of the yielding shear building: lateral loads proportional to
    `pattern` (per floor), the roof displacement driven to roof_target [m] in `steps` equal
    increments (DisplacementControl, Newton); returns (roof displacements [m], base shears [N])."""
    ops = shear_building(masses, stiffnesses, yield_forces, ratios, heights, 0.0, p_delta, g)
    n = len(masses)
    return _static_pushover(ops, n, pattern, roof_target, steps)


def imk_material(params, strains):
    """OpenSees's `IMKBilin` uniaxial material (its 21 parameters in the command's order) driven
    through `strains` (a list, or the path of a JSON file holding one) as openseespy's `setStrain`
    drives it (setTrialStrain and commitState per sample): the stresses, one per sample (NaN as
    JSON null)."""
    if isinstance(strains, str):
        with open(strains) as f:
            strains = json.load(f)
    ops = load()
    ops.wipe()
    ops.uniaxialMaterial("IMKBilin", 1, *[float(p) for p in params])
    ops.testUniaxialMaterial(1)
    out = []
    for e in strains:
        ops.setStrain(float(e))
        s = ops.getStress()
        out.append(s if s == s else None)
    return out


def imk_pushover_curve(masses, laws, heights, p_delta, pattern, roof_target, steps, g=9.81):
    """OpenSees's static pushover of a shear building of `IMKBilin` storeys (zeroLength elements,
    each law 21 numbers in the command's order) with P-Delta as parallel `Elastic(-P/h)` springs:
    lateral loads proportional to `pattern`, the roof driven to roof_target [m] in `steps` equal
    increments (DisplacementControl, Newton); (roof displacements [m], base shears [N])."""
    ops = load()
    n = len(masses)
    _floors(ops, masses)
    for k in range(1, n + 1):
        ops.uniaxialMaterial("IMKBilin", k, *[float(v) for v in laws[k - 1]])
        ops.element("zeroLength", k, k - 1, k, "-mat", k, "-dir", 1)
        if p_delta:
            ops.uniaxialMaterial("Elastic", 100 + k, -g * sum(masses[k - 1:]) / float(heights[k - 1]))
            ops.element("zeroLength", 100 + k, k - 1, k, "-mat", 100 + k, "-dir", 1)
    return _static_pushover(ops, n, pattern, roof_target, steps)


def _static_pushover(ops, n, pattern, roof_target, steps):
    """Push the building in the domain (floors 1..n) by lateral loads proportional to `pattern`,
    the roof driven to roof_target [m] in `steps` equal increments (DisplacementControl, Newton,
    until done or a step fails); (roof displacements [m], base shears [N])."""
    ops.timeSeries("Linear", 1)
    ops.pattern("Plain", 1, 1)
    for k, value in enumerate(pattern, start=1):
        ops.load(k, float(value))
    ops.constraints("Plain")
    ops.numberer("Plain")
    ops.system("FullGeneral")
    ops.test("NormDispIncr", 1e-12, 50)
    ops.algorithm("Newton")
    ops.integrator("DisplacementControl", n, 1, float(roof_target) / steps)
    ops.analysis("Static")
    total = float(sum(pattern))
    roof, shear = [0.0], [0.0]
    for _ in range(int(steps)):
        if ops.analyze(1) != 0:
            break
        roof.append(ops.nodeDisp(n, 1))
        shear.append(ops.getLoadFactor(1) * total)
    ops.wipe()
    return roof, shear
