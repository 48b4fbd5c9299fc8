# Type hints for the isoquad package (the docstrings are in __init__.py).
from os import PathLike
from typing import Any, Callable, Literal, Optional, Sequence, Tuple, Union

import numpy as np
import numpy.typing as npt

__version__: str
__all__: list[str]

ArrayLike = npt.ArrayLike
Path = Union[str, PathLike[str]]
Progress = Callable[[float, str, str], None]

class Error(Exception):
    message: str
    code: str
    exit_status: int
    file: str
    line: Optional[int]
    vertices: list[int]
    faces: list[int]
    def __init__(
        self,
        message: str,
        code: str,
        exit_status: int,
        file: str = ...,
        line: Optional[int] = ...,
        vertices: Sequence[int] = ...,
        faces: Sequence[int] = ...,
    ) -> None: ...

class InputError(Error): ...
class TopologyError(Error): ...
class LayoutError(Error): ...
class SolverError(Error): ...
class ExtractionError(Error): ...
class InternalError(Error): ...

class RemeshResult(Tuple[npt.NDArray[np.float64], npt.NDArray[np.int32], dict[str, Any]]):
    patch: npt.NDArray[np.int32]
    def __new__(
        cls,
        V: npt.NDArray[np.float64],
        Q: npt.NDArray[np.int32],
        report: dict[str, Any],
        patch: npt.NDArray[np.int32],
    ) -> RemeshResult: ...

class Mesh(Tuple[npt.NDArray[np.float64], npt.NDArray[np.int32]]):
    unshared_vertices: bool
    def __new__(
        cls, V: npt.NDArray[np.float64], F: npt.NDArray[np.int32], unshared_vertices: bool
    ) -> Mesh: ...

def remesh(
    V: ArrayLike,
    F: ArrayLike,
    quads: Optional[float] = ...,
    edge_length: Optional[float] = ...,
    *,
    patches: Union[int, Literal["auto"]] = ...,
    seed: int = ...,
    weights: Literal["smvc", "mvc"] = ...,
    relax: Literal["adaptive", "bisection", "locked"] = ...,
    segmentation: Literal["vsa", "field"] = ...,
    corners: Literal["global", "local"] = ...,
    improve_corners: bool = ...,
    feature_angle: float = ...,
    repair: bool = ...,
    weld_eps: float = ...,
    weld_all: bool = ...,
    smooth: int = ...,
    untangle: bool = ...,
    snap: bool = ...,
    fold_rounds: int = ...,
    split_patches: bool = ...,
    tip_split: bool = ...,
    refine: bool = ...,
    patch_rounds: bool = ...,
    misfit_split: bool = ...,
    tolerance: float = ...,
    tolerance_rounds: int = ...,
    allow_topology_change: bool = ...,
    allow_invalid: bool = ...,
    threads: int = ...,
    quality: bool = ...,
    progress: Optional[Progress] = ...,
) -> RemeshResult: ...
def read(path: Path, repair: bool = ...) -> Mesh: ...
def write(path: Path, V: ArrayLike, F: ArrayLike, patch: Optional[ArrayLike] = ...) -> None: ...
def quality(
    V: ArrayLike, Q: ArrayLike, reference: Optional[Tuple[ArrayLike, ArrayLike]] = ...
) -> dict[str, Any]: ...
def tune_allocator() -> None: ...
