"""The surrogate's pipeline: resumable UVLM data sets (Dask + SQLite, ``dataset``), Levenberg-Marquardt training
(``train``) and validation plots (``plots``). The trained network's files and inference are an aerodynamic
model like the others: :mod:`hawksim.backends.network`."""
