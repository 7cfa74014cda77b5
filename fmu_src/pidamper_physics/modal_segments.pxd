# Types for the compiled build of modal_segments.py (Cython, pure-Python mode).
from .modal cimport _dot_real
