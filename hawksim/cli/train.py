"""`hawksim train`: the surrogate network trained by Levenberg-Marquardt on a UVLM data set."""

from __future__ import annotations

import shlex

from hawksim.cli.args import UsageError, positive_int_arg, seconds_arg, seed_arg, speed_arg, writable_file
from hawksim.cli.progress import progress_for


def cmd_train(args) -> dict:
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
    status("reading the samples")  # the bar opens once the options are checked (a bad one: one line, no bar)
    table = read_samples(args.data, speed=speed, seed=args.data_seed)
    x = table.x if speed is not None else np.column_stack([table.x, table.speed])
    cfg = TrainConfig(hidden=args.hidden, max_iter=args.max_iter, time_limit_s=args.time_limit)
    command = ["hawksim", "train", "--data", str(args.data), "--out", str(args.out), "--seed", str(args.seed),
               "--hidden", str(args.hidden), "--max-iter", str(args.max_iter), "--time-limit", f"{args.time_limit:g}"]
    command += ["--all-speeds"] if speed is None else ["--speed", f"{speed:g}"]
    command += [] if args.data_seed is None else ["--data-seed", str(args.data_seed)]
    meta = {"command": shlex.join(command), "data": str(args.data),
            "data_sha256": file_sha256(args.data, speed, args.data_seed),
            "n_samples": int(len(table.y)),
            "speeds": speeds if speed is None else [speed],
            "n_diverged_left_out": table.n_diverged, "n_unsettled_left_out": table.n_unsettled}
    if args.data_seed is not None:
        meta["data_seed"] = args.data_seed
    r = train(x, table.y, InputDefinition.for_speed(speed), seed=args.seed, cfg=cfg, meta=meta, progress=progress,
              groups=np.round(table.speed * 1000).astype(int) if speed is None else None, status=status)
    if bar is not None:
        bar.close()
    r.surrogate.save(args.out)
    if args.validation_png:
        from hawksim.surrogate.plots import validation_figure

        validation_figure(r, args.validation_png)
    return {"n_train": r.n_train, "n_val": r.n_val, "n_test": r.n_test,
            "rmse": r.test_scores.rmse, "r2": r.test_scores.r2, "iterations": r.iterations,
            "stopped_by": r.surrogate.meta.get("stopped_by"),
            "speed": speed, "out": str(args.out), "wall_time_s": r.wall_time_s}


def register(sub) -> None:
    p = sub.add_parser("train", help="train the surrogate (7-500-4 sigmoid network, Levenberg-Marquardt)")
    p.add_argument("--data", required=True, help="SQLite data set from `hawksim dataset`")
    p.add_argument("--out", type=writable_file, required=True, help="model file to write (.safetensors)")
    p.add_argument("--seed", type=seed_arg, default=0, help="seed of the split and the initial weights (0)")
    which = p.add_mutually_exclusive_group()
    which.add_argument("--speed", type=speed_arg, help="train the network of this speed (file with several speeds)")
    which.add_argument("--all-speeds", action="store_true",
                   help="one network with the ascent speed as an 8th input, on all speeds in the file")
    p.add_argument("--data-seed", type=seed_arg, help="use only the samples drawn with this seed")
    p.add_argument("--hidden", type=positive_int_arg("hidden"), default=500, help="hidden sigmoid units (500)")
    p.add_argument("--max-iter", type=positive_int_arg("max-iter"), default=300, help="LM iterations at most (300)")
    p.add_argument("--time-limit", type=seconds_arg, default=3600.0,
                   help="stop after this many seconds, keeping the best weights (3600)")
    p.add_argument("--validation-png", type=writable_file,
                   help="write the held-out scatter plot (PNG at 300 dpi, and a PDF beside it)")
    p.add_argument("--no-progress", action="store_true")
    p.add_argument("--json", action="store_true")
    p.set_defaults(func=cmd_train)
