"""The Python examples (examples/python/) run as written, on tiny settings: from the
repository root, with the module on PYTHONPATH (set by ctest). A plot is drawn when
matplotlib is installed; without it the example says so and prints its table."""
import os
import subprocess
import sys

import multiray

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))


def run_example(name, *args):
    p = subprocess.run([sys.executable, os.path.join("examples", "python", name), *args],
                       cwd=ROOT, capture_output=True, text=True, timeout=60)
    assert p.returncode == 0, p.stderr
    assert p.stderr == "", p.stderr
    return p.stdout


def plotted_or_said_so(out, png):
    if "matplotlib is not installed" in out:
        assert not os.path.exists(png)
    else:
        assert f"wrote {png}" in out and os.path.getsize(png) > 0


def test_balancer_sweep(tmp_path):
    png = str(tmp_path / "sweep.png")
    out = run_example("balancer_sweep.py", png, "--res", "32x18", "--frames", "3",
                      "--devices", "1,2,4", "--balancers", "uniform,queue")
    lines = out.splitlines()
    header = next(i for i, line in enumerate(lines) if line.startswith("balancer"))
    assert lines[header].split() == ["balancer", "1", "2", "4"]
    rows = [line.split() for line in lines[header + 1:header + 3]]
    assert [r[0] for r in rows] == ["uniform", "queue"]
    assert all(0 < float(e) <= 1.0 + 1e-9 for r in rows for e in r[1:])
    plotted_or_said_so(out, png)


def test_balancer_sweep_tabulates_simulate(trace, tmp_path):
    """On a given trace, the table holds simulate()'s efficiencies, row by balancer."""
    out = run_example("balancer_sweep.py", str(tmp_path / "s.png"), "--trace", trace,
                      "--devices", "1,2,4", "--balancers", "queue,uniform,hybrid")
    doc = multiray.simulate(trace, devices="1,2,4", balancers="queue,uniform,hybrid",
                            link="lan", slowdown=20, speeds="random:0.3", noise=0.05,
                            frames=40)  # the example's defaults
    table = {}
    for line in out.splitlines():
        cells = line.split()
        if cells and cells[0] in ("queue", "uniform", "hybrid"):
            table[cells[0]] = [float(e) for e in cells[1:]]
    for run in doc["runs"]:
        name = run["balancer"].split(":")[0]
        column = [1, 2, 4].index(run["devices"])
        assert table[name][column] == round(run["efficiency"], 3), (name, run["devices"])


def test_volume_targeting(tmp_path):
    png = str(tmp_path / "targeting.png")
    out = run_example("volume_targeting.py", png, "--targets", "1,3", "--res", "24x18",
                      "--frames", "3", "--size", "12", "--adapt", "none,last-frame")
    rows = [line.split(None, 4) for line in out.splitlines() if line[:9].strip() in ("1", "3")]
    assert len(rows) == 4, out  # two targets x two modes
    assert sorted(r[4] for r in rows) == sorted(["static adapt=none",
                                                 "static adapt=last-frame"] * 2), out
    assert all(float(r[1]) > 0 and float(r[3]) > 0 for r in rows), out
    plotted_or_said_so(out, png)


def test_cycles_balancer_runs_as_a_script():
    # Issue 51 item 5: run as its header says, it benches itself beside the C++ `cycles`.
    out = run_example("cycles_balancer.py")
    assert "pycycles:interval_ms=1000:" in out and "cycles:interval_ms=1000:" in out
    assert "images: identical, frame for frame" in out
