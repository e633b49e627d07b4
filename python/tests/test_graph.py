"""Pose graphs: reading, vertices as numpy, optimization against
`rove graph-slam --json`."""

import numpy as np
import pytest

import rove
from conftest import DATA_DIR, run_cli_json

W100 = DATA_DIR / "posegraph" / "w100.graph"
CIRCLE = DATA_DIR / "posegraph" / "graph_2d_circle_50nodes.graph"


def test_read_and_vertices():
    g = rove.read_graph(W100)
    assert isinstance(g, rove.PoseGraph2D)
    assert g.num_vertices == 60 and g.num_edges == 240
    v = g.vertices()
    assert v.shape == (60, 3) and v.dtype == np.float64
    ids = g.vertex_ids  # EQUIV records merged 21..60 into others: 0..20, 61..99 remain
    np.testing.assert_array_equal(ids, np.r_[np.arange(21), np.arange(61, 100)])
    # The file's second vertex: VERTEX2 1 0.995595 0.0837204 0.0146728.
    np.testing.assert_allclose(v[1], [0.995595, 0.0837204, 0.0146728], rtol=0, atol=1e-15)
    p = g.pose(1)
    assert isinstance(p, rove.SE2) and p.x == v[1, 0]
    assert g.edges().shape == (240, 2)


def test_optimize_equals_the_command_line(tmp_path):
    cli = run_cli_json("graph-slam", "-i", W100, "-o", tmp_path / "out.graph")
    g = rove.read_graph(W100)
    assert g.initialize("auto") == cli["init"]
    r = g.optimize()
    assert r.status == cli["termination"] and r.converged == cli["converged"]
    assert r.iterations == cli["iterations"]
    assert r.initial_chi2 == pytest.approx(cli["initial_chi2"], rel=1e-12)
    assert r.final_chi2 == pytest.approx(cli["final_chi2"], rel=1e-12)
    assert g.chi2() == pytest.approx(r.final_chi2, rel=1e-12)
    # The optimized poses are those the command line wrote.
    written = rove.read_graph(tmp_path / "out.graph").vertices()
    np.testing.assert_allclose(g.vertices(), written, atol=1e-12)


def test_build_write_read_3d(tmp_path):
    g = rove.PoseGraph3D()
    step = rove.SE3.exp(np.array([1.0, 0, 0, 0, 0, 0.1]))
    pose = rove.SE3()
    for i in range(5):
        g.add_vertex(i, pose, fixed=(i == 0))
        pose = pose * step
    for i in range(4):
        g.add_edge(i, i + 1, step)
    g.add_edge(0, 4, step * step * step * step, information=np.eye(6) * 10)
    assert g.chi2() == pytest.approx(0.0, abs=1e-20)
    g.write(tmp_path / "g.g2o")
    h = rove.read_graph(tmp_path / "g.g2o")
    assert isinstance(h, rove.PoseGraph3D) and h.num_edges == 5
    np.testing.assert_allclose(h.vertices(), g.vertices(), atol=1e-12)
    assert h.vertices().shape == (5, 7)
    r = h.optimize()
    assert r.converged or r.status == "converged", r.message


def test_graph_errors(tmp_path):
    bad = tmp_path / "bad.graph"
    bad.write_text("VERTEX2 0 0 0 0\nVERTEX2 1 1 zero 0\n")
    with pytest.raises(rove.ParseError) as e:
        rove.read_graph(bad)
    assert e.value.line == 2
    with pytest.raises(rove.IoError):
        rove.read_graph(tmp_path / "none.graph")
    g = rove.read_graph(CIRCLE)
    with pytest.raises(ValueError):
        g.pose(10**9)
    with pytest.raises(ValueError):
        g.optimize(solver="newton")
    with pytest.raises(ValueError):
        g.add_edge(0, 1, rove.SE2(), information=-np.eye(3))
