"""Study (issue 23): convect the far wake with its velocity on itself summed every K steps and held in between.
Measured, not shipped: at K = 2 the cycle averages already move by percents, 100-1000x issue 23's bound.

The idea. Most of a long free wake's convection cost is the old (far) wake acting on itself: with a 10-beat wake
and the newest beat called near, 81 % of the wake-on-wake pairs. If that velocity changed slowly, summing it every K
steps and holding it would cut the 10-beat-wake flight's pairs ~2.5x at K = 4 (the target of 1 wingbeat per wall
second on hosts whose lattice kernel gives ~2 G pairs/s: docs/performance.md).

The scheme (:class:`HeldFarWakeUVLM`). Each wing's wake lattice is split at corner row s into a near part (corner
rows 0..s, the trailing edge first) and a far part (rows s..), edge for edge (:func:`split_lattice`: every edge in
one part with its circulation and core, so the parts sum to the lattice). Every step the velocity at every wake
corner from the wings and the near part, and at the near corners from the far part, is the direct sum; the far
part's velocity at the far corners is summed every K steps and held in between, corner by corner (a step sheds one
row, so the split moves one row down with the corners it was made for). The wings' own velocities (solve, loads)
are untouched.

Sections (prints ONE JSON object):
* ``change_per_step``: why it fails. On the reference case (scripts/benchmarks/bench_uvlm.py: two flapping wings as
  mirror images, 8 x 16 rings, 25 Hz, 220 steps in 3 beats, free wake, hover), the direct far-on-far velocity of the
  same corners from one step to the next (split at row ``--near-rows`` and moved with the wake), relative to the
  largest far-on-far velocity: its largest and median change, steps 60-100.
* ``accuracy``: the cycle averages of the last beat with the hold at K = ``--intervals`` against the direct sum, on
  bench_treecode.py's three cases (the reference case: L, D, M, P; `hawksim aero`'s held-body evaluation at hover and
  2 m/s: L+, D+, M+, P+); relative differences and whether within issue 23's bound (1e-4).
* ``flight``: `hawksim fly --aero uvlm --speed 1 --cycles 20 --wake-cycles 10` open loop, the direct sum against
  K = ``--flight-interval``: each beat's mean vertical speed, their differences, the loop's wall times.

    python -m scripts.studies.far_wake_hold [--near-rows 40] [--intervals 2 4 8] [--flight-interval 4]
        [--sections change_per_step accuracy flight] [--out FILE]
"""

from __future__ import annotations

import argparse
import contextlib
import sys

import numpy as np

from scripts.benchmarks.bench_treecode import BOUND, accuracy_cases  # noqa: I001  (imports aero first)

import aero.uvlm as aero_uvlm  # noqa: E402
import hawksim.backends.uvlm as backend_uvlm  # noqa: E402
from aero.lattice import Lattice  # noqa: E402
from aero.uvlm import UVLM, UVLMConfig  # noqa: E402
from hawksim.jsonout import emit, host_info  # noqa: E402


def split_lattice(lat: Lattice, s: int) -> tuple[Lattice, Lattice]:
    """The near (corner rows 0..s) and far (corner rows s..r) parts of a wake lattice of r ring rows, 0 < s < r:
    near has the spanwise edges of rows 0..s (row s's with the lattice's net circulation and core) and the
    chordwise edges of ring rows 0..s-1; far the rest (row s's spanwise edges at zero circulation)."""
    far_span = np.array(lat.span_gamma[s:], dtype=float)
    far_span[0] = 0.0
    return (Lattice(lat.G[:s + 1], lat.span_gamma[:s + 1], lat.span_rc2[:s + 1], lat.chord_gamma[:s],
                    lat.chord_rc2[:s]),
            Lattice(lat.G[s:], far_span, lat.span_rc2[s:], lat.chord_gamma[s:], lat.chord_rc2[s:]))


class HeldFarWakeUVLM(UVLM):
    """The UVLM with the far wake's velocity on itself summed every ``interval`` steps and held in between (the
    module docstring); ``near_rows``: the split row at a sum. Float64 direct sums only (the config's wake_summation
    and wake_precision are not read). Class attributes, set by :func:`held_far_wake`."""

    interval = 1
    near_rows = 40

    def __init__(self, *a, **kw):
        super().__init__(*a, **kw)
        self._hold = None  # (step of the last sum, its split row, per wing the far corners' held velocity)

    def _convect(self, dt, rings, gammas, freestream, mirror) -> None:
        from aero.lattice import ring_lattice

        c = self.config
        rows = self.wakes[0].rows
        plan = None
        if c.free_wake and self.interval > 1 and rows:
            if self._hold is not None:
                j = self.step_count - self._hold[0]
                if 0 < j < self.interval and self._hold[1] + j < rows:
                    plan = (self._hold[1] + j, False)
            if plan is None and rows > self.near_rows:
                plan = (self.near_rows, True)
        if plan is None:
            self._hold = None
            return super()._convect(dt, rings, gammas, freestream, mirror)
        s, fresh = plan
        rcv = c.convection_core_chords * self.chord
        bound = [ring_lattice(G, g, rcv * rcv, rcv * rcv) for G, g in zip(rings, gammas)]
        parts = [split_lattice(lat, s) for lat in self._wake_lattices(r_attached=rcv)]
        far = [f for _, f in parts]
        grids = [w.vertices[1:] for w in self.wakes]  # corner rows 1..rows, (rows, ns + 1, 3) each
        pts = np.concatenate([g.reshape(-1, 3) for g in grids])
        v = freestream.at(pts) + self._induced(pts, bound + [n for n, _ in parts], mirror)
        if fresh:
            vf = self._induced(pts, far, mirror)
            v = v + vf
        else:
            vn = self._induced(np.concatenate([g[:s - 1].reshape(-1, 3) for g in grids]), far, mirror)
        held, off, off_near = [], 0, 0
        for w, g in enumerate(grids):
            n = g.shape[0] * g.shape[1]
            vw = v[off:off + n].reshape(g.shape)
            if fresh:
                held.append(vf[off:off + n].reshape(g.shape)[s - 1:].copy())
            else:
                m = (s - 1) * g.shape[1]
                vw[:s - 1] += vn[off_near:off_near + m].reshape(s - 1, g.shape[1], 3)
                vw[s - 1:] += self._hold[2][w][:g.shape[0] - s + 1]
                off_near += m
            self.wakes[w].vertices[1:] += vw * dt
            self.wakes[w].age += dt
            self.wakes[w].age[0] = 0.0
            off += n
        if fresh:
            self._hold = (self.step_count, s, held)


@contextlib.contextmanager
def uvlm_class(cls):
    """Within the block, every UVLM that aero.uvlm.run_prescribed and the UVLM backend build is a ``cls``."""
    saved = aero_uvlm.UVLM, backend_uvlm.UVLM
    aero_uvlm.UVLM = backend_uvlm.UVLM = cls
    try:
        yield
    finally:
        aero_uvlm.UVLM, backend_uvlm.UVLM = saved


def held_far_wake(interval: int, near_rows: int):
    """:func:`uvlm_class` with a :class:`HeldFarWakeUVLM` of these settings (interval 1: the direct sum, through the
    same class)."""
    return uvlm_class(type("Held", (HeldFarWakeUVLM,), {"interval": interval, "near_rows": near_rows}))


def _load():
    return host_info()["loadavg"]


def change_per_step(near_rows: int, steps: int = 100, first: int = 60) -> dict:
    """The direct far-on-far velocity's change per step on the reference case (split at near_rows, moved with
    the wake one row a step, re-split every 4 steps as the hold would; only steps whose split moved are compared),
    relative to the largest far-on-far velocity of the step."""
    from aero.uvlm_kinematics import two_wing_motion
    from scripts.benchmarks.bench_uvlm import reference_wing

    prev, largest, median = {}, [], []

    class Probe(UVLM):
        def _convect(self, dt, rings, gammas, freestream, mirror):
            rcv = self.config.convection_core_chords * self.chord
            k = self.step_count
            if k >= first and self.wakes[0].rows > near_rows + 4:
                s = near_rows + (k - first) % 4
                _, far = split_lattice(self._wake_lattices(r_attached=rcv)[0], s)
                g = self.wakes[0].vertices[1:]
                vf = self._induced(g.reshape(-1, 3), [far], mirror).reshape(g.shape)[s - 1:]
                if prev.get("step") == k - 1 and s > near_rows:
                    d = np.linalg.norm(vf[:len(prev["v"])] - prev["v"], axis=-1)
                    scale = np.linalg.norm(vf, axis=-1).max()
                    largest.append(float(d.max() / scale))
                    median.append(float(np.median(d) / scale))
                prev.update(step=k, v=vf)
            return super()._convect(dt, rings, gammas, freestream, mirror)

    t = np.linspace(0.0, 3 / 25.0 * steps / 220, steps)
    R, o, v, w = two_wing_motion(t, freq=25.0)
    with uvlm_class(Probe):
        aero_uvlm.run_prescribed([reference_wing()], UVLMConfig(), t, R[:, :1], o[:, :1], v[:, :1], w[:, :1],
                                 mirror_plane=(np.zeros(3), np.array([0.0, 1.0, 0.0])))
    return {"case": "reference", "steps": [first, steps], "near_rows": near_rows, "compared_steps": len(largest),
            "largest_change_over_largest_velocity": {"max": max(largest), "median": float(np.median(largest))},
            "median_change_over_largest_velocity": {"max": max(median), "median": float(np.median(median))}}


def accuracy(intervals, near_rows: int) -> dict:
    def held(k):
        def run(case, base):
            with held_far_wake(k, near_rows):
                return case(UVLMConfig(**base))
        return run

    return {"near_rows": near_rows, "bound": BOUND,
            "cases": accuracy_cases({str(k): held(k) for k in intervals}, "held")}


def flight(interval: int, near_rows: int, cycles: int = 20) -> dict:
    from hawksim.cli.fly import fly_named

    runs = {}
    for name, k in (("direct", 1), (f"held_{interval}", interval)):
        with held_far_wake(k, near_rows):
            fly_named(1.0, 1, "uvlm", wake_cycles=10, wake_summation="direct")  # warm-up
            load = _load()
            r = fly_named(1.0, cycles, "uvlm", wake_cycles=10, wake_summation="direct")
        runs[name] = {"interval": k, "loop_wall_s": round(r.wall_time_s, 2), "load_before": load,
                      "load_after": _load(),
                      "mean_vertical_speed_per_beat": [b["mean_vertical_speed"] for b in r.summary()["beats"]]}
    a, b = (runs[k]["mean_vertical_speed_per_beat"] for k in runs)
    walls = [runs[k]["loop_wall_s"] for k in runs]
    diff = [abs(x - y) for x, y in zip(a, b)]
    return {"speed_m_s": 1.0, "cycles": cycles, "wake_cycles": 10, "near_rows": near_rows, "runs": runs,
            "abs_difference_per_beat_m_s": diff,
            "first_beat_over_1e-4_m_s": next((i + 1 for i, d in enumerate(diff) if d > 1e-4), None),
            "wall_ratio_direct_over_held": round(walls[0] / walls[1], 3)}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--near-rows", type=int, default=40)
    ap.add_argument("--intervals", type=int, nargs="+", default=[2, 4, 8])
    ap.add_argument("--flight-interval", type=int, default=4)
    ap.add_argument("--sections", nargs="+", default=["change_per_step", "accuracy", "flight"],
                    choices=["change_per_step", "accuracy", "flight"])
    ap.add_argument("--out")
    a = ap.parse_args()
    out = {"command": "python -m scripts.studies.far_wake_hold " + " ".join(sys.argv[1:]), "began": host_info()}
    if "change_per_step" in a.sections:
        out["change_per_step"] = change_per_step(a.near_rows)
    if "accuracy" in a.sections:
        out["accuracy"] = accuracy(a.intervals, a.near_rows)
    if "flight" in a.sections:
        out["flight"] = flight(a.flight_interval, a.near_rows)
    emit(out, a.out, host=True)


if __name__ == "__main__":
    main()
