# Type stubs of rove.batch (python/rove/batch.py); python/tests/test_package.py
# checks that they name exactly the module's public functions and classes,
# with the same parameters.
import os
import pathlib
from typing import Any, Callable, Iterable, Mapping, Optional, Sequence, Union

_Path = Union[str, os.PathLike[str]]
_Grid = Union[None, Mapping[str, Sequence[Any]], Sequence[str]]
_Evals = Optional[Union[Eval, str, Sequence[Union[Eval, str]]]]

class BatchError(ValueError): ...
class RunFailed(RuntimeError): ...

class Run(dict[str, Any]):
    name: str
    index: int
    input: Optional[str]
    params: dict[str, Any]
    status: str
    exit_status: Optional[int]
    attempts: int
    wall_seconds: Optional[float]
    cpu_seconds: Optional[float]
    worker: str
    folder: str
    figures: dict[str, Any]
    eval: dict[str, dict[str, Any]]
    issues: list[str]
    error: str

class BatchResult:
    runs: list[Run]
    csv_path: pathlib.Path
    json_path: pathlib.Path
    wall_seconds: float
    def __init__(self, runs: list[Run], csv_path: pathlib.Path, json_path: pathlib.Path,
                 wall_seconds: float) -> None: ...
    @property
    def failed(self) -> list[Run]: ...
    @property
    def exit_status(self) -> int: ...

class Eval:
    KINDS: tuple[str, ...]
    kind: str
    reference: Optional[str]
    trajectory: str
    def __init__(self, kind: str, reference: Optional[_Path] = ..., trajectory: str = ...) -> None: ...
    @classmethod
    def parse(cls, spec: str, trajectory: str = ...) -> Eval: ...
    def reference_for(self, input_path: Optional[str]) -> Optional[str]: ...

def parse_param(spec: str) -> tuple[str, list[Any]]: ...
def parse_grid(params: _Grid) -> dict[str, list[Any]]: ...
def expand_inputs(inputs: Union[None, _Path, Iterable[_Path]]) -> list[pathlib.Path]: ...
def find_rove(explicit: Optional[_Path] = ...) -> str: ...
def plan(job: Union[str, Callable[..., Any]], inputs: Any = ..., params: _Grid = ..., *, out: _Path,
         config: Optional[_Path] = ..., eval: _Evals = ..., rove: Optional[_Path] = ...,
         timeout: Optional[float] = ...) -> list[dict[str, Any]]: ...
def execute(task: Mapping[str, Any]) -> Run: ...
def write_table(runs: Sequence[Run], out_dir: pathlib.Path, wall_seconds: float,
                header: Mapping[str, Any]) -> tuple[pathlib.Path, pathlib.Path]: ...
def run(job: Union[str, Callable[..., Any]], inputs: Any = ..., params: _Grid = ..., *, out: _Path,
        config: Optional[_Path] = ..., eval: _Evals = ..., scheduler: Optional[str] = ...,
        workers: Optional[int] = ..., retries: int = ..., client: Any = ..., serial: bool = ...,
        rove: Optional[_Path] = ..., timeout: Optional[float] = ...,
        on_result: Optional[Callable[[Run], None]] = ...) -> BatchResult: ...
def main(argv: Optional[Sequence[str]] = ...) -> int: ...
