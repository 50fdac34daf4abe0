"""Stability about an operating point: the paper's cycle-averaged linear model and the Floquet analysis of the
free body's one-beat map.

Modules:

- ``derivatives``: stability derivatives from disturbed held-body runs (Eq. 15).
- ``system``: the A matrices and their modes (Eqs. 8-12), nondimensional.
- ``linear_model``: :class:`LinearModel`, the one linear model about an operating point (every map).
- ``floquet``: the monodromy matrix of the one-beat map about a periodic orbit, its multipliers and modes.
- ``history_floquet``: the same with a history network's record of calls in the state.
- ``prediction``: perturbed flights predicted by either linear model.
- ``validation``: the predictions against nonlinear flights, per speed.
- ``report``: the stability report of ``hawksim stability``.
"""

from hawksim.lazy import lazy_exports

__all__, __getattr__, __dir__ = lazy_exports(__name__, {
    ".derivatives": ("dimensional_derivatives", "DerivativeRuns"),
    ".system": ("a_long", "a_lat", "modes", "Mode", "nondimensional_system", "MassProperties"),
    ".linear_model": ("LinearModel", "MAPS"),
    ".floquet": ("Floquet", "monodromy", "floquet_analysis", "AveragedSystem", "quasi_steady_system"),
    ".history_floquet": ("HistoryFloquet", "history_monodromy", "history_floquet_analysis"),
    ".prediction": ("Prediction", "predict_flight"),
    ".validation": ("validate_speed",),
    ".report": ("stability_report",),
})
