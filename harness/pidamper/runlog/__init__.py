"""Run logs: every run written to MCAP (Foxglove) and to Rerun, and any MCAP run replayed into Rerun.
`schema` is the one description of what a log holds (state and impact records, run info, the 3D
drawing's geometry and frames), `mcap_log` and `rerun_log` write and read it, `logged_run` runs the
FMU and logs as it goes, `screenshot` renders a Rerun recording headless.  It may use the running
room (simulation, fmu) and the inputs (forcing); nothing below it imports it but scene files'
validation of the log options (scene)."""
