"""The damper unit on a shear building, co-simulated: PendulumImpactDamperUnit.fmu + ShearBuilding<N>.fmu.

The coupled system (names as in the FMUs): the unit hangs from floor j of the building;

    building.floor[j].a  ->  unit.a_s         (absolute acceleration of the attachment)
    unit.F_s             ->  building.F[j]    (mean force of the unit on the floor over the step)
    unit.J_s, unit.t_J   ->  building.J[j], building.t_J[j]      (impulse-aware coupling only)

Masters (each returns a `Run`: floor displacements on the communication grid, impacts, wall time):

- `gauss_seidel(scenario, h, mode)`: fmpy's FMU2Slave driven directly.  At each step it reads
  floor[j].a (absolute, with the F[j] the building received for the previous step: direct
  feedthrough), steps the unit with it held, passes F_s to F[j] (and, impulse-aware, J_s, t_J to
  J[j], t_J[j]), then steps the building over the same interval.  Modes (MODES):
  "mean": the unit runs with impulse_aware = 0; F_s carries the impacts' impulses spread over the
  step, and the attachment's share of each impulse reaches the unit through the next floor[j].a.
  "impulse": the unit runs with impulse_aware = 1; F_s is the smooth force only, the building
  applies J_s at t_J (the step's momentum and its first moment kept), and the unit applies the
  attachment's share J/M_s in its own frame at the impact (floor[j].a, an instantaneous
  acceleration, never carries an impulse).
  "impulse-extrapolated": as "impulse", but the unit's a_s is the linear extrapolation of the
  attachment's smooth mean acceleration over the last two steps (from floor[j].v and J_s / M_s)
  instead of the held floor[j].a: the master's input extrapolation that the second order needs.
  Both held-floor[j].a modes are first order: the unit sees the attachment's acceleration held
  from the step's start, computed with the previous step's mean force (a lag of about h); the
  impulse-aware inputs remove the impacts' share of the error, not that lag.
- `physics_gauss_seidel(scenario, h, mode)`: the same master on the physics classes directly (no
  FMI), for tests: it reproduces `gauss_seidel` bit for bit.
- `libcosim_jacobi(scenario, h, impulse_aware)`: the same system in libcosim (libcosimpy), loaded
  from the OSP system structure this module writes; its fixed-step algorithm steps both FMUs in
  parallel on the outputs of the previous step (Jacobi): the unit's a_s is a step older than in
  Gauss-Seidel and F_s reaches the building a step late (impulse-aware: J_s with a t_J in the
  past, which the building applies at the step's start).

`reference(scenario, times)` is the exact monolithic solution the measurements compare with: the
physics core's building level (Damper with storeys, issue 14 part 1) when it is there, else an
independent event-driven integration (`ivp_reference`: scipy DOP853 at rtol 1e-12 with its own
impact law).  `export_system(out_dir, scenario)` writes the SSP files and the OSP system
structures beside the FMUs.

Room: co-simulation (scenario, masters, references, system files, the command).  It may import the
running room (FMU location, the FMU wrapper) and the physics core; nothing above it.
"""
from .components import component_fmus
from .masters import LABELS, MODES, gauss_seidel, libcosim_jacobi, physics_gauss_seidel
from .reference import error, ivp_reference, monolithic_reference, reference
from .scenario import BUILDING, SYSTEM, UNIT, Run, Scenario, scenario_from
from .system_files import export_system, ssd_text, write_osp, write_ssp

__all__ = ["BUILDING", "LABELS", "MODES", "SYSTEM", "UNIT", "Run", "Scenario", "component_fmus", "error",
           "export_system", "gauss_seidel", "ivp_reference", "libcosim_jacobi", "monolithic_reference",
           "physics_gauss_seidel", "reference", "scenario_from", "ssd_text", "write_osp", "write_ssp"]
