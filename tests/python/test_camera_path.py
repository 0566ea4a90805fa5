"""Renderer.set_camera_path: a path set from Python renders what the CLI's --camera-path
renders (same frames, same hashes), and bad paths raise cleanly."""
import json
import math

import pytest

import multiray
from conftest import SMALL, run_cli

KEYS = [
    {"frame": 0, "eye": [0, 1, 4], "target": [0, 1, 0], "fov": 40},
    {"frame": 3, "eye": [2, 1.5, 3], "target": [0, 0.8, 0], "up": [0, 1, 0], "fov": 50},
]


def cli_hashes(cli, tmp_path, path_value):
    out = tmp_path / "out"
    code, err = run_cli(cli, "render", "--res", SMALL["res"], "--spp", str(SMALL["spp"]),
                        "--seed", str(SMALL["seed"]), "--frames", "3", "--camera-path",
                        path_value, "--quiet", "-o", str(out), "--overwrite")
    assert code == 0, err
    with open(out / "stats.json") as f:
        return [fr["image_hash"] for fr in json.load(f)["frames"]]


@pytest.mark.parametrize("form", ["list", "dict"])
def test_keyframes_from_python_equal_the_cli_file(cli, tmp_path, form):
    path_file = tmp_path / "path.json"
    path_file.write_text(json.dumps({"keyframes": KEYS}))
    expected = cli_hashes(cli, tmp_path, str(path_file))
    r = multiray.Renderer(**SMALL)  # its own path is the fixed camera
    r.set_camera_path(KEYS if form == "list" else {"keyframes": KEYS})
    got = [f["stats"]["image_hash"] for f in r.render(3)]
    assert got == expected
    assert len(set(got)) == 3  # the camera moved


def test_an_orbit_by_name_equals_the_cli_and_drops_a_set_camera(cli, tmp_path):
    expected = cli_hashes(cli, tmp_path, "orbit:8")
    r = multiray.Renderer(**SMALL)
    r.set_camera("0,1,4,0,1,0,0,1,0,40")
    r.set_camera_path("orbit:8")
    assert [f["stats"]["image_hash"] for f in r.render(3)] == expected


def test_bad_paths_raise_one_line():
    r = multiray.Renderer(**SMALL)
    with pytest.raises(TypeError):
        r.set_camera_path(42)
    with pytest.raises(TypeError):
        r.set_camera_path([{"frame": 0, "eye": object()}])
    with pytest.raises(ValueError):
        r.set_camera_path([{"frame": 0, "eye": [0, 1, math.nan], "target": [0, 0, 0]}])
    with pytest.raises(ValueError, match="keyframe 0: 'fov'"):
        r.set_camera_path([{"frame": 0, "eye": [0, 1, 4], "target": [0, 1, 0], "fov": 500}])
    with pytest.raises(ValueError, match="orbit period"):
        r.set_camera_path("orbit:0")
    with pytest.raises(ValueError, match="cannot open camera path"):
        r.set_camera_path("/nonexistent/path.json")
    for bad in ([], {"frames": []}):
        with pytest.raises(ValueError):
            r.set_camera_path(bad)
    assert len(r.render(1)) == 1  # still usable
