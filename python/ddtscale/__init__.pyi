# Type stub of the ddtscale package: the keyword options spelled out for
# editors and type checkers. Their defaults are the library's, listed at run
# time in UPSCALE_OPTIONS, VOLUME_OPTIONS, SEQUENCE_OPTIONS and GRID_OPTIONS (and in each
# function's docstring); "..." here stands for them.
from typing import Any, Literal, Optional, Sequence, Tuple, Union

import numpy as np

__version__: str
UPSCALE_OPTIONS: dict[str, Any]
UPSCALE_FILE_OPTIONS: dict[str, Any]
VOLUME_OPTIONS: dict[str, Any]
SEQUENCE_OPTIONS: dict[str, Any]
GRID_OPTIONS: dict[str, Any]

_Optimizer = Literal["lawson", "anneal", "lookahead"]

def upscale(
    array: np.ndarray,
    scale: Optional[float] = None,
    size: Union[int, Tuple[int, int], None] = None,
    *,
    width: Optional[int] = ...,
    height: Optional[int] = ...,
    cost: str = ...,
    cost_channel: Literal["sum", "luma"] = ...,
    render: Literal["cubic", "linear"] = ...,
    slopes: Literal["mc4", "mc", "central", "minmod"] = ...,
    model: str = ...,
    no_step_edges: bool = ...,
    no_optimize: bool = ...,
    tolerance: float = ...,
    max_pixels: int = ...,
    compare: Optional[str] = ...,
    mesh: Optional[str] = ...,
    mesh_roi: Optional[str] = ...,
    optimizer: _Optimizer = ...,
    seed: int = ...,
    anneal_t0: float = ...,
    anneal_accept: float = ...,
    anneal_cooling: float = ...,
    anneal_steps: int = ...,
    anneal_moves: float = ...,
    verbose: bool = ...,
    quiet: bool = ...,
    threads: int = ...,
    tile_rows: int = ...,
    mesh_band_rows: int = ...,
    max_memory: Union[int, str, None] = ...,
    alpha_channel: int = ...,
    region_rows: int = ...,
) -> np.ndarray: ...

def upscale_file(
    input: str,
    output: str,
    scale: Optional[float] = None,
    size: Union[int, Tuple[int, int], None] = None,
    **options: Any,
) -> Tuple[int, int]: ...

def upscale_volume(
    array: np.ndarray,
    scale: Optional[float] = None,
    size: Union[int, Tuple[int, int, int], Tuple[int, int, int, int], None] = None,
    *,
    method: Literal["ddt", "delaunay", "trilinear", "tricubic", "quadrilinear", "tricubic-linear"] = ...,
    cost: str = ...,
    render: Literal["cubic", "linear"] = ...,
    slopes: Literal["mc4", "mc", "central", "minmod"] = ...,
    tolerance: float = ...,
    presmooth: Optional[float] = ...,
    time_scale: Optional[float] = ...,
    node_centred_time: bool = ...,
    max_voxels: int = ...,
    verbose: bool = ...,
    threads: int = ...,
) -> np.ndarray: ...

def upscale_sequence(
    frames: np.ndarray,
    time_scale: float = 1,
    scale: Optional[float] = None,
    size: Union[int, Tuple[int, int], None] = None,
    *,
    method: Literal["ddt", "delaunay"] = ...,
    cost: str = ...,
    render: Literal["linear", "cubic"] = ...,
    slopes: Literal["mc4", "mc", "central", "minmod"] = ...,
    presmooth: Optional[float] = ...,
    tolerance: float = ...,
    flip_slow_texture: bool = ...,
    motion: str = ...,
    time_tile: int = ...,
    time_margin: int = ...,
    exact_tiles: bool = ...,
    max_pixels: int = ...,
    verbose: bool = ...,
    threads: int = ...,
) -> np.ndarray: ...

def grid(
    points: np.ndarray,
    values: np.ndarray,
    size: Union[int, Tuple[int, int]],
    bounds: Optional[Sequence[float]] = None,
    *,
    cost: str = ...,
    cost_channel: Union[Literal["sum", "luma"], int] = ...,
    no_optimize: bool = ...,
    optimizer: _Optimizer = ...,
    seed: int = ...,
    anneal_t0: float = ...,
    anneal_accept: float = ...,
    anneal_cooling: float = ...,
    anneal_steps: int = ...,
    anneal_moves: float = ...,
    tolerance: float = ...,
    nodata: float = ...,
    alpha: bool = ...,
    max_pixels: int = ...,
    verbose: bool = ...,
    threads: int = ...,
) -> np.ndarray: ...
