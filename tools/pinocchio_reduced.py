#!/usr/bin/env python3
"""Writes the reduced-model fixture of tumble's tests from Pinocchio's buildReducedModel.

Usage (from the repository root):

    python3 -m venv /tmp/venv-pin && /tmp/venv-pin/bin/pip install pin numpy
    /tmp/venv-pin/bin/python tools/pinocchio_reduced.py

For each case: a robot of crates/tumble/tests/fixtures/robots/ (the URDFs that
tools/pinocchio_fixtures.py copied), the joints to lock and a random reference configuration
q_ref; Pinocchio's buildReducedModel(model, locked, q_ref) holds them at their value in q_ref. For
a few random states of the reduced model the fixture gives its joint names (in Pinocchio's order),
mass matrix (CRBA), bias forces (RNEA with a = 0) and the world placement of every link frame
(oMf after framesForwardKinematics), so that the frames re-parented onto the merged bodies are
checked too.

Conventions as in tools/pinocchio_fixtures.py: free-flyer q written [x, y, z, qw, qx, qy, qz],
v [linear; angular] in the base frame, matrices row by row; a frame's placement as its rotation
world_from_link (rows) and its origin in the world.
Writes crates/tumble/tests/fixtures/robots/reduced.json.
"""
import json
import os

import numpy as np
import pinocchio as pin

from pinocchio_fixtures import OUT, random_state

# (robot, floating base, joints to lock)
CASES = [
    ("panda", False, ["panda_joint4", "panda_finger_joint1", "panda_finger_joint2"]),
    ("panda", False, ["panda_joint1", "panda_joint6"]),
    ("solo12", True, ["FL_KFE", "HR_HAA", "HR_HFE", "HR_KFE"]),
    ("talos_reduced", True, ["torso_2_joint", "arm_left_4_joint", "arm_right_1_joint", "arm_right_2_joint",
                             "gripper_left_joint", "head_1_joint", "head_2_joint"]),
]
STATES = 3


def case(robot, floating, locked, seed):
    path = os.path.join(OUT, robot + ".urdf")
    model = pin.buildModelFromUrdf(path, pin.JointModelFreeFlyer()) if floating else pin.buildModelFromUrdf(path)
    rng = np.random.default_rng(seed)
    q_ref, q_ref_tumble, _ = random_state(model, rng)
    reduced = pin.buildReducedModel(model, [model.getJointId(n) for n in locked], q_ref)
    data = reduced.createData()
    links = [f.name for f in reduced.frames if f.type == pin.FrameType.BODY]
    states = []
    for _ in range(STATES):
        q, q_tumble, v = random_state(reduced, rng)
        m = pin.crba(reduced, data, q).copy()
        m = np.triu(m) + np.triu(m, 1).T  # Pinocchio fills the upper triangle
        bias = pin.rnea(reduced, data, q, v, np.zeros(reduced.nv)).copy()
        pin.framesForwardKinematics(reduced, data, q)
        frames = {}
        for name in links:
            placement = data.oMf[reduced.getFrameId(name)]
            frames[name] = {"rotation": placement.rotation.tolist(), "origin": placement.translation.tolist()}
        states.append({"q": q_tumble.tolist(), "v": v.tolist(), "mass_matrix": m.tolist(), "bias": bias.tolist(),
                       "frames": frames})
    print("%-14s locked %-60s nq %d -> %d, nv %d -> %d" % (robot, ",".join(locked), model.nq, reduced.nq,
                                                          model.nv, reduced.nv))
    return {"robot": robot, "urdf": robot + ".urdf", "floating": floating, "locked": locked,
            "q_ref": q_ref_tumble.tolist(), "joints": list(reduced.names)[1:], "nq": reduced.nq, "nv": reduced.nv,
            "states": states}


def main():
    cases = [case(robot, floating, locked, 2000 + k) for k, (robot, floating, locked) in enumerate(CASES)]
    out = {"generator": "tools/pinocchio_reduced.py, pinocchio %s (buildReducedModel)" % pin.__version__,
           "cases": cases}
    with open(os.path.join(OUT, "reduced.json"), "w") as f:
        json.dump(out, f, indent=None, separators=(",", ":"))
        f.write("\n")


if __name__ == "__main__":
    main()
