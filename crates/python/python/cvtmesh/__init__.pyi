from os import PathLike
from typing import Any, Callable, Optional, Sequence, Tuple, Union

import numpy as np
import numpy.typing as npt

from ._cvtmesh import Mesh as Mesh
from ._cvtmesh import MeshError as MeshError
from ._cvtmesh import Region as Region
from ._cvtmesh import __version__ as __version__
from ._cvtmesh import methods as methods
from ._cvtmesh import regions as regions

RegionLike = Union[str, PathLike[str], Region, npt.ArrayLike]

def mesh(
    region: RegionLike,
    *,
    holes: Optional[Sequence[npt.ArrayLike]] = None,
    n: Optional[int] = None,
    size: Union[None, float, str, Tuple[Any, Any, Any], Callable[[npt.NDArray[np.float64]], Any]] = None,
    method: str = "ccvt",
    seed: int = 1,
    tol: float = 1e-4,
    max_iter: int = 10000,
    density: Union[None, str, Callable[[npt.NDArray[np.float64]], Any]] = None,
    corner_angle: Optional[float] = None,
    progress: Optional[Callable[[int, float, float], Any]] = None,
    size_min: Optional[float] = None,
    size_max: Optional[float] = None,
    gradation: Optional[float] = 0.3,
    size_toward: Union[str, Sequence[str]] = (),
    size_threshold: Optional[Tuple[float, float, float, float]] = None,
    simplify: Union[None, float, str] = None,
    time_limit: Optional[float] = None,
    polish: float = 40.0,
) -> Mesh: ...
def measures(points: npt.ArrayLike, triangles: npt.ArrayLike, region: RegionLike) -> dict[str, float]: ...
def size_conformity(
    points: npt.ArrayLike, triangles: npt.ArrayLike, region: RegionLike, size: Any
) -> dict[str, float]: ...
