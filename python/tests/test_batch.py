"""rove.batch and `rove batch`: runs on a Dask LocalCluster against a serial
run (the same figures, even when a worker is killed mid-run), the table's
contents against each run's own files, failures reported, bad grids
refused."""

import csv
import json
import os
import pathlib
import signal
import subprocess

import pytest

import rove
from rove import batch
from conftest import ICP_SLAM_INI, TELECOM, dataset, run_cli

COMMAND = "icp-slam {config} {input} -o {out} --no-progress"


@pytest.fixture(scope="module")
def cli():
    path = os.environ.get("ROVE_CLI")
    if not path:
        pytest.skip("the rove command line was not built (ROVE_BUILD_APPS=OFF)")
    return path


@pytest.fixture(scope="module")
def cluster():
    distributed = pytest.importorskip("distributed")
    import logging
    c = distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                                 dashboard_address=":0", silence_logs=logging.CRITICAL)
    client = distributed.Client(c)
    yield client
    client.close()
    c.close()


def running(*argv):
    """Whether a process with exactly this command line runs, read from /proc
    (not pgrep: under the sanitizer suite a helper program would inherit
    LD_PRELOAD of the sanitizer runtime, and pgrep hangs with it)."""
    want = "\0".join(argv).encode() + b"\0"
    for entry in pathlib.Path("/proc").iterdir():
        if entry.name.isdigit():
            try:
                if (entry / "cmdline").read_bytes() == want:
                    return True
            except OSError:  # ended meanwhile
                pass
    return False


def timing(key):
    return "seconds" in key or key.endswith("per_second")


def deterministic(figures):
    return {k: v for k, v in figures.items() if not timing(k)}


def read_csv(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


KILL_GRID = {"ICP.thresholdDist": [0.5, 0.6, 0.75, 1.0], "max-steps": [180, 224]}  # 8 runs, every map consistent


@pytest.fixture(scope="module")
def serial_runs(tmp_path_factory, cli):
    """The killed-worker tests' reference: their 8 runs one after another."""
    serial = batch.run(COMMAND, [TELECOM], KILL_GRID, config=ICP_SLAM_INI,
                       out=tmp_path_factory.mktemp("serial"), serial=True, rove=cli)
    assert [r.status for r in serial.runs] == ["ok"] * 8
    return serial


def killed_worker_run(tmp_path, cli, cluster, serial):
    grid = KILL_GRID

    killed = []

    def kill_a_running_worker(row):
        if killed:
            return
        # A run that started (its attempt is logged with the worker's pid) and
        # has not finished (no run.json yet): kill the worker computing it.
        for tries in sorted((tmp_path / "dask" / "runs").glob(".*.attempts")):
            folder = tries.with_name(tries.name[1:-len(".attempts")])
            if not (folder / "run.json").exists():
                pid = int(tries.read_text().split()[-1])
                os.kill(pid, signal.SIGKILL)
                killed.append((folder.name, pid))
                return

    seen = []
    result = batch.run(COMMAND, [TELECOM], grid, config=ICP_SLAM_INI, out=tmp_path / "dask",
                       client=cluster, retries=1, rove=cli,
                       on_result=lambda r: (seen.append(r.name), kill_a_running_worker(r)))
    assert killed, "no run was in flight after the first result"
    assert len(seen) == 8 and sorted(seen) == [r.name for r in serial.runs]
    assert [r.status for r in result.runs] == ["ok"] * 8
    assert result.exit_status == 0
    victim = next(r for r in result.runs if r.name == killed[0][0])
    assert victim.attempts == 2 and victim.worker.split(":")[1] != str(killed[0][1])
    for a, b in zip(serial.runs, result.runs):
        assert a.params == b.params
        assert deterministic(a.figures) == deterministic(b.figures), a.name
        for f in ("path.tum", "points.ply", "keyframes.tum"):
            assert (pathlib.Path(a.folder) / f).read_bytes() == (pathlib.Path(b.folder) / f).read_bytes()
    # The grid changed what ran: the step limit, and the threshold the config copy set.
    assert [r.figures["steps"] for r in result.runs] == [180, 224] * 4
    assert len({r.figures["icp_iterations"] for r in result.runs}) > 2
    # Nothing of the attempts is left behind.
    assert not list((tmp_path / "dask" / "runs").glob(".*"))


def test_killed_worker_still_gives_every_result_as_serial(tmp_path, cli, cluster, serial_runs):
    killed_worker_run(tmp_path, cli, cluster, serial_runs)


def test_killed_worker_given_up_by_dask_is_sent_again(tmp_path, cli, serial_runs):
    # allowed-failures 0: the scheduler does not reschedule the dead worker's
    # task but fails it (KilledWorker); rove.batch submits it again itself.
    distributed = pytest.importorskip("distributed")
    import dask
    import logging
    with dask.config.set({"distributed.scheduler.allowed-failures": 0}):
        with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                                      dashboard_address=":0", silence_logs=logging.CRITICAL) as c, \
                distributed.Client(c) as client:
            killed_worker_run(tmp_path, cli, client, serial_runs)


def test_table_holds_each_runs_parameters_and_figures(tmp_path, cli, cluster):
    result = batch.run(COMMAND, [TELECOM], ["ICP.thresholdDist=0.6,0.9", "max-steps=120"],
                       config=ICP_SLAM_INI, out=tmp_path, client=cluster, rove=cli)
    rows = read_csv(tmp_path / "runs.csv")
    assert [r["name"] for r in rows] == [r.name for r in result.runs]
    assert list(rows[0])[:5] == ["index", "name", "input", "param.ICP.thresholdDist", "param.max-steps"]
    doc = json.loads((tmp_path / "runs.json").read_text())
    assert doc["runs"] == 2 and doc["ok"] == 2 and doc["failed"] == 0
    assert doc["params"] == {"ICP.thresholdDist": [0.6, 0.9], "max-steps": [120]}
    for row, value in zip(rows, (0.6, 0.9)):
        folder = pathlib.Path(tmp_path / "runs" / row["name"])
        summary = json.loads((folder / "summary.json").read_text())
        assert float(row["param.ICP.thresholdDist"]) == value and row["param.max-steps"] == "120"
        assert row["status"] == "ok" and row["exit_status"] == "0" and row["error"] == ""
        assert row["input"] == str(TELECOM) and int(row["attempts"]) == 1
        assert int(row["steps"]) == summary["steps"] == 120
        assert float(row["final_pose.x"]) == summary["final_pose"]["x"]
        assert int(row["icp_accepted"]) == summary["icp_accepted"]
        assert float(row["wall_seconds"]) > 0
        # The job's CPU time (a child process) is counted, and within its wall time.
        assert 0 < float(row["cpu_seconds"]) <= float(row["wall_seconds"]) * 1.05
        # The run's config is the original with its value set, and the run used it.
        config = (folder / "config.ini").read_text()
        assert config.startswith(ICP_SLAM_INI.read_text().rstrip("\n"))
        assert config.rstrip().endswith(f"[ICP]\nthresholdDist = {value}")
        run_json = json.loads((folder / "run.json").read_text())
        assert run_json["status"] == "ok" and "--max-steps=120" in run_json["command"]
        assert {f.name for f in folder.iterdir()} >= {"path.tum", "summary.json", "run.json", "config.ini"}
    # The same run made by hand with that config gives the same figures.
    handmade = tmp_path / "handmade"
    subprocess.run([cli, "icp-slam", tmp_path / "runs" / rows[1]["name"] / "config.ini", TELECOM,
                    "-o", handmade, "--max-steps", "120", "--no-progress"], check=True, capture_output=True)
    made = batch._flatten(json.loads((handmade / "summary.json").read_text()))
    made = {k: v for k, v in made.items() if k not in ("config", "rawlog")}
    assert deterministic(made) == deterministic(result.runs[1].figures)


def test_a_library_entry_point_runs_as_the_command_does(tmp_path, cli, cluster):
    params = {"ICP.thresholdDist": [0.6], "max_steps": [150]}
    # On the cluster: rove's compiled entry points travel to the workers by name.
    lib = batch.run(rove.icp_slam, [TELECOM], params, config=ICP_SLAM_INI, out=tmp_path / "lib",
                    client=cluster)
    cmd = batch.run(COMMAND, [TELECOM], {"ICP.thresholdDist": [0.6], "max-steps": [150]},
                    config=ICP_SLAM_INI, out=tmp_path / "cmd", serial=True, rove=cli)
    a, b = lib.runs[0], cmd.runs[0]
    assert a.status == b.status == "ok"
    for key in ("steps", "icp_accepted", "keyframes", "icp_iterations"):
        assert a.figures[key] == b.figures[key], key
    assert a.figures["final_pose.x"] == pytest.approx(b.figures["final_pose.x"], abs=1e-9)
    # The library run wrote its path as TUM: the same poses as the command's path.tum.
    import numpy as np
    pa = np.loadtxt(pathlib.Path(a.folder) / "path.tum")
    pb = np.loadtxt(pathlib.Path(b.folder) / "path.tum")
    assert pa.shape == pb.shape and np.allclose(pa[:, 1:3], pb[:, 1:3], atol=1e-6)


def test_a_python_function_as_the_job(tmp_path, cluster):
    def job(path, scale, out_dir):  # a closure: Dask pickles it by value
        size = pathlib.Path(path).stat().st_size
        (pathlib.Path(out_dir) / "note.txt").write_text(str(size))
        return {"bytes": size * scale, "issues": []}

    result = batch.run(job, [TELECOM, ICP_SLAM_INI], {"scale": [1, 2]}, out=tmp_path, client=cluster)
    sizes = [TELECOM.stat().st_size] * 2 + [ICP_SLAM_INI.stat().st_size] * 2
    assert [r.figures["bytes"] for r in result.runs] == [s * k for s, k in zip(sizes, [1, 2, 1, 2])]
    assert all(r.status == "ok" for r in result.runs)
    assert (pathlib.Path(result.runs[3].folder) / "note.txt").read_text() == str(sizes[3])

    def picky(path):
        if str(path).endswith(".ini"):
            raise ValueError(f"{path}: not a log")
        return {"ok": True}

    result = batch.run(picky, [TELECOM, ICP_SLAM_INI], None, out=tmp_path / "picky", client=cluster, retries=2)
    good, bad = result.runs
    assert good.status == "ok" and good.attempts == 1
    assert bad.status == "failed" and bad.attempts == 3 and bad.exit_status == 1
    assert bad.error == f"picky: ValueError: {ICP_SLAM_INI}: not a log"
    assert result.exit_status == 1


def test_eval_ate_against_a_reference(tmp_path, cli):
    ref = batch.run(COMMAND, [TELECOM], {"max-steps": [224]}, config=ICP_SLAM_INI,
                    out=tmp_path / "ref", serial=True, rove=cli).runs[0]
    gt = pathlib.Path(ref.folder) / "path.tum"
    res = batch.run(COMMAND, [TELECOM], {"ICP.thresholdDist": [0.3, 3.0]}, config=ICP_SLAM_INI,
                    out=tmp_path / "ev", serial=True, rove=cli, eval=f"ate={gt}")
    same, other = res.runs  # 0.3 is the config's own value: the reference itself
    assert same.eval["ate"]["translation_m.rmse"] == pytest.approx(0.0, abs=1e-6)
    assert other.eval["ate"]["translation_m.rmse"] > 1e-3
    assert same.eval["ate"]["pairs"] == 224
    row = read_csv(tmp_path / "ev" / "runs.csv")[1]
    assert float(row["eval.ate.translation_m.rmse"]) == other.eval["ate"]["translation_m.rmse"]


def test_a_failing_job_is_reported(tmp_path, cli, cluster):
    not_a_log = tmp_path / "notes.txt"
    not_a_log.write_text("no robot here\n")
    result = batch.run(COMMAND, [TELECOM, not_a_log], {"max-steps": [50]}, config=ICP_SLAM_INI,
                       out=tmp_path / "out", client=cluster, retries=1, rove=cli)
    good, bad = result.runs
    assert good.status == "ok" and good.figures["steps"] == 50
    assert bad.status == "failed" and bad.exit_status == 1 and bad.attempts == 2
    assert "notes.txt" in bad.error and bad.error.startswith("rove icp-slam: exit status 1")
    assert result.exit_status == 1
    rows = read_csv(tmp_path / "out" / "runs.csv")
    assert rows[1]["status"] == "failed" and rows[1]["error"] == bad.error and rows[1]["steps"] == ""
    assert json.loads((pathlib.Path(bad.folder) / "run.json").read_text())["status"] == "failed"
    assert "notes.txt" in (pathlib.Path(bad.folder) / "job.stderr.txt").read_text()

    # The command line: exit status 1, the failure named on stderr, the table written.
    proc = subprocess.run([cli, "batch", COMMAND, "-c", ICP_SLAM_INI, "-i", TELECOM, not_a_log,
                           "-p", "max-steps=50", "--workers", "2", "--retries", "0", "-o", tmp_path / "cli"],
                          capture_output=True, text=True)
    assert proc.returncode == 1, proc.stderr
    assert "2 runs" in proc.stdout and "1 ok" in proc.stdout and "1 failed" in proc.stdout
    assert "rove batch: failed: 0001-notes" in proc.stderr
    assert [r["status"] for r in read_csv(tmp_path / "cli" / "runs.csv")] == ["ok", "failed"]


def test_issues_exit_status(tmp_path, cli):
    # A threshold no ICP result passes: the command exits 3, the run is "issues".
    result = batch.run(COMMAND, [TELECOM], {"MappingApplication.minICPgoodnessToAccept": [1],
                                            "max-steps": [30]},
                       config=ICP_SLAM_INI, out=tmp_path, serial=True, rove=cli)
    run = result.runs[0]
    assert run.status == "issues" and run.exit_status == 3 and run.issues == ["no-icp-accepted"]
    assert result.exit_status == 3


@pytest.mark.parametrize("params, message", [
    (["thresholdDist"], "expected NAME=V1,V2"),
    (["ICP.thresholdDist="], "empty value"),
    (["ICP.thresholdDist=0.5,,1"], "empty value"),
    (["ICP.thresholdDist=0.5,0.5"], "repeated"),
    (["ICP.thresholdDist=1", "icp.THRESHOLDDIST=2"], "given twice"),
    (["9lives=1"], "not a parameter name"),
    (["NoSuchSection.key=1"], "section [NoSuchSection] is not in"),
    ({"ICP.thresholdDist": []}, "no values"),
    ({"ICP.thresholdDist": [float("nan")]}, "not finite"),
])
def test_bad_grid_is_refused(tmp_path, params, message, cli):
    with pytest.raises(batch.BatchError, match=message.replace("[", r"\[").replace("]", r"\]")):
        batch.run(COMMAND, [TELECOM], params, config=ICP_SLAM_INI, out=tmp_path, serial=True, rove=cli)
    assert not (tmp_path / "runs").exists()


@pytest.mark.parametrize("command, kwargs, message", [
    ("icp-slam {config} {input}", {}, "must write into {out}"),
    ("icp-slam {config} {input} -o {out} --x {typo}", {}, "uses {typo}"),
    ("icp-slam {input} -o {out}", {}, "has no {config}"),
    (COMMAND, {"inputs": ["/no/such/dir/*.rawlog"]}, "matches no file"),
    (COMMAND, {"params": ["ICP.thresholdDist=1"], "config": None}, "no config was given"),
])
def test_bad_batch_is_refused(tmp_path, command, kwargs, message, cli):
    args = dict(inputs=[TELECOM], params=None, config=ICP_SLAM_INI)
    args.update(kwargs)
    with pytest.raises(batch.BatchError, match=message.replace("{", r"\{").replace("}", r"\}")):
        batch.run(command, args["inputs"], args["params"], config=args["config"], out=tmp_path,
                  serial=True, rove=cli)


def test_cli_refuses_a_bad_grid(tmp_path, cli):
    proc = subprocess.run([cli, "batch", COMMAND, "-c", ICP_SLAM_INI, "-i", TELECOM,
                           "-p", "ICP.thresholdDist=0.5,,1", "-o", tmp_path], capture_output=True, text=True)
    assert proc.returncode == 1
    assert proc.stderr.strip() == ("rove batch: error: --param 'ICP.thresholdDist=0.5,,1': "
                                   "empty value in the list '0.5,,1'")
    proc = subprocess.run([cli, "batch", "--no-such-flag"], capture_output=True, text=True)
    assert proc.returncode == 2 and "usage: rove batch" in proc.stderr


def test_parse_param_types():
    assert batch.parse_param("ICP.thresholdDist=0.5,1,2e-1") == ("ICP.thresholdDist", [0.5, 1, 0.2])
    assert batch.parse_param("method=icp, gicp") == ("method", ["icp", "gicp"])
    assert batch.parse_grid({"seed": 3}) == {"seed": [3]}


@pytest.mark.datasets
def test_relations_on_aces(tmp_path, cli):
    # The first 1,500 of ACES's 7,374 scans (the whole log, whose figures
    # docs/eval.md gives, takes minutes under the sanitizers; bench/ runs it):
    # the run's relation figures are those `rove eval relations` gives for its path.
    aces = dataset("radish/aces.clf.bz2")
    relations = dataset("radish/aces.relations")
    result = batch.run("icp-slam {config} {input} -o {out} --no-progress --max-range 50 --max-steps 1500",
                       [aces], None, config=pathlib.Path(ICP_SLAM_INI).parents[1] / "icp-slam_carmen.ini",
                       out=tmp_path, serial=True, rove=cli, eval="relations")
    run = result.runs[0]
    e = run.eval["relations"]
    _, out = run_cli("eval", "relations", "--log", aces, pathlib.Path(run.folder) / "path.tum", relations,
                     "--json", expect=(0, 3))
    direct = json.loads(out)
    assert e["used"] == direct["used"] == 210  # of 1,279: the rest lie beyond the run
    assert e["translation_m.mean"] == direct["translation_m"]["mean"] < 0.1
    assert e["rotation_rad.std"] == direct["rotation_rad"]["std"]


def test_jobs_do_not_inherit_the_environment_dask_sets_for_its_workers(tmp_path, cluster):
    # Regression: Dask's nanny sets MALLOC_TRIM_THRESHOLD_=65536 in its
    # workers; inherited, it made icp-slam on ACES take 3.4 times its CPU time.
    on_worker = cluster.run(lambda: os.environ.get("MALLOC_TRIM_THRESHOLD_"))
    assert set(on_worker.values()) == {"65536"}
    result = batch.run("-c 'env > {out}/env.txt'", None, None, out=tmp_path, client=cluster,
                       rove="/bin/sh")
    env = dict(line.split("=", 1) for line in
               (pathlib.Path(result.runs[0].folder) / "env.txt").read_text().splitlines() if "=" in line)
    assert "MALLOC_TRIM_THRESHOLD_" not in env and "OMP_NUM_THREADS" not in env
    assert env.get("PATH") == os.environ.get("PATH")


def test_a_cluster_started_with_dasks_command_line(tmp_path, cli):
    """docs/batch.md's real-cluster recipe on one machine: `dask scheduler`,
    `dask worker ... --nthreads 1`, and `rove batch --scheduler ADDR`."""
    import shutil
    import sys
    import time
    dask_cli = shutil.which("dask")
    if dask_cli is None:
        pytest.skip("Dask's command line is not installed (python3-distributed)")
    info = tmp_path / "scheduler.json"
    procs = [subprocess.Popen([sys.executable, dask_cli, "scheduler", "--port", "0", "--no-dashboard",
                               "--scheduler-file", info], stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)]
    try:
        procs.append(subprocess.Popen([sys.executable, dask_cli, "worker", "--scheduler-file", info,
                                       "--nworkers", "2", "--nthreads", "1", "--no-dashboard"],
                                      stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL))
        deadline = time.monotonic() + 60
        while not info.is_file() and time.monotonic() < deadline:
            time.sleep(0.1)
        address = json.loads(info.read_text())["address"]
        args = [COMMAND, "-c", ICP_SLAM_INI, "-i", TELECOM, "-p", "ICP.thresholdDist=0.5,1.0",
                "-p", "max-steps=80"]
        proc = subprocess.run([cli, "batch", *args, "--scheduler", address, "-o", tmp_path / "cluster"],
                              capture_output=True, text=True, timeout=300)
        assert proc.returncode == 0, proc.stderr
        ref = subprocess.run([cli, "batch", *args, "--serial", "-o", tmp_path / "serial"],
                             capture_output=True, text=True, timeout=300)
        assert ref.returncode == 0, ref.stderr
    finally:
        for p in reversed(procs):
            p.terminate()
        for p in reversed(procs):
            try:
                p.wait(timeout=30)
            except subprocess.TimeoutExpired:
                p.kill()
    cluster_doc = json.loads((tmp_path / "cluster" / "runs.json").read_text())
    serial_doc = json.loads((tmp_path / "serial" / "runs.json").read_text())
    assert cluster_doc["scheduler"] == address and cluster_doc["ok"] == 2
    for a, b in zip(cluster_doc["rows"], serial_doc["rows"]):
        assert deterministic(a["figures"]) == deterministic(b["figures"]) and a["figures"]["steps"] == 80
        assert int(a["worker"].split(":")[1]) not in (os.getpid(), procs[0].pid)


def test_ctrl_c_stops_with_the_table_of_finished_runs(tmp_path, cli):
    import time
    out = tmp_path / "out"
    proc = subprocess.Popen([cli, "batch", "-p", "t=0,60", "--serial", "--rove", "/bin/sh", "-o", out,
                             "--", "-c 'sleep {t}; echo done > {out}/x.txt'"],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    deadline = time.monotonic() + 60
    while time.monotonic() < deadline and not (out / "runs.csv").is_file():
        time.sleep(0.05)
    time.sleep(0.5)  # the second run is sleeping
    proc.send_signal(signal.SIGINT)
    stdout, stderr = proc.communicate(timeout=30)
    assert proc.returncode == 130, stderr
    assert "stopped (Ctrl-C)" in stderr and "[1/2] 0000-t=0: ok" in stdout
    rows = read_csv(out / "runs.csv")
    assert [(r["name"], r["status"]) for r in rows] == [("0000-t=0", "ok")]
    # The job's own child (sleep) was ended with it.
    assert not running("sleep", "60")
    assert not (out / "runs" / "0001-t=60" / "run.json").exists() or \
        json.loads((out / "runs" / "0001-t=60" / "run.json").read_text())["status"] == "failed"


def test_timeout_fails_the_run(tmp_path):
    result = batch.run("-c 'sleep {t} && touch {out}/done'", None, {"t": [0, 30]}, out=tmp_path,
                       serial=True, retries=0, timeout=1.0, rove="/bin/sh")
    fast, slow = result.runs
    assert fast.status == "ok" and (pathlib.Path(fast.folder) / "done").is_file()
    assert slow.status == "failed" and slow.error == "sh -c: stopped after the timeout of 1.0 s"
    assert slow.wall_seconds < 10 and not (pathlib.Path(slow.folder) / "done").exists()
    assert not running("sleep", "30")
