"""rove.rawlog_convert against `rove rawlog convert` on the same logs (MRPT,
CARMEN, to and from ROS bags when rove has the ROS adapter), and what it
refuses."""

import re

import numpy as np
import pytest

import rove
from conftest import SOURCE_DIR, TELECOM, cli_error, run_cli

CARMEN = SOURCE_DIR / "modules" / "io" / "tests" / "data" / "carmen_intel_head.clf"


def cli_convert(*args):
    """The command's report: (entries read, written, kept, dropped)."""
    _, out = run_cli("rawlog", "convert", "--no-progress", *args)
    m = re.search(r"entries: (\d+) read, (\d+) (?:messages )?written", out)
    kept, dropped, section = {}, {}, None
    for line in out.splitlines():
        if line.startswith("kept:"):
            section = kept
        elif line.startswith("dropped:"):
            section = dropped
        elif section is not None and (row := re.match(r"\s+(\d+)  (.+)$", line)):
            section[row.group(2)] = int(row.group(1))
    return int(m.group(1)), int(m.group(2)), kept, dropped


def scans(path):
    return [o for o in rove.read_rawlog(path).observations() if isinstance(o, rove.RangeScan2D)]


@pytest.mark.parametrize("source,args,kwargs", [
    (TELECOM, [], {}),
    (CARMEN, ["--layout", "2"], {"layout": 2}),
    (CARMEN, ["--no-gzip"], {"gzip": False}),
])
def test_convert_equals_the_command_line(tmp_path, source, args, kwargs):
    entries_in, entries_out, kept, dropped = cli_convert(*args, source, tmp_path / "cli.rawlog")
    progress = []
    r = rove.rawlog_convert(source, tmp_path / "py.rawlog", on_progress=progress.append, **kwargs)
    assert (r.entries_in, r.entries_out) == (entries_in, entries_out)
    assert r.kept == kept and r.dropped == dropped
    assert len(progress) == entries_in and progress[-1]["position"] > 0
    a, b = scans(tmp_path / "py.rawlog"), scans(tmp_path / "cli.rawlog")
    assert len(a) == len(b) > 0
    np.testing.assert_array_equal(a[-1].ranges, b[-1].ranges)
    gz = (tmp_path / "py.rawlog").read_bytes()[:2] == b"\x1f\x8b"
    assert gz == kwargs.get("gzip", True)


def test_convert_to_and_from_a_bag(tmp_path):
    if not rove._rove._has_ros():
        pytest.skip("rove was built without the ROS adapter")
    entries_in, written, kept, dropped = cli_convert("--compression", "bz2", TELECOM, tmp_path / "cli.bag")
    r = rove.rawlog_convert(TELECOM, tmp_path / "py.bag", compression="bz2")
    assert (r.entries_in, r.entries_out, r.kept) == (entries_in, written, kept)
    assert sum(r.messages_by_topic.values()) == written and r.dropped == dropped
    # Back from the bag: the command's reading of the bag.
    back = cli_convert(tmp_path / "py.bag", tmp_path / "cli_back.rawlog")
    b = rove.rawlog_convert(tmp_path / "py.bag", tmp_path / "py_back.rawlog", topics=["/scan", "/odom"])
    assert b.input_format == "ROS bag" and (b.entries_in, b.entries_out, b.kept) == back[:3]
    assert len(scans(tmp_path / "py_back.rawlog")) == len(scans(TELECOM))


def test_convert_bad_input(tmp_path):
    missing = tmp_path / "none.rawlog"
    with pytest.raises(rove.IoError):
        rove.rawlog_convert(missing, tmp_path / "out.rawlog")
    with pytest.raises(rove.IoError) as e:
        rove.rawlog_convert(TELECOM, TELECOM)  # over its input
    assert str(e.value) == cli_error("rawlog", "convert", "--no-progress", TELECOM, TELECOM)
    junk = tmp_path / "junk.rawlog"
    junk.write_bytes(b"\x07" * 64)
    with pytest.raises(rove.ParseError) as e:
        rove.rawlog_convert(junk, tmp_path / "out.rawlog")
    assert str(e.value) == cli_error("rawlog", "convert", "--no-progress", junk, tmp_path / "out.rawlog")
    with pytest.raises(rove.InvalidArgument, match="layout = 3"):
        rove.rawlog_convert(TELECOM, tmp_path / "out.rawlog", layout=3)
    with pytest.raises(rove.InvalidArgument, match="zstd"):
        rove.rawlog_convert(TELECOM, tmp_path / "out.bag", compression="zstd")
    with pytest.raises(rove.InvalidArgument, match="max_range"):
        rove.rawlog_convert(CARMEN, tmp_path / "out.rawlog", max_range=-2)
    with pytest.raises(TypeError):
        rove.rawlog_convert(TELECOM, 7)
    assert not (tmp_path / "out.rawlog").exists()
