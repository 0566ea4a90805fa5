"""Bad arguments raise Python exceptions with the CLI's messages; none crashes."""
import numpy as np
import pytest

import multiray
from conftest import run_cli

# Each a bad value build_run refuses, as keyword argument and as the CLI's option.
BAD = [
    (dict(res="0x5"), ["--res", "0x5"]),
    (dict(spp=-1), ["--spp", "-1"]),
    (dict(devices="gpu9"), ["--devices", "gpu9"]),
    (dict(balancer="nonesuch"), ["--balancer", "nonesuch"]),
    (dict(scene="/nonexistent/scene.obj"), ["/nonexistent/scene.obj"]),
]


@pytest.mark.parametrize("kwargs,args", BAD, ids=[a[0] for _, a in BAD])
def test_value_error_has_the_cli_message(cli, tmp_path, kwargs, args):
    res = [] if "res" in kwargs else ["--res", "8x8"]
    code, err = run_cli(cli, "render", *res, *args, "-o", str(tmp_path / "out"))
    assert code == 2
    prefix = "multiray: error: "
    assert err.startswith(prefix), err
    with pytest.raises(ValueError) as e:
        multiray.Renderer(**{"res": "8x8", **kwargs})
    assert str(e.value) == err[len(prefix):].strip()


@pytest.mark.parametrize("kwargs", [dict(spp="many"), dict(res=[1, 2]), dict(frames=True),
                                    dict(perturb=[1]), dict(allow_outside_paths=1)])
def test_wrong_types_raise_type_error(kwargs):
    with pytest.raises(TypeError):
        multiray.Renderer(**kwargs)


def test_unknown_and_hostile_arguments():
    with pytest.raises(TypeError, match="unexpected keyword argument 'sp'"):
        multiray.render(sp=4)
    with pytest.raises(ValueError, match="out of range"):
        multiray.Renderer(spp=1 << 70)
    with pytest.raises(ValueError):
        multiray.Renderer(spp=1 << 40)
    with pytest.raises(ValueError):
        multiray.Renderer(res="8x8", camera="1,2,3")
    r = multiray.Renderer(res="8x8", spp=1, devices="cpu:threads=1")
    with pytest.raises(ValueError):
        r.set_camera("not a camera")
    with pytest.raises(ValueError):
        r.render(-1)
    with pytest.raises(TypeError):
        r.render("2")
    with pytest.raises(ValueError):
        multiray.read_exr("/nonexistent.exr")
    with pytest.raises(TypeError):
        multiray.image_hash(np.zeros((2, 2, 3), np.float64))
    with pytest.raises(ValueError):
        multiray.image_hash(np.zeros((2, 2), np.float32))
