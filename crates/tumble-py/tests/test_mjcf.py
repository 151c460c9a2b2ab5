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
