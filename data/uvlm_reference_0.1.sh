#!/bin/bash
# reference-lattice labels, seed 0 (same kinematics as data/uvlm_training_0.3.sqlite idx 0..n-1), round robin
# (run 2026-12-02 06:07-07:25 UTC; stopped and restarted twice between runs to compute the held-out labels, which
# resumes: the file holds samples 0-999 of seed 0 at each speed)
cd "$(dirname "$0")/.."  # the repository root
export NUMBA_NUM_THREADS=1 OMP_NUM_THREADS=1
for n in 100 200 400 600 800 1000; do
  for v in 0 0.5 1 1.5 2; do
    echo "$(date -u +%FT%TZ) start V=$v n=$n load $(cat /proc/loadavg)" >> data/uvlm_reference_0.1.log
    nice -n 10 .venv/bin/hawksim dataset --speed $v --samples $n --out data/uvlm_reference_0.1.sqlite --seed 0 \
      --n-chord 6 --n-span 12 --steps-per-cycle 40 --cycles 3 --workers 1 --no-progress --json >> data/uvlm_reference_0.1.log 2>&1
    echo >> data/uvlm_reference_0.1.log
  done
done
