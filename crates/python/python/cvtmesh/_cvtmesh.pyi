"""Type stubs of the compiled module (see ``cvtmesh/__init__.py`` for the public layer)."""

from os import PathLike
from typing import Any, Callable, Optional, Sequence, Tuple, Union

import numpy as np
import numpy.typing as npt

__version__: str

class MeshError(ValueError):
    """A region, request or file that cvtmesh cannot use; the message names the problem."""

class Region:
    """A planar region: an outer boundary loop and holes, each made of boundary pieces."""

    @staticmethod
    def from_file(path: Union[str, PathLike[str]]) -> Region: ...
    @staticmethod
    def builtin(name: str) -> Region: ...
    @staticmethod
    def load(spec: str) -> Region: ...
    @staticmethod
    def from_triangles(
        points: npt.ArrayLike,
        triangles: npt.ArrayLike,
        name: str = "mesh",
        walls: Optional[Tuple[npt.ArrayLike, npt.ArrayLike]] = None,
    ) -> Region: ...
    @staticmethod
    def from_loops(
        outer: npt.ArrayLike, holes: Sequence[npt.ArrayLike] = ..., name: str = "region"
    ) -> Region: ...
    @staticmethod
    def from_parts(
        parts: Sequence[Tuple[npt.ArrayLike, Sequence[npt.ArrayLike]]], name: str = "region"
    ) -> Region: ...
    def with_corner_angle(self, degrees: float) -> Region: ...
    def simplified(self, tolerance: float) -> Tuple[Region, float]: ...
    def with_default_corners(self) -> Region: ...
    @property
    def num_parts(self) -> int: ...
    @property
    def name(self) -> str: ...
    @property
    def area(self) -> float: ...
    @property
    def corners(self) -> npt.NDArray[np.float64]: ...
    @property
    def pieces(self) -> list[dict[str, Any]]: ...
    @property
    def piece_markers(self) -> Optional[list[int]]: ...
    @property
    def bbox(self) -> tuple[tuple[float, float], tuple[float, float]]: ...
    def polygonize(self, tol: float) -> list[npt.NDArray[np.float64]]: ...
    def contains(self, xy: npt.ArrayLike) -> npt.NDArray[np.bool_]: ...
    def signed_distance(self, xy: npt.ArrayLike) -> npt.NDArray[np.float64]: ...

class Mesh:
    """A triangle mesh and how it was made; arrays are read-only."""

    points: npt.NDArray[np.float64]
    triangles: npt.NDArray[np.int64]
    boundary_edges: npt.NDArray[np.int64]
    boundary_loop: npt.NDArray[np.int64]
    converged: bool
    iterations: int
    notes: list[str]
    energy_history: npt.NDArray[np.float64]
    def write(self, path: Union[str, PathLike[str]], order: int = 1) -> None: ...
    def quadratic(
        self, region: Optional[Region] = None
    ) -> Tuple[npt.NDArray[np.float64], npt.NDArray[np.int64]]: ...
    def boundary_pieces(self, region: Optional[Region] = None) -> npt.NDArray[np.int64]: ...
    def boundary_markers(self, region: Optional[Region] = None) -> npt.NDArray[np.int64]: ...
    def measures(self, region: Optional[Region] = None) -> dict[str, float]: ...
    def to_meshio(self, order: int = 1) -> Any: ...
    def polished(self, region: Optional[Region] = None, below: float = 40.0) -> Mesh: ...
    @staticmethod
    def read(path: Union[str, PathLike[str]]) -> Mesh: ...

def mesh(
    region: Region,
    *,
    n: Optional[int] = None,
    size: Union[None, float, str, Tuple[Any, Any, Any], Callable[[npt.NDArray[np.float64]], Any]] = None,
    method: str = "ccvt",
    seed: int = 1,
    tol: float = 1e-4,
    max_iter: int = 10000,
    density: Union[None, str, Callable[[npt.NDArray[np.float64]], Any]] = None,
    progress: Optional[Callable[[int, float, float], Any]] = None,
    size_min: Optional[float] = None,
    size_max: Optional[float] = None,
    gradation: Optional[float] = 0.3,
    size_toward: Sequence[str] = ...,
    size_threshold: Optional[Tuple[float, float, float, float]] = None,
    simplify: Union[None, float, str] = None,
    time_limit: Optional[float] = None,
    polish: float = 40.0,
) -> Mesh: ...
def measures(
    points: npt.NDArray[np.float64], triangles: npt.NDArray[np.int64], region: Region
) -> dict[str, float]: ...
def size_conformity(
    points: npt.NDArray[np.float64], triangles: npt.NDArray[np.int64], region: Region, size: Any
) -> dict[str, float]: ...
def regions() -> list[str]: ...
def methods() -> list[str]: ...
def cli(argv: Sequence[Union[str, PathLike[str]]]) -> int: ...
