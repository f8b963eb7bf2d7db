"""Column meshes: distinct crack nodes, tags, grading, and meshio round trips."""

import numpy as np
import pytest

from colonna.meshes.column import column_mesh, from_arrays
from colonna.meshes.io import read, write, write_time_series
from colonna.rigid import InputError


@pytest.fixture(params=[True, False], ids=["cracked", "solid"])
def mesh(request):
    return column_mesh(0.8, 4.0, 0.1, cracked=request.param, pinned_heights=(1.0, 3.0))


def test_crack_is_not_welded():
    m = column_mesh(0.8, 4.0, 0.1, cracked=True)
    left, right = m.crack_nodes
    np.testing.assert_allclose(m.points[:, left], m.points[:, right])  # same places
    assert not set(left) & set(right)  # different nodes
    # no cell uses nodes of both bodies
    assert np.all(m.node_body[m.cells] == m.cell_body[None, :])
    assert m.n_bodies == 2


def test_tags_and_area(mesh):
    p = mesh.points
    for nodes in mesh.base_nodes:
        assert np.all(p[1, nodes] == 0.0) and np.all(np.diff(p[0, nodes]) > 0)
    assert np.all(np.abs(np.abs(p[0, np.concatenate(mesh.outer_nodes)]) - 0.4) < 1e-12)
    q = p[:, mesh.cells]
    area = 0.5 * np.abs(
        (q[0, 0] - q[0, 2]) * (q[1, 1] - q[1, 3]) - (q[0, 1] - q[0, 3]) * (q[1, 0] - q[1, 2])
    )
    assert area.sum() == pytest.approx(0.8 * 4.0, rel=1e-12)


def test_pinned_collar_heights_are_nodes(mesh):
    for y in (1.0, 3.0):
        for body in range(mesh.n_bodies):
            node = mesh.outer_node_at(body, y)
            assert mesh.points[1, node] == pytest.approx(y, abs=1e-14)


def test_grading_refines_toward_base_corners():
    m = column_mesh(0.8, 4.0, 0.05, cracked=True, grading=0.6)
    x = np.sort(np.unique(m.points[0, m.base_nodes[0]]))
    assert x[1] - x[0] < 0.5 * (x[len(x) // 2 + 1] - x[len(x) // 2])
    y = np.sort(np.unique(m.points[1, m.outer_nodes[0]]))
    assert y[1] - y[0] < 0.5 * (y[-1] - y[-2])


@pytest.mark.parametrize("suffix", [".vtu", ".msh"])
def test_round_trip(tmp_path, mesh, suffix):
    path = tmp_path / f"column{suffix}"
    field = np.arange(mesh.n_nodes, dtype=float)
    write(path, mesh, point_data={"f": field} if suffix == ".vtu" else None)
    back = read(path)
    assert back.cracked == mesh.cracked and back.n_nodes == mesh.n_nodes
    np.testing.assert_allclose(back.points, mesh.points, atol=1e-12)
    for a, b in zip(back.crack_nodes, mesh.crack_nodes):
        np.testing.assert_array_equal(a, b)
    for a, b in zip(back.base_nodes, mesh.base_nodes):
        np.testing.assert_array_equal(a, b)


def test_from_arrays_orients_cells():
    m = column_mesh(0.8, 2.0, 0.2, cracked=False)
    flipped = from_arrays(m.points, m.cells[::-1])
    p = flipped.points[:, flipped.cells]
    area2 = (p[0, 1] - p[0, 0]) * (p[1, 2] - p[1, 0]) - (p[0, 2] - p[0, 0]) * (p[1, 1] - p[1, 0])
    assert np.all(area2 > 0)


def test_xdmf_time_series(tmp_path):
    import meshio

    m = column_mesh(0.8, 2.0, 0.2)
    write_time_series(
        tmp_path / "run.xdmf", m, [0.0, 0.1], lambda k: {"u": np.full((m.n_nodes, 2), float(k))}
    )
    with meshio.xdmf.TimeSeriesReader(tmp_path / "run.xdmf") as reader:
        reader.read_points_cells()
        t, pd, _ = reader.read_data(1)
    assert t == pytest.approx(0.1) and np.all(pd["u"][:, :2] == 1.0)


@pytest.mark.parametrize(
    "kwargs, name",
    [
        (dict(width=-1.0, height=4.0, size=0.1), "width"),
        (dict(width=0.8, height=4.0, size=0.5), "mesh size"),
        (dict(width=0.8, height=4.0, size=0.1, grading=1.2), "grading"),
        # issue 49: the toe's settings are one ToeGrading, a dict of them is refused by name
        (dict(width=0.8, height=4.0, size=0.1, toe={"size": 0.01}), "toe = .* is not a"),
    ],
)
def test_bad_mesh_input(kwargs, name):
    with pytest.raises(InputError, match=name):
        column_mesh(**kwargs)
