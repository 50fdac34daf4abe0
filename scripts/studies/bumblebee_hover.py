"""The bumblebee in hover (issue 50, item 6): minimum-power trim, free-body orbit, Floquet multipliers beside the
averaged modes, and a controlled hover of 20 beats, with the quasi-steady and the UVLM backends.

The insect is the shipped folder ``hawksim/insects/bumblebee/`` (``insect.toml``; its README gives each number's source
or rule). Stages (each written to --out as it finishes; a rerun skips the stages already there, so the run is
resumable):

* ``qs_search``: the minimum of Eq. 3 (:func:`hawksim.trim.search.fitness`, the insect's bounds and P0) on the
  quasi-steady backend itself (there is no bumblebee network): :func:`hawksim.trim.search.ga_nelder_mead` (a
  population of 128, not the paper's 1e5: each evaluation is a held-body run, not a network call; :func:`_ga`) at 40
  steps a beat (:func:`_res`).
* ``qs_trim``: Nelder-Mead of Eq. 3 at 200 steps a beat (the resolution of the hawkmoth's quasi-steady trim table)
  from that optimum, then balanced there by :func:`hawksim.trim.balance.balance_on_uvlm` (f, beta, phi0, alpha0):
  the hawkmoth's pipeline (search on the cheap model, refine on the accurate one) with the step as the fidelity.
* ``uvlm_trim``: the same balance on the UVLM (:data:`hawksim.trim.balance.TRIM_RESOLUTION`) from the quasi-steady
  trim, as the hawkmoth's UVLM balance starts from the surrogate's optimum (a Nelder-Mead on the UVLM, at 2.5-6 s
  an evaluation and thousands of evaluations, is not affordable here; theta0, phi_a, alpha_a stay the start's). From
  the quasi-steady minimum it cannot balance (f on its bound), so it is also started from ``qs_measured_amplitude``
  (:func:`uvlm_trim`).
* ``qs_orbit``, ``uvlm_orbit``: :func:`hawksim.flight.orbit.periodic_orbit` from each trim (the UVLM's from the
  quasi-steady trim when run without ``uvlm_trim``, as ``--stages qs_trim,uvlm_orbit`` does), with its
  :func:`hawksim.stability.floquet.monodromy` multipliers; beside them the averaged modes of
  :func:`hawksim.stability.floquet.quasi_steady_system` at the quasi-steady orbit's kinematics (exp(lambda) per beat).
* ``qs_lqr``: 20 beats of the per-beat LQR about the quasi-steady orbit, started off it (q = 60 deg/s), the
  flight of ``hawksim fly --speed 0 --insect bumblebee --control lqr --cycles 20
  --perturb q=60`` (in process: that command's own orbit solve starts from the hawkmoth's trim, :func:`qs_lqr`).

    python scripts/studies/bumblebee_hover.py --out results/bumblebee_hover.json [--stages qs_trim,...] \\
        [--plot docs/images/bumblebee_hover.png]
"""

from __future__ import annotations

import argparse
import json
import os
import sys
import time
from dataclasses import replace
from pathlib import Path

import numpy as np

SPEC = "bumblebee"
"""The shipped insect's name (its folder hawksim/insects/bumblebee/)."""
SEED = 0
STAGES = ("qs_search", "qs_trim", "qs_measured_amplitude", "uvlm_trim", "qs_orbit", "qs_lqr", "uvlm_orbit",
          "uvlm_floquet")
PERTURB_Q_DEG_S = 400.0
"""The controlled hover's start off the orbit: pitch rate [deg/s]. The hawkmoth's tests start 60 deg/s off at ~30 Hz
(q T = 2 deg); the same q T at the bumblebee's ~190 Hz is about 400 deg/s."""
BEATS = 20
MEASURED_PHI_A_DEG, MEASURED_F_HZ = 58.0, 155.0
"""Sun & Xiong (2005, J. Exp. Biol. 208:447)'s hovering bumblebee: stroke amplitude 116 deg, 6.4 ms a beat (the
frequency as ../shared/sources/insect-morphology.md quotes it; the amplitude as recalled from that paper, not read in
the sources file: a comparison point, not an input)."""
UVLM_MAX_ITER = 8
"""Newton iterations of the UVLM orbit (each ~7 UVLM flights of 3 beats). The bumblebee's stalls at 8.2e-4 from
iteration 7 on (steps halved to 5e-4), below its wake's floor (3.3e-3), as the hawkmoth's hover orbit stalls at its
floor (docs/free_flight.md)."""


def _insect():
    from hawksim.insect.folder import load_insect

    return load_insect(SPEC)


def _res():
    from hawksim.backends.resolution import Resolution

    search = Resolution(aero="quasi-steady", steps_per_cycle=40, cycles=2)
    return search, replace(search, steps_per_cycle=200)


def _ga():
    from hawksim.trim.search import GAConfig

    return GAConfig(population=128, max_generations=30, stall_generations=8, nm_max_evals=3000, nm_restarts=2)


def _avg_json(a) -> dict:
    return {"L_plus": a.L_plus, "D_plus": a.D_plus, "M_plus": a.M_plus, "P_plus": a.P_plus, "power_W": a.power_W}


def _trim_json(t) -> dict:
    a = t.averages
    return {"kinematics": t.kinematics.to_edge(), "averages": _avg_json(a),
            "residuals": {"L_plus_minus_1": a.L_plus - 1.0, "D_plus": a.D_plus, "M_plus": a.M_plus},
            "converged": t.converged, "evaluations": t.evaluations, "wall_time_s": t.wall_time_s,
            "source": t.source}


def _qs_objective(insect, res, calls):
    """Eq. 3 on the quasi-steady backend at ``res``: u (m, 7) in the insect's box -> F (m,)."""
    from hawksim.backends.held import run
    from hawksim.insect.kinematics import Kinematics
    from hawksim.trim.search import fitness

    lo, hi = insect.bounds_si()

    def y_of(x):
        calls[0] += 1
        a = run(Kinematics.from_array(x), 0.0, res, insect=insect).averages
        return np.array([a.L_plus, a.D_plus, a.M_plus, a.P_plus])

    def objective(u):
        x = lo + np.atleast_2d(u) * (hi - lo)
        return fitness(np.array([y_of(xi) for xi in x]), x, lo=lo, hi=hi)

    return objective


def qs_search(insect) -> dict:
    """GA + Nelder-Mead of Eq. 3 on the quasi-steady backend at SEARCH_RES (40 steps a beat)."""
    from hawksim.backends.held import run
    from hawksim.insect.kinematics import Kinematics
    from hawksim.trim.search import ga_nelder_mead

    search, _ = _res()
    cfg = _ga()
    lo, hi = insect.bounds_si()
    calls = [0]

    def progress(gen, total, best):
        print(f"  GA generation {gen}/{total}: best F {best:.5f} ({calls[0]} evaluations)", file=sys.stderr,
              flush=True)

    t0 = time.perf_counter()
    u, F, ga, nfev = ga_nelder_mead(_qs_objective(insect, search, calls), 7, cfg, np.random.default_rng(SEED),
                                    progress=progress)
    x = np.clip(lo + u * (hi - lo), lo, hi)
    kin = Kinematics.from_array(x)
    a40 = run(kin, 0.0, search, insect=insect).averages
    print(f"  GA+NM optimum F = {F:.5f} after {ga.generations} generations + {nfev} Nelder-Mead evaluations "
          f"({time.perf_counter() - t0:.0f} s): {kin.to_edge()}", file=sys.stderr, flush=True)
    return {"method": "GA + Nelder-Mead (hawksim.trim.search.ga_nelder_mead) of Eq. 3 on the quasi-steady backend "
                      "at 40 steps a beat",
            "seed": SEED, "ga": {"population": cfg.population, "max_generations": cfg.max_generations,
                                 "stall_generations": cfg.stall_generations, "generations": ga.generations,
                                 "best_history": list(ga.best_history), "nm_evaluations": nfev,
                                 "nm_max_evals": cfg.nm_max_evals, "nm_restarts": cfg.nm_restarts},
            "search_resolution": search.to_dict(),
            "optimum": {"kinematics": kin.to_edge(), "fitness": F, "averages_40_steps": _avg_json(a40)},
            "wall_time_s": time.perf_counter() - t0}


def qs_trim(insect, out) -> dict:
    """Nelder-Mead of Eq. 3 at QS_RES (200 steps) from the search's optimum (restarted as in
    :func:`hawksim.trim.search.ga_nelder_mead`), then its balance (f, beta, phi0, alpha0) at QS_RES. The 40-step
    optimum sits on the f bound with L+ 1.5 % short at 200 steps, which the balance alone cannot make up (f is
    bounded): the fine Nelder-Mead moves the amplitudes too."""
    from scipy.optimize import minimize

    from hawksim.backends.held import run
    from hawksim.insect.kinematics import Kinematics
    from hawksim.trim.balance import balance_on_uvlm

    _, fine = _res()
    cfg = _ga()
    lo, hi = insect.bounds_si()
    calls = [0]
    obj = _qs_objective(insect, fine, calls)

    def one(u):
        return float(obj(np.asarray(u)[None, :])[0])

    t0 = time.perf_counter()
    x0 = Kinematics.from_edge(out["qs_search"]["optimum"]["kinematics"], check_bounds=False).as_array()
    u = (x0 - lo) / (hi - lo)
    f, nfev = one(u), 0
    for _ in range(cfg.nm_restarts + 1):
        nm = minimize(one, u, method="Nelder-Mead",
                      options={"xatol": cfg.nm_tol, "fatol": cfg.nm_tol, "maxfev": cfg.nm_max_evals, "adaptive": True})
        nfev += int(nm.nfev)
        print(f"  Nelder-Mead at 200 steps: F {nm.fun:.6f} ({nfev} evaluations)", file=sys.stderr, flush=True)
        if not nm.fun < f - cfg.nm_tol:
            break
        u, f = np.asarray(nm.x), float(nm.fun)
    kin = Kinematics.from_array(np.clip(lo + u * (hi - lo), lo, hi))
    a = run(kin, 0.0, fine, insect=insect).averages
    bal = balance_on_uvlm(kin, 0.0, fine, insect=insect)
    return {"method": "Nelder-Mead of Eq. 3 on the quasi-steady backend at 200 steps a beat from the 40-step GA + "
                      "Nelder-Mead optimum (qs_search), then balanced (hawksim.trim.balance.balance_on_uvlm, free: "
                      "f, beta, phi0, alpha0) at 200 steps", "resolution": fine.to_dict(),
            "optimum": {"kinematics": kin.to_edge(), "fitness": f, "averages": _avg_json(a), "nm_evaluations": nfev},
            "balanced": _trim_json(bal), "wall_time_s": time.perf_counter() - t0}


def qs_measured_amplitude(insect, out) -> dict:
    """How much the quasi-steady optimum's small stroke saves: the balance (f, beta, phi0, alpha0) at 200 steps with
    the sweep amplitude of Sun & Xiong's (2005) hovering bumblebee, phi_a = 58 deg (stroke 116 deg), started at their
    ~155 Hz, theta0 and alpha_a at the optimum's."""
    from hawksim.insect.kinematics import Kinematics
    from hawksim.trim.balance import balance_on_uvlm

    _, fine = _res()
    edge = dict(out["qs_trim"]["balanced"]["kinematics"], phi_a=MEASURED_PHI_A_DEG, f=MEASURED_F_HZ)
    bal = balance_on_uvlm(Kinematics.from_edge(edge, check_bounds=False), 0.0, fine, insect=insect)
    return {"method": "quasi-steady balance at phi_a = 58 deg from f = 155 Hz (Sun & Xiong 2005's hovering "
                      "bumblebee), the other angles the trim's", "balanced": _trim_json(bal)}


def uvlm_trim(insect, out) -> dict:
    """The UVLM balance (f, beta, phi0, alpha0) from the quasi-steady minimum (``from_qs_minimum``) and, as that
    cannot balance (the UVLM's L+ there is about 0.6 with f on its bound), from the quasi-steady balance at the
    measured stroke amplitude (``balanced``, :func:`qs_measured_amplitude`)."""
    from hawksim.insect.kinematics import Kinematics
    from hawksim.trim.balance import TRIM_RESOLUTION, balance_on_uvlm

    res = {"method": "UVLM balance (hawksim.trim.balance.balance_on_uvlm, free: f, beta, phi0, alpha0) started from "
                     "the quasi-steady minimum and from the quasi-steady balance at phi_a = 58 deg",
           "resolution": TRIM_RESOLUTION.to_dict()}
    for name, key in (("from_qs_minimum", "qs_trim"), ("balanced", "qs_measured_amplitude")):
        kin = Kinematics.from_edge(out[key]["balanced"]["kinematics"], check_bounds=False)
        bal = balance_on_uvlm(kin, 0.0, TRIM_RESOLUTION, insect=insect)
        res[name] = {"start": key, "start_averages": _avg_json(bal.start.averages), **_trim_json(bal)}
        print(f"  UVLM balance from {key}: converged {bal.converged}, {bal.averages}", file=sys.stderr, flush=True)
    return res


def _floquet_json(fl) -> dict:
    def c(z):
        return [[float(np.real(v)), float(np.imag(v))] for v in z]

    return {"multipliers_long": c(fl.multipliers_long), "multipliers_lat": c(fl.multipliers_lat),
            "max_multiplier": fl.max_multiplier, "delta": fl.delta, "reach_long": list(fl.reach_long),
            "reach_lat": list(fl.reach_lat), "coupling": fl.coupling, "wall_time_s": fl.wall_time_s}


def _orbit_json(orbit) -> dict:
    return {"converged": orbit.converged, "residual": orbit.residual, "iterations": orbit.iterations,
            "kinematics": orbit.kinematics.to_edge(), "initial_state": orbit.initial_state.as_array().tolist(),
            "mean_velocity": np.asarray(orbit.mean_velocity).tolist(), "mean_pitch_deg": np.rad2deg(orbit.mean_pitch),
            "P_plus": orbit.P_plus, "power_W": orbit.P_plus * orbit.insect.P0, "floor": orbit.floor,
            "launch_state": orbit.launch_state.as_array().tolist(), "residuals": np.asarray(orbit.residuals).tolist(),
            "warm_beats": orbit.warm_beats, "wall_time_s": orbit.wall_time_s}


def orbit_stage(insect, out, aero: str) -> dict:
    from hawksim.flight.orbit import periodic_orbit
    from hawksim.insect.kinematics import Kinematics
    from hawksim.stability.floquet import monodromy

    key = "qs_trim" if aero == "quasi-steady" or "uvlm_trim" not in out else "uvlm_trim"
    kin = Kinematics.from_edge(out[key]["balanced"]["kinematics"], check_bounds=False)
    max_iter = 20 if aero == "quasi-steady" else UVLM_MAX_ITER
    orbit = periodic_orbit(0.0, aero, kinematics=kin, insect=insect, max_iter=max_iter,
                           log=lambda s: print("  " + s, file=sys.stderr, flush=True))
    res = {"aero": aero, "start": f"the {key.replace('_', ' ')}", "max_iter": max_iter, "orbit": _orbit_json(orbit)}
    if not orbit.converged:
        return res
    fl = monodromy(orbit)
    res["floquet"] = _floquet_json(fl)
    if aero == "quasi-steady":
        from hawksim.stability.floquet import quasi_steady_system

        sys_ = quasi_steady_system(orbit.kinematics, 0.0, insect=insect)
        res["averaged"] = {"eig_long": [[float(z.real), float(z.imag)] for z in sys_.eig_long],
                           "eig_lat": [[float(z.real), float(z.imag)] for z in sys_.eig_lat],
                           "exp_eig_long": [[float(np.exp(z).real), float(np.exp(z).imag)] for z in sys_.eig_long],
                           "exp_eig_lat": [[float(np.exp(z).real), float(np.exp(z).imag)] for z in sys_.eig_lat],
                           "nondimensional": {k: float(v) for k, v in sys_.nondimensional.items()
                                              if isinstance(v, (int, float))}}
    return res


def uvlm_floquet(insect, out) -> dict:
    """The UVLM orbit's monodromy when Newton stalled at the wake's floor (residual <= floor) without meeting the
    backend's SI tolerance: the orbit re-launched from its stored launch state and kinematics (no iteration), its
    residual components in SI against the tolerance, and :func:`hawksim.stability.floquet.monodromy` (16 UVLM flights;
    each mode's reach says whether it is resolved)."""
    from hawksim.backends.registry import descriptor
    from hawksim.flight.orbit import periodic_orbit, scales
    from hawksim.insect.kinematics import Kinematics
    from hawksim.stability.floquet import REACH_MIN, monodromy

    o = out["uvlm_orbit"]["orbit"]
    orbit = periodic_orbit(0.0, "uvlm", kinematics=Kinematics.from_edge(o["kinematics"], check_bounds=False),
                           x0=np.array(o["launch_state"]), insect=insect, max_iter=0)
    U, T = scales(orbit.kinematics, insect.morphology)
    r = np.abs(orbit.residuals)
    tol = descriptor("uvlm").orbit_tolerance
    res = {"residual": orbit.residual, "floor": orbit.floor, "converged": orbit.converged,
           "si": {"velocity_m_s": float(max(r[0], r[1], r[4], r[5]) * U), "pitch_rate_rad_s": float(r[2] / T),
                  "pitch_rad": float(r[3])},
           "tolerance": {"velocity_m_s": tol.velocity, "pitch_rate_rad_s": tol.rate, "pitch_rad": tol.rate * T},
           "U_m_s": U, "T_s": T}
    fl = monodromy(orbit)
    res["floquet"] = _floquet_json(fl) | {"reach_min": REACH_MIN}
    return res


def qs_lqr(insect, out) -> dict:
    """20 beats of the per-beat LQR (`hawksim fly --control lqr`'s flight, in process) about the bumblebee's own
    quasi-steady orbit, solved from the bumblebee's trim (as in ``qs_orbit``) and handed to the schedule by
    :func:`hawksim.control.schedule.operating_point_override` (`hawksim fly --insect bumblebee --control lqr` solves
    the same orbit from the spec's reference kinematics, that trim: tests/hawksim/test_bumblebee.py)."""
    from hawksim.control.command import command_summary, fly_command
    from hawksim.control.derivatives import linearize
    from hawksim.control.schedule import operating_point_override
    from hawksim.flight.orbit import periodic_orbit
    from hawksim.insect.kinematics import Kinematics

    kin = Kinematics.from_edge(out["qs_trim"]["balanced"]["kinematics"], check_bounds=False)
    orbit = periodic_orbit(0.0, "quasi-steady", kinematics=kin, insect=insect)
    if not orbit.converged:
        return {"error": f"the quasi-steady orbit did not converge ({orbit.residual:.1e})"}
    with operating_point_override(0.0, "quasi-steady", orbit, linearize(orbit)):
        cl = fly_command(0.0, BEATS, control="lqr", perturb={"q": PERTURB_Q_DEG_S}, insect=insect,
                         aero="quasi-steady", rate="beat")
    fly = command_summary(cl, BEATS, "lqr", "quasi-steady", "beat")
    beats = fly["beats"]
    return {"flight": f"hawksim fly --speed 0 --insect bumblebee --control lqr "
                      f"--cycles {BEATS} --perturb q={PERTURB_Q_DEG_S:g} (in process, on the orbit of the bumblebee's "
                      "trim)",
            "departed_at_beat": fly.get("departed_at_beat"), "orbit_f_hz": orbit.kinematics.f,
            "kinematics": fly["kinematics"], "last_cycle": fly["last_cycle"],
            "last_beats_max_abs": fly["control"]["last_beats_max_abs"],
            "beats": [{k: b[k] for k in b if isinstance(b[k], (int, float))} for b in beats]}


def plot(out: dict, path: Path) -> Path:
    """The figure of docs/bumblebee.md: (a) the quasi-steady Floquet exponents ln(mu) per beat beside the averaged
    eigenvalues, (b) the 20-beat controlled hover's beat-mean vertical speed and pitch."""
    from hawksim import plotting

    with plotting.style():
        plt = plotting.pyplot()
        fig, (ax, bx) = plt.subplots(1, 2, figsize=(plotting.WIDE, 3.4))
        o = out["qs_orbit"]
        for kind, mk in (("long", "o"), ("lat", "s")):
            ln = np.log(np.array([complex(*z) for z in o["floquet"]["multipliers_" + kind]]))
            ev = np.array([complex(*z) for z in o["averaged"]["eig_" + kind]])
            ax.plot(ln.real, ln.imag, mk, mfc="none", color="C0", label=f"Floquet ln mu ({kind})")
            ax.plot(ev.real, ev.imag, mk, color="C1", ms=3, label=f"averaged eig(A) ({kind})")
        ax.axvline(0, color="0.6", lw=0.8)
        ax.set_xlabel(plotting.RE_LAMBDA)
        ax.set_ylabel(plotting.IM_LAMBDA)
        ax.legend()
        f = out["qs_lqr"]
        k = np.arange(1, len(f["beats"]) + 1)
        bx.plot(k, [b["mean_vertical_speed"] * 1e3 for b in f["beats"]], "o-", label="mean vertical speed [mm/s]")
        bx.set_xlabel("wingbeat")
        bx.set_ylabel("beat-mean vertical speed [mm/s]")
        cx = bx.twinx()
        cx.plot(k, [b["pitch_deg"] for b in f["beats"]], "s-", color="C2", label="pitch [deg]")
        cx.set_ylabel("beat-mean pitch [deg]")
        plotting.panel_letters([ax, bx], ("quasi-steady orbit: Floquet vs averaged",
                                             f"LQR hover, q = {PERTURB_Q_DEG_S:g} deg/s at 0"))
        return plotting.save(fig, path, title="Bumblebee hover (quasi-steady)",
                             caption="(a) Floquet exponents ln(mu) per wingbeat of the free-body orbit (open) and "
                                     "the eigenvalues of the cycle-averaged A matrices at its kinematics (filled), "
                                     "t+ = t/T. (b) 20 beats of the per-beat LQR from the orbit with a pitch-rate "
                                     f"perturbation of {PERTURB_Q_DEG_S:g} deg/s: beat-mean vertical speed (circles) "
                                     "and pitch (squares). results/bumblebee_hover.json.")


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", required=True)
    ap.add_argument("--stages", default=",".join(STAGES), help="comma-separated subset of " + ", ".join(STAGES))
    ap.add_argument("--plot", help="also draw docs/bumblebee.md's figure to this PNG (and a PDF beside it)")
    a = ap.parse_args()
    path = Path(a.out)
    out = json.loads(path.read_text()) if path.exists() else {}
    from aero.numba_cache import sources_digest
    from hawksim.jsonout import host_info

    insect = _insect()
    out.update(command="python " + " ".join(sys.argv[:1] + ["--out", a.out]), seed=SEED,
               sources_digest=sources_digest(), insect=insect.to_dict(), speed=0.0)
    stages = [s for s in a.stages.split(",") if s]
    for s in stages:
        if s not in STAGES:
            ap.error(f"unknown stage {s!r}")

    done = set()

    def save():  # the file as it is on disk now (another process may be writing other stages), with this run's stages
        path.parent.mkdir(parents=True, exist_ok=True)
        disk = json.loads(path.read_text()) if path.exists() else {}
        merged = {**disk, **{k: v for k, v in out.items() if k not in STAGES or k in done}}
        tmp = path.with_suffix(f".{os.getpid()}.tmp")
        tmp.write_text(json.dumps(merged, indent=1) + "\n")
        tmp.replace(path)

    for s in STAGES:
        if s not in stages or s in out:
            continue
        print(f"stage {s}", file=sys.stderr, flush=True)
        t0 = time.perf_counter()
        if s == "qs_search":
            out[s] = qs_search(insect)
        elif s == "qs_trim":
            out[s] = qs_trim(insect, out)
        elif s == "qs_measured_amplitude":
            out[s] = qs_measured_amplitude(insect, out)
        elif s == "uvlm_trim":
            out[s] = uvlm_trim(insect, out)
        elif s == "qs_orbit":
            out[s] = orbit_stage(insect, out, "quasi-steady")
        elif s == "uvlm_orbit":
            out[s] = orbit_stage(insect, out, "uvlm")
        elif s == "uvlm_floquet":
            out[s] = uvlm_floquet(insect, out)
        elif s == "qs_lqr":
            out[s] = qs_lqr(insect, out)
        out[s]["stage_wall_time_s"] = time.perf_counter() - t0
        out[s]["host"] = host_info()
        print(f"stage {s} done in {out[s]['stage_wall_time_s']:.0f} s", file=sys.stderr, flush=True)
        done.add(s)
        save()
    save()
    out = json.loads(path.read_text())
    if a.plot and "qs_orbit" in out and "floquet" in out["qs_orbit"] and "beats" in out.get("qs_lqr", {}):
        print(f"figure {plot(out, Path(a.plot))}", file=sys.stderr)


if __name__ == "__main__":
    main()
