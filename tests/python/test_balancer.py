"""Balancers written in Python (multiray.Balancer): the Cycles twin of
examples/python/cycles_balancer.py against the C++ `cycles` on a recorded trace, rendering on
real devices through the engine, registration, the GIL, and hostile balancers."""
import os
import sys
import threading
import time

import pytest

import multiray
from conftest import run_cli

sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "..", "examples", "python"))
from cycles_balancer import Cycles  # noqa: E402

TINY = dict(res="64x36", spp=1, seed=7, devices="cpu:threads=1,cpu:threads=1")

if "pycycles" not in multiray.balancer_names():
    multiray.register_balancer("pycycles", Cycles, help="Cycles' balancer in Python",
                               params={"interval_ms": 1000.0})


@pytest.fixture(scope="module")
def trace(cli, tmp_path_factory):
    """A small recorded trace. The second device is emulated at half speed, so that the
    replayed devices differ and Cycles' weights move (with equal devices they never do)."""
    out = tmp_path_factory.mktemp("trace")
    code, err = run_cli(cli, "render", "--res", "64x36", "--spp", "1", "--frames", "6",
                        "--devices", "cpu:threads=1,cpu:threads=1:speed=0.5",
                        "--balancer", "queue", "--trace", str(out / "T"), "--out",
                        str(out / "D"), "--quiet")
    assert code == 0, err
    return multiray.read_trace(str(out / "T"))


def test_trace_reads(trace):
    assert len(trace) == 6 and trace.balancer.startswith("queue")
    assert [d["speed"] for d in trace.devices] == [1.0, 0.5]
    assert trace[0].shape.width == 64 and len(trace[-1].devices) == 2


@pytest.mark.parametrize("spec,kwargs", [("cycles", {}),
                                         ("cycles:interval_ms=0", {"interval_ms": 0.0})])
def test_cycles_twin_plans_equal_the_cpp_ones_exactly(trace, spec, kwargs):
    cpp = multiray.replay(trace, spec, frames=24)
    twin = multiray.replay(trace, Cycles(2, **kwargs), frames=24)
    assert len(cpp) == len(twin) == 24
    for a, b in zip(cpp, twin):
        # The same arithmetic in the same order: equal items and bit-equal ratios.
        assert a["plan"].assigned == b["plan"].assigned, a["frame"]
        assert a["plan"].ratios == b["plan"].ratios, a["frame"]
        assert a["plan"] == b["plan"] and a["times_ms"] == b["times_ms"]
        assert a["plan_ms"] >= 0 and b["update_ms"] >= 0
    if kwargs:  # the weights moved: the comparison is not between two even splits
        assert len({tuple(f["plan"].ratios) for f in cpp}) > 3
    # A registered Python balancer is a spec like any other.
    by_name = multiray.replay(trace, spec.replace("cycles", "pycycles"), frames=24)
    assert [f["plan"] for f in by_name] == [f["plan"] for f in cpp]


def test_python_balancer_renders_the_cpp_balancers_image():
    cpp = multiray.Renderer(**TINY, balancer="cycles:interval_ms=0").render(3)
    r = multiray.Renderer(**TINY, balancer="pycycles:interval_ms=0")
    assert r.balancer == "pycycles:interval_ms=0"
    py = r.render(3)
    for a, b in zip(cpp, py):
        assert multiray.image_hash(a["views"]) == multiray.image_hash(b["views"])
        assert b["stats"]["image_hash"] == a["stats"]["image_hash"]


def test_registration_errors():
    with pytest.raises(ValueError, match="already registered"):
        multiray.register_balancer("cycles", Cycles)
    with pytest.raises(ValueError, match="already registered"):
        multiray.register_balancer("pycycles", Cycles)
    with pytest.raises(ValueError):
        multiray.register_balancer("a:b=1", Cycles)
    with pytest.raises(TypeError):
        multiray.register_balancer("not_callable", 42)
    # Names follow the CLI's grammar: a newline broke bench's traces, a comma balancer lists.
    for bad in ["py\nline", "py,comma", "py space", "py.dot", ""]:
        with pytest.raises(ValueError, match="letters, digits"):
            multiray.register_balancer(bad, Cycles)
        assert bad not in multiray.balancer_names()
    with pytest.raises(ValueError, match="nonsense"):
        multiray.Renderer(**TINY, balancer="pycycles:nonsense=1")
    if "pynotabalancer" not in multiray.balancer_names():
        multiray.register_balancer("pynotabalancer", lambda devices: object())
    with pytest.raises(TypeError, match="multiray.Balancer"):
        multiray.Renderer(**TINY, balancer="pynotabalancer")


def test_gil_released_while_a_python_balanced_render_runs():
    """A Python thread keeps running while frames balanced in Python render: the engine
    takes the GIL only for plan() and update()."""
    ticks, stop, planned = [], threading.Event(), []

    class Counted(Cycles):
        def plan(self, shape, frame):
            planned.append(frame)
            return super().plan(shape, frame)

    def tick():
        while not stop.is_set():
            ticks.append(time.monotonic())
            time.sleep(0.001)

    if "pycounted" not in multiray.balancer_names():
        multiray.register_balancer("pycounted", lambda d: Counted(d))
    r = multiray.Renderer(res="160x90", spp=8, seed=7, devices=TINY["devices"],
                          balancer="pycounted")
    thread = threading.Thread(target=tick)
    thread.start()
    try:
        start = time.monotonic()
        r.render(3)
        end = time.monotonic()
    finally:
        stop.set()
        thread.join()
    assert planned == [0, 1, 2]
    assert end - start > 0.05, "the render was too short to tell"
    inside = [t for t in ticks if start + 0.02 < t < end - 0.02]
    assert len(inside) >= 3, f"{len(inside)} ticks in a {end - start:.3f} s render"


class Hostile(multiray.Balancer):
    """Cycles' plan bent by `how`."""

    def __init__(self, devices, how):
        super().__init__(devices)
        self.how, self.inner = how, Cycles(devices)

    def plan(self, shape, frame):
        p = self.inner.plan(shape, frame)
        if self.how == "int":
            return 42
        if self.how == "str_item":
            p.assigned[0].append("item")
        elif self.how == "missing_pixels":
            p.assigned[1].pop()
        elif self.how == "lists":
            p.assigned.append([])
        elif self.how == "ratios":
            p.ratios = ["half", "half"]
        elif self.how == "zero_ratios":
            p.ratios = [0.0, 0.0]
        elif self.how == "inverted":
            p.assigned[0].append(multiray.WorkItem(0, 10, 10, 5, 5))
        return p

    def update(self, stats):
        if self.how == "update":
            raise ZeroDivisionError("update failed on purpose")


HOSTILE = [("int", TypeError, "returned int, not a multiray.Plan"),
           ("str_item", TypeError, r"assigned\[0\]\[1\] is str"),
           ("missing_pixels", ValueError, "plan of frame 0 is wrong: pixel .* is not covered"),
           ("lists", ValueError, "3 device lists for 2 devices"),
           ("zero_ratios", ValueError, "plan of frame 0 is wrong: ratios sum to 0"),
           ("inverted", ValueError, r"plan of frame 0 is wrong: item \[10,5\)x\[10,5\) .*inverted"),
           ("ratios", TypeError, "ratios holds str"),
           ("update", ZeroDivisionError, "on purpose")]


@pytest.mark.parametrize("how,error,message", HOSTILE)
def test_hostile_balancer_in_replay(trace, how, error, message):
    with pytest.raises(error, match=message):
        multiray.replay(trace, Hostile(2, how))


@pytest.mark.parametrize("how,error,message", HOSTILE)
def test_hostile_balancer_on_devices(how, error, message):
    """The error crosses the engine (which runs with the GIL released) to the caller."""
    name = "pyhostile_" + how
    if name not in multiray.balancer_names():
        multiray.register_balancer(name, lambda devices, how=how: Hostile(devices, how))
    r = multiray.Renderer(**TINY, balancer=name)
    with pytest.raises(error, match=message):
        r.render(2)


def test_base_class_contract(trace):
    with pytest.raises(NotImplementedError):
        multiray.replay(trace, multiray.Balancer(2))
    with pytest.raises(ValueError, match="for 3 devices"):
        multiray.replay(trace, Cycles(3))
    with pytest.raises(ValueError):
        multiray.Balancer(0)
    with pytest.raises(ValueError, match="cannot open"):
        multiray.read_trace("/nonexistent/trace")


class AliveRows(multiray.Balancer):
    """Even row bands over the devices still alive; remembers what it was told."""

    def __init__(self, devices):
        super().__init__(devices)
        self.alive, self.dropped = [True] * devices, []

    def plan(self, shape, frame):
        alive = [i for i in range(self.devices) if self.alive[i]]
        cuts = [shape.height * k // len(alive) for k in range(len(alive) + 1)]
        assigned, ratios = [[] for _ in range(self.devices)], [0.0] * self.devices
        for k, i in enumerate(alive):
            assigned[i] = [multiray.WorkItem(v, 0, cuts[k], shape.width, cuts[k + 1])
                           for v in range(shape.views)]
            ratios[i] = 1.0 / len(alive)
        return multiray.Plan(assigned, ratios)

    def drop_device(self, index):
        self.alive[index] = False
        self.dropped.append(index)


def test_a_failed_device_is_dropped_and_must_be_given_nothing():
    made = []
    if "pyaliverows" not in multiray.balancer_names():
        multiray.register_balancer("pyaliverows", lambda d: made.append(AliveRows(d)) or made[-1])
    failing = dict(TINY, devices="cpu:threads=1,cpu:threads=1:fail_after=1")
    frames = multiray.Renderer(**failing, balancer="pyaliverows").render(3)
    assert made and made[-1].dropped == [1]
    healthy = multiray.Renderer(**TINY, balancer="uniform").render(3)
    assert [multiray.image_hash(f["views"]) for f in frames] == [
        multiray.image_hash(f["views"]) for f in healthy]
    # The twin follows no drops: its next plan still gives the failed device rows.
    with pytest.raises(ValueError, match="device 1 was dropped but is given work"):
        multiray.Renderer(**failing, balancer="pycycles").render(3)


def test_interpreter_exits_cleanly_with_balancers_alive():
    """Registered factories and a Renderer still holding a Python balancer at exit."""
    code = ("import multiray\n"
            "class B(multiray.Balancer):\n"
            "    def plan(self, s, f):\n"
            "        return multiray.Plan([[multiray.WorkItem(0, 0, 0, s.width, s.height)]],"
            " [1.0])\n"
            "multiray.register_balancer('b', B)\n"
            "r = multiray.Renderer(res='16x16', spp=1, devices='cpu:threads=1', balancer='b')\n"
            "r.render(1)\n"
            "print('ok')\n")
    import subprocess
    p = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=60)
    assert p.returncode == 0 and p.stdout.strip() == "ok", p.stderr


def test_plan_values():
    import numpy as np
    item = multiray.WorkItem(0, 0, 0, 4, 2)
    p = multiray.Plan(([item], ()), np.array([1.0, 0.0]))
    assert p.ratios == [1.0, 0.0] and p.assigned == [[item], ()] and item.area == 8
    assert p == multiray.Plan([[multiray.WorkItem(0, 0, 0, 4, 2)], []], [1, 0])
    assert p != multiray.Plan([[item], []], [0.5, 0.5])
    with pytest.raises(TypeError, match="Plan.assigned must be a list"):
        multiray.Plan(5, [1.0])
    shape = multiray.FrameShape(4, 2, pixel_weight=np.ones((1, 2, 4)))
    assert shape.pixel_weight.dtype == np.float32 and shape.pixel_weight.shape == (1, 2, 4)
    with pytest.raises(ValueError):
        multiray.FrameShape(4, 2, pixel_weight=np.ones(3))


def test_python_balancer_in_simulate_and_bench(cli, tmp_path):
    """A registered Python balancer is a spec to multiray.simulate() and bench() too (they
    build balancers by name); the twin's simulated frame times equal the C++ ones."""
    code, err = run_cli(cli, "render", "--res", "64x36", "--spp", "1", "--frames", "4",
                        "--devices", "cpu:threads=1,cpu:threads=1:speed=0.5",
                        "--balancer", "queue", "--trace", str(tmp_path / "T"), "--out",
                        str(tmp_path / "D"), "--quiet")
    assert code == 0, err
    doc = multiray.simulate(str(tmp_path / "T"), devices=[2, 3], frames=12,
                            speeds="linear:0.4",
                            balancers=["pycycles:interval_ms=0", "cycles:interval_ms=0"])
    runs = doc["runs"]
    assert [r["balancer"].split(":")[0] for r in runs] == ["pycycles", "cycles"] * 2
    for py_run, cpp_run in zip(runs[::2], runs[1::2]):
        assert py_run["frame_ms"] == cpp_run["frame_ms"], py_run["devices"]
    # And to bench(): the same images as the C++ one renders, frame by frame.
    doc = multiray.bench(res="32x18", spp=1, frames=3, devices=TINY["devices"], repeats=1,
                         balancers="pycycles,cycles", probe_ms=0, ideal_frames=1)
    assert [r["balancer"].split(":")[0] for r in doc["runs"]] == ["pycycles", "cycles"]
    hashes = [[f["image_hash"] for f in r["frames"]] for r in doc["runs"]]
    assert doc["images_identical"] is True and hashes[0] == hashes[1]
