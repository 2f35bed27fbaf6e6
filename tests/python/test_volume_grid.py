# ddtscale.upscale_volume and ddtscale.grid: samples and planes reproduced,
# dtypes kept, bad input refused.
import numpy as np
import pytest

import ddtscale


def test_volume_reproduces_its_samples_and_keeps_the_dtype():
    rng = np.random.default_rng(5)
    volume = (rng.random((6, 7, 8)) * 200).astype(np.uint8)  # z, y, x
    for method in ("ddt", "delaunay"):
        out = ddtscale.upscale_volume(volume, 3, method=method)
        assert out.shape == (18, 21, 24) and out.dtype == np.uint8
        # Voxel 3i + 1 samples voxel i at its centre; values are not rescaled.
        np.testing.assert_array_equal(out[1::3, 1::3, 1::3], volume)


def test_volume_render_cubic_by_default_linear_on_request():
    z, y, x = np.mgrid[0:8, 0:8, 0:8].astype(np.float32)
    volume = np.exp(-((x - 3.5) ** 2 + (y - 3.2) ** 2 + (z - 3.9) ** 2) / 8).astype(np.float32)
    cubic = ddtscale.upscale_volume(volume, 2)
    np.testing.assert_array_equal(cubic, ddtscale.upscale_volume(volume, 2, render="cubic", slopes="mc4"))
    linear = ddtscale.upscale_volume(volume, 2, render="linear")
    assert np.abs(cubic - linear).max() > 1e-3
    with pytest.raises(ValueError, match="render"):
        ddtscale.upscale_volume(volume, 2, render="quintic")


def test_volume_size_is_z_y_x_and_int16_keeps_its_range():
    volume = np.full((4, 5, 6), -1000, np.int16)
    volume[2:] = 3000
    out = ddtscale.upscale_volume(volume, size=(8, 10, 12))
    assert out.shape == (8, 10, 12) and out.dtype == np.int16
    assert out.min() == -1000 and out.max() == 3000


@pytest.mark.parametrize("array,kwargs,message", [
    (np.zeros((4, 4)), dict(scale=2), "3 dimensions|2 dimensions"),
    (np.zeros((0, 4, 4)), dict(scale=2), "empty"),
    (np.zeros((4, 4, 4), np.complex64), dict(scale=2), "complex64"),
    (np.full((3, 3, 3), np.nan), dict(scale=2), "NaN"),
    (np.zeros((4, 4, 4)), dict(scale=2, method="sinc"), "--method"),
    (np.zeros((4, 4, 4)), dict(scale=2, max_voxels=100), "--max-voxels"),
    (np.zeros((4, 4, 4)), dict(), "give the magnification"),
])
def test_bad_volumes_raise_value_error(array, kwargs, message):
    with pytest.raises(ValueError, match=message):
        ddtscale.upscale_volume(array, **kwargs)


def test_grid_reproduces_a_plane_inside_the_hull():
    rng = np.random.default_rng(11)
    points = rng.random((300, 2)) * 100
    values = 2 * points[:, 0] - 3 * points[:, 1] + 5
    out = ddtscale.grid(points, values, (40, 50), bounds=(0, 0, 100, 100))
    assert out.shape == (40, 50) and out.dtype == np.float64
    x = (np.arange(50) + 0.5) * 2
    y = 100 - (np.arange(40) + 0.5) * 2.5  # row 0 is the top
    plane = 2 * x[None, :] - 3 * y[:, None] + 5
    inside = ~np.isnan(out)
    assert inside.sum() > 0.8 * out.size
    np.testing.assert_allclose(out[inside], plane[inside], atol=1e-3 * np.abs(plane).max())
    assert np.isnan(out[~inside]).all()


def test_grid_channels_alpha_and_duplicates():
    points = np.array([[0, 0], [1, 0], [0, 1], [1, 1], [1, 1]], float)
    values = np.array([[0, 1], [1, 1], [1, 1], [2, 1], [4, 1]], np.float32)  # the last two merge: 3
    out = ddtscale.grid(points, values, 8, alpha=True, nodata=0)
    assert out.shape == (8, 8, 3) and out.dtype == np.float32
    assert (out[..., 2] == 1).all()
    np.testing.assert_allclose(out[..., 1], 1, atol=1e-6)
    assert abs(out[0, -1, 0] - 3) < 0.5  # top right corner is (1, 1)


@pytest.mark.parametrize("points,values,kwargs,message", [
    (np.zeros((3, 3)), np.zeros(3), {}, "N x 2"),
    (np.zeros((3, 2)), np.zeros(4), {}, "one row per point"),
    (np.array([[0, 0], [1, 0], [np.nan, 1]]), np.zeros(3), {}, "NaN"),
    (np.array([[0, 0], [1, 0], [0, 1]]), np.array([0, 1, np.inf]), {}, "NaN or infinite"),
    (np.array([[0, 0], [1, 0], [0, 1]]), np.zeros(3), dict(bounds=(1, 0, 0, 1)), "--bounds"),
    (np.array([[0, 0], [1, 0], [0, 1]]), np.zeros(3), dict(cost_channel=2), "--cost-channel"),
    (np.array([[0, 0], [1, 1], [2, 2]]), np.zeros(3), {}, "line|collinear|points"),
])
def test_bad_points_raise_value_error(points, values, kwargs, message):
    with pytest.raises(ValueError, match=message):
        ddtscale.grid(points, values, 8, **kwargs)
