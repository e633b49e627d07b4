"""File formats from Python: PCD, PLY, rawlogs; errors name the file."""

import numpy as np
import pytest

import rove
from conftest import DATA_DIR, TELECOM, run_cli_json

BUNNY = DATA_DIR / "pointcloud" / "bunny.pcd"


@pytest.mark.parametrize("fmt", ["ascii", "binary", "binary_compressed"])
def test_pcd_round_trip(tmp_path, fmt):
    c = rove.read_pcd(BUNNY)
    path = tmp_path / "b.pcd"
    rove.write_pcd(str(path), c, format=fmt)
    d = rove.read_cloud(str(path))
    np.testing.assert_array_equal(d.points, c.points)  # every encoding is exact


@pytest.mark.parametrize("fmt", ["ascii", "binary_little_endian", "binary_big_endian"])
def test_ply_round_trip_with_channels(tmp_path, fmt):
    rng = np.random.default_rng(3)
    c = rove.PointCloud(rng.random((50, 3), dtype=np.float32),
                        colors=rng.integers(0, 256, (50, 3)).astype(np.uint8),
                        intensities=rng.random(50, dtype=np.float32))
    path = tmp_path / "c.ply"
    rove.write_ply(str(path), c, format=fmt)
    d = rove.read_ply(str(path))
    np.testing.assert_array_equal(d.points, c.points)
    np.testing.assert_array_equal(d.colors, c.colors)
    np.testing.assert_array_equal(d.intensities, c.intensities)


def test_read_errors(tmp_path):
    with pytest.raises(rove.IoError) as e:
        rove.read_pcd(str(tmp_path / "missing.pcd"))
    assert isinstance(e.value, OSError) and e.value.path.endswith("missing.pcd")
    bad = tmp_path / "bad.pcd"
    bad.write_text("# .PCD v0.7\nVERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\n"
                   "COUNT 1 1 1\nWIDTH 2\nHEIGHT 1\nPOINTS 2\nDATA ascii\n1 2 3\n4 five 6\n")
    with pytest.raises(rove.ParseError) as e:
        rove.read_pcd(str(bad))
    assert isinstance(e.value, ValueError)
    assert e.value.source.endswith("bad.pcd") and e.value.line == 12
    with pytest.raises(rove.IoError, match="unknown point cloud format"):
        rove.read_cloud(str(tmp_path / "x.xyz"))
    with pytest.raises(ValueError, match="format"):
        rove.write_pcd(str(tmp_path / "y.pcd"), rove.read_pcd(BUNNY), format="zip")


def test_rawlog_matches_rawlog_info():
    log = rove.read_rawlog(str(TELECOM))
    info = run_cli_json("rawlog", "info", "--no-progress", TELECOM)
    assert len(log) == info["entries"] == 449
    assert log.format == info["format"] and log.layout == "actions-and-frames"
    obs = log.observations()
    assert len(obs) == info["observations"]
    scan = obs[0]
    assert isinstance(scan, rove.RangeScan2D) and scan.kind == "RangeScan2D"
    assert scan.time == pytest.approx(info["time_first"], abs=1e-6)
    assert obs[-1].time == pytest.approx(info["time_last"], abs=1e-6)
    r = scan.ranges
    assert r.dtype == np.float32 and not r.flags.writeable
    pts = scan.points(sensor_frame=True)
    valid = scan.valid
    angles = np.asarray(scan.angles())
    expected = np.c_[r * np.cos(angles), r * np.sin(angles)][valid]
    np.testing.assert_allclose(pts, expected, atol=1e-5)


def test_rawlog_errors(tmp_path):
    bad = tmp_path / "junk.rawlog"
    bad.write_bytes(b"\x00\x01\x02\x03" * 10)
    with pytest.raises(rove.ParseError):
        rove.read_rawlog(str(bad))
    with pytest.raises(OSError):
        rove.read_rawlog(str(tmp_path))  # a folder
