"""MJCF from Python: `Model.from_mjcf` reads a MuJoCo world, `World.set_ctrl` drives its actuators."""

import pickle

import numpy as np
import pytest

import tumble
from conftest import REPO

ANT = REPO / "crates/tumble/tests/fixtures/mjcf/gymnasium/ant.xml"

# a pendulum (2 kg, centre of mass 0.5 m below a hinge about x) with a position servo and a motor
SERVO = """<mujoco model="servo">
  <compiler angle="radian"/>
  <option timestep="0.001" integrator="Euler"/>
  <worldbody>
    <body name="bob">
      <joint name="pivot" type="hinge" axis="1 0 0" damping="10"/>
      <inertial pos="0 0 -0.5" mass="2" diaginertia="0.02 0.02 0.01"/>
    </body>
  </worldbody>
  <actuator>
    <position name="servo" joint="pivot" kp="50" ctrlrange="-1 1"/>
    <motor name="push" joint="pivot" gear="2"/>
  </actuator>
</mujoco>
"""


def test_from_mjcf_reads_the_options_the_floor_and_the_tree():
    m = tumble.Model.from_mjcf(ANT)
    assert m.robot_names == ["ant"]
    # ant.xml: <option timestep="0.01" integrator="RK4">
    assert m.dt == 0.01 and m.integrator == "rk4"
    # its motors are unnamed: actuatorN, in the file's order (as MuJoCo numbers them)
    assert m.actuator_names() == [f"actuator{i}" for i in range(8)]
    w = tumble.World(m)
    z0 = w.state()[2]
    w.step(200)
    x = w.state()
    assert np.all(np.isfinite(x))
    # the free root's z: the torso came down onto its legs on the floor plane of the file
    assert 0.2 < x[2] < z0
    # pickled and rebuilt, the same world
    w2 = tumble.World(pickle.loads(pickle.dumps(m)))
    w2.step(200)
    assert np.array_equal(w2.state(), x)


@pytest.mark.parametrize("ctrl, balance", [
    # k_p (u − q) = m g l sin q
    ([0.6, 0.0], lambda q: 50.0 * (0.6 - q) - 9.81 * np.sin(q)),
    # clamped to ctrlrange [−1, 1]
    ([3.0, 0.0], lambda q: 50.0 * (1.0 - q) - 9.81 * np.sin(q)),
    # the motor, gear 2: g u = k_p q + m g l sin q
    ([0.0, 0.3], lambda q: 0.6 - 50.0 * q - 9.81 * np.sin(q)),
])
def test_set_ctrl_drives_the_actuators_to_their_equilibrium(tmp_path, ctrl, balance):
    path = tmp_path / "servo.xml"
    path.write_text(SERVO)
    m = tumble.Model.from_mjcf(path)
    assert m.actuator_names() == ["servo", "push"]
    w = tumble.World(m)
    w.set_ctrl("servo", ctrl)
    w.step(6000)
    q, v = w.state()[0], w.state()[1]
    assert abs(v) < 1e-8
    assert abs(balance(q)) < 1e-7, (q, balance(q))


def test_set_ctrl_errors_name_the_problem(tmp_path):
    path = tmp_path / "servo.xml"
    path.write_text(SERVO)
    w = tumble.World(tumble.Model.from_mjcf(path))
    with pytest.raises(tumble.TumbleError, match="ctrl"):
        w.set_ctrl("servo", [1.0])
    with pytest.raises(tumble.TumbleError, match="no such file"):
        tumble.Model.from_mjcf(tmp_path / "missing.xml")
    urdf = tumble.World(tumble.Model.from_urdf(REPO / "scenes/robots/double_pendulum.urdf"))
    with pytest.raises(tumble.TumbleError, match="no MJCF actuator"):
        urdf.set_ctrl(0, [1.0])
    with pytest.raises(tumble.TumbleError, match="no MJCF actuator"):
        urdf.model.ctrl_torque([1.0])


def test_a_rollout_driven_by_ctrl_equals_set_ctrl_in_a_world(tmp_path):
    path = tmp_path / "servo.xml"
    path.write_text(SERVO)
    m = tumble.Model.from_mjcf(path)
    rng = np.random.default_rng(7)
    ctrl = rng.uniform(-1.5, 1.5, (3, 400, 2))  # beyond ctrlrange at times: clamped alike
    u = m.ctrl_torque(ctrl)
    assert u.shape == (3, 400, m.nu)
    x0 = np.zeros((3, m.nstate))
    x0[:, 0] = [0.0, 0.2, -0.3]
    got = tumble.rollout(m, x0, 400, u, nthread=2)
    for row in range(3):
        w = tumble.World(m)
        w.set_state(x0[row])
        for k in range(400):
            w.set_ctrl(0, ctrl[row, k])
            w.step()
            assert np.array_equal(w.state(), got[row, k])
    with pytest.raises(tumble.TumbleError, match="n_actuators"):
        m.ctrl_torque(np.zeros((4, 3)))


# two hinges about y with springs (3 and 5 N·m/rad), a tendon L = q1 + 0.6 q2 over them, a servo
# on it (kp 4, forcerange as given) and a geared motor on a second tendon
FINGER = """<mujoco model="finger">
  <compiler angle="radian"/>
  <option timestep="0.001" integrator="Euler" gravity="0 0 0"/>
  <worldbody>
    <body name="a">
      <joint name="j1" type="hinge" axis="0 1 0" stiffness="3" damping="0.5"/>
      <geom type="capsule" fromto="0 0 0 0.3 0 0" size="0.03" contype="0" conaffinity="0"/>
      <body name="b" pos="0.3 0 0">
        <joint name="j2" type="hinge" axis="0 1 0" stiffness="5" damping="0.5"/>
        <geom type="capsule" fromto="0 0 0 0.2 0 0" size="0.02" contype="0" conaffinity="0"/>
      </body>
    </body>
  </worldbody>
  <tendon>
    <fixed name="flex"><joint joint="j1" coef="1"/><joint joint="j2" coef="0.6"/></fixed>
    <fixed name="twist"><joint joint="j1" coef="0.5"/><joint joint="j2" coef="-1"/></fixed>
  </tendon>
  <actuator>
    <position name="servo" tendon="flex" kp="4" FORCERANGE/>
    <motor name="motor" tendon="twist" gear="2"/>
  </actuator>
</mujoco>
"""


def test_set_ctrl_drives_an_actuator_on_a_tendon(tmp_path):
    path = tmp_path / "finger.xml"
    path.write_text(FINGER.replace("FORCERANGE", 'forcerange="-0.5 0.5"'))
    m = tumble.Model.from_mjcf(path)
    assert m.actuator_names() == ["servo", "motor"]
    w = tumble.World(m)
    # the servo alone: k_i q_i = c_i f, f = kp (u − L) clamped to 0.5 N
    w.set_ctrl(0, [0.5, 0.0])
    w.step(20000)
    q = w.state()[:2]
    f = min(4.0 * 0.5 / (1.0 + 4.0 * (1.0 / 3.0 + 0.36 / 5.0)), 0.5)
    assert f == 0.5  # the forcerange holds it
    assert np.allclose(q, [f / 3.0, 0.6 * f / 5.0], atol=1e-9), q
    # the servo's force is clamped after the control is added: no joint-force equivalent
    with pytest.raises(tumble.TumbleError, match="forcerange"):
        m.ctrl_torque([0.5, 0.0])


def test_a_rollout_driven_by_ctrl_on_tendons_equals_set_ctrl(tmp_path):
    path = tmp_path / "finger.xml"
    path.write_text(FINGER.replace("FORCERANGE", ""))
    m = tumble.Model.from_mjcf(path)
    rng = np.random.default_rng(8)
    ctrl = rng.uniform(-1.0, 1.0, (2, 300, 2))
    u = m.ctrl_torque(ctrl)
    # the motor on `twist` (gear 2): g c_i u on each joint, with the servo's k u on `flex`
    assert np.allclose(u[0, 0], 4.0 * ctrl[0, 0, 0] * np.array([1.0, 0.6]) + 2.0 * ctrl[0, 0, 1] * np.array([0.5, -1.0]))
    x0 = np.zeros((2, m.nstate))
    got = tumble.rollout(m, x0, 300, u, nthread=1)
    for row in range(2):
        w = tumble.World(m)
        for k in range(300):
            w.set_ctrl(0, ctrl[row, k])
            w.step()
        assert np.allclose(w.state(), got[row, -1], rtol=0, atol=1e-12)
