"""Where `hawksim train`'s time goes before and in its first Levenberg-Marquardt iterations (issue 18: the bar sat at
0 for ~30 s); prints ONE JSON object: the seconds of each stage that ``train(status=...)`` names, in order (the
torch import, the normalisation, each block of J^T J, each damped Cholesky try), with the host's load average (a
shared machine: compare only runs of one sitting).

    python scripts/benchmarks/bench_train_stages.py [--speed 1] [--iterations 2] [--out results/bench_train_stages.json]
"""

import argparse
import time

from hawksim.jsonout import emit


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--data", default="data/uvlm_training_0.3.sqlite")
    ap.add_argument("--speed", type=float, default=1.0)
    ap.add_argument("--iterations", type=int, default=2)
    ap.add_argument("--out")
    a = ap.parse_args()
    stages = []
    last = [time.perf_counter(), "reading the samples"]

    def status(text):
        now = time.perf_counter()
        stages.append({"stage": last[1], "seconds": round(now - last[0], 3)})
        last[:] = [now, text]

    from hawksim.backends.network import InputDefinition
    from hawksim.surrogate.dataset import read_samples

    table = read_samples(a.data, speed=a.speed)
    from hawksim.surrogate.train import TrainConfig, train

    r = train(table.x, table.y, InputDefinition.for_speed(a.speed), seed=0, cfg=TrainConfig(max_iter=a.iterations),
              status=status, progress=lambda i, n, tr, va: status(f"(iteration {i} done)"))
    status("end")
    first = next(i for i, s in enumerate(stages) if s["stage"] == "(iteration 1 done)")
    emit({"data": a.data, "speed": a.speed, "n_samples": int(len(table.y)), "n_train": r.n_train,
          "stages": [s for s in stages if not s["stage"].startswith("(")],
          "seconds_to_first_iteration_end": round(sum(s["seconds"] for s in stages[:first]), 2)}, a.out, host=True)


if __name__ == "__main__":
    main()
