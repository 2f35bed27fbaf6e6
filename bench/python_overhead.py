#!/usr/bin/env python3
"""The Python module's overhead against the command line on the same image.

    PYTHONPATH=build/python python3 bench/python_overhead.py [--input IMG] [--scale 4] [--runs 5]

Measures, interleaved, --runs times each (medians):
  cli            `ddtscale IN OUT --scale S -q`, a child process (wall time, peak memory by GNU time)
  python process `python3 -c "import ddtscale; ddtscale.upscale_file(IN, OUT, S)"`, a child
                 process: the same start, read, work and write, through the module
  python file    ddtscale.upscale_file(IN, OUT, S) in this process (module imported once)
  python array   ddtscale.upscale(array, S): the numpy path, no files (array in and out)
and prints their ratios to the CLI's time. Target (issue 19): python process <= 1.05 x cli.
The default input is a 512x512 RGB PNG made from images/astronaut_face.png
(mirrored 4x4 by oiiotool), enlarged x4 into PNG.
"""

import argparse
import os
import resource
import statistics
import subprocess
import sys
import tempfile
import time

import numpy as np

import ddtscale

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def read_ppm(path):
    data = open(path, "rb").read()
    fields = data.split(maxsplit=4)
    w, h = int(fields[1]), int(fields[2])
    return np.frombuffer(fields[4], np.uint8)[: w * h * 3].reshape(h, w, 3)


def run_cli(cli, args):
    # Peak memory by GNU time's wait4 in a small process: a child forked from
    # this interpreter would inherit its high-water mark (ru_maxrss survives exec).
    with tempfile.NamedTemporaryFile("r") as report:
        start = time.perf_counter()
        status = subprocess.run(["/usr/bin/time", "-f", "%M", "-o", report.name, cli] + args).returncode
        elapsed = time.perf_counter() - start
        if status != 0:
            sys.exit(f"python_overhead: {cli} {' '.join(args)} failed")
        return elapsed, int(report.read().split()[-1]) / 1024


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--cli", default=os.path.join(ROOT, "build", "ddtscale"))
    parser.add_argument("--input", help="an RGB image (default: the astronaut mirrored to 512x512)")
    parser.add_argument("--scale", type=float, default=4)
    parser.add_argument("--runs", type=int, default=5)
    parser.add_argument("--threads", type=int, default=0)
    args = parser.parse_args()

    with tempfile.TemporaryDirectory() as work:
        source = args.input or os.path.join(work, "in.png")
        if not args.input:
            face = os.path.join(ROOT, "images", "astronaut_face.png")
            subprocess.run(["oiiotool", face, "--dup", "--flop", "--siappend", "--mosaic:pad=0", "2x1", "--dup",
                            "--flip", "--siappend", "--mosaic:pad=0", "1x2", "--dup", "--siappend",
                            "--mosaic:pad=0", "2x1", "--dup", "--siappend", "--mosaic:pad=0", "1x2",
                            "-o", source], check=True, capture_output=True)
        ppm = os.path.join(work, "in.ppm")
        subprocess.run(["oiiotool", source, "--ch", "R,G,B", "-d", "uint8", "-o", ppm], check=True)
        array = read_ppm(ppm)
        out_cli, out_py = os.path.join(work, "cli.png"), os.path.join(work, "py.png")
        options = dict(quiet=True, threads=args.threads)
        cli_args = [source, out_cli, "--scale", str(args.scale), "-q", "--threads", str(args.threads)]

        run_cli(args.cli, cli_args)  # warm the file cache and the module
        ddtscale.upscale(array[:8, :8], 2)
        times = {"cli": [], "python process": [], "python file": [], "python array": []}
        cli_memory, process_memory = [], []
        script = (f"import ddtscale; ddtscale.upscale_file({source!r}, {out_py!r}, {args.scale!r}, "
                  f"quiet=True, threads={args.threads})")
        for _ in range(args.runs):
            elapsed, memory = run_cli(args.cli, cli_args)
            times["cli"].append(elapsed)
            cli_memory.append(memory)
            elapsed, memory = run_cli(sys.executable, ["-c", script])
            times["python process"].append(elapsed)
            process_memory.append(memory)
            start = time.perf_counter()
            ddtscale.upscale_file(source, out_py, args.scale, **options)
            times["python file"].append(time.perf_counter() - start)
            start = time.perf_counter()
            out = ddtscale.upscale(array, args.scale, **options)
            times["python array"].append(time.perf_counter() - start)
        python_memory = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
        same = subprocess.run(["oiiotool", out_cli, out_py, "--diff"], capture_output=True).returncode == 0

    h, w = array.shape[:2]
    print(f"input {w}x{h} RGB uint8, x{args.scale:g} -> {out.shape[1]}x{out.shape[0]}, {args.runs} runs, "
          f"threads {args.threads or 'all'}, load {os.getloadavg()[0]:.2f}")
    print("| path | median s | min s | ratio to cli (median) |")
    print("|---|---|---|---|")
    cli = statistics.median(times["cli"])
    for name, values in times.items():
        m = statistics.median(values)
        print(f"| {name} | {m:.3f} | {min(values):.3f} | {m / cli:.3f} |")
    print(f"peak memory: cli {statistics.median(cli_memory):.0f} MB, python process "
          f"{statistics.median(process_memory):.0f} MB (child processes), this interpreter "
          f"{python_memory:.0f} MB (numpy, the module and every run)")
    print(f"python file output identical to the cli's: {same}")


if __name__ == "__main__":
    main()
