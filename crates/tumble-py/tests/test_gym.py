"""tumble.gym: the tasks pass Gymnasium's checker; each vector form is the single one, batched, bit for bit."""

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


# --- Go1Walk ---------------------------------------------------------------------------------------


def test_go1_check_env_passes():
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        check_env(tg.Go1Walk(), skip_render_check=True)


def test_go1_packaged_scene_is_the_repository_scene():
    data = resources.files("tumble").joinpath("data")
    assert data.joinpath("go1_stand.toml").read_bytes() == (SCENES / "go1_stand.toml").read_bytes()
    urdf = "robots/example-robot-data/robots/go1_description/urdf/go1.urdf"
    assert data.joinpath(urdf).read_bytes() == (SCENES / urdf).read_bytes()


def test_go1_random_policy_episode_runs_and_is_truncated():
    env = gymnasium.make("tumble/Go1Walk-v0", max_episode_steps=200)
    env.action_space.seed(0)
    obs, _ = env.reset(seed=0)
    assert obs.shape == (48,) and env.observation_space.contains(obs)
    command = env.unwrapped.command
    assert -0.5 <= command[0] <= 1.0 and abs(command[1]) <= 0.3 and abs(command[2]) <= 1.0
    assert np.array_equal(obs[-3:], command)
    for k in range(200):
        obs, reward, terminated, truncated, info = env.step(env.action_space.sample())
        assert np.isfinite(reward) and env.observation_space.contains(obs)
        if terminated or truncated:
            break
    # small random offsets about the standing pose do not throw it over: it stands to the end
    assert truncated and not terminated and k == 199
    assert set(info["reward_terms"]) == {"track_lin_vel", "track_yaw_rate", "lin_vel_z", "ang_vel_xy", "torque", "action_rate"}


def test_go1_standing_still_is_rewarded_for_a_still_command():
    env = tg.Go1Walk()
    env.reset(seed=0)
    env._command = np.zeros(3)
    for _ in range(50):
        _, reward, terminated, *_ = env.step(np.zeros(12, dtype=np.float32))
    assert not terminated and reward > 1.4  # the two tracking terms are 1 and 0.5 at most


def test_go1_pushed_over_terminates():
    env = tg.Go1Walk()
    env.reset(seed=1)
    x = env.world.state()
    x[env.task.v0 + 1] = 3.0  # a sideways shove: 3 m/s along the base's y axis
    env.world.set_state(x)
    for k in range(100):
        obs, _, terminated, truncated, _ = env.step(np.zeros(12, dtype=np.float32))
        if terminated:
            break
    assert terminated and not truncated
    assert -obs[2] < np.cos(np.pi / 3)  # tilted beyond 60°


def test_go1_collapsing_without_stiffness_terminates():
    env = tg.Go1Walk(kp=0.0, kd=0.5)  # joints only damped: it sinks onto its belly
    env.reset(seed=1)
    for k in range(100):
        _, _, terminated, *_ = env.step(np.zeros(12, dtype=np.float32))
        if terminated:
            break
    assert terminated and env.world.state()[2] < 0.15


def test_go1_a_thigh_on_the_floor_terminates():
    # height and tilt checks off: only the contact of a link other than a foot or calf ends it
    kwargs = dict(kp=0.0, kd=0.5, min_height=0.0, max_tilt=np.pi)
    env = tg.Go1Walk(**kwargs)
    env.reset(seed=1)
    for k in range(100):
        _, _, terminated, *_ = env.step(np.zeros(12, dtype=np.float32))
        if terminated:
            break
    assert terminated
    touching = {c["b"] for c in env.world.contacts()}
    assert any(name.endswith("_thigh") for name in touching), touching
    env = tg.Go1Walk(terminate_on_body_contact=False, **kwargs)
    env.reset(seed=1)
    assert not any(env.step(np.zeros(12, dtype=np.float32))[2] for _ in range(100))


def test_step_worlds_is_stepping_each_world_alone():
    model = tg.go1_model()
    worlds = [tumble.World(model) for _ in range(3)]
    alone = [tumble.World(model) for _ in range(3)]
    q = worlds[0].state()[: model.nq()]
    rng = np.random.default_rng(0)
    out = np.empty((3, model.nstate))
    for k in range(20):
        targets = np.tile(q, (3, 1))
        targets[:, 7:] += rng.uniform(-0.3, 0.3, (3, 12))
        status = tumble.step_worlds(worlds, 5, q_target=targets, out=out, nthread=1 + k % 2)
        assert status.tolist() == [5, 5, 5]
        for b, w in enumerate(alone):
            w.set_pd_target(0, targets[b])
            w.step(5)
            assert np.array_equal(w.state(), out[b]) and np.array_equal(worlds[b].state(), out[b])
    with pytest.raises(tumble.TumbleError, match="the same World twice"):
        tumble.step_worlds([worlds[0], worlds[0]], 1)
    with pytest.raises(tumble.TumbleError, match=r"q_target: shape \(3, 18\)"):
        tumble.step_worlds(worlds, 1, q_target=np.zeros((3, 18)))
    before = [w.state() for w in worlds]
    with pytest.raises(tumble.TumbleError, match="not finite"):
        tumble.step_worlds(worlds, 1, q_target=np.full((3, model.nq()), np.nan))
    assert all(np.array_equal(w.state(), x) for w, x in zip(worlds, before))  # nothing changed
    with pytest.raises(tumble.TumbleError, match="no PD gains"):
        tumble.step_worlds([tumble.World(tg.pendulum_model())], 1, q_target=np.zeros((1, 2)))


def test_go1_vector_env_is_the_single_envs_bit_for_bit():
    n, steps = 3, 60
    kwargs = dict(max_episode_steps=25)  # the shove tips env 1 over in about 17 steps
    vec = tg.Go1WalkVector(num_envs=n, nthread=2, **kwargs)
    singles = [tg.Go1Walk(**kwargs) for _ in range(n)]
    obs, _ = vec.reset(seed=7)
    for i, env in enumerate(singles):
        obs_i, _ = env.reset(seed=7 + i)
        assert np.array_equal(obs[i], obs_i)
    # env 1 is shoved over, so that a termination and its autoreset are compared too
    for world in (vec.worlds[1], singles[1].world):
        x = world.state()
        x[vec.task.v0 + 1] = 3.0
        world.set_state(x)
    rng = np.random.default_rng(0)
    done = np.zeros(n, dtype=bool)
    ended = {"terminated": 0, "truncated": 0}
    for k in range(steps):
        a = rng.uniform(-1, 1, (n, 12)).astype(np.float32)
        obs, r, term, trunc, _ = vec.step(a)
        for i, env in enumerate(singles):
            if done[i]:  # next-step autoreset: the vector env restarts it, ignoring the action
                obs_i, _ = env.reset()
                r_i, term_i, trunc_i = 0.0, False, False
            else:
                obs_i, r_i, term_i, trunc_i, _ = env.step(a[i])
            assert np.array_equal(obs[i], obs_i), (k, i)
            assert r[i] == r_i and term[i] == term_i and trunc[i] == trunc_i, (k, i)
        ended["terminated"] += int(term.sum())
        ended["truncated"] += int(trunc.sum())
        done = term | trunc
    assert ended["terminated"] >= 1 and ended["truncated"] >= 2


def test_go1_made_as_a_vector_env_by_gymnasium():
    vec = gymnasium.make_vec("tumble/Go1Walk-v0", num_envs=2, vectorization_mode="vector_entry_point")
    obs, _ = vec.reset(seed=0)
    assert obs.shape == (2, 48)
    obs, r, term, trunc, _ = vec.step(np.zeros((2, 12), dtype=np.float32))
    assert obs.shape == (2, 48) and r.shape == (2,)
