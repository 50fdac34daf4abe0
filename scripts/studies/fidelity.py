"""Sensitivity of the hawkmoth model to the feathering-axis position and the wing mass model (issue 22), and of
the UVLM to its tuned constants.

Morphology variants (:class:`hawksim.insect.morphology.Morphology`; body, planform and hinge as the default):
feathering axis at 25 % of the local chord (the default), 10 %, and on the leading edge (``Morphology.sourced``'s
axis); wing mass model uniform 47 mg (the default), ``VEINED_WING`` 47 mg (``Morphology.sourced``'s, provisional
constants) and uniform 23.5 mg (half the mass; the body gets the rest, the total mass stays Table 1's).

Parts (``--parts``, each written to ``<out-dir>/<part>.json`` with the command, date and load average):

* ``aero``: L+, P+ of the held-body UVLM (`hawksim aero`'s lattice and step: 6 x 12 rings, 40 steps per beat) at
  Table 3's kinematics, 0 / 1 / 2 m/s, 4 beats with beats 2-4 averaged (docs/uvlm.md's Table 4 window). The UVLM
  runs once per axis and speed; the wing mass models reuse its loads (the held body's wing motion, and so the
  aerodynamic loads, do not depend on the mass; checked: the replay reproduces the direct run's P+ to 1e-12) with
  MuJoCo's inverse dynamics of each mass model for the inertial power.
* ``aero_travel``: the same with the UVLM's "travel" shedding rule (``UVLMConfig.shed_rule``), which converges
  in the time step where the default "ring" rule does not (docs/fidelity.md).
* ``recoil``: the free-flight recoil of the body against its wings: a quasi-steady free flight (`hawksim fly`'s
  loop: 200 steps per beat, gravity, start on the periodic path) of 3 beats from the shipped quasi-steady trim of
  the default model at 0 / 1 / 2 m/s; per beat the peak-to-peak of the body's vertical and horizontal velocity
  (world) and of its pitch, averaged over beats 2-3. The trim is the default model's for every variant (the
  recoil is the within-beat oscillation, driven by the wings' inertia; the beat-mean drift of an unbalanced
  variant is reported separately as the change of the mean vertical speed from beat 1 to 3).
* ``trim``: theta0 (and the other parameters, P+) of the minimum-power trim on the quasi-steady model: Eq. 3's
  fitness (r = 2, s = 5) on quasi-steady held-body averages (40 steps per beat, 2 beats, the second averaged),
  minimised by adaptive Nelder-Mead in Table 2's scaled box from the shipped quasi-steady trim of the default
  model (Table 3's theta0, phi_a and alpha_a; f, beta, phi0, alpha0 balanced), up to 3 passes of 300
  evaluations while it improves. A local, budget-limited search, not the paper's GA: it says where the minimum
  moves with the variant from the same start (the fitness reached is reported).
* ``shed_convergence``: both shedding rules at 40, 80 and 160 steps per beat (1 m/s, the lattice fixed).
* ``lattice_convergence``: both rules on docs/uvlm.md's ladder of lattices (4 x 8 / 30 steps to 12 x 24 / 80
  steps per beat, refined together; 1 m/s).
* ``uvlm_parameters``: L+, P+ at Table 3's kinematics, 0 / 1 / 2 m/s (default morphology and lattice, beats 2-4)
  with each tuned constant of ``aero.uvlm.UVLMConfig`` changed one at a time, and the shedding rule at 40 and 80
  steps per beat.

    NUMBA_NUM_THREADS=1 python scripts/studies/fidelity.py --out-dir results/fidelity
    python scripts/studies/fidelity.py --tables      # the markdown tables of docs/fidelity.md

Runs one UVLM case at a time (the machine is shared); ~5 min in all on this machine.
"""

from __future__ import annotations

import argparse
import json
import os
import sys
import time
from dataclasses import replace

import numpy as np
from scipy.optimize import minimize

from aero.uvlm import ROTOR_A_PRIME, UVLMConfig
from hawksim.backends.held import held_flight
from hawksim.backends.quasi_steady import QuasiSteadyBackend
from hawksim.backends.uvlm import UVLMBackend
from hawksim.flight.fly import fly
from hawksim.insect.kinematics import Kinematics, bounds_si, table3_kinematics
from hawksim.insect.model import load_model
from hawksim.insect.morphology import P0_W, RHO_AIR, UNIFORM_WING, Morphology, WingMassModel
from hawksim.jsonout import host_info
from hawksim.trim.search import fitness
from hawksim.trim.tables import shipped_trim

SPEEDS = (0.0, 1.0, 2.0)
VEINED_WING = WingMassModel("veined", span_decay=1.0, chord_decay=1.0)
"""Issue 22's provisional areal density (exp(-r/R) exp(-s)), kept here so that the study reproduces its table;
issue 49 replaced it in Morphology.sourced() by ROOT_HEAVY_WING, fitted to the measured radius of gyration."""
AXES = {"25 % (default)": 0.25, "10 %": 0.10, "leading edge (sourced)": 0.0}
MASSES = {
    "uniform 47 mg (default)": {"wing_mass_model": UNIFORM_WING},
    "veined 47 mg (sourced, provisional)": {"wing_mass_model": VEINED_WING},
    "uniform 23.5 mg (half)": {"wing_mass_model": UNIFORM_WING, "wing_mass": 23.5e-6},
}
UVLM_BEATS, UVLM_AVERAGED, UVLM_STEPS = 4, 3, 40
QS_TRIM_STEPS, QS_TRIM_BEATS = 40, 2
NM_PASSES, NM_MAX_EVALS = 3, 300
FLY_BEATS = 3
REPLAY_RTOL = 1e-12
OUT_DIR = ["results/fidelity"]


def morph_of(axis: float, mass: dict) -> Morphology:
    return Morphology(axis_fraction=axis, **mass)


class _Recorder:
    """Passes a backend's loads through and keeps them (for the replay)."""

    def __init__(self, inner):
        self.inner, self.name, self.seen = inner, inner.name, []

    def reset(self, state):
        self.inner.reset(state)
        self.seen = []

    def loads(self, state):
        out = self.inner.loads(state)
        self.seen.append(out)
        return out


class _Replay:
    """Returns recorded loads in order (the same held-body wing motion)."""

    name = "replay"

    def __init__(self, seen):
        self.seen, self.i = seen, 0

    def reset(self, state):
        self.i = 0

    def loads(self, state):
        out = self.seen[self.i]
        self.i += 1
        return out


def _averages(r) -> dict:
    a = r.averages
    n = UVLM_AVERAGED * r.steps_per_cycle
    return {"L_plus": a.L_plus, "D_plus": a.D_plus, "M_plus": a.M_plus, "P_plus": a.P_plus,
            "mean_abs_P_inertial_over_P0": float(np.abs(r.power_inertial[-n:]).mean() / P0_W),
            "mean_P_aero_over_P0": float(r.power_aero[-n:].mean() / P0_W)}


def part_aero(shed_rule: str = "ring") -> dict:
    rows = []
    cfg = UVLMConfig(rho=RHO_AIR, shed_rule=shed_rule)
    for axis_name, axis in AXES.items():
        for V in SPEEDS:
            kin = table3_kinematics(V)
            base = morph_of(axis, MASSES["uniform 47 mg (default)"])
            rec = _Recorder(UVLMBackend(base, config=cfg))
            t0 = time.perf_counter()
            direct = held_flight(kin, V, rec, cycles=UVLM_BEATS, average_cycles=UVLM_AVERAGED,
                                 steps_per_cycle=UVLM_STEPS, model=load_model(morph=base), morph=base)
            wall = time.perf_counter() - t0
            for mass_name, mass in MASSES.items():
                m = morph_of(axis, mass)
                r = held_flight(kin, V, _Replay(rec.seen), cycles=UVLM_BEATS, average_cycles=UVLM_AVERAGED,
                                steps_per_cycle=UVLM_STEPS, model=load_model(morph=m), morph=m)
                if mass_name.startswith("uniform 47") and not np.isclose(r.averages.P_plus, direct.averages.P_plus,
                                                                         rtol=REPLAY_RTOL, atol=0):
                    raise RuntimeError(f"replay P+ {r.averages.P_plus} != direct {direct.averages.P_plus}")
                rows.append({"axis": axis_name, "axis_fraction": axis, "mass": mass_name, "speed": V,
                             **_averages(r), "uvlm_wall_s": round(wall, 2)})
                print(json.dumps(rows[-1]), file=sys.stderr, flush=True)
    return {"rows": rows, "kinematics": "Table 3 (hawksim.insect.kinematics.table3_kinematics)",
            "shed_rule": shed_rule, "resolution": {"n_chord": 6, "n_span": 12, "steps_per_cycle": UVLM_STEPS,
                                                   "beats": UVLM_BEATS, "averaged_beats": UVLM_AVERAGED}}


def _peak_to_peak_per_beat(x: np.ndarray, n: int, beats) -> float:
    return float(np.mean([np.ptp(x[k * n:(k + 1) * n]) for k in beats]))


def part_recoil() -> dict:
    rows = []
    for axis_name, axis in AXES.items():
        for mass_name, mass in MASSES.items():
            m = morph_of(axis, mass)
            for V in SPEEDS:
                trim = shipped_trim(V, "quasi-steady")
                res = fly(trim, QuasiSteadyBackend(m), FLY_BEATS, model=load_model(morph=m))
                n = res.steps_per_cycle
                later = range(1, FLY_BEATS)
                pitch = np.rad2deg(res.pitch())
                beats = res.beats()
                rows.append({"axis": axis_name, "mass": mass_name, "speed": V,
                             "vz_peak_to_peak_m_s": _peak_to_peak_per_beat(res.body_v[:, 2], n, later),
                             "vx_peak_to_peak_m_s": _peak_to_peak_per_beat(res.body_v[:, 0], n, later),
                             "pitch_peak_to_peak_deg": _peak_to_peak_per_beat(pitch, n, later),
                             "mean_vertical_speed_beats_1_3": [b["mean_vertical_speed"] for b in beats]})
                print(json.dumps(rows[-1]), file=sys.stderr, flush=True)
    return {"rows": rows, "backend": "quasi-steady", "steps_per_cycle": 200, "beats": FLY_BEATS,
            "trim": "shipped quasi-steady trim of the default model "
                    "(hawksim/insects/hawkmoth/data/trim_table_quasi_steady.json)"}


def _qs_trim(m: Morphology, V: float) -> dict:
    lo, hi = bounds_si()
    model = load_model(morph=m)
    backend = QuasiSteadyBackend(m)
    evals = [0]

    def averages(x):
        r = held_flight(Kinematics.from_array(x), V, backend, cycles=QS_TRIM_BEATS, average_cycles=1,
                        steps_per_cycle=QS_TRIM_STEPS, model=model, morph=m)
        a = r.averages
        return np.array([a.L_plus, a.D_plus, a.M_plus, a.P_plus])

    def objective(u):
        evals[0] += 1
        x = lo + np.asarray(u) * (hi - lo)
        return float(fitness(averages(x)[None], x[None])[0])

    u = (shipped_trim(V, "quasi-steady").kinematics.as_array() - lo) / (hi - lo)
    f = f0 = objective(u)
    for _ in range(NM_PASSES):
        nm = minimize(objective, u, method="Nelder-Mead",
                      options={"xatol": 1e-6, "fatol": 1e-7, "maxfev": NM_MAX_EVALS, "adaptive": True})
        if not nm.fun < f - 1e-7:
            break
        u, f = np.asarray(nm.x), float(nm.fun)
    x = np.clip(lo + u * (hi - lo), lo, hi)
    y = averages(x)
    kin = Kinematics.from_array(x)
    return {"fitness": f, "start_fitness": f0, "evaluations": evals[0], "kinematics": kin.to_edge(),
            "theta0_deg": kin.to_edge()["theta0"], "L_plus": y[0], "D_plus": y[1], "M_plus": y[2], "P_plus": y[3]}


def part_trim(partial_path: str | None = None) -> dict:
    """One trim per (axis, mass, speed); with ``partial_path`` the rows done so far are kept there (JSON lines)
    and a rerun skips them (resumable: the machine is shared and the part takes tens of minutes under load)."""
    rows = []
    if partial_path and os.path.exists(partial_path):
        with open(partial_path) as f:
            rows = [json.loads(line) for line in f if line.strip()]
    done = {(r["axis"], r["mass"], r["speed"]) for r in rows}
    for axis_name, axis in AXES.items():
        for mass_name, mass in MASSES.items():
            for V in SPEEDS:
                if (axis_name, mass_name, V) in done:
                    continue
                t0 = time.perf_counter()
                row = {"axis": axis_name, "mass": mass_name, "speed": V, **_qs_trim(morph_of(axis, mass), V),
                       "wall_s": round(time.perf_counter() - t0, 1)}
                rows.append(row)
                print(json.dumps(row), file=sys.stderr, flush=True)
                if partial_path:
                    with open(partial_path, "a") as f:
                        f.write(json.dumps(row) + "\n")
    if partial_path and os.path.exists(partial_path):
        os.remove(partial_path)  # complete: the part's JSON holds every row
    return {"rows": rows, "backend": "quasi-steady",
            "objective": "Eq. 3 (r = 2, s = 5) on quasi-steady held-body averages, 40 steps per beat, beat 2 of 2",
            "search": "adaptive Nelder-Mead in Table 2's scaled box from the shipped quasi-steady trim, up to "
                      f"{NM_PASSES} passes of {NM_MAX_EVALS} evaluations while it improves"}


UVLM_VARIANTS = {
    "default": {},
    "a_prime rotor 6.5e-5": {"a_prime": ROTOR_A_PRIME},
    "a_prime 3e-3": {"a_prime": 3e-3},
    "a_prime 3e-2": {"a_prime": 3e-2},
    "core growth off": {"core_growth": False},
    "wake_core_chords 0.025": {"wake_core_chords": 0.025},
    "wake_core_chords 0.1": {"wake_core_chords": 0.1},
    "core_fraction 0.01": {"core_fraction": 0.01},
    "core_fraction 0.04": {"core_fraction": 0.04},
    "convection_core_chords 0.05": {"convection_core_chords": 0.05},
    "convection_core_chords 0.2": {"convection_core_chords": 0.2},
    "no leading-edge suction": {"le_suction": False},
    "shed_rule travel": {"shed_rule": "travel"},
}
UVLM_STEP_VARIANTS = {("ring", 80): {}, ("travel", 80): {"shed_rule": "travel"}}


def part_uvlm_parameters() -> dict:
    rows = []
    m = Morphology()
    model = load_model(morph=m)
    cases = [(name, kw, UVLM_STEPS) for name, kw in UVLM_VARIANTS.items()]
    cases += [(f"shed_rule {rule}, {steps} steps", kw, steps) for (rule, steps), kw in UVLM_STEP_VARIANTS.items()]
    for name, kw, steps in cases:
        for V in SPEEDS:
            cfg = replace(UVLMConfig(rho=RHO_AIR), **kw)
            t0 = time.perf_counter()
            try:
                r = held_flight(table3_kinematics(V), V, UVLMBackend(m, config=cfg), cycles=UVLM_BEATS,
                                average_cycles=UVLM_AVERAGED, steps_per_cycle=steps, model=model, morph=m)
                row = {"variant": name, "config": kw, "steps_per_cycle": steps, "speed": V, **_averages(r)}
            except FloatingPointError as exc:
                row = {"variant": name, "config": kw, "steps_per_cycle": steps, "speed": V, "error": str(exc)}
            row["wall_s"] = round(time.perf_counter() - t0, 2)
            rows.append(row)
            print(json.dumps(row), file=sys.stderr, flush=True)
    return {"rows": rows, "kinematics": "Table 3", "lattice": "6 x 12 rings", "beats": UVLM_BEATS,
            "averaged_beats": UVLM_AVERAGED}


def _load(out_dir: str, part: str) -> dict | None:
    path = os.path.join(out_dir, f"{part}.json")
    if not os.path.exists(path):
        return None
    with open(path) as f:
        return json.load(f)


def tables(out_dir: str) -> str:
    """Markdown tables of the saved parts (docs/fidelity.md)."""
    lines = []
    speeds = " | ".join(f"{V:g} m/s" for V in SPEEDS)
    rule = "|---|---|" + "---|" * len(SPEEDS)
    for part, title in (("aero", "default shedding rule"), ("aero_travel", '"travel" shedding rule')):
        lines += _aero_tables(_load(out_dir, part), title)
    return _rest_tables(out_dir, lines, speeds, rule)


def _aero_tables(aero: dict | None, title: str) -> list[str]:
    lines = []
    speeds = " | ".join(f"{V:g} m/s" for V in SPEEDS)
    rule = "|---|---|" + "---|" * len(SPEEDS)
    if aero:
        lines += [f"**L+ / P+** (UVLM, {title}, Table 3 kinematics, beats 2-4):", "",
                  f"| feathering axis | wing mass | {speeds} |", rule]
        for r0 in aero["rows"]:
            if r0["speed"] != SPEEDS[0]:
                continue
            cells = [next(r for r in aero["rows"] if r["axis"] == r0["axis"] and r["mass"] == r0["mass"]
                          and r["speed"] == V) for V in SPEEDS]
            lines.append(f"| {r0['axis']} | {r0['mass']} | "
                         + " | ".join(f"{c['L_plus']:.3f} / {c['P_plus']:.3f}" for c in cells) + " |")
        lines += ["| paper, Table 4 | | 0.97 / 0.86 | 0.99 / 1.09 | 0.99 / 1.34 |", ""]
        lines += ["Mean |P_inertial| / P0 and mean P_aero / P0 (the two parts of P+ before max(0, .)):", "",
                  f"| feathering axis | wing mass | {speeds} |", rule]
        for r0 in aero["rows"]:
            if r0["speed"] != SPEEDS[0]:
                continue
            cells = [next(r for r in aero["rows"] if r["axis"] == r0["axis"] and r["mass"] == r0["mass"]
                          and r["speed"] == V) for V in SPEEDS]
            lines.append(f"| {r0['axis']} | {r0['mass']} | " + " | ".join(
                f"{c['mean_abs_P_inertial_over_P0']:.2f} / {c['mean_P_aero_over_P0']:.2f}" for c in cells) + " |")
        lines.append("")
    return lines


def _rest_tables(out_dir: str, lines: list[str], speeds: str, rule: str) -> str:
    rec = _load(out_dir, "recoil")
    if rec:
        lines += ["**Recoil per beat** (quasi-steady free flight, beats 2-3; peak-to-peak of the body's vertical / "
                  "horizontal velocity [m/s] and pitch [deg]):", "",
                  f"| feathering axis | wing mass | {speeds} |", rule]
        for r0 in rec["rows"]:
            if r0["speed"] != SPEEDS[0]:
                continue
            cells = [next(r for r in rec["rows"] if r["axis"] == r0["axis"] and r["mass"] == r0["mass"]
                          and r["speed"] == V) for V in SPEEDS]
            lines.append(f"| {r0['axis']} | {r0['mass']} | " + " | ".join(
                f"{c['vz_peak_to_peak_m_s']:.2f} / {c['vx_peak_to_peak_m_s']:.2f} / {c['pitch_peak_to_peak_deg']:.1f}"
                for c in cells) + " |")
        lines.append("")
    trim = _load(out_dir, "trim")
    if trim:
        lines += ["**Minimum-power trim on the quasi-steady model**: theta0 [deg] / P+ / max(|L+ - 1|, |D+|, |M+|) "
                  "(Table 2 bound: theta0 <= 25 deg; the paper's UVLM trim: 15.8 / 15.0 / 14.8 deg):", "",
                  f"| feathering axis | wing mass | {speeds} |", rule]
        for r0 in trim["rows"]:
            if r0["speed"] != SPEEDS[0]:
                continue
            cells = [next(r for r in trim["rows"] if r["axis"] == r0["axis"] and r["mass"] == r0["mass"]
                          and r["speed"] == V) for V in SPEEDS]
            lines.append(f"| {r0['axis']} | {r0['mass']} | " + " | ".join(
                f"{c['theta0_deg']:.1f} / {c['P_plus']:.3f} / "
                f"{max(abs(c['L_plus'] - 1), abs(c['D_plus']), abs(c['M_plus'])):.3f}" for c in cells) + " |")
        lines.append("")
    sc = _load(out_dir, "shed_convergence")
    if sc:
        lines += ["**Time-step convergence of the shedding rules** (Table 3, 1 m/s, 6 x 12 rings): L+ / P+", "",
                  "| shedding rule | 40 steps | 80 steps | 160 steps |", "|---|---|---|---|"]
        for rule_name in ("ring", "travel"):
            cells = [r for r in sc["rows"] if r["shed_rule"] == rule_name]
            lines.append(f"| {rule_name} | " + " | ".join(f"{c['L_plus']:.3f} / {c['P_plus']:.3f}" for c in cells)
                         + " |")
        lines.append("")
    lc = _load(out_dir, "lattice_convergence")
    if lc:
        lines += ["**Lattice convergence with each shedding rule** (Table 3, 1 m/s; rings per wing and steps per beat "
                  "refined together, docs/uvlm.md's ladder): L+ / P+", "",
                  "| shedding rule | " + " | ".join(f"{a} x {b}, {c}" for a, b, c in LATTICE_LADDER) + " |",
                  "|---|" + "---|" * len(LATTICE_LADDER)]
        for rule_name in ("travel", "ring"):
            cells = []
            for a, b, c in LATTICE_LADDER:
                hit = [r for r in lc["rows"] if r["shed_rule"] == rule_name and (r["n_chord"], r["n_span"],
                                                                                r["steps_per_cycle"]) == (a, b, c)]
                cells.append(f"{hit[0]['L_plus']:.3f} / {hit[0]['P_plus']:.3f}" if hit else "-")
            lines.append(f"| {rule_name} | " + " | ".join(cells) + " |")
        lines.append("")
    up = _load(out_dir, "uvlm_parameters")
    if up:
        lines += ["**UVLM constants** (default morphology, Table 3 kinematics, beats 2-4): L+ / P+", "",
                  f"| variant | steps per beat | {speeds} |", rule]
        names = []
        for r in up["rows"]:
            if r["variant"] not in names:
                names.append(r["variant"])
        for name in names:
            cells = [next(r for r in up["rows"] if r["variant"] == name and r["speed"] == V) for V in SPEEDS]
            lines.append(f"| {name} | {cells[0]['steps_per_cycle']} | " + " | ".join(
                ("diverged" if "error" in c else f"{c['L_plus']:.3f} / {c['P_plus']:.3f}") for c in cells) + " |")
        lines.append("")
    return "\n".join(lines)


def part_shed_convergence() -> dict:
    """L+, P+ at Table 3's 1 m/s kinematics with each shedding rule at 40, 80 and 160 steps per beat (lattice
    fixed at 6 x 12 rings: the time step alone is refined)."""
    rows = []
    m = Morphology()
    model = load_model(morph=m)
    for rule in ("ring", "travel"):
        for steps in (40, 80, 160):
            t0 = time.perf_counter()
            backend = UVLMBackend(m, config=UVLMConfig(rho=RHO_AIR, shed_rule=rule))
            r = held_flight(table3_kinematics(1.0), 1.0, backend, cycles=UVLM_BEATS, average_cycles=UVLM_AVERAGED,
                            steps_per_cycle=steps, model=model, morph=m)
            rows.append({"shed_rule": rule, "steps_per_cycle": steps, "speed": 1.0, **_averages(r),
                         "wall_s": round(time.perf_counter() - t0, 1)})
            print(json.dumps(rows[-1]), file=sys.stderr, flush=True)
    return {"rows": rows, "kinematics": "Table 3 at 1 m/s", "lattice": "6 x 12 rings", "beats": UVLM_BEATS,
            "averaged_beats": UVLM_AVERAGED}


LATTICE_LADDER = ((4, 8, 30), (6, 12, 40), (8, 16, 60), (12, 24, 80))
"""(n_chord, n_span, steps per beat): docs/uvlm.md's convergence ladder (panels and step refined together)."""


def part_lattice_convergence() -> dict:
    """L+, P+ at Table 3's 1 m/s kinematics with each shedding rule on docs/uvlm.md's ladder of lattices."""
    rows = []
    m = Morphology()
    model = load_model(morph=m)
    for rule in ("travel", "ring"):
        for nc, ns, steps in LATTICE_LADDER:
            t0 = time.perf_counter()
            backend = UVLMBackend(m, nc, ns, config=UVLMConfig(rho=RHO_AIR, shed_rule=rule))
            r = held_flight(table3_kinematics(1.0), 1.0, backend, cycles=UVLM_BEATS, average_cycles=UVLM_AVERAGED,
                            steps_per_cycle=steps, model=model, morph=m)
            rows.append({"shed_rule": rule, "n_chord": nc, "n_span": ns, "steps_per_cycle": steps, "speed": 1.0,
                         **_averages(r), "per_beat_L_plus": [c.L_plus for c in r.per_cycle],
                         "wall_s": round(time.perf_counter() - t0, 1)})
            print(json.dumps(rows[-1]), file=sys.stderr, flush=True)
    return {"rows": rows, "kinematics": "Table 3 at 1 m/s", "beats": UVLM_BEATS, "averaged_beats": UVLM_AVERAGED}


PARTS = {"aero": part_aero, "aero_travel": lambda: part_aero("travel"), "recoil": part_recoil,
         "trim": lambda: part_trim(os.path.join(OUT_DIR[0], "trim.partial.jsonl")),
         "uvlm_parameters": part_uvlm_parameters, "shed_convergence": part_shed_convergence,
         "lattice_convergence": part_lattice_convergence}


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out-dir", default="results/fidelity")
    ap.add_argument("--parts", default=",".join(PARTS), help=f"comma-separated subset of {', '.join(PARTS)}")
    ap.add_argument("--tables", action="store_true", help="print the markdown tables of the saved parts and exit")
    args = ap.parse_args()
    if args.tables:
        print(tables(args.out_dir))
        return
    os.makedirs(args.out_dir, exist_ok=True)
    OUT_DIR[0] = args.out_dir
    for part in args.parts.split(","):
        t0 = time.perf_counter()
        out = PARTS[part]()
        out = {"part": part, "command": "NUMBA_NUM_THREADS=1 python " + " ".join(sys.argv), **out,
               "wall_s": round(time.perf_counter() - t0, 1), "host": host_info()}
        path = os.path.join(args.out_dir, f"{part}.json")
        with open(path, "w") as f:
            json.dump(out, f, indent=1)
        print(json.dumps({"part": part, "file": path, "wall_s": out["wall_s"]}))


if __name__ == "__main__":
    main()
