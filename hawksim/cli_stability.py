"""`hawksim stability`: UVLM stability derivatives at the trim, A_long and A_lat, eigen-analysis."""

from __future__ import annotations

from hawksim.cli import positive_int_arg, speed_arg


def stability_report(speed: float, *, kinematics=None, client=None) -> dict:
    """The CLI contract's JSON for one ascent speed (also used by the studies of `hawksim reproduce`); client: a
    dask.distributed client whose workers run the UVLM cases (`hawksim.derivatives.dimensional_derivatives`)."""
    from hawksim.derivatives import dimensional_derivatives, mass_properties
    from hawksim.stability import LAT_DERIVATIVES, LONG_DERIVATIVES, modes_json, nondimensional_system
    from hawksim.trim_table import trim_kinematics, trim_source

    kin = kinematics if kinematics is not None else trim_kinematics(speed)
    runs = dimensional_derivatives(kin, speed, client=client)
    mp = mass_properties(kin)
    d, A_long, A_lat, scalars = nondimensional_system(kin, speed, runs.derivatives, mp)
    return {
        "speed": speed,
        "trim": {"kinematics": kin.to_edge(), "source": trim_source() if kinematics is None else "given"},
        "longitudinal": {"derivatives": {k: d[k] for k in LONG_DERIVATIVES}, **modes_json(A_long)},
        "lateral": {"derivatives": {k: d[k] for k in LAT_DERIVATIVES}, **modes_json(A_lat)},
        "derivatives_dimensional": runs.derivatives,
        "nondimensional": scalars,
        "mass_properties": vars(mp),
        "disturbances": runs.deltas,
        "resolution": runs.resolution.to_dict(),
        "wall_time_s": runs.wall_time_s,
    }


def cmd_stability(args) -> dict:
    from hawksim.cluster import dask_client
    from hawksim.kinematics import Kinematics

    kin = args.kinematics if isinstance(args.kinematics, Kinematics) else None
    if args.workers == 1 and not args.scheduler:
        return stability_report(args.speed, kinematics=kin)
    with dask_client(args.scheduler, args.workers) as client:
        return stability_report(args.speed, kinematics=kin, client=client)


def register(sub) -> None:
    from hawksim.cli import parse_kinematics

    p = sub.add_parser("stability", help="stability derivatives, A matrices and modes at the trim (UVLM)")
    p.add_argument("--speed", type=speed_arg, required=True, help="ascent speed V [m/s], 0 to 2")
    p.add_argument("--kinematics", type=parse_kinematics, help="use these kinematics instead of the trim table")
    p.add_argument("--workers", type=positive_int_arg("workers"), default=None,
                   help="single-threaded worker processes for the 14 UVLM runs (default: the machine's cores; "
                        "1: run them in this process)")
    p.add_argument("--scheduler", help="address of a running Dask scheduler to run them on instead")
    p.add_argument("--json", action="store_true")
    p.set_defaults(func=cmd_stability)
