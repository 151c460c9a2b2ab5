"""Steps per second of the Go1 walking task as a vector environment.

    python crates/tumble-py/bench/go1_vector_bench.py [NUM_ENVS] [STEPS]

For 1 and 2 threads: `Go1WalkVector(NUM_ENVS)` (default 16) stepped STEPS times (default 200) with
uniform random actions — environment steps per second (one environment advanced by one action, 10
physics steps of 1 ms) and physics steps per second — beside the bare `tumble.step_worlds` call
on the same worlds and targets (no observation, reward or autoreset), and one `Go1Walk` stepped in
a Python loop. Best of 5 quiet runs (bench/quiet.py). Episodes reset as they end (a random policy
seldom falls).
"""

import sys

import numpy as np

import tumble
import tumble.gym as tg
from quiet import best as quiet_best


def best(f, repeat=5):
    t, quiet = quiet_best(f, repeat)
    return t, "" if quiet else " (no quiet run)"


def main():
    num_envs = int(sys.argv[1]) if len(sys.argv) > 1 else 16
    steps = int(sys.argv[2]) if len(sys.argv) > 2 else 200
    rng = np.random.default_rng(0)
    actions = rng.uniform(-1, 1, (steps, num_envs, 12)).astype(np.float32)
    skip = tg.Go1Walk().task.frame_skip
    print(f"Go1WalkVector, {num_envs} envs x {steps} steps of {skip} physics steps")
    print(f"{'':28} {'env steps/s':>12} {'physics steps/s':>16}")

    def report(name, t, n, note):
        print(f"{name:28} {n / t:12.0f} {n * skip / t:16.0f}{note}")

    single = tg.Go1Walk()
    single.reset(seed=0)

    def run_single():
        for k in range(steps):
            single.step(actions[k, 0])

    t, note = best(run_single)
    report("Go1Walk, Python loop", t, steps, note)
    for nthread in (1, 2):
        vec = tg.Go1WalkVector(num_envs, nthread=nthread)
        vec.reset(seed=0)

        def run_vec():
            for k in range(steps):
                vec.step(actions[k])

        t, note = best(run_vec)
        report(f"Go1WalkVector, {nthread} thread(s)", t, steps * num_envs, note)
        targets = vec.task.targets(np.clip(actions.astype(np.float64), -1, 1))
        out = np.empty((num_envs, vec.model.nstate))

        def run_bare():
            for k in range(steps):
                tumble.step_worlds(vec.worlds, skip, q_target=targets[k], out=out, nthread=nthread)

        t, note = best(run_bare)
        report(f"  step_worlds alone, {nthread}", t, steps * num_envs, note)


if __name__ == "__main__":
    main()
