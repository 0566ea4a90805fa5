"""Fixtures of the multiray module's tests: the module from the build tree (PYTHONPATH,
set by ctest: tests/python/CMakeLists.txt) and the CLI beside it (MULTIRAY_CLI)."""
import json
import os
import subprocess

import pytest

# Small renders: the whole file runs in a few seconds on two shared cores.
SMALL = dict(res="96x54", spp=2, seed=7)


@pytest.fixture(scope="session")
def cli():
    path = os.environ.get("MULTIRAY_CLI")
    if not path or not os.access(path, os.X_OK):
        pytest.skip("MULTIRAY_CLI does not name the multiray program (set by ctest)")
    return path


def run_cli(cli, *args):
    """The CLI's exit code and stderr for `multiray ARGS`."""
    p = subprocess.run([cli, *args], capture_output=True, text=True, timeout=60)
    return p.returncode, p.stderr


@pytest.fixture(scope="session")
def cli_render(cli, tmp_path_factory):
    """The CLI's render of the default scene at SMALL: (stats.json, frame 0's EXR path)."""
    out = tmp_path_factory.mktemp("cli")
    code, err = run_cli(cli, "render", "--res", SMALL["res"], "--spp", str(SMALL["spp"]),
                        "--seed", str(SMALL["seed"]), "--exr", "--quiet", "-o", str(out),
                        "--overwrite", "--denoise", "none")
    assert code == 0, err
    with open(out / "stats.json") as f:
        stats = json.load(f)
    return stats, out / "frame_0000.exr"


@pytest.fixture(scope="session")
def trace(cli, tmp_path_factory):
    """A small trace recorded by the CLI: 4 frames of 64x36 on two one-thread CPUs."""
    d = tmp_path_factory.mktemp("trace")
    code, err = run_cli(cli, "render", "--res", "64x36", "--spp", "1", "--frames", "4",
                        "--devices", "cpu:threads=1,cpu:threads=1", "--balancer", "queue",
                        "--trace", str(d / "T"), "--out", str(d / "D"), "--quiet")
    assert code == 0, err
    return str(d / "T")
