"""rove.octomap_build and rove.map_build against `rove octomap build` and
`rove map build` on the same inputs, and what they refuse."""

import numpy as np
import pytest

import rove
from conftest import DATA_DIR, ICP_SLAM_INI, cli_error, run_cli_json

CLOUDS = DATA_DIR / "pointcloud"
MRPT = DATA_DIR / "mrpt"


def test_octomap_build_equals_the_command_line(tmp_path):
    scan = CLOUDS / "room_scan1.pcd"
    cli = run_cli_json("octomap", "build", scan, "-o", tmp_path / "cli.bt", "--res", "0.1",
                       "--ply", tmp_path / "cli.ply")
    seen = []
    r = rove.octomap_build([scan], output=tmp_path / "py.bt", resolution=0.1, on_cloud=seen.append)
    assert seen == [1]
    for k in ("points", "skipped_points", "nodes", "leaves", "occupied_leaves", "memory_bytes"):
        assert getattr(r, k) == cli[k], k
    assert r.bounds == cli["bounds"] and r.colors == cli["colors"]
    assert r.issues == [(i["code"], i["message"]) for i in cli["issues"]] == []
    # The same octree, byte for byte, and the same occupied cells.
    assert (tmp_path / "py.bt").read_bytes() == (tmp_path / "cli.bt").read_bytes()
    ply = rove.read_ply(tmp_path / "cli.ply")
    assert len(r.occupied) == len(ply) == cli["occupied_leaves"]
    np.testing.assert_allclose(np.sort(r.occupied.points, axis=0), np.sort(ply.points, axis=0), atol=1e-6)


def test_octomap_build_with_poses_and_options(tmp_path):
    bunny = CLOUDS / "bunny.pcd"
    poses = np.array([[0, 0, 0, 0, 0, 0, 0, 1], [1, 0.2, 0, 0, 0, 0, 0.3826834, 0.9238795]])
    pose_file = tmp_path / "poses.tum"
    np.savetxt(pose_file, poses, fmt="%.9f")
    cli = run_cli_json("octomap", "build", bunny, bunny, "--poses", pose_file, "--res", "0.005",
                       "--mode", "every-ray", "--arithmetic", "octomap", "--max-range", "4", "--threads", "2",
                       "-o", tmp_path / "cli.ot")
    for p in (pose_file, poses):
        r = rove.octomap_build([bunny, bunny], output=tmp_path / "py.ot", poses=p, resolution=0.005,
                               mode="every-ray", arithmetic="octomap", max_range=4, threads=2)
        assert (r.points, r.nodes, r.occupied_leaves) == (cli["points"], cli["nodes"], cli["occupied_leaves"])
        assert (tmp_path / "py.ot").read_bytes() == (tmp_path / "cli.ot").read_bytes()
    o = rove.octomap_build(bunny, resolution=0.005, origin=(0.5, 0.2, 0.3), max_range=4)
    c = run_cli_json("octomap", "build", "--origin", "0.5,0.2,0.3", "--max-range", "4", "--res", "0.005",
                     bunny, "-o", tmp_path / "origin.bt")
    assert o.outputs == [] and (o.nodes, o.leaves) == (c["nodes"], c["leaves"])


def test_octomap_build_bad_input(tmp_path):
    with pytest.raises(TypeError, match="argument 'clouds'"):
        rove.octomap_build(3)
    with pytest.raises(ValueError, match="no cloud"):
        rove.octomap_build([])
    with pytest.raises(rove.InvalidArgument, match="sideways"):
        rove.octomap_build(CLOUDS / "bunny.pcd", mode="sideways")
    with pytest.raises(rove.InvalidArgument, match="rainbow"):
        rove.octomap_build(CLOUDS / "bunny.pcd", color="rainbow")
    with pytest.raises(rove.InvalidArgument):
        rove.octomap_build(CLOUDS / "bunny.pcd", resolution=-1)
    with pytest.raises(rove.IoError, match="expected .bt or .ot"):
        rove.octomap_build(CLOUDS / "bunny.pcd", output=tmp_path / "tree.txt")
    with pytest.raises(rove.IoError):
        rove.octomap_build(CLOUDS / "bunny.pcd", output=CLOUDS / "bunny.pcd")  # over its input
    missing = tmp_path / "none.pcd"
    with pytest.raises(rove.IoError) as e:
        rove.octomap_build([missing])
    assert str(e.value) == cli_error("octomap", "build", missing, "-o", tmp_path / "t.bt")
    one = tmp_path / "one.tum"
    one.write_text("0 0 0 0 0 0 0 1\n")
    bunny = CLOUDS / "bunny.pcd"
    with pytest.raises(rove.ParseError) as e:
        rove.octomap_build([bunny, bunny], poses=one)
    assert str(e.value) == cli_error("octomap", "build", bunny, bunny, "--poses", one, "-o", tmp_path / "t.bt")


def test_map_build_equals_the_command_line(tmp_path):
    ini = MRPT / "localization_demo.ini"
    simplemap = MRPT / "localization_demo.simplemap.gz"
    cli = run_cli_json("map", "build", "--section", "MetricMap", ini, simplemap, "-o", tmp_path / "cli")
    done = []
    r = rove.map_build(ini, simplemap, out=tmp_path / "py", section="MetricMap", on_progress=done.append)
    for k in ("section", "input_kind", "keyframes", "odometry_steps", "observations", "observations_used"):
        assert getattr(r, k) == cli[k], k
    assert done and done == sorted(done)
    assert len(r.maps) == len(cli["maps"])
    for m, c in zip(r.maps, cli["maps"]):
        assert {k: m[k] for k in m} == {k: c[k] for k in m}
    grid = r.grids[0]
    assert grid.size_x * grid.size_y == cli["maps"][0]["total_cells"]
    assert [str(f).replace(str(tmp_path / "py"), "") for f in r.files] == \
        [f.replace(str(tmp_path / "cli"), "") for f in cli["files"]]
    for f in r.files:
        other = f.replace(str(tmp_path / "py"), str(tmp_path / "cli"))
        assert open(f, "rb").read() == open(other, "rb").read(), f
    assert r.issues == [(i["code"], i["message"]) for i in cli["issues"]]
    assert r.ignored_keys == cli["ignored_keys"]


def test_map_build_of_a_rawlog_without_files(tmp_path):
    log = MRPT / "2006-01ENE-21-SENA_Telecom_Faculty_one_loop_only.rawlog"
    cli = run_cli_json("map", "build", ICP_SLAM_INI, log, "-o", tmp_path / "cli")
    r = rove.map_build(ICP_SLAM_INI, log)
    assert r.files == [] and r.input_kind == "rawlog" == cli["input_kind"]
    assert r.maps[0]["points"] == cli["maps"][0]["points"] == len(r.point_maps[0])
    assert r.odometry_steps == cli["odometry_steps"]


def test_map_build_bad_input(tmp_path):
    log = MRPT / "2006-01ENE-21-SENA_Telecom_Faculty_one_loop_only.rawlog"
    with pytest.raises(rove.IoError):
        rove.map_build(tmp_path / "none.ini", log)
    with pytest.raises(rove.IoError) as e:
        rove.map_build(ICP_SLAM_INI, log, out=log)
    assert str(e.value) == cli_error("map", "build", ICP_SLAM_INI, log, "-o", log)
    beacons = tmp_path / "beacons.ini"
    beacons.write_text("[M]\nbeaconMap_count=1\n")
    r = rove.map_build(beacons, log)
    assert r.issues[0][0] == "nothing-inserted"
    typo = tmp_path / "typo.ini"
    typo.write_text("[M]\noccupancyGrid_count=1\n[M_occupancyGrid_00_creationOpts]\nresolutoin=0.1\n")
    with pytest.raises(rove.ConfigError) as e:
        rove.map_build(typo, log)
    assert str(e.value) == cli_error("map", "build", typo, log, "-o", tmp_path / "out")
    with pytest.raises(rove.ConfigError):
        rove.map_build(ICP_SLAM_INI, log, section="NoSuchSection")


def test_map_check_equals_the_command_line(tmp_path):
    simplemap = MRPT / "localization_demo.simplemap.gz"
    cli = run_cli_json("map", "check", simplemap)
    r = rove.map_check(simplemap)
    assert (r.keyframes, r.scans, r.checked, r.contradicted) == (
        cli["keyframes"], cli["scans"], cli["checked"], cli["contradicted"]) == (72, 72, 71, 0)
    assert r.resolution == cli["resolution"] and r.issues == []
    assert r.through_walls.shape == (72,) and r.through_walls[0] == 0.0
    assert r.poses.shape == (72, 3)
    worst = cli["worst"][0]
    assert r.through_walls[worst["scan"]] == worst["through_walls"] == r.through_walls.max()
    assert (r.poses[worst["scan"], 0], r.poses[worst["scan"], 1]) == (worst["x"], worst["y"])
    # A coarser grid is what it says.
    assert rove.map_check(simplemap, resolution=0.2).resolution == pytest.approx(0.2)


def test_map_check_refuses_what_the_command_refuses():
    with pytest.raises(rove.ParseError) as e:
        rove.map_check(ICP_SLAM_INI)
    assert str(e.value).split("\n")[0] in cli_error("map", "check", ICP_SLAM_INI)
    with pytest.raises(ValueError):
        rove.map_check(MRPT / "localization_demo.simplemap.gz", resolution=0.0)
