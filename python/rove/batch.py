"""rove.batch: one rove job over many inputs and a parameter grid, on a Dask
cluster.

A job is a `rove` command line with placeholders (``"icp-slam {config}
{input} -o {out}"``) or a Python callable (a library entry point such as
``rove.icp_slam``). Every combination of an input and the grid's values is a
run; the runs are Dask tasks on a ``LocalCluster`` (by default) or on the
cluster whose scheduler address is given. Results stream back as they
finish; a failed run is retried (Dask's ``retries=``), and a run whose worker
died is computed again. Each run writes into its own folder
``OUT/runs/NNNN-name/`` and ends with ``run.json``; the table of all runs
(inputs, parameters, status, figures read from each run's ``summary.json``
and from the optional ``rove eval`` step, wall time, errors) is written as
``OUT/runs.csv`` and ``OUT/runs.json``, each file under a temporary name and
renamed when complete. ``rove batch`` (or ``python3 -m rove.batch``) is the
command line. See docs/batch.md.
"""

from __future__ import annotations

import argparse
import csv
import ctypes
import glob as globlib
import inspect
import io
import itertools
import json
import logging
import math
import os
import pathlib
import re
import resource
import shlex
import shutil
import signal
import socket
import subprocess
import sys
import time
from typing import Any, Callable, Iterable, Mapping, Optional, Sequence, Union

__all__ = ["BatchError", "RunFailed", "Run", "BatchResult", "Eval", "parse_param", "parse_grid",
           "expand_inputs", "find_rove", "plan", "execute", "write_table", "run", "main"]

# Exit statuses of the rove command line (README, "What rove tells you").
_EXIT_OK, _EXIT_ISSUES = 0, 3


class BatchError(ValueError):
    """A batch that cannot start: a bad parameter grid, template, input list
    or option. The message names the offending argument."""


class RunFailed(RuntimeError):
    """One run's job failed (raised on the worker, so that Dask retries it);
    the message holds the exit status and the end of the job's stderr."""


# ------------------------------------------------------------------ the grid

_NAME = re.compile(r"^[A-Za-z_][A-Za-z0-9_-]*(\.[A-Za-z_][A-Za-z0-9_.-]*)?$")


def _scalar(text: str) -> Union[int, float, str]:
    """A grid value as typed: int, float, else the text."""
    for kind in (int, float):
        try:
            value = kind(text)
        except ValueError:
            continue
        if kind is float and not math.isfinite(value):
            return text
        return value
    return text


def parse_param(spec: str) -> tuple[str, list]:
    """``"ICP.thresholdDist=0.5,0.75,1"`` -> ("ICP.thresholdDist", [0.5, 0.75, 1]).

    A name with a dot is a config key (``SECTION.key``); one without is a
    template placeholder or, if the template has none of that name, a
    command-line option (``seed=1,2`` adds ``--seed 1``). Raises BatchError."""
    if not isinstance(spec, str) or "=" not in spec:
        raise BatchError(f"--param {spec!r}: expected NAME=V1,V2,... (e.g. ICP.thresholdDist=0.5,0.75)")
    name, _, values = spec.partition("=")
    name = name.strip()
    if not _NAME.match(name):
        raise BatchError(f"--param {spec!r}: '{name}' is not a parameter name "
                         "(SECTION.key for a config key, or a name of letters, digits, '_' and '-')")
    items = [v.strip() for v in values.split(",")]
    if not values.strip() or any(v == "" for v in items):
        raise BatchError(f"--param {spec!r}: empty value in the list '{values}'")
    if len(set(items)) != len(items):
        raise BatchError(f"--param {spec!r}: a value is repeated")
    return name, [_scalar(v) for v in items]


def parse_grid(params: Union[None, Mapping[str, Sequence], Sequence[str]]) -> dict[str, list]:
    """A parameter grid from ``{"ICP.thresholdDist": [0.5, 1.0]}`` or from
    ``["ICP.thresholdDist=0.5,1.0", ...]``, checked: names well formed and
    not repeated (config keys compared without case, as rove's INI reader
    does), each list non-empty and finite. Raises BatchError."""
    if params is None:
        return {}
    if isinstance(params, str):
        params = [params]
    pairs = []
    if isinstance(params, Mapping):
        for name, values in params.items():
            if not isinstance(name, str) or not _NAME.match(name):
                raise BatchError(f"parameter {name!r}: not a parameter name (SECTION.key or a plain name)")
            if isinstance(values, (str, bytes)) or not isinstance(values, Iterable):
                values = [values]
            values = list(values)
            if not values:
                raise BatchError(f"parameter '{name}': no values")
            for v in values:
                if isinstance(v, float) and not math.isfinite(v):
                    raise BatchError(f"parameter '{name}': value {v} is not finite")
                if not isinstance(v, (bool, int, float, str)):
                    raise BatchError(f"parameter '{name}': value {v!r} is not a number, bool or string")
            pairs.append((name, values))
    else:
        pairs = [parse_param(p) for p in params]
    grid: dict[str, list] = {}
    seen: dict[str, str] = {}
    for name, values in pairs:
        key = name.lower() if "." in name else name
        if key in seen:
            raise BatchError(f"parameter '{name}' is given twice (as '{seen[key]}' before)")
        seen[key] = name
        grid[name] = values
    return grid


def _combinations(grid: Mapping[str, list]) -> list[dict]:
    names = list(grid)
    return [dict(zip(names, combo)) for combo in itertools.product(*(grid[n] for n in names))]


def expand_inputs(inputs: Union[None, str, os.PathLike, Iterable]) -> list[pathlib.Path]:
    """Input files from paths and glob patterns (``*``, ``?``, ``[...]``,
    ``**``), absolute, in the order given (each pattern's matches sorted).
    A pattern that matches nothing or a path that is not a file is a
    BatchError; a file named twice runs once."""
    if inputs is None:
        return []
    if isinstance(inputs, (str, os.PathLike)):
        inputs = [inputs]
    out: list[pathlib.Path] = []
    for item in inputs:
        text = os.fspath(item)
        if globlib.has_magic(text):
            matches = sorted(m for m in globlib.glob(text, recursive=True) if os.path.isfile(m))
            if not matches:
                raise BatchError(f"input pattern '{text}' matches no file")
        else:
            if not os.path.isfile(text):
                raise BatchError(f"input '{text}': no such file" if not os.path.exists(text)
                                 else f"input '{text}': not a regular file")
            matches = [text]
        for m in matches:
            p = pathlib.Path(m).resolve()
            if p not in out:
                out.append(p)
    return out


# ------------------------------------------------------------ the rove binary

def find_rove(explicit: Optional[Union[str, os.PathLike]] = None) -> str:
    """The `rove` executable the command jobs run: `explicit`, else the
    ROVE_CLI environment variable, else the one built beside this package
    (<build>/apps/rove for <build>/python/rove), else `rove` on PATH.
    Raises BatchError naming what was tried."""
    tried = []
    candidates = []
    if explicit:
        candidates.append(("the rove= argument", os.fspath(explicit)))
    elif os.environ.get("ROVE_CLI"):
        candidates.append(("ROVE_CLI", os.environ["ROVE_CLI"]))
    else:
        here = pathlib.Path(__file__).resolve().parent
        candidates.append(("the build tree", str(here.parents[1] / "apps" / "rove")))
        on_path = shutil.which("rove")
        if on_path:
            candidates.append(("PATH", on_path))
    for origin, path in candidates:
        if os.path.isfile(path) and os.access(path, os.X_OK):
            return os.path.abspath(path)
        tried.append(f"{path} ({origin})")
    raise BatchError("cannot find the rove command line; tried " + (", ".join(tried) or "PATH") +
                     "; pass rove=PATH (--rove) or set ROVE_CLI")


# ------------------------------------------------------------------ the runs

class Eval:
    """A `rove eval` step after each run, on the run's trajectory file.

    ``Eval("relations")`` takes, for each input ``X.clf.bz2`` (or ``X.log``,
    ...), the Freiburg relations file ``X.relations`` beside it (inputs without
    one get no evaluation, and the table says so); ``Eval("relations",
    "aces.relations")`` uses that file for every input; ``Eval("ate",
    "groundtruth.tum")`` or ``Eval("rpe", ...)`` compare against a reference
    trajectory. `trajectory` is the file of the run folder evaluated."""

    KINDS = ("relations", "ate", "rpe")

    def __init__(self, kind: str, reference: Optional[Union[str, os.PathLike]] = None,
                 trajectory: str = "path.tum") -> None:
        if kind not in self.KINDS:
            raise BatchError(f"eval '{kind}': unknown kind (known: {', '.join(self.KINDS)})")
        if reference is None and kind != "relations":
            raise BatchError(f"eval '{kind}' needs a reference trajectory ({kind}=FILE)")
        if reference is not None:
            if not os.path.isfile(reference):
                raise BatchError(f"eval {kind}: reference '{os.fspath(reference)}' is not a file")
            reference = os.path.abspath(reference)
        if not trajectory or "/" in trajectory:
            raise BatchError(f"eval: trajectory '{trajectory}' must be a file name in the run folder")
        self.kind, self.reference, self.trajectory = kind, reference, trajectory

    @classmethod
    def parse(cls, spec: str, trajectory: str = "path.tum") -> "Eval":
        """``relations``, ``relations=FILE``, ``ate=FILE``, ``rpe=FILE``."""
        kind, _, ref = spec.partition("=")
        return cls(kind.strip(), ref.strip() or None, trajectory)

    def reference_for(self, input_path: Optional[str]) -> Optional[str]:
        if self.reference is not None:
            return self.reference
        if input_path is None:
            return None
        name = pathlib.Path(input_path).name
        stem = name.split(".")[0]
        cand = pathlib.Path(input_path).with_name(stem + ".relations")
        return str(cand) if cand.is_file() else None

    def __repr__(self) -> str:
        return f"Eval({self.kind!r}, {self.reference!r}, trajectory={self.trajectory!r})"


class Run(dict):
    """One row of the table: ``name``, ``index``, ``input``, ``params``,
    ``status`` (``ok``, ``issues`` for exit status 3, ``failed``), ``exit_status``,
    ``attempts``, ``wall_seconds``, ``cpu_seconds`` (the job's processes and,
    for a Python job, the calling thread), ``worker``, ``folder``, ``figures`` (from
    summary.json, flattened with dots), ``eval`` (``rove eval``'s figures),
    ``issues`` (codes) and ``error``. A dict, so it pickles and dumps as JSON."""

    def __getattr__(self, key):
        try:
            return self[key]
        except KeyError:
            raise AttributeError(key) from None


class BatchResult:
    """What a batch did: the runs in input/grid order, the table's files and
    the exit status `rove batch` reports (0 all ok, 3 some ran with issues,
    1 some failed)."""

    def __init__(self, runs: list[Run], csv_path: pathlib.Path, json_path: pathlib.Path,
                 wall_seconds: float) -> None:
        self.runs, self.csv_path, self.json_path, self.wall_seconds = runs, csv_path, json_path, wall_seconds

    @property
    def failed(self) -> list[Run]:
        return [r for r in self.runs if r["status"] == "failed"]

    @property
    def exit_status(self) -> int:
        if self.failed:
            return 1
        return 3 if any(r["status"] == "issues" for r in self.runs) else 0

    def __repr__(self) -> str:
        counts = {s: sum(r["status"] == s for r in self.runs) for s in ("ok", "issues", "failed")}
        return (f"BatchResult({len(self.runs)} runs: {counts['ok']} ok, {counts['issues']} with issues, "
                f"{counts['failed']} failed; {self.wall_seconds:.1f} s; table {self.csv_path})")


_PLACEHOLDER = re.compile(r"\{([A-Za-z_][A-Za-z0-9_.-]*)\}")
_RESERVED = ("input", "out", "config", "name")


def _slug(text: str, limit: int = 60) -> str:
    s = re.sub(r"[^A-Za-z0-9._=-]+", "_", text).strip("._")
    return s[:limit] or "run"


def _value_text(v: Any) -> str:
    if isinstance(v, bool):
        return "true" if v else "false"
    return str(v)


def plan(job: Union[str, Callable], inputs: Any = None, params: Any = None, *,
         out: Union[str, os.PathLike], config: Optional[Union[str, os.PathLike]] = None,
         eval: Optional[Union[Eval, str, Sequence[Union[Eval, str]]]] = None,
         rove: Optional[Union[str, os.PathLike]] = None, timeout: Optional[float] = None) -> list[dict]:
    """The runs a batch would make, checked before anything starts: one task
    description (a plain dict) per input × grid combination. Raises
    BatchError for a bad template, grid, input list, config or eval."""
    grid = parse_grid(params)
    files = expand_inputs(inputs)
    out_dir = pathlib.Path(out).resolve()
    config_path = None
    if config is not None:
        if not os.path.isfile(config):
            raise BatchError(f"config '{os.fspath(config)}': no such file")
        config_path = str(pathlib.Path(config).resolve())
    config_keys = [n for n in grid if "." in n]
    if config_keys:
        if config_path is None and isinstance(job, str):
            raise BatchError(f"parameter '{config_keys[0]}' is a config key (SECTION.key) but no "
                             "config was given (--config FILE, and {config} in the command)")
        if config_path is not None:
            sections = _ini_sections(config_path)
            for n in config_keys:
                section = n.split(".", 1)[0]
                if section.lower() not in sections:
                    raise BatchError(f"parameter '{n}': section [{section}] is not in {config_path} "
                                     f"(sections: {', '.join(sorted(sections.values())) or 'none'})")
    evals = _evals(eval)
    spec: dict[str, Any] = {"out_dir": str(out_dir), "config": config_path, "timeout": timeout,
                            "evals": evals}
    if evals or isinstance(job, str):
        spec["rove"] = find_rove(rove)
    if isinstance(job, str):
        argv = shlex.split(job)
        if argv and os.path.basename(argv[0]) == "rove":
            argv = argv[1:]
        if not argv:
            raise BatchError("the command is empty (e.g. \"icp-slam {config} {input} -o {out}\")")
        used = {m for a in argv for m in _PLACEHOLDER.findall(a)}
        unknown = used - set(_RESERVED) - set(grid)
        if unknown:
            raise BatchError(f"the command uses {{{sorted(unknown)[0]}}}, which is neither "
                             f"{', '.join('{' + r + '}' for r in _RESERVED)} nor a --param name")
        if "out" not in used:
            raise BatchError("the command must write into {out} (each run's own folder), e.g. -o {out}")
        if files and "input" not in used:
            raise BatchError("inputs were given but the command has no {input}")
        if "input" in used and not files:
            raise BatchError("the command uses {input} but no input was given (--inputs)")
        if config_path is not None and "config" not in used:
            raise BatchError("a config was given but the command has no {config}")
        if "config" in used and config_path is None:
            raise BatchError("the command uses {config} but no config was given (--config FILE)")
        for n in grid:
            if n in _RESERVED:
                raise BatchError(f"parameter '{n}' has the name of a placeholder the batch sets")
        spec["kind"] = "command"
        spec["argv"] = argv
    elif callable(job):
        spec["kind"] = "callable"
        spec["callable"] = _job_reference(job)
        if not files:
            raise BatchError("a Python job needs inputs (it is called as job(input, **params))")
    else:
        raise BatchError(f"job must be a command line (str) or a callable, not {type(job).__name__}")

    runs = []
    combos = _combinations(grid)
    for i, (f, combo) in enumerate(itertools.product(files or [None], combos)):
        label = ([pathlib.Path(f).name.split(".")[0][:32]] if f else []) + \
            [f"{n.split('.')[-1]}={_value_text(v)}" for n, v in combo.items()]
        name = f"{i:04d}-" + _slug("_".join(label) or "run", 96)
        runs.append(dict(spec, index=i, name=name, input=str(f) if f else None, params=combo,
                         folder=str(out_dir / "runs" / name)))
    return runs


def _job_reference(fn: Callable) -> Any:
    """What travels to the workers for a Python job: "module:name" for a
    function importable by name (rove's entry points are compiled functions,
    which pickle cannot send), else the callable itself (pickled by Dask)."""
    module, name = getattr(fn, "__module__", None), getattr(fn, "__name__", None)
    if module and name:
        try:
            if getattr(__import__(module, fromlist=[name]), name) is fn:
                return f"{module}:{name}"
        except (ImportError, AttributeError):
            pass
    return fn


def _resolve_job(ref: Any) -> Callable:
    if isinstance(ref, str):
        module, _, name = ref.partition(":")
        return getattr(__import__(module, fromlist=[name]), name)
    return ref


def _evals(spec) -> list[Eval]:
    if spec is None:
        return []
    if isinstance(spec, (str, Eval)):
        spec = [spec]
    return [e if isinstance(e, Eval) else Eval.parse(e) for e in spec]


def _ini_sections(path: str) -> dict[str, str]:
    """Section names of an INI file, lower case -> as written."""
    sections = {"": ""}
    try:
        text = pathlib.Path(path).read_text(errors="replace")
    except OSError as e:
        raise BatchError(f"config '{path}': {e.strerror}") from None
    for line in text.splitlines():
        m = re.match(r"^\s*\[([^\]]*)\]", line)
        if m:
            name = m.group(1).strip()
            sections.setdefault(name.lower(), name)
    return sections


# ------------------------------------------------- one run, on the worker

def _write_atomic(path: pathlib.Path, text: str) -> None:
    tmp = path.with_name(f".{path.name}.tmp-{os.getpid()}")
    tmp.write_text(text)
    os.replace(tmp, path)


def _flatten(obj: Any, prefix: str = "") -> dict[str, Any]:
    """Scalars of a summary, nested keys joined by dots; lists and the
    `files` list are left out (the table keeps `issues` separately)."""
    out: dict[str, Any] = {}
    if isinstance(obj, Mapping):
        for k, v in obj.items():
            key = f"{prefix}{k}"
            if isinstance(v, Mapping):
                out.update(_flatten(v, key + "."))
            elif isinstance(v, (bool, int, float, str)) or v is None:
                out[key] = v
    return out


def _die_with_parent() -> None:
    """In the child before exec: SIGKILL when the worker that started it
    dies (Linux), so a killed worker leaves no job writing into a folder
    that its retry is writing too."""
    try:
        libc = ctypes.CDLL(None, use_errno=True)
        libc.prctl(1, signal.SIGKILL)  # PR_SET_PDEATHSIG
    except (OSError, AttributeError):
        pass


def _job_environment() -> dict[str, str]:
    """The environment of a job: this process's, less what is there for
    Python's sake only. A sanitizer runtime preloaded into the interpreter
    is not the job's; and Dask's nanny sets distributed.nanny.pre-spawn-environ
    in its workers (MALLOC_TRIM_THRESHOLD_=65536, OMP/MKL/OpenBLAS threads 1),
    which a job would inherit: with that malloc setting glibc returns memory
    to the system on nearly every free, and icp-slam on ACES takes 3.4 times
    its CPU time (45.8 s instead of 13.3 s)."""
    env = dict(os.environ)
    env.pop("LD_PRELOAD", None)
    try:
        from distributed import get_worker
        get_worker()
    except (ImportError, ValueError):
        return env  # not on a Dask worker
    try:
        import dask
        spawned = dask.config.get("distributed.nanny.pre-spawn-environ", {}) or {}
    except ImportError:
        spawned = {}
    for key, value in spawned.items():
        if env.get(key) == str(value):
            del env[key]
    return env


def _run_process(argv: list[str], folder: pathlib.Path, timeout: Optional[float],
                 log_name: str) -> tuple[int, str]:
    """Runs argv; its stdout and stderr go to files in `folder`. Returns the
    exit status (negative: killed by that signal) and the stderr text."""
    env = _job_environment()
    out_path, err_path = folder / f"{log_name}.stdout.txt", folder / f"{log_name}.stderr.txt"
    with open(out_path, "wb") as out, open(err_path, "wb") as err:
        # Its own process group (in this session), so that a timeout or
        # Ctrl-C ends the job's own children too.
        try:
            proc = subprocess.Popen(argv, stdout=out, stderr=err, stdin=subprocess.DEVNULL, env=env,
                                    preexec_fn=_die_with_parent, process_group=0)
        except OSError as e:
            raise RunFailed(f"cannot start {argv[0]}: {e.strerror}") from None
        try:
            code = proc.wait(timeout=timeout)
        except subprocess.TimeoutExpired:
            code = None
        except BaseException:
            _kill_group(proc)
            raise
        if code is None:
            _kill_group(proc)
    stderr = err_path.read_text(errors="replace")
    if code is None:
        what = " ".join([os.path.basename(argv[0])] + argv[1:2])
        raise RunFailed(f"{what}: stopped after the timeout of {timeout} s")
    return code, stderr


def _kill_group(proc: subprocess.Popen) -> None:
    try:
        os.killpg(proc.pid, signal.SIGKILL)
    except OSError:
        pass
    proc.wait()


def _failure_message(what: str, code: int, stderr: str) -> str:
    how = f"killed by signal {-code}" if code < 0 else f"exit status {code}"
    lines = [ln for ln in stderr.replace("\r", "\n").splitlines() if ln.strip()]
    tail = [ln for ln in lines if "error" in ln.lower()][-3:] or lines[-3:]
    return f"{what}: {how}" + (": " + " | ".join(t.strip() for t in tail) if tail else "")


def _attempt_number(folder: pathlib.Path) -> int:
    """Counts this run's attempts in a file beside its folder (on the shared
    storage, so attempts on any machine count)."""
    tries = folder.with_name(f".{folder.name}.attempts")
    with open(tries, "a") as f:
        f.write(f"{socket.gethostname()} {os.getpid()}\n")
    with open(tries) as f:
        return sum(1 for _ in f)


def _config_with(config: str, overrides: Mapping[str, Any], folder: pathlib.Path) -> str:
    """The run's copy of the config with its keys set: the original text and
    a section per key at the end (rove's INI reader merges a repeated
    section, and a repeated key takes its last value)."""
    text = pathlib.Path(config).read_text(errors="surrogateescape")
    lines = [text.rstrip("\n"), "", f"// rove batch: this run's parameters (original: {config})"]
    for name, value in overrides.items():
        section, key = name.split(".", 1)
        lines += [f"[{section}]", f"{key} = {_value_text(value)}"]
    path = folder / "config.ini"
    _write_atomic(path, "\n".join(lines) + "\n")
    return str(path)


def _command_argv(task: Mapping[str, Any], folder: pathlib.Path, config: Optional[str]) -> list[str]:
    values = {"input": task["input"], "out": str(folder), "config": config, "name": task["name"]}
    values.update({n: _value_text(v) for n, v in task["params"].items() if "." not in n})
    argv = [task["rove"]]
    used = set()
    for arg in task["argv"]:
        def sub(m):
            used.add(m.group(1))
            return str(values[m.group(1)])
        argv.append(_PLACEHOLDER.sub(sub, arg))
    for n, v in task["params"].items():  # the others are options: --name=value
        if "." not in n and n not in used:
            argv += [f"--{n}={_value_text(v)}"] if len(n) > 1 else [f"-{n}", _value_text(v)]
    return argv


def _evaluate(task: Mapping[str, Any], folder: pathlib.Path, record: dict) -> None:
    for ev in task["evals"]:
        kind, key = ev.kind, ev.kind
        ref_file = ev.reference_for(task["input"])
        if ref_file is None:  # relations beside the input, and this input has none
            continue
        est = folder / ev.trajectory
        if not est.is_file():
            raise RunFailed(f"eval {kind}: the run wrote no {ev.trajectory}")
        argv = [task["rove"], "eval", kind]
        argv += [str(est), ref_file] if kind == "relations" else [ref_file, str(est)]
        if kind == "relations" and task["input"] and not task["input"].endswith((".g2o", ".graph")):
            argv += ["--log", task["input"]]
        argv.append("--json")
        code, stderr = _run_process(argv, folder, task["timeout"], f"eval-{kind}")
        if code not in (_EXIT_OK, _EXIT_ISSUES):
            raise RunFailed(_failure_message(f"rove eval {kind}", code, stderr))
        result = json.loads((folder / f"eval-{kind}.stdout.txt").read_text())
        figures = _flatten({k: v for k, v in result.items() if k not in ("estimate",)})
        figures = {k: v for k, v in figures.items() if v is not None and not isinstance(v, str)}
        record["eval"][key] = figures
        record["issues"] += [f"eval-{kind}:{i['code']}" for i in result.get("issues", [])]
        if code == _EXIT_ISSUES and record["status"] == "ok":
            record["status"] = "issues"


def _write_tum(path: pathlib.Path, times, poses) -> None:
    lines = []
    for t, (x, y, phi) in zip(times, poses):
        lines.append(f"{float(t):.9f} {x:.9g} {y:.9g} 0 0 0 {math.sin(phi / 2):.9g} {math.cos(phi / 2):.9g}")
    _write_atomic(path, "\n".join(lines) + ("\n" if lines else ""))


def _call_library(task: Mapping[str, Any], folder: pathlib.Path, record: dict) -> None:
    fn = _resolve_job(task["callable"])
    overrides: dict[str, dict] = {}
    kwargs: dict[str, Any] = {}
    for n, v in task["params"].items():
        if "." in n:
            section, key = n.split(".", 1)
            overrides.setdefault(section, {})[key] = v
        else:
            kwargs[n.replace("-", "_")] = v
    try:
        accepted = inspect.signature(fn).parameters
    except (TypeError, ValueError):  # a compiled function without a signature: pybind11 gives one
        accepted = {}
    if task["config"] is not None:
        kwargs["config"] = task["config"]
    if overrides:
        kwargs["overrides"] = overrides
    if "out_dir" in accepted:
        kwargs["out_dir"] = str(folder)
    try:
        result = fn(task["input"], **kwargs)
    except Exception as e:  # the job's own error, reported as the run's
        raise RunFailed(f"{getattr(fn, '__name__', 'job')}: {type(e).__name__}: {e}") from None
    summary = result.summary() if hasattr(result, "summary") else result
    if isinstance(summary, Mapping):
        summary = dict(summary)
    elif hasattr(summary, "__dict__"):
        summary = {k: v for k, v in vars(summary).items() if isinstance(v, (bool, int, float, str, dict))}
    else:
        summary = {"result": summary}
    _write_atomic(folder / "summary.json", json.dumps(summary, indent=2, default=str) + "\n")
    path, times = getattr(result, "path", None), getattr(result, "times", None)
    if path is not None and times is not None and getattr(path, "shape", (0, 0))[1:] == (3,):
        _write_tum(folder / "path.tum", times, path)
    issues = getattr(result, "issues", None) or summary.get("issues") or []
    record["issues"] = [i[0] if isinstance(i, (tuple, list)) else i.get("code", str(i))
                        if isinstance(i, Mapping) else str(i) for i in issues]
    record["figures"] = _flatten(summary)
    record["status"] = "issues" if record["issues"] else "ok"


def _cpu_seconds() -> float:
    """CPU time of the finished child processes of this process and of the
    calling thread. A run's share is exact when its worker runs one task at
    a time (one thread per worker, as rove.batch's local cluster does)."""
    children = resource.getrusage(resource.RUSAGE_CHILDREN)
    thread = resource.getrusage(getattr(resource, "RUSAGE_THREAD", resource.RUSAGE_SELF))
    return children.ru_utime + children.ru_stime + thread.ru_utime + thread.ru_stime


def execute(task: Mapping[str, Any]) -> Run:
    """Runs one task of plan() in its folder (what each Dask task calls).
    Returns the run's row; raises RunFailed when the job failed, after
    writing the folder's run.json and the job's logs."""
    folder = pathlib.Path(task["folder"])
    folder.parent.mkdir(parents=True, exist_ok=True)
    attempt = _attempt_number(folder)
    if folder.exists():  # what an earlier attempt left
        shutil.rmtree(folder)
    folder.mkdir()
    record = Run(name=task["name"], index=task["index"], input=task["input"], params=dict(task["params"]),
                 status="failed", exit_status=None, attempts=attempt, wall_seconds=None, cpu_seconds=None,
                 worker=f"{socket.gethostname()}:{os.getpid()}", folder=str(folder), figures={},
                 eval={}, issues=[], error="")
    start, cpu_start = time.perf_counter(), _cpu_seconds()
    try:
        overrides = {n: v for n, v in task["params"].items() if "." in n}
        if task["kind"] == "command":
            config = task["config"]
            if config is not None and overrides:
                config = _config_with(config, overrides, folder)
            argv = _command_argv(task, folder, config)
            record["command"] = shlex.join(argv)
            code, stderr = _run_process(argv, folder, task["timeout"], "job")
            record["exit_status"] = code
            if code not in (_EXIT_OK, _EXIT_ISSUES):
                raise RunFailed(_failure_message(f"rove {task['argv'][0]}", code, stderr))
            summary_path = folder / "summary.json"
            if summary_path.is_file():
                try:
                    summary = json.loads(summary_path.read_text())
                except ValueError as e:
                    raise RunFailed(f"{summary_path}: not JSON ({e})") from None
                record["figures"] = _flatten({k: v for k, v in summary.items()
                                              if k not in ("files", "config", "rawlog")})
                record["issues"] = [i.get("code", "") for i in summary.get("issues", [])
                                    if isinstance(i, Mapping)]
            record["status"] = "issues" if code == _EXIT_ISSUES else "ok"
        else:
            _call_library(task, folder, record)
            record["exit_status"] = _EXIT_ISSUES if record["status"] == "issues" else _EXIT_OK
        _evaluate(task, folder, record)
    except Exception as e:  # the job's failure, or one reading what it wrote (a full disk, ...)
        failure = e if isinstance(e, RunFailed) else RunFailed(f"{type(e).__name__}: {e}")
        record["status"], record["error"] = "failed", str(failure)
        if record["exit_status"] in (None, _EXIT_OK, _EXIT_ISSUES):
            record["exit_status"] = 1
        if failure is e:
            raise
        raise failure from None
    finally:
        record["wall_seconds"] = time.perf_counter() - start
        record["cpu_seconds"] = _cpu_seconds() - cpu_start
        _write_atomic(folder / "run.json", json.dumps(record, indent=2, default=str) + "\n")
    return record


# ------------------------------------------------------------- the table

_FIXED = ["index", "name", "input", "status", "exit_status", "attempts", "wall_seconds", "cpu_seconds",
          "worker", "error"]


def _columns(runs: Sequence[Run]) -> tuple[list[str], list[str], list[str]]:
    params, figures, evals = [], [], []
    for r in runs:
        for k in r["params"]:
            if k not in params:
                params.append(k)
        for k in r["figures"]:
            if k not in figures:
                figures.append(k)
        for kind, figs in r["eval"].items():
            for k in figs:
                if f"eval.{kind}.{k}" not in evals:
                    evals.append(f"eval.{kind}.{k}")
    return params, figures, evals


def _csv_value(v: Any) -> str:
    if v is None:
        return ""
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, float):
        return repr(v)
    return str(v)


def write_table(runs: Sequence[Run], out_dir: pathlib.Path, wall_seconds: float,
                header: Mapping[str, Any]) -> tuple[pathlib.Path, pathlib.Path]:
    """OUT/runs.csv (one row per run: the fixed columns, one per parameter
    `param.NAME`, per summary figure, per eval figure `eval.KIND.FIGURE`,
    and `issues`) and OUT/runs.json (the batch's settings and the rows as
    objects), each written under a temporary name then renamed."""
    runs = sorted(runs, key=lambda r: r["index"])
    params, figures, evals = _columns(runs)
    buf = io.StringIO()
    w = csv.writer(buf, lineterminator="\n")
    w.writerow(_FIXED[:3] + [f"param.{p}" for p in params] + _FIXED[3:] + figures + evals + ["issues"])
    for r in runs:
        row = [r[k] for k in _FIXED[:3]] + [r["params"].get(p) for p in params] + [r[k] for k in _FIXED[3:]]
        row += [r["figures"].get(f) for f in figures]
        for e in evals:
            kind, fig = e[len("eval."):].split(".", 1)
            row.append(r["eval"].get(kind, {}).get(fig))
        row.append(" ".join(r["issues"]))
        w.writerow([_csv_value(v) for v in row])
    out_dir.mkdir(parents=True, exist_ok=True)
    csv_path, json_path = out_dir / "runs.csv", out_dir / "runs.json"
    _write_atomic(csv_path, buf.getvalue())
    doc = dict(header, wall_seconds=wall_seconds, runs=len(runs),
               ok=sum(r["status"] == "ok" for r in runs),
               with_issues=sum(r["status"] == "issues" for r in runs),
               failed=sum(r["status"] == "failed" for r in runs), rows=list(runs))
    _write_atomic(json_path, json.dumps(doc, indent=2, default=str) + "\n")
    return csv_path, json_path


# ------------------------------------------------------------- the batch

def _failed_row(task: Mapping[str, Any], error: str) -> Run:
    """The row of a run whose last attempt did not return (its worker died
    too often, or the job raised): from the folder's run.json if the job
    wrote one, else from the task."""
    folder = pathlib.Path(task["folder"])
    try:
        row = Run(json.loads((folder / "run.json").read_text()))
        row["status"] = "failed"
        row["error"] = row.get("error") or error
        return row
    except (OSError, ValueError):
        pass
    tries = folder.with_name(f".{folder.name}.attempts")
    attempts = sum(1 for _ in open(tries)) if tries.is_file() else 0
    return Run(name=task["name"], index=task["index"], input=task["input"], params=dict(task["params"]),
               status="failed", exit_status=None, attempts=attempts, wall_seconds=None, cpu_seconds=None,
               worker="",
               folder=str(folder), figures={}, eval={}, issues=[], error=error)


def _error_text(exc: BaseException) -> str:
    if isinstance(exc, RunFailed):
        return str(exc)
    return f"{type(exc).__name__}: {exc}"


def run(job: Union[str, Callable], inputs: Any = None, params: Any = None, *,
        out: Union[str, os.PathLike], config: Optional[Union[str, os.PathLike]] = None,
        eval: Optional[Union[Eval, str, Sequence[Union[Eval, str]]]] = None,
        scheduler: Optional[str] = None, workers: Optional[int] = None, retries: int = 2,
        client: Any = None, serial: bool = False, rove: Optional[Union[str, os.PathLike]] = None,
        timeout: Optional[float] = None,
        on_result: Optional[Callable[[Run], None]] = None) -> BatchResult:
    """Runs `job` for every input × parameter combination and writes the table.

    job: a rove command line with placeholders {input}, {out} (the run's
      folder, required), {config} (the config with the run's SECTION.key
      values), {name} and {PARAM}; or a callable called as
      ``job(input, config=..., overrides={section: {key: v}}, **other_params)``
      (``out_dir=`` too if it takes one) returning an object with
      ``summary()`` or a dict.
    inputs: paths and glob patterns. params: ``{"ICP.thresholdDist": [0.5, 1]}``
      or ``["ICP.thresholdDist=0.5,1", "max-range=40,80"]``.
    eval: "relations", "relations=FILE", "ate=FILE", "rpe=FILE" or Eval objects.
    scheduler: a Dask scheduler address ("tcp://host:8786"); else `client`,
      else a LocalCluster of `workers` processes (default: the CPU count),
      one thread each. serial=True runs the jobs one after another here,
      without Dask (a reference, and the baseline of bench/batch_sweep.sh).
    retries: how many times a failed run is tried again (Dask's retries=),
      and how many times a run is sent again after Dask gave it up because
      its workers kept dying.
    on_result: called with each run's row as it finishes (in finishing order).
    """
    if not isinstance(retries, int) or retries < 0:
        raise BatchError(f"retries must be a count >= 0, not {retries!r}")
    if workers is not None and (not isinstance(workers, int) or workers < 1):
        raise BatchError(f"workers must be a count >= 1, not {workers!r}")
    tasks = plan(job, inputs, params, out=out, config=config, eval=eval, rove=rove, timeout=timeout)
    out_dir = pathlib.Path(out).resolve()
    (out_dir / "runs").mkdir(parents=True, exist_ok=True)
    for stale in (out_dir / "runs").glob(".*.attempts"):
        stale.unlink()
    header = {"job": job if isinstance(job, str) else getattr(job, "__qualname__", repr(job)),
              "config": tasks[0]["config"] if tasks else None,
              "params": {k: v for k, v in parse_grid(params).items()},
              "eval": [[e.kind, e.reference, e.trajectory] for e in (tasks[0]["evals"] if tasks else [])],
              "scheduler": "serial" if serial else (scheduler or ("client" if client else "local")),
              "retries": retries}
    start = time.perf_counter()
    rows: dict[int, Run] = {}

    def done(row: Run) -> None:
        rows[row["index"]] = row
        write_table(list(rows.values()), out_dir, time.perf_counter() - start, header)
        if on_result is not None:
            on_result(row)

    try:
        if serial:
            for task in tasks:
                for attempt in range(retries + 1):
                    try:
                        row = execute(task)
                        break
                    except RunFailed as e:
                        if attempt == retries:
                            row = _failed_row(task, str(e))
                done(row)
        else:
            _run_dask(tasks, scheduler, client, workers, retries, done)
    except KeyboardInterrupt:  # the table of the runs that finished, even if none did
        write_table(list(rows.values()), out_dir, time.perf_counter() - start, header)
        raise
    for stale in (out_dir / "runs").glob(".*.attempts"):
        stale.unlink()
    wall = time.perf_counter() - start
    runs = [rows[t["index"]] for t in tasks]
    csv_path, json_path = write_table(runs, out_dir, wall, header)
    return BatchResult(runs, csv_path, json_path, wall)


def _run_dask(tasks, scheduler, client, workers, retries, done) -> None:
    from distributed import Client, LocalCluster, as_completed

    own = []
    if client is None:
        if scheduler:
            client = Client(scheduler)
        else:
            n = workers or os.cpu_count() or 1
            # Warnings of failed tasks are the table's error column already.
            cluster = LocalCluster(n_workers=n, threads_per_worker=1, processes=True,
                                   dashboard_address=":0", silence_logs=logging.ERROR)
            own.append(cluster)
            client = Client(cluster)
        own.insert(0, client)
    try:
        by_key = {}
        resent = {}
        futures = []
        for task in tasks:
            f = client.submit(execute, task, retries=retries, pure=False, key=f"rove-batch-{task['name']}-0")
            by_key[f.key] = task
            futures.append(f)
        pending = as_completed(futures)
        for f in pending:
            task = by_key.pop(f.key)
            if f.status == "finished":
                done(f.result())
                continue
            try:
                exc = f.exception()
            except BaseException as e:  # cancelled: its worker or the scheduler went away
                exc = e
            if isinstance(exc, RunFailed):  # the job failed retries + 1 times
                done(_failed_row(task, _error_text(exc)))
                continue
            # Its workers died (KilledWorker) or the connection broke: send it again.
            n = resent.get(task["index"], 0)
            if n < retries:
                resent[task["index"]] = n + 1
                g = client.submit(execute, task, retries=retries, pure=False,
                                  key=f"rove-batch-{task['name']}-{n + 1}")
                by_key[g.key] = task
                pending.add(g)
            else:
                done(_failed_row(task, _error_text(exc)))
    finally:
        for obj in own:
            obj.close()


# ------------------------------------------------------------ command line

def _parser() -> argparse.ArgumentParser:
    p = argparse.ArgumentParser(
        prog="rove batch",
        description="Run a rove command over many inputs and a parameter grid on a Dask cluster "
                    "(a local one by default) and write a table of the runs (OUT/runs.csv, OUT/runs.json).",
        epilog="example: rove batch 'icp-slam {config} {input} -o {out} --no-progress' "
               "--config data/icp-slam_carmen.ini --inputs 'logs/*.clf.bz2' "
               "--param ICP.thresholdDist=0.5,0.75,1.0 --eval relations -o sweep/")
    p.add_argument("command", help="the rove command line, quoted, with {input}, {out} (required), "
                   "{config}, {name} and {PARAM} placeholders; 'rove' in front is optional")
    p.add_argument("-i", "--inputs", nargs="+", default=[], metavar="PATH",
                   help="input files or glob patterns (quote them); one run per input and grid point")
    p.add_argument("-p", "--param", action="append", default=[], metavar="NAME=V1,V2",
                   help="a grid axis: SECTION.key sets a config key in each run's copy of --config; "
                        "a NAME fills {NAME} in the command, or else adds --NAME V")
    p.add_argument("-c", "--config", help="the config file the command reads as {config}")
    p.add_argument("-e", "--eval", action="append", default=[], metavar="KIND[=FILE]",
                   help="rove eval after each run on its --trajectory: relations (X.relations beside "
                        "each input X.*), relations=FILE, ate=GT, rpe=GT")
    p.add_argument("--trajectory", default="path.tum", help="the run's file --eval reads (default path.tum)")
    p.add_argument("-o", "--output", required=True, help="output folder: runs/, runs.csv, runs.json")
    p.add_argument("--scheduler", help="address of a Dask scheduler (tcp://HOST:8786); "
                   "default: a local cluster")
    p.add_argument("--workers", type=int, help="workers of the local cluster (default: CPU count)")
    p.add_argument("--retries", type=int, default=2, help="tries again per failed run (default 2)")
    p.add_argument("--serial", action="store_true", help="run one job after another, without Dask")
    p.add_argument("--timeout", type=float, help="seconds after which a job is stopped (a failure)")
    p.add_argument("--rove", help="the rove executable (default: ROVE_CLI, the build tree, PATH)")
    p.add_argument("--json", action="store_true", help="print runs.json instead of the text report")
    return p


def _line(row: Run, total: int) -> str:
    figs = row["figures"]
    keys = [k for k in ("final_pose.x", "final_pose.y", "icp_accepted", "keyframes") if k in figs]
    for kind, e in row["eval"].items():
        if "translation_m.mean" in e:
            keys.append(f"eval.{kind}.translation_m.mean")
    shown = []
    for k in keys:
        v = figs.get(k) if not k.startswith("eval.") else row["eval"][k.split(".")[1]]["translation_m.mean"]
        shown.append(f"{k}={v:.4g}" if isinstance(v, float) else f"{k}={v}")
    wall = f"{row['wall_seconds']:.1f} s" if row["wall_seconds"] is not None else "-"
    tail = row["error"] if row["status"] == "failed" else " ".join(shown)
    return f"[{row['index'] + 1}/{total}] {row['name']}: {row['status']} ({wall}, attempt {row['attempts']}) {tail}"


def main(argv: Optional[Sequence[str]] = None) -> int:
    """`rove batch` / `python3 -m rove.batch`; returns the exit status (0 all
    runs ok, 3 some with issues, 1 some failed or the batch could not start,
    2 a bad command line)."""
    args = _parser().parse_args(argv)
    try:
        evals = [Eval.parse(e, args.trajectory) for e in args.eval]
        total = []

        def progress(row: Run) -> None:
            if not args.json:
                print(_line(row, len(total[0])), flush=True)

        total.append(plan(args.command, args.inputs, args.param, out=args.output, config=args.config,
                          eval=evals, rove=args.rove, timeout=args.timeout))
        result = run(args.command, args.inputs, args.param, out=args.output, config=args.config,
                     eval=evals, scheduler=args.scheduler, workers=args.workers, retries=args.retries,
                     serial=args.serial, rove=args.rove, timeout=args.timeout, on_result=progress)
    except BatchError as e:
        print(f"rove batch: error: {e}", file=sys.stderr)
        return 1
    except KeyboardInterrupt:
        print("rove batch: stopped (Ctrl-C); the table holds the runs finished so far", file=sys.stderr)
        return 130
    if args.json:
        sys.stdout.write(result.json_path.read_text())
    else:
        ok = sum(r["status"] == "ok" for r in result.runs)
        issues = sum(r["status"] == "issues" for r in result.runs)
        print(f"{len(result.runs)} runs in {result.wall_seconds:.1f} s: {ok} ok, {issues} with issues, "
              f"{len(result.failed)} failed; table: {result.csv_path} and {result.json_path}")
        for r in result.failed:
            print(f"rove batch: failed: {r['name']}: {r['error']}", file=sys.stderr)
    return result.exit_status


if __name__ == "__main__":
    sys.exit(main())
