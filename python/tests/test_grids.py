"""rove.OccupancyGrid: the cells as a numpy view, probabilities, ROS maps."""

import gc

import numpy as np
import pytest

import rove


def test_cells_view_is_the_cpp_buffer():
    g = rove.OccupancyGrid(-1.0, 1.0, -2.0, 2.0, 0.1)
    assert (g.size_x, g.size_y) == (20, 40)
    c = g.cells
    assert c.shape == (40, 20) and c.dtype == np.int8
    assert c.__array_interface__["data"][0] == g._cells_address()
    c[:] = 0  # log-odds 0: p(free) = 0.5
    np.testing.assert_allclose(g.free_probability(), 0.5)


def test_cells_view_outlives_the_grid():
    cells = rove.OccupancyGrid(0.0, 1.0, 0.0, 1.0, 0.25, p_free=0.9).cells
    gc.collect()
    assert cells.shape == (4, 4) and (cells == cells[0, 0]).all() and cells[0, 0] > 0


def test_from_free_probability_round_trip():
    p = np.full((3, 5), 0.5)
    p[0, 0], p[2, 4] = 0.0, 1.0
    g = rove.OccupancyGrid.from_free_probability(p, x_min=1.0, y_min=-1.0, resolution=0.5)
    assert g.shape == (3, 5) and g.x_min == 1.0 and g.y_max == pytest.approx(0.5)
    f = g.free_probability()
    assert f[0, 0] < 0.01 and f[2, 4] > 0.99 and abs(f[1, 2] - 0.5) < 0.01
    assert g.free_probability_at(1.1, -0.9) == f[0, 0]
    assert g.cell_of(1.1, -0.9) == (0, 0)
    np.testing.assert_allclose(g.occupancy(), 1 - f, atol=1e-7)


def test_ros_map_round_trip(tmp_path):
    p = np.full((10, 8), 0.5)
    p[:, :3] = 0.0
    p[:, 5:] = 1.0
    g = rove.OccupancyGrid.from_free_probability(p, x_min=-2.0, y_min=3.0, resolution=0.1)
    yaml, image = rove.save_ros_map(str(tmp_path / "map"), g)
    assert yaml.endswith("map.yaml") and image.endswith("map.png")
    h = rove.load_ros_map(yaml)
    assert h.shape == g.shape and h.x_min == pytest.approx(-2.0) and h.y_min == pytest.approx(3.0)
    f = h.free_probability()
    assert (f[:, :3] < 0.35).all() and (f[:, 5:] > 0.8).all()


def test_bad_grids():
    with pytest.raises(ValueError, match="resolution"):
        rove.OccupancyGrid(0.0, 1.0, 0.0, 1.0, -0.1)
    with pytest.raises(ValueError):
        rove.OccupancyGrid(0.0, float("nan"), 0.0, 1.0, 0.1)
    with pytest.raises(ValueError, match=r"\[0, 1\]"):
        rove.OccupancyGrid.from_free_probability(np.full((2, 2), 1.5), 0.0, 0.0, 0.1)
    with pytest.raises(ValueError, match="not finite"):
        rove.OccupancyGrid.from_free_probability(np.full((2, 2), np.nan), 0.0, 0.0, 0.1)
    with pytest.raises(TypeError):
        rove.OccupancyGrid.from_free_probability([[0.5]], 0.0, 0.0, 0.1)
    with pytest.raises(ValueError, match="mode"):
        rove.save_ros_map("/tmp/x", rove.OccupancyGrid(), mode="raw")


def test_pickle_round_trip():
    import pickle
    p = np.linspace(0, 1, 12).reshape(3, 4)
    g = rove.OccupancyGrid.from_free_probability(p, x_min=-1.0, y_min=2.0, resolution=0.25)
    h = pickle.loads(pickle.dumps(g))
    assert (h.shape, h.x_min, h.y_max, h.resolution) == (g.shape, g.x_min, g.y_max, g.resolution)
    np.testing.assert_array_equal(h.cells, g.cells)
