"""An insect is a folder of data (issue 50, item 1): the hawkmoth's folder (spec with each number's source, MJCF,
README, tables and networks keyed by kind, backend and model digest), ``load_insect`` and its one-line errors, and a
copy of the folder under another name flying the same numbers."""

import dataclasses
import hashlib
import json
import shutil
import tomllib

import pytest

from hawksim.insect.folder import (INSECTS_DIR, SOURCE_CLASSES, default_insect, load_insect, shipped_insects,
                                   spec_file)
from hawksim.insect.insect import Insect
from hawksim.insect.kinematics import PARAM_NAMES, TABLE2_BOUNDS_DEG, TABLE3_DEG, TABLE3_SPEEDS
from hawksim.insect.morphology import P0_W, Morphology
from hawksim.insect.tables import KINDS, manifest, mjcf_digest, table_path, table_status

HAWKMOTH_DIR = INSECTS_DIR / "hawkmoth"
KIN = "f=29.4,beta=2.8,phi0=-4.7,theta0=15.0,alpha0=1.2,phi_a=60.0,alpha_a=65.0"


def test_the_hawkmoth_folder_is_todays_default_hawkmoth():
    """The spec names today's ``Morphology()`` number for number (issue 49's sourced hawkmoth, on which the shipped
    tables were regenerated), P0 and Table 2's bounds; its reference kinematics are Table 3."""
    bug = default_insect()
    assert "hawkmoth" in shipped_insects() and load_insect("hawkmoth") is bug
    assert bug == Insect() and bug.morphology == Morphology() and bug.morphology.name == "sourced"
    assert bug.P0 == P0_W and dict(bug.bounds_deg) == {k: tuple(v) for k, v in TABLE2_BOUNDS_DEG.items()}
    assert bug.name == "hawkmoth" and bug.folder == HAWKMOTH_DIR and bug.model_file == "hawkmoth.xml"
    assert bug.reference_deg["speed"] == TABLE3_SPEEDS
    assert all(bug.reference_deg[k] == TABLE3_DEG[k] for k in PARAM_NAMES)
    for name in shipped_insects():  # a shipped insect's spec names its folder
        f = spec_file(INSECTS_DIR / name)  # TOML, or JSON by its suffix (the bumblebee's spec until converted)
        assert (json.loads if f.suffix == ".json" else tomllib.loads)(f.read_text()).get("name", name) == name
    import hawksim

    assert hawksim.load_insect is load_insect and hawksim.default_insect is default_insect


def test_every_number_of_the_spec_has_a_source_class_and_a_citation():
    spec = tomllib.loads(spec_file(HAWKMOTH_DIR).read_text())
    fields = [f.name for f in dataclasses.fields(Morphology) if f.name != "name"]
    assert sorted(k for k in spec["morphology"] if k != "name") == sorted(fields)  # every number named
    entries = {f"morphology.{k}": spec["morphology"][k] for k in fields} | {
        k: spec[k] for k in ("P0", "bounds", "reference_kinematics")}
    for key, e in entries.items():
        assert e["source"] in SOURCE_CLASSES and e["citation"] and e["unit"], key
    assert set(default_insect().sources) == set(entries)


def test_the_committed_mjcf_and_every_shipped_table_carry_the_model_digest():
    bug = default_insect()
    digest = mjcf_digest(bug)
    assert digest == hashlib.sha256((HAWKMOTH_DIR / "hawkmoth.xml").read_bytes()).hexdigest()
    entries = manifest(bug)
    shipped = {p for p in (HAWKMOTH_DIR / "data").rglob("*") if p.suffix in (".json", ".safetensors")}
    assert {e.path for e in entries} == shipped  # every table and network is keyed, none is listed twice
    assert len(entries) == len(shipped) and all(e.kind in KINDS and e.model_sha256 == digest for e in entries)
    assert table_path(bug, "orbit", "uvlm") == HAWKMOTH_DIR / "data" / "orbit_table_uvlm.json"
    assert table_path(bug, "trim", "surrogate") == HAWKMOTH_DIR / "data" / "trim_table.json"
    assert table_path(bug, "orbit", "surrogate-mean") is None  # none shipped: None, not an error
    assert table_path(Insect(), "orbit", "uvlm") is None  # an insect without a folder ships nothing


def _copy(tmp_path, name="moth2", edit=None):
    dest = tmp_path / name
    shutil.copytree(HAWKMOTH_DIR, dest, symlinks=True)
    spec = dest / "insect.toml"
    if edit:
        spec.write_text(edit(spec.read_text()))
    return dest


def test_a_table_of_another_model_is_refused(tmp_path):
    longer = load_insect(_copy(tmp_path, edit=lambda s: s.replace("value = 0.0485\n", "value = 0.05\n")))
    assert longer.morphology.R == 0.05 and longer.name == "moth2"
    with pytest.raises(ValueError, match=r"orbit table for uvlm \(orbit_table_uvlm.json\) was computed on the "
                                         r"model b6b14ba74309, not on its MJCF [0-9a-f]{12}: regenerate") as e:
        table_path(longer, "orbit", "uvlm")
    assert "\n" not in str(e.value)
    path, reason = table_status(longer, "trim", "quasi-steady")
    assert path is None and "was computed on the model" in reason


def test_restamp_sets_the_digest_of_the_named_files_only(tmp_path):
    """scripts/regenerate.py restamps what a stage wrote: the named entries take the insect's MJCF digest, the others
    and the manifest's comments stay as they were."""
    from hawksim.insect.tables import manifest, restamp

    longer = load_insect(_copy(tmp_path, edit=lambda s: s.replace("value = 0.0485\n", "value = 0.05\n")))
    text = (longer.folder / "data" / "manifest.toml").read_text()
    assert restamp(longer, ["orbit_table_uvlm.json"]) == ["orbit_table_uvlm.json"]
    assert table_path(longer, "orbit", "uvlm") == longer.folder / "data" / "orbit_table_uvlm.json"
    with pytest.raises(ValueError, match="computed on the model"):
        table_path(longer, "orbit", "quasi-steady")
    after = (longer.folder / "data" / "manifest.toml").read_text()
    assert after.splitlines()[:3] == text.splitlines()[:3] and after.count("[[file]]") == text.count("[[file]]")
    assert restamp(longer, ["orbit_table_uvlm.json"]) == []  # already stamped
    assert sum(e.model_sha256 == mjcf_digest(longer) for e in manifest(longer)) == 1
    with pytest.raises(ValueError, match="not in the manifest"):
        restamp(longer, ["no_such_table.json"])


def test_a_copy_under_another_name_gives_the_same_aero_numbers(tmp_path):
    from hawksim.backends.held import run
    from hawksim.backends.resolution import Resolution
    from hawksim.insect.kinematics import table3_kinematics

    copy = load_insect(_copy(tmp_path))
    assert copy == default_insect() and copy.name == "moth2" and copy.folder == tmp_path / "moth2"
    res = Resolution(aero="quasi-steady", cycles=2, steps_per_cycle=40, average_cycles=1)
    a, b = (run(table3_kinematics(1.0), 1.0, res, insect=i).averages for i in (copy, default_insect()))
    assert a == b


BAD = [
    ("wingspan = 1\n", "unknown insect field 'wingspan'"),
    ('[morphology]\nname = "x"\n', "insect field 'morphology.total_mass' is missing"),
    ('base = "hawkmoth"\n[morphology.R]\nvalue = 0.05\nsource = "guessed"\ncitation = "x"\n',
     "insect field 'morphology.R.source' must be one of quoted, measured"),
    ('base = "hawkmoth"\n[morphology.R]\nvalue = "long"\nsource = "quoted"\ncitation = "x"\n',
     "insect field 'R' must be a finite number"),
    ('base = "hawkmoth"\n[P0]\nvalue = -1.0\nsource = "quoted"\ncitation = "x"\n',
     "insect field 'P0' must be positive"),
    ('base = "hawkmoth"\n[bounds]\nsource = "quoted"\ncitation = "x"\nf = [40.0, 15.0]\n',
     "insect field 'bounds_deg.f' must have lower < upper"),
    ('base = "bumblebee2"\n', "insect field 'base' must name a shipped insect"),
    ("format = 2\n", "insect field 'format' must be 1"),
    ("name = \n", "is not valid TOML"),
]


@pytest.mark.parametrize("text, message", BAD)
def test_a_bad_spec_is_one_line_naming_the_field(tmp_path, text, message):
    spec = tmp_path / "bad.toml"
    spec.write_text(text)
    with pytest.raises(ValueError) as e:
        load_insect(spec)
    assert message in str(e.value) and str(spec) in str(e.value) and "\n" not in str(e.value)


def test_unknown_names_and_json_specs():
    with pytest.raises(ValueError, match="unknown insect 'dragonfly': neither a shipped insect"):
        load_insect("dragonfly")
    structured = json.dumps({"base": "hawkmoth", "P0": {"value": 0.1, "unit": "W", "source": "model choice",
                                                         "citation": "a test"}})
    import tempfile
    from pathlib import Path

    with tempfile.TemporaryDirectory() as d:
        p = Path(d) / "p0.json"
        p.write_text(structured)
        bug = load_insect(p)
    assert bug.P0 == 0.1 and bug.morphology == Morphology() and bug.sources["P0"] == ("model choice", "a test")


@pytest.mark.parametrize("command, args", [
    ("dataset", ["--samples", "1", "--out", "{tmp}/d.sqlite", "--speed", "1"]),
    ("train", ["--data", "{tmp}/d.sqlite", "--out", "{tmp}/n.safetensors", "--speed", "1"]),
    ("reproduce", ["--out", "{tmp}/r"]),
])
def test_commands_that_cannot_fly_another_insect_refuse_it(tmp_path, capsys, command, args):
    from hawksim.cli import main

    spec = tmp_path / "p0.json"
    spec.write_text(json.dumps({"P0_W": 0.1}))
    code = main([command, *(a.format(tmp=tmp_path) for a in args), "--insect", str(spec)])
    err = capsys.readouterr().err
    assert code == 2 and len(err.strip().splitlines()) == 1
    assert f"hawksim {command}: --insect p0 is not the default insect (hawkmoth)" in err
    assert not list(tmp_path.glob("d.sqlite")) and not list(tmp_path.glob("n.safetensors"))


def test_predict_takes_the_insects_p0_and_refuses_another_morphology(tmp_path, capsys):
    from hawksim.cli import main

    def predict(*extra):
        code = main(["predict", "--speed", "1", "--kinematics", KIN, "--json", *extra])
        io = capsys.readouterr()
        return code, (json.loads(io.out) if code == 0 else None), io.err

    _, base, _ = predict()
    spec = tmp_path / "p0.json"
    spec.write_text(json.dumps({"P0_W": 2 * P0_W}))
    _, half, _ = predict("--insect", str(spec))
    assert half["P_plus"] == pytest.approx(base["P_plus"] / 2, rel=1e-12) and half["L_plus"] == base["L_plus"]
    spec.write_text(json.dumps({"R": 0.05}))
    code, _, err = predict("--insect", str(spec))
    assert code == 2 and "the surrogate network was trained on the default hawkmoth" in err
    # --network FILE is the one spelling of a network file; --model FILE still works, with a note
    from hawksim.backends.network import shipped_path

    net = str(shipped_path(1.0))
    _, by_network, err = predict("--network", net)
    assert err == "" and by_network["network"] == "file"
    _, by_model, err = predict("--model", net)
    assert "--model FILE is deprecated here: use --network FILE" in err
    _, per_speed, _ = predict("--network", "shipped")  # the family whose 1 m/s file `net` is
    assert by_model["P_plus"] == by_network["P_plus"] == per_speed["P_plus"]
    assert base["network"] == "reference"  # predict's default (issue 49: it follows `hawksim aero`)
