#!/usr/bin/env python3
"""Writes the contact-point fixture of tumble's tests from Pinocchio: the Jacobian of a point on a link,
its collision matrix K = J M^-1 J^T, and the velocity after a rigid impact there.

Usage (from the repository root; a venv with `pin`, e.g. the one of tools/pinocchio_fixtures.py):

    /tmp/venv-pin/bin/python tools/pinocchio_impulse.py

For each model (scenes/robots/panda.urdf and scenes/robots/double_pendulum.urdf on a fixed base, the
Panda on a free-flyer base) it adds a few frames at random points of random moving links, and for a few
random states writes, per point:
- `point_link`: the point in its link's frame (m), and `point_world` (m);
- `jacobian`: the 3 x nv Jacobian of the point's world velocity, rows x, y, z
  (`getFrameJacobian(..., LOCAL_WORLD_ALIGNED)`, its linear rows: Pinocchio puts them first);
- `collision_matrix`: K = J M^-1 J^T, with M^-1 from `computeMinverse` (upper triangle, symmetrised);
- `v_after_r0`, `v_after_r1` and `impulse_r0`, `impulse_r1`: `impulseDynamics(model, data, q, v, J, r)`
  for r = 0 (the point stops) and r = 1 (its velocity reverses), and Pinocchio's contact impulse. Rows of J
  that vanish are left out of that call (the double pendulum moves in the y-z plane, so its x row is zero and
  J M^-1 J^T singular, which impulseDynamics cannot factor without damping); their impulse is written as 0.

Conventions are those of tools/pinocchio_fixtures.py (free-flyer q as [x, y, z, qw, qx, qy, qz], both
engines' free-flyer v as [linear; angular] in the base frame, continuous joints as one angle); vectors follow
Pinocchio's joint order, listed in `joints`.

scenes/robots/double_pendulum.urdf writes only `ixx iyy izz`; Pinocchio's URDF parser (urdfdom) then drops the
whole <inertial> element with an error, so the missing products of inertia are written as the URDF default 0
into a temporary copy, which is what Pinocchio reads (the masses are checked against tumble in the test).
"""
import json
import os
import re
import sys
import tempfile

import numpy as np
import pinocchio as pin

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from pinocchio_fixtures import random_state  # noqa: E402

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..")
OUT = os.path.join(ROOT, "crates", "tumble", "tests", "fixtures", "contact_point.json")

# (name, URDF under the repository root, floating base)
MODELS = [
    ("panda", "scenes/robots/panda.urdf", False),
    ("double_pendulum", "scenes/robots/double_pendulum.urdf", False),
    ("panda_floating", "scenes/robots/panda.urdf", True),
]
STATES = 3
POINTS = 4


def with_products_of_inertia(text):
    """The URDF with ixy, ixz, iyz = 0 (the URDF default) written where an <inertia> omits them."""
    def fill(m):
        tag = m.group(0)
        for key in ("ixy", "ixz", "iyz"):
            if key + "=" not in tag:
                tag = tag.replace("<inertia", '<inertia %s="0"' % key, 1)
        return tag
    return re.sub(r"<inertia\b[^>]*>", fill, text)


def load(rel, floating):
    with open(os.path.join(ROOT, rel)) as f:
        text = with_products_of_inertia(f.read())
    with tempfile.NamedTemporaryFile("w", suffix=".urdf", delete=False) as f:
        f.write(text)
        path = f.name
    try:
        return pin.buildModelFromUrdf(path, pin.JointModelFreeFlyer()) if floating else pin.buildModelFromUrdf(path)
    finally:
        os.unlink(path)


def symmetric(upper):
    """Pinocchio fills the upper triangle of M and M^-1."""
    return np.triu(upper) + np.triu(upper, 1).T


def fixture(name, rel, floating, seed):
    model = load(rel, floating)
    rng = np.random.default_rng(seed)
    # links moved by a joint (not fixed to the world)
    # (copies: adding frames reallocates model.frames)
    links = [(f.name, f.parentJoint, pin.SE3(f.placement)) for f in model.frames
             if f.type == pin.FrameType.BODY and f.parentJoint > 0]
    points = []
    for p in range(POINTS):
        link_name, joint, link_placement = links[rng.integers(len(links))]
        point_link = rng.uniform(-0.15, 0.15, 3)
        # the point's frame, placed in the link's joint frame
        placement = link_placement * pin.SE3(np.eye(3), point_link)
        fid = model.addFrame(pin.Frame("contact_%d" % p, joint, model.getFrameId(link_name), placement,
                                       pin.FrameType.OP_FRAME))
        points.append((link_name, point_link, fid))
    data = model.createData()
    states = []
    for _ in range(STATES):
        q, q_tumble, v = random_state(model, rng)
        pin.computeJointJacobians(model, data, q)
        pin.updateFramePlacements(model, data)
        minv = symmetric(pin.computeMinverse(model, data, q).copy())
        contacts = []
        for link_name, point_link, fid in points:
            point_world = data.oMf[fid].translation.copy()
            jac = pin.getFrameJacobian(model, data, fid, pin.LOCAL_WORLD_ALIGNED)[:3].copy()
            k = jac @ minv @ jac.T
            entry = {"link": link_name, "point_link": point_link.tolist(), "point_world": point_world.tolist(),
                     "jacobian": jac.tolist(), "collision_matrix": k.tolist()}
            # rows of J that vanish (the planar double pendulum's x row) constrain nothing and would make
            # J M^-1 J^T singular, which impulseDynamics (a Cholesky factor, no damping here) cannot take
            rows = [i for i in range(3) if np.abs(jac[i]).max() > 1e-14]
            for r in (0, 1):
                v_after = pin.impulseDynamics(model, data, q, v, jac[rows], float(r)).copy()
                impulse = np.zeros(3)
                impulse[rows] = np.asarray(data.impulse_c)
                entry["v_after_r%d" % r] = v_after.tolist()
                entry["impulse_r%d" % r] = impulse.tolist()
                # Pinocchio's own check of its impact: J v+ = -r J v-
                residual = np.abs(jac @ v_after + r * (jac @ v)).max()
                assert residual <= 1e-9 * max(1.0, np.abs(jac @ v).max()), (name, link_name, r, residual)
            contacts.append(entry)
        states.append({"q": q_tumble.tolist(), "v_before": v.tolist(), "contacts": contacts})
    joints = [{"name": n, "nq": (j.nq if j.shortname() != "JointModelFreeFlyer" else 7) - (
        1 if j.shortname().startswith("JointModelRUB") else 0), "nv": j.nv}
        for n, j in zip(model.names[1:], model.joints[1:])]
    print("%-16s nv=%d  %d states x %d points, mass %.6f" % (name, model.nv, STATES, POINTS,
                                                           sum(i.mass for i in model.inertias[1:])))
    return {"name": name, "urdf": rel, "floating": floating, "nv": model.nv,
            "moving_mass": float(sum(i.mass for i in model.inertias[1:])), "joints": joints, "states": states}


def main():
    out = {"generator": "tools/pinocchio_impulse.py, pinocchio %s" % pin.__version__,
           "models": [fixture(name, rel, floating, 2000 + s) for s, (name, rel, floating) in enumerate(MODELS)]}
    with open(OUT, "w") as f:
        json.dump(out, f, indent=None, separators=(",", ":"))
        f.write("\n")


if __name__ == "__main__":
    main()
