"""Screenshots of hawksim recordings' default view, taken by the real Rerun viewer (for docs/recording.md).

Usage (from the repository root)::

    python scripts/render_recording.py                       # the documented flights -> docs/images/recording-*.png
    python scripts/render_recording.py A.rrd [B.rrd ...]     # any recordings (at their last step) -> docs/images/

Options: ``--out-dir DIR`` (default docs/images), ``--size WxH`` (the viewer's window in points, default 1600x900;
the PNG is saved at that size).

The documented flights (open loop, from the shipped periodic orbit at 1 m/s, as ``hawksim fly --control none``):

* ``recording-quasi-steady.png``: 2 wingbeats, quasi-steady aerodynamics, cut at the step of largest lift in the
  second beat (so that the force arrows are long);
* ``recording-uvlm.png``: 2 wingbeats, UVLM with its panels and wake at every UVLM update (``fly --aero uvlm
  --rrd``), cut at the update of largest lift in the second beat;
* ``recording-pitch-over.png``: 10 wingbeats after a pitch-rate kick (``fly --perturb q=100 --control none``): the
  moth pitches over and the attitude panel shows the pitch passing 90 deg with the roll staying 0.

Needs: the viewer of the installed rerun-sdk (``rerun`` beside the Python executable, or on PATH); an X display
(``DISPLAY``), or Xvfb, which the script starts on a free display (Debian: ``apt-get install -y xvfb``); a Vulkan
driver, which without a GPU is Mesa's software one (``apt-get install -y mesa-vulkan-drivers``). Rerun's OpenGL
backend on Mesa's llvmpipe does not start ("Adapter does not support drawing to texture format R32Float"). Each
screenshot takes 10-30 s of CPU under the software renderer. The viewer is run as ``rerun --screenshot-to PNG
--window-size WxH FILE``; the PNG is then downscaled to the window size and reduced to 256 colours (Pillow).

Prints one JSON object: {"images": [paths], "viewer": path}.
"""

from __future__ import annotations

import argparse
import dataclasses
import json
import os
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
VIEWER_TIMEOUT_S = 300


def viewer() -> str:
    exe = Path(sys.executable).with_name("rerun")
    found = str(exe) if exe.exists() else shutil.which("rerun")
    if not found:
        sys.exit("render_recording: the Rerun viewer `rerun` was found neither beside python nor on PATH")
    return found


class Display:
    """The X display to draw on: ``DISPLAY`` if set, else an Xvfb started here (stopped on exit). The screen is
    larger than the window, so that the pointer (at the screen's centre) is off the window and shows no tooltip."""

    def __init__(self):
        self.proc = None
        self.env = dict(os.environ)

    def __enter__(self):
        if not self.env.get("DISPLAY"):
            xvfb = shutil.which("Xvfb")
            if xvfb is None:
                sys.exit("render_recording: no DISPLAY and no Xvfb (Debian: apt-get install -y xvfb)")
            n = next(k for k in range(90, 200) if not Path(f"/tmp/.X11-unix/X{k}").exists()
                     and not Path(f"/tmp/.X{k}-lock").exists())
            self.proc = subprocess.Popen([xvfb, f":{n}", "-screen", "0", "7000x4200x24", "-nolisten", "tcp"],
                                         stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
            for _ in range(100):
                if Path(f"/tmp/.X11-unix/X{n}").exists():
                    break
                time.sleep(0.1)
            self.env["DISPLAY"] = f":{n}"
        if not self.env.get("XDG_RUNTIME_DIR"):
            self.env["XDG_RUNTIME_DIR"] = tempfile.mkdtemp(prefix="xdg-")
        return self

    def __exit__(self, *exc):
        if self.proc is not None:
            self.proc.terminate()
            self.proc.wait(timeout=10)


def screenshot(rrd: Path, png: Path, size: str, display: Display) -> Path:
    """The viewer's screenshot of ``rrd``'s default view (the time cursor at its last step), saved at ``size``."""
    from PIL import Image

    raw = png.with_suffix(".raw.png")
    cmd = [viewer(), "--screenshot-to", str(raw), "--window-size", size, str(rrd)]
    out = subprocess.run(cmd, env=display.env, capture_output=True, text=True, timeout=VIEWER_TIMEOUT_S, check=False)
    if out.returncode != 0 or not raw.exists():
        err = [line for line in out.stderr.splitlines() if "ERROR" in line or "Error" in line]
        sys.exit(f"render_recording: the viewer failed on {rrd} (exit {out.returncode}): "
                 f"{err[-1] if err else out.stderr[-500:]}")
    w, h = (int(v) for v in size.split("x"))
    img = Image.open(raw).convert("RGB").resize((w, h), Image.LANCZOS)
    img.quantize(colors=256, method=Image.Quantize.MEDIANCUT).save(png, optimize=True)
    raw.unlink()
    return png


def cut(result, k: int):
    """The flight's first ``k`` steps (a recording cut there shows step k-1 at its end)."""
    arrays = ("t", "body_pos", "body_quat", "body_v", "body_omega", "wing_R", "wing_origin", "force", "moment",
              "power_aero", "power_joint")
    return dataclasses.replace(result, **{a: getattr(result, a)[:k] for a in arrays}, end_t=None, end_pos=None,
                               extras=[(i, e) for i, e in result.extras if i < k])


def largest_lift_step(result, beat: int, every: int = 1) -> int:
    """The step (a multiple of ``every``) of largest lift in wingbeat ``beat`` (0-based)."""
    n = result.steps_per_cycle
    steps = np.arange(beat * n, (beat + 1) * n, every)
    return int(steps[np.argmax(result.lift_drag()[0][steps])])


def documented_recordings(tmp: Path) -> list[tuple[Path, str]]:
    """(rrd, image name) of the documented flights (module docstring)."""
    from hawksim.cli.fly import fly_named
    from hawksim.flight.recording import write_rrd

    out = []
    qs = fly_named(1.0, 2, "quasi-steady")
    out.append((write_rrd(tmp / "qs.rrd", cut(qs, largest_lift_step(qs, 1) + 1)), "recording-quasi-steady.png"))
    uv = fly_named(1.0, 2, "uvlm", keep_extras_every=uv_every())
    out.append((write_rrd(tmp / "uvlm.rrd", cut(uv, largest_lift_step(uv, 1, uv_every()) + 1)),
                "recording-uvlm.png"))
    po = fly_named(1.0, 10, "quasi-steady", perturb={"q": 100.0})
    out.append((write_rrd(tmp / "pitch-over.rrd", po), "recording-pitch-over.png"))
    return out


def uv_every() -> int:
    from types import SimpleNamespace

    from hawksim.flight.simulator import aero_every_for

    return aero_every_for(SimpleNamespace(name="uvlm"), 200)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("rrd", nargs="*", type=Path, help="recordings to render (default: the documented flights)")
    ap.add_argument("--out-dir", type=Path, default=ROOT / "docs" / "images")
    ap.add_argument("--size", default="1600x900", help="viewer window WxH in points (default 1600x900)")
    args = ap.parse_args(argv)
    args.out_dir.mkdir(parents=True, exist_ok=True)
    images = []
    with tempfile.TemporaryDirectory() as tmp, Display() as display:
        jobs = ([(p, p.with_suffix(".png").name) for p in args.rrd] if args.rrd
                else documented_recordings(Path(tmp)))
        for rrd, name in jobs:
            images.append(str(screenshot(rrd, args.out_dir / name, args.size, display)))
            print(f"render_recording: {images[-1]}", file=sys.stderr)
    print(json.dumps({"images": images, "viewer": viewer()}))
    return 0


if __name__ == "__main__":
    sys.exit(main())
