"""FMI 2.0 co-simulation adapter (pythonfmu) over the pidamper_physics core.

`slave.py` is the model script that build_fmu packs into the FMU, together with a
renamed copy of pidamper_physics.  It is not imported by the harness.
"""
