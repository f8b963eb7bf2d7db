"""Typed results (colonna.core.quantities): every key of a model run's summary declares its SI
unit, the summary dicts are what the typed objects serialise to, and the units they declare
are the ones the command line shows."""

import argparse
import dataclasses
import json
import math

import pytest

from colonna.core import quantities
from colonna.core.motion import Motion, Release
from colonna.core.quantities import quantity, selected, to_dict, to_json, typed_result, units_of
from colonna.fem.assembly import Stone
from colonna.fem.ensemble import EnsembleTally, ensemble_summary
from colonna.fem.model import Loads, build_model
from colonna.fem.settings import FemSettings
from colonna.fem.solver import FemRunSummary, run, run_ensemble
from colonna.meshes.column import column_mesh
from colonna.rigid import Block, Collar, NoMotion, pulse_from_ratios, rock
from colonna.rigid.multibody import MultibodyContact, MultibodySummary, rock_multibody
from colonna.rigid.solve import RockingSummary
from colonna.studies.crosscheck.runner import MULTIBODY_KEYS as CROSSCHECK_KEYS
from colonna.studies.output import _plain
from colonna.studies.units import declared_unit, guessed_unit, unit_of

BLOCK = Block(b=0.2, h=1.0)
LOADED = Block(b=0.2, h=1.0, mass=500.0, top_load=2000.0)
COLLARS = (Collar(y=0.5, t=0.005, h=0.03), Collar(y=1.5, t=0.01, h=0.05))
PLASTIC = (Collar(y=0.5, t=0.005, h=0.03, plastic=True),)

# the keys of each summary in their order, as summary.json has always had them
ROCKING_KEYS = (
    "verdict overturned mode motion impacts max_abs_theta max_abs_theta_over_alpha "
    "overturn_time model solver p alpha restitution restitution_housner top_load critical_angle"
).split()
ROCKING_COLLAR_KEYS = (
    "collars collar_max_utilisation collar_state collar_first_yield_time collar_law".split()
)
MULTIBODY_KEYS = (
    "verdict model overturned mode motion status impacts max_abs_theta max_abs_theta_over_alpha "
    "max_abs_theta_left max_abs_theta_right overturn_time cracked friction crack_friction p "
    "alpha restitution_housner impact_velocity_ratio_mean max_uplift max_crack_opening "
    "max_abs_crack_slip energy_dissipated energy_external_work energy_error_max dt steps "
    "wall_seconds"
).split()
MULTIBODY_COLLAR_KEYS = (
    "collars collar_max_utilisation collar_first_yield_time collar_max_plastic_strain "
    "collar_plastic_work collar_max_fibre_strain collar_ductility_demand collar_fractured "
    "collar_fracture_time collar_state"
).split()
FEM_KEYS = (
    "overturned status max_abs_theta_left max_abs_theta_right collar_max_utilisation "
    "collar_first_yield_time edge_stress_max edge_stress_ratio edge_length edge_time "
    "base_reaction_static collar_max_plastic_strain collar_plastic_work crack_slip_residual "
    "friction_work_base friction_work_crack contact_damping_work contact_penalty_energy_max "
    "toe_contact_length toe_contact_nodes toe_node_spacing toe_pressure_max toe_resultant "
    "toe_resultant_offset toe_pressure_winkler bed_stiffness bed_yield_pressure bed_plastic_work "
    "top_load energy_error_max energy_error_limit energy_reliable dt dt_critical "
    "dt_critical_elastic stable_step_reduction_by_contact penalty_base_mean steps dofs "
    "wall_seconds t_end batch_size step_halvings step_note"
).split()
FEM_COLLAR_KEYS = (
    "collar_max_fibre_strain collar_ductility_demand collar_fractured collar_fracture_time".split()
)
# a cracked column's, after crack_slip_residual
FEM_CRACK_KEYS = (
    "crack_normal_force_mean crack_normal_force_mean_closed crack_normal_force_max "
    "crack_closed_fraction"
).split()


def _rock_runs():
    pulse = pulse_from_ratios(LOADED, "sine", 3.0, 2.5, "nonlinear")
    gentle = pulse_from_ratios(LOADED, "sine", 3.0, 1.2, "nonlinear")
    stiff = (Collar(y=1.0, t=0.02, h=0.08),)
    return {
        "solid": rock(BLOCK, Motion(pulse_from_ratios(BLOCK, "sine", 3.0, 2.5, "linear"))),
        "collars yield": rock(LOADED, Motion(pulse), COLLARS, model="nonlinear"),
        "collars elastic": rock(LOADED, Motion(gentle, duration=3.0), stiff, model="nonlinear"),
    }


def _multibody_runs():
    pulse = pulse_from_ratios(LOADED, "sine", 3.0, 2.5, "nonlinear")
    return {
        "solid": rock_multibody(BLOCK, Motion(pulse, duration=1.0)),
        "cracked, collars": rock_multibody(
            LOADED,
            Motion(pulse, duration=1.0),
            COLLARS,
            contact=MultibodyContact(cracked=True, crack_friction=0.5),
        ),
        "cracked, plastic collar": rock_multibody(
            LOADED, Motion(pulse, duration=1.0), PLASTIC, contact=MultibodyContact(cracked=True)
        ),
    }


@pytest.fixture(scope="module")
def fem_runs():
    """A small cracked column with a plastic collar (two replicas) and a solid one."""
    pulse = pulse_from_ratios(Block(b=0.1, h=1.0), "sine", 3.0, 2.5, "nonlinear")
    cracked = build_model(
        column_mesh(0.4, 2.0, 0.1, cracked=True, pinned_heights=(1.0,)),
        Stone(),
        0.3,
        collars=(Collar(y=1.0, t=0.005, h=0.03, plastic=True),),
        loads=Loads(top_load=1000.0),
    )
    solid = build_model(column_mesh(0.4, 2.0, 0.1, cracked=False), Stone(), 0.3)
    settings = FemSettings(progress=False, output_interval=2e-3)
    return {
        "cracked, collar": run_ensemble(cracked, Motion(pulse, 0.02), settings, replicas=2),
        "solid": [run(solid, Motion(pulse, 0.02), settings)],
    }


def _nested_keys(summary: dict) -> set[str]:
    keys = set(summary)
    for entry in summary.get("collars", []):
        keys |= set(entry)
    return keys


# --- every key has a unit; the dicts are the typed objects' ----------------------------------


@pytest.mark.parametrize("name", ["solid", "collars yield", "collars elastic"])
def test_rocking_summary_is_its_typed_object_and_every_key_has_a_unit(name):
    result = _rock_runs()[name]
    summary, typed = result.summary(), result.typed_summary()
    assert isinstance(typed, RockingSummary)
    assert list(summary) == list(to_dict(typed))  # same keys, same order
    assert summary == to_dict(typed)
    assert json.dumps(to_json(typed)) == json.dumps(_plain(summary))  # summary.json's text
    assert not [key for key in _nested_keys(summary) if declared_unit(key) is None]
    with_collars = ROCKING_KEYS + ROCKING_COLLAR_KEYS
    expected = {
        "solid": ROCKING_KEYS,
        "collars yield": with_collars + ["collar_note"],  # a collar passed f_y
        "collars elastic": with_collars,
    }[name]
    assert list(summary) == expected
    if name == "collars elastic":  # no collar yields: its time is there, and None
        assert summary["collar_first_yield_time"] is None


@pytest.mark.parametrize("name", ["solid", "cracked, collars", "cracked, plastic collar"])
def test_multibody_summary_is_its_typed_object_and_every_key_has_a_unit(name):
    result = _multibody_runs()[name]
    summary, typed = result.summary(), result.typed_summary()
    assert isinstance(typed, MultibodySummary)
    assert list(summary) == list(to_dict(typed))
    assert summary == to_dict(typed)
    assert json.dumps(to_json(typed)) == json.dumps(_plain(summary))
    assert not [key for key in _nested_keys(summary) if declared_unit(key) is None]
    assert list(summary) == MULTIBODY_KEYS + (MULTIBODY_COLLAR_KEYS if "collar" in name else [])


def test_fem_summary_is_its_typed_object_and_every_key_has_a_unit(fem_runs):
    for name, results in fem_runs.items():
        for result in results:
            typed = result.typed_summary
            assert isinstance(typed, FemRunSummary)
            assert list(result.summary) == list(to_dict(typed))
            assert result.summary == to_dict(typed)
            assert json.dumps(to_json(typed)) == json.dumps(_plain(result.summary))
            assert not [key for key in result.summary if declared_unit(key) is None]
            collar_keys = FEM_COLLAR_KEYS if "collar" in name else []
            crack_keys = FEM_CRACK_KEYS if "cracked" in name else []
            position = FEM_KEYS.index("crack_slip_residual")
            assert list(result.summary) == (
                FEM_KEYS[:position]
                + collar_keys
                + FEM_KEYS[position : position + 1]
                + crack_keys
                + FEM_KEYS[position + 1 :]
            )


def test_ensemble_summary_keys_have_units(fem_runs):
    summary = ensemble_summary([r.summary for r in fem_runs["cracked, collar"]])
    assert not [key for key in summary if declared_unit(key) is None]
    added = [key for key in summary if key not in FEM_KEYS + FEM_COLLAR_KEYS + FEM_CRACK_KEYS]
    # the tally's keys, in its order (a partial crack's answer only with one)
    assert added == [key for key in units_of(EnsembleTally) if not key.startswith("crack_grew")]
    assert summary["statuses"] == ["completed", "completed"]


def test_selected_gives_the_crosscheck_keys_in_order_none_where_left_out():
    """The cross-check's rigid_multibody block: its keys from the summary's class, a key the
    run leaves out (a solid column's collars) None, as the hand-copied selection had it."""
    runs = _multibody_runs()
    keys = CROSSCHECK_KEYS
    for result in runs.values():
        summary = result.summary()
        by_hand = {key: summary.get(key) for key in keys}
        assert selected(summary, MultibodySummary, keys) == by_hand
        assert list(selected(result.typed_summary(), MultibodySummary, keys)) == list(keys)
    assert selected(runs["solid"].summary(), MultibodySummary, keys)["collar_fractured"] is None
    with pytest.raises(KeyError, match="max_abs_theta_middle"):
        selected(runs["solid"].summary(), MultibodySummary, ("max_abs_theta_middle",))


# --- the units are right --------------------------------------------------------------------


def test_declared_units_pin_the_physics():
    """p in rad/s is sqrt(3 g / (4 R)) of the half block; released from rest at theta0, the
    lifted toe is at 2b sin(theta0) m for the solid block and 4b sin(theta0) for the cracked
    column (both halves tip about the column's outer toe)."""
    assert units_of(RockingSummary)["p"] == "rad/s"
    assert units_of(MultibodySummary)["max_uplift"] == "m"
    R = math.hypot(BLOCK.b, BLOCK.h)
    p = rock(BLOCK, Motion(NoMotion(), duration=0.5), release=Release(tilt=0.05)).summary()["p"]
    assert p == pytest.approx(math.sqrt(3.0 * 9.81 / (4.0 * R)), rel=1e-12)
    tilt = 0.05
    for cracked, width in ((False, 2.0 * BLOCK.b), (True, 4.0 * BLOCK.b)):
        summary = rock_multibody(
            BLOCK,
            Motion(NoMotion(), duration=0.2),
            contact=MultibodyContact(cracked=cracked, friction=2.0),
            release=Release(tilt=tilt),
        ).summary()
        assert summary["max_uplift"] == pytest.approx(width * math.sin(tilt), rel=1e-9)
        assert summary["p"] == pytest.approx(p, rel=1e-12)


def test_one_key_has_one_unit_everywhere(monkeypatch):
    monkeypatch.setattr(quantities, "_RESULTS", list(quantities._RESULTS))

    @dataclasses.dataclass(frozen=True, kw_only=True)
    class Clash:
        dt: float = quantity("m", "a time step in metres")

    with pytest.raises(TypeError, match="one key, one unit"):
        typed_result(Clash)
    with pytest.raises(ValueError, match="unit"):
        quantity("MPa", "a display unit is not an SI one")


# --- the command line shows the declared units ----------------------------------------------


def test_cli_prints_declared_units_before_any_guess(monkeypatch, capsys):
    """Stresses in MPa and forces in kN from the registry. A key whose words would guess
    wrong shows its declared unit: a collar's y (no unit word) is in m, energy_reliable (a
    yes/no, 'energy' guesses J) has none, and a registered toe_peak in Pa prints in MPa."""
    from colonna.studies import cli

    monkeypatch.setattr(quantities, "_RESULTS", list(quantities._RESULTS))

    @typed_result
    @dataclasses.dataclass(frozen=True, kw_only=True)
    class ToeSummary:
        toe_peak: float = quantity("Pa", "largest toe stress")

    assert guessed_unit("toe_peak") == ("", 1.0)  # its words say nothing
    assert unit_of("toe_peak") == ("MPa", 1e-6)
    assert unit_of("y") == ("m", 1.0) and guessed_unit("y") == ("", 1.0)
    assert unit_of("energy_reliable")[0] == "" and guessed_unit("energy_reliable")[0] == "J"
    assert unit_of("max_abs_crack_slip") == ("m", 1.0)
    cli._emit(
        argparse.Namespace(json=False),
        {"edge_stress_max": 2.5e6, "toe_peak": 3.25e6, "top_load": 1500.0, "steps": 12},
    )
    lines = capsys.readouterr().out.splitlines()
    assert [line.split(None, 1)[1] for line in lines] == ["2.5 MPa", "3.25 MPa", "1.5 kN", "12"]


def test_keys_no_typed_result_declares_fall_back_to_their_words():
    """A study's own keys (the command line's uplift_acceleration, the design's yield_moment)
    keep the unit their words give."""
    assert declared_unit("uplift_acceleration") is None
    assert unit_of("uplift_acceleration") == ("m/s^2", 1.0)
    assert unit_of("yield_moment") == ("kN m", 1e-3)
