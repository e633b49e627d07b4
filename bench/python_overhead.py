#!/usr/bin/env python3
"""What calling rove from Python adds to the time of a job, against the C++
command line on the same input, in one run (issue 26: < 5 %).

  align:    the small_gicp pair, GICP with `rove align`'s defaults. C++: the
            `seconds` of `rove align --json` (the align_clouds call, clouds
            already read). Python: rove.align on clouds already read.
  icp-slam: the Telecom rawlog with MRPT's icp-slam_demo_classic.ini. C++:
            read_seconds + mapping_seconds of the command line's summary
            (the run_icp_slam call). Python: the whole rove.icp_slam call
            (config parsing, map setup, the run, the GIL handover per step).
            Also in the same process: the Python call's wall time against
            the library's own read_seconds + mapping_seconds of that run
            (what the bindings add, without the command line's cold start).

Runs alternate C++ and Python, several times, and report medians.

  PYTHONPATH=build/release/python /usr/bin/python3 bench/python_overhead.py \\
      --rove build/release/apps/rove --datasets ../shared/datasets [--runs 7]
"""

import argparse
import json
import pathlib
import statistics
import subprocess
import tempfile
import time

import rove

ROOT = pathlib.Path(__file__).resolve().parents[1]


def cli_json(exe, *args):
    out = subprocess.run([exe, *map(str, args), "--json"], capture_output=True, text=True)
    if out.returncode not in (0, 3):
        raise SystemExit(out.stderr)
    return json.loads(out.stdout)


def bench_align(exe, datasets, runs):
    src = datasets / "pointcloud" / "small_gicp_source.ply"
    tgt = datasets / "pointcloud" / "small_gicp_target.ply"
    s, t = rove.read_ply(src), rove.read_ply(tgt)
    cpp, py = [], []
    for _ in range(runs):
        cpp.append(cli_json(exe, "align", src, tgt)["seconds"])
        t0 = time.perf_counter()
        r = rove.align(s, t)
        py.append(time.perf_counter() - t0)
    assert r.converged, r.message
    return cpp, py


def bench_icp_slam(exe, runs):
    ini = ROOT / "data" / "mrpt" / "icp-slam_demo_classic.ini"
    log = ROOT / "data" / "mrpt" / "2006-01ENE-21-SENA_Telecom_Faculty_one_loop_only.rawlog"
    cpp, py, lib = [], [], []
    with tempfile.TemporaryDirectory() as out:
        for _ in range(runs):
            j = cli_json(exe, "icp-slam", ini, log, "-o", out, "--no-progress")
            cpp.append(j["read_seconds"] + j["mapping_seconds"])
            t0 = time.perf_counter()
            r = rove.icp_slam(log, config=ini)
            py.append(time.perf_counter() - t0)
            s = r.summary()
            assert s["final_pose"] == j["final_pose"]
            lib.append(s["read_seconds"] + s["mapping_seconds"])
    return cpp, py, lib


def report(name, cpp, py):
    c, p = statistics.median(cpp), statistics.median(py)
    print(f"{name:9s} C++ {c * 1e3:9.2f} ms  Python {p * 1e3:9.2f} ms  "
          f"overhead {100 * (p / c - 1):+6.2f} %  (medians of {len(cpp)}; "
          f"min C++ {min(cpp) * 1e3:.2f} ms, min Python {min(py) * 1e3:.2f} ms)")


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--rove", required=True, help="the rove command line (Release build)")
    ap.add_argument("--datasets", default=str(ROOT.parent / "shared" / "datasets"))
    ap.add_argument("--runs", type=int, default=7)
    a = ap.parse_args()
    report("align", *bench_align(a.rove, pathlib.Path(a.datasets), a.runs))
    cpp, py, lib = bench_icp_slam(a.rove, a.runs)
    report("icp-slam", cpp, py)
    report("in-proc.", lib, py)


if __name__ == "__main__":
    main()
