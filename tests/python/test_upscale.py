# ddtscale.upscale on numpy arrays: the mathematics (samples reproduced, the
# model's averages reproduced), the dtypes, the options and bad input.
import os
import re
import subprocess
import sys
import threading
import time
import warnings
import zlib

import numpy as np
import pytest

import ddtscale


def test_point_model_reproduces_the_samples(textured):
    # Scale 3: output pixel 3i + 1 samples input pixel i at its centre, where
    # the surface interpolates the samples.
    for render in ("linear", "cubic"):
        out = ddtscale.upscale(textured.astype(np.float32), 3, model="point", render=render)
        assert out.shape == (120, 144, 3)
        np.testing.assert_allclose(out[1::3, 1::3], textured.astype(np.float32), atol=1e-6)


def test_box_model_reproduces_the_pixel_averages(textured):
    out = ddtscale.upscale(textured, 2)
    averages = out.reshape(40, 2, 48, 2, 3).mean(axis=(1, 3))
    assert np.abs(averages - textured).max() < 2e-3
    # ... which the plain interpolation does not
    plain = ddtscale.upscale(textured, 2, model="point").reshape(40, 2, 48, 2, 3).mean(axis=(1, 3))
    assert np.abs(plain - textured).max() > 10 * np.abs(averages - textured).max()


def test_a_constant_image_stays_constant():
    out = ddtscale.upscale(np.full((9, 7), 0.25, np.float32), 2.5)
    assert out.shape == (23, 18)  # round(22.5), round(17.5)
    np.testing.assert_allclose(out, 0.25, atol=1e-6)


def test_flips_follow_an_edge():
    # A diagonal step: DDT's flips give a sharper edge than plain Delaunay
    # (fewer intermediate values).
    y, x = np.mgrid[0:24, 0:24]
    step = (x + 0.5 * y > 18).astype(np.float32)
    ddt = ddtscale.upscale(step, 4, model="point", render="linear")
    delaunay = ddtscale.upscale(step, 4, model="point", render="linear", no_optimize=True)
    blurred = lambda a: np.count_nonzero((a > 0.05) & (a < 0.95))
    assert blurred(ddt) < blurred(delaunay)


@pytest.mark.parametrize("dtype,peak", [(np.uint8, 255), (np.uint16, 65535), (np.float32, 1), (np.float64, 1)])
def test_dtype_is_kept(textured, dtype, peak):
    array = (textured * peak).round().astype(dtype) if peak > 1 else textured.astype(dtype)
    out = ddtscale.upscale(array, size=(50, 60))
    assert out.dtype == dtype and out.shape == (50, 60, 3)
    # Integers are the float result rounded: the same as the float call on the scaled samples.
    as_float = ddtscale.upscale(array.astype(np.float32) / peak, size=(50, 60))
    expected = np.clip(np.round(as_float * peak), 0, peak) if peak > 1 else as_float
    assert np.abs(out.astype(np.float64) - expected).max() <= (1 if peak > 1 else 1e-6)


def test_sizes_may_be_numpy_integers(textured):
    assert ddtscale.upscale(textured, size=np.int64(100)).shape == (100, 100, 3)
    assert ddtscale.upscale(textured, size=np.array([90, 70])).shape == (90, 70, 3)
    assert ddtscale.upscale(textured, np.float32(1.5)).shape == (60, 72, 3)


def test_two_dimensional_arrays_stay_two_dimensional(textured):
    grey = textured[..., 0]
    out = ddtscale.upscale(grey, width=96)
    assert out.shape == (80, 96)
    np.testing.assert_array_equal(out, ddtscale.upscale(grey[..., None], 2)[..., 0])


def test_any_strides_give_the_contiguous_result(textured):
    flipped = textured[::-1, ::2]  # negative and non-unit strides
    assert not flipped.flags.c_contiguous
    np.testing.assert_array_equal(ddtscale.upscale(flipped, 2), ddtscale.upscale(np.ascontiguousarray(flipped), 2))
    fortran = np.asfortranarray(textured)
    np.testing.assert_array_equal(ddtscale.upscale(fortran, 2), ddtscale.upscale(textured, 2))


def test_threads_do_not_change_the_result(textured):
    one = ddtscale.upscale(textured, 3, threads=1)
    np.testing.assert_array_equal(one, ddtscale.upscale(textured, 3, threads=2))


def test_the_gil_is_released_while_it_works():
    image = np.random.default_rng(1).random((300, 300)).astype(np.float32)
    ticks = [0]
    stop = threading.Event()

    def count():
        while not stop.is_set():
            ticks[0] += 1

    counter = threading.Thread(target=count)
    counter.start()
    time.sleep(0.05)
    before = ticks[0]
    start = time.perf_counter()
    ddtscale.upscale(image, 3, threads=1)
    elapsed = time.perf_counter() - start
    during = ticks[0] - before
    stop.set()
    counter.join()
    # A counter that held no GIL would stall for the whole call: it advances
    # while the call runs (the interpreter's switch interval is 5 ms).
    assert elapsed > 0.05
    assert during > 1000


def test_defaults_are_the_librarys():
    d = ddtscale.UPSCALE_OPTIONS
    assert d["cost"] == "sederberg" and d["model"] == "box" and d["render"] == "cubic"
    assert d["threads"] == 0 and d["max_pixels"] > 0
    for name in d:
        assert name in ddtscale.upscale.__doc__


def test_options_match_the_command_line(cli):
    out = subprocess.run([cli, "--help"], capture_output=True, text=True, check=True).stdout
    for name in ddtscale.UPSCALE_OPTIONS:
        if name in ("alpha_channel", "region_rows"):  # the library's, no command-line flags
            continue
        assert "--" + name.replace("_", "-") in out, name
    # ... and every option of the command line is a keyword (but those about files and the command itself).
    flags = set(re.findall(r"^\s+(?:-\w,)?--([a-z][a-z0-9-]*)", out, re.MULTILINE))
    # scale: positional; the files' options are upscale_file's (below)
    not_keywords = {"help", "list-costs", "version", "outdir", "suffix", "format", "overwrite", "jobs", "scale"}
    file_flags = {"compression", "quality", "half", "float", "tile-size", "no-stream", "max-input-pixels"}
    not_keywords |= file_flags
    assert file_flags <= {k.replace("_", "-") for k in ddtscale.UPSCALE_FILE_OPTIONS}
    assert set(ddtscale.UPSCALE_OPTIONS) - {"compare", "mesh", "mesh_roi"} <= set(ddtscale.UPSCALE_FILE_OPTIONS)
    assert flags - not_keywords <= {k.replace("_", "-") for k in ddtscale.UPSCALE_OPTIONS}, \
        flags - not_keywords - {k.replace("_", "-") for k in ddtscale.UPSCALE_OPTIONS}
    assert "scale" in flags and "tile-rows" in flags


@pytest.mark.parametrize("options,message", [
    (dict(cost="nope"), "unknown cost 'nope'"),
    (dict(render="flat"), "flat"),
    (dict(slopes="x"), "x"),
    (dict(model="gauss:-1"), "--model"),
    (dict(cost_channel="red"), "--cost-channel"),
    (dict(tolerance=2.0), "--tolerance"),
    (dict(tolerance=float("nan")), "--tolerance"),
    (dict(optimizer="greedy"), "greedy"),
    (dict(anneal_cooling=1.5, optimizer="anneal"), "cooling"),
    (dict(threads=-2), "--threads"),
    (dict(max_pixels=10), "exceeds --max-pixels 10"),
    (dict(compare="nearest-ish"), "--compare"),
    (dict(colour="red"), "unknown option 'colour'"),
    (dict(alpha_channel=5), "alpha_channel 5"),
])
def test_bad_options_raise_value_error(textured, options, message):
    with pytest.raises(ValueError, match=message.replace("(", r"\(")):
        ddtscale.upscale(textured, 2, **options)


def test_wrong_types_raise_type_error(textured):
    with pytest.raises(TypeError):
        ddtscale.upscale(textured, 2, cost=3)
    with pytest.raises(TypeError):
        ddtscale.upscale(textured, "two")


@pytest.mark.parametrize("size_args,message", [
    (dict(), "give the magnification"),
    (dict(scale=2, size=10), "not both"),
    (dict(scale=-1), "--scale must be a positive number"),
    (dict(scale=float("inf")), "--scale must be a positive number"),
    (dict(size=(10, 0)), "must be positive"),
    (dict(size=(1, 2, 3)), "height, width"),
])
def test_bad_sizes_raise_value_error(textured, size_args, message):
    with pytest.raises(ValueError, match=message):
        ddtscale.upscale(textured, **size_args)


@pytest.mark.parametrize("array,message", [
    (np.zeros((0, 5)), "empty"),
    (np.zeros((4, 0, 3)), "empty"),
    (np.zeros(5), "1 dimensions"),
    (np.zeros((2, 2, 2, 2)), "4 dimensions"),
    (np.zeros((4, 4), np.int32), "int32"),
    (np.zeros((4, 4), np.complex64), "complex64"),
    (np.array([[0.0, np.nan], [1, 2]]), "NaN or infinite"),
    (np.array([[0.0, np.inf], [1, 2]], np.float32), "NaN or infinite"),
])
def test_bad_arrays_raise_value_error(array, message):
    with pytest.raises(ValueError, match=message):
        ddtscale.upscale(array, 2)


def test_compare_puts_a_classic_method_beside(textured):
    out = ddtscale.upscale(textured, 2, compare="bicubic")
    assert out.shape == (80, 2 * 96 + 2, 3)
    np.testing.assert_array_equal(out[:, 98:], ddtscale.upscale(textured, 2))


def test_mesh_view_is_written_and_bad_paths_raise_os_error(textured, tmp_path):
    path = tmp_path / "mesh.svg"
    ddtscale.upscale(textured, 2, mesh=str(path))
    assert path.read_text().lstrip().startswith("<")
    with pytest.raises(OSError):
        ddtscale.upscale(textured, 2, mesh=str(tmp_path / "no" / "such" / "dir" / "mesh.svg"))


def test_tiles_give_the_untiled_result_under_the_default_model():
    image = np.random.default_rng(3).random((600, 16)).astype(np.float32)
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # no fallback to another model, nothing to warn about
        tiled = ddtscale.upscale(image, 2, region_rows=16, tile_rows=150)
    np.testing.assert_array_equal(tiled, ddtscale.upscale(image, 2, region_rows=16, tile_rows=-1))


def _write_ppm(path, image):
    with open(path, "wb") as f:
        f.write(b"P6\n%d %d\n255\n" % (image.shape[1], image.shape[0]))
        f.write(image.tobytes())


def _read_ppm(path):
    data = open(path, "rb").read()
    fields = data.split(maxsplit=3)  # P6, width, height; then the maximum and one whitespace byte
    w, h = int(fields[1]), int(fields[2])
    return np.frombuffer(data[len(data) - w * h * 3:], np.uint8).reshape(h, w, 3)


def test_equals_the_command_line_bit_for_bit(textured, cli, tmp_path):
    image = (textured * 255).round().astype(np.uint8)
    _write_ppm(tmp_path / "in.ppm", image)
    for args, options in [(["--scale", "2.5"], {}), (["--scale", "3", "--model", "point", "--cost", "variance"],
                                                     dict(model="point", cost="variance"))]:
        subprocess.run([cli, str(tmp_path / "in.ppm"), str(tmp_path / "out.ppm"), "-q"] + args, check=True)
        scale = float(args[1])
        np.testing.assert_array_equal(ddtscale.upscale(image, scale, **options), _read_ppm(tmp_path / "out.ppm"))
        os.remove(tmp_path / "out.ppm")


def test_upscale_file_keeps_depth_and_refuses_bad_files(textured, tmp_path):
    image = (textured * 255).round().astype(np.uint8)
    _write_ppm(tmp_path / "in.ppm", image)
    assert ddtscale.upscale_file(tmp_path / "in.ppm", tmp_path / "out.ppm", 2) == (80, 96)
    np.testing.assert_array_equal(_read_ppm(tmp_path / "out.ppm"), ddtscale.upscale(image, 2))
    with pytest.raises(OSError, match="missing.ppm"):
        ddtscale.upscale_file(tmp_path / "missing.ppm", tmp_path / "x.ppm", 2)
    with pytest.raises(OSError):
        ddtscale.upscale_file(tmp_path / "in.ppm", tmp_path / "in.ppm", 2)


def test_a_script_of_files_does_not_start_numpy(textured, tmp_path):
    # A cold process that only enlarges files pays the library's start, not numpy's (issue 19's overhead).
    image = (textured * 255).round().astype(np.uint8)
    _write_ppm(tmp_path / "in.ppm", image)
    script = ("import sys, ddtscale; ddtscale.upscale_file(sys.argv[1], sys.argv[2], 2, quiet=True); "
              "print('numpy' in sys.modules)")
    done = subprocess.run([sys.executable, "-c", script, str(tmp_path / "in.ppm"), str(tmp_path / "out.ppm")],
                          capture_output=True, text=True, env=dict(os.environ, PYTHONPATH=os.pathsep.join(sys.path)))
    assert done.returncode == 0, done.stderr
    assert done.stdout.strip() == "False"
    np.testing.assert_array_equal(_read_ppm(tmp_path / "out.ppm"), ddtscale.upscale(image, 2))


@pytest.mark.parametrize("model", ["box", "point"])
def test_upscale_file_reads_by_bands_to_the_same_bits(tmp_path, capfd, model):
    # The command line's job (pipeline/file_upscale.hpp): tile_rows reads, enlarges and writes by bands.
    rng = np.random.default_rng(7)
    ramp = np.linspace(0, 1, 512)[:, None, None] * np.array([0.8, 0.3, 0.5])
    image = (np.clip(ramp + rng.uniform(0, 0.2, (512, 192, 3)), 0, 1) * 255).round().astype(np.uint8)
    _write_ppm(tmp_path / "in.ppm", image)
    options = dict(model=model, region_rows=32)
    assert ddtscale.upscale_file(tmp_path / "in.ppm", tmp_path / "b.ppm", 2, tile_rows=128, verbose=True,
                                 **options) == (1024, 384)
    assert "read by bands of 128 rows" in capfd.readouterr().err
    np.testing.assert_array_equal(_read_ppm(tmp_path / "b.ppm"), ddtscale.upscale(image, 2, tile_rows=-1, **options))
    # A limit the whole job fits: not banded, the same bits.
    ddtscale.upscale_file(tmp_path / "in.ppm", tmp_path / "m.ppm", 2, max_memory=1 << 40, verbose=True, **options)
    assert "read by bands" not in capfd.readouterr().err
    np.testing.assert_array_equal(_read_ppm(tmp_path / "m.ppm"), _read_ppm(tmp_path / "b.ppm"))


def test_upscale_file_mesh_bands_write_the_bits_of_one_mesh(tmp_path, capfd):
    # The box model's streamed wavefront from meshes made by bands (pipeline/banded_meshes.hpp).
    rng = np.random.default_rng(8)
    ramp = np.linspace(0, 1, 400)[:, None, None] * np.array([0.2, 0.7, 0.4])
    image = (np.clip(ramp + rng.uniform(0, 0.25, (400, 96, 3)), 0, 1) * 255).round().astype(np.uint8)
    _write_ppm(tmp_path / "in.ppm", image)
    options = dict(region_rows=16, tile_rows=-1)
    ddtscale.upscale_file(tmp_path / "in.ppm", tmp_path / "b.ppm", 2, mesh_band_rows=100, verbose=True, **options)
    assert "mesh bands: 4 of 100 rows" in capfd.readouterr().err
    ddtscale.upscale_file(tmp_path / "in.ppm", tmp_path / "o.ppm", 2, mesh_band_rows=-1, **options)
    np.testing.assert_array_equal(_read_ppm(tmp_path / "b.ppm"), _read_ppm(tmp_path / "o.ppm"))


def _png_image_data(path):
    """A PNG's IDAT chunks joined and inflated (every chunk's CRC checked)."""
    data, at, idat = open(path, "rb").read(), 8, b""
    assert data[:8] == b"\x89PNG\r\n\x1a\n"
    while at < len(data):
        n = int.from_bytes(data[at:at + 4], "big")
        kind, body = data[at + 4:at + 8], data[at + 8:at + 8 + n]
        assert zlib.crc32(kind + body) == int.from_bytes(data[at + 8 + n:at + 12 + n], "big")
        if kind == b"IDAT":
            idat += body
        at += 12 + n
    return zlib.decompress(idat)


def test_upscale_file_takes_the_command_lines_file_options(textured, tmp_path):
    image = (textured * 255).round().astype(np.uint8)
    _write_ppm(tmp_path / "in.ppm", image)
    small, fast = tmp_path / "small.tif", tmp_path / "fast.tif"
    ddtscale.upscale_file(tmp_path / "in.ppm", small, 2, compression="zip:9", quiet=True)
    ddtscale.upscale_file(tmp_path / "in.ppm", fast, 2, compression="none", no_stream=True, quiet=True)
    assert os.path.getsize(small) < os.path.getsize(fast)
    half, full = tmp_path / "half.exr", tmp_path / "full.exr"
    ddtscale.upscale_file(tmp_path / "in.ppm", half, 2, half=True, quiet=True)
    ddtscale.upscale_file(tmp_path / "in.ppm", full, 2, float=True, quiet=True)
    assert os.path.getsize(half) < os.path.getsize(full)
    # PNG: the default (igzip) and zlib's levels, the same pixels.
    ddtscale.upscale_file(tmp_path / "in.ppm", tmp_path / "small.png", 2, quiet=True)
    png_in = tmp_path / "small.png"
    ddtscale.upscale_file(png_in, tmp_path / "fast.png", 2, compression="fast:sub", quiet=True)
    ddtscale.upscale_file(png_in, tmp_path / "zlib.png", 2, compression="9:sub", quiet=True)
    assert _png_image_data(tmp_path / "fast.png") == _png_image_data(tmp_path / "zlib.png")  # the same filtered rows
    assert open(tmp_path / "fast.png", "rb").read() != open(tmp_path / "zlib.png", "rb").read()
    for options, message in [(dict(quality=0), "--quality"), (dict(compression="zip"), "--compression"),
                             (dict(compression="1:up:zigzag"), "unknown zlib strategy"),
                             (dict(compression="fast:adaptive"), "fast takes a filter only"),
                             (dict(half=True, float=True), "--half"), (dict(tile_size=8), "--tile-size"),
                             (dict(compare="bicubic"), "unknown option 'compare'"),
                             (dict(max_input_pixels=100), "--max-input-pixels"),
                             (dict(max_memory="10M"), "give --max-memory"),
                             (dict(max_memory="2Q"), "not a memory size"), (dict(max_memory=-5), "--max-memory")]:
        with pytest.raises((ValueError, OSError), match=message):
            ddtscale.upscale_file(tmp_path / "in.ppm", tmp_path / "bad.png", 2, **options)
        assert not (tmp_path / "bad.png").exists()


def test_version_is_the_command_line_s(cli):
    out = subprocess.run([cli, "--version"], capture_output=True, text=True, check=True).stdout
    assert re.fullmatch(r"\d+\.\d+\.\d+", ddtscale.__version__)
    assert out.startswith("ddtscale " + ddtscale.__version__ + " (")
