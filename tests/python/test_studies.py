"""multiray.simulate and multiray.bench against the CLI's `simulate --json` and
`bench --json` documents (src/python/studies.cpp)."""
import json
import signal
import subprocess
import sys
import time

import pytest

import multiray
from conftest import run_cli

# A bench on tiny frames: two balancers, one block, no contention probe (a fraction of a
# second in all).
BENCH = dict(res="32x18", spp=1, frames=3, devices="cpu:threads=1,cpu:threads=1",
             balancers="uniform,queue", repeats=1, probe_ms=0, ideal_frames=1, seed=3)


def cli_args(kwargs):
    """Keyword arguments as the CLI's options (the names with '-' for '_')."""
    args = []
    for k, v in kwargs.items():
        args += ["--" + k.replace("_", "-"), str(v)]
    return args


SIMULATE = [
    dict(devices="2,4", balancers="uniform,queue,hybrid"),
    dict(devices="1,3", speeds="linear:0.5", noise=0.1, seed=9, link="lan",
         result_encoding="half", frames=7, warmup=2, balancers="static,dlb"),
    dict(devices="2", slowdown=4, link="wifi"),  # every balancer
]


@pytest.mark.parametrize("kwargs", SIMULATE, ids=["plain", "noisy", "every"])
def test_simulate_equals_the_cli_document(cli, trace, tmp_path, kwargs):
    out = tmp_path / "sim.json"
    code, err = run_cli(cli, "simulate", trace, *cli_args(kwargs), "--json", str(out))
    assert code == 0, err
    with open(out) as f:
        expected = json.load(f)
    got = multiray.simulate(trace, **kwargs)
    assert got == expected
    assert got["runs"] and all(r["frame_ms"] for r in got["runs"])


def test_calibrated_simulation_equals_the_cli_document(cli, trace, tmp_path):
    """calibrate=True and predict=[...] give `simulate --calibrate/--predict --json`."""
    for kwargs in (dict(calibrate=True, balancers="uniform,hybrid", warmup=1),
                   dict(predict=[trace, trace], contention=0.2, noise=0.05, seed=4),
                   dict(predict=[trace], calibration="pooled", warmup=1)):
        out = tmp_path / "cal.json"
        args = ["--calibrate"] if kwargs.get("calibrate") else []
        for k, v in kwargs.items():
            if k == "calibrate":
                continue
            args += ["--" + k, ",".join(v) if isinstance(v, list) else str(v)]
        code, err = run_cli(cli, "simulate", trace, *args, "--json", str(out))
        assert code == 0, err
        with open(out) as f:
            expected = json.load(f)
        got = multiray.simulate(trace, **kwargs)
        assert got == expected
        assert got["calibration"] and got["rows"]
    with pytest.raises(ValueError, match="contention"):
        multiray.simulate(trace, calibrate=True, contention=11)
    with pytest.raises(TypeError):
        multiray.simulate(trace, calibrate="yes")
    with pytest.raises(ValueError, match="--calibration"):
        multiray.simulate(trace, predict=[trace], calibration="sideways")


def test_simulate_takes_lists_and_paths(trace):
    import pathlib
    by_text = multiray.simulate(trace, devices="2,4", balancers="uniform,queue")
    by_list = multiray.simulate(pathlib.Path(trace), devices=[2, 4],
                                balancers=["uniform", "queue"])
    assert by_list == by_text
    assert [(r["devices"], r["balancer"].split(":")[0]) for r in by_list["runs"]] == [
        (2, "uniform"), (2, "queue"), (4, "uniform"), (4, "queue")]


def test_bench_has_the_cli_document(cli, tmp_path):
    out = tmp_path / "bench.json"
    code, err = run_cli(cli, "bench", *cli_args(BENCH), "--json", str(out))
    assert code == 0, err
    with open(out) as f:
        expected = json.load(f)
    got = multiray.bench(**BENCH)
    assert set(got) == set(expected)
    assert len(got["runs"]) == len(expected["runs"]) == 2
    for g, e in zip(got["runs"], expected["runs"]):
        assert set(g) == set(e)
        assert g["balancer"] == e["balancer"] and g["lane"] == e["lane"]
        assert len(g["frames"]) == len(e["frames"]) == 3
        assert set(g["frames"][0]) == set(e["frames"][0])
        # Timings vary; the images do not.
        assert [f["image_hash"] for f in g["frames"]] == [f["image_hash"] for f in e["frames"]]
    for key in ("scene", "resolution", "views", "spp", "frames", "camera_path",
                "images_identical"):
        assert got[key] == expected[key], key
    assert got["images_identical"] is True


HOSTILE = [
    (dict(balancers="nonesuch"), ValueError),
    (dict(frames=-1), ValueError),
    (dict(devices="0"), ValueError),
    (dict(noise=2), ValueError),
    (dict(frames="4"), TypeError),
    (dict(devices=[1.5]), TypeError),
    (dict(seed=-1), ValueError),
    (dict(noise="lots"), TypeError),
    (dict(json="out.json"), TypeError),
]


@pytest.mark.parametrize("kwargs,error", HOSTILE, ids=[str(k) for k, _ in HOSTILE])
def test_simulate_refuses_hostile_arguments(cli, trace, kwargs, error):
    with pytest.raises(error) as e:
        multiray.simulate(trace, **kwargs)
    assert "\n" not in str(e.value)
    if error is ValueError and "seed" not in kwargs:  # the CLI's own message, one line
        code, err = run_cli(cli, "simulate", trace, *cli_args(kwargs))
        assert code == 2 and err.strip() == "multiray: error: " + str(e.value)


def test_simulate_refuses_missing_or_mistyped_traces(tmp_path):
    with pytest.raises(ValueError, match="cannot read trace"):
        multiray.simulate(str(tmp_path / "none.trace"))
    (tmp_path / "junk.trace").write_text("not a trace\n")
    with pytest.raises(ValueError):
        multiray.simulate(str(tmp_path / "junk.trace"))
    with pytest.raises(TypeError):
        multiray.simulate(3)
    with pytest.raises(TypeError):
        multiray.simulate()


@pytest.mark.parametrize("kwargs,error", [
    (dict(balancers="nonesuch"), ValueError), (dict(frames=-1), ValueError),
    (dict(repeats=0), ValueError), (dict(balancers=""), ValueError),
    (dict(devices="gpu9"), ValueError), (dict(balancer="queue"), TypeError),
    (dict(repeats="2"), TypeError), (dict(balancers=[1]), TypeError)])
def test_bench_refuses_hostile_arguments(kwargs, error):
    with pytest.raises(error) as e:
        multiray.bench(**{**BENCH, **kwargs})
    assert "\n" not in str(e.value)


CHILD = """
import signal, sys, multiray
signal.signal(signal.SIGINT, signal.default_int_handler)  # inherited ignored in background jobs
print("start", flush=True)
try:
    multiray.bench(res="32x18", spp=1, frames=10**5, devices="cpu:threads=1",
                   balancers="uniform", repeats=1, probe_ms=0, ideal_frames=1)
except KeyboardInterrupt:
    print("interrupted", flush=True)
"""


def test_ctrl_c_stops_a_bench_between_frames():
    child = subprocess.Popen([sys.executable, "-c", CHILD], stdout=subprocess.PIPE, text=True)
    try:
        assert child.stdout.readline().strip() == "start"
        time.sleep(0.5)
        child.send_signal(signal.SIGINT)
        sent = time.monotonic()
        out, _ = child.communicate(timeout=60)
        stopped = time.monotonic() - sent
    finally:
        child.kill()
    assert out.startswith("interrupted"), out
    # Between frames, not after the whole bench (minutes of frames; one takes under 1 ms).
    assert stopped < 5, f"{stopped:.1f} s from Ctrl-C to the end"
    assert child.returncode == 0


def test_simulate_and_bench_are_quiet(trace, capfd):
    multiray.simulate(trace, devices="2", balancers="uniform")
    # auto: the CLI prints its choice on stderr
    multiray.bench(**{**BENCH, "balancers": "auto,uniform"})
    out, err = capfd.readouterr()
    assert out == "" and err == ""


SIM_CHILD = """
import signal, sys, multiray
signal.signal(signal.SIGINT, signal.default_int_handler)  # inherited ignored in background jobs
print("start", flush=True)
try:  # 60 studies of about a second each
    multiray.simulate(sys.argv[1], devices=[256] * 60, balancers="hybrid", frames=2000)
except KeyboardInterrupt:
    print("interrupted", flush=True)
"""


def test_ctrl_c_stops_a_simulation_between_studies(trace):
    child = subprocess.Popen([sys.executable, "-c", SIM_CHILD, trace], stdout=subprocess.PIPE,
                             text=True)
    try:
        assert child.stdout.readline().strip() == "start"
        time.sleep(0.5)
        child.send_signal(signal.SIGINT)
        sent = time.monotonic()
        out, _ = child.communicate(timeout=30)
        stopped = time.monotonic() - sent
    finally:
        child.kill()
    assert out.startswith("interrupted"), out
    assert stopped < 10, f"{stopped:.1f} s from Ctrl-C to the end"
