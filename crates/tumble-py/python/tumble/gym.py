"""Gymnasium tasks on tumble robots.

``PendulumSwingUp``: the double pendulum of ``scenes/robots/double_pendulum.urdf`` (two 1 m, 1 kg
links on a fixed pivot) starts hanging near rest; both joints are driven, with torques up to
``max_torque`` N·m, and the task is to swing it up and hold it upright. ``PendulumSwingUpVector``
runs ``num_envs`` of them as one ``gymnasium.vector.VectorEnv`` whose step is one
``tumble.rollout`` call over all the environments (threads, GIL released).

Importing this module registers ``tumble/PendulumSwingUp-v0`` (``gymnasium.make`` and
``gymnasium.make_vec``). A quadruped standing task waits for robots that collide with the ground
(robot links do not collide yet).
"""

from __future__ import annotations

from importlib import resources
from typing import Any, Optional

import gymnasium
import numpy as np
from gymnasium import spaces
from gymnasium.vector import AutoresetMode, VectorEnv

import tumble

__all__ = ["PendulumSwingUp", "PendulumSwingUpVector", "pendulum_model"]

_URDF = "double_pendulum.urdf"

#: joint speeds in observations are clipped to ±MAX_SPEED (rad/s), the bound of the observation space
MAX_SPEED = 50.0
_OBS_HIGH = np.array([1.0, 1.0, 1.0, 1.0, MAX_SPEED, MAX_SPEED])


def pendulum_model() -> tumble.Model:
    """The double pendulum on a fixed pivot (RK4, dt = 1 ms, gravity −9.81 m/s² along z, no damping)."""
    path = resources.files("tumble") / "data" / _URDF
    with resources.as_file(path) as p:
        return tumble.Model.from_urdf(str(p))


def _wrap(angle: np.ndarray) -> np.ndarray:
    """Angles to (−π, π]."""
    return np.pi - np.mod(np.pi - angle, 2.0 * np.pi)


def _observe(qv: np.ndarray) -> np.ndarray:
    """``[cos q1, sin q1, cos q2, sin q2, v1, v2]`` from ``[q1, q2, v1, v2]`` (last axis)."""
    q, v = qv[..., :2], np.clip(qv[..., 2:4], -MAX_SPEED, MAX_SPEED)
    return np.concatenate([np.cos(q[..., :1]), np.sin(q[..., :1]), np.cos(q[..., 1:]), np.sin(q[..., 1:]), v], axis=-1)


def _cost(qv: np.ndarray, action: np.ndarray) -> np.ndarray:
    """Distance from upright (shoulder at π, elbow straight), speed and effort."""
    up = _wrap(qv[..., 0] - np.pi) ** 2 + _wrap(qv[..., 1]) ** 2
    return up + 0.01 * np.sum(qv[..., 2:4] ** 2, axis=-1) + 0.001 * np.sum(action**2, axis=-1)


class PendulumSwingUp(gymnasium.Env):
    """Swing a double pendulum up and hold it there.

    - action: ``(2,)`` float32 in [−1, 1], the joint torques as fractions of ``max_torque`` (N·m);
    - observation: ``[cos q1, sin q1, cos q2, sin q2, v1, v2]`` (float64; rad/s, clipped to
      ±``MAX_SPEED``), q1 the shoulder angle from hanging down, q2 the elbow angle;
    - reward: ``−(wrap(q1 − π)² + wrap(q2)² + 0.01 |v|² + 0.001 |a|²)`` per control step;
    - an episode is ``max_episode_steps`` control steps of ``frame_skip`` simulation steps (1 ms
      each), then truncated; it terminates early only if the simulation diverges.
    """

    metadata = {"render_modes": []}

    def __init__(self, max_torque: float = 20.0, frame_skip: int = 20, max_episode_steps: int = 250) -> None:
        self.model = pendulum_model()
        self.world = tumble.World(self.model)
        self.max_torque = float(max_torque)
        self.frame_skip = int(frame_skip)
        self.max_episode_steps = int(max_episode_steps)
        self.action_space = spaces.Box(-1.0, 1.0, shape=(2,), dtype=np.float32)
        self.observation_space = spaces.Box(-_OBS_HIGH, _OBS_HIGH, dtype=np.float64)
        self._state = np.empty(self.model.nstate)
        self._elapsed = 0

    def reset(
        self, *, seed: Optional[int] = None, options: Optional[dict[str, Any]] = None
    ) -> tuple[np.ndarray, dict[str, Any]]:
        super().reset(seed=seed)
        self.world.reset()
        x = np.concatenate([self.np_random.uniform(-0.1, 0.1, 2), self.np_random.uniform(-0.1, 0.1, 2)])
        self.world.set_state(x)
        self._elapsed = 0
        self.world.state(out=self._state)
        return _observe(self._state), {}

    def step(self, action: Any) -> tuple[np.ndarray, float, bool, bool, dict[str, Any]]:
        a = np.clip(np.asarray(action, dtype=np.float64), -1.0, 1.0)
        self.world.set_torque(0, a * self.max_torque)
        info: dict[str, Any] = {}
        terminated = False
        try:
            self.world.step(self.frame_skip)
        except tumble.DivergedError as e:
            terminated = True
            info["diverged"] = str(e)
        self._elapsed += 1
        self.world.state(out=self._state)
        reward = -float(_cost(self._state, a))
        truncated = self._elapsed >= self.max_episode_steps
        return _observe(self._state), reward, terminated, truncated, info


class PendulumSwingUpVector(VectorEnv):
    """``num_envs`` swing-up tasks stepped together by ``tumble.rollout`` on ``nthread`` threads.

    Same spaces, rewards and episodes as ``PendulumSwingUp``; autoreset on the step after an episode
    ends (``AutoresetMode.NEXT_STEP``, Gymnasium's default).
    """

    metadata = {"render_modes": [], "autoreset_mode": AutoresetMode.NEXT_STEP}

    def __init__(
        self,
        num_envs: int,
        max_torque: float = 20.0,
        frame_skip: int = 20,
        max_episode_steps: int = 250,
        nthread: Optional[int] = None,
    ) -> None:
        single = PendulumSwingUp(max_torque, frame_skip, max_episode_steps)
        self.model = single.model
        self.num_envs = int(num_envs)
        self.max_torque, self.frame_skip, self.max_episode_steps = max_torque, frame_skip, max_episode_steps
        self.nthread = nthread
        self.single_action_space = single.action_space
        self.single_observation_space = single.observation_space
        self.action_space = spaces.Box(-1.0, 1.0, shape=(self.num_envs, 2), dtype=np.float32)
        high = np.tile(_OBS_HIGH, (self.num_envs, 1))
        self.observation_space = spaces.Box(-high, high, dtype=np.float64)
        self._x = np.zeros((self.num_envs, self.model.nstate))
        self._elapsed = np.zeros(self.num_envs, dtype=np.int64)
        self._done = np.zeros(self.num_envs, dtype=bool)
        self._control = np.zeros((self.num_envs, self.frame_skip, self.model.nu))
        self._states = np.empty((self.num_envs, self.frame_skip, self.model.nstate))

    def _initial(self, n: int) -> np.ndarray:
        return self.np_random.uniform(-0.1, 0.1, size=(n, 4))

    def reset(
        self, *, seed: Optional[int] = None, options: Optional[dict[str, Any]] = None
    ) -> tuple[np.ndarray, dict[str, Any]]:
        super().reset(seed=seed)
        self._x[:] = self._initial(self.num_envs)
        self._elapsed[:] = 0
        self._done[:] = False
        return _observe(self._x), {}

    def step(self, actions: Any) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, dict[str, Any]]:
        a = np.clip(np.asarray(actions, dtype=np.float64), -1.0, 1.0).reshape(self.num_envs, 2)
        self._control[:] = (a * self.max_torque)[:, None, :]
        states, status = tumble.rollout(
            self.model, self._x, self.frame_skip, self._control, self.nthread, out=self._states, return_status=True
        )
        diverged = status < self.frame_skip
        stepped = ~diverged
        self._x[stepped] = states[stepped, -1]
        rewards = -_cost(self._x, a)
        self._elapsed += 1
        terminated = diverged.copy()
        truncated = self._elapsed >= self.max_episode_steps
        # the environments whose episode ended on the previous step start again, ignoring their action
        restart = self._done
        if restart.any():
            self._x[restart] = self._initial(int(restart.sum()))
            self._elapsed[restart] = 0
            rewards[restart] = 0.0
            terminated[restart] = False
            truncated[restart] = False
        self._done = terminated | truncated
        return _observe(self._x), rewards, terminated, truncated, {}


def _register() -> None:
    env_id = "tumble/PendulumSwingUp-v0"
    if env_id not in gymnasium.registry:
        gymnasium.register(
            id=env_id,
            entry_point="tumble.gym:PendulumSwingUp",
            vector_entry_point="tumble.gym:PendulumSwingUpVector",
        )


_register()
