# ddtscale.dask: bands of rows through map_overlap equal the in-process call
# bit for bit, on a real distributed.LocalCluster (scheduler and worker
# processes); batches of files through dask.bag.
import os

import numpy as np
import pytest

import ddtscale

da = pytest.importorskip("dask.array")
distributed = pytest.importorskip("distributed")
import ddtscale.dask as ddask  # noqa: E402


@pytest.fixture(scope="module")
def client():
    cluster = distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None)
    with distributed.Client(cluster) as c:
        yield c
    cluster.close()


def noisy(height, width, channels=None, seed=4):
    rng = np.random.default_rng(seed)
    shape = (height, width) + ((channels,) if channels else ())
    image = rng.random(shape) * 0.3
    image[:, width // 3:] += 0.6  # an edge through every band
    return image.astype(np.float32)


def test_bands_equal_the_in_process_call_on_a_cluster(client):
    image = noisy(150, 90, 3)
    options = dict(model="point", region_rows=8)  # small regions, so that bands cut many
    array = da.from_array(image, chunks=(40, 90, 3))
    for scale in (2.0, 2.5):
        result = ddask.upscale(array, scale, band_rows=40, **options)
        assert result.numblocks[0] > 1
        expected = ddtscale.upscale(image, scale, **options)
        computed = client.compute(result).result()
        assert computed.dtype == expected.dtype
        np.testing.assert_array_equal(computed, expected)


def test_bands_of_the_consistent_models_equal_the_in_process_call_on_a_cluster(client):
    # Tall enough for bands cut on both sides with the reconstruction's margins.
    image = (noisy(1200, 48, 3) * 255).astype(np.uint8)
    array = da.from_array(image, chunks=(100, 48, 3))
    for model, scale in (("box", 2.0), ("box", 2.5), ("bicubic", 2.0)):
        result = ddask.upscale(array, scale, model=model, region_rows=8, band_rows=96)
        assert result.numblocks[0] >= 3
        np.testing.assert_array_equal(client.compute(result).result(),
                                      ddtscale.upscale(image, scale, model=model, region_rows=8))


def test_uint8_bands_and_the_whole_image_fallback():
    image = (noisy(120, 64) * 255).astype(np.uint8)
    banded = ddask.upscale(da.from_array(image), 3, model="point", region_rows=8, render="linear", cost="variance",
                           band_rows=48, margin=48)
    assert banded.numblocks[0] > 1
    np.testing.assert_array_equal(banded.compute(scheduler="threads"),
                                  ddtscale.upscale(image, 3, model="point", region_rows=8, render="linear",
                                                   cost="variance"))
    # Without region_rows an image this small has no region schedule: one task, same result.
    whole = ddask.upscale(da.from_array(image, chunks=(30, 64)), 2)
    assert whole.numblocks == (1, 1)
    np.testing.assert_array_equal(whole.compute(scheduler="sync"), ddtscale.upscale(image, 2))


def test_a_too_narrow_margin_names_its_band_and_the_margin_needed():
    image = noisy(120, 64)
    result = ddask.upscale(da.from_array(image), 2, model="point", region_rows=16, band_rows=32, margin=2)
    with pytest.raises(ValueError, match=r"rows \d+\.\.\d+ of the image: .*give at least \d+ rows"):
        result.compute(scheduler="sync")


def test_band_plan_covers_the_image_in_whole_regions():
    options = dict(model="point", region_rows=8)
    for height in (100, 150, 161, 300):
        bands, margin = ddask.band_plan((height, 50), options, band_rows=40)
        assert sum(bands) == height
        assert all(b % 8 == 0 for b in bands[:-1]) and all(b >= margin for b in bands)
    # The consistent models take wider margins (their reach), annealing no bands.
    _, point_margin = ddask.band_plan((3000, 50), options)
    _, box_margin = ddask.band_plan((3000, 50), dict(options, model="box"))
    assert box_margin > point_margin
    with pytest.warns(UserWarning, match="one task"):
        assert ddask.band_plan((300, 50), dict(options, optimizer="anneal")) == ((300,), 0)


def test_bad_options_fail_before_any_task():
    with pytest.raises(ValueError, match="unknown cost"):
        ddask.upscale(da.zeros((10, 10)), 2, cost="nope")
    with pytest.raises(ValueError, match="int64"):
        ddask.upscale(da.zeros((10, 10), dtype=np.int64), 2)
    with pytest.raises(ValueError, match="compare and mesh"):
        ddask.upscale(da.zeros((10, 10)), 2, compare="bicubic")
    # width= alone: the height follows the aspect, as in ddtscale.upscale
    image = noisy(20, 30)
    np.testing.assert_array_equal(ddask.upscale(da.from_array(image), width=45).compute(scheduler="sync"),
                                  ddtscale.upscale(image, width=45))


def _write_pgm(path, image):
    with open(path, "wb") as f:
        f.write(b"P5\n%d %d\n255\n" % (image.shape[1], image.shape[0]) + image.tobytes())


def test_files_through_a_bag_on_the_cluster(client, tmp_path):
    image = (noisy(20, 24) * 255).astype(np.uint8)
    inputs = []
    for name in ("a", "b"):
        _write_pgm(tmp_path / f"{name}.pgm", image)
        inputs.append(str(tmp_path / f"{name}.pgm"))
    (tmp_path / "broken.pgm").write_bytes(b"P5\n")
    inputs.append(str(tmp_path / "broken.pgm"))
    outdir = tmp_path / "out"
    results = client.compute(ddask.upscale_files(inputs, str(outdir), 2, suffix="_x2", format="tif",
                                                 threads=1)).result()
    status = {os.path.basename(r["input"]): r for r in results}
    assert status["a.pgm"]["status"] == "done" and status["b.pgm"]["status"] == "done"
    assert status["broken.pgm"]["status"] == "failed" and "broken.pgm" in status["broken.pgm"]["error"]
    assert sorted(os.listdir(outdir)) == ["a_x2.tif", "b_x2.tif"]
    again = ddask.upscale_files(inputs[:1], str(outdir), 2, suffix="_x2", format="tif").compute(scheduler="sync")
    assert again[0]["status"] == "skipped"
