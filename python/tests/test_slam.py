"""The SLAM and localization entry points against the command line's
summaries on the same data, callbacks, and views into results."""

import gc

import numpy as np
import pytest

import rove
from conftest import DATA_DIR, ICP_SLAM_INI, TELECOM, dataset, run_cli_json

MRPT = DATA_DIR / "mrpt"


def test_icp_slam_equals_the_command_line(tmp_path):
    cli = run_cli_json("icp-slam", ICP_SLAM_INI, TELECOM, "-o", tmp_path / "out", "--no-progress")
    steps = []
    r = rove.icp_slam(TELECOM, config=ICP_SLAM_INI, on_step=lambda s: steps.append(s["index"]))
    s = r.summary()
    for key in ("steps", "scans", "observations", "icp_runs", "icp_accepted",
                "icp_rejected_goodness", "icp_iterations", "keyframes", "keyframes_checked",
                "keyframes_contradicted", "consistency_resolution"):
        assert s[key] == cli[key], key
    assert s["keyframes_checked"] == s["keyframes"] - 1 and s["keyframes_contradicted"] == 0
    assert s["final_pose"] == cli["final_pose"]  # the same numbers to the bit
    assert len(steps) == cli["steps"] and steps == sorted(steps)
    path = r.path
    assert path.shape == (cli["steps"], 3)
    np.testing.assert_array_equal(path[-1], [cli["final_pose"][k] for k in ("x", "y", "phi")])
    assert r.final_pose.x == cli["final_pose"]["x"]
    # The path written by the command line (TUM: t x y z qx qy qz qw).
    tum = np.loadtxt(tmp_path / "out" / "path.tum")
    np.testing.assert_allclose(path[:, :2], tum[:, 1:3], atol=1e-6)
    cloud = r.point_maps[0]
    assert len(cloud) == cli["map_points"]
    assert r.issues == [(i["code"], i["message"]) for i in cli["issues"]]


def test_icp_slam_views_outlive_the_result():
    r = rove.icp_slam(TELECOM, config=ICP_SLAM_INI, max_steps=30)
    cloud = r.point_maps[0]
    pts = cloud.points
    assert pts.__array_interface__["data"][0] == cloud._points_address()  # no copy
    expected = pts.copy()
    del r, cloud
    gc.collect()
    np.testing.assert_array_equal(pts, expected)  # the view keeps the map alive


def test_overrides_change_the_run():
    base = rove.icp_slam(TELECOM, config=ICP_SLAM_INI, max_steps=40)
    fewer = rove.icp_slam(TELECOM, config=ICP_SLAM_INI, max_steps=40,
                          overrides={"MappingApplication": {"insertionLinDistance": 5.0}})
    assert len(base.path) == len(fewer.path) == 40
    assert fewer.summary()["keyframes"] < base.summary()["keyframes"]


class Stop(Exception):
    pass


def test_callback_exception_stops_the_run():
    seen = []

    def cb(step):
        seen.append(step["index"])
        if len(seen) == 5:
            raise Stop("enough")

    with pytest.raises(Stop, match="enough"):
        rove.icp_slam(TELECOM, config=ICP_SLAM_INI, on_step=cb)
    assert len(seen) == 5


def test_slam_bad_input(tmp_path):
    with pytest.raises(rove.IoError):
        rove.icp_slam(tmp_path / "none.rawlog", config=ICP_SLAM_INI)
    with pytest.raises(rove.ConfigError) as e:
        rove.icp_slam(TELECOM, config=ICP_SLAM_INI, overrides={"ICP": {"maxIterations": "many"}})
    assert e.value.section == "ICP" and e.value.key == "maxIterations"
    with pytest.raises(TypeError, match="overrides"):
        rove.icp_slam(TELECOM, config=ICP_SLAM_INI, overrides={"ICP": 3})
    with pytest.raises(rove.ParseError):
        junk = tmp_path / "junk.rawlog"
        junk.write_bytes(b"\x07" * 64)
        rove.icp_slam(junk, config=ICP_SLAM_INI)


def test_lidar_slam_equals_the_command_line(tmp_path):
    cli = run_cli_json("lidar-slam", TELECOM, "-o", tmp_path / "out", "--no-progress",
                       "--max-scans", "120")
    r = rove.lidar_slam(TELECOM, max_scans=120)
    s = r.summary()
    assert s["scans"] == cli["scans"] and s["nodes"] == cli["nodes"]
    assert (s["nodes_checked"], s["nodes_contradicted"]) == (cli["nodes_checked"], cli["nodes_contradicted"])
    assert s["consistency_resolution"] == cli["consistency_resolution"] > 0
    assert s["submaps"] == cli["submaps"]
    assert s["loop_closures_accepted"] == cli["loops_accepted"]
    assert s["window_edges"] == cli["refinement"]["window_edges"] > 0
    assert s["window_failed"] == cli["refinement"]["window_failed"]
    assert r.graph.num_vertices == cli["graph_vertices"]
    assert (r.map.size_x, r.map.size_y) == tuple(cli["map_cells"])
    assert r.path.shape == (cli["scans"], 3)


def test_pf_localization_equals_the_command_line(tmp_path):
    ini, log = MRPT / "localization_demo.ini", MRPT / "localization_demo.rawlog"
    simplemap = MRPT / "localization_demo.simplemap.gz"
    cli = run_cli_json("pf-localization", ini, log, "--map", simplemap, "--no-progress",
                       "--seed", "3", "-o", tmp_path / "out", expect=(0, 3))
    r = rove.pf_localization(log, ini, seed=3,
                             overrides={"LocalizationExperiment": {"map_file": str(simplemap)}})
    assert r.status == cli["termination"] and r.converged == cli["converged"]
    assert len(r.path) == cli["steps"]
    np.testing.assert_array_equal(r.path[-1], [cli["final_pose"][k] for k in ("x", "y", "phi")])
    assert r.peak_particles == cli["peak_particles"]
    assert r.particles.shape[1] == 3 and len(r.particles) == len(r.log_weights)


def test_kf_slam_equals_the_command_line(tmp_path):
    ini = "/usr/share/mrpt/config_files/kf-slam/EKF-SLAM_6D_test.ini"
    log = MRPT / "kf-slam_demo.rawlog"
    cli = run_cli_json("kf-slam", ini, log, "--no-progress", "-o", tmp_path / "out", expect=(0, 3))
    r = rove.kf_slam(log, ini)
    assert len(r.path) == cli["steps"] and len(r.landmarks) == cli["landmark_count"]
    np.testing.assert_array_equal(r.path[-1], cli["final_position"])
    if cli.get("landmark_rmse") is not None:
        assert r.landmark_rmse == cli["landmark_rmse"]


def test_rbpf_slam_equals_the_command_line(tmp_path):
    ini = MRPT / "gridmapping_optimal_sampling.ini"
    cli = run_cli_json("rbpf-slam", ini, TELECOM, "--particles", "2", "--max-steps", "40",
                       "--no-progress", "-o", tmp_path / "out", expect=(0, 3))
    r = rove.rbpf_slam(TELECOM, ini, particles=2, max_steps=40)
    assert r.scans == cli["scans"]
    np.testing.assert_array_equal(r.path[-1], [cli["final_pose"][k] for k in ("x", "y", "phi")])
    assert (r.map.size_x, r.map.size_y) == (cli["map_cells"]["x"], cli["map_cells"]["y"])
    assert r.contradicted_updates == cli["contradicted_updates"]
    assert [code for code, _ in r.issues] == [i["code"] for i in cli["issues"]]
    cells = r.map.cells
    assert cells.__array_interface__["data"][0] == r.map._cells_address()


@pytest.mark.datasets
def test_rgbd_slam_equals_the_command_line(tmp_path):
    if not hasattr(rove, "rgbd_slam"):
        pytest.skip("rove was built without rove::vision (OpenCV)")
    seq = dataset("rgbd/tum_fr1_rpy/groundtruth.txt").parent
    cli = run_cli_json("rgbd-slam", seq, "--max-frames", "40", "--no-progress", "-o", tmp_path / "out",
                       expect=(0, 3))
    seen = []
    r = rove.rgbd_slam(seq, max_frames=40, on_frame=lambda u: seen.append(u["index"]))
    assert seen == list(range(40)) and r.camera == "tum-fr1"
    assert r.trajectory.shape == (40, 8) and r.keyframes.shape == (cli["keyframes"], 8)
    assert r.stats["keyframes"] == cli["keyframes"] and r.stats["icp_edges"] == cli["icp_edges"]
    assert r.ate_rmse == cli["ate"]["rmse_m"] < 0.05
    # The command line's trajectory file holds the same poses (TUM, 9 digits).
    rows = np.loadtxt(tmp_path / "out" / "trajectory.tum")
    np.testing.assert_allclose(r.trajectory, rows, rtol=0, atol=2e-6)
    # The tutorial's preset through the keyword, an override, and a bad key.
    t = rove.rgbd_slam(seq, max_frames=10, preset="tutorial", overrides={"": {"icp_voxel": 0.03}})
    assert t.stats["frames"] == 10 and t.stats["icp_edges"] + t.stats["icp_refused"] > 0
    with pytest.raises(rove.ConfigError, match="no_such_key"):
        rove.rgbd_slam(seq, max_frames=2, overrides={"rgbd-slam": {"no_such_key": 1}})
    with pytest.raises(ValueError, match="preset"):
        rove.rgbd_slam(seq, max_frames=2, preset="fast")


def test_ctrl_c_stops_the_run():
    import signal
    seen = []

    def cb(step):
        seen.append(step["index"])
        if len(seen) == 3:
            signal.raise_signal(signal.SIGINT)  # as Ctrl-C in the terminal

    with pytest.raises(KeyboardInterrupt):
        rove.icp_slam(TELECOM, config=ICP_SLAM_INI, on_step=cb)
    assert 3 <= len(seen) <= 4
