"""rove.PointCloud: numpy views without copies, in both directions, and
their lifetime; bad arrays are TypeError / ValueError."""

import gc

import numpy as np
import pytest

import rove
from conftest import DATA_DIR

BUNNY = DATA_DIR / "pointcloud" / "bunny.pcd"


def address(a):
    return a.__array_interface__["data"][0]


def test_points_view_is_the_cpp_buffer():
    c = rove.read_pcd(BUNNY)
    p = c.points
    assert p.shape == (397, 3) and p.dtype == np.float32
    assert address(p) == c._points_address()
    assert p.base is c or p.base is not None
    # Writing through the view changes the C++ cloud (a copy would not).
    p[0] = [1.0, 2.0, 3.0]
    np.testing.assert_array_equal(c.points[0], [1.0, 2.0, 3.0])
    assert c.bounding_box()[1][2] >= 3.0


def test_view_outlives_the_python_reference():
    pts = rove.read_pcd(BUNNY).points  # the cloud has no other reference
    gc.collect()
    expected = rove.read_pcd(BUNNY).points.copy()
    np.testing.assert_array_equal(pts, expected)  # under ASan: no use after free
    cloud = rove.PointCloud(np.ones((5, 3)))
    view = cloud.points
    del cloud
    gc.collect()
    assert view.sum() == 15.0


def test_float32_arrays_are_read_in_place():
    a = np.random.default_rng(1).random((100, 3), dtype=np.float32)
    assert rove._points_address(a) == address(a)
    a64 = a.astype(np.float64)
    assert rove._points_address(a64) != address(a64)  # converted to float32
    c = rove.PointCloud(a)
    assert c._points_address() == rove._points_address(c)
    np.testing.assert_array_equal(c.points, a)


def test_channels_and_copy():
    n = 4
    c = rove.PointCloud(np.zeros((n, 3)), normals=np.tile([0.0, 0.0, 1.0], (n, 1)),
                        colors=np.array([[255, 0, 0]] * n, dtype=np.uint8),
                        intensities=np.arange(n, dtype=np.float32))
    assert c.normals.shape == (n, 3) and c.colors.dtype == np.uint8
    np.testing.assert_array_equal(c.intensities, [0, 1, 2, 3])
    d = c.copy()
    d.points[:] = 7
    assert c.points.max() == 0  # the copy is independent
    moved = c.transformed(rove.SE3(rove.SO3.rot_x(np.pi), [1.0, 0.0, 0.0]))
    np.testing.assert_allclose(moved.points, np.tile([1.0, 0.0, 0.0], (n, 1)), atol=1e-6)
    np.testing.assert_allclose(moved.normals, np.tile([0.0, 0.0, -1.0], (n, 1)), atol=1e-6)


def test_bad_arrays():
    with pytest.raises(TypeError, match="'points'.*float32 or float64"):
        rove.PointCloud(np.zeros((3, 3), dtype=np.int32))
    with pytest.raises(TypeError, match="'points'.*numpy array"):
        rove.PointCloud([[0.0, 0.0, 0.0]])
    with pytest.raises(ValueError, match=r"'points'.*shape \(N, 3\), got \(3, 2\)"):
        rove.PointCloud(np.zeros((3, 2)))
    with pytest.raises(ValueError, match="shape"):
        rove.PointCloud(np.zeros(9))
    with pytest.raises(ValueError, match="C-contiguous"):
        rove.PointCloud(np.zeros((3, 6))[:, ::2])
    with pytest.raises(ValueError, match="C-contiguous"):
        rove.PointCloud(np.asfortranarray(np.zeros((3, 3))))
    with pytest.raises(TypeError, match="float32"):
        rove.PointCloud(np.zeros((3, 3), dtype=">f4"))  # not the native byte order
    with pytest.raises(ValueError, match="'colors'.*outside 0..255"):
        rove.PointCloud(np.zeros((1, 3)), colors=np.array([[300, 0, 0]]))
    with pytest.raises(ValueError, match="'normals'.*2 rows for 1 points"):
        rove.PointCloud(np.zeros((1, 3)), normals=np.zeros((2, 3)))
    with pytest.raises(ValueError, match="'normals': row 0 is not finite"):
        rove.PointCloud(np.zeros((1, 3)), normals=np.array([[np.nan, 0, 1]]))
    with pytest.raises(ValueError, match="leaf"):
        rove.PointCloud(np.zeros((1, 3))).voxel_downsample(float("nan"))
    # NaN coordinates are allowed in a cloud (PCD's not-dense clouds).
    assert rove.PointCloud(np.array([[np.nan, 0, 0], [1, 2, 3]])).count_finite() == 1


def test_voxel_downsample():
    pts = np.array([[0.01, 0.01, 0.01], [0.02, 0.02, 0.02], [1.5, 1.5, 1.5]], dtype=np.float32)
    d = rove.PointCloud(pts).voxel_downsample(1.0)
    assert len(d) == 2
    np.testing.assert_allclose(sorted(d.points[:, 0]), [0.015, 1.5], atol=1e-6)


def test_pickle_round_trip():
    import pickle
    c = rove.PointCloud(np.arange(12, dtype=np.float32).reshape(4, 3),
                        colors=np.full((4, 3), 7, dtype=np.uint8))
    d = pickle.loads(pickle.dumps(c))
    np.testing.assert_array_equal(d.points, c.points)
    np.testing.assert_array_equal(d.colors, c.colors)
    assert d.normals is None and d._points_address() != c._points_address()


def test_unpickled_float32_array_is_read_in_place():
    # Regression: an unpickled array's dtype equals float32 without being the
    # same dtype object; it was refused as "not float32".
    import pickle
    a = pickle.loads(pickle.dumps(np.ones((5, 3), dtype=np.float32)))
    assert rove._points_address(a) == address(a)
    assert len(rove.PointCloud(a)) == 5
