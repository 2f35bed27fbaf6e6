# pytest set-up for the Python module's tests (run by ctest: python_module).
# The module is imported from the build tree: PYTHONPATH=build/python.
import os
import shutil

import numpy as np
import pytest


@pytest.fixture
def textured():
    """A small colour image with edges, a ramp and noise (many flips)."""
    rng = np.random.default_rng(7)
    y, x = np.mgrid[0:40, 0:48]
    image = np.zeros((40, 48, 3))
    image[..., 0] = (x > 20) * 0.7 + 0.1
    image[..., 1] = x / 47.0
    image[..., 2] = ((x - 24) ** 2 + (y - 20) ** 2 < 120) * 0.8
    image += rng.normal(0, 0.03, image.shape)
    return np.clip(image, 0, 1)


@pytest.fixture
def cli():
    """The command line binary (DDTSCALE_CLI, as ctest sets it), or skip."""
    path = os.environ.get("DDTSCALE_CLI") or shutil.which("ddtscale")
    if not path or not os.path.exists(path):
        pytest.skip("the ddtscale binary is not known (set DDTSCALE_CLI)")
    return path
