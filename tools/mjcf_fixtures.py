#!/usr/bin/env python3
"""Writes the MJCF reference fixtures of tumble's tests from MuJoCo.

Usage (from the repository root):

    python3 -m venv /tmp/venv-mj && /tmp/venv-mj/bin/pip install mujoco gymnasium numpy
    /tmp/venv-mj/bin/python tools/mjcf_fixtures.py            # every fixture but the tendon models'
    /tmp/venv-mj/bin/python tools/mjcf_fixtures.py --tendons   # the models with tendons only

For each model it copies the XML (the Allegro hand is read in place, with its meshes) into crates/tumble/tests/fixtures/mjcf/ (the Gymnasium files as
they are, MIT; the Menagerie robots from ../shared/menagerie/ with their LICENSE, without meshes:
their bodies carry <inertial>, so the dynamics needs no mesh) and writes NAME.json with a few
random states and, in MuJoCo's own conventions (tumble's tests map them with MujocoLayout):

- qpos, qvel;
- mass_matrix: mj_fullM after mj_forward (row by row), armature included;
- qfrc_bias: Coriolis, centrifugal and gravity (RNE with zero acceleration);
- qfrc_passive: joint damping and springs, tendon springs and dampers, and the fluid forces
  (MuJoCo 4 adds qfrc_fluid to it; the swimmer's <option density viscosity> makes them non-zero);
- qacc: forward dynamics with contacts, joint limits, equality constraints, friction loss and
  actuators disabled (model.opt.disableflags), so that qacc = M^-1 (qfrc_passive - qfrc_bias);
- xpos, xquat (w x y z) of every body from mj_kinematics (the world first);
- for the models with tendons (written by `--tendons`, without touching the others): ctrl, random
  controls within each ctrlrange, and qfrc_actuator, MuJoCo's actuator forces at that state with
  actuation enabled (forceranges applied), and ten_length, the tendons' lengths;
- body_velocity: mj_objectVelocity of every body frame (mjOBJ_XBODY; mjOBJ_BODY is the inertial frame), local: [omega; v] of the body origin in
  the body frame (to check the free joint's qvel: linear in the world, angular in the body frame).
"""
import json
import os
import shutil
import sys

import mujoco
import numpy as np
import gymnasium

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.normpath(os.path.join(HERE, ".."))
OUT = os.path.join(ROOT, "crates", "tumble", "tests", "fixtures", "mjcf")
GYM = os.path.join(os.path.dirname(gymnasium.__file__), "envs", "mujoco", "assets")
MENAGERIE = os.path.normpath(os.path.join(ROOT, "..", "shared", "menagerie"))

GYMNASIUM = ["ant", "half_cheetah", "hopper", "walker2d", "swimmer", "humanoid", "humanoidstandup", "reacher",
             "pusher", "inverted_pendulum", "inverted_double_pendulum"]
# (fixture name, folder, file)
MENAGERIE_MODELS = [("anymal_c", "anybotics_anymal_c", "anymal_c.xml"), ("iiwa14", "kuka_iiwa_14", "iiwa14.xml")]
# read in place from ../shared/menagerie/ (their meshes are needed: inertia from mesh geoms)
MENAGERIE_IN_PLACE = [("allegro_right", "wonik_allegro", "right_hand.xml")]
# refused (closed loops): their XML copied for the refusal tests
# models with fixed tendons and actuators on them: their fixtures also hold actuator forces
TENDON_SYNTHETIC = ["tendons"]
TENDON_MENAGERIE = [("shadow_right", "shadow_hand", "right_hand.xml")]
MENAGERIE_REFUSED = [("robotiq_2f85", ["2f85.xml", "scene.xml"]), ("agility_cassie", ["cassie.xml"])]
# small models written for the conventions (orientation forms, eulerseq, defaults, inertia from geoms)
SYNTHETIC = ["orientations", "eulerseq_radian", "eulerseq_mixed", "defaults_inertia"]
STATES = 3
DISABLE = (mujoco.mjtDisableBit.mjDSBL_CONTACT | mujoco.mjtDisableBit.mjDSBL_LIMIT
           | mujoco.mjtDisableBit.mjDSBL_EQUALITY | mujoco.mjtDisableBit.mjDSBL_FRICTIONLOSS
           | mujoco.mjtDisableBit.mjDSBL_ACTUATION)


def random_quat(rng):
    q = rng.normal(size=4)
    return q / np.linalg.norm(q)


def random_state(m, rng):
    qpos = m.qpos0.copy()
    for j in range(m.njnt):
        a = m.jnt_qposadr[j]
        t = m.jnt_type[j]
        if t == mujoco.mjtJoint.mjJNT_FREE:
            qpos[a:a + 3] = rng.uniform(-1, 1, 3)
            qpos[a + 3:a + 7] = random_quat(rng)
        elif t == mujoco.mjtJoint.mjJNT_BALL:
            qpos[a:a + 4] = random_quat(rng)
        else:
            qpos[a] += rng.uniform(-1, 1)
    qvel = rng.normal(scale=1.0, size=m.nv)
    return qpos, qvel


def random_ctrl(m, rng):
    """A control per actuator: uniform in its ctrlrange (clamped a little outside, to test the
    clamp), or normal when it has none."""
    u = rng.normal(size=m.nu)
    for a in range(m.nu):
        if m.actuator_ctrllimited[a]:
            lo, hi = m.actuator_ctrlrange[a]
            u[a] = rng.uniform(lo - 0.2 * (hi - lo), hi + 0.2 * (hi - lo))
    return u


def actuator_forces(m, qpos, qvel, ctrl):
    """qfrc_actuator and ten_length at a state, with actuation enabled."""
    flags = m.opt.disableflags
    m.opt.disableflags = flags & ~int(mujoco.mjtDisableBit.mjDSBL_ACTUATION)
    d = mujoco.MjData(m)
    d.qpos[:] = qpos
    d.qvel[:] = qvel
    d.ctrl[:] = ctrl
    mujoco.mj_forward(m, d)
    m.opt.disableflags = flags
    return d.qfrc_actuator.tolist(), d.ten_length.tolist()


def fixture(name, path, rng, actuated=False):
    m = mujoco.MjModel.from_xml_path(path)
    m.opt.disableflags |= DISABLE
    d = mujoco.MjData(m)
    states = []
    for _ in range(STATES):
        qpos, qvel = random_state(m, rng)
        d.qpos[:] = qpos
        d.qvel[:] = qvel
        d.ctrl[:] = 0
        mujoco.mj_forward(m, d)
        full = np.zeros((m.nv, m.nv))
        mujoco.mj_fullM(m, d, full)
        vel = np.zeros((m.nbody, 6))
        for b in range(m.nbody):
            mujoco.mj_objectVelocity(m, d, mujoco.mjtObj.mjOBJ_XBODY, b, vel[b], 1)
        states.append({
            "qpos": qpos.tolist(),
            "qvel": qvel.tolist(),
            "mass_matrix": full.reshape(-1).tolist(),
            "qfrc_bias": d.qfrc_bias.tolist(),
            "qfrc_passive": d.qfrc_passive.tolist(),
            "qacc": d.qacc.tolist(),
            "xpos": d.xpos.reshape(-1).tolist(),
            "xquat": d.xquat.reshape(-1).tolist(),
            "body_velocity": vel.reshape(-1).tolist(),
        })
        if actuated:
            ctrl = random_ctrl(m, rng)
            states[-1]["ctrl"] = ctrl.tolist()
            states[-1]["qfrc_actuator"], states[-1]["ten_length"] = actuator_forces(m, qpos, qvel, ctrl)
    names = lambda kind, n: [mujoco.mj_id2name(m, kind, i) for i in range(n)]
    return {
        "model": name,
        "mujoco": mujoco.__version__,
        "nq": m.nq,
        "nv": m.nv,
        "qpos0": m.qpos0.tolist(),
        "bodies": names(mujoco.mjtObj.mjOBJ_BODY, m.nbody),
        "joints": names(mujoco.mjtObj.mjOBJ_JOINT, m.njnt),
        "body_mass": m.body_mass.tolist(),
        "gravity": m.opt.gravity.tolist(),
        "timestep": m.opt.timestep,
        "states": states,
    }


def write(name, data):
    with open(os.path.join(OUT, name + ".json"), "w") as f:
        json.dump(data, f, separators=(",", ":"))
        f.write("\n")


def tendons():
    """The models with tendons, with their own random states (the other fixtures are untouched); the
    Shadow hand's collision meshes beside its copy."""
    rng = np.random.default_rng(24)
    for name in TENDON_SYNTHETIC:
        write(name, fixture(name, os.path.join(OUT, "synthetic", name + ".xml"), rng, actuated=True))
        print(name)
    for name, folder, file in TENDON_MENAGERIE:
        src = os.path.join(MENAGERIE, folder, file)
        dst = os.path.join(OUT, "menagerie", file.replace(".xml", "_" + folder + ".xml"))
        shutil.copyfile(src, dst)
        shutil.copyfile(os.path.join(MENAGERIE, folder, "LICENSE"), os.path.join(OUT, "menagerie", name + ".LICENSE"))
        # the meshes of the geoms that can collide, which a scene's robot needs (the visual ones stay out)
        m = mujoco.MjModel.from_xml_path(src)
        spec = mujoco.MjSpec.from_file(src)
        assets = os.path.join(OUT, "menagerie", spec.meshdir)
        os.makedirs(assets, exist_ok=True)
        for g in range(m.ngeom):
            if m.geom_type[g] == mujoco.mjtGeom.mjGEOM_MESH and (m.geom_contype[g] or m.geom_conaffinity[g]):
                file = spec.mesh(mujoco.mj_id2name(m, mujoco.mjtObj.mjOBJ_MESH, m.geom_dataid[g])).file
                shutil.copyfile(os.path.join(MENAGERIE, folder, spec.meshdir, file), os.path.join(assets, file))
        write(name, fixture(name, src, rng, actuated=True))
        print(name)


def main():
    if sys.argv[1:] == ["--tendons"]:
        tendons()
        return
    os.makedirs(os.path.join(OUT, "gymnasium"), exist_ok=True)
    os.makedirs(os.path.join(OUT, "menagerie"), exist_ok=True)
    rng = np.random.default_rng(23)
    for name in GYMNASIUM:
        src = os.path.join(GYM, name + ".xml")
        dst = os.path.join(OUT, "gymnasium", name + ".xml")
        shutil.copyfile(src, dst)
        write(name, fixture(name, dst, rng))
        print(name)
    for name in SYNTHETIC:
        write(name, fixture(name, os.path.join(OUT, "synthetic", name + ".xml"), rng))
        print(name)
    lic = os.path.join(os.path.dirname(gymnasium.__file__), "..", "gymnasium-%s.dist-info" % gymnasium.__version__,
                       "licenses", "LICENSE")
    if os.path.exists(lic):
        shutil.copyfile(lic, os.path.join(OUT, "gymnasium", "LICENSE"))
    for name, folder, file in MENAGERIE_MODELS:
        src = os.path.join(MENAGERIE, folder, file)
        if not os.path.exists(src):
            print("skipped (not found):", src, file=sys.stderr)
            continue
        dst = os.path.join(OUT, "menagerie", file)
        shutil.copyfile(src, dst)
        shutil.copyfile(os.path.join(MENAGERIE, folder, "LICENSE"), os.path.join(OUT, "menagerie", name + ".LICENSE"))
        # MuJoCo compiles the original (its meshes are beside it); the copy without meshes is what tumble reads
        write(name, fixture(name, src, rng))
        print(name)
    for name, folder, file in MENAGERIE_IN_PLACE:
        write(name, fixture(name, os.path.join(MENAGERIE, folder, file), rng))
        print(name)
    for folder, files in MENAGERIE_REFUSED:
        os.makedirs(os.path.join(OUT, "menagerie", folder), exist_ok=True)
        for file in files + ["LICENSE"]:
            shutil.copyfile(os.path.join(MENAGERIE, folder, file), os.path.join(OUT, "menagerie", folder, file))


if __name__ == "__main__":
    main()
