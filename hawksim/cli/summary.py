"""The pieces the commands' summaries are written with (docs/output.md): a number for a person, the kinematics in
one line, the four cycle averages, a held-body resolution, a labelled line.

Every summary is a function of the command's ``--json`` object alone (``render(out) -> str``), so that what a person
reads and what a script reads are the same numbers; edge units as in the JSON (Hz, deg, m/s, s).
"""

from __future__ import annotations

LABEL_WIDTH = 13
"""Width of the label column of a summary's lines (``"  kinematics    f 28.5 Hz, ..."``); a label is at most this
long, and one space follows it."""

LOADS = (("L_plus", "L+"), ("D_plus", "D+"), ("M_plus", "M+"), ("P_plus", "P+"))
"""The cycle averages' JSON keys and their printed names (paper: L/W, D/W, M/(W c), P/P0)."""

ANGLES = ("beta", "phi0", "theta0", "alpha0", "phi_a", "alpha_a")
"""The kinematic angles of ``kinematics`` objects [deg], in the paper's order after f."""


def num(x, digits: int = 4) -> str:
    """A float for a person: ``digits`` significant digits, fixed notation from 1e-3 to 1e5, scientific outside;
    '-' for None. Zero prints as 0."""
    if x is None:
        return "-"
    x = float(x)
    if x == 0:
        return "0"
    if 1e-3 <= abs(x) < 1e5:
        text = f"{x:.{digits}g}"
        return text if "e" not in text else f"{x:.0f}"
    return f"{x:.{max(digits - 1, 1)}e}"


def line(label: str, text: str) -> str:
    """One line of a summary: two spaces, the label padded to :data:`LABEL_WIDTH`, a space, the text."""
    return f"  {label:<{LABEL_WIDTH}} {text}"


def kinematics_text(kin: dict) -> str:
    """``f 28.5 Hz, beta 2.47, phi0 -4.5, theta0 15, alpha0 1.8, phi_a 60, alpha_a 65 deg`` from a ``kinematics``
    object (f in Hz, angles in deg)."""
    return f"f {num(kin['f'])} Hz, " + ", ".join(f"{k} {num(kin[k])}" for k in ANGLES) + " deg"


def loads_text(d: dict, digits: int = 4) -> str:
    """``L+ 0.8042, D+ 0.05571, M+ 0.04081, P+ 0.8922`` from an object with the four cycle averages."""
    return ", ".join(f"{name} {num(d[key], digits)}" for key, name in LOADS)


def balance_residual(d: dict) -> float:
    """The balance residual of cycle averages: max(|1 - L+|, |D+|, |M+|) (lift equal to the weight, no net drag, no
    net pitching moment: a trim's three conditions, paper Eq. 3)."""
    return max(abs(1.0 - d["L_plus"]), abs(d["D_plus"]), abs(d["M_plus"]))


def resolution_text(res: dict) -> str:
    """A held-body resolution in words: ``UVLM 6 x 12 rings per wing, 40 steps per beat, 3 beats (last 1
    averaged)`` (the quasi-steady model has no lattice)."""
    model = (f"UVLM {res['n_chord']} x {res['n_span']} rings per wing, " if res["aero"] == "uvlm"
             else f"{res['aero']}, ")
    return (model + f"{res['steps_per_cycle']} steps per beat, {res['cycles']} beats (last "
            f"{res['average_cycles']} averaged)")
