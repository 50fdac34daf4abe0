"""`hawksim predict`: the surrogate's cycle averages (L+, D+, M+, P+) for one kinematics at one speed."""

from __future__ import annotations

import math

from hawksim.cli.args import KINEMATICS_HELP, add_insect_arg, parse_kinematics, speed_arg
from hawksim.cli.loads_report import render_predict


NETWORK_FAMILIES = ("shipped", "reference")
"""Choices of --network: the keys of hawksim.backends.network.NETWORKS (not imported here: every command builds
this parser; tests/hawksim/test_surrogate_reference.py checks they agree)."""


NETWORK_HELP = ("the network: a family of shipped networks (hawksim.backends.network.NETWORKS: shipped, trained on the "
                "training lattice's labels; or reference, plus a correction trained on `hawksim aero`'s "
                "default-lattice labels: mean |error| against it 0.014-0.032 in L+ and 0.013-0.024 in P+ at "
                "held-out kinematics, docs/surrogate.md), or a network file (.safetensors)")
"""Help text of --network in `predict` and `trim`."""

MODEL_DEPRECATED = ("--model FILE is deprecated here: use --network FILE (--model names an MJCF model in `hawksim "
                    "fly`; --insect chooses the insect)")
"""The note printed when `predict` or `trim` is given the old spelling --model for a network file."""


def add_network_args(p, default: str | None) -> None:
    """``--network NAME|FILE`` (a family of :data:`NETWORK_FAMILIES` or a network file) and the deprecated
    ``--model FILE`` (the same as ``--network FILE``), mutually exclusive."""
    which = p.add_mutually_exclusive_group()
    which.add_argument("--network", metavar="NAME|FILE", default=default,
                       help=NETWORK_HELP + f" (default: {default or 'shipped'})")
    which.add_argument("--model", help="deprecated spelling of --network FILE")


def network_choice(args) -> tuple[str | None, str]:
    """(network file or None, family) of ``--network``/``--model``; --model prints :data:`MODEL_DEPRECATED`. Sets
    ``args.model`` to the file (the outputs' ``model`` and ``network`` keys read it)."""
    import sys

    if args.model is not None:
        print(f"hawksim {args.command}: {MODEL_DEPRECATED}", file=sys.stderr)
    elif args.network is not None and args.network not in NETWORK_FAMILIES:
        args.model, args.network = args.network, None
    args.network = args.network or "shipped"
    return args.model, args.network


def insect_scale(args) -> float:
    """P0 of the default insect over ``--insect``'s (1 without --insect): the network's P+ is in the default insect's
    P0. ValueError (:func:`hawksim.trim.search.surrogate_insect`) for an insect whose morphology is not the default's
    (the networks' training insect)."""
    if getattr(args, "insect", None) is None:
        return 1.0
    from hawksim.insect.folder import default_insect
    from hawksim.trim.search import surrogate_insect

    return default_insect().P0 / surrogate_insect(args.insect).P0


def cmd_predict(args) -> dict:
    from hawksim.backends.network import load_for_speed

    path, network = network_choice(args)
    p_scale = insect_scale(args)
    sur = load_for_speed(path, args.speed, network)
    import numpy as np

    with np.errstate(all="ignore"):  # an overflow is reported below, in one line
        out = sur.predict_kinematics(args.kinematics, args.speed)
    if p_scale != 1.0:
        out["P_plus"] *= p_scale
    bad = [f"{k} = {v}" for k, v in out.items() if not math.isfinite(v)]
    if bad:  # finite weights can still overflow (a crafted file: weights x 1e300)
        raise FloatingPointError(f"the network {args.model or args.network!r} gives {', '.join(bad)} at these "
                                 "kinematics (no result)")
    out.update({"speed": args.speed, "kinematics": args.kinematics.to_edge(),
                "chi_deg": math.degrees(args.kinematics.chi),
                "model": sur.meta.get("command", args.model or args.network),
                "network": "file" if args.model else args.network,
                "model_speed": sur.inputs.speed})
    return out | ({} if args.insect is None else {"insect": args.insect.name})


def register(sub) -> None:
    p = sub.add_parser("predict", help="the surrogate's cycle-averaged L+, D+, M+, P+ for one kinematics")
    p.add_argument("--speed", type=speed_arg, required=True, help="ascent speed V [m/s], 0 to 2")
    p.add_argument("--kinematics", type=parse_kinematics, required=True,
                   help=KINEMATICS_HELP)
    add_network_args(p, "reference")  # the one that follows `hawksim aero` (issue 49's target), docs/surrogate.md
    add_insect_arg(p, "; its morphology must be the default insect's (the networks' training insect); P+ is in its P0")
    p.add_argument("--json", action="store_true")
    p.set_defaults(func=cmd_predict, human=render_predict)
