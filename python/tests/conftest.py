"""Shared fixtures of the Python tests: where the sources, the shared
datasets and the `rove` command line are (set by ctest, see
python/CMakeLists.txt)."""

import json
import os
import pathlib
import subprocess

import pytest

SOURCE_DIR = pathlib.Path(os.environ.get("ROVE_SOURCE_DIR", pathlib.Path(__file__).parents[2]))
DATA_DIR = SOURCE_DIR / "data"
DATASETS_DIR = pathlib.Path(os.environ.get("ROVE_DATASETS_DIR", SOURCE_DIR.parent / "shared" / "datasets"))
TELECOM = DATA_DIR / "mrpt" / "2006-01ENE-21-SENA_Telecom_Faculty_one_loop_only.rawlog"
ICP_SLAM_INI = DATA_DIR / "mrpt" / "icp-slam_demo_classic.ini"


def dataset(relative):
    """A file of the shared datasets; the test fails (not skips) without it,
    as every test labelled `datasets` does."""
    path = DATASETS_DIR / relative
    assert path.is_file(), f"{path} is missing (set ROVE_DATASETS_DIR)"
    return path


def run_cli(*args, expect=(0,)):
    """Runs the `rove` command line and returns (exit status, stdout)."""
    cli = os.environ.get("ROVE_CLI")
    if not cli:
        pytest.skip("the rove command line was not built (ROVE_BUILD_APPS=OFF)")
    env = dict(os.environ)
    env.pop("LD_PRELOAD", None)  # the command line links its own sanitizer runtime
    proc = subprocess.run([cli, *map(str, args)], capture_output=True, text=True, env=env)
    assert proc.returncode in expect, proc.stderr
    return proc.returncode, proc.stdout


def run_cli_json(*args, expect=(0,)):
    """run_cli with --json; the parsed object."""
    _, out = run_cli(*args, "--json", expect=expect)
    return json.loads(out)


def cli_error(*args, expect=(1,)):
    """Runs the `rove` command line expecting it to fail; the first line of
    rove's message on stderr (after "rove: error: "), for comparing with
    the message of the Python exception raised on the same input."""
    cli = os.environ.get("ROVE_CLI")
    if not cli:
        pytest.skip("the rove command line was not built (ROVE_BUILD_APPS=OFF)")
    env = dict(os.environ)
    env.pop("LD_PRELOAD", None)
    proc = subprocess.run([cli, *map(str, args)], capture_output=True, text=True, env=env)
    assert proc.returncode in expect, proc.stderr
    line = proc.stderr.splitlines()[0]
    prefix = "rove: error: "
    assert line.startswith(prefix), proc.stderr
    return line[len(prefix):]
