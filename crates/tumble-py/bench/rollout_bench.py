"""Rollout speed: tumble.rollout on 1 and 2 threads beside the pure-Rust loop (the example
`rollout_loop`) and beside `mujoco.rollout` on the same work.

    cargo build --release -p tumble --example rollout_loop
    python crates/tumble-py/bench/rollout_bench.py [--quick] [--quadrupeds] [--trot] [--pairs N]

    --quick       fewer rows and pairs (a smoke test)
    --quadrupeds  only the quadrupeds (no Rust loop to build)
    --trot        the quadrupeds trotting too (scenes/*_trot.toml)
    --pairs N     interleaved pairs (default 15, 5 with --quick)

Workloads (RK4, dt = 1 ms, no contacts in either engine):
- free bodies: 100 free bodies (mass 1 kg, principal moments 1, 2, 3 kg·m², spinning, under
  gravity); in MuJoCo 100 bodies with a free joint and the same inertia, no geometry;
- double pendulum: scenes/robots/double_pendulum.urdf on a fixed pivot;
- Panda: scenes/robots/panda.urdf, fixed base (9 joints).
MuJoCo loads the same URDF files (with the zero products of inertia that its reader requires written
out), with joint damping and armature switched off, as tumble's `Model.from_urdf` has none; both
enforce the URDF's joint limits (tumble's default; Panda starts at q = 0, outside its joint 4's
limits, which both engines then hold).

Quadrupeds (contacts): Go1, Solo-12 and ANYmal C of example-robot-data standing on the floor under
their scene's PD (scenes/{go1,solo12,anymal_c}_stand.toml: semi-implicit Euler, dt = 1 ms, friction
0.9, the URDF's collision geometry, let go 5 mm above the floor: each row lands in its first 40 steps
and then stands), every row from the scene's initial state. tumble: `tumble.rollout(model, x0, nstep)`
with no control (the scene's PD acts in the step). MuJoCo: the same URDF and scene turned into an
MjModel by tools/legged_mujoco_bench.py (`Scene.mujoco_model`: same dt, gravity, friction, PD gains as
position actuators, effort and joint limits, collision geometry; integrator Euler), both friction cones
(pyramidal, MuJoCo's default, and elliptic), `ctrl` = the scene's PD targets at every step, one MjData
per thread. Both return every state. Measured in PAIRS interleaved rounds: in a round, at one thread
then at two, tumble and the two MuJoCo variants run back to back (the order reversed every other
round), each the best of 3 quiet runs (of at most 9 tries); reported per engine the median steps/s
over the rounds, and the ratios tumble ÷ MuJoCo (speed: > 1 is tumble faster) and 2 threads ÷ 1
taken within a round, median (range) over the rounds. With --trot, the *_trot scenes too (the PD
targets swing at 2 Hz; MuJoCo's ctrl follows the same q*(t_n)).

Steps per second count one step of one row (one world). Best of 5 quiet runs each (3 for MuJoCo):
runs during which other processes used the CPUs are taken again (bench/quiet.py).

Two threads against one: on a virtual machine the speed of each CPU drifts from one second to the
next (the host's other guests, its clock), by ±30 % here, more than the effect measured. So the
scaling is also measured in PAIRS interleaved runs, one thread then two threads on the same batch, and
reported as the median of the pairs' ratios with its range: a drift slower than a pair cancels.
"""

import argparse
import json
import re
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

import tumble
from quiet import best as quiet_best

REPO = Path(__file__).resolve().parents[3]
TARGET = Path(os.environ.get("CARGO_TARGET_DIR", REPO / "target"))
ARGS = argparse.ArgumentParser(description="tumble.rollout against the Rust loop and mujoco.rollout")
ARGS.add_argument("--quick", action="store_true")
ARGS.add_argument("--quadrupeds", action="store_true", help="only the quadrupeds")
ARGS.add_argument("--trot", action="store_true", help="the quadrupeds trotting too")
ARGS.add_argument("--pairs", type=int, default=None)
ARGS = ARGS.parse_args()
QUICK = ARGS.quick
PAIRS = ARGS.pairs or (5 if QUICK else 15)


NOISY = []  # workloads timed while other processes used the CPUs


def best(f, repeat=5, attempts=40):
    t, quiet = quiet_best(f, repeat, attempts)
    if not quiet:
        NOISY.append(f)
    return t


def free_bodies_toml(n):
    rng = np.random.default_rng(0)
    lines = ['version = 1', '[world]', 'dt = 0.001', 'integrator = "rk4"']
    for i in range(n):
        w = rng.normal(0, 2, 3)
        lines += [
            "[[body]]",
            f'name = "b{i}"',
            "mass = 1.0",
            "inertia = [1.0, 2.0, 3.0]",
            f"position = [{i * 3.0}, 0.0, 0.0]",
            f"angular_velocity = [{w[0]}, {w[1]}, {w[2]}]",
        ]
    return "\n".join(lines) + "\n"


def free_bodies_mjcf(n):
    rng = np.random.default_rng(0)
    bodies = "".join(
        f'<body pos="{i * 3.0} 0 0"><freejoint/><inertial pos="0 0 0" mass="1" diaginertia="1 2 3"/></body>'
        for i in range(n)
    )
    xml = f'<mujoco><option timestep="0.001" integrator="RK4"/><worldbody>{bodies}</worldbody></mujoco>'
    import mujoco

    model = mujoco.MjModel.from_xml_string(xml)
    data = mujoco.MjData(model)
    data.qvel[:] = np.concatenate([np.concatenate([np.zeros(3), rng.normal(0, 2, 3)]) for _ in range(n)])
    return model, data


def urdf_mujoco(path):
    import mujoco

    # MuJoCo's URDF reader requires every inertia attribute: write out the zeros the file leaves out
    text = re.sub(
        r"<inertia ([^/]*)/>",
        lambda m: "<inertia " + m.group(1) + "".join(f' {k}="0"' for k in ("ixy", "ixz", "iyz") if k not in m.group(1)) + "/>",
        Path(path).read_text(),
    )
    model = mujoco.MjModel.from_xml_string(text)
    model.opt.timestep = 0.001
    model.opt.integrator = mujoco.mjtIntegrator.mjINT_RK4
    model.dof_damping[:] = 0.0
    model.dof_armature[:] = 0.0
    return model, mujoco.MjData(model)


def rust_loop(scene_path, rows, nstep):
    exe = TARGET / "release" / "examples" / "rollout_loop"
    if not exe.is_file():
        sys.exit(f"{exe} is missing: cargo build --release -p tumble --example rollout_loop")
    result = {}

    def run():
        done = subprocess.run([str(exe), str(scene_path), str(rows), str(nstep)], capture_output=True, text=True, check=True)
        result.update(json.loads(done.stdout))

    best(run, repeat=2)  # the example keeps the best of its own 5 runs
    return result["steps_per_s"]


def paired_scaling(one, two):
    """Median (min, max) over PAIRS of time(one) / time(two), the two run back to back."""
    ratios = []
    for _ in range(PAIRS):
        t0 = time.perf_counter()
        one()
        t1 = time.perf_counter()
        two()
        t2 = time.perf_counter()
        ratios.append((t1 - t0) / (t2 - t1))
    return float(np.median(ratios)), min(ratios), max(ratios)


def tumble_rollout(model, rows, nstep, nthread):
    x0 = np.tile(tumble.World(model).state(), (rows, 1))
    out = np.empty((rows, nstep, model.nstate))
    t = best(lambda: tumble.rollout(model, x0, nstep, nthread=nthread, out=out))
    return rows * nstep / t


def against_rust_loop(scene_path, model, rows, nstep):
    """Median (min, max) over PAIRS of the Rust loop's best of 5 (its own) ÷ the one-thread rollout's
    best of 5, the two run back to back: the one-thread ratio, free of the machine's drift."""
    exe = TARGET / "release" / "examples" / "rollout_loop"
    x0 = np.tile(tumble.World(model).state(), (rows, 1))
    out = np.empty((rows, nstep, model.nstate))
    ratios = []
    for _ in range(PAIRS):
        done = subprocess.run([str(exe), str(scene_path), str(rows), str(nstep)], capture_output=True, text=True, check=True)
        rust = json.loads(done.stdout)["seconds"]
        times = []
        for _ in range(5):
            t0 = time.perf_counter()
            tumble.rollout(model, x0, nstep, nthread=1, out=out)
            times.append(time.perf_counter() - t0)
        ratios.append(rust / min(times))
    return float(np.median(ratios)), min(ratios), max(ratios)


def tumble_scaling(model, rows, nstep):
    x0 = np.tile(tumble.World(model).state(), (rows, 1))
    out = np.empty((rows, nstep, model.nstate))
    run = lambda n: lambda: tumble.rollout(model, x0, nstep, nthread=n, out=out)  # noqa: E731
    return paired_scaling(run(1), run(2))


def mujoco_rollout(mj, rows, nstep, nthread):
    import mujoco
    from mujoco import rollout

    model, data = mj
    spec = mujoco.mjtState.mjSTATE_FULLPHYSICS
    x = np.empty(mujoco.mj_stateSize(model, spec))
    mujoco.mj_getState(model, data, x, spec)
    x0 = np.tile(x, (rows, 1))
    datas = [mujoco.MjData(model) for _ in range(nthread)]
    state = np.empty((rows, nstep, x.size))
    with rollout.Rollout(nthread=nthread) as r:
        t = best(lambda: r.rollout(model, datas, x0, nstep=nstep, state=state), repeat=3)
    return rows * nstep / t


def mujoco_scaling(mj, rows, nstep):
    import mujoco
    from mujoco import rollout

    model, data = mj
    spec = mujoco.mjtState.mjSTATE_FULLPHYSICS
    x = np.empty(mujoco.mj_stateSize(model, spec))
    mujoco.mj_getState(model, data, x, spec)
    x0 = np.tile(x, (rows, 1))
    state = np.empty((rows, nstep, x.size))
    with rollout.Rollout(nthread=1) as r1, rollout.Rollout(nthread=2) as r2:
        d1 = [mujoco.MjData(model)]
        d2 = [mujoco.MjData(model) for _ in range(2)]
        return paired_scaling(
            lambda: r1.rollout(model, d1, x0, nstep=nstep, state=state),
            lambda: r2.rollout(model, d2, x0, nstep=nstep, state=state),
        )


def legged():
    """tools/legged_mujoco_bench.py: the scene → MjModel construction shared with the legged bench."""
    sys.path.insert(0, str(REPO / "tools"))
    import legged_mujoco_bench

    return legged_mujoco_bench


class QuadrupedCase:
    """One scene in both engines: rows × nstep from the scene's initial state."""

    CONES = ("pyramidal", "elliptic")

    def __init__(self, key, rows, nstep):
        import mujoco

        scene = legged().Scene(*key.rsplit("_", 1), duration=nstep * 1e-3)
        assert scene.nstep == nstep and scene.integrator == "semi_implicit_euler"
        self.key, self.rows, self.nstep = key, rows, nstep
        self.model = tumble.Model.from_file(scene.path)
        assert self.model.dt == scene.dt and self.model.integrator == scene.integrator
        self.x0 = np.tile(tumble.World(self.model).state(), (rows, 1))
        self.out = np.empty((rows, nstep, self.model.nstate))
        self.mj = {}
        spec = mujoco.mjtState.mjSTATE_FULLPHYSICS
        for cone in self.CONES:
            model, data = scene.mujoco_model("Euler", cone)
            x = np.empty(mujoco.mj_stateSize(model, spec))
            mujoco.mj_getState(model, data, x, spec)
            # the PD targets q*(t_n) of every step (constant when standing), for every row
            ctrl = np.ascontiguousarray(np.broadcast_to(scene.control(nstep), (rows, nstep, model.nu)))
            state = np.empty((rows, nstep, x.size))
            self.mj[cone] = (model, np.tile(x, (rows, 1)), ctrl, state)
        self.z_index = 2  # tumble: the base's q = [x, y, z, qw, ...] comes first (no free bodies)
        assert self.model.state_names[self.z_index] == f"{scene.name}.q[2]"

    def tumble_run(self, nthread):
        return lambda: tumble.rollout(self.model, self.x0, self.nstep, nthread=nthread, out=self.out)

    def mujoco_run(self, cone, pool, datas):
        model, x0, ctrl, state = self.mj[cone]
        return lambda: pool.rollout(model, datas, x0, ctrl, nstep=self.nstep, state=state)

    def check(self, pools):
        """Both engines' rows land and stand (base height at the end), tumble's rows are the same on
        1 and 2 threads and all equal (same initial state)."""
        self.tumble_run(1)()
        one = self.out.copy()
        self.tumble_run(2)()
        assert np.array_equal(one, self.out), f"{self.key}: 1 and 2 threads differ"
        assert np.all(one == one[:1]), f"{self.key}: rows with the same initial state differ"
        z = {"tumble": one[0, -1, self.z_index]}
        for cone in self.CONES:
            n, pool, datas = pools[1][cone]
            self.mujoco_run(cone, pool, datas)()
            z[f"MuJoCo {cone}"] = self.mj[cone][3][0, -1, 1 + 2]  # FULLPHYSICS: time, then qpos
        assert all(v > 0.1 for v in z.values()), (self.key, z)
        return z


def quadrupeds():
    import mujoco
    from mujoco import rollout

    rows = 4 if QUICK else 16
    nstep = 1000
    keys = [f"{r}_{m}" for m in (["stand", "trot"] if ARGS.trot else ["stand"]) for r in ("go1", "solo12", "anymal_c")]
    cases = [QuadrupedCase(k, rows, nstep) for k in keys]
    print(f"Quadrupeds, {rows} rows × {nstep} steps from the scene's initial state (landing in the first 40 steps), "
          f"{PAIRS} interleaved rounds, best of 3 quiet runs per slot; mujoco {mujoco.__version__}, tumble's "
          "semi_implicit_euler against MuJoCo's Euler")
    print()
    results = {}
    with rollout.Rollout(nthread=1) as r1, rollout.Rollout(nthread=2) as r2:
        for case in cases:
            pools = {
                n: {cone: (n, r, [mujoco.MjData(case.mj[cone][0]) for _ in range(n)]) for cone in case.CONES}
                for n, r in ((1, r1), (2, r2))
            }
            z = case.check(pools)
            print(f"{case.key}: base height after {nstep} steps: " + ", ".join(f"{k} {v:.4f} m" for k, v in z.items()))
            engines = ["tumble"] + [f"MuJoCo {c}" for c in case.CONES]
            times = {(e, n): [] for e in engines for n in (1, 2)}
            for k in range(PAIRS):
                for n in (1, 2):
                    slots = [("tumble", case.tumble_run(n))] + [
                        (f"MuJoCo {c}", case.mujoco_run(c, pools[n][c][1], pools[n][c][2])) for c in case.CONES
                    ]
                    for name, f in slots[::-1] if k % 2 else slots:
                        times[(name, n)].append(best(f, repeat=3, attempts=9))
            results[case.key] = (case, times)
    print()
    per_s = lambda case, t: case.rows * case.nstep / np.asarray(t)  # noqa: E731
    g = lambda r: f"{np.median(r):.2f} ({np.min(r):.2f}–{np.max(r):.2f})"  # noqa: E731
    print("| scene | rows × steps | threads | tumble | MuJoCo pyramidal | MuJoCo elliptic | tumble ÷ MuJoCo pyramidal | tumble ÷ MuJoCo elliptic |")
    print("|" + "---|" * 8)
    for key, (case, times) in results.items():
        for n in (1, 2):
            tu = per_s(case, times[("tumble", n)])
            cells = [f"{np.median(tu) / 1e3:.1f} k/s"]
            ratios = []
            for c in case.CONES:
                mj = per_s(case, times[(f"MuJoCo {c}", n)])
                cells.append(f"{np.median(mj) / 1e3:.1f} k/s")
                ratios.append(f"**{g(tu / mj)}**")
            print(f"| {key} | {case.rows} × {case.nstep} | {n} | " + " | ".join(cells + ratios) + " |")
    print()
    print("2 threads ÷ 1 thread (steps/s), median (range) over the rounds:")
    print()
    print("| scene | tumble | MuJoCo pyramidal | MuJoCo elliptic |")
    print("|---|---|---|---|")
    for key, (case, times) in results.items():
        cells = [g(np.asarray(times[(e, 1)]) / np.asarray(times[(e, 2)])) for e in ["tumble"] + [f"MuJoCo {c}" for c in case.CONES]]
        print(f"| {key} | " + " | ".join(cells) + " |")


def main():
    if not ARGS.quadrupeds:
        others()
        print()
    quadrupeds()


def others():
    scale = 4 if QUICK else 1
    with tempfile.TemporaryDirectory() as tmp:
        free = Path(tmp) / "free_bodies.toml"
        free.write_text(free_bodies_toml(100))
        pendulum_urdf = REPO / "scenes" / "robots" / "double_pendulum.urdf"
        panda_urdf = REPO / "scenes" / "robots" / "panda.urdf"
        # the Rust loop reads scene files: robots through a one-robot scene like Model.from_urdf's
        scenes = {}
        for name, urdf in [("pendulum", pendulum_urdf), ("panda", panda_urdf)]:
            path = Path(tmp) / f"{name}.toml"
            path.write_text(tumble.Model.from_urdf(urdf).text)
            scenes[name] = path
        cases = [
            ("100 free bodies", free, tumble.Model.from_file(free), lambda: free_bodies_mjcf(100), 16, 1000),
            ("double pendulum", scenes["pendulum"], tumble.Model.from_urdf(pendulum_urdf), lambda: urdf_mujoco(pendulum_urdf), 256, 1000),
            ("Panda (9 joints)", scenes["panda"], tumble.Model.from_urdf(panda_urdf), lambda: urdf_mujoco(panda_urdf), 64, 1000),
        ]
        head = f"| workload | rows × steps | Rust loop | tumble 1 thread (× Rust) | tumble 2 threads (× 1 thread) | MuJoCo 1 thread | MuJoCo 2 threads | tumble ÷ MuJoCo (1 / 2 threads) |"
        print(head)
        print("|" + "---|" * 8)
        scaling = []
        for name, scene_path, model, mj_make, rows, nstep in cases:
            rows //= scale
            rust = rust_loop(scene_path, rows, nstep)
            one = tumble_rollout(model, rows, nstep, 1)
            two = tumble_rollout(model, rows, nstep, 2)
            mj = mj_make()
            mj_one = mujoco_rollout(mj, rows, nstep, 1)
            mj_two = mujoco_rollout(mj, rows, nstep, 2)
            f = lambda s: f"{s / 1e6:.3g} M/s"  # noqa: E731
            print(
                f"| {name} | {rows} × {nstep} | {f(rust)} | {f(one)} ({one / rust:.2f}) | {f(two)} ({two / one:.2f}) "
                f"| {f(mj_one)} | {f(mj_two)} | {one / mj_one:.1f} / {two / mj_two:.1f} |"
            )
            scaling.append(
                (
                    name,
                    against_rust_loop(scene_path, model, rows, nstep),
                    tumble_scaling(model, rows, nstep),
                    mujoco_scaling(mj, rows, nstep),
                )
            )
        print()
        print(f"Median (range) of {PAIRS} interleaved pairs:")
        print()
        print("| workload | tumble 1 thread ÷ Rust loop | tumble 2 threads ÷ 1 | MuJoCo 2 threads ÷ 1 |")
        print("|---|---|---|---|")
        g = lambda r: f"{r[0]:.2f} ({r[1]:.2f}–{r[2]:.2f})"  # noqa: E731
        for name, rust, ours, theirs in scaling:
            print(f"| {name} | {g(rust)} | {g(ours)} | {g(theirs)} |")


if __name__ == "__main__":
    # other work on the machine shows here: the figures mean something only on a quiet machine
    print(f"load average before: {os.getloadavg()[0]:.2f}")
    main()
    print(f"load average after: {os.getloadavg()[0]:.2f}")
    if NOISY:
        print(f"warning: {len(NOISY)} timings had no quiet run: other processes were busy")
