#!/usr/bin/env python3
"""ddtscale.dask.upscale against the in-process call on a large image.

    PYTHONPATH=build/python python3 bench/dask_bands.py [--tiles 6] [--scale 2] [--workers 2] [--band-rows N]
        [--model box]

The image: images/astronaut_face.png mirrored into a 256 x 256 tile,
repeated tiles x tiles times (6: 1536 x 1536 RGB, uint8). Runs
ddtscale.upscale(image, scale, model=MODEL) in this process and
ddtscale.dask.upscale on a distributed.LocalCluster of --workers worker
processes (one thread each, threads=1), and prints the optimizer's phases,
the bands, the margin, both wall times and the number of output samples
that differ (0: bit for bit).
"""

import argparse
import os
import subprocess
import tempfile
import time

import numpy as np

import ddtscale
import ddtscale.dask as ddask
import dask.array as da
import distributed

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def tile_image(tiles):
    with tempfile.TemporaryDirectory() as work:
        ppm = os.path.join(work, "face.ppm")
        subprocess.run(["oiiotool", os.path.join(ROOT, "images", "astronaut_face.png"), "--ch", "R,G,B",
                        "-d", "uint8", "-o", ppm], check=True)
        data = open(ppm, "rb").read()
    fields = data.split(maxsplit=4)
    w, h = int(fields[1]), int(fields[2])
    face = np.frombuffer(fields[4], np.uint8)[: w * h * 3].reshape(h, w, 3)
    tile = np.concatenate([face, face[:, ::-1]], 1)
    tile = np.concatenate([tile, tile[::-1]], 0)
    return np.ascontiguousarray(np.tile(tile, (tiles, tiles, 1)))


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--tiles", type=int, default=6)
    parser.add_argument("--scale", type=float, default=2)
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument("--band-rows", type=int, help="input rows per band (default: ddtscale.dask's)")
    parser.add_argument("--model", default="box", help="acquisition model (default: box, the library's)")
    args = parser.parse_args()
    image = tile_image(args.tiles)
    options = dict(model=args.model, threads=1)
    phases = []
    start = time.perf_counter()
    expected = ddtscale.upscale(image, args.scale, **options)
    in_process = time.perf_counter() - start
    out_size = tuple(expected.shape[:2])
    bands, margin = ddask.band_plan(image.shape, options, args.band_rows, None, out_size)
    with distributed.LocalCluster(n_workers=args.workers, threads_per_worker=1, dashboard_address=None) as cluster, \
            distributed.Client(cluster) as client:
        result = ddask.upscale(da.from_array(image), args.scale, band_rows=args.band_rows, **options)
        start = time.perf_counter()
        computed = client.compute(result).result()
        blocked = time.perf_counter() - start
    regions = ddtscale._ddtscale.region_rows(image.shape[1], image.shape[0], options)
    print(f"image {image.shape[1]}x{image.shape[0]}x3 uint8 x{args.scale:g}, regions of {regions} rows, "
          f"bands {bands}, margin {margin} rows, load {os.getloadavg()[0]:.2f}")
    print(f"in-process (1 thread): {in_process:.2f} s; dask on {args.workers} worker processes: {blocked:.2f} s")
    print(f"differing output samples: {np.count_nonzero(computed != expected)} of {expected.size}")


if __name__ == "__main__":
    main()
