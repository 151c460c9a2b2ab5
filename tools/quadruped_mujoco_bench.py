#!/usr/bin/env python3
"""A quadruped standing on the floor, tumble beside MuJoCo in one run: contact quality and time per step.

    cargo build --release -p tumble-cli
    python tools/quadruped_mujoco_bench.py [--pairs N] [PATH/TO/tumble]   (default: target/release/tumble, 15 pairs)

The scene is scenes/quadruped.toml: robots/quadruped.urdf (4.6 kg, floating base, 8 revolute joints, sphere
feet of radius 0.02 m), let go with its base at z = 0.265 m (hips 0.8, knees -1.6 rad), held by PD
(kp = 200 N·m/rad, kd = 1 N·m·s/rad) at those angles, on a plane, dt = 1e-3 s, 5 s.

MuJoCo loads the SAME URDF (`MjSpec.from_file`) and gets what the scene adds:
- a free joint on `base`, a ground plane, gravity (0, 0, -9.81), timestep 1e-3;
- the PD as position actuators, `kp = 200`, `kv = 1` (tau = kp (q* - q) - kv v), their targets in `ctrl`;
  the URDF's `effort` (20 N·m) becomes each joint's `actuatorfrcrange`, as tumble clamps to it;
- friction mu = sqrt(0.8 * 0.5) on every geom (tumble's combination of the links' 0.8 and the ground's
  default 0.5; MuJoCo takes the larger of the two geoms' values, here equal), condim 3;
- `inertiafromgeom = false`: the feet (links with no <inertial>) stay massless, as in tumble (MuJoCo's
  default would give each foot sphere 33 g of density 1000);
- no self-collision (tumble's `self_collision = false` default): the robot's geoms have conaffinity 0,
  the ground 1, so a link meets the ground only;
- MuJoCo's default contact: soft constraints, solref (0.02, 1), solimp (0.9, 0.95, 0.001, 0.5, 2), margin 0,
  Newton solver; the cone is the default PYRAMIDAL one, and ELLIPTIC (like tumble's friction disc) is
  measured too. Integrators: RK4 (the scene's) and Euler (MuJoCo's default).

Quality (one run of each, sampled every 10 steps as tumble's trajectory is): base height at 5 s; over
t in [1, 5] s the sum of the normal contact forces over the weight (mean and range), the deepest
penetration, and the largest horizontal displacement of a foot centre from where it was at t = 1 s; the
deepest penetration over the whole run (the landing). tumble's figures come from `--out` and
`--contacts` (force = the step's impulse over dt); MuJoCo's from `data.contact.dist` and
`mj_contactForce`, evaluated by `mj_forward` on a copy of the data at each sample.

Speed: PAIRS interleaved rounds (this machine's CPU speed drifts by +-30 %, so each ratio is taken
within a round and the median of the rounds' ratios is reported, with their range). In a round each
variant runs three times back to back and keeps its shortest time; the variants compared (tumble rk4
and MuJoCo RK4, tumble semi-implicit Euler and MuJoCo Euler) are neighbours. A round runs
`tumble run scenes/quadruped.toml --quiet --summary S.json --out T.csv` (its `wall_time_s`: the step
loop with its sampling, not the process start or the scene load) and MuJoCo's 5000 steps in
`mujoco.rollout` (one thread, the loop in C), for each MuJoCo variant; the order within a round
alternates. A Python loop of `mj_step` minus the empty loop's time is reported as a cross-check.
"""
import copy
import json
import os
import subprocess
import sys
import tempfile
import time

import numpy as np
import mujoco
from mujoco import rollout

ROOT = os.path.normpath(os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
SCENE = os.path.join(ROOT, "scenes", "quadruped.toml")
URDF = os.path.join(ROOT, "scenes", "robots", "quadruped.urdf")
DT, DURATION, SAMPLE_EVERY = 1e-3, 5.0, 10
NSTEP = int(round(DURATION / DT))
G = 9.81
MU = float(np.sqrt(0.8 * 0.5))
BASE_Z = 0.265
TARGETS = {f"{leg}_{j}": q for leg in ("FL", "FR", "HL", "HR") for j, q in (("hip", 0.8), ("knee", -1.6))}
FEET = ["FL", "FR", "HL", "HR"]
BEST = 3  # runs of each variant in a round, the shortest kept
SETTLED = 1.0  # s: quality figures over [SETTLED, DURATION]
VARIANTS = [("RK4", "pyramidal"), ("Euler", "pyramidal"), ("RK4", "elliptic"), ("Euler", "elliptic")]
# tumble: the scene as it is (rk4), the same without the samples between the first and the last (the
# step loop alone), and with semi-implicit Euler, the integrator that matches MuJoCo's Euler (one
# evaluation of the dynamics per step, the position moved with the new velocity)
TUMBLE = [("tumble, rk4", []),
          ("tumble, rk4, no samples", ["--sample-every", str(NSTEP)]),
          ("tumble, semi_implicit_euler", ["--integrator", "semi_implicit_euler"])]


# ---------------------------------------------------------------------------------------------- MuJoCo

def mujoco_model(integrator, cone):
    spec = mujoco.MjSpec.from_file(URDF)
    spec.compiler.inertiafromgeom = mujoco.mjtInertiaFromGeom.mjINERTIAFROMGEOM_FALSE
    spec.body("base").add_freejoint()
    for g in spec.geoms:
        g.friction[0] = MU
        g.contype, g.conaffinity = 1, 0
    spec.worldbody.add_geom(name="ground", type=mujoco.mjtGeom.mjGEOM_PLANE, size=[0, 0, 1],
                            friction=[MU, 0.005, 0.0001], contype=1, conaffinity=1)
    spec.option.timestep = DT
    spec.option.gravity = [0.0, 0.0, -G]
    spec.option.integrator = getattr(mujoco.mjtIntegrator, "mjINT_" + integrator.upper())
    spec.option.cone = getattr(mujoco.mjtCone, "mjCONE_" + cone.upper())
    for name in TARGETS:
        spec.add_actuator(name=name, target=name, trntype=mujoco.mjtTrn.mjTRN_JOINT).set_to_position(kp=200.0, kv=1.0)
    model = spec.compile()
    data = mujoco.MjData(model)
    data.qpos[:3] = [0.0, 0.0, BASE_Z]
    for name, q in TARGETS.items():
        data.joint(name).qpos = q
        data.actuator(name).ctrl = q
    mujoco.mj_forward(model, data)
    assert abs(model.body_mass.sum() - 4.6) < 1e-12, model.body_mass.sum()
    assert np.all(model.jnt_actfrclimited[1:]) and np.all(model.jnt_actfrcrange[1:, 1] == 20.0)
    return model, data


def foot_geoms(model):
    """The foot spheres (fused by MuJoCo into the lower legs), by leg."""
    feet = {}
    for g in range(model.ngeom):
        if model.geom_type[g] == mujoco.mjtGeom.mjGEOM_SPHERE:
            feet[mujoco.mj_id2name(model, mujoco.mjtObj.mjOBJ_BODY, model.geom_bodyid[g])[:2]] = g
    return [feet[f] for f in FEET]


def mujoco_quality(integrator, cone):
    model, data = mujoco_model(integrator, cone)
    feet = foot_geoms(model)
    weight = model.body_mass.sum() * G
    force = np.zeros(6)
    samples = []  # (t, sum Fn / W, deepest penetration, foot xy)
    for step in range(NSTEP + 1):
        if step % SAMPLE_EVERY == 0:
            probe = copy.copy(data)
            mujoco.mj_forward(model, probe)
            fn, depth = 0.0, 0.0
            for i in range(probe.ncon):
                mujoco.mj_contactForce(model, probe, i, force)
                fn += force[0]
                depth = max(depth, -probe.contact[i].dist)
            samples.append((step * DT, fn / weight, depth, probe.geom_xpos[feet, :2].copy()))
        if step < NSTEP:
            mujoco.mj_step(model, data)
    return figures(samples, data.qpos[2], float(np.linalg.norm(data.qvel[:3])))


# ---------------------------------------------------------------------------------------------- tumble

def tumble_quality(tumble, tmp, extra):
    traj, contacts = os.path.join(tmp, "q.jsonl"), os.path.join(tmp, "c.jsonl")
    subprocess.run([tumble, "run", SCENE, "--quiet", "--out", traj, "--contacts", contacts] + extra, check=True)
    weight = 4.6 * G
    samples = []
    last = None
    for row, con in zip(open(traj), open(contacts)):
        row, con = json.loads(row), json.loads(con)
        assert abs(row["t"] - con["t"]) < 1e-12
        links = {b["name"]: b for b in row["bodies"]}
        fn = sum(np.dot(c["force"], c["normal"]) for c in con["contacts"])
        depth = max([c["depth"] for c in con["contacts"]], default=0.0)
        feet = np.array([links[f"quad/{f}_foot"]["position"][:2] for f in FEET])
        samples.append((row["t"], fn / weight, depth, feet))
        last = links["quad/base"]
    return figures(samples, last["position"][2], float(np.linalg.norm(last["velocity"])))


def tumble_time(tumble, tmp, extra):
    summary = os.path.join(tmp, "s.json")
    subprocess.run([tumble, "run", SCENE, "--quiet", "--summary", summary, "--out", os.path.join(tmp, "t.csv")]
                   + extra, check=True)
    s = json.load(open(summary))
    assert s["steps"] == NSTEP and s["stopped"] == "completed"
    return s["wall_time_s"]


# ---------------------------------------------------------------------------------------------- both

def figures(samples, base_z, base_speed):
    settled = [s for s in samples if s[0] >= SETTLED - 1e-9]
    ratio = np.array([s[1] for s in settled])
    feet0 = settled[0][3]
    slide = max(np.max(np.linalg.norm(s[3] - feet0, axis=1)) for s in settled)
    return {
        "base_z": base_z,
        "base_speed": base_speed,
        "fn_mean": ratio.mean(), "fn_min": ratio.min(), "fn_max": ratio.max(),
        "pen_settled": max(s[2] for s in settled),
        "pen_all": max(s[2] for s in samples),
        "slide": slide,
    }


class MujocoTimer:
    """5000 steps from the initial state, in mujoco.rollout (one thread) and in a Python loop."""

    def __init__(self, integrator, cone):
        self.model, data = mujoco_model(integrator, cone)
        spec = mujoco.mjtState.mjSTATE_FULLPHYSICS
        self.x0 = np.empty((1, mujoco.mj_stateSize(self.model, spec)))
        mujoco.mj_getState(self.model, data, self.x0[0], spec)
        self.ctrl = np.tile(data.ctrl, (1, NSTEP, 1))
        self.datas = [mujoco.MjData(self.model)]
        self.state = np.empty((1, NSTEP, self.x0.shape[1]))
        self.data0 = data
        self.roller = rollout.Rollout(nthread=0)

    def rollout(self):
        t0 = time.perf_counter()
        self.roller.rollout(self.model, self.datas, self.x0, self.ctrl, nstep=NSTEP, state=self.state)
        return time.perf_counter() - t0

    def python_loop(self):
        data = copy.copy(self.data0)
        m, step = self.model, mujoco.mj_step
        t0 = time.perf_counter()
        for _ in range(NSTEP):
            step(m, data)
        t1 = time.perf_counter()
        for _ in range(NSTEP):
            pass
        t2 = time.perf_counter()
        return (t1 - t0) - (t2 - t1), data.qpos[2]

    def base_z(self):
        return self.state[0, -1, 1 + 2]  # FULLPHYSICS: time, then qpos


def main():
    args = list(sys.argv[1:])
    pairs = 15
    if "--pairs" in args:
        i = args.index("--pairs")
        pairs = int(args[i + 1])
        del args[i:i + 2]
    tumble = args[0] if args else os.path.join(ROOT, "target", "release", "tumble")
    mj_names = [f"MuJoCo {mujoco.__version__}, {i}, {c}" for i, c in VARIANTS]
    names = [n for n, _ in TUMBLE] + mj_names
    short = ["t-rk4", "t-rk4-ns", "t-sie"] + ["mj-" + i.lower() + "-" + c[:3] for i, c in VARIANTS]

    with tempfile.TemporaryDirectory() as tmp:
        # ---- quality
        quality = {n: tumble_quality(tumble, tmp, extra) for n, extra in TUMBLE if "no samples" not in n}
        quality.update({n: mujoco_quality(i, c) for n, (i, c) in zip(mj_names, VARIANTS)})
        print("Quality: the quadruped standing, 5 s; 'settled' = over t in [1, 5] s; slide = largest horizontal")
        print("displacement of a foot centre from its place at t = 1 s; |v_base| = base speed written at 5 s")
        print("%-32s %9s %10s %24s %10s %10s %10s" % (
            "", "base z", "|v_base|", "sum Fn / weight", "depth mm", "depth mm", "slide"))
        print("%-32s %9s %10s %24s %10s %10s %10s" % (
            "", "5 s (m)", "5 s (m/s)", "settled: mean [min, max]", "settled", "whole run", "(mm)"))
        for name, q in quality.items():
            print("%-32s %9.6f %10.2e %8.5f [%.5f, %.5f] %10.3f %10.3f %10.2e" % (
                name, q["base_z"], q["base_speed"], q["fn_mean"], q["fn_min"], q["fn_max"],
                q["pen_settled"] * 1e3, q["pen_all"] * 1e3, q["slide"] * 1e3))
        print("base height, tumble rk4 - MuJoCo RK4 pyramidal: %.3f mm" % (
            (quality["tumble, rk4"]["base_z"] - quality[mj_names[0]]["base_z"]) * 1e3))
        print()

        # ---- speed, interleaved
        timers = [MujocoTimer(i, c) for i, c in VARIANTS]
        for timer, n in zip(timers, mj_names):  # warm up, and check the rollout stands where the stepping did
            timer.rollout()
            assert abs(timer.base_z() - quality[n]["base_z"]) < 1e-9, (timer.base_z(), quality[n]["base_z"])
        for _, extra in TUMBLE:
            tumble_time(tumble, tmp, extra)
        # a round runs each variant BEST times back to back and keeps the shortest (the run least
        # disturbed by the machine's other jobs); the tumble and MuJoCo runs compared are neighbours
        # in the round's order, which is reversed every other round
        times = {n: [] for n in names}
        loops = {n: [] for n in mj_names[:2]}
        order0 = [0, 3, 2, 4, 5, 6, 1]  # t-rk4, mj-rk4-pyr, t-sie, mj-euler-pyr, mj-rk4-ell, mj-euler-ell, t-rk4-ns
        for k in range(pairs):
            order = order0[::-1] if k % 2 else order0
            for j in order:
                if j < len(TUMBLE):
                    times[names[j]].append(min(tumble_time(tumble, tmp, TUMBLE[j][1]) for _ in range(BEST)))
                else:
                    timer = timers[j - len(TUMBLE)]
                    times[names[j]].append(min(timer.rollout() for _ in range(BEST)))
                    if names[j] in loops:
                        loops[names[j]].append(timer.python_loop()[0])
            print("round %2d (µs/step): " % (k + 1) + "  ".join(
                "%s %.1f" % (sn, times[n][-1] / NSTEP * 1e6) for sn, n in zip(short, names)), flush=True)
        for t in timers:
            t.roller.close()

    us = {n: np.array(t) / NSTEP * 1e6 for n, t in times.items()}
    print()
    print("Speed: µs per step, median [min, max] of %d interleaved rounds; ratios per round, median [min, max]" % pairs)
    print("%-32s %21s %24s %24s" % ("", "µs/step", "tumble rk4 / this", "tumble s.-i. Euler / this"))
    for n in names:
        r1, r2 = us[names[0]] / us[n], us[names[2]] / us[n]
        print("%-32s %6.1f [%5.1f, %5.1f] %10.2f [%.2f, %.2f] %12.2f [%.2f, %.2f]" % (
            n, np.median(us[n]), us[n].min(), us[n].max(),
            np.median(r1), r1.min(), r1.max(), np.median(r2), r2.min(), r2.max()))
    for n, t in loops.items():
        t = np.array(t) / NSTEP * 1e6
        print("%-32s %6.1f [%5.1f, %5.1f]  Python loop of mj_step, minus the empty loop" % (
            n, np.median(t), t.min(), t.max()))


if __name__ == "__main__":
    main()
