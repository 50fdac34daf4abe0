"""`hawksim predict`: the surrogate's cycle averages (L+, D+, M+, P+) for one kinematics at one speed."""

from __future__ import annotations

import math

from hawksim.cli.args import KINEMATICS_HELP, parse_kinematics, speed_arg


def cmd_predict(args) -> dict:
    from hawksim.backends.network import load_for_speed

    sur = load_for_speed(args.model, args.speed)
    out = sur.predict_kinematics(args.kinematics, args.speed)
    out.update({"speed": args.speed, "kinematics": args.kinematics.to_edge(),
                "chi_deg": math.degrees(args.kinematics.chi),
                "model": sur.meta.get("command", args.model or "shipped"),
                "model_speed": sur.inputs.speed})
    return out


def register(sub) -> None:
    p = sub.add_parser("predict", help="the surrogate's cycle-averaged L+, D+, M+, P+ for one kinematics")
    p.add_argument("--speed", type=speed_arg, required=True, help="ascent speed V [m/s], 0 to 2")
    p.add_argument("--kinematics", type=parse_kinematics, required=True,
                   help=KINEMATICS_HELP)
    p.add_argument("--model", help="surrogate file (.safetensors; default: the shipped network for V)")
    p.add_argument("--json", action="store_true")
    p.set_defaults(func=cmd_predict)
