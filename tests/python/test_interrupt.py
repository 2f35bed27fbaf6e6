# Ctrl-C (SIGINT) stops a long ddtscale call with KeyboardInterrupt before
# it ends, and the module works again after it (issue 19).
import os
import signal
import subprocess
import sys
import textwrap

import numpy as np
import pytest

# The child logs each stage (verbose=True) on stderr; the parent sends SIGINT
# once the triangulation is logged, while the optimizer works through a
# million noisy points (seconds). An uninterruptible call would go on to
# log its render and, for upscale_file, write its output.
CHILD = textwrap.dedent(
    """
    import sys
    import numpy as np
    import ddtscale
    mode, path = sys.argv[1], sys.argv[2]
    image = np.random.default_rng(3).random((1024, 1024)).astype(np.float32)
    try:
        if mode == "array":
            ddtscale.upscale(image, 4, model="point", verbose=True)
        else:
            ddtscale.upscale_file(path + "/in.pgm", path + "/out.pgm", 4, model="point", verbose=True)
        print("finished", flush=True)
    except KeyboardInterrupt:
        print("interrupted", flush=True)
    print("again", ddtscale.upscale(np.eye(8), 2).shape, flush=True)
    """
)


@pytest.mark.parametrize("mode", ["array", "file"])
def test_sigint_stops_a_long_call(mode, tmp_path):
    if mode == "file":
        noise = (np.random.default_rng(3).random((1024, 1024)) * 255).astype(np.uint8)
        (tmp_path / "in.pgm").write_bytes(b"P5 1024 1024 255\n" + noise.tobytes())
    child = subprocess.Popen(
        [sys.executable, "-c", CHILD, mode, str(tmp_path)],
        stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, env=os.environ,
    )
    try:
        logged = []
        for line in child.stderr:
            logged.append(line)
            if line.startswith("triangulate"):
                child.send_signal(signal.SIGINT)
                break
        out, err = child.communicate(timeout=300)
    finally:
        child.kill()
    logged.append(err)
    assert any(line.startswith("triangulate") for line in logged), "".join(logged)
    assert child.returncode == 0, "".join(logged)
    lines = out.split("\n")
    assert "interrupted" in lines and "finished" not in lines
    assert "render" not in "".join(logged)
    assert "again (16, 16)" in lines
    assert not (tmp_path / "out.pgm").exists()
