"""The surrogates' pipeline: UVLM data sets, training, validation plots. The trained networks themselves are
aerodynamic models like the others (:mod:`hawksim.backends.network`, :mod:`hawksim.backends.step_network`).

Modules:

- ``dataset``: resumable held-body UVLM samples (Dask + SQLite).
- ``flights``: UVLM flights recorded per update, the per-step network's data.
- ``train``: the cycle-mean network's Levenberg-Marquardt training.
- ``step_train``: the per-step network's training (torch, Adam) and scores.
- ``multifidelity``: the reference-lattice correction of a training set.
- ``plots``: validation figures.
"""

from hawksim.lazy import lazy_exports

__all__, __getattr__, __dir__ = lazy_exports(__name__, {
    ".dataset": ("open_dataset", "DatasetError", "Sample", "generate", "read_samples"),
    ".flights": ("FlightSpec", "FlightSample", "StoredFlight", "sample_flight", "evaluate_flight", "read_flights"),
    ".train": ("TrainResult", "Scores"),
    ".step_train": ("fit", "flight_cycle_means"),
    ".plots": ("validation_figure",),
})
