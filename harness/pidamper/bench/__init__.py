"""Benchmarks of speed against error (pidamper bench) and the hard-case stress table (pidamper stress)."""
