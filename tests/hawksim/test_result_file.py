"""FlightResult.save / FlightResult.load: the `hawksim fly --out` file read back into a FlightResult, bit for bit."""

import dataclasses
import json
import zipfile

import numpy as np
import pytest

import hawksim
from hawksim.flight.export import FORMAT, STEP_ARRAYS
from hawksim.insect.kinematics import Kinematics
from hawksim.trim import shipped_trim

SPEED = 1.0
CYCLES = 2


@pytest.fixture(scope="module")
def flight():
    """A short quasi-steady flight from the shipped trim at 1 m/s, slightly perturbed (so no array is trivial), its f
    nudged to a number that 12 significant digits do not hold (the edge's Hz and degrees would lose it)."""
    trim = shipped_trim(SPEED, "quasi-steady")
    kin = dataclasses.replace(trim.kinematics, f=trim.kinematics.f * (1 + 1e-6 / 7))
    trim = dataclasses.replace(trim, kinematics=kin)
    backend = hawksim.make_backend("quasi-steady", kinematics=trim.kinematics)
    return hawksim.fly(trim, backend, CYCLES, perturb={"q": 20.0, "phi": 2.0})


def _rewrite(src, dst, edit):
    """Copy the npz ``src`` to ``dst`` with its metadata passed through ``edit(meta) -> meta``."""
    with np.load(src, allow_pickle=False) as z:
        arrays = {k: z[k] for k in z.files}
    arrays["metadata"] = np.array(json.dumps(edit(json.loads(str(arrays["metadata"])))))
    np.savez(dst, **arrays)


def test_round_trip_is_bit_for_bit(flight, tmp_path):
    path = tmp_path / "flight.npz"
    assert flight.save(path) == path
    back = hawksim.FlightResult.load(path)
    for f in dataclasses.fields(hawksim.FlightResult):
        a, b = getattr(flight, f.name), getattr(back, f.name)
        if f.name == "extras":
            assert b == []
        elif isinstance(a, np.ndarray):
            assert b.dtype == a.dtype and b.shape == a.shape, f.name
            assert np.array_equal(a, b), f.name  # exact, not within a tolerance
        else:
            assert type(b) is type(a) and b == a, f.name
    assert back.kinematics == flight.kinematics  # SI floats, not the 12-digit degrees of the edge:
    assert Kinematics.from_edge(flight.kinematics.to_edge(), check_bounds=False) != flight.kinematics
    assert back.summary()["beats"] == flight.summary()["beats"]
    assert len(back.t) == CYCLES * flight.steps_per_cycle and abs(back.end_pos[2] - SPEED * back.end_t) < 0.05


def test_the_file_reads_without_hawksim(flight, tmp_path):
    """What save writes is the documented layout: plain arrays, units in the JSON metadata, the beat table."""
    path = flight.save(tmp_path / "f.npz")
    with zipfile.ZipFile(path) as zf:
        names = {n.removesuffix(".npy") for n in zf.namelist()}
    assert set(STEP_ARRAYS) <= names and "beat_mean_vertical_speed" in names
    with np.load(path, allow_pickle=False) as z:
        meta = json.loads(str(z["metadata"]))
        vz = z["beat_mean_vertical_speed"]
    assert meta["format"] == FORMAT and meta["units"]["force"] == "N" and meta["aero_every"] == 1
    assert np.array_equal(vz, [b["mean_vertical_speed"] for b in flight.beats()])


def test_a_file_without_the_exact_keys_loads_from_the_edge_values(flight, tmp_path):
    """A file written before kinematics_si, aero_every and flight_wall_time_s: kinematics to 12 digits."""
    flight.save(tmp_path / "new.npz")
    drop = ("kinematics_si", "aero_every", "flight_wall_time_s")
    _rewrite(tmp_path / "new.npz", tmp_path / "old.npz", lambda m: {k: v for k, v in m.items() if k not in drop})
    back = hawksim.FlightResult.load(tmp_path / "old.npz")
    np.testing.assert_allclose(back.kinematics.as_array(), flight.kinematics.as_array(), rtol=1e-11, atol=1e-14)
    assert back.aero_every == flight.aero_every and np.array_equal(back.force, flight.force)


def _not_a_flight(tmp_path, kind):
    p = tmp_path / f"{kind}.npz"
    if kind == "text":
        p.write_text("t,z\n0,1\n")
    elif kind == "empty":
        p.write_bytes(b"")
    elif kind == "npy":
        np.save(p.with_suffix(".npy"), np.zeros(3))
        p = p.with_suffix(".npy")
    elif kind == "npz":
        np.savez(p, t=np.zeros(3))
    elif kind == "pickle":
        np.savez(p, metadata=np.array(json.dumps({"format": FORMAT})), t=np.array([{"a": 1}], dtype=object))
    return p


@pytest.mark.parametrize("kind", ["text", "empty", "npy", "npz", "pickle"])
def test_other_files_are_refused_in_one_line(tmp_path, kind):
    p = _not_a_flight(tmp_path, kind)
    with pytest.raises(ValueError) as e:
        hawksim.FlightResult.load(p)
    msg = str(e.value)
    assert "\n" not in msg and str(p) in msg and "not a hawksim flight file" in msg


def test_another_format_is_refused(flight, tmp_path):
    flight.save(tmp_path / "f.npz")
    _rewrite(tmp_path / "f.npz", tmp_path / "v2.npz", lambda m: {**m, "format": "hawksim-flight-npz/2"})
    with pytest.raises(ValueError, match=r"v2\.npz.*format is 'hawksim-flight-npz/2'"):
        hawksim.FlightResult.load(tmp_path / "v2.npz")


def test_a_missing_file_names_its_path(tmp_path):
    with pytest.raises(FileNotFoundError, match="nowhere.npz"):
        hawksim.FlightResult.load(tmp_path / "nowhere.npz")


def test_load_never_unpickles(tmp_path, monkeypatch):
    """allow_pickle=False: an object array raises instead of running pickle."""
    import pickle

    def boom(*a, **k):
        raise AssertionError("unpickled")

    monkeypatch.setattr(pickle, "load", boom)
    monkeypatch.setattr(pickle, "loads", boom)
    with pytest.raises(ValueError):
        hawksim.FlightResult.load(_not_a_flight(tmp_path, "pickle"))


def test_a_richer_beat_table_is_saved_as_given(flight, tmp_path):
    """save(beats=...): a controlled flight's table (nested keys flattened, as `hawksim fly --out` writes it)."""
    rows = [{**b, "commands": {"f_hz": 30.0 + k}} for k, b in enumerate(flight.beats())]
    flight.save(tmp_path / "f.npz", beats=rows)
    with np.load(tmp_path / "f.npz", allow_pickle=False) as z:
        assert np.array_equal(z["beat_commands_f_hz"], [30.0, 31.0])
        assert json.loads(str(z["metadata"]))["units"]["beat_commands_f_hz"] == "Hz"
    assert np.array_equal(hawksim.FlightResult.load(tmp_path / "f.npz").force, flight.force)


def test_loads_the_file_of_hawksim_fly_out(tmp_path, capsys):
    """`hawksim fly --out` (open loop, quasi-steady): the loaded result gives the command's own beat table."""
    from hawksim.cli import main

    path = tmp_path / "cli.npz"
    assert main(["fly", "--speed", "1", "--cycles", "2", "--aero", "quasi-steady", "--control", "none", "--json",
                 "--no-progress", "--out", str(path)]) == 0
    out = json.loads(capsys.readouterr().out)
    back = hawksim.FlightResult.load(path)
    assert back.aero == "quasi-steady" and back.cycles == 2 and back.kinematics.to_edge() == out["kinematics"]
    keys = ("mean_vertical_speed", "horizontal_speed", "pitch_deg", "roll_deg", "yaw_deg")
    assert [{k: b[k] for k in keys} for b in out["beats"]] == back.beats()  # exact: JSON floats round-trip
    assert back.summary()["last_cycle"]["L_plus"] == pytest.approx(out["last_cycle"]["L_plus"], rel=1e-12)
