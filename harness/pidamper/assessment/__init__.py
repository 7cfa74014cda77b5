"""Performance-based assessment: the driver (`assess`: a suite of ground motions scaled in stripes,
run with and without the damper, fragility, hazard and risk) and the statistics (`fragility`).  It
may import the studies' runner, the inputs, the scenes' parameter mapping and the running room."""
