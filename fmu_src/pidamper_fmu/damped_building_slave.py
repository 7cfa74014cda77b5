"""DampedShearBuilding<N> (N = 1..10): the pendulum damper on a floor of an N-storey linear shear
building, the particle FMU of slave.py with the building's tables (particle_tables.tables(N)).

Parameters g, mu (of the building's total mass), FR (over its first frequency), d, e (tunable), F0,
Omega, phi, fidelity (0..2), zeta_s (every mode), zeta_p, angle_limit, alpha_0, alpha_dot_0,
damper_floor (0 = the top), floor[k].m, storey[k].k and storey[k].h (k = 1..N); inputs F (on the
damper floor) and a_g; the particle's outputs as in PendulumImpactDamper (its primary is the damper
floor) and per floor and storey x, a, drift, drift_ratio and the running maxima drift_ratio_max,
v_abs_max, a_abs_max, located exactly inside fmi2DoStep (pidamper_physics.peaks).  The building
starts at rest.

One class per storey count, each defined once here (pythonfmu re-executes the model script at
every instantiation and keeps every class that execution defines: the script imports its class).
"""
from pythonfmu.default_experiment import DefaultExperiment

from pidamper_physics.params import MAX_STOREYS

from .slave import ParticleSlave


def _model(n):
    return type(f"DampedShearBuilding{n}", (ParticleSlave,), {
        "STOREYS": n,
        "__doc__": f"The pendulum damper on a {n}-storey shear building, exact event-driven co-simulation.",
        "__module__": __name__,
        "description": (f"{n}-storey linear shear building (lumped floors, storey springs, classical modal damping) "
                        "with the pendulum impact damper on a floor: exact event-driven motion, impacts, chatter, "
                        "sticking and the response's peaks located inside doStep"),
        "default_experiment": DefaultExperiment(start_time=0.0, stop_time=20.0, step_size=0.005),
    })


for _n in range(1, MAX_STOREYS + 1):
    globals()[f"DampedShearBuilding{_n}"] = _model(_n)
del _n
