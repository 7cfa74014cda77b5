# Types for the compiled build of building_level.py (Cython, pure-Python mode): only the modal sums it
# calls, cimported so that the compiled build calls them in C; its classes stay Python classes.
from .modal cimport _dot3, _dot_change, _dot_real, _matrix_sum, _total
