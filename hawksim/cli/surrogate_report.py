"""What `hawksim dataset` and `hawksim train` print without ``--json``: how many samples (or flights) the file now
holds and how many this run computed, with the diverged and unsettled ones said plainly; the trained network's
held-out scores, its iterations and why it stopped, and where it was written. docs/output.md shows them."""

from __future__ import annotations

from hawksim.cli.summary import LOADS, line, num, resolution_text

STOPPED_BY = {"max_iter": "NOT converged: stopped at --max-iter", "early_stopping": "stopped early: the validation "
              "error stopped falling", "mu_max": "stopped: the damping reached its limit (a local minimum)",
              "time_limit": "NOT converged: stopped at --time-limit"}
"""Levenberg-Marquardt's ``stopped_by`` (hawksim.surrogate.train) in words."""


def render_dataset(out: dict) -> str:
    """`hawksim dataset`'s summary (samples, or with ``--kind flights`` flights; module docstring)."""
    if out.get("kind") == "flights":
        return render_flights(out)
    diverged, unsettled = out["diverged_new"], out["unsettled_new"]
    ok = out["new"] - diverged - unsettled
    labels = f"{ok} ok"
    if diverged:
        labels += f", {diverged} DIVERGED (a wake vortex crossed the lattice: stored, left out of training)"
    else:
        labels += ", 0 diverged"
    if unsettled:
        labels += (f", {unsettled} UNSETTLED (the averaged beat still changing by more than 0.1: stored, left out "
                   "of training)")
    else:
        labels += ", 0 unsettled"
    rate = f", {num(out['samples_per_s'], 3)} per s" if out["new"] else ""
    lines = [
        f"hawksim dataset: held-body samples at {out['speed']:g} m/s ascent, seed {out['seed']}; "
        f"{resolution_text(out['resolution'])}",
        line("file", f"{out['path']}: {out['samples']} samples of this speed and seed"),
        line("this run", (f"{out['new']} new samples in {out['wall_time_s']:.1f} s{rate}" if out["new"]
                          else "nothing new: the file already held them"))]
    if out["new"]:
        lines.append(line("new labels", labels))
    return "\n".join(lines)


def render_flights(out: dict) -> str:
    """`hawksim dataset --kind flights`'s summary."""
    diverged = out["diverged_new"]
    return "\n".join([
        f"hawksim dataset --kind flights: UVLM-in-the-loop free flights, family {out['family']}, seed {out['seed']}",
        line("file", f"{out['path']}: {out['samples']} flights"),
        line("this run", (f"{out['new']} new flights ({out['rows_new']} rows) in {out['wall_time_s']:.1f} s"
                          if out["new"] else "nothing new: the file already held them")),
        line("diverged", f"{diverged} of the new flights DIVERGED (stored, left out of training)" if diverged
             else "none of the new flights")])


def _scores(d: dict, digits: int = 3) -> str:
    return ", ".join(f"{name} {num(d[key], digits)}" for key, name in LOADS if key in d)


def render_train(out: dict) -> str:
    """`hawksim train`'s summary (the cycle-mean network, or with ``--kind step`` the per-step one)."""
    if out.get("kind") == "step":
        return render_train_step(out)
    speed = "all speeds (speed as an input)" if out["speed"] is None else f"{out['speed']:g} m/s"
    worse = [name for key, name in LOADS if out["r2"][key] < 0]
    lines = [f"hawksim train: cycle-mean surrogate for {speed}, {out['hidden']} hidden units, Levenberg-Marquardt",
             line("samples", f"{out['n_train']} training, {out['n_val']} validation, {out['n_test']} held out"),
             line("held-out R^2", _scores(out["r2"])
                  + (f"; {', '.join(worse)} WORSE than their mean (R^2 < 0)" if worse else "")),
             line("held-out RMSE", _scores(out["rmse"])),
             line("iterations", f"{out['iterations']} ({STOPPED_BY.get(out['stopped_by'], out['stopped_by'])}), "
                                f"{out['wall_time_s']:.1f} s"),
             line("written", str(out["out"]))]
    return "\n".join(lines)


def render_train_step(out: dict) -> str:
    """`hawksim train --kind step`'s summary."""
    return "\n".join([
        "hawksim train --kind step: per-step surrogate (tanh MLP, Adam)",
        line("data", f"{out['n_train']} training rows, {out['n_val']} validation, {out['n_test']} held out from "
                     f"{out['test_flights']} flights"),
        line("held-out R^2", f"per step, worst output {num(out['r2_min'], 3)} (wing axes)"),
        line("cycle means", f"mean |error| {_scores(out['cycle_mean_abs_error'])}; largest "
                            f"{_scores(out['cycle_mean_max_error'])}"),
        line("epochs", f"{out['epochs']} in {out['wall_time_s']:.1f} s"),
        line("written", str(out["out"]))])
