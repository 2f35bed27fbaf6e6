"""ddtscale on Dask: images larger than one machine's memory, and batches of files.

upscale(array, scale, **options) enlarges a dask array in bands of rows
(map_overlap), each band with margins of rows above and below it. The
result equals ddtscale.upscale(array.compute(), scale, **options) bit for
bit (tests/python/test_dask.py), because the library proves a band with
wide enough margins exact (ddt::upscale_rows, src/pipeline/upscale.hpp) when

  * optimizer="lawson" (the default, or no_optimize=True), and
  * the optimizer runs in regions: always on images of more than
    2 * 2^18 triangles (about 512 x 512 pixels), else when region_rows > 0
    is given (to both calls, so that they do the same work).

Under a consistent model (the default "box", "gauss:S", "bicubic") the
margins also cover the reconstruction's reach, and every band is given the
whole input's range and code grid (ddtscale's input_statistics), computed
from the array's blocks before the bands are planned: the input is read
once for them, then again by the bands.

Otherwise the whole image is one task (exact too, but on one machine; a
UserWarning says so for images the region schedule would split). A band
whose margin proves too narrow raises ValueError naming the margin needed:
pass margin= (rows) to widen it.

upscale_files(paths, outdir, scale, **options) enlarges files through
dask.bag, one task per file; a file that fails is reported in the results
and does not stop the others.
"""

from __future__ import annotations

import os
import warnings
from typing import Any, Iterable, List, Optional, Tuple, Union

import numpy as np

from . import _ddtscale

try:
    import dask
    import dask.array as da
    import dask.bag as db
except ImportError as error:  # pragma: no cover - dask is a Debian package (python3-dask)
    raise ImportError("ddtscale.dask needs Dask (Debian: python3-dask)") from error

__all__ = ["upscale", "upscale_files", "band_plan"]


# Rows a triangle of an optimized mesh is planned to span (the library's
# planned_triangle_rows, src/consistency/consistent_reconstruction.hpp).
_PLANNED_TRIANGLE_ROWS = 16


def _block_statistics(block: np.ndarray) -> Tuple[List[float], List[float], float]:
    # A module-level function: workers unpickle it by name (the compiled one cannot be pickled).
    return _ddtscale.input_statistics(block)


def _statistics(array: "da.Array") -> Tuple[List[float], List[float], float]:
    """The whole array's input_statistics, merged from its blocks."""
    parts = dask.compute(*[dask.delayed(_block_statistics)(block) for block in array.to_delayed().ravel()])
    merged = parts[0]
    for part in parts[1:]:
        merged = _ddtscale.merge_statistics(merged, part)
    return merged


def _regions(width: int, height: int, options: dict) -> int:
    return _ddtscale.region_rows(width, height, options)


def band_plan(shape: Tuple[int, ...], options: dict, band_rows: Optional[int] = None,
              margin: Optional[int] = None,
              out_size: Optional[Tuple[int, int]] = None) -> Tuple[Tuple[int, ...], int]:
    """The bands of rows (chunk sizes along axis 0) and the margin upscale() uses.

    One band (the whole image) unless the options allow exact bands (see the
    module's docstring). Bands are whole regions of the optimizer, at least
    band_rows (default: 16 regions) and at least the margin tall; the
    default margin covers 5 phases of the optimizer (photographs and noise
    take 2 in the automatic regions, docs/scale-out.md), and is at least 64
    rows (small regions take more phases), plus under a consistent model
    the reconstruction's reach for the output size out_size (height, width;
    default: twice the input's).
    """
    height, width = shape[0], shape[1]
    regions = _regions(width, height, options)
    optimizer = options.get("optimizer", _ddtscale.upscale_defaults()["optimizer"])
    banded = regions > 0 and (optimizer == "lawson" or options.get("no_optimize"))
    if not banded:
        if regions > 0:
            warnings.warn("ddtscale.dask: these options are exact only on the whole image "
                          "(optimizer='lawson' splits it); it runs as one task", stacklevel=3)
        return (height,), 0
    if margin is None:
        # Small regions take more phases (6 with 8-row regions in the tests): at least 64 rows.
        out_h, out_w = out_size or (2 * height, 2 * width)
        margin = max(_ddtscale.band_margin_needed(5, regions), 64) + _ddtscale.consistency_margin_needed(
            _PLANNED_TRIANGLE_ROWS, width, height, out_w, out_h, options)
    rows = max(band_rows or 16 * regions, margin)
    rows = -(-rows // regions) * regions  # whole regions
    bands = [rows] * (height // rows)
    if height % rows:
        bands.append(height % rows)
    if len(bands) > 1 and bands[-1] < margin:  # map_overlap needs bands at least the margin
        last = bands.pop()
        bands[-1] += last
    return tuple(bands), margin


def upscale(array: "da.Array", scale: Optional[float] = None, size: Union[int, Tuple[int, int], None] = None,
            band_rows: Optional[int] = None, margin: Optional[int] = None, **options: Any) -> "da.Array":
    """Enlarge a dask array (H x W or H x W x C) as ddtscale.upscale does, in bands of rows.

    scale, size and the options are ddtscale.upscale's. band_rows: input rows
    per task (rounded up to whole regions of the optimizer); margin: rows
    of overlap above and below each band (default: enough for 5 phases of
    the optimizer). Returns a lazy dask array of the input's dtype; a band
    that fails raises with its rows in the message.
    """
    if not isinstance(array, da.Array):
        array = da.from_array(np.asarray(array))
    if array.ndim not in (2, 3):
        raise ValueError(f"an image array is H x W or H x W x C; this one has {array.ndim} dimensions")
    height, width = array.shape[0], array.shape[1]
    if height == 0 or width == 0 or (array.ndim == 3 and array.shape[2] == 0):
        raise ValueError("the input image is empty")
    if options.get("compare") or options.get("mesh"):
        raise ValueError("compare and mesh are not options of ddtscale.dask.upscale")
    out_h, out_w = _ddtscale.output_size(width, height, scale, size, options)
    options = {k: v for k, v in options.items() if k not in ("width", "height")}  # now in out_h, out_w
    # Options and dtype checked now, not in the first task.
    _ddtscale.upscale(np.zeros((1, 1) + array.shape[2:], array.dtype), 1.0, None, dict(options, quiet=True))
    bands, margin = band_plan(array.shape, options, band_rows, margin, (out_h, out_w))
    array = array.rechunk((bands, -1) + ((-1,) if array.ndim == 3 else ()))
    starts = np.concatenate([[0], np.cumsum(bands)]).astype(int)
    out_rows = [_ddtscale.output_row_of(int(y), height, out_h) for y in starts]
    out_chunks = (tuple(np.diff(out_rows).astype(int)), (out_w,)) + ((array.shape[2],) if array.ndim == 3 else ())

    if len(bands) == 1:
        def whole(block):
            return _ddtscale.upscale(block, None, (out_h, out_w), dict(options))
        return array.map_blocks(whole, chunks=out_chunks, dtype=array.dtype)

    # The whole input's statistics for the consistent models (one read of it).
    model = options.get("model", _ddtscale.upscale_defaults()["model"])
    statistics = _statistics(array) if model != "point" else None

    def band(block, block_info=None):
        i = block_info[0]["chunk-location"][0]
        first, end = int(starts[i]), int(starts[i + 1])
        top = max(0, first - margin)
        if block.shape[0] != min(height, end + margin) - top:
            raise RuntimeError(f"ddtscale.dask: band {i} came with {block.shape[0]} rows, not its margins")
        try:
            return _ddtscale.upscale_rows(block, top, height, first, end, out_w, out_h, dict(options), statistics)
        except Exception as error:
            raise type(error)(f"rows {first}..{end} of the image: {error}") from error

    depth = {0: margin, 1: 0}
    if array.ndim == 3:
        depth[2] = 0
    return da.map_overlap(band, array, depth=depth, boundary="none", trim=False, allow_rechunk=False,
                          chunks=out_chunks, dtype=array.dtype)


def _output_path(path: str, outdir: str, suffix: str, format: Optional[str]) -> str:
    stem, extension = os.path.splitext(os.path.basename(path))
    extension = "." + format.lstrip(".") if format else extension
    return os.path.join(outdir, stem + suffix + extension)


def _upscale_one(path: str, outdir: str, suffix: str, format: Optional[str], overwrite: bool,
                 scale: Optional[float], size: Any, options: dict) -> dict:
    from . import upscale_file  # on the worker
    output = _output_path(path, outdir, suffix, format)
    result = {"input": path, "output": output, "status": "done", "error": ""}
    if not overwrite and os.path.exists(output):
        result["status"] = "skipped"
        return result
    try:
        upscale_file(path, output, scale, size, **options)
    except Exception as error:  # reported per file; the others go on
        result["status"] = "failed"
        result["error"] = f"{path}: {error}"
    return result


def upscale_files(paths: Iterable[str], outdir: str, scale: Optional[float] = None,
                  size: Union[int, Tuple[int, int], None] = None, suffix: str = "", format: Optional[str] = None,
                  overwrite: bool = False, partition_size: int = 1, **options: Any) -> "db.Bag":
    """Enlarge image files through dask.bag, one task per file.

    Each file is written to outdir as stem + suffix + extension (format=,
    e.g. "exr", replaces the extension); an existing output is skipped
    unless overwrite=True. Returns a lazy bag of one dict per file,
    {"input", "output", "status": "done" | "skipped" | "failed", "error"};
    call .compute(). Options are ddtscale.upscale_file's (threads=1 suits
    one task per core).
    """
    paths = [str(p) for p in paths]
    os.makedirs(outdir, exist_ok=True)
    return db.from_sequence(paths, partition_size=partition_size).map(
        _upscale_one, outdir, suffix, format, overwrite, scale, size, dict(options))
