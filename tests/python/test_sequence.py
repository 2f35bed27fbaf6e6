# ddtscale.upscale_sequence: frame-rate upsampling on numpy arrays.
import re
import subprocess

import numpy as np
import pytest

import ddtscale


def moving_edge(frames, step, shape=(16, 24), dtype=np.uint8):
    out = np.zeros((frames,) + shape, dtype)
    top = np.iinfo(dtype).max if np.issubdtype(dtype, np.integer) else 1.0
    for t in range(frames):
        out[t, :, 4 + step * t:] = top
    return out


def test_frames_kept_and_counted_dtype_kept():
    for dtype in (np.uint8, np.uint16, np.float32, np.float64):
        f = moving_edge(3, 3, dtype=dtype)
        out = ddtscale.upscale_sequence(f, 4)
        assert out.shape == (9, 16, 24) and out.dtype == dtype
        assert (out[::4] == f).all()


def test_the_edge_moves_between_the_frames_instead_of_fading():
    f = moving_edge(2, 4)  # the edge at x = 4, then x = 8
    mid = ddtscale.upscale_sequence(f, 2)[1]
    row = mid[8].astype(float) / 255
    assert row[:5].max() < 0.05 and row[7:].min() > 0.95  # a step at x = 6, not two half steps
    blend = (f[0].astype(float) + f[1]) / 2 / 255
    assert abs(blend[8, 5] - 0.5) < 0.01  # what blending would show there


def test_a_frame_rate_ratio_makes_the_frames_at_its_instants():
    f = moving_edge(5, 2)  # 24 to 60 frames a second: 4 x 2.5 + 1 = 11 frames
    out = ddtscale.upscale_sequence(f, 60 / 24)
    assert out.shape == (11, 16, 24)
    assert (out[::5] == f[::2]).all()  # output frame 5 k is the instant 2 k
    with pytest.raises(ValueError, match="time-scale"):
        ddtscale.upscale_sequence(f, 0.0)


def test_colour_space_scale_and_size():
    f = np.stack([moving_edge(3, 2)] * 3, axis=-1)
    assert ddtscale.upscale_sequence(f, 2, scale=2).shape == (5, 32, 48, 3)
    assert ddtscale.upscale_sequence(f, 3, size=(20, 30)).shape == (7, 20, 30, 3)
    assert ddtscale.upscale_sequence(f[:, ::-1], 2).shape == (5, 16, 24, 3)  # negative strides accepted


def test_a_given_zoom_keeps_the_frames_and_a_linear_field():
    # A field linear in x, y and t is rebuilt exactly on any valid mesh: the
    # mesh carried along a zoom of 6 % a frame and a shift too.
    t, y, x = np.meshgrid(np.arange(4.0), np.arange(12.0), np.arange(16.0), indexing="ij")
    f = (0.1 + 0.02 * x + 0.03 * y + 0.05 * t).astype(np.float32)
    out = ddtscale.upscale_sequence(f, 2, motion="0.5,-0.25,1.06")
    assert out.shape == (7, 12, 16)
    assert (out[::2] == f).all()
    truth = (0.1 + 0.02 * x[0] + 0.03 * y[0] + 0.05 * 0.5)
    assert np.abs(out[1] - truth).max() < 2e-6
    with pytest.raises(ValueError, match="ZOOM"):
        ddtscale.upscale_sequence(f, 2, motion="0,0,3")


@pytest.mark.parametrize("frames,kwargs,message", [
    (np.zeros((0, 8, 8), np.uint8), {}, "no frames"),
    (np.zeros((8, 8), np.uint8), {}, "dimensions"),
    (np.zeros((2, 8, 8), np.uint8), dict(time_scale=0), "--time-scale"),
    (np.zeros((2, 8, 8), np.uint8), dict(presmooth=-1), "--presmooth"),
    (np.zeros((2, 8, 8), np.uint8), dict(method="tricubic"), "--method"),
    (np.zeros((2, 8, 8), np.uint8), dict(nope=1), "nope"),
    (np.full((2, 8, 8), np.nan, np.float32), {}, "NaN"),
    (np.zeros((2, 8, 8), np.uint8), dict(motion="fast"), "--motion"),
])
def test_bad_input_raises_value_error(frames, kwargs, message):
    time_scale = kwargs.pop("time_scale", 2)
    with pytest.raises(ValueError, match=re.escape(message)):
        ddtscale.upscale_sequence(frames, time_scale, **kwargs)


def test_options_match_the_command_line(cli):
    out = subprocess.run([cli, "in_%04d.png", "out_%04d.png", "--help"], capture_output=True, text=True,
                         check=True).stdout
    flags = set(re.findall(r"^\s+(?:-\w,)?--([a-z][a-z0-9-]*)", out, re.MULTILINE))
    # positional or per call: time-scale, scale, size; how files and videos are encoded
    not_keywords = {"help", "time-scale", "scale", "size", "compression", "quality", "half", "float", "tile-size",
                    "quiet", "fps", "crf", "slow-motion"}
    assert flags - not_keywords == {k.replace("_", "-") for k in ddtscale.SEQUENCE_OPTIONS}
    assert ddtscale.upscale_sequence.__doc__ and "presmooth" in ddtscale.upscale_sequence.__doc__


def test_presmooth_by_default_narrows_along_a_motion_and_a_given_sigma_holds():
    assert ddtscale.SEQUENCE_OPTIONS["presmooth"] is None
    f = np.random.default_rng(5).random((3, 24, 32)).astype(np.float32)
    along = ddtscale.upscale_sequence(f, 4, motion="3,0")
    assert (along == ddtscale.upscale_sequence(f, 4, motion="3,0", presmooth=0.5)).all()
    assert not (along == ddtscale.upscale_sequence(f, 4, motion="3,0", presmooth=1)).all()
    lattice = ddtscale.upscale_sequence(f, 4, motion="off")
    assert (lattice == ddtscale.upscale_sequence(f, 4, motion="off", presmooth=1)).all()
