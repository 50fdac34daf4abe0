"""Perturbed nonlinear free flights against both linear models (issue 19, item 4).

From the periodic orbit (:func:`hawksim.flight.orbit.periodic_orbit`) the open-loop nonlinear flight
(:func:`hawksim.flight.orbit.fly_orbit`, one continuous flight) is launched with a small perturbation and strobed
at phase 0 every beat; the unperturbed orbit flight of the same length is subtracted (this removes the orbit's own
residual drift, which grows by the multipliers too), leaving the per-beat deviation d_k (8,), normalized as the
Floquet states (u/U, v/U, w/U, pT, qT, rT, phi, theta; U = 2 phi_a f r2, T = 1/f, :func:`state_scale`).

Perturbations, per system (longitudinal (u, w, q, theta), lateral (v, p, r, phi); orders of
:mod:`hawksim.stability.system` and of the Floquet blocks, checked identical):

* along each Floquet mode: the real part of its right eigenvector (and, for a complex pair, separately the
  imaginary part), scaled to max-norm ``eps``;
* along each state separately (``eps`` in that normalized state), for the model-free fit and the figures.

Fits. (1) MODAL (the reported ``nonlinear``): the deviation is projected on the Floquet modal coordinates,
a_k = (V^-1 d_k)[i] (rows of V^-1 are the left eigenvectors, so the other three modes drop out to first order),
and ln a_k = ln a_0 + lambda k is fitted by least squares (Re lambda from ln|a_k|, Im lambda from the unwrapped
phase) over the fit window. This fits one exponential per mode over many beats, so a stable mode is measured
although the unstable ones dominate the state; only the projection uses the Floquet vectors, the rate is the
flight's. (2) LINEAR MAP (``nonlinear_map``, no Floquet input): from the four per-state flights of a system,
the least-squares map M_nl with d_{k+1} = M_nl d_k over the window (stacked over the four flights); its
eigenvalues' logarithms. Rates are per wingbeat, comparable with the Floquet exponents ln(mu) and the
eigenvalues of the nondimensional averaged A (t+ = t/T).

Window and amplitude. The fit window is the first J beats, J the largest <= ``beats`` at which the unperturbed
flight still lies within :data:`DRIFT_MAX` of the orbit (the linearization is about the orbit, not about a
departing flight); for a mode's own fit the window also ends when |a_k| falls below :data:`NOISE_REL` |a_0|
(stable modes decay into round-off). The amplitude is eps = min(:data:`EPS_MAX`, :data:`DEV_MAX` /
max(1, |mu_max|)^J) (normalized units) longitudinally, so that the largest deviation in the window stays near
DEV_MAX, and min(:data:`LAT_EPS`, :data:`LAT_DEV_MAX` / max(1, |mu_max|)^J) laterally (larger: see LAT_EPS on
the quasi-steady load switch). Linearity
is SHOWN, not assumed: every fit is repeated at eps / 2 and the two rates compared (``halving``).

Averaged model: the quasi-steady A of :func:`hawksim.stability.floquet.quasi_steady_system` at the orbit's
kinematics, or for the UVLM the A of :func:`hawksim.stability.report.stability_report` at the orbit's kinematics.
Its eigenvalues are paired with the Floquet exponents by the assignment of least total distance.
"""

from __future__ import annotations

import io
import itertools
import json
import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from hawksim.atomic import write_bytes, write_text
from hawksim.flight.orbit import Orbit, fly_orbit, periodic_orbit
from hawksim.stability.floquet import LAT, LONG, monodromy, state_scale

SYSTEMS = {"longitudinal": (LONG, ("u", "w", "q", "theta")), "lateral": (LAT, ("v", "p", "r", "phi"))}
"""System -> (indices into the 8 Floquet states, state names); the orders of A_long / A_lat (system.py)."""

BEATS = 15
"""Wingbeats flown per perturbed flight (quasi-steady)."""

UVLM_BEATS = 8
"""Wingbeats flown per perturbed flight (UVLM; the orbit's warm-up beats come on top)."""

DRIFT_MAX = 1e-2
"""Max-norm (normalized) distance of the unperturbed flight from the orbit's phase-0 state up to which beats
enter the fit. Measured (quasi-steady, 15 beats): 2e-3 at 0-1 m/s at beat 15, reached at beat 11 at 1.5 m/s and
beat 9 at 2 m/s (the flight departs at beat 13 there)."""

DEV_MAX = 1e-3
"""Target max-norm (normalized) of the perturbation's deviation at the end of the fit window."""

EPS_MAX = 1e-4
"""Largest perturbation amplitude (normalized)."""

UVLM_EPS = 1e-3
"""UVLM perturbation amplitude (normalized): the free wake amplifies round-off, so smaller perturbations
difference noise (the orbit's finite-difference step is the same, hawksim.flight.orbit.UVLM_FD_STEP)."""

NOISE_REL = 1e-3
"""A mode's fit window ends when its modal amplitude falls below this fraction of its start."""

LAT_EPS = 4e-3
"""Lateral perturbation amplitude (normalized), unless LAT_DEV_MAX / max(1, |mu_max|)^J is smaller. Larger than
the longitudinal one on purpose: the quasi-steady model's load switch at chordwise-velocity reversal (centre of
pressure and 3/4-chord point jump, aero/quasi_steady.py ``if uc >= 0``) makes the fixed-step map piecewise
smooth: a perturbation that moves a strip's reversal across a time step changes that step's load by a finite
amount. The left/right-antisymmetric lateral perturbation moves the two wings' reversals apart, so lateral
deviations carry this switching noise; its relative size falls as the number of switched steps grows with
the amplitude (measured at 1 m/s, lateral slow mode: fitted rate -0.017-0.082i at 1e-3, -0.022-0.076i at
4e-3, -0.023-0.074i at 1e-2, Floquet -0.028-0.068i; at 1e-4 the deviation is dominated by single switches)."""

LAT_DEV_MAX = 2e-2
"""Target max-norm (normalized) of a lateral deviation at the end of the fit window."""

TARGET_REL_ERROR = 0.05
"""Issue 19's target: nonlinear vs Floquet exponent within 5 % on every unstable mode (``meets_target`` in the
JSON: null for a stable or an unresolved mode, see hawksim.stability.floquet.RESOLVE_TOL)."""

MIN_WINDOW = 3
"""Fewest beats (k = 0 .. MIN_WINDOW - 1) in a fit."""


@dataclass(frozen=True)
class Flight:
    """Per-beat normalized deviation (beats + 1, 8) of a perturbed flight from the unperturbed one."""

    d: np.ndarray
    wall_time_s: float


def _fly_dev(orbit: Orbit, ref: np.ndarray, d8: np.ndarray, beats: int, symmetric: bool | None) -> Flight:
    sc = state_scale(orbit.kinematics, orbit.insect.morphology)
    dx = np.zeros(9)
    dx[:8] = d8 * sc
    b = fly_orbit(orbit, beats, perturbation=dx, symmetric=symmetric)
    return Flight(b.states[:, :8] / sc - ref, b.wall_time_s)


def fit_rate(a: np.ndarray) -> complex:
    """Least-squares exponent lambda of a_k = a_0 exp(lambda k), k = 0 .. len(a) - 1: Re from ln|a_k|, Im from the
    unwrapped phase."""
    k = np.arange(len(a))
    re = np.polyfit(k, np.log(np.abs(a)), 1)[0]
    im = np.polyfit(k, np.unwrap(np.angle(a)), 1)[0]
    return complex(re, im)


def _window(a: np.ndarray, J: int) -> int:
    """Beats 0 .. n - 1 of a modal amplitude a that enter the fit: within the drift window J and above noise."""
    n = J + 1
    small = np.nonzero(np.abs(a[:n]) < NOISE_REL * np.abs(a[0]))[0]
    if len(small):
        n = int(small[0])
    return max(min(n, len(a)), MIN_WINDOW)


def fit_map(devs: list[np.ndarray], n: int) -> np.ndarray:
    """Least-squares one-beat map M (m, m) with d_{k+1} = M d_k, k < n - 1, over all flights in devs
    ((beats + 1, m) each)."""
    X = np.concatenate([d[: n - 1] for d in devs]).T
    Y = np.concatenate([d[1:n] for d in devs]).T
    return np.linalg.lstsq(X.T, Y.T, rcond=None)[0].T


def pair_exponents(floq: np.ndarray, avg: np.ndarray) -> list[int]:
    """For each Floquet exponent the index of the averaged eigenvalue (assignment of least total distance)."""
    best = min(itertools.permutations(range(len(avg))),
               key=lambda p: sum(abs(floq[i] - avg[p[i]]) for i in range(len(floq))))
    return list(best)


def _c(z) -> list[float]:
    z = complex(z)
    return [float(z.real), float(z.imag)]


def _rel(a, b) -> float:
    den = abs(complex(b))
    return float(abs(complex(a) - complex(b)) / den) if den > 0 else float("inf")


def chart_map(system: str, V_over_U: float, u_e: float = 0.0) -> np.ndarray:
    """T (4, 4) with x_avg = T x_orbit: the averaged model's states (Etkin's BODY-fixed stability axes, velocity
    components that turn with the perturbed attitude) from the orbit chart's (velocities in the LEVEL heading
    axes, :mod:`hawksim.flight.orbit`). About the equilibrium velocity (0, 0, w_e) the body components are
    v_b = v_level - a x (0, 0, w_e), a = (phi, theta, 0): u_b = u - w_e theta, v_b = v + w_e phi (normalized,
    w_e+ = -V/U); rates and angles agree to first order (the averaged reference has no rotation). Eigenvalues
    do not depend on the chart; eigenvectors and per-state predictions do: expm(A k) is compared as
    T^-1 expm(A k) T. Checked: T^-1 A_long T has the (u, q) entry Xq/m (0.001 at 2 m/s) against logm of the
    Floquet block's -0.014, where A_long's own entry is Xq/m - w_e = 1.3.

    Forward flight (``u_e`` = U / U_ref, the forward speed normalized; :mod:`hawksim.stability.system`): about the
    equilibrium velocity (u_e, 0, w_e) also w_b = w + u_e theta; the heading axes turn with the yaw, so v has no
    psi term."""
    T = np.eye(4)
    T[0, 3] = V_over_U if system == "longitudinal" else -V_over_U
    if u_e and system == "longitudinal":
        T[1, 3] = u_e
    return T


def drift(ref_states: np.ndarray, orbit: Orbit) -> np.ndarray:
    """(beats + 1,) max-norm normalized distance of a flight's phase-0 states from the orbit's."""
    sc = state_scale(orbit.kinematics, orbit.insect.morphology)
    return np.abs(ref_states[:, :8] / sc - orbit.initial_state.as_array()[:8] / sc).max(axis=1)


def validate_speed(orbit: Orbit, floquet, A: dict[str, np.ndarray], *, beats: int | None = None,
                   systems: tuple[str, ...] = ("longitudinal", "lateral"), modes: str = "all",
                   state_flights: bool = True, eps: float | None = None, log=None) -> dict:
    """Perturbed nonlinear flights about ``orbit`` against its Floquet matrix ``floquet``
    (:class:`hawksim.stability.floquet.Floquet`) and the averaged A matrices ``A`` ({'longitudinal': A_long,
    'lateral': A_lat}, nondimensional, t+ = t/T). ``modes``: 'all' or 'unstable' (``|mu| > 1`` only). Returns the
    JSON-ready result of the speed (see the module docstring), with the raw deviations under ``_flights``."""
    from scipy.linalg import expm

    uvlm = orbit.aero == "uvlm"
    beats = beats if beats is not None else (UVLM_BEATS if uvlm else BEATS)
    sc = state_scale(orbit.kinematics, orbit.insect.morphology)
    t0 = time.perf_counter()
    refs = {}
    for sym in ((True, False) if uvlm else (None,)):
        b = fly_orbit(orbit, beats, symmetric=sym if uvlm else None)
        refs[sym] = b.states
    dr = drift(refs[next(iter(refs))], orbit)
    J = int(max(k for k in range(beats + 1) if k <= beats and np.all(dr[: k + 1] <= DRIFT_MAX)))
    J = max(J, MIN_WINDOW - 1)
    out = {"speed": orbit.speed, "aero": orbit.aero, "beats": beats, "fit_window_beats": J,
           "reference_drift": dr.tolist(), "systems": {}, "_flights": {}} | (
               {"forward_speed": orbit.forward_speed} if orbit.forward_speed else {})
    for name in systems:
        idx, names = SYSTEMS[name]
        idx = list(idx)
        block = floquet.long if name == "longitudinal" else floquet.lat
        mu, V = np.linalg.eig(block)
        order = np.argsort(-np.abs(mu), kind="stable")
        mu, V = mu[order], V[:, order]
        Vinv = np.linalg.inv(V)
        lam_f = np.log(mu.astype(complex))
        fq_ex = floquet.exponents_long if name == "longitudinal" else floquet.exponents_lat
        fq_ok = floquet.resolved_long if name == "longitudinal" else floquet.resolved_lat
        fq_reach = floquet.reach_long if name == "longitudinal" else floquet.reach_lat
        near = [int(np.argmin(np.abs(fq_ex - z))) for z in lam_f]
        lam_a = np.linalg.eigvals(A[name])
        pairing = pair_exponents(lam_f, lam_a)
        sym = (name == "longitudinal") if uvlm else None
        ref = refs[sym if uvlm else None][:, :8] / sc
        mu_max = max(1.0, float(np.abs(mu).max()))
        if eps is not None:
            e = eps
        elif uvlm:
            e = UVLM_EPS
        elif name == "longitudinal":
            e = min(EPS_MAX, DEV_MAX / mu_max**J)
        else:
            e = min(LAT_EPS, LAT_DEV_MAX / mu_max**J)

        def fly(d4, amp, idx=idx, ref=ref, name=name):
            d8 = np.zeros(8)
            d8[idx] = amp * d4
            f = _fly_dev(orbit, ref, d8, beats, None if not uvlm else (name == "longitudinal"))
            return f.d[:, idx]

        entries, raw = [], {}
        done = set()
        for i in range(4):
            if i in done or (modes == "unstable" and abs(mu[i]) <= 1.0):
                continue
            cplx = abs(mu[i].imag) > 1e-12
            if cplx:
                j = int(np.argmin(np.abs(mu - np.conj(mu[i])) + (np.arange(4) == i) * 1e9))
                done.add(j)
                if mu[i].imag < 0:  # report the member with Im >= 0
                    i, j = j, i
            done.add(i)
            parts = (("real", np.real(V[:, i])), ("imag", np.imag(V[:, i]))) if cplx else (("real", np.real(V[:, i])),)
            fits = {}
            for part, vec in parts:
                vec = vec / np.abs(vec).max()
                res = {}
                for tag, amp in (("full", e), ("half", e / 2)):
                    dev = fly(vec, amp)
                    a = dev @ Vinv[i]
                    n = _window(a, J)
                    res[tag] = (fit_rate(a[:n]), n)
                    if tag == "full" and part == "real":
                        raw[f"mode{i}"] = {"d0": (amp * vec).tolist(), "dev": dev.tolist(), "modal": _c_list(a)}
                fits[part] = res
            lam_nl, n_fit = fits["real"]["full"]
            lam_half = fits["real"]["half"][0]
            la = lam_a[pairing[i]]
            entry = {
                "mode": i, "kind": "oscillatory" if cplx else ("divergence" if abs(mu[i]) > 1 else "subsidence"),
                "multiplier": _c(mu[i]), "abs_multiplier": float(abs(mu[i])),
                "floquet": _c(lam_f[i]), "averaged": _c(la), "nonlinear": _c(lam_nl),
                "rel_error_nonlinear_vs_floquet": _rel(lam_nl, lam_f[i]),
                "rel_error_nonlinear_vs_averaged": _rel(lam_nl, la),
                "rel_error_averaged_vs_floquet": _rel(la, lam_f[i]),
                "amplitude": e, "fit_beats": n_fit, "resolved": bool(fq_ok[near[i]]),
                "reach": float(fq_reach[near[i]]),
                "halving": {"nonlinear_half_amplitude": _c(lam_half), "rel_change": _rel(lam_half, lam_nl)},
            }
            if cplx:
                li, lih = fits["imag"]["full"][0], fits["imag"]["half"][0]
                entry["nonlinear_from_imag_part"] = _c(li)
                entry["rel_error_imag_part_vs_floquet"] = _rel(li, lam_f[i])
                entry["halving"]["imag_part_rel_change"] = _rel(lih, li)
            entries.append(entry)
            if log is not None:
                log(f"  {name} mode {i}: floquet {lam_f[i]:.4f} averaged {la:.4f} nonlinear {lam_nl:.4f} "
                    f"(half {lam_half:.4f}) fit {n_fit} beats, eps {e:.2e}")
        sysout = {"states": list(names), "amplitude": e, "modes": entries,
                  "floquet_exponents": [_c(z) for z in lam_f], "averaged_eigenvalues": [_c(z) for z in lam_a],
                  "pairing_floquet_to_averaged": pairing}
        if state_flights:
            devs, devs_h = [], []
            for s in range(4):
                unit = np.eye(4)[s]
                devs.append(fly(unit, e))
                devs_h.append(fly(unit, e / 2))
            n = J + 1
            lm = np.log(np.linalg.eigvals(fit_map(devs, n)).astype(complex))
            lmh = np.log(np.linalg.eigvals(fit_map(devs_h, n)).astype(complex))
            pm = pair_exponents(lam_f, lm)
            ph = pair_exponents(lam_f, lmh)
            sysout["nonlinear_map"] = {
                "exponents_paired_to_floquet": [_c(lm[pm[i]]) for i in range(4)],
                "half_amplitude": [_c(lmh[ph[i]]) for i in range(4)],
                "rel_error_vs_floquet": [_rel(lm[pm[i]], lam_f[i]) for i in range(4)],
                "halving_rel_change": [_rel(lmh[ph[i]], lm[pm[i]]) for i in range(4)],
                "window_beats": n}
            M = block
            Tc = chart_map(name, orbit.speed / sc[0], orbit.forward_speed / sc[0])
            Ad = np.linalg.solve(Tc, A[name] @ Tc)
            for s in range(4):
                x0 = devs[s][0]
                raw[f"state_{names[s]}"] = {
                    "dev": devs[s].tolist(),
                    "floquet": [(np.linalg.matrix_power(M, k) @ x0).tolist() for k in range(beats + 1)],
                    "averaged": [(expm(Ad * k) @ x0).real.tolist() for k in range(beats + 1)],
                    "averaged_chart": "T^-1 expm(A k) T x0 (chart_map)"}
        out["systems"][name] = sysout
        out["_flights"][name] = {"amplitude": e, **raw}
    out["wall_time_s"] = time.perf_counter() - t0
    return out


def _c_list(a) -> list[list[float]]:
    return [_c(z) for z in a]


def averaged_A_uvlm(orbit: Orbit, client=None) -> tuple[dict, dict]:
    """(A by system, the stability report) of the UVLM's cycle-averaged derivatives at the orbit's kinematics."""
    from hawksim.stability.report import stability_report

    rep = stability_report(orbit.speed, kinematics=orbit.kinematics, client=client,
                           forward_speed=orbit.forward_speed)
    return ({"longitudinal": np.array(rep["longitudinal"]["matrix"]),
             "lateral": np.array(rep["lateral"]["matrix"])}, rep)


def run_speed(speed: float, aero: str = "quasi-steady", *, client=None, log=None, lateral: bool = True,
              orbit: Orbit | None = None, **kw) -> dict:
    """Orbit, Floquet matrix, averaged A and the perturbed flights at one speed; wall times of each. ``orbit``: the
    periodic orbit to validate about (default: the shipped one at ``speed``, else solved; a forward-flight orbit,
    ``orbit.forward_speed`` > 0, is given this way and its averaged model is taken at its condition)."""
    from hawksim.stability.floquet import quasi_steady_system

    from hawksim.flight.orbit import shipped_orbit

    t = time.perf_counter()
    if orbit is None:
        orbit = shipped_orbit(speed, aero) or periodic_orbit(speed, aero)
    t_orbit = time.perf_counter() - t if orbit.wall_time_s == 0 else orbit.wall_time_s
    if log is not None:
        log(f"{aero} {speed} m/s: orbit residual {orbit.residual:.2e} ({orbit.iterations} it, {t_orbit:.1f} s)")
    t = time.perf_counter()
    fq = monodromy(orbit, lateral=lateral)
    t_mono = time.perf_counter() - t
    t = time.perf_counter()
    if aero == "uvlm":
        A, _ = averaged_A_uvlm(orbit, client)
    else:
        av = quasi_steady_system(orbit.kinematics, speed, forward_speed=orbit.forward_speed)
        A = {"longitudinal": av.A_long, "lateral": av.A_lat}
    t_avg = time.perf_counter() - t
    res = validate_speed(orbit, fq, A, systems=("longitudinal", "lateral") if lateral else ("longitudinal",),
                         log=log, **kw)
    res["orbit"] = {"residual": orbit.residual, "converged": orbit.converged, "iterations": orbit.iterations,
                    "floor": orbit.floor, "f_hz": orbit.kinematics.f,
                    "phi0_deg": float(np.degrees(orbit.kinematics.phi0)),
                    "warm_beats": orbit.warm_beats}
    res["floquet_coupling"] = fq.coupling
    res["wall_times_s"] = {"orbit": t_orbit, "monodromy": t_mono, "averaged": t_avg, "flights": res["wall_time_s"]}
    res["monodromy_lateral"] = lateral
    res["A"] = {k: np.asarray(v).tolist() for k, v in A.items()}
    return res


# ---- figures -------------------------------------------------------------------------------------------
LABELS = {"u": r"$\Delta u/U$ (-)", "w": r"$\Delta w/U$ (-)", "q": r"$\Delta q\,T$ (rad)",
          "theta": r"$\Delta\theta$ (rad)", "v": r"$\Delta v/U$ (-)", "p": r"$\Delta p\,T$ (rad)",
          "r": r"$\Delta r\,T$ (rad)", "phi": r"$\Delta\phi$ (rad)"}


def plot_speed(res: dict, out_dir: Path) -> list[str]:
    """Per system: a 4 x 4 grid, row = the state perturbed at the launch, column = the deviated state; nonlinear
    per-beat deviation (dots) with the Floquet (M^k x0) and averaged (expm(A k) x0) predictions, divided by the
    amplitude. PNG (300 dpi) and PDF."""
    from hawksim import plotting

    plt = plotting.pyplot()
    out_dir.mkdir(parents=True, exist_ok=True)
    paths = []
    for name, sysout in res["systems"].items():
        raw = res["_flights"][name]
        names = sysout["states"]
        if f"state_{names[0]}" not in raw:
            continue
        eps = raw["amplitude"]
        fig, axs = plt.subplots(4, 4, figsize=(13, 10.5), sharex=True)
        J = res["fit_window_beats"]
        for r, sp in enumerate(names):
            fl = raw[f"state_{sp}"]
            dev, pf, pa = (np.array(fl[k]) / eps for k in ("dev", "floquet", "averaged"))
            k = np.arange(len(dev))
            for c, sc_ in enumerate(names):
                ax = axs[r, c]
                ax.plot(k, pf[:, c], "-", color="C0", lw=1.4, label="Floquet $M^k x_0$")
                ax.plot(k, pa[:, c], "--", color="C3", lw=1.4, label="averaged $e^{Ak}x_0$")
                ax.plot(k, dev[:, c], "o", color="k", ms=3.5, label="nonlinear flight")
                if J < len(dev) - 1:
                    ax.axvspan(J, len(dev) - 1, color="0.9", zorder=-1)
                lim = 1.3 * max(np.abs(dev[: J + 1, c]).max(), np.abs(pf[: J + 1, c]).max(), 1e-12)
                ax.set_ylim(-lim, lim)
                ax.text(0.03, 0.9, f"({chr(97 + 4 * r + c)})", transform=ax.transAxes, fontsize=9, weight="bold")
                if r == 3:
                    ax.set_xlabel("wingbeat k (t/T)")
                if c == 0:
                    ax.set_ylabel(f"perturbed {sp}\n" + LABELS[sc_] + r" / $\epsilon$", fontsize=9)
                else:
                    ax.set_ylabel(LABELS[sc_] + r" / $\epsilon$", fontsize=9)
                ax.tick_params(labelsize=8)
        axs[0, 0].legend(fontsize=7, loc="lower left")
        fig.suptitle(f"{res['aero']}, V = {res['speed']:g} m/s, {name}: deviation from the orbit flight per unit "
                     f"launch perturbation ($\\epsilon$ = {eps:.2g}, normalized); grey: beyond the fit window",
                     fontsize=10)
        fig.tight_layout(rect=(0, 0, 1, 0.97))
        stem = out_dir / f"validation_{res['aero'].replace('-', '_')}_{res['speed']:g}ms_{name}"
        try:
            for ext in plotting.FORMATS:  # each file all or nothing (a full disk: OSError naming it)
                buf = io.BytesIO()
                fig.savefig(buf, format=ext, dpi=plotting.DPI)
                write_bytes(f"{stem}.{ext}", buf.getvalue(), "figure")
                paths.append(f"{stem}.{ext}")
        finally:
            plt.close(fig)
    return paths


def write(results: list[dict], out_dir: Path, meta: dict, figures: bool = True, name: str = "validation.json") -> dict:
    """validation.json (one entry per speed, system and mode; raw deviations left out) and the figures."""
    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    figs = []
    if figures:
        for r in results:
            figs += plot_speed(r, out_dir)
    rows = []
    for r in results:
        for sysname, s in r["systems"].items():
            for m in s["modes"]:
                rows.append({"speed": r["speed"], "aero": r["aero"], "system": sysname, **m})
    path = out_dir / name
    old = json.loads(path.read_text()) if path.is_file() else {}
    rows = [{**e, "meets_target": (e["rel_error_nonlinear_vs_floquet"] <= TARGET_REL_ERROR
                                   if e["abs_multiplier"] > 1.0 and e.get("resolved", True) else None)}
            for e in rows]
    keep = [e for e in old.get("entries", []) if e["aero"] not in {r["aero"] for r in results}]
    keep_speeds = [e for e in old.get("speeds", []) if e["aero"] not in {r["aero"] for r in results}]
    doc = {"meta": {**old.get("meta", {}), **meta},
           "entries": keep + rows,
           "speeds": keep_speeds + [{k: v for k, v in r.items() if k not in ("_flights",)} for r in results],
           "figures": sorted(set(old.get("figures", []) + [Path(p).name for p in figs]))}
    write_text(path, json.dumps(doc, indent=1), "validation")
    return {"json": str(path), "figures": figs}


def reproduce(out_dir: Path, *, aero: str = "quasi-steady", speeds=None, log=print, client=None) -> dict:
    """`hawksim reproduce --only validation` (quasi-steady, five speeds) or ``validation_uvlm`` (UVLM, 0, 1, 2)."""
    import datetime
    import platform

    if speeds is None:
        speeds = (0.0, 0.5, 1.0, 1.5, 2.0) if aero == "quasi-steady" else (0.0, 1.0, 2.0)
    t0 = time.perf_counter()
    results = []
    for v in speeds:
        try:
            results.append(run_speed(v, aero, client=client, log=log))
        except Exception as exc:  # a speed whose orbit/flight fails is reported, not fatal
            log(f"{aero} {v} m/s failed: {exc!r}")
            results.append({"speed": v, "aero": aero, "error": repr(exc), "systems": {}, "_flights": {}})
    step = "validation" if aero == "quasi-steady" else "validation_uvlm"
    meta = {f"{aero}": {"command": f"hawksim reproduce --only {step}",
                        "date": datetime.datetime.now().isoformat(timespec="seconds"), "host": platform.node(),
                        "wall_time_s": time.perf_counter() - t0,
                        "constants": {"BEATS": BEATS, "UVLM_BEATS": UVLM_BEATS, "DRIFT_MAX": DRIFT_MAX,
                                      "DEV_MAX": DEV_MAX, "EPS_MAX": EPS_MAX,
                                      "LAT_EPS": LAT_EPS, "LAT_DEV_MAX": LAT_DEV_MAX, "UVLM_EPS": UVLM_EPS,
                                      "NOISE_REL": NOISE_REL}},
            "fit": "modal: least-squares exponent of the Floquet modal coordinate (left eigenvectors) of the "
                   "deviation from the unperturbed flight; nonlinear_map: least-squares one-beat map of the four "
                   "per-state flights (no Floquet input)",
            "units": "exponents per wingbeat (t+ = t/T); states normalized u/U, qT, rad; U = 2 phi_a f r2"}
    return write(results, out_dir, meta)
