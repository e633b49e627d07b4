"""rove.align against `rove align --json` on the same clouds, zero-copy
inputs, and bad input."""

import numpy as np
import pytest

import rove
from conftest import DATA_DIR, dataset, run_cli_json

ROOM1 = DATA_DIR / "pointcloud" / "room_scan1.pcd"
ROOM2 = DATA_DIR / "pointcloud" / "room_scan2.pcd"


def check_same(r, cli):
    np.testing.assert_array_equal(r.T_target_source, np.array(cli["T_target_source"]))
    assert r.status == cli["termination"]
    assert r.converged == cli["converged"]
    assert r.iterations == cli["iterations"]
    assert r.fitness == cli["fitness_m2"]
    assert r.source_points == cli["source_points"]
    assert r.voxel_sizes == cli["voxel"]


def test_ndt_room_pair_equals_the_command_line():
    cli = run_cli_json("align", "--method", "ndt", "--voxel", "0.2",
                       "--init", "1.79387,0.720047,0,0.6931rad,0,0", ROOM2, ROOM1)
    init = rove.SE3(rove.SO3.rot_z(0.6931), [1.79387, 0.720047, 0.0])
    r = rove.align(rove.read_pcd(ROOM2), rove.read_pcd(ROOM1), method="ndt", voxel=0.2, init=init)
    check_same(r, cli)
    assert r.converged and r.status == "Converged"
    # The same from numpy arrays (float32 in place, float64 converted).
    src, tgt = rove.read_pcd(ROOM2).points, rove.read_pcd(ROOM1).points
    r32 = rove.align(src, tgt, method="ndt", voxel=0.2, init=init)
    r64 = rove.align(src.astype(np.float64), tgt, method="ndt", voxel=0.2, init=init)
    np.testing.assert_array_equal(r32.T_target_source, r.T_target_source)
    np.testing.assert_array_equal(r64.T_target_source, r.T_target_source)
    d = r.to_dict()
    assert d["termination"] == "Converged" and d["iterations"] == cli["iterations"]


@pytest.mark.datasets
@pytest.mark.parametrize("method", ["gicp", "icp"])
def test_small_gicp_pair_equals_the_command_line(method):
    src = dataset("pointcloud/small_gicp_source.ply")
    tgt = dataset("pointcloud/small_gicp_target.ply")
    cli = run_cli_json("align", "--method", method, src, tgt, expect=(0, 3))
    r = rove.align(rove.read_ply(src), rove.read_ply(tgt), method=method)
    check_same(r, cli)
    if method == "gicp":
        # The published transform (small_gicp's T_target_source.txt).
        np.testing.assert_allclose(r.pose.translation, [0.4889, 0.1212, -0.0253], atol=6e-3)


def test_synthetic_transform_recovered():
    rng = np.random.default_rng(7)
    # Three orthogonal planes: well constrained.
    u = rng.random((3000, 2)) * 4 - 2
    tgt = np.concatenate([np.c_[u[:1000], np.zeros(1000)], np.c_[u[1000:2000, 0], np.zeros(1000), u[1000:2000, 1]],
                          np.c_[np.zeros(1000), u[2000:]]]).astype(np.float32)
    T = rove.SE3.exp(np.array([0.05, -0.03, 0.02, 0.02, -0.01, 0.03]))
    src = T.inverse().act_points(tgt).astype(np.float32)  # tgt = T · src
    for method in ("icp", "point-to-plane", "gicp"):
        r = rove.align(src, tgt, method=method, voxel=0)
        assert r.converged, r.message
        assert r.pose.ominus(T) == pytest.approx(np.zeros(6), abs=2e-3)


def test_empty_clouds_are_a_result_not_an_error():
    r = rove.align(np.zeros((0, 3), np.float32), np.zeros((0, 3), np.float32), voxel=0.5)
    assert r.status == "InvalidInput" and not r.converged


def test_bad_input():
    good = np.zeros((10, 3), np.float32)
    with pytest.raises(TypeError, match="'source'"):
        rove.align(np.zeros((10, 3), np.int64), good)
    with pytest.raises(ValueError, match="'target'.*shape"):
        rove.align(good, np.zeros((10, 4), np.float32))
    with pytest.raises(ValueError, match="'source'.*C-contiguous"):
        rove.align(np.zeros((10, 6), np.float32)[:, ::2], good)
    bad = good.copy()
    bad[3, 1] = np.nan
    with pytest.raises(ValueError, match="'source': row 3 is not finite"):
        rove.align(bad, good)
    with pytest.raises(ValueError, match="method"):
        rove.align(good, good, method="sift")
    with pytest.raises(ValueError, match="voxel"):
        rove.align(good, good, voxel="big")
    with pytest.raises(ValueError, match="ndt takes one voxel size"):
        rove.align(good, good, method="ndt", voxel=[0.5, 0.2])
    with pytest.raises(ValueError, match="neighbors"):
        rove.align(good, good, neighbors=1)
    with pytest.raises(ValueError, match="threads|num_threads"):
        rove.align(good, good, threads=100000)
    with pytest.raises(TypeError):
        rove.align(good, good, init=np.eye(4))


def test_concurrent_calls_give_the_serial_results():
    # align releases the GIL: two threads run it at once on shared inputs.
    from concurrent.futures import ThreadPoolExecutor
    src, tgt = rove.read_pcd(ROOM2), rove.read_pcd(ROOM1)
    init = rove.SE3(rove.SO3.rot_z(0.6931), [1.79387, 0.720047, 0.0])
    serial = rove.align(src, tgt, method="ndt", voxel=0.2, init=init).T_target_source
    with ThreadPoolExecutor(2) as pool:
        futures = [pool.submit(rove.align, src, tgt, method="ndt", voxel=0.2, init=init)
                   for _ in range(4)]
        for f in futures:
            np.testing.assert_array_equal(f.result().T_target_source, serial)
