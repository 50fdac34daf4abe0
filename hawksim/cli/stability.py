"""`hawksim stability`: UVLM stability derivatives at the trim, A_long and A_lat, eigen-analysis."""

from __future__ import annotations

from hawksim.cli.args import parse_kinematics, positive_int_arg, speed_arg


def cmd_stability(args) -> dict:
    from hawksim.cluster import dask_client
    from hawksim.insect.kinematics import Kinematics
    from hawksim.stability.report import stability_report

    kin = args.kinematics if isinstance(args.kinematics, Kinematics) else None
    if args.workers == 1 and not args.scheduler:
        return stability_report(args.speed, kinematics=kin)
    with dask_client(args.scheduler, args.workers) as client:
        return stability_report(args.speed, kinematics=kin, client=client)


def register(sub) -> None:
    p = sub.add_parser("stability", help="stability derivatives, A matrices and modes at the trim (UVLM)")
    p.add_argument("--speed", type=speed_arg, required=True, help="ascent speed V [m/s], 0 to 2")
    p.add_argument("--kinematics", type=parse_kinematics, help="use these kinematics instead of the trim table")
    p.add_argument("--workers", type=positive_int_arg("workers"), default=None,
                   help="single-threaded worker processes for the 14 UVLM runs (default: the machine's cores; "
                        "1: run them in this process)")
    p.add_argument("--scheduler", help="address of a running Dask scheduler to run them on instead")
    p.add_argument("--json", action="store_true")
    p.set_defaults(func=cmd_stability)
