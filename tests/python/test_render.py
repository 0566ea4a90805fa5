"""multiray.render and multiray.Renderer against the CLI's `render`."""
import signal
import subprocess
import sys
import threading
import time

import numpy as np
import pytest

import multiray
from conftest import SMALL


def test_default_scene_equals_cli_bit_for_bit(cli_render):
    stats, exr = cli_render
    frames = multiray.render(**SMALL)
    assert len(frames) == 1
    image = frames[0]["image"]
    assert image.dtype == np.float32 and image.shape == (54, 96, 3)
    expected = multiray.read_exr(str(exr))
    # Bit for bit: compare the float bits, so that NaNs and -0 count too.
    assert np.array_equal(image.view(np.uint32), expected.view(np.uint32))
    cli_frame = stats["frames"][0]
    assert frames[0]["stats"]["image_hash"] == cli_frame["image_hash"]
    assert multiray.image_hash(image) == cli_frame["image_hash"]
    # The same record as stats.json's (times differ, the fields do not).
    assert set(frames[0]["stats"]) == set(cli_frame)


def test_renderer_continues_frames_and_takes_a_camera():
    r = multiray.Renderer(**SMALL, devices="cpu:threads=1")
    assert r.scene and r.devices and r.next_frame == 0
    first = r.render()
    assert [f["frame"] for f in first] == [0] and r.next_frame == 1
    r.set_camera("0,1,4,0,1,0,0,1,0,40")
    moved = r.render(1)[0]
    assert moved["frame"] == 1
    assert not np.array_equal(moved["image"], first[0]["image"])
    r.set_camera(None)
    back = r.render(1)[0]  # the fixed path again: frame 0's camera and seed-driven noise
    assert back["image"].shape == first[0]["image"].shape
    assert r.render(0) == []


def test_balancer_defaults_to_auto_as_in_the_cli():
    # auto is resolved from the devices: one device has nothing to balance.
    one = multiray.Renderer(**SMALL, devices="cpu:threads=1")
    assert one.balancer.startswith("uniform:")
    two = multiray.Renderer(**SMALL, devices="cpu:threads=1,cpu:threads=1")
    assert two.balancer.startswith("hybrid:")
    assert multiray.Renderer(**SMALL, balancer="auto", devices="cpu:threads=1").balancer == (
        one.balancer
    )


def test_gil_released_while_rendering():
    """A Python thread keeps running while frames render (it could not with the GIL held)."""
    ticks = []
    stop = threading.Event()

    def tick():
        while not stop.is_set():
            ticks.append(time.monotonic())
            time.sleep(0.001)

    r = multiray.Renderer(res="160x90", spp=8, seed=1, devices="cpu:threads=1")
    thread = threading.Thread(target=tick)
    thread.start()
    try:
        start = time.monotonic()
        r.render(2)
        end = time.monotonic()
    finally:
        stop.set()
        thread.join()
    assert end - start > 0.05, "the render was too short to tell"
    inside = [t for t in ticks if start + 0.02 < t < end - 0.02]
    assert len(inside) >= 3, f"{len(inside)} ticks in a {end - start:.3f} s render"


CHILD = """
import signal, sys, multiray
signal.signal(signal.SIGINT, signal.default_int_handler)  # inherited ignored in background jobs
r = multiray.Renderer(res="32x18", spp=1, devices="cpu:threads=1")
print("start", flush=True)
try:
    r.render(10**6)
except KeyboardInterrupt:
    print("interrupted", r.next_frame, flush=True)
"""


def test_ctrl_c_stops_a_render_between_frames():
    child = subprocess.Popen([sys.executable, "-c", CHILD], stdout=subprocess.PIPE, text=True)
    try:
        assert child.stdout.readline().strip() == "start"
        time.sleep(0.3)
        child.send_signal(signal.SIGINT)
        out, _ = child.communicate(timeout=30)
    finally:
        child.kill()
    assert out.startswith("interrupted"), out
    assert child.returncode == 0
