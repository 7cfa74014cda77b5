"""Running the FMUs: locate or build the one of a model (`fmu`), fit start values to it (`variants`),
the FMU unpacked once per process (`unpacked`), one FMU wrapper (`instance`: instantiate,
initialise, set/get by name, step, free), whole runs with fmpy against a forcing signal
(`simulation`), step-by-step drivers with save and restore over the FMU or the physics core
(`stepper`), and calls in a child process for checks that may crash (`isolated`).  It may import
the physics core, build_fmu, the FMU's variable tables (pidamper_fmu.particle_tables) and the inputs
(pidamper.forcing); nothing else of the harness."""
