"""The FEM run's parameter objects (colonna.fem.settings, issue 49): each refuses a bad value
naming its field, and the solver refuses what is not a Motion, before any step is taken."""

import math

import numpy as np
import pytest

from colonna.core.errors import InputError
from colonna.core.ground import NoMotion
from colonna.core.motion import Motion, Release
from colonna.fem.assembly import Stone
from colonna.fem.model import build_model
from colonna.fem.settings import FemSettings, FemStart, Replicas
from colonna.fem.solver import iter_batch, run, run_ensemble
from colonna.meshes.column import column_mesh


@pytest.mark.parametrize(
    "make, words",
    [
        (lambda: FemSettings(dt=0.0), "run dt"),
        (lambda: FemSettings(safety=-1.0), "run safety"),
        (lambda: FemSettings(output_interval=-1e-3), "run output_interval"),
        (lambda: FemSettings(edge_length=0.0), "edge_length"),
        (lambda: FemSettings(edge_time=0.02), "edge_time"),
        (lambda: FemStart(tilt=0.25 * math.pi), "start.tilt"),
        (lambda: FemStart(angular_velocity=math.inf), "start.angular_velocity"),
        (lambda: FemStart(time=math.nan), "start.time"),
        (lambda: FemStart(contact={}), "start.contact needs start.state"),
        (lambda: FemStart(state=(np.zeros(2), np.zeros(2)), tilt=0.01), "not both"),
        (lambda: Replicas(0), "replicas = 0"),
        (lambda: Replicas(2, perturbation=1e-3), "replica perturbation"),
    ],
)
def test_a_bad_setting_is_refused_naming_its_field(make, words):
    with pytest.raises(InputError, match=words):
        make()


def test_a_release_is_a_start_with_its_tilt_and_spin_only():
    start = FemStart.of(Release(0.02, -0.1))
    assert (start.tilt, start.angular_velocity) == (0.02, -0.1)
    assert start.state is None and start.velocity is None and start.time == 0.0
    assert not start.static and FemStart().static
    assert not FemStart(velocity=np.zeros(4)).static


@pytest.fixture(scope="module")
def model():
    return build_model(column_mesh(0.2, 1.0, 0.1, cracked=False), Stone(), 0.2)


def test_the_solver_takes_motions_not_bare_ground_motions(model):
    with pytest.raises(InputError, match="run motion 1: a colonna.core.motion.Motion"):
        run(model, NoMotion())
    with pytest.raises(InputError, match="run motion 2: a FEM run needs its duration"):
        next(iter_batch(model, [Motion(NoMotion(), 0.01), Motion(NoMotion())]))
    with pytest.raises(InputError, match="run replicas = 0"):
        run_ensemble(model, Motion(NoMotion(), 0.01), replicas=0)
