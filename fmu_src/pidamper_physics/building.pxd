# Types for the compiled build of building.py (Cython, pure-Python mode): only the modal sums it calls,
# cimported so that the compiled build calls them in C; ShearBuilding stays a Python class.
from .modal cimport _dot3, _matrix_sum
