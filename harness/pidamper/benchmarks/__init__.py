"""Benchmarks that print figures and write the measured pages (no timing assertions live in the
tests): speed against error (`pidamper bench`, workprecision, levels), the hard-case stress table
(`pidamper stress`), the cost per step as hosts see it, per impact and of logging, the buildings and
co-simulation pages, and the checks that make the FMU refuse a call on purpose (fatal_checks).  They may
import every room of the harness below the command line (the oracles among them); of the rooms, only `cli` imports
them."""
