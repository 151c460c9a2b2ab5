"""MuJoCo's state at a keyframe: crates/tumble/tests/fixtures/mjcf/keyframe/keys.xml (a free box
beside a tree with a free root, a hinge with `ref`, a ball and a slide with `ref`, two actuators,
a named key with non-unit quaternions, velocities and controls, and an unnamed key) and keys.json:
for each key, MuJoCo's qpos after mj_resetDataKeyframe and mj_normalizeQuat, qvel, ctrl, and the
free box's frame (xpos, xquat) and velocity at its centre of mass in the world frame
(mj_objectVelocity, mjOBJ_BODY, world axes: [angular; linear]). Read by
crates/tumble/tests/mjcf_world.rs.

    /work/venv/bin/python tools/mjcf_keyframe_fixtures.py
"""
import json
import pathlib

import mujoco
import numpy as np

OUT = pathlib.Path(__file__).resolve().parent.parent / "crates/tumble/tests/fixtures/mjcf/keyframe"

XML = """<mujoco model="keys">
  <compiler angle="radian"/>
  <option timestep="0.001"/>
  <worldbody>
    <geom name="floor" type="plane" size="5 5 0.1"/>
    <body name="box" pos="1 0 0.5">
      <freejoint name="box_free"/>
      <geom type="box" size="0.1 0.2 0.05"/>
    </body>
    <body name="torso" pos="0 0 1">
      <freejoint name="root"/>
      <geom type="sphere" size="0.1"/>
      <body name="arm" pos="0.2 0 0">
        <joint name="hinge" type="hinge" axis="0 1 0" ref="0.3" range="-2 2"/>
        <geom type="capsule" fromto="0 0 0 0.3 0 0" size="0.03"/>
        <body name="hand" pos="0.3 0 0">
          <joint name="ball" type="ball"/>
          <geom type="sphere" size="0.04" pos="0.05 0 0"/>
          <body name="finger">
            <joint name="slide" type="slide" axis="1 0 0" ref="0.01"/>
            <geom type="box" size="0.02 0.01 0.01" pos="0.1 0 0"/>
          </body>
        </body>
      </body>
    </body>
  </worldbody>
  <actuator>
    <position name="servo" joint="hinge" kp="10"/>
    <motor name="push" joint="slide"/>
  </actuator>
  <keyframe>
    <key name="spin" time="1.5"
         qpos="1.2 -0.3 0.8  2 0.4 -0.2 1   0.1 0.2 1.1  1 0.1 0 0.3   0.7   0.9 0 0.3 0.1   0.04"
         qvel="0.5 -1 2  3 -2 1   0.1 -0.2 0.3  0.4 0.5 -0.6   1.5   -0.3 0.2 0.7   0.05"
         ctrl="0.4 -1"/>
    <key qpos="1 0 0.05  1 0 0 0   0 0 1  1 0 0 0   0.3   1 0 0 0   0.01"/>
  </keyframe>
</mujoco>
"""


def main():
    OUT.mkdir(parents=True, exist_ok=True)
    (OUT / "keys.xml").write_text(XML)
    m = mujoco.MjModel.from_xml_string(XML)
    d = mujoco.MjData(m)
    box = mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_BODY, "box")
    keys = {}
    for k in range(m.nkey):
        mujoco.mj_resetDataKeyframe(m, d, k)
        mujoco.mj_normalizeQuat(m, d.qpos)
        mujoco.mj_forward(m, d)
        vel = np.zeros(6)
        mujoco.mj_objectVelocity(m, d, mujoco.mjtObj.mjOBJ_BODY, box, vel, 0)
        name = m.key(k).name or str(k)
        keys[name] = {
            "time": float(d.time),
            "qpos": d.qpos.tolist(),
            "qvel": d.qvel.tolist(),
            "ctrl": d.ctrl.tolist(),
            "box_xpos": d.xpos[box].tolist(),
            "box_xquat": d.xquat[box].tolist(),
            "box_xipos": d.xipos[box].tolist(),
            "box_angular_world": vel[:3].tolist(),
            "box_linear_world": vel[3:].tolist(),
        }
    out = {"mujoco": mujoco.__version__, "keys": keys}
    (OUT / "keys.json").write_text(json.dumps(out, indent=1) + "\n")
    print(json.dumps(out, indent=1)[:1500])


if __name__ == "__main__":
    main()
