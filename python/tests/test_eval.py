"""rove.eval_ate, eval_rpe and eval_relations against `rove eval` on the
same trajectories (files, and the same poses given as numpy rows), and
what they refuse."""

import math

import numpy as np
import pytest

import rove
from conftest import DATA_DIR, ICP_SLAM_INI, cli_error, dataset, run_cli, run_cli_json

GRAPHS = DATA_DIR / "posegraph"
GT = GRAPHS / "graph_2d_circle_50nodes_groundtruth.graph"
EST = GRAPHS / "graph_2d_circle_50nodes.graph"


def issues_of(cli):
    return [(i["code"], i["message"]) for i in cli["issues"]]


def rows_of(graph):
    """(N, 4) rows t x y theta of a 2D graph's vertices, the id as time."""
    g = rove.read_graph(graph)
    v = g.vertices()
    return np.column_stack([g.vertex_ids.astype(float), v])


def same_stats(py, cli):
    assert py.keys() == cli.keys()
    for k in cli:
        assert py[k] == pytest.approx(cli[k], rel=1e-12, abs=1e-15), k


@pytest.mark.parametrize("align", ["se3", "se2", "sim3", "none"])
def test_ate_equals_the_command_line(align):
    cli = run_cli_json("eval", "ate", "--align", align, GT, EST, expect=(0, 3))
    r = rove.eval_ate(GT, EST, align=align)
    assert r.metric == "ate" and r.pairs == cli["pairs"] == 50
    assert r.reference_format == cli["reference"]["format"] == "graph (2D vertices, id as time)"
    assert r.estimate_poses == cli["estimate"]["poses"]
    assert r.alignment["method"] == cli["alignment"]["method"]
    for k in ("scale", "position_spread_m"):
        assert r.alignment[k] == pytest.approx(cli["alignment"][k], rel=1e-12)
    np.testing.assert_allclose(r.alignment["translation"], cli["alignment"]["translation"], atol=1e-12)
    same_stats(r.translation_m, cli["translation_m"])
    same_stats(r.rotation_rad, cli["rotation_rad"])
    assert r.issues == issues_of(cli)
    assert r.translation_errors.shape == (50,) and r.aligned_estimate.shape == (50, 8)
    assert math.sqrt(np.mean(r.translation_errors ** 2)) == pytest.approx(r.translation_m["rmse"])
    # The same poses as numpy rows (t x y theta and TUM) give the same figures.
    a = rove.eval_ate(rows_of(GT), rows_of(EST), align=align)
    assert a.estimate_format == "array (t x y theta)"
    same_stats(a.translation_m, cli["translation_m"])
    t = rove.eval_ate(GT, r.aligned_estimate, align="none")  # the aligned poses, as TUM rows
    assert t.translation_m["rmse"] == pytest.approx(r.translation_m["rmse"], rel=1e-9)


def test_ate_of_a_tum_file_against_numpy_rows(tmp_path):
    # icp-slam's path (TUM, written by the command) against the odometry rows.
    log = DATA_DIR / "mrpt" / "2006-01ENE-21-SENA_Telecom_Faculty_one_loop_only.rawlog"
    run_cli("icp-slam", ICP_SLAM_INI, log, "-o", tmp_path / "out", "--no-progress", "--max-steps", "80")
    path = tmp_path / "out" / "path.tum"
    rows = np.loadtxt(path)
    odo = rove.icp_slam(log, config=ICP_SLAM_INI, max_steps=80)
    est = np.column_stack([rows[:, 0], odo.odometry])
    est_file = tmp_path / "odometry.tum"
    np.savetxt(est_file, np.column_stack([rows[:, 0], odo.odometry[:, :2], np.zeros(len(rows)),
                                          np.zeros((len(rows), 2)), np.sin(odo.odometry[:, 2] / 2),
                                          np.cos(odo.odometry[:, 2] / 2)]), fmt="%.9f")
    cli = run_cli_json("eval", "ate", "--align", "se2", path, est_file, expect=(0, 3))
    r = rove.eval_ate(path, est, align="se2")
    assert r.reference_format == "tum" and r.pairs == cli["pairs"] == 80
    assert r.translation_m["rmse"] == pytest.approx(cli["translation_m"]["rmse"], rel=1e-6)
    assert r.rotation_rad["max"] == pytest.approx(cli["rotation_rad"]["max"], rel=1e-6, abs=1e-9)


@pytest.mark.parametrize("delta,unit,align", [(1, "frames", "none"), (5, "frames", "sim3"), (2.0, "m", "none")])
def test_rpe_equals_the_command_line(delta, unit, align):
    cli = run_cli_json("eval", "rpe", "--delta", delta, "--unit", unit, "--align", align, GT, EST,
                       expect=(0, 3))
    r = rove.eval_rpe(GT, EST, delta=delta, unit=unit, align=align)
    assert r.intervals == cli["intervals"] > 0 and r.pairs == cli["pairs"]
    assert r.unit == cli["unit"] and r.scale == pytest.approx(cli["scale"], rel=1e-12)
    same_stats(r.translation_m, cli["translation_m"])
    same_stats(r.rotation_rad, cli["rotation_rad"])
    assert r.issues == issues_of(cli)
    assert r.interval_indices.shape == (r.intervals, 2)
    a = rove.eval_rpe(rows_of(GT), rows_of(EST), delta=delta, unit=unit, align=align)
    same_stats(a.rotation_rad, cli["rotation_rad"])


def relation_rows(graph, pairs):
    """Freiburg relation rows t1 t2 x y z roll pitch yaw from a 2D graph."""
    rows = rows_of(graph)
    pose = {int(r[0]): rove.SE2(r[1], r[2], r[3]) for r in rows}
    out = []
    for i, j in pairs:
        d = pose[i].inverse() * pose[j] if j in pose else rove.SE2(1, 0, 0)
        out.append([i, j, d.translation[0], d.translation[1], 0, 0, 0, d.log()[2]])
    return np.array(out)


def test_relations_equal_the_command_line(tmp_path):
    pairs = [(i, i + 5) for i in range(0, 44, 3)] + [(2, 999)]  # 999: no such pose
    rel = relation_rows(GT, pairs)
    rel_file = tmp_path / "circle.relations"
    np.savetxt(rel_file, rel, fmt="%.17g")
    cli = run_cli_json("eval", "relations", EST, rel_file, expect=(3,))
    r = rove.eval_relations(EST, rel_file)
    assert r.relations == cli["relations"] == len(pairs) and r.used == cli["used"] == len(pairs) - 1
    for key in ("translation_m", "translation_squared_m2", "rotation_rad", "rotation_squared_rad2"):
        same_stats(getattr(r, key), cli[key])
    assert r.issues == issues_of(cli) and r.issues[0][0] == "missing-times"
    assert list(r.missing_times) == [999.0]
    # The relations and the estimate as arrays.
    a = rove.eval_relations(rows_of(EST), rel)
    same_stats(a.translation_m, cli["translation_m"])


@pytest.mark.datasets
def test_relations_with_a_carmen_clock(tmp_path):
    """ACES: the relations name the FLASER lines' ipc times; log= maps them
    to the logger times of rove's path, as --log does."""
    aces = dataset("radish/aces.clf.bz2")
    relations = dataset("radish/aces.relations")
    run = rove.icp_slam(aces, config=DATA_DIR / "icp-slam_carmen.ini", max_steps=400, max_range=50)
    rows = np.column_stack([run.times, run.path])
    path = tmp_path / "path.tum"
    np.savetxt(path, np.column_stack([rows[:, :3], np.zeros((len(rows), 3)), np.sin(rows[:, 3] / 2),
                                      np.cos(rows[:, 3] / 2)]), fmt="%.9f")
    cli = run_cli_json("eval", "relations", "--log", aces, path, relations, expect=(0, 3))
    r = rove.eval_relations(path, relations, log=aces)
    assert r.used == cli["used"] > 0 and r.relations == cli["relations"]
    same_stats(r.translation_m, cli["translation_m"])
    same_stats(r.rotation_rad, cli["rotation_rad"])
    assert r.issues == issues_of(cli)
    a = rove.eval_relations(rows, relations, log=aces)
    assert a.used == cli["used"]
    assert a.translation_m["mean"] == pytest.approx(cli["translation_m"]["mean"], rel=1e-6)


def test_eval_bad_input(tmp_path):
    with pytest.raises(TypeError, match="argument 'reference'"):
        rove.eval_ate(3, EST)
    with pytest.raises(ValueError, match=r"argument 'estimate': expected shape \(N, 8\).*got \(4, 5\)"):
        rove.eval_ate(GT, np.zeros((4, 5)))
    with pytest.raises(ValueError, match="row 1 is not finite"):
        rove.eval_ate(GT, np.array([[0, 0, 0, 0], [1, np.nan, 0, 0]]))
    with pytest.raises(ValueError, match="quaternion"):
        rove.eval_ate(GT, np.zeros((3, 8)))
    with pytest.raises(TypeError, match="argument 'relations'"):
        rove.eval_relations(EST, [1, 2])
    missing = tmp_path / "none.tum"
    with pytest.raises(rove.IoError) as e:
        rove.eval_ate(GT, missing)
    assert str(e.value) == cli_error("eval", "ate", GT, missing)
    with pytest.raises(rove.InvalidArgument, match="affine"):
        rove.eval_ate(GT, EST, align="affine")
    with pytest.raises(rove.InvalidArgument, match="expected none or sim3"):
        rove.eval_rpe(GT, EST, align="se3")
    with pytest.raises(rove.InvalidArgument, match="furlongs"):
        rove.eval_rpe(GT, EST, unit="furlongs")
    with pytest.raises(rove.InvalidArgument, match="csv"):
        rove.eval_ate(GT, EST, format="csv")
    with pytest.raises(rove.InvalidArgument):
        rove.eval_ate(GT, EST, max_dt=-1)
    # Errors with the command line's messages: no pose associates, a file
    # that is no trajectory, a malformed row.
    later = tmp_path / "later.tum"
    later.write_text("100 0 0 0 0 0 0 1\n101 1 0 0 0 0 0 1\n")
    with pytest.raises(rove.InvalidArgument) as e:
        rove.eval_ate(GT, later)
    assert str(e.value) == cli_error("eval", "ate", GT, later)
    five = tmp_path / "five.txt"
    five.write_text("1 2 3 4 5\n")
    with pytest.raises(rove.ParseError) as e:
        rove.eval_ate(GT, five)
    assert "the first row has 5 fields" in str(e.value) and e.value.field == "format"
    assert str(e.value) == cli_error("eval", "ate", GT, five)
    bad = tmp_path / "bad.tum"
    bad.write_text("0 0 0 0 0 0 0 1\n1 1 zero 0 0 0 0 1\n")
    with pytest.raises(rove.ParseError) as e:
        rove.eval_rpe(bad, bad)
    assert e.value.line == 2 and str(e.value) == cli_error("eval", "rpe", bad, bad)
