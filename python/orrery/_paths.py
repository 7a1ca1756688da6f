# Replaced by CMake (build/python/orrery/_paths.py, or the installed copy):
# the liborrery this copy of the package loads. From the source tree, set
# ORRERY_LIBRARY instead.
LIBRARY = None
VERSION = None
