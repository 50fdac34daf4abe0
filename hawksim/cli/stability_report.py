"""What `hawksim stability` prints without ``--json``: the eigenvalues of the cycle-averaged model and the Floquet
multipliers themselves, one line per system, each mode's kind and stability beside it (``--json`` adds the
derivatives, matrices, eigenvectors and control derivatives; docs/output.md)."""

from __future__ import annotations


def complex_text(z, digits: int = 4) -> str:
    """``[re, im]`` as ``re`` (im = 0) or ``re+/-|im|i`` (a conjugate pair written once; ASCII for any terminal)."""
    re, im = float(z[0]), float(z[1])
    if im == 0:
        return f"{re:.{digits}g}"
    return f"{re:.{digits}g}+/-{abs(im):.{digits}g}i"


def modes_text(modes: list[dict], key: str) -> str:
    """The modes of one system on one line, largest first as given, a conjugate pair once: value (kind, UNSTABLE
    where it grows; 'not resolved' for a Floquet mode the launches do not reach)."""
    parts = []
    for m in modes:
        z = m[key]
        if float(z[1]) < 0 and any(float(o[key][1]) == -float(z[1]) and float(o[key][0]) == float(z[0])
                                   for o in modes):
            continue  # the conjugate of one written already
        text = complex_text(z)
        if key == "multiplier" and float(z[1]) != 0:
            text += f" |{m.get('abs_multiplier', abs(complex(*z))):.4g}|"
        notes = [m.get("kind", "")] + ([] if m.get("stable", True) else ["UNSTABLE"])
        if m.get("resolved") is False:
            notes.append("not resolved")
        parts.append(f"{text} ({', '.join(n for n in notes if n)})")
    return ", ".join(parts)


def render(out: dict) -> str:
    """The stability summary (module docstring)."""
    kin = (out.get("trim") or {}).get("kinematics") or (out.get("orbit") or {}).get("kinematics") or {}
    kin_text = ", ".join(f"{k} {v:.4g}" for k, v in kin.items())
    fwd = f", {out['forward_speed']:g} m/s forward" if out.get("forward_speed") else ""
    lines = [f"hawksim stability: {out['aero']} model at {out['speed']:g} m/s{fwd}"
             + (f"; kinematics {kin_text} (f in Hz, angles in deg)" if kin_text else "")]
    if "longitudinal" in out:
        lines.append("  cycle-averaged model, eigenvalues (nondimensional, paper Eqs. 6-12):")
        for name in ("longitudinal", "lateral"):
            lines.append(f"    {name:<13}{modes_text(out[name]['modes'], 'eigenvalue')}")
    fl = out.get("floquet")
    if fl:
        o = out.get("orbit") or {}
        conv = "converged" if o.get("converged") else "NOT converged"
        lines.append(f"  Floquet multipliers per wingbeat (periodic orbit: f {o.get('kinematics', {}).get('f', 0):.4g} "
                     f"Hz, residual {o.get('residual', 0):.1e}, {conv}):")
        for name in ("longitudinal", "lateral"):
            lines.append(f"    {name:<13}{modes_text(fl[name]['modes'], 'multiplier')}")
        lines.append(f"    largest |multiplier| {fl['max_abs_multiplier']:.4g} per beat"
                     + (f" (resolved: {fl['max_abs_resolved_multiplier']:.4g})"
                        if fl.get("max_abs_resolved_multiplier") != fl["max_abs_multiplier"] else ""))
        if fl.get("records"):
            lines.append(f"    (on the augmented state: the body and the {fl['records']} records of the network's "
                         "calls)")
    if o_note := (out.get("orbit") or {}).get("kinematics_solved"):
        lines.append(f"  note         {o_note['note']}")
    lines.append("  --json adds the derivatives, the A matrices, the eigenvectors and the control derivatives")
    return "\n".join(lines)
