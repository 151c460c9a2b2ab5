"""rollout: the same numbers as one World per row, for any thread count and split (free bodies in
contact, a pendulum, quadrupeds standing and trotting on their feet under the scene's PD); bad rows
and diverging rows; the thread count from OMP_NUM_THREADS."""

import os
import subprocess
import sys

import numpy as np
import pytest

import tumble
from conftest import SCENES, step_rows


def pendulum_batch(pendulum, n, seed=1):
    rng = np.random.default_rng(seed)
    return np.column_stack([rng.uniform(-3, 3, (n, 2)), rng.uniform(-1, 1, (n, 2))])


def demo_batch(demo, n, seed=2):
    """The demo's bodies with perturbed velocities (contacts, flips)."""
    rng = np.random.default_rng(seed)
    x = np.tile(tumble.World(demo).state(), (n, 1))
    for b in range(len(demo.body_names)):
        x[:, 13 * b + 7 : 13 * b + 10] += rng.normal(0, 0.5, (n, 3))
    return x


@pytest.mark.parametrize("nthread", [1, 2, 3])
def test_rollout_equals_one_world_per_row(demo, nthread):
    x0 = demo_batch(demo, 5)
    expected = step_rows(demo, x0, 300)
    got = tumble.rollout(demo, x0, 300, nthread=nthread)
    assert got.shape == (5, 300, demo.nstate) and got.dtype == np.float64
    assert np.array_equal(got, expected)


def landed_batch(model, n, seed=4):
    """n states of a quadruped on its feet (the scene stepped 150 ms: landed), joint
    velocities perturbed in all rows but the first."""
    w = tumble.World(model)
    w.step(150)
    assert len(w.contacts()) >= 2  # on its feet (two of them while trotting)
    x = np.tile(w.state(), (n, 1))
    nq, nv = model.nq(), model.nv()
    joints = slice(nq + 6, nq + nv)  # the state is q, then v; v starts with the base's 6
    x[1:, joints] += np.random.default_rng(seed).normal(0, 0.5, (n - 1, nv - 6))
    return x


@pytest.mark.parametrize("scene", ["go1_stand", "solo12_stand", "anymal_c_stand", "go1_trot"])
def test_quadruped_rollout_with_contacts_equals_one_world_per_row(scene):
    """A floating-base robot on the floor under its scene's PD (the trot's targets move with time,
    so feet lift and land): rollout rows are Worlds stepped one by one, on 1 or 2 threads, with and
    without added joint torques."""
    model = tumble.Model.from_file(SCENES / f"{scene}.toml")
    x0 = landed_batch(model, 4)
    nstep = 60
    expected = step_rows(model, x0, nstep)
    for nthread in (1, 2):
        assert np.array_equal(tumble.rollout(model, x0, nstep, nthread=nthread), expected)
    u = np.zeros((4, nstep, model.nu))
    u[:, :, 6:] = np.random.default_rng(5).normal(0, 0.5, (4, nstep, model.nu - 6))  # N·m on the joints
    expected_u = step_rows(model, x0, nstep, u)
    assert not np.array_equal(expected_u, expected)
    for nthread in (1, 2):
        assert np.array_equal(tumble.rollout(model, x0, nstep, u, nthread), expected_u)
    # the rows are in contact with the floor: row 0 (with torques) at every step, the others stand
    w = tumble.World(model)
    w.set_state(x0[0])
    for t in range(nstep):
        w.set_torque(0, u[0, t])
        w.step()
        assert len(w.contacts()) >= 1, t
    assert np.array_equal(w.state(), expected_u[0, -1]) and np.all(expected_u[:, -1, 2] > 0.1)


def test_rollout_with_controls_equals_set_torque(pendulum):
    x0 = pendulum_batch(pendulum, 7)
    u = np.random.default_rng(3).normal(0, 2, (7, 200, pendulum.nu))
    expected = step_rows(pendulum, x0, 200, u)
    for nthread in (1, 2):
        assert np.array_equal(tumble.rollout(pendulum, x0, 200, u, nthread), expected)
    # and the controls act: without them the rows differ
    assert not np.array_equal(tumble.rollout(pendulum, x0, 200), expected)


def test_rollout_does_not_depend_on_how_rows_are_split(pendulum):
    x0 = pendulum_batch(pendulum, 40)
    whole = tumble.rollout(pendulum, x0, 100, nthread=2)
    parts = np.concatenate([tumble.rollout(pendulum, x0[a:b], 100, nthread=1) for a, b in [(0, 1), (1, 17), (17, 40)]])
    assert np.array_equal(whole, parts)
    reversed_rows = tumble.rollout(pendulum, x0[::-1], 100, nthread=2)[::-1]
    assert np.array_equal(whole, reversed_rows)


def test_rollout_into_out(pendulum):
    x0 = pendulum_batch(pendulum, 3)
    out = np.full((3, 50, 4), -1.0)
    got = tumble.rollout(pendulum, x0, 50, out=out)
    assert got is out and np.array_equal(out, tumble.rollout(pendulum, x0, 50))
    with pytest.raises(tumble.TumbleError, match=r"out: shape \(3, 49, 4\), expected \(3, 50, 4\)"):
        tumble.rollout(pendulum, x0, 50, out=np.empty((3, 49, 4)))


def test_a_diverging_row_stops_only_itself(projectile):
    x0 = np.tile(tumble.World(projectile).state(), (3, 1))
    x0[1, 0], x0[1, 7] = 1e10 - 4.5e6, 1e9  # beyond 1e10 m in its 5th step
    states, status = tumble.rollout(projectile, x0, 20, nthread=2, return_status=True)
    assert status.tolist() == [20, 4, 20] and status.dtype == np.int64
    assert np.all(np.isfinite(states[1, :4])) and np.all(np.isnan(states[1, 4:]))
    assert np.array_equal(states[[0, 2]], step_rows(projectile, x0[[0, 2]], 20))
    assert np.array_equal(states[1, :4], step_rows(projectile, x0[[1]], 4)[0])


@pytest.mark.parametrize(
    "x0, message",
    [
        (np.zeros(4), r"x0: shape \(4,\), expected \(B, 4\)"),
        (np.zeros((2, 5)), r"x0: shape \(2, 5\), expected \(B, 4\)"),
        (np.zeros((2, 4), dtype=np.float32), "x0: dtype float32, expected float64"),
        (np.array([[0.0, 0.0, 0.0, 0.0], [0.0, np.nan, 0.0, 0.0]]), r"x0\[1\]: state\[1\] .*q\[1\]\) is not finite"),
    ],
)
def test_rollout_rejects_bad_initial_states(pendulum, x0, message):
    with pytest.raises(tumble.TumbleError, match=message):
        tumble.rollout(pendulum, x0, 10)


def test_rollout_rejects_bad_controls_and_threads(pendulum, demo):
    x0 = np.zeros((2, 4))
    with pytest.raises(tumble.TumbleError, match=r"control: shape \(2, 10\), expected \(2, 10, 2\)"):
        tumble.rollout(pendulum, x0, 10, np.zeros((2, 10)))
    with pytest.raises(tumble.TumbleError, match="control: entry 5 is not finite"):
        c = np.zeros((2, 10, 2))
        c.flat[5] = np.inf
        tumble.rollout(pendulum, x0, 10, c)
    with pytest.raises(tumble.TumbleError, match="nthread: must be at least 1"):
        tumble.rollout(pendulum, x0, 10, nthread=0)
    bad_quaternion = np.tile(tumble.World(demo).state(), (2, 1))
    bad_quaternion[1, 3:7] = [0.5, 0.5, 0.5, 0.0]
    with pytest.raises(tumble.TumbleError, match=r"x0\[1\]: .*not a unit quaternion"):
        tumble.rollout(demo, bad_quaternion, 10)


def test_empty_batch_and_zero_steps(pendulum):
    assert tumble.rollout(pendulum, np.zeros((0, 4)), 10).shape == (0, 10, 4)
    assert tumble.rollout(pendulum, np.zeros((3, 4)), 0).shape == (3, 0, 4)


def test_thread_count_from_omp_num_threads():
    code = "import tumble; print(tumble.default_nthread())"

    def run(**env):
        base = {k: v for k, v in os.environ.items() if k != "OMP_NUM_THREADS"}
        done = subprocess.run([sys.executable, "-c", code], env={**base, **env}, capture_output=True, text=True)
        assert done.returncode == 0, done.stderr
        return int(done.stdout)

    cores = run()
    assert cores >= 1
    assert run(OMP_NUM_THREADS="3") == 3
    assert run(OMP_NUM_THREADS="0") == cores  # not a usable count: ignored
