"""Generic flapping-wing aerodynamics: extended UVLM and quasi-steady blade elements.

Imports neither mujoco nor hawksim, and does no file I/O.
"""
