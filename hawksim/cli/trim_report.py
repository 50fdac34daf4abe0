"""What `hawksim trim` prints without ``--json``: the trim's kinematics, whether any sits on a bound of the paper's
Table 2, the balance residual, P+, whether the search converged, and the UVLM's check or balance where asked; with
``--free-flight``, the periodic orbit's kinematics, launch state, residual and convergence. docs/output.md shows
both."""

from __future__ import annotations

from hawksim.cli.summary import balance_residual, kinematics_text, line, num

BALANCE_TOL = 0.01
"""A trim is balanced when max(|1 - L+|, |D+|, |M+|) <= 0.01: the tolerance of the UVLM balance
(hawksim.trim.balance.balance_on_uvlm's ``tol``) and of the shipped trim table."""
BOUND_FRACTION = 1e-4
"""A parameter within this fraction of its Table 2 range of a bound sits on it (Nelder-Mead works to 1e-10 in the
range-scaled coordinates, and an optimum past a bound is moved onto it: hawksim.trim.search)."""


def on_bounds(kin: dict, bounds_deg: dict | None = None) -> list[str]:
    """The parameters of ``kin`` (f in Hz, angles in deg) that sit on a bound of ``bounds_deg`` ({parameter:
    [lower, upper]}, Hz and deg; None: the default insect's, Table 2), as ``"theta0 25 deg (upper)"``."""
    if bounds_deg is None:
        from hawksim.insect.folder import default_insect

        bounds_deg = default_insect().bounds_deg
    hits = []
    for k, (lo, hi) in bounds_deg.items():
        tol = BOUND_FRACTION * (hi - lo)
        unit = "Hz" if k == "f" else "deg"
        if abs(kin[k] - lo) <= tol:
            hits.append(f"{k} {lo:g} {unit} (lower)")
        elif abs(kin[k] - hi) <= tol:
            hits.append(f"{k} {hi:g} {unit} (upper)")
    return hits


def balance_text(d: dict) -> str:
    """``L+ 1, D+ -2.41e-12, M+ -1.29e-12: balanced, residual 9.3e-12 <= 0.01`` (or ``NOT balanced, residual 0.092 >
    0.01``) of cycle averages; the residual is max(|1 - L+|, |D+|, |M+|)."""
    r = balance_residual(d)
    verdict = (f"balanced, residual {num(r, 2)} <= {BALANCE_TOL:g}" if r <= BALANCE_TOL
               else f"NOT balanced, residual {num(r, 2)} > {BALANCE_TOL:g}")
    return f"L+ {num(d['L_plus'])}, D+ {num(d['D_plus'], 3)}, M+ {num(d['M_plus'], 3)}: {verdict}"


def render_trim(out: dict) -> str:
    """`hawksim trim`'s summary (the surrogate's minimum-power trim; module docstring)."""
    if "initial_state" in out:
        return render_orbit(out)
    if "search_optimum" in out:
        return render_model_trim(out)
    from hawksim.trim.search import GAConfig

    max_gen = GAConfig().max_generations
    bounds = on_bounds(out["kinematics"], out.get("bounds_deg"))
    lines = [f"hawksim trim: minimum-power trim at {out['speed']:g} m/s ascent on the surrogate (GA, seed "
             f"{out['seed']}, then Nelder-Mead; paper Eq. 3)",
             line("kinematics", f"{kinematics_text(out['kinematics'])}; body angle chi {num(out['chi'])} deg"),
             line("bounds", ("ON A BOUND of Table 2: " + ", ".join(bounds)) if bounds
                  else "inside Table 2's bounds"),
             line("balance", f"{balance_text(out)} (the surrogate's)"),
             line("power", f"P+ {num(out['P_plus'])} (the surrogate's, minimised; Eq. 3 fitness "
                           f"{num(out['fitness'])})")]
    ga = (f"GA stalled after {out['generations']} generations (converged)" if out["generations"] < max_gen
          else f"GA NOT converged: stopped at its limit of {max_gen} generations")
    lines.append(line("search", f"{ga}; Nelder-Mead {out['nm_evaluations']} evaluations; {out['wall_time_s']:.1f} s"))
    if "uvlm" in out:
        u = out["uvlm"]
        settled = "" if u["status"] == "ok" else f" ({u['status'].upper()})"
        lines.append(line("UVLM check", f"{balance_text(u)}; P+ {num(u['P_plus'])}{settled}"))
    if "uvlm_balanced" in out:
        b = out["uvlm_balanced"]
        conv = "converged" if b["converged"] else "NOT converged"
        lines.append(line("UVLM balance", f"{conv} after {b['evaluations']} runs: f {num(b['kinematics']['f'])} Hz, "
                                          f"beta {num(b['kinematics']['beta'])}, phi0 {num(b['kinematics']['phi0'])}, "
                                          f"alpha0 {num(b['kinematics']['alpha0'])} deg; {balance_text(b)}; "
                                          f"P+ {num(b['P_plus'])}"))
    lines.append(line("model", str(out["model"])))
    return "\n".join(lines)


def render_model_trim(out: dict) -> str:
    """`hawksim trim --aero MODEL`'s summary: the trim searched and balanced on that model itself
    (hawksim.cli.trim.trim_json's object: the quasi-steady population search or the UVLM's local search)."""
    fwd = f", {out['forward_speed']:g} m/s forward" if out.get("forward_speed") else ""
    how = (f"local search from {out['start_source']}, at most {out['max_evals']} runs" if "max_evals" in out
           else f"GA (seed {out['seed']}, population {out['population']}) and Nelder-Mead, then balanced")
    bounds = on_bounds(out["kinematics"])
    start = out["search_optimum"]
    lines = [f"hawksim trim: minimum-power trim at {out['speed']:g} m/s ascent{fwd} on the {out['model']} model "
             f"({how})",
             line("kinematics", f"{kinematics_text(out['kinematics'])}; body angle chi {num(out['chi'])} deg"),
             line("bounds", ("ON A BOUND of Table 2: " + ", ".join(bounds)) if bounds
                  else "inside Table 2's bounds"),
             line("balance", balance_text(out)),
             line("power", f"P+ {num(out['P_plus'])} (the start's or search optimum's {num(start['P_plus'])})"),
             line("search", f"{out['evaluations']} runs, {out['wall_time_s']:.1f} s: {out['source']}")]
    if "body" in out:
        b = out["body"]
        lines.append(line("body", f"L+ {num(b['L_plus'], 3)}, D+ {num(b['D_plus'], 3)}, M+ {num(b['M_plus'], 3)} "
                                  "(its share of the averages)"))
    return "\n".join(lines)


def render_orbit(out: dict) -> str:
    """`hawksim trim --free-flight`'s summary: the periodic orbit (hawksim.cli.stability.orbit_json's object)."""
    s = out["initial_state"]
    conv = "converged" if out["converged"] else "NOT converged"
    v = ", ".join(f"{x:.3f}".replace("-0.000", "0.000") for x in out["mean_velocity"])
    floor = f" (the wake's beat-to-beat floor {num(out['floor'], 2)})" if out.get("floor") else ""
    return "\n".join([
        f"hawksim trim --free-flight: periodic orbit of the free body at {out['speed']:g} m/s ascent"
        + (f", {out['forward_speed']:g} m/s forward" if out.get("forward_speed") else "")
        + f", {out['aero']} aerodynamics",
        line("kinematics", f"{kinematics_text(out['kinematics'])}; body angle chi {num(out['chi_deg'])} deg "
                           "(f and phi0 solved)"),
        line("residual", f"{num(out['residual'], 2)} after {out['iterations']} Newton iterations: {conv}{floor}"),
        line("start", f"u {num(s['u'])}, w {num(s['w'])} m/s, q {num(s['q_deg_s'])} deg/s, pitch "
                      f"{num(s['theta_deg'])} deg (heading axes: x forward, z down; at the beat's start)"),
        line("mean", f"velocity ({v}) m/s (world, z up), pitch "
                     f"{num(out['mean_pitch_deg'])} deg; P+ {num(out['P_plus'])}"),
        line("wall time", f"{out['wall_time_s']:.1f} s")])
