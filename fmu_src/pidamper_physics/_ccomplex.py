"""complex(re, im) under a name the compiled build gives a C body: `_ccomplex.pxd` builds the C
complex of those parts in place (signed zeros kept, as CPython's complex(re, im)), where calling the
complex type would be a Python call.  Plain Python, never compiled itself: a module that cimports
the .pxd gets its inline body, the plain build this alias."""
parts = complex
