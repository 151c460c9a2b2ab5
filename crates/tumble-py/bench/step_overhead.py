"""Overhead of one `World.step()` call from Python over the Rust step it runs.

    python crates/tumble-py/bench/step_overhead.py

Per scene: the time per step of `world.step(N)` (one call: the Rust loop), the time per call of
`world.step()` in a Python `for` loop (N calls), their difference (the overhead of a call: argument
parsing, the World's borrow, releasing and taking back the GIL, the loop itself), and the time of
`world.state(out=buf)`. Best of 5 quiet runs (bench/quiet.py).
"""

import os
import time
from pathlib import Path

import numpy as np

import tumble
from quiet import best as quiet_best

SCENES = Path(__file__).resolve().parents[3] / "scenes"
N = 200_000


def best(f, repeat=5):
    t, quiet = quiet_best(f, repeat)
    if not quiet:
        print("warning: no quiet run (other processes were busy)")
    return t


def main():
    print(f"{'scene':32} {'Rust step':>12} {'Python step()':>14} {'overhead':>10} {'state(out=)':>12}")
    for name, scene in [("one free body (rk4)", "projectile.toml"), ("double pendulum (rk4)", "double_pendulum.toml")]:
        model = tumble.Model.from_file(SCENES / scene)
        world = tumble.World(model)
        rust = best(lambda: world.step(N)) / N
        step = world.step

        def loop():
            for _ in range(N):
                step()

        python = best(loop) / N
        out = np.empty(model.nstate)
        state = world.state

        def read():
            for _ in range(N):
                state(out=out)

        read_time = best(read) / N
        print(
            f"{name:32} {rust * 1e9:10.0f} ns {python * 1e9:12.0f} ns {(python - rust) * 1e9:8.0f} ns"
            f" {read_time * 1e9:10.0f} ns"
        )


if __name__ == "__main__":
    # other work on the machine shows here: the figures mean something only on a quiet machine
    print(f"load average before: {os.getloadavg()[0]:.2f}")
    main()
    print(f"load average after: {os.getloadavg()[0]:.2f}")
