"""Benchmarks that print figures and write the measured pages (no timing assertions live in the
tests): speed against error (`pidamper bench`, workprecision, levels), the hard-case stress table
(`pidamper stress`), the cost per step as hosts see it, per impact and of logging, the buildings and
co-simulation pages, and the checks that make the FMU refuse a call on purpose (fatal_checks).  They
use the oracles (pidamper.oracles) and everything else of the harness."""
