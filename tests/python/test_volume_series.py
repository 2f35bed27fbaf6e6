# ddtscale.upscale_volume on series (T x Z x Y x X): node-centred time, every
# input step kept, the classic series methods, bad input refused.
import numpy as np
import pytest

import ddtscale


def moving_ball(t_steps=5, n=8):
    t, z, y, x = np.mgrid[0:t_steps, 0:n, 0:n, 0:n].astype(np.float32)
    return ((x - 2.5 - 0.8 * t) ** 2 + (y - 3.5) ** 2 + (z - 3.7) ** 2 < 6.5).astype(np.float32)


def test_series_keeps_every_input_step_and_sample():
    series = moving_ball()
    out = ddtscale.upscale_volume(series, 3, time_scale=2)
    assert out.shape == (9, 24, 24, 24) and out.dtype == np.float32
    # Output step 2k is input step k (instants); voxel 3i + 1 samples voxel i.
    np.testing.assert_array_equal(out[::2, 1::3, 1::3, 1::3], series)


def test_series_sizes_scale_time_scale_and_cells():
    series = moving_ball(t_steps=4, n=6)
    assert ddtscale.upscale_volume(series, 2).shape == (7, 12, 12, 12)  # --scale on every axis
    assert ddtscale.upscale_volume(series, time_scale=4, method="quadrilinear").shape == (13, 6, 6, 6)
    assert ddtscale.upscale_volume(series, size=(5, 7, 8, 9), method="tricubic-linear").shape == (5, 7, 8, 9)
    assert ddtscale.upscale_volume(series, size=(7, 8, 9), time_scale=2, render="linear").shape == (7, 7, 8, 9)
    assert ddtscale.upscale_volume(series, 2, node_centred_time=False, method="delaunay").shape == (8, 12, 12, 12)


def test_series_linear_field_is_exact_for_every_method():
    t, z, y, x = np.mgrid[0:4, 0:4, 0:5, 0:6].astype(np.float64)
    series = 0.1 + 0.02 * x - 0.03 * y + 0.01 * z + 0.05 * t
    for method in ("ddt", "delaunay", "quadrilinear"):
        out = ddtscale.upscale_volume(series, 3, time_scale=2, method=method)
        T = np.arange(out.shape[0])[:, None, None, None] / 2.0
        Z = np.clip((np.arange(out.shape[1]) + 0.5) / 3 - 0.5, 0, 3)[None, :, None, None]
        Y = np.clip((np.arange(out.shape[2]) + 0.5) / 3 - 0.5, 0, 4)[None, None, :, None]
        X = np.clip((np.arange(out.shape[3]) + 0.5) / 3 - 0.5, 0, 5)[None, None, None, :]
        np.testing.assert_allclose(out, 0.1 + 0.02 * X - 0.03 * Y + 0.01 * Z + 0.05 * T, atol=3e-6)


def test_series_fractional_time_scale_samples_the_instants_g_over_t():
    # As image sequences count frames: 4 steps at 2.4 become floor(3 * 2.4) + 1 = 8, step g at instant g / 2.4.
    t, z, y, x = np.mgrid[0:4, 0:3, 0:3, 0:4].astype(np.float64)
    series = 0.1 + 0.02 * x - 0.03 * y + 0.01 * z + 0.05 * t
    for method in ("ddt", "quadrilinear"):
        out = ddtscale.upscale_volume(series, 1, time_scale=2.4, method=method)
        assert out.shape == (8, 3, 3, 4)
        T = np.arange(8)[:, None, None, None] / 2.4
        np.testing.assert_allclose(out, 0.1 + 0.02 * x[0] - 0.03 * y[0] + 0.01 * z[0] + 0.05 * T, atol=3e-6)


@pytest.mark.parametrize("array,kwargs,message", [
    (np.zeros((3, 3, 3, 3), np.float32), dict(scale=2, time_scale=-1), "time-scale"),
    (np.zeros((3, 3, 3), np.float32), dict(scale=2, time_scale=2), "series"),
    (np.zeros((3, 3, 3, 3), np.float32), dict(scale=2, method="lanczos"), "quadrilinear"),
    (np.zeros((3, 3, 3, 3, 3), np.float32), dict(scale=2), "T x Z x Y x X"),
    (np.zeros((3, 3, 3, 3), np.float32), dict(size=(4, 6, 6, 6), time_scale=2), "steps"),
])
def test_series_bad_input(array, kwargs, message):
    with pytest.raises(ValueError, match=message):
        ddtscale.upscale_volume(array, **kwargs)
