"""The stability report of one ascent speed: derivatives, A matrices and modes in the CLI contract's JSON
(`hawksim stability`; also the input of the paper's Figs. 15-19 in :mod:`hawksim.paper.studies`)."""

from __future__ import annotations


def stability_report(speed: float, *, kinematics=None, client=None) -> dict:
    """The CLI contract's JSON for one ascent speed (also used by the studies of `hawksim reproduce`); client: a
    dask.distributed client whose workers run the UVLM cases
    (:func:`hawksim.stability.derivatives.dimensional_derivatives`)."""
    from hawksim.stability.derivatives import dimensional_derivatives, mass_properties
    from hawksim.stability.system import LAT_DERIVATIVES, LONG_DERIVATIVES, modes_json, nondimensional_system
    from hawksim.trim.tables import shipped_trim

    trim = shipped_trim(speed) if kinematics is None else None
    kin = kinematics if kinematics is not None else trim.kinematics
    runs = dimensional_derivatives(kin, speed, client=client)
    mp = mass_properties(kin)
    d, A_long, A_lat, scalars = nondimensional_system(kin, speed, runs.derivatives, mp)
    return {
        "speed": speed,
        "trim": {"kinematics": kin.to_edge(), "source": trim.source if kinematics is None else "given"},
        "longitudinal": {"derivatives": {k: d[k] for k in LONG_DERIVATIVES}, **modes_json(A_long)},
        "lateral": {"derivatives": {k: d[k] for k in LAT_DERIVATIVES}, **modes_json(A_lat)},
        "derivatives_dimensional": runs.derivatives,
        "nondimensional": scalars,
        "mass_properties": vars(mp),
        "disturbances": runs.deltas,
        "resolution": runs.resolution.to_dict(),
        "wall_time_s": runs.wall_time_s,
    }
