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


def test_a_device_failure_raises_runtime_error_with_the_cli_message(cli, tmp_path):
    """Every device of the run failed: the CLI exits non-zero with one line, Python raises
    RuntimeError (multiray's DeviceError) with the same line."""
    # Frame 0 is one item; the device fails on frame 1's.
    args = ["--res", "32x18", "--spp", "1", "--frames", "2", "--quiet", "--devices",
            "cpu:threads=1:fail_after=1"]
    code, err = run_cli(cli, "render", *args, "-o", str(tmp_path / "out"))
    prefix = "multiray: device error: "
    assert code == 3 and err.startswith(prefix) and err.count("\n") == 1, err
    r = multiray.Renderer(res="32x18", spp=1, frames=2, devices="cpu:threads=1:fail_after=1")
    with pytest.raises(RuntimeError) as e:
        r.render()
    assert str(e.value) == err[len(prefix):].strip()


def test_render_refuses_frames_that_would_not_fit_max_memory():
    """render(n) copies n frames into NumPy: counted against max_memory before rendering."""
    r = multiray.Renderer(res="640x360", spp=1, max_memory="64M", devices="cpu:threads=1")
    with pytest.raises(ValueError, match="frames returned to Python.*--max-memory"):
        r.render(100)  # 100 x 2.8 MB
    assert r.next_frame == 0  # nothing rendered


def test_an_interpreter_without_numpy_fails_at_import_naming_both():
    """Issue 51 item 5: a python3 without numpy (a pyenv or virtualenv one first on PATH)
    fails at `import multiray` in one line naming the interpreter it was built for, not
    later with a bare "No module named 'numpy'"."""
    import subprocess
    import sys

    code = "import sys; sys.modules['numpy'] = None; import multiray"
    p = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=60)
    assert p.returncode != 0
    last = p.stderr.strip().splitlines()[-1]
    assert last.startswith("ImportError: multiray was built for ")
    assert "needs numpy" in last and sys.executable in last


def test_a_mistyped_keyword_gets_the_nearest_one():
    """Issue 51 item 5: keyword typos get "did you mean", as the CLI's option typos do."""
    import multiray

    with pytest.raises(TypeError, match=r"unexpected keyword argument 'sp' \(did you mean 'spp'\?\)"):
        multiray.render(sp=4)
    with pytest.raises(TypeError) as far:
        multiray.render(zzzzzz=4)
    assert "did you mean" not in str(far.value)
