#!/usr/bin/env python3
"""Writes the multibody reference fixtures of tumble's tests from Pinocchio.

Usage (from the repository root):

    python3 -m venv /tmp/venv-pin && /tmp/venv-pin/bin/pip install pin example-robot-data numpy
    /tmp/venv-pin/bin/python tools/pinocchio_fixtures.py

For each robot it copies the URDF into crates/tumble/tests/fixtures/robots/ (without <visual>,
<collision>, <gazebo> and <transmission> elements, which carry no dynamics, to keep the copies small)
and writes NAME.json: a few random states and Pinocchio's mass matrix (CRBA), bias forces
(RNEA with a = 0), inverse dynamics tau = RNEA(q, v, a) and forward dynamics qdd = ABA(q, v, tau_in).

Conventions converted here, so that the fixtures speak tumble's conventions:
- free-flyer q: Pinocchio [x, y, z, qx, qy, qz, qw] -> tumble [x, y, z, qw, qx, qy, qz];
- free-flyer v: both [linear; angular] in the base frame (no change);
- continuous joints: Pinocchio (cos t, sin t) -> tumble t;
- matrices are written row by row.
The URDFs come from example-robot-data (BSD-3-Clause).
"""
import json
import os
import re
import sys

import numpy as np
import pinocchio as pin

# the robots of the example-robot-data package, installed by pip under cmeel.prefix
_PIN = os.path.abspath(pin.__file__)
ROBOTS_DIR = os.path.join(_PIN[:_PIN.index("cmeel.prefix")], "cmeel.prefix", "share", "example-robot-data", "robots")
OUT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "crates", "tumble", "tests", "fixtures",
                   "robots")

# (fixture name, URDF under robots/, floating base)
ROBOTS = [
    ("double_pendulum", "double_pendulum_description/urdf/double_pendulum.urdf", False),
    ("double_pendulum_continuous", "double_pendulum_description/urdf/double_pendulum_continuous.urdf", False),
    ("ur5", "ur_description/urdf/ur5_robot.urdf", False),
    ("panda", "panda_description/urdf/panda.urdf", False),
    ("solo12", "solo_description/robots/solo12.urdf", True),
    ("talos_reduced", "talos_data/robots/talos_reduced.urdf", True),
]
STATES = 3


def strip(text):
    """The URDF without the elements that carry no dynamics."""
    for tag in ("visual", "collision", "gazebo", "transmission"):
        text = re.sub(r"<%s\b.*?</%s>" % (tag, tag), "", text, flags=re.S)
        text = re.sub(r"<%s\b[^>]*/>" % tag, "", text)
    text = re.sub(r"<!--.*?-->", "", text, flags=re.S)
    return "\n".join(line for line in text.splitlines() if line.strip()) + "\n"


def random_state(model, rng):
    """A random (q, v) in Pinocchio's conventions, and q in tumble's."""
    q_pin = np.zeros(model.nq)
    q_tumble = []
    for j in model.joints[1:]:
        kind = j.shortname()
        iq = j.idx_q
        if kind == "JointModelFreeFlyer":
            p = rng.uniform(-1, 1, 3)
            quat = rng.normal(size=4)
            quat /= np.linalg.norm(quat)  # x, y, z, w
            q_pin[iq:iq + 7] = np.concatenate([p, quat])
            q_tumble += list(p) + [quat[3], quat[0], quat[1], quat[2]]
        elif kind.startswith("JointModelRUB"):  # continuous: cos, sin
            t = rng.uniform(-np.pi, np.pi)
            q_pin[iq:iq + 2] = [np.cos(t), np.sin(t)]
            q_tumble.append(t)
        elif j.nq == 1:
            t = rng.uniform(-1.5, 1.5)
            q_pin[iq] = t
            q_tumble.append(t)
        else:
            raise ValueError("unexpected joint " + kind)
    v = rng.uniform(-2, 2, model.nv)
    return q_pin, np.array(q_tumble), v


def fixture(name, rel, floating, seed):
    path = os.path.join(ROBOTS_DIR, rel)
    with open(path) as f:
        text = f.read()
    urdf_name = name + ".urdf"
    with open(os.path.join(OUT, urdf_name), "w") as f:
        f.write(strip(text))
    model = pin.buildModelFromUrdf(path, pin.JointModelFreeFlyer()) if floating else pin.buildModelFromUrdf(path)
    data = model.createData()
    rng = np.random.default_rng(seed)
    states = []
    for _ in range(STATES):
        q, q_tumble, v = random_state(model, rng)
        a = rng.uniform(-3, 3, model.nv)
        tau_in = rng.uniform(-10, 10, model.nv)
        tau = pin.rnea(model, data, q, v, a).copy()
        bias = pin.rnea(model, data, q, v, np.zeros(model.nv)).copy()
        m = pin.crba(model, data, q).copy()
        m = np.triu(m) + np.triu(m, 1).T  # Pinocchio fills the upper triangle
        qdd = pin.aba(model, data, q, v, tau_in).copy()
        states.append({
            "q": q_tumble.tolist(), "v": v.tolist(), "a": a.tolist(), "tau_in": tau_in.tolist(),
            "tau": tau.tolist(), "bias": bias.tolist(), "qdd": qdd.tolist(),
            "mass_matrix": m.tolist(),
        })
    joints = [{"name": n, "nq": (j.nq if j.shortname() != "JointModelFreeFlyer" else 7) - (
        1 if j.shortname().startswith("JointModelRUB") else 0), "nv": j.nv}
        for n, j in zip(model.names[1:], model.joints[1:])]
    out = {
        "robot": name, "urdf": urdf_name, "floating": floating, "source": "example-robot-data/robots/" + rel,
        "generator": "tools/pinocchio_fixtures.py, pinocchio %s" % pin.__version__,
        "gravity": model.gravity.linear.tolist(), "nv": model.nv, "total_mass": float(sum(
            i.mass for i in model.inertias[1:])),
        "joints": joints, "states": states,
    }
    with open(os.path.join(OUT, name + ".json"), "w") as f:
        json.dump(out, f, indent=None, separators=(",", ":"))
        f.write("\n")
    print("%-28s nq=%d nv=%d  %d states" % (name, model.nq, model.nv, len(states)))


def main():
    os.makedirs(OUT, exist_ok=True)
    for seed, (name, rel, floating) in enumerate(ROBOTS):
        fixture(name, rel, floating, 1000 + seed)


if __name__ == "__main__":
    main()
