"""The CLI and Python give the same numbers, bit for bit: `tumble run --out` beside World.step."""

import json
import subprocess

import numpy as np

import tumble
from conftest import SCENES, tumble_cli


def run_cli(tmp_path, scene, out, duration):
    done = subprocess.run(
        [str(tumble_cli()), "run", str(SCENES / scene), "--duration", str(duration), "--out", str(out), "--quiet"],
        capture_output=True,
        text=True,
    )
    assert done.returncode == 0, done.stderr


def test_csv_rows_are_world_states(tmp_path):
    """The demo (contacts, flips): every sampled row of the CSV is the Python state at that step."""
    out = tmp_path / "demo.csv"
    run_cli(tmp_path, "demo.toml", out, 1.5)
    model = tumble.Model.from_file(SCENES / "demo.toml")
    lines = out.read_text().splitlines()
    assert lines[0] == "t,body,x,y,z,qw,qx,qy,qz,vx,vy,vz,wx,wy,wz"
    rows = {}
    for line in lines[1:]:
        t, body, *numbers = line.split(",")
        rows.setdefault(t, {})[body] = [float(x) for x in numbers]
    world = tumble.World(model)
    sample_every = 10  # scenes/demo.toml
    checked = 0
    for t, bodies in rows.items():
        step = round(float(t) / model.dt)
        assert step % sample_every == 0
        world.step(step - world.steps)
        assert world.time == float(t)
        x = world.state().reshape(-1, 13)
        for b, name in enumerate(model.body_names):
            assert np.array_equal(x[b], bodies[name]), (t, name)
        checked += 1
    assert checked == 151


def test_json_lines_robot_coordinates_are_world_states(tmp_path):
    out = tmp_path / "pendulum.jsonl"
    run_cli(tmp_path, "double_pendulum.toml", out, 2.0)
    model = tumble.Model.from_file(SCENES / "double_pendulum.toml")
    world = tumble.World(model)
    samples = [json.loads(line) for line in out.read_text().splitlines()]
    assert len(samples) == 201
    for sample in samples:
        world.step(round(sample["t"] / model.dt) - world.steps)
        (robot,) = sample["robots"]
        assert np.array_equal(world.state(), robot["q"] + robot["v"]), sample["t"]
