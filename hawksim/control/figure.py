"""The figure of a controlled flight (docs/control.md): speeds, attitude errors and commands per wingbeat.

Four panels over time [s], one point per wingbeat (beat boundaries from each beat's flown f): (a) commanded speed,
the rate-limited reference, the beat-mean and the within-beat vertical speed [m/s]; (b) pitch error against the
orbit's mean pitch, roll and yaw, beat means [deg], the +-2 deg band of issue 20's bounds shaded; (c) the
symmetric commands, f [Hz] and phi0, alpha0, theta0 [deg]; (d) the antisymmetric commands (left minus right
phi_a, phi0, alpha0 [deg]) and the lateral offset Y [mm] (commands once per beat, or per half-stroke at both
updates). Gusts are shaded over their beats.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from hawksim import plotting


def controlled_flight_figure(cl, path: str | Path, *, title: str, caption: str | None = None) -> Path:
    """Draw the :class:`hawksim.control.closed_loop.ClosedLoop` ``cl`` (flown with ``record=True``) to ``path``
    (PNG and PDF, :func:`hawksim.plotting.save`); returns the PNG's path."""
    r, b = cl.result, cl.beats
    tb = np.cumsum([0.0] + [1 / x["commands"]["f_hz"] for x in b])  # beat boundaries [s]
    tm = (tb[:-1] + tb[1:]) / 2
    with plotting.style():
        plt = plotting.pyplot()
        fig, ax = plt.subplots(4, 1, figsize=(7.5, 9), sharex=True)
        ax[0].plot(r.t, r.body_v[:, 2], color="0.75", lw=0.6, label="within-beat vz")
        ax[0].step(tb, np.r_[[x["speed_command"] for x in b], b[-1]["speed_command"]], where="post", color="k",
                   lw=1, label="command")
        ax[0].step(tb, np.r_[[x["speed_reference"] for x in b], b[-1]["speed_reference"]], where="post",
                   color="C1", lw=1, ls="--", label="reference (rate-limited)")
        ax[0].plot(tm, [x["mean_vertical_speed"] for x in b], "o", ms=3, color="C0", label="beat-mean vz")
        ax[0].set_ylabel("vertical speed [m/s]")
        ax[0].legend(loc="upper left")
        ax[1].plot(tm, [x["pitch_error_deg"] for x in b], "o-", ms=3, label="pitch - orbit mean pitch")
        ax[1].plot(tm, [x["roll_deg"] for x in b], "s-", ms=3, label="roll (right wing down +)")
        ax[1].plot(tm, [x["yaw_deg"] for x in b], "^-", ms=3, label="yaw (nose right +)")
        ax[1].axhspan(-2, 2, color="0.92", zorder=0)
        ax[1].set_ylabel("beat mean [deg]")
        ax[1].legend()
        if "commands_half_stroke" in b[0]:  # per half-stroke: the phase-0 command at mid-beat, phase-0.5 at its end
            tc = np.ravel(np.column_stack([tb[:-1] + (tb[1:] - tb[:-1]) / 2, tb[1:]]))
            c = {key: np.ravel([[x["commands"][key], x["commands_half_stroke"][key]] for x in b])
                 for key in b[0]["commands"]}
        else:
            tc, c = tm, {key: [x["commands"][key] for x in b] for key in b[0]["commands"]}
        ax2 = ax[2].twinx()
        ax[2].plot(tc, c["f_hz"], "o-", ms=3, color="C0", label="f [Hz] (left axis)")
        for key, col in (("phi0_deg", "C1"), ("alpha0_deg", "C2"), ("theta0_deg", "C3")):
            ax2.plot(tc, c[key], ".-", color=col, label=key.replace("_deg", " [deg]"))
        ax[2].set_ylabel("f [Hz]")
        ax2.set_ylabel("symmetric angles [deg]")
        ax2.legend(loc="upper right")
        for key, col in (("dphi_a_deg", "C4"), ("dphi0_deg", "C5"), ("dalpha0_deg", "C6")):
            ax[3].plot(tc, c[key], ".-", color=col, label=key.replace("_deg", "") + " left - right [deg]")
        ax3 = ax[3].twinx()
        ax3.plot(tm, [1e3 * x["horizontal_offset_m"][1] for x in b], "k--", lw=1, label="lateral offset Y [mm]")
        ax3.set_ylabel("Y (right) [mm]")
        ax3.legend(loc="lower right")
        ax[3].set_ylabel("antisymmetric [deg]")
        ax[3].legend(loc="upper right")
        ax[3].set_xlabel("time [s]")
        for g in cl.gusts:
            for a in ax:
                a.axvspan(tb[g.start - 1], tb[min(len(b), g.start - 1 + g.beats)], color="C3", alpha=0.12, zorder=0)
        plotting.panel_letters(ax)
        return plotting.save(fig, path, title=title, caption=caption)
