"""tumble.gym: the swing-up task passes Gymnasium's checker; the vector form is the single one, batched."""

import warnings
from importlib import resources

import gymnasium
import numpy as np
import pytest
from gymnasium.utils.env_checker import check_env

import tumble
import tumble.gym as tg
from conftest import SCENES


def test_check_env_passes():
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # the checker's warnings too
        check_env(tg.PendulumSwingUp(), skip_render_check=True)


def test_registered_and_made_by_gymnasium():
    env = gymnasium.make("tumble/PendulumSwingUp-v0", max_episode_steps=5)
    obs, _ = env.reset(seed=0)
    assert obs.shape == (6,)
    for k in range(5):
        obs, reward, terminated, truncated, _ = env.step(env.action_space.sample())
    assert truncated and not terminated
    vec = gymnasium.make_vec("tumble/PendulumSwingUp-v0", num_envs=3, vectorization_mode="vector_entry_point")
    obs, _ = vec.reset(seed=0)
    assert obs.shape == (3, 6)


def test_the_packaged_urdf_is_the_scene_robot():
    packaged = resources.files("tumble").joinpath("data/double_pendulum.urdf").read_bytes()
    assert packaged == (SCENES / "robots" / "double_pendulum.urdf").read_bytes()


def test_upright_is_rewarded_hanging_is_not():
    env = tg.PendulumSwingUp(frame_skip=1)
    env.reset(seed=0)
    env.world.set_state([np.pi, 0.0, 0.0, 0.0])
    _, up, *_ = env.step(np.zeros(2, dtype=np.float32))
    env.world.set_state([0.0, 0.0, 0.0, 0.0])
    _, down, *_ = env.step(np.zeros(2, dtype=np.float32))
    assert up > -1e-3 and down == pytest.approx(-np.pi**2, rel=1e-3)


def test_vector_env_steps_as_the_single_env():
    single = tg.PendulumSwingUp(max_episode_steps=4)
    vec = tg.PendulumSwingUpVector(num_envs=3, max_episode_steps=4, nthread=2)
    obs1, _ = single.reset(seed=5)
    vec.reset(seed=5)
    vec._x[1] = single.world.state()  # the same start in row 1
    rng = np.random.default_rng(0)
    for k in range(4):
        a = rng.uniform(-1, 1, (3, 2)).astype(np.float32)
        obs1, r1, term1, trunc1, _ = single.step(a[1])
        obs, r, term, trunc, _ = vec.step(a)
        assert np.array_equal(obs[1], obs1) and r[1] == r1
        assert trunc[1] == trunc1 and term[1] == term1
    assert trunc.all()
    # next-step autoreset: the step after the end starts new episodes, reward 0
    obs, r, term, trunc, _ = vec.step(np.zeros((3, 2), dtype=np.float32))
    assert np.all(r == 0.0) and not trunc.any()
    assert np.all(np.abs(vec._x) <= 0.1)
