"""`hawksim predict`: the surrogate's cycle averages (L+, D+, M+, P+) for one kinematics at one speed."""

from __future__ import annotations

import math

from hawksim.cli.args import KINEMATICS_HELP, parse_kinematics, speed_arg
from hawksim.cli.loads_report import render_predict


NETWORK_FAMILIES = ("shipped", "reference")
"""Choices of --network: the keys of hawksim.backends.network.NETWORKS (not imported here: every command builds
this parser; tests/hawksim/test_surrogate_reference.py checks they agree)."""


def cmd_predict(args) -> dict:
    from hawksim.backends.network import load_for_speed

    sur = load_for_speed(args.model, args.speed, args.network)
    import numpy as np

    with np.errstate(all="ignore"):  # an overflow is reported below, in one line
        out = sur.predict_kinematics(args.kinematics, args.speed)
    bad = [f"{k} = {v}" for k, v in out.items() if not math.isfinite(v)]
    if bad:  # finite weights can still overflow (a crafted file: weights x 1e300)
        raise FloatingPointError(f"the network {args.model or args.network!r} gives {', '.join(bad)} at these "
                                 "kinematics (no result)")
    out.update({"speed": args.speed, "kinematics": args.kinematics.to_edge(),
                "chi_deg": math.degrees(args.kinematics.chi),
                "model": sur.meta.get("command", args.model or args.network),
                "network": "file" if args.model else args.network,
                "model_speed": sur.inputs.speed})
    return out


def register(sub) -> None:
    p = sub.add_parser("predict", help="the surrogate's cycle-averaged L+, D+, M+, P+ for one kinematics")
    p.add_argument("--speed", type=speed_arg, required=True, help="ascent speed V [m/s], 0 to 2")
    p.add_argument("--kinematics", type=parse_kinematics, required=True,
                   help=KINEMATICS_HELP)
    which = p.add_mutually_exclusive_group()
    which.add_argument("--model", help="surrogate file (.safetensors; default: the shipped network for V)")
    which.add_argument("--network", choices=NETWORK_FAMILIES, default="shipped",
                       help="family of shipped networks (hawksim.backends.network.NETWORKS): shipped (trained on the "
                            "training lattice's labels; the default) or reference (plus a correction trained on "
                            "`hawksim aero`'s default-lattice labels: mean |error| against it 0.010-0.023 in L+ and "
                            "P+ at held-out kinematics, docs/surrogate.md)")
    p.add_argument("--json", action="store_true")
    p.set_defaults(func=cmd_predict, human=render_predict)
