"""The stability report of one ascent speed: derivatives, A matrices and modes in the CLI contract's JSON
(`hawksim stability`; also the input of the paper's Figs. 15-19 in :mod:`hawksim.paper.studies`)."""

from __future__ import annotations

import numpy as np


def stability_report(speed: float, *, kinematics=None, client=None, progress=None, forward_speed: float = 0.0) -> dict:
    """The CLI contract's JSON for one ascent speed (also used by the studies of `hawksim reproduce`); client: a
    dask.distributed client whose workers run the UVLM cases
    (:func:`hawksim.stability.derivatives.dimensional_derivatives`). ``forward_speed`` [m/s] > 0 (forward flight,
    :mod:`hawksim.condition`) starts from ``kinematics`` or, without them, the shipped forward trims
    (:func:`hawksim.trim.tables.forward_start`: level flight, 0-4 m/s; ValueError naming ``forward_speed``
    elsewhere); the JSON then carries ``forward_speed``."""
    forward_source = None
    if forward_speed and kinematics is None:
        from hawksim.trim.tables import forward_start

        kinematics, forward_source = forward_start(forward_speed, speed), "shipped forward trims"
    from hawksim.stability.derivatives import dimensional_derivatives, mass_properties
    from hawksim.stability.system import (LAT_DERIVATIVES, LONG_DERIVATIVES, about_centre_of_mass, modes_json,
                                          nondimensional_system)
    from hawksim.trim.tables import shipped_trim

    trim = shipped_trim(speed) if kinematics is None else None
    kin = kinematics if kinematics is not None else trim.kinematics
    fwd = {"forward_speed": forward_speed} if forward_speed else {}
    runs = dimensional_derivatives(kin, speed, client=client, progress=progress, **fwd)
    mp = mass_properties(kin)
    d, A_long, A_lat, scalars = nondimensional_system(kin, speed, runs.derivatives, mp, **fwd)
    return {
        "speed": speed, **fwd,
        "trim": {"kinematics": kin.to_edge(),
                 "source": trim.source if kinematics is None else forward_source or "given"},
        "longitudinal": {"derivatives": {k: d[k] for k in LONG_DERIVATIVES}, **modes_json(A_long)},
        "lateral": {"derivatives": {k: d[k] for k in LAT_DERIVATIVES}, **modes_json(A_lat)},
        "derivatives_dimensional": about_centre_of_mass(runs.derivatives, mp.body_cg),
        "derivatives_dimensional_about_body_cg": runs.derivatives,
        "nondimensional": scalars,
        "mass_properties": vars(mp),
        "disturbances": runs.deltas,
        "resolution": runs.resolution.to_dict(),
        "wall_time_s": runs.wall_time_s,
    }


def _pairs(z) -> list[list[float]]:
    return [[float(complex(v).real), float(complex(v).imag)] for v in z]


def _mode(mu, ex, vec_abs, resolved: bool, reach: float) -> dict:
    """One mode's entry of a ``floquet`` block: multiplier and exponent [re, im], |mu|, kind, stability, whether
    it is a mode of the flight and how strongly it is reached, the eigenvector's magnitudes."""
    from hawksim.stability.system import classify

    kind, _ = classify(ex)
    return {"multiplier": _pairs([mu])[0], "exponent": _pairs([ex])[0], "abs_multiplier": float(abs(mu)),
            "kind": kind, "stable": bool(abs(mu) < 1.0), "resolved": bool(resolved), "reach": float(reach),
            "eigenvector_abs": list(map(float, vec_abs))}


def floquet_json(fl) -> dict:
    """The CLI contract's ``floquet`` block of a :class:`hawksim.stability.floquet.Floquet` (or of the monodromy's
    :class:`hawksim.stability.linear_model.LinearModel`, analysed by
    :func:`hawksim.stability.floquet.floquet_analysis`): per system the multipliers mu and exponents ln(mu) per
    wingbeat (comparable with the nondimensional eigenvalues, t+ = t/T) as
    [re, im], and the modes (kind and stability of each exponent, |mu| and the eigenvector's magnitudes)."""
    from hawksim.stability.linear_model import LinearModel

    if isinstance(fl, LinearModel):
        from hawksim.stability.floquet import floquet_analysis

        fl = floquet_analysis(fl)
    out = {}
    for name, mu, ex, vec, ok, rch in (
            ("longitudinal", fl.multipliers_long, fl.exponents_long, fl.eigenvectors_long, fl.resolved_long,
             fl.reach_long),
            ("lateral", fl.multipliers_lat, fl.exponents_lat, fl.eigenvectors_lat, fl.resolved_lat, fl.reach_lat)):
        modes = [_mode(mu[k], ex[k], np.abs(vec[:, k]), ok[k], rch[k]) for k in range(len(mu))]
        out[name] = {"multipliers": _pairs(mu), "exponents": _pairs(ex), "modes": modes,
                     "states": list(("u", "w", "q", "theta") if name == "longitudinal" else ("v", "p", "r", "phi"))}
    out["resolution"] = ("'reach': how strongly the launches reach the mode at the periodic beat (1 for a settable "
                         "state); 'resolved': reach >= hawksim.stability.floquet.REACH_MIN, else the launch "
                         "family's extrapolation, not a mode of the flight")
    out["coupling"] = float(fl.coupling)
    out["max_abs_multiplier"] = fl.max_multiplier
    out["max_abs_resolved_multiplier"] = fl.max_resolved_multiplier
    out["wall_time_s"] = fl.wall_time_s
    return out


def history_floquet_json(hf, count: int = 4) -> dict:
    """The ``floquet`` block (the keys of :func:`floquet_json`) of a history network's augmented monodromy
    (:class:`hawksim.stability.history_floquet.HistoryFloquet`, or its LinearModel, ``map="history"``): per system
    its ``count`` largest body modes (the
    eigenvalues whose eigenvectors put at least 5 % of their norm in the 4 body states,
    :meth:`HistoryFloquet.body_modes`), each with its eigenvector's body-state magnitudes (normalized to 1) and
    ``body_share``; every mode is a mode of the map (``resolved``, reach 1)."""
    from hawksim.stability.linear_model import LinearModel

    if isinstance(hf, LinearModel):
        from hawksim.stability.history_floquet import history_floquet_analysis

        hf = history_floquet_analysis(hf)
    out = {}
    for name, M in (("longitudinal", hf.long), ("lateral", hf.lat)):
        w, V = np.linalg.eig(M)
        order = np.argsort(-np.abs(w), kind="stable")
        w, V = w[order], V[:, order]
        share = np.linalg.norm(V[:4], axis=0) / np.linalg.norm(V, axis=0)
        keep = [k for k in range(len(w)) if share[k] >= 0.05][:count]
        mu = w[keep]
        ex = np.log(mu.astype(complex))
        modes = []
        for k, m, e in zip(keep, mu, ex):
            body = np.abs(V[:4, k])
            modes.append({**_mode(m, e, body / np.linalg.norm(body), True, 1.0), "body_share": float(share[k])})
        out[name] = {"multipliers": _pairs(mu), "exponents": _pairs(ex), "modes": modes,
                     "states": list(("u", "w", "q", "theta") if name == "longitudinal" else ("v", "p", "r", "phi"))}
    mx = max(abs(m["abs_multiplier"]) for s in ("longitudinal", "lateral") for m in out[s]["modes"])
    out["resolution"] = (f"the monodromy on the augmented state: the body's 8 states and the {hf.records} records of "
                         "the network's calls (hawksim.stability.history_floquet); the body modes, each a mode of the "
                         "map")
    out["coupling"] = float(hf.coupling)
    out["max_abs_multiplier"] = out["max_abs_resolved_multiplier"] = float(mx)
    out["records"] = int(hf.records)
    out["residual"] = float(hf.residual)
    out["wall_time_s"] = float(hf.wall_time_s)
    return out


def averaged_json(system) -> dict:
    """The contract's ``longitudinal`` / ``lateral`` blocks of an :class:`hawksim.stability.floquet.AveragedSystem`
    or of the averaged :class:`hawksim.stability.linear_model.LinearModel` (``map="averaged"``: A_long and A_lat its
    diagonal blocks) (cycle-averaged derivatives of one backend)."""
    from hawksim.stability.system import LAT_DERIVATIVES, LONG_DERIVATIVES, modes_json

    d = system.nondimensional
    if getattr(system, "map", None) == "averaged":
        A_long, A_lat = system.A[:4, :4], system.A[4:, 4:]
    else:
        A_long, A_lat = system.A_long, system.A_lat
    return {"longitudinal": {"derivatives": {k: d[k] for k in LONG_DERIVATIVES}, **modes_json(A_long)},
            "lateral": {"derivatives": {k: d[k] for k in LAT_DERIVATIVES}, **modes_json(A_lat)},
            "derivatives_dimensional": system.derivatives, "nondimensional": system.scalars}
