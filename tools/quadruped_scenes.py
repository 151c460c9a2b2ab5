#!/usr/bin/env python3
"""Writes the quadruped scenes of example-robot-data: scenes/{solo12,go1,anymal_c}_{stand,trot}.toml.

    python tools/quadruped_scenes.py

Each robot stands in the standing pose of its SRDF (example-robot-data 6.0.0), let go 5 mm above
the SRDF's base height, held by PD at those angles, on a plane, dt = 1e-3 s, semi-implicit Euler,
friction 0.9 on the floor and on every link. The trot variant adds to the knee and hip-flexion
targets a sine of 2 Hz, the diagonal pairs (FL+HR, FR+HL) half a period apart, so that the feet
lift and land; the velocity target stays 0 (tau = kp (q*(t) - q) - kd v, as MuJoCo's position
actuator with its ctrl set to q*(t)). `tools/quadruped_mujoco_bench.py` reads these scenes to build
the same models in MuJoCo.
"""
import math
import os

ROOT = os.path.normpath(os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
ERD = "robots/example-robot-data/robots"

ROBOTS = {
    "solo12": dict(
        title="Solo-12 (2.5 kg, 12 joints, STL collision meshes for every link)",
        urdf=f"{ERD}/solo_description/robots/solo12.urdf",
        z=0.235, feet=0.0, balance=False, kp=20.0, kd=0.5,
        legs=[("FL", 0.1, 0.8, -1.6), ("FR", -0.1, 0.8, -1.6), ("HL", 0.1, -0.8, 1.6), ("HR", -0.1, -0.8, 1.6)],
        names=("HAA", "HFE", "KFE"), sep="_", suffix=""),
    "go1": dict(
        title="Unitree Go1 (12.7 kg, 12 joints, boxes and cylinders, sphere feet; balance_inertia for its URDF)",
        urdf=f"{ERD}/go1_description/urdf/go1.urdf",
        # kd = 2 leaves the landing's slow pitch rocking for some 3 s (5 mm of base motion after 1 s)
        z=0.26, feet=-0.0088, balance=True, kp=60.0, kd=4.0,
        legs=[("FL", 0.0, 0.8, -1.853), ("FR", 0.0, 0.8, -1.853), ("RL", 0.0, 0.8, -1.853), ("RR", 0.0, 0.8, -1.853)],
        names=("hip", "thigh", "calf"), sep="_", suffix="_joint"),
    "anymal_c": dict(
        title="ANYmal C (52 kg, 12 joints, boxes and cylinders, sphere feet; balance_inertia for its URDF)",
        urdf=f"{ERD}/anymal_c_simple_description/urdf/anymal.urdf",
        z=0.528, feet=-0.0076, balance=True, kp=200.0, kd=5.0,
        legs=[("LF", -0.1, 0.7, -1.0), ("RF", 0.1, 0.7, -1.0), ("LH", -0.1, -0.7, 1.0), ("RH", 0.1, -0.7, 1.0)],
        names=("HAA", "HFE", "KFE"), sep="_", suffix=""),
}
DROP = 0.005        # m: the feet's lowest point above the floor when let go
# `feet`: the height of the feet's lowest point (m) with the base at the SRDF's standing height `z`,
# as tumble's forward kinematics of the URDF gives it (Go1's and ANYmal C's SRDF heights put their
# sphere feet 8.8 and 7.6 mm into the floor; Solo-12's mesh feet touch it)
FRICTION = 0.9
GAIT_HZ = 2.0
KNEE_AMPLITUDE = 0.35   # rad
HIP_AMPLITUDE = 0.15    # rad, a quarter period ahead of the knee


def joint(r, leg, k):
    return f"{leg}{r['sep']}{r['names'][k]}{r['suffix']}"


def scene(key, trot):
    r = ROBOTS[key]
    lines = []
    what = "trotting in place" if trot else "standing"
    lines.append(f"# {r['title']},")
    lines.append(f"# {what} on the floor under PD (example-robot-data 6.0.0; written by tools/quadruped_scenes.py).")
    lines.append("# Let go in its SRDF standing pose with its feet 5 mm above the floor, it lands on them and")
    if trot:
        lines.append(f"# stands; its knee and hip-flexion targets then swing at {GAIT_HZ:g} Hz, diagonal legs half a period apart,")
        lines.append("# so that the feet lift and land.")
    else:
        lines.append("# stands: the feet's normal forces carry its weight, the feet stay where they landed.")
    lines += ["version = 1", "", "[world]", "gravity = [0.0, 0.0, -9.81]   # m/s²", "dt = 0.001                    # s",
              "duration = 5.0                # s", 'integrator = "semi_implicit_euler"', "sample_every = 10", "",
              "[[body]]", 'name = "ground"', 'shape = { type = "plane" }    # z = 0', "fixed = true",
              f"friction = {FRICTION}", "", "[[robot]]", f'name = "{key}"', f'urdf = "{r["urdf"]}"', 'base = "floating"',
              f"position = [0.0, 0.0, {r['z'] - r['feet'] + DROP:.4f}]  # m: the base, its feet 5 mm above the floor (SRDF standing height {r['z']} m)"]
    q = []
    for leg, haa, hfe, kfe in r["legs"]:
        for k, v in enumerate((haa, hfe, kfe)):
            q.append(f"{joint(r, leg, k)} = {v}")
    lines.append("q = { " + ", ".join(q) + " }")
    lines.append(f"friction = {FRICTION}               # of every link")
    if r["balance"]:
        lines.append("balance_inertia = true        # the URDF has link inertias that are not physical")
    lines += ["", "[robot.pd]                    # N·m/rad, N·m·s/rad" + ("; amplitude rad, frequency Hz, phase rad" if trot else "")]
    for n, (leg, haa, hfe, kfe) in enumerate(r["legs"]):
        diagonal = leg in ("FL", "HR", "RR", "LF", "RH") if key != "go1" else leg in ("FL", "RR")
        if key == "anymal_c":
            diagonal = leg in ("LF", "RH")
        if key == "solo12":
            diagonal = leg in ("FL", "HR")
        phase = 0.0 if diagonal else math.pi
        sign = 1.0 if hfe > 0 else -1.0   # hind legs of Solo and ANYmal bend the other way
        for k, v in enumerate((haa, hfe, kfe)):
            gains = f"target = {v}, kp = {r['kp']}, kd = {r['kd']}"
            if trot and k == 1:
                gains += f", amplitude = {sign * HIP_AMPLITUDE}, frequency = {GAIT_HZ}, phase = {phase + math.pi / 2!r}"
            if trot and k == 2:
                gains += f", amplitude = {-sign * KNEE_AMPLITUDE}, frequency = {GAIT_HZ}, phase = {phase!r}"
            lines.append(f"{joint(r, leg, k)} = {{ {gains} }}")
    return "\n".join(lines) + "\n"


def main():
    for key in ROBOTS:
        for trot in (False, True):
            path = os.path.join(ROOT, "scenes", f"{key}_{'trot' if trot else 'stand'}.toml")
            with open(path, "w") as f:
                f.write(scene(key, trot))
            print(path)


if __name__ == "__main__":
    main()
