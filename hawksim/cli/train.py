"""`hawksim train`: the cycle-mean surrogate network trained by Levenberg-Marquardt on a UVLM data set, or
(``--kind step``) the per-step surrogate trained by Adam on UVLM flights (:mod:`hawksim.surrogate.step_train`)."""

from __future__ import annotations

import argparse
import shlex
from pathlib import Path

from hawksim import interrupts
from hawksim.cli.args import (UsageError, add_insect_arg, positive_int_arg, refuse_insect, seconds_arg, seed_arg,
                              speed_arg, writable_file)
from hawksim.cli.progress import progress_for
from hawksim.cli.surrogate_report import render_train


MAX_LAG_BEATS = 8
"""Longest --lags [wingbeats]: the flights of `hawksim dataset --kind flights` are
:data:`hawksim.surrogate.flights.FLIGHT_BEATS` (8) beats long, and a longer lag would read every row's history from
the flight's first row (1e308 overflowed the conversion to steps)."""
MAX_LAYER_WIDTH = 4096
"""Widest --layers entry: ~20x the shipped per-step network's 192; a 4096 x 4096 float32 layer is 64 MB, four times
that with Adam's state and its gradient, per ensemble member (200000,200000 asked torch for 160 GB)."""
MAX_LAYERS = 16
"""Most hidden layers of --layers: five times the shipped network's 3 (a bound on the parameters and the time per
epoch, like the width's)."""
MAX_WEIGHT_DECAY = 1.0
"""Largest --weight-decay: AdamW shrinks the weights by lr x decay each step; 1 is 100x the largest value tried
(1e-2, docs/surrogate.md), past it the weights decay faster than they learn."""


def _floats(text: str) -> tuple[float, ...]:
    """--lags: comma-separated lags in wingbeats, each finite, > 0 and <= MAX_LAG_BEATS."""
    try:
        v = tuple(float(x) for x in text.split(",") if x.strip())
    except ValueError:
        raise argparse.ArgumentTypeError(f"--lags {text!r} is not a comma-separated list of numbers") from None
    for x in v:
        if not (0 < x <= MAX_LAG_BEATS):  # NaN fails too
            raise argparse.ArgumentTypeError(f"--lags {text!r}: each lag must be > 0 and at most {MAX_LAG_BEATS} "
                                             f"wingbeats (a flight's length), not {x:g}")
    return v


def _ints(text: str) -> tuple[int, ...]:
    """--layers: comma-separated hidden-layer widths, 1 to MAX_LAYER_WIDTH each, at most MAX_LAYERS of them."""
    try:
        v = tuple(int(x) for x in text.split(",") if x.strip())
    except ValueError:
        raise argparse.ArgumentTypeError(f"--layers {text!r} is not a comma-separated list of integers") from None
    if not v or any(not 1 <= x <= MAX_LAYER_WIDTH for x in v):
        raise argparse.ArgumentTypeError(f"--layers {text!r}: layer widths must be integers from 1 to "
                                         f"{MAX_LAYER_WIDTH}")
    if len(v) > MAX_LAYERS:
        raise argparse.ArgumentTypeError(f"--layers {text!r}: at most {MAX_LAYERS} hidden layers")
    return v


def _weight_decay(text: str) -> float:
    """--weight-decay: finite, from 0 to MAX_WEIGHT_DECAY."""
    try:
        v = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"--weight-decay {text!r} is not a number") from None
    if not 0 <= v <= MAX_WEIGHT_DECAY:  # inf and NaN fail too
        raise argparse.ArgumentTypeError(f"--weight-decay {text} must be from 0 to {MAX_WEIGHT_DECAY:g}")
    return v


def cmd_train_step(args) -> dict:
    """`hawksim train --kind step`: the per-step surrogate on the flights of ``--data``."""
    import sys

    import numpy as np

    import torch

    from hawksim.surrogate.flights import WARM_BEATS
    from hawksim.surrogate.step_train import TrainConfig, fit

    torch.set_num_threads(1)
    cfg = TrainConfig(hidden=args.layers, lags=args.lags, epochs=args.max_iter, seed=args.seed,
                      max_seconds=args.time_limit, weight_decay=args.weight_decay, ensemble=args.ensemble,
                      age_beats=WARM_BEATS if args.wake_age else 0.0)
    command = ["hawksim", "train", "--kind", "step", "--data", str(args.data), "--out", str(args.out), "--seed",
               str(args.seed), "--layers", ",".join(map(str, args.layers)), "--lags", ",".join(f"{v:g}" for v in
                                                                                           args.lags),
               "--max-iter", str(args.max_iter), "--time-limit", f"{args.time_limit:g}",
               "--weight-decay", f"{args.weight_decay:g}", "--ensemble", str(args.ensemble)]
    if args.wake_age:
        command.append("--wake-age")
    for p in args.extra_data or ():
        command += ["--extra-data", str(p)]
    net, sc = fit(args.data, cfg, command=shlex.join(command), extra=tuple(args.extra_data or ()),
                  log=None if args.no_progress else lambda s: print(s, file=sys.stderr, flush=True))
    interrupts.begin_work()  # until the network is written, a Ctrl-C leaves at once (nothing to clean up)
    net.save(args.out)
    return {"kind": "step", "n_train": net.meta["n_train_rows"], "n_val": net.meta["n_val_rows"],
            "n_test": sc["n_rows"], "test_flights": sc["n_flights"], "r2": sc["r2"], "r2_min": sc["r2_min"],
            "cycle_mean_abs_error": sc["cycle_mean_abs_error"], "cycle_mean_max_error": sc["cycle_mean_max_error"],
            "r2_body": sc["r2_body"], "epochs": net.meta["history"]["epochs"], "out": str(args.out),
            "wall_time_s": float(np.sum(net.meta["history"]["wall_s"]))}


def _save_with_figure(net, out, result, png) -> None:
    """Write the network to ``out`` and, with ``png``, its validation figure, all or nothing (issue 53, defect 14: a
    failed figure left the network behind): the network goes to a temporary file beside its target, the figure is
    drawn and written (PNG, then PDF), and only then the network is renamed into place. On a failure the temporary
    network and any figure file this command created are removed (a figure file that existed before and was already
    replaced stays replaced: each is written whole), and the error is raised naming ``out`` or the figure."""
    import os

    from hawksim.atomic import keep_mode, output_target, temporary_beside

    if not png:
        net.save(out)
        return
    from hawksim.surrogate.plots import validation_figure

    target = output_target(out, "surrogate")
    tmp = temporary_beside(target)
    figures = [Path(png).with_suffix(ext) for ext in (".png", ".pdf")]
    new_figures = [f for f in figures if not os.path.lexists(f)]
    done = False
    try:
        try:
            net.save(tmp)
        except OSError as exc:
            raise OSError(exc.errno, str(exc.strerror).replace(str(tmp), str(out))) from None
        validation_figure(result, png)
        keep_mode(tmp, target)
        try:
            os.replace(tmp, target)
        except OSError as exc:
            raise OSError(exc.errno, f"cannot write surrogate {out}: {exc.strerror or exc}") from None
        done = True
    finally:
        tmp.unlink(missing_ok=True)
        if not done:
            for f in new_figures:
                f.unlink(missing_ok=True)


def cmd_train(args) -> dict:
    refuse_insect(args, "train", "a network is trained on a data set of the default insect (the data set holds no "
                  "other insect's labels yet; docs/insects.md)")
    bar = progress_for(args, "train (LM)", "it")
    state = {"done": 0, "mse": {}}  # LM iterations done, the last train / validation errors

    def status(text: str) -> None:  # the stage in progress, from the start (an LM iteration takes 20-40 s)
        if bar is not None:
            bar(state["done"], args.max_iter, **state["mse"], stage=text)

    def progress(i, n, train_mse, val_mse):
        state["done"], state["mse"] = i, {"train": f"{train_mse:.2e}", "val": f"{val_mse:.2e}"}
        if bar is not None:
            bar(i, n, **state["mse"])

    import numpy as np

    if args.kind == "step":
        if args.validation_png:  # issue 53, defect 14: it was ignored
            raise UsageError("--validation-png does not apply to --kind step: it plots the cycle-mean network's "
                             "held-out samples")
        return cmd_train_step(args)
    if args.extra_data:
        raise UsageError("--extra-data needs --kind step (the per-step surrogate's flights)")
    if args.wake_age:
        raise UsageError("--wake-age needs --kind step (the per-step surrogate's flights)")

    from hawksim.backends.network import InputDefinition
    from hawksim.surrogate.dataset import file_sha256, read_samples, speeds_in
    from hawksim.surrogate.train import TrainConfig, train

    speeds = speeds_in(args.data)
    if not speeds:
        raise UsageError(f"--data {args.data}: the data set holds no usable samples")
    if args.all_speeds:
        speed = None
    elif args.speed is not None:
        if not any(abs(v - args.speed) < 1e-6 for v in speeds):
            raise UsageError(f"--speed {args.speed:g}: the data set holds speeds {speeds} m/s only")
        speed = args.speed
    elif len(speeds) == 1:
        speed = speeds[0]
    else:
        raise UsageError(f"--data {args.data} holds speeds {speeds} m/s: pass --speed V or --all-speeds")
    if args.base is not None and args.validation_png:
        raise UsageError("--validation-png plots a network's own targets; with --base those are the corrections: "
                         "score the folded network with scripts/studies/surrogate_vs_reference.py instead")
    status("reading the samples")  # the bar opens once the options are checked (a bad one: one line, no bar)
    table = read_samples(args.data, speed=speed, seed=args.data_seed)
    x = table.x if speed is not None else np.column_stack([table.x, table.speed])
    cfg = TrainConfig(hidden=args.hidden, max_iter=args.max_iter, time_limit_s=args.time_limit)
    command = ["hawksim", "train", "--data", str(args.data), "--out", str(args.out), "--seed", str(args.seed),
               "--hidden", str(args.hidden), "--max-iter", str(args.max_iter), "--time-limit", f"{args.time_limit:g}"]
    command += ["--all-speeds"] if speed is None else ["--speed", f"{speed:g}"]
    command += [] if args.data_seed is None else ["--data-seed", str(args.data_seed)]
    command += [] if args.base is None else ["--base", str(args.base)]
    base = base_meta = None
    y = table.y
    if args.base is not None:  # multi-fidelity: train a correction on the labels minus the base's prediction
        from hawksim.backends.network import load, shipped_path
        from hawksim.surrogate.multifidelity import correction_targets

        base_path = shipped_path(speed) if args.base == "shipped" else args.base
        base = load(base_path, expect=InputDefinition.for_speed(speed))
        base_meta = {"path": str(base_path) if args.base != "shipped" else f"shipped:{Path(base_path).name}",
                     "file_sha256": _file_sha256(base_path), "command": base.meta.get("command"),
                     "hidden": base.hidden}
        status("the base network's predictions")
        y = correction_targets(base, x, table.y)
    meta = {"command": shlex.join(command), "data": str(args.data),
            "data_sha256": file_sha256(args.data, speed, args.data_seed),
            "n_samples": int(len(table.y)),
            "speeds": speeds if speed is None else [speed],
            "n_diverged_left_out": table.n_diverged, "n_unsettled_left_out": table.n_unsettled}
    if args.data_seed is not None:
        meta["data_seed"] = args.data_seed
    r = train(x, y, InputDefinition.for_speed(speed), seed=args.seed, cfg=cfg, meta=meta, progress=progress,
              groups=np.round(table.speed * 1000).astype(int) if speed is None else None, status=status)
    if bar is not None:
        bar.close()
    net, test_scores = r.surrogate, r.test_scores
    if base is not None:
        net, test_scores = _fold_correction(base, base_meta, r)
    interrupts.begin_work()  # until the network is written, a Ctrl-C leaves at once (nothing to clean up)
    _save_with_figure(net, args.out, r, args.validation_png)
    return {"n_train": r.n_train, "n_val": r.n_val, "n_test": r.n_test,
            "rmse": test_scores.rmse, "r2": test_scores.r2, "iterations": r.iterations,
            "stopped_by": r.surrogate.meta.get("stopped_by"), "hidden": net.hidden,
            "speed": speed, "out": str(args.out), "wall_time_s": r.wall_time_s}


def _file_sha256(path) -> str:
    import hashlib

    return hashlib.sha256(Path(path).read_bytes()).hexdigest()


def _fold_correction(base, base_meta: dict, r):
    """The base network plus the trained correction ``r.surrogate`` as one network, its metadata and its held-out
    scores against the labels themselves (``r``'s scores are of the correction against the differences: the same
    RMSE, another R^2)."""
    from hawksim.surrogate.multifidelity import fold
    from hawksim.surrogate.train import scores

    corr = r.surrogate
    speed = r.test_x[:, 7] if base.inputs.speed is None else None
    labels = r.test_y + base.predict(r.test_x[:, :7], speed)
    m = dict(corr.meta)
    m.update(route="multi-fidelity", base=base_meta, correction_hidden=corr.hidden, hidden=base.hidden + corr.hidden,
             correction_test_rmse=m.pop("test_rmse"), correction_test_r2=m.pop("test_r2"))
    net = fold(base, corr, meta=m)
    sc = scores(labels, net.predict(r.test_x[:, :7], speed))
    base_sc = scores(labels, base.predict(r.test_x[:, :7], speed))
    net.meta.update(test_rmse=sc.rmse, test_r2=sc.r2, base_test_rmse=base_sc.rmse, base_test_r2=base_sc.r2)
    return net, sc


def register(sub) -> None:
    p = sub.add_parser("train", help="train the cycle-mean surrogate (7-500-4 sigmoid network, Levenberg-Marquardt) "
                                     "or, with --kind step, the per-step surrogate (tanh MLP, Adam)")
    p.add_argument("--kind", choices=("mean", "step"), default="mean",
                   help="mean: the cycle-mean network on held-body samples (--aero surrogate-mean); step: the "
                        "per-step network on UVLM flights from `hawksim dataset --kind flights` (--aero surrogate)")
    p.add_argument("--layers", type=_ints, default=(128, 128, 128),
                   help="--kind step: hidden tanh layer widths (128,128,128)")
    p.add_argument("--lags", type=_floats, default=(),
                   help="--kind step: history lags of the body state [wingbeats], e.g. 0.5,1 (none)")
    p.add_argument("--weight-decay", type=_weight_decay, default=0.0, help="--kind step: AdamW weight decay (0: Adam)")
    p.add_argument("--ensemble", type=positive_int_arg("ensemble"), default=1,
                   help="--kind step: networks trained from different seeds, folded into one (1)")
    p.add_argument("--wake-age", action="store_true",
                   help="--kind step: add the wake's age (wingbeats since the launch from no wake, saturating at the "
                        "flights' warm-up) as an input and train on the warm-up rows too (docs/surrogate.md)")
    p.add_argument("--data", required=True, help="SQLite data set from `hawksim dataset`")
    p.add_argument("--extra-data", action="append", metavar="PATH",
                   help="--kind step: another flights data set (e.g. --family wide) whose training and validation "
                        "flights join --data's (each file split on its own; repeatable)")
    p.add_argument("--out", type=writable_file, required=True, help="model file to write (.safetensors)")
    p.add_argument("--seed", type=seed_arg, default=0, help="seed of the split and the initial weights (0)")
    which = p.add_mutually_exclusive_group()
    which.add_argument("--speed", type=speed_arg, help="train the network of this speed (file with several speeds)")
    which.add_argument("--all-speeds", action="store_true",
                   help="one network with the ascent speed as an 8th input, on all speeds in the file")
    p.add_argument("--data-seed", type=seed_arg, help="use only the samples drawn with this seed")
    p.add_argument("--base", help="multi-fidelity: train a correction on the labels minus this network's prediction "
                                  "and write base + correction as one network ('shipped': the shipped network of "
                                  "--speed, or the speed-input one with --all-speeds; or a .safetensors file); "
                                  "hawksim.surrogate.multifidelity")
    p.add_argument("--hidden", type=positive_int_arg("hidden"), default=500, help="hidden sigmoid units (500)")
    p.add_argument("--max-iter", type=positive_int_arg("max-iter"), default=300,
                   help="LM iterations (--kind step: epochs) at most (300)")
    p.add_argument("--time-limit", type=seconds_arg, default=3600.0,
                   help="stop after this many seconds, keeping the best weights (3600)")
    p.add_argument("--validation-png", type=writable_file,
                   help="write the held-out scatter plot (PNG at 300 dpi, and a PDF beside it)")
    p.add_argument("--no-progress", action="store_true")
    add_insect_arg(p, "; only the default insect yet (the data set's)")
    p.add_argument("--json", action="store_true")
    # it writes nothing before the network: a Ctrl-C until then leaves at once, wherever it lands (the import of
    # torch takes 2-4 s on two loaded cores, and a Ctrl-C in an import would wait for its end: hawksim.interrupts)
    p.set_defaults(func=cmd_train, work_begins_in_command=True, human=render_train)
