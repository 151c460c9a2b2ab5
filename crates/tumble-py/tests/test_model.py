"""Model: loading from a file, a string and a URDF; pickling; errors that name the problem."""

import pickle
import threading

import numpy as np
import pytest

import tumble
from conftest import REPO, SCENES


def test_from_file_reads_the_scene(demo):
    assert demo.nstate == 13 * len(demo.body_names)
    assert "flipper" in demo.body_names
    assert "floor" not in demo.body_names  # fixed bodies have no state
    assert demo.integrator == "splitting"
    assert demo.dt == 0.001
    assert len(demo.state_names) == demo.nstate
    assert demo.state_names[:4] == [f"{demo.body_names[0]}.{c}" for c in ("x", "y", "z", "qw")]


def test_from_str_and_from_file_agree(projectile):
    text = (SCENES / "projectile.toml").read_text()
    m = tumble.Model.from_str(text)
    a, b = tumble.World(m), tumble.World(projectile)
    a.step(100)
    b.step(100)
    assert np.array_equal(a.state(), b.state())


def test_from_str_json():
    m = tumble.Model.from_str(
        '{"version": 1, "body": [{"name": "b", "mass": 2.0, "inertia": [1, 2, 3], "velocity": [1, 0, 0]}]}', "json"
    )
    assert m.body_names == ["b"]
    w = tumble.World(m)
    assert np.allclose(w.linear_momentum(), [2.0, 0.0, 0.0])


def test_urdf_paths_of_a_string_scene_are_relative_to_base_dir():
    text = (SCENES / "double_pendulum.toml").read_text()
    m = tumble.Model.from_str(text, base_dir=SCENES)
    assert m.robot_names == ["pendulum"] and m.nq() == 2 and m.nv("pendulum") == 2
    with pytest.raises(tumble.TumbleError, match="double_pendulum.urdf"):
        tumble.Model.from_str(text, base_dir=REPO / "docs")


def test_from_urdf_fixed_and_floating():
    urdf = SCENES / "robots" / "double_pendulum.urdf"
    fixed = tumble.Model.from_urdf(urdf)
    assert (fixed.nq(), fixed.nv(), fixed.nstate) == (2, 2, 4)
    panda = SCENES / "robots" / "panda.urdf"
    fixed_arm = tumble.Model.from_urdf(panda)
    floating = tumble.Model.from_urdf(str(panda), floating=True)
    assert (floating.nq(), floating.nv()) == (fixed_arm.nq() + 7, fixed_arm.nv() + 6)
    w = tumble.World(floating)
    w.step(100)  # free fall: no joint moves, the base drops by g t²/2 (exact for RK4)
    x = w.state()
    assert x[2] == pytest.approx(-0.5 * 9.81 * 0.1**2, rel=1e-9)
    assert np.allclose(x[7 : floating.nq()], 0.0, atol=1e-12)


def test_from_urdf_holds_joint_limits_and_clamps_efforts():
    """The scene defaults go through `from_urdf`: the shoulder of `limited_arm.urdf` (limits
    [0.6, 2.5] rad, effort 40 N·m) pushed by 100 N·m stops at its upper limit, and moves exactly as
    when pushed by 40 N·m (the clamp)."""
    m = tumble.Model.from_urdf(SCENES / "robots" / "limited_arm.urdf")
    worlds = []
    for tau in (100.0, 40.0):
        w = tumble.World(m)
        w.set_state(np.array([1.0, 0.0, 0.0, 0.0]))  # q = [1, 0], v = 0
        w.set_torque(0, [tau, 0.0])
        w.step(3000)
        worlds.append(w)
    x = worlds[0].state()
    assert abs(x[0] - 2.5) < 1e-4  # at the upper limit, not past it
    assert abs(x[2]) < 1e-6  # and at rest there
    assert np.array_equal(x, worlds[1].state())


def test_pickle_round_trip_gives_the_same_simulation(pendulum):
    copy = pickle.loads(pickle.dumps(pendulum))
    assert isinstance(copy, tumble.Model) and copy.nstate == pendulum.nstate
    a, b = tumble.World(pendulum), tumble.World(copy)
    a.step(500)
    b.step(500)
    assert np.array_equal(a.state(), b.state())
    urdf = tumble.Model.from_urdf(SCENES / "robots" / "panda.urdf")
    assert pickle.loads(pickle.dumps(urdf)).nq() == urdf.nq()


def test_model_is_immutable(demo):
    with pytest.raises(AttributeError):
        demo.nstate = 3  # type: ignore[misc]


def test_one_model_shared_by_threads(pendulum):
    """Each thread its own World of one shared Model: the same numbers as one after the other."""
    x0 = np.array([[0.2 * k, -0.1 * k, 0.0, 0.5] for k in range(6)])
    results = [None] * len(x0)

    def run(k):
        w = tumble.World(pendulum)
        w.set_state(x0[k])
        w.step(2000)
        results[k] = w.state()

    threads = [threading.Thread(target=run, args=(k,)) for k in range(len(x0))]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    for k in range(len(x0)):
        w = tumble.World(pendulum)
        w.set_state(x0[k])
        w.step(2000)
        assert np.array_equal(results[k], w.state())


def test_missing_file_names_it(tmp_path):
    missing = tmp_path / "nowhere.toml"
    with pytest.raises(tumble.TumbleError, match="nowhere.toml") as e:
        tumble.Model.from_file(missing)
    assert isinstance(e.value, ValueError)
    with pytest.raises(tumble.TumbleError, match="nowhere.urdf"):
        tumble.Model.from_urdf(tmp_path / "nowhere.urdf")


def test_bad_scene_names_line_and_field():
    with pytest.raises(tumble.TumbleError, match=r"<string>:4:\d+: .*mass") as e:
        tumble.Model.from_str('version = 1\n[[body]]\nname = "b"\nmass = -1.0\ninertia = [1, 1, 1]\n')
    assert "must be" in str(e.value)
    with pytest.raises(tumble.TumbleError, match="format"):
        tumble.Model.from_str("version = 1", format="yaml")


def test_robot_lookup_errors(pendulum, demo):
    with pytest.raises(tumble.TumbleError, match="no robot named `arm`"):
        pendulum.nq("arm")
    with pytest.raises(tumble.TumbleError, match="out of range"):
        pendulum.nq(3)
    with pytest.raises(tumble.TumbleError, match="no robot"):
        demo.nq()
