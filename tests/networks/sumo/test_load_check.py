"""SUMO's own verdict on a network: asked once, before any run; the tool reads what it loads."""

from __future__ import annotations

import pytest

from clearance.networks.loading import load_network, load_networks
from clearance.networks.samples.sources import SAMPLES_DIR
from clearance.networks.sumo.load_check import SumoLoadCheck
from clearance.vehicles.errors import InputError
from tests.networks import damaged


@pytest.mark.parametrize("case", sorted(damaged.CASES))
def test_sumo_refuses_exactly_the_cases_said_to_be_refused(tmp_path, case):
    # the split of tests/networks/damaged.py is SUMO's, not ours: asked of SUMO itself
    path, _ = damaged.damage(case, tmp_path)
    assert (SumoLoadCheck(path).refusal() is not None) == (case in damaged.REFUSED)


@pytest.mark.parametrize("case", sorted(damaged.REFUSED))
def test_what_sumo_refuses_is_bad_input_in_sumos_words(tmp_path, case):
    path, expected = damaged.damage(case, tmp_path)
    with pytest.raises(InputError) as info:
        load_network(path)
    assert str(info.value).startswith(expected)


def test_the_answer_is_kept_per_file_and_a_changed_file_is_asked_again(tmp_path):
    path, _ = damaged.damage("lane-width-nan", tmp_path)
    assert SumoLoadCheck(path).refusal() is None
    assert SumoLoadCheck(path)._proc is None  # known: no SUMO started
    bad, _ = damaged.damage("lane-length-nan", tmp_path)
    path.write_bytes(bad.read_bytes() + b"\n")  # same path, new size: asked again
    check = SumoLoadCheck(path)
    assert check._proc is not None and check.refusal() is not None


def test_several_networks_are_loaded_in_order_and_the_first_refused_is_named(tmp_path):
    good = [SAMPLES_DIR / n / f"{n}.net.xml" for n in ("intersection", "roundabout")]
    nets = load_networks(good)
    assert [n.path for n in nets] == good
    bad, expected = damaged.damage("unknown-to-edge", tmp_path)
    with pytest.raises(InputError) as info:
        load_networks([good[0], bad, good[1]])
    assert str(info.value).startswith(expected)
