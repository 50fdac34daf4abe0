"""Studies behind the documented measurements (each prints JSON or writes results/). Run as
``python -m scripts.studies.<name>``."""
