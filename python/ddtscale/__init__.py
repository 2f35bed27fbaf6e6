"""ddtscale: enlarge images and volumes by data-dependent triangulation (DDT).

The samples become a heightfield, triangulated (Delaunay, then edge flips
that lower a cost, so that long thin triangles follow the edges); the
surface on the mesh is rendered at the new size.

    >>> import numpy as np, ddtscale
    >>> image = np.zeros((32, 32, 3), np.uint8); image[:, 16:] = 255
    >>> ddtscale.upscale(image, 4).shape
    (128, 128, 3)

Functions: upscale (images), upscale_volume (volumes), upscale_sequence
(frame-rate upsampling of image sequences), grid (scattered
points), and ddtscale.dask.upscale / upscale_files (Dask). Options are the
command line's (`ddtscale --help`), with '-' written '_'; their defaults
are in UPSCALE_OPTIONS, VOLUME_OPTIONS and GRID_OPTIONS. Bad input raises
ValueError with the command line's one-line message (OSError for files,
TypeError for a value of the wrong type). The work runs without the GIL,
on all cores unless threads= says otherwise.
"""

from __future__ import annotations

from . import _ddtscale

# The annotations are never evaluated (see the import from __future__): numpy
# and typing are left to the type checkers, and numpy is imported where an
# array is made, so that a script that enlarges files starts as fast as the
# command line.
TYPE_CHECKING = False
if TYPE_CHECKING:
    from typing import Any, Optional, Sequence, Tuple, Union

    import numpy as np

#: The version of ddtscale, as `ddtscale --version` prints it.
__version__: str = _ddtscale.version

__all__ = ["upscale", "upscale_volume", "upscale_sequence", "grid", "UPSCALE_OPTIONS", "UPSCALE_FILE_OPTIONS", "VOLUME_OPTIONS",
           "SEQUENCE_OPTIONS", "GRID_OPTIONS"]

#: The keyword options of upscale() and their defaults (the library's).
UPSCALE_OPTIONS: dict = dict(_ddtscale.upscale_defaults())
#: The keyword options of upscale_file() and their defaults: upscale()'s but
#: compare and mesh, and how the output file is written.
UPSCALE_FILE_OPTIONS: dict = dict(_ddtscale.upscale_file_defaults())
#: The keyword options of upscale_volume() and their defaults.
VOLUME_OPTIONS: dict = dict(_ddtscale.volume_defaults())
#: The keyword options of upscale_sequence() and their defaults.
SEQUENCE_OPTIONS: dict = dict(_ddtscale.sequence_defaults())
#: The keyword options of grid() and their defaults.
GRID_OPTIONS: dict = dict(_ddtscale.grid_defaults())


def _options_doc(defaults: dict) -> str:
    return "\n".join(f"        {name} = {value!r}" for name, value in defaults.items())


def upscale(array: np.ndarray, scale: Optional[float] = None,
            size: Union[int, Tuple[int, int], None] = None, **options: Any) -> np.ndarray:
    return _ddtscale.upscale(array, scale, size, options)


def upscale_volume(array: np.ndarray, scale: Optional[float] = None,
                   size: Union[int, Tuple[int, int, int], Tuple[int, int, int, int], None] = None,
                   **options: Any) -> np.ndarray:
    return _ddtscale.upscale_volume(array, scale, size, options)


def upscale_sequence(frames: np.ndarray, time_scale: float = 1, scale: Optional[float] = None,
                     size: Union[int, Tuple[int, int], None] = None, **options: Any) -> np.ndarray:
    import numpy

    return numpy.stack(_ddtscale.upscale_sequence(frames, time_scale, scale, size, options))


def grid(points: np.ndarray, values: np.ndarray, size: Union[int, Tuple[int, int]],
         bounds: Optional[Sequence[float]] = None, **options: Any) -> np.ndarray:
    options["bounds"] = bounds
    return _ddtscale.grid(points, values, size, options)


upscale.__doc__ = f"""Enlarge an image by data-dependent triangulation.

    array   H x W or H x W x C array: uint8 or uint16 (read as 0..1, as image
            files are), float32 or float64 (as they are). Any strides.
    scale   magnification, any real > 0 (the output is round(H * scale) x
            round(W * scale)); or
    size    (height, width) of the output, or one number for both; or the
            keywords width= and/or height= (the other follows the aspect).

    Returns an array of the input's dtype and number of dimensions; integer
    outputs are rounded and clamped, as the command line writes PNG/TIFF.

    Options (the command line's, `ddtscale --help`), with their defaults:
{_options_doc(UPSCALE_OPTIONS)}
    alpha_channel: the index of an alpha channel (interpolated, never drives
    flips); region_rows: rows of the optimizer's parallel regions (0:
    automatic, -1: one region); compare: a classic method shown left of the
    result (the output is then both, side by side); mesh: a file to draw the
    optimized triangulation in (mesh_roi "x,y,w,h" chooses the region).

    Raises ValueError (bad input or option, with the command line's message),
    TypeError (an option of the wrong type), OSError (the mesh file).
    A UserWarning says when a large image was tiled and the model was not
    applied (quiet=True silences it).
    """

upscale_volume.__doc__ = f"""Enlarge a scalar volume, or a volume series, by data-dependent tetrahedrization.

    array   Z x Y x X array (x fastest, as NRRD), or T x Z x Y x X for a
            series of T time steps (4D: enlarged in 4D, 4-simplices); an
            integer type of up to 32 bits, float32 or float64; values are
            kept as stored (no rescaling).
    scale   magnification on every axis (a series' time too, unless
            time_scale); or
    size    (z, y, x) of the output, or one number for all three; for a
            series also (t, z, y, x) (with (z, y, x) the steps follow
            time_scale, else stay).

    Series: time_scale=T enlarges the time axis alone (alone, space keeps its
    size). The steps are instants (node_centred_time=True, the default): T
    steps enlarged by s become (T - 1) * s + 1 and output step s * k is input
    step k; node_centred_time=False treats them as cells (T * s steps).
    Methods of series: ddt, delaunay, quadrilinear (linear in space and
    time), tricubic-linear (Catmull-Rom in space, linear in time).

    Returns an array of the input's dtype and number of dimensions (integers
    rounded and clamped to the type's range).

    Options (`ddtscale in.nrrd out.nrrd --help`), with their defaults:
{_options_doc(VOLUME_OPTIONS)}
    Raises ValueError with the command line's message on bad input.
    """

upscale_sequence.__doc__ = f"""Frame-rate upsampling (and enlargement) of an image sequence by
    data-dependent tetrahedrization of (x, y, t) (docs/sequences.md).

    frames      T x H x W or T x H x W x C array: uint8, uint16 (read as 0..1),
                float32 or float64, as upscale() takes images
    time_scale  frames made per input frame: at a whole number T frames
                become (T - 1) * time_scale + 1, frame k * time_scale is input
                frame k; any number > 0 works (60 / 24 = 2.5 makes 60 frames a
                second of 24): output frame g is the instant g / time_scale,
                floor((T - 1) * time_scale) + 1 frames
    scale       spatial magnification of every frame (default 1); or
    size        (height, width) of the output frames, or one number for both

    Returns a floor((T - 1) * time_scale) + 1 x H' x W' [x C] array of the
    input's dtype.

    Options (`ddtscale in_%04d.png out_%04d.png --help`), with their defaults:
{_options_doc(SEQUENCE_OPTIONS)}
    presmooth None: 0.5 pixel where the mesh starts along a zoom or a shift
    of whole pixels a frame (found, or given by motion=), or where the
    frames move by a pixel or less a frame, else 1; a number: that sigma
    either way.
    Raises ValueError with the command line's message on bad input.
    """

grid.__doc__ = f"""Grid scattered points by data-dependent triangulation.

    points  N x 2 array of x, y positions (points at the same position are
            merged, their values averaged)
    values  N or N x C array of values
    size    (height, width) of the grid, or one number for both
    bounds  (xmin, ymin, xmax, ymax) of the grid's outer edges (default: the
            points' bounding box); row 0 is the top (ymax), as gdal_grid.

    Returns a height x width (values of one dimension) or height x width x C
    array (C + 1 with alpha=True), float64 for float64 values, else float32;
    pixels outside the points' convex hull hold nodata (NaN by default).

    Options (`ddtscale grid --help`), with their defaults:
{_options_doc(GRID_OPTIONS)}
    cost_channel: "sum", "luma" or a value channel's index (0-based).
    Raises ValueError with the command line's message on bad input.
    """


def upscale_file(input: str, output: str, scale: Optional[float] = None,
                 size: Union[int, Tuple[int, int], None] = None, **options: Any) -> Tuple[int, int]:
    """Enlarge an image file into another, as `ddtscale input output` does.

    The output's format follows its extension; integer formats keep the
    input's bit depth, alpha stays alpha. The file is written atomically
    (never a truncated or clobbered file on failure). This is the command
    line's job: the output is encoded by bands while the work goes on, and
    an image whose job does not fit in memory (or tile_rows=N, or more than
    max_memory: bytes or a size such as "2G") is read, enlarged and written
    by bands, to the same bits; under the box model at whole scales a tall
    image's mesh is made by bands of rows as the reconstruction reaches them
    and the input file is read a window of rows at a time (mesh_band_rows=N;
    0: automatic, -1: one mesh), to the same bits too.
    Options are those of
    upscale() but compare and mesh, and the command line's for the file
    (UPSCALE_FILE_OPTIONS): compression ("fast", "1:up:rle", "9:adaptive" for PNG;
    "piz", "zip", "dwaa:45" for EXR; "lzw", "jpeg:90" for TIFF), quality
    (JPEG, 1 to 100), half and float (EXR samples), tile_size (TIFF and EXR
    tiles), no_stream, max_input_pixels. Returns the output's (height, width).
    Raises OSError when a file cannot be read or written, ValueError on a
    bad option.
    """
    return tuple(_ddtscale.upscale_file(str(input), str(output), scale, size, options))


__all__.append("upscale_file")
