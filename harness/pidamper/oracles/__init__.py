"""Independent references the tests and benchmarks compare the model with: event-driven solve_ivp
integrations of the pendulum levels, the nonlinear double pendulum and the damper on a shear
building, each with its own equations and contact logic (numpy and scipy only).  They may import
nothing of the model (pidamper_physics, pidamper_fmu) nor of the rest of the harness: an oracle that
shares code with what it checks checks nothing (an import-linter contract in pyproject.toml)."""
