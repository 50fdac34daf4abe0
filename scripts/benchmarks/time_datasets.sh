#!/bin/bash
# Issue 23 item 5: the held-body data sets generated fresh on the 2 cores and timed (the route of the reference
# surrogate, issue 22 item 3): 5 x 3000 samples at the training lattice (the paper's set, the shipped networks'
# labels), then 5 x 1000 at the reference lattice (`hawksim aero`'s default: the correction network's labels).
# Seeded (seed 0); writes OUT/training.sqlite, OUT/reference.sqlite, OUT/run.log, then prints a JSON summary.
#   scripts/benchmarks/time_datasets.sh /tmp/ds      (75 min on 2 workers at load ~2.4, 2026-12-02)
set -euo pipefail
out=${1:?usage: time_datasets.sh OUT_DIR}
cd "$(dirname "$0")/../.."
mkdir -p "$out"
export NUMBA_NUM_THREADS=1 OMP_NUM_THREADS=1
log=$out/run.log
for res in training reference; do
  n=3000; [ "$res" = reference ] && n=1000
  for v in 0 0.5 1 1.5 2; do
    echo "$(date -u +%FT%TZ) start $res V=$v n=$n load $(cat /proc/loadavg)" >> "$log"
    .venv/bin/hawksim dataset --speed $v --samples $n --out "$out/$res.sqlite" --seed 0 --resolution $res \
      --workers 2 --no-progress --json >> "$log" 2>&1
    echo >> "$log"
  done
done
echo "$(date -u +%FT%TZ) done load $(cat /proc/loadavg)" >> "$log"
.venv/bin/python scripts/benchmarks/time_datasets_summary.py "$log"
