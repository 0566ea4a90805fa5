"""Renderer.set_transfer_function: a volume's transfer function changed between frames
from Python renders what the CLI's --tf renders (preset and JSON), and bad ones raise."""
import json

import numpy as np
import pytest

import multiray
from conftest import run_cli

TF = {"name": "red", "units": "fraction", "points": [
    {"value": 0, "color": [0, 0, 0], "opacity": 0},
    {"value": 1, "color": [1, 0.2, 0.1], "opacity": 0.6}]}


@pytest.fixture
def ball(tmp_path):
    """A 24^3 uint8 raw volume: a ball of 200 in zeros."""
    z, y, x = np.mgrid[0:24, 0:24, 0:24]
    data = np.where((x - 11.5) ** 2 + (y - 11.5) ** 2 + (z - 11.5) ** 2 < 64, 200, 0)
    path = tmp_path / "ball.raw"
    path.write_bytes(data.astype(np.uint8).tobytes())
    return str(path)


ARGS = dict(raw="24x24x24:uint8", res="40x30", seed=3)


def cli_hash(cli, tmp_path, ball, tf):
    out = tmp_path / ("out-" + tf.replace("/", "_"))
    code, err = run_cli(cli, "render", ball, "--raw", ARGS["raw"], "--res", ARGS["res"],
                        "--seed", "3", "--tf", tf, "--quiet", "-o", str(out), "--overwrite")
    assert code == 0, err
    with open(out / "stats.json") as f:
        return json.load(f)["frames"][0]["image_hash"]


def test_transfer_functions_set_between_frames_equal_the_clis(cli, tmp_path, ball):
    tf_file = tmp_path / "red.json"
    tf_file.write_text(json.dumps(TF))
    r = multiray.Renderer(scene=ball, tf="grey", **ARGS)
    grey = r.render(1)[0]["stats"]["image_hash"]
    assert grey == cli_hash(cli, tmp_path, ball, "grey")
    grey_frame1 = r.render(1)[0]["stats"]["image_hash"]
    # Each against the CLI's frame 0: a fresh Renderer per transfer function.
    for tf, expected_from in (("angio", "angio"), (TF, str(tf_file))):
        fresh = multiray.Renderer(scene=ball, tf="grey", **ARGS)
        fresh.set_transfer_function(tf)
        got = fresh.render(1)[0]["stats"]["image_hash"]
        assert got == cli_hash(cli, tmp_path, ball, expected_from)
        assert got != grey
        fresh.set_transfer_function(None)  # back to --tf
        assert fresh.render(1)[0]["stats"]["image_hash"] == grey_frame1


def test_bad_transfer_functions_raise(ball):
    r = multiray.Renderer(scene=ball, **ARGS)
    with pytest.raises(ValueError, match="unknown transfer function|transfer"):
        r.set_transfer_function("nonesuch")
    with pytest.raises(ValueError):
        r.set_transfer_function({"points": [{"value": 0, "color": [0, 0, 0], "opacity": 2}]})
    with pytest.raises(TypeError):
        r.set_transfer_function(3)
    with pytest.raises(ValueError, match="not a volume"):
        multiray.Renderer(res="8x8").set_transfer_function("angio")
    assert len(r.render(1)) == 1
