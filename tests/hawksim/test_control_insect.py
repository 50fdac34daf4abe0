"""The controller of another insect (issue 50, item 1): its schedule's orbits, linear models and gains are its own,
and the process's caches (hawksim.control.schedule) and the disk cache's keys (hawksim.control.cache) never give one
insect another's; the default insect's keys are as they were."""

import dataclasses

import numpy as np

from hawksim.control import cache
from hawksim.control.schedule import _POINTS, insect_key, schedule_point
from hawksim.trim.registry import point_key
from hawksim.insect.insect import DEFAULT_INSECT, Insect
from hawksim.insect.model import load_model
from hawksim.insect.morphology import HAWKMOTH

HEAVY = Insect(dataclasses.replace(HAWKMOTH, total_mass=1.2 * HAWKMOTH.total_mass, name="heavier"))


def test_insect_key_names_the_insect_and_keeps_the_default_keys():
    assert insect_key(None) == insect_key(DEFAULT_INSECT) == ()
    assert insect_key(HEAVY) != () and insect_key(HEAVY) == insect_key(Insect.from_dict(HEAVY.to_dict()))
    lighter = Insect(dataclasses.replace(HAWKMOTH, total_mass=0.9 * HAWKMOTH.total_mass, name="heavier"))
    assert insect_key(lighter) != insect_key(HEAVY)  # same name, other mass


def test_two_insects_never_share_orbits_or_gains():
    hawk = schedule_point(1.0)
    heavy = schedule_point(1.0, insect=HEAVY)
    assert hawk.orbit.insect == DEFAULT_INSECT and heavy.orbit.insect == HEAVY
    assert point_key(1.0, "quasi-steady") in _POINTS and point_key(1.0, "quasi-steady", HEAVY) in _POINTS
    assert heavy.orbit.kinematics.f > hawk.orbit.kinematics.f + 1.5  # 30.6 vs 28.5 Hz: it carries 1.2x the weight
    assert np.abs(heavy.model.A - hawk.model.A).max() > 1e-3
    assert np.abs(heavy.long.K - hawk.long.K).max() > 1e-3
    assert schedule_point(1.0).orbit is hawk.orbit  # each insect's entry is reused, not the other's
    assert schedule_point(1.0, insect=HEAVY).orbit is heavy.orbit
    # the disk cache's key (history networks' maps) holds the insect twice: the orbit's JSON and the MJCF's mechanics
    assert "insect" in heavy.orbit.to_json() and "insect" not in hawk.orbit.to_json()
    assert cache.model_digest(load_model(morph=HEAVY.morphology)) != cache.model_digest(load_model())
    assert cache.map_key("beat", heavy.orbit, load_model(morph=HEAVY.morphology)) != \
        cache.map_key("beat", hawk.orbit, load_model())
