"""rove.nav_plan and rove.nav_run against `rove nav plan` / `rove nav run`
on the same map (a small room written as a ROS map, and MRPT's Malaga
campus map), and what they refuse."""

import math

import numpy as np
import pytest

import rove
from conftest import cli_error, dataset, run_cli_json


def room():
    """A 10 m x 8 m room at 5 cm: walls around, a wall at x = 5 with a
    1.5 m door at its top, a pillar."""
    p = np.ones((160, 200))
    p[:3, :] = p[-3:, :] = 0
    p[:, :3] = p[:, -3:] = 0
    p[:110, 99:102] = 0
    p[40:60, 140:160] = 0
    return rove.OccupancyGrid.from_free_probability(p, 0.0, 0.0, 0.05)


@pytest.fixture
def room_yaml(tmp_path):
    yaml, _ = rove.save_ros_map(tmp_path / "room", room())
    return yaml


@pytest.mark.parametrize("method", ["value-iteration", "astar"])
def test_plan_equals_the_command_line(tmp_path, room_yaml, method):
    out = tmp_path / "path.tum"
    cli = run_cli_json("nav", "plan", room_yaml, "--start", "1,1", "--goal", "9,2,90", "--method", method,
                       "--robot-radius", "0.3", "--simplify", "-o", out)
    r = rove.nav_plan(room_yaml, (1, 1), (9, 2, math.pi / 2), method=method, robot_radius=0.3,
                      simplify=True)
    assert r.termination == cli["termination"] == "found" and r.message == cli["message"]
    assert r.map_kind == cli["map_kind"] == "ROS map" and r.method == cli["method"]
    assert r.points == cli["points"] and r.path_cells == cli["path_cells"]
    assert r.expanded_cells == cli["expanded_cells"]
    assert r.length_m == pytest.approx(cli["length_m"], rel=1e-12)
    assert r.min_clearance_m == pytest.approx(cli["min_clearance_m"], rel=1e-12)
    # The path the command wrote: TUM rows, time = distance along the path.
    tum = np.loadtxt(out)
    np.testing.assert_allclose(r.path[:, :2], tum[:, 1:3], atol=1e-6)
    np.testing.assert_allclose(r.distances, tum[:, 0], atol=1e-6)
    assert r.path[-1, 2] == pytest.approx(math.pi / 2)
    # The grid itself, without a file: the same path.
    g = rove.nav_plan(room(), rove.SE2(1, 1, 0), (9, 2, math.pi / 2), method=method,
                      robot_radius=0.3, simplify=True)
    np.testing.assert_array_equal(g.path, r.path)


def test_run_equals_the_command_line(tmp_path, room_yaml):
    cli = run_cli_json("nav", "run", room_yaml, "--start", "1,1,0", "--goal", "9,1.5", "-o", tmp_path / "run",
                       expect=(0, 3))
    frames = []
    log = tmp_path / "run.rawlog"
    r = rove.nav_run(room_yaml, (1, 1, 0), (9, 1.5), rawlog=log, on_frame=lambda f: frames.append(f["time"]))
    assert r.termination == cli["termination"] == "goal-reached" and r.ok
    assert r.cycles == cli["cycles"] > 0 and r.replans == cli["replans"]
    assert r.cycles - 1 <= len(frames) <= r.cycles
    assert r.infeasible_cycles == cli["infeasible_cycles"]
    for k in ("planned_length_m", "driven_length_m", "time_s", "min_clearance_m"):
        assert getattr(r, k) == pytest.approx(cli[k], rel=1e-9), k
    driven = np.loadtxt(tmp_path / "run" / "driven.tum")
    np.testing.assert_allclose(r.driven[:, :2], driven[:, 1:3], atol=1e-6)
    np.testing.assert_allclose(r.times, driven[:, 0], atol=1e-9)
    clearance = np.loadtxt(tmp_path / "run" / "clearance.txt")
    np.testing.assert_allclose(r.clearances, clearance[:, 4], atol=1e-4)
    assert r.issues == [(i["code"], i["message"]) for i in cli["issues"]]
    # The log holds the run's odometry and scans, as the command's does.
    ours = rove.read_rawlog(log)
    theirs = rove.read_rawlog(tmp_path / "run" / "run.rawlog")
    assert len(ours) == len(theirs) > 0 and ours.layout == theirs.layout


def test_run_with_the_reactive_navigator(tmp_path, room_yaml):
    cli = run_cli_json("nav", "run", room_yaml, "--start", "1,1,0", "--goal", "3,6", "--planner", "reactive",
                       "--robot-radius", "0.25", "-o", tmp_path / "run", expect=(0, 3))
    r = rove.nav_run(room_yaml, (1, 1, 0), (3, 6), planner="reactive", robot_radius=0.25)
    assert r.termination == cli["termination"] and r.cycles == cli["cycles"]
    assert r.driven_length_m == pytest.approx(cli["driven_length_m"], rel=1e-9)


@pytest.mark.datasets
def test_plan_on_malaga_equals_the_command_line(tmp_path):
    gridmap = dataset("mrpt/2006-MalagaCampus.gridmap.gz")
    cli = run_cli_json("nav", "plan", gridmap, "--start", "20,-110", "--goal", "90,40", "--robot-radius", "0.3",
                       "-o", tmp_path / "vi.tum")
    r = rove.nav_plan(gridmap, (20, -110), (90, 40), robot_radius=0.3)
    assert r.map_kind == "MRPT gridmap" and r.points == cli["points"]
    assert r.expanded_cells == cli["expanded_cells"]
    assert r.length_m == pytest.approx(cli["length_m"], rel=1e-12)


def test_nav_bad_input(tmp_path, room_yaml):
    with pytest.raises(TypeError, match="argument 'map'"):
        rove.nav_plan(3, (1, 1), (9, 2))
    with pytest.raises(ValueError, match=r"argument 'start': expected \(x, y\) or \(x, y, yaw\), got 4"):
        rove.nav_plan(room_yaml, (1, 2, 3, 4), (9, 2))
    with pytest.raises(TypeError, match="argument 'goal'"):
        rove.nav_plan(room_yaml, (1, 1), "far away")
    with pytest.raises(rove.InvalidArgument, match="dijkstra"):
        rove.nav_plan(room_yaml, (1, 1), (9, 2), method="dijkstra")
    with pytest.raises(rove.InvalidArgument, match="robot_radius"):
        rove.nav_plan(room_yaml, (1, 1), (9, 2), robot_radius=0)
    with pytest.raises(rove.InvalidArgument, match="occupancy_threshold"):
        rove.nav_plan(room_yaml, (1, 1), (9, 2), occupancy_threshold=2)
    with pytest.raises(rove.IoError, match="unknown input kind"):
        rove.nav_plan(tmp_path / "room.png", (1, 1), (9, 2))
    missing = tmp_path / "none.yaml"
    with pytest.raises(rove.IoError) as e:
        rove.nav_plan(missing, (1, 1), (9, 2))
    assert str(e.value) == cli_error("nav", "plan", missing, "--start", "1,1", "--goal", "9,2",
                                     "-o", tmp_path / "p.tum")
    # No path: the goal in the pillar, with the command's message.
    with pytest.raises(rove.Error) as e:
        rove.nav_plan(str(room_yaml), (1, 1), (7.5, 2.5))
    assert str(e.value) == cli_error("nav", "plan", room_yaml, "--start", "1,1", "--goal", "7.5,2.5",
                                     "-o", tmp_path / "p.tum")
    with pytest.raises(rove.Error) as e:
        rove.nav_run(str(room_yaml), (1, 1, 0), (7.5, 2.5))
    assert str(e.value) == cli_error("nav", "run", room_yaml, "--start", "1,1,0", "--goal", "7.5,2.5",
                                     "-o", tmp_path / "r")
    typo = tmp_path / "typo.ini"
    typo.write_text("[TEB]\nmax_vel_x = 0.5\nweight_obstacles = 10\n")
    with pytest.raises(rove.ConfigError) as e:
        rove.nav_run(room_yaml, (1, 1, 0), (9, 1.5), config=typo)
    assert e.value.key == "weight_obstacles"
    assert str(e.value) == cli_error("nav", "run", room_yaml, "--start", "1,1,0", "--goal", "9,1.5",
                                     "--config", typo, "-o", tmp_path / "r")
    with pytest.raises(rove.InvalidArgument, match="planner 'dwa'"):
        rove.nav_run(room_yaml, (1, 1, 0), (9, 1.5), planner="dwa")
    with pytest.raises(rove.InvalidArgument, match="max_v"):
        rove.nav_run(room_yaml, (1, 1, 0), (9, 1.5), max_v=0)
    with pytest.raises(rove.IoError):
        rove.nav_run(room_yaml, (1, 1, 0), (9, 1.5), rawlog=room_yaml)  # over its input


class Stop(Exception):
    pass


def test_run_callback_exception_stops_the_run(room_yaml):
    seen = []

    def cb(frame):
        seen.append(frame)
        if len(seen) == 4:
            raise Stop("enough")

    with pytest.raises(Stop):
        rove.nav_run(room_yaml, (1, 1, 0), (9, 1.5), on_frame=cb)
    assert len(seen) == 4 and isinstance(seen[0]["pose"], rove.SE2)
