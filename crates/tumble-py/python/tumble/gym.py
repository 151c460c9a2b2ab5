"""Gymnasium tasks on tumble robots.

``PendulumSwingUp``: the double pendulum of ``scenes/robots/double_pendulum.urdf`` (two 1 m, 1 kg
links on a fixed pivot) starts hanging near rest; both joints are driven, with torques up to
``max_torque`` N·m, and the task is to swing it up and hold it upright. ``PendulumSwingUpVector``
runs ``num_envs`` of them as one ``gymnasium.vector.VectorEnv`` whose step is one
``tumble.rollout`` call over all the environments (threads, GIL released).

``Go1Walk``: Unitree Go1 (``scenes/go1_stand.toml``, packaged with its URDF) walks to a velocity
command drawn at reset, by PD position targets at 100 Hz. ``Go1WalkVector`` runs ``num_envs`` of
them, one ``tumble.World`` each, stepped together by one ``tumble.step_worlds`` call (threads, GIL
released).

Importing this module registers ``tumble/PendulumSwingUp-v0`` and ``tumble/Go1Walk-v0``
(``gymnasium.make`` and ``gymnasium.make_vec``).
"""

from __future__ import annotations

from importlib import resources
from typing import Any, Optional

import gymnasium
import numpy as np
from gymnasium import spaces
from gymnasium.utils import seeding
from gymnasium.vector import AutoresetMode, VectorEnv

import tumble

__all__ = ["GO1_JOINTS", "Go1Walk", "Go1WalkVector", "PendulumSwingUp", "PendulumSwingUpVector", "go1_model", "pendulum_model"]

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


# --- Go1: walking to a commanded velocity -------------------------------------------------------

_GO1_SCENE = "go1_stand.toml"

#: the twelve joints in the order of ``q`` and ``v`` (and of the actions): the URDF's
GO1_JOINTS = tuple(f"{leg}_{part}_joint" for leg in ("FR", "FL", "RR", "RL") for part in ("hip", "thigh", "calf"))

#: bounds of the observation's parts; values beyond them are clipped
_GO1_BOUNDS = {"lin_vel": 10.0, "ang_vel": 50.0, "q": np.pi, "v": 100.0}


def go1_model() -> tumble.Model:
    """``scenes/go1_stand.toml``, packaged with its URDF: Unitree Go1 on a floor (friction 0.9), floating
    base, PD on its 12 joints (kp 60 N·m/rad, kd 2 N·m·s/rad), dt = 1 ms, semi-implicit Euler."""
    path = resources.files("tumble") / "data" / _GO1_SCENE
    with resources.as_file(path) as p:
        return tumble.Model.from_file(str(p))


def _gravity_in_base(quat: np.ndarray) -> np.ndarray:
    """The unit gravity direction in the base frame, ``Rᵀ (0, 0, −1)``, from ``[qw, qx, qy, qz]`` (last axis)."""
    w, x, y, z = quat[..., 0], quat[..., 1], quat[..., 2], quat[..., 3]
    return -np.stack([2.0 * (x * z - w * y), 2.0 * (y * z + w * x), 1.0 - 2.0 * (x * x + y * y)], axis=-1)


class _Go1Task:
    """What the single and the vector Go1 environments share: the layout, observation, reward,
    termination and the draw of a start; every function works on the last axis, so one row of a
    batch gives the single environment's numbers bit for bit."""

    def __init__(
        self,
        frame_skip: int,
        max_episode_steps: int,
        action_scale: float,
        command_low: tuple[float, float, float],
        command_high: tuple[float, float, float],
        kp: float,
        kd: float,
        min_height: float,
        max_tilt: float,
        terminate_on_body_contact: bool,
    ) -> None:
        self.model = go1_model()
        self.frame_skip = int(frame_skip)
        self.max_episode_steps = int(max_episode_steps)
        self.action_scale = float(action_scale)
        self.command_low = np.asarray(command_low, dtype=np.float64)
        self.command_high = np.asarray(command_high, dtype=np.float64)
        self.kp, self.kd = float(kp), float(kd)
        self.min_height = float(min_height)
        self.max_tilt = float(max_tilt)
        self.terminate_on_body_contact = bool(terminate_on_body_contact)
        m = self.model
        self.link_prefix = m.robot_names[0] + "/"
        self.nq, self.nv = m.nq(0), m.nv(0)
        self.q0 = len(m.body_names) * 13  # the robot's q in the state; then its v
        self.v0 = self.q0 + self.nq
        initial = tumble.World(m).state()
        self.x_stand = initial  # the scene's start: 5 mm above the standing height, at rest
        self.q_stand = initial[self.q0 : self.q0 + self.nq].copy()  # base pose, then the standing joints
        self.joints_stand = self.q_stand[7:]
        self.gain_kp = np.r_[np.zeros(6), np.full(self.nv - 6, self.kp)]
        self.gain_kd = np.r_[np.zeros(6), np.full(self.nv - 6, self.kd)]
        n = self.nv - 6
        b = _GO1_BOUNDS
        high = np.concatenate(
            [
                np.ones(3),
                np.full(3, b["lin_vel"]),
                np.full(3, b["ang_vel"]),
                np.full(n, b["q"]),
                np.full(n, b["v"]),
                np.ones(n),
                np.maximum(np.abs(self.command_low), np.abs(self.command_high)),
            ]
        )
        self.obs_high = high
        self.nact = n

    def start(self, rng: np.random.Generator) -> tuple[np.ndarray, np.ndarray]:
        """A start and a command: the standing state with the joints moved by up to ±0.05 rad, the
        command uniform in [command_low, command_high]."""
        x = self.x_stand.copy()
        x[self.q0 + 7 : self.q0 + self.nq] += rng.uniform(-0.05, 0.05, self.nact)
        command = rng.uniform(self.command_low, self.command_high)
        return x, command

    def targets(self, action: np.ndarray) -> np.ndarray:
        """PD position targets (…, nq) from actions (…, 12) in [−1, 1] (already clipped)."""
        q = np.broadcast_to(self.q_stand, action.shape[:-1] + (self.nq,)).copy()
        q[..., 7:] += self.action_scale * action
        return q

    def observe(self, x: np.ndarray, last_action: np.ndarray, command: np.ndarray) -> np.ndarray:
        b = _GO1_BOUNDS
        q = x[..., self.q0 : self.q0 + self.nq]
        v = x[..., self.v0 : self.v0 + self.nv]
        return np.concatenate(
            [
                _gravity_in_base(q[..., 3:7]),
                np.clip(v[..., 0:3], -b["lin_vel"], b["lin_vel"]),
                np.clip(v[..., 3:6], -b["ang_vel"], b["ang_vel"]),
                np.clip(q[..., 7:] - self.joints_stand, -b["q"], b["q"]),
                np.clip(v[..., 6:], -b["v"], b["v"]),
                last_action,
                command,
            ],
            axis=-1,
        )

    def reward(
        self, x: np.ndarray, action: np.ndarray, last_action: np.ndarray, command: np.ndarray, q_target: np.ndarray
    ) -> tuple[np.ndarray, dict[str, np.ndarray]]:
        """Velocity tracking minus penalties; the terms are also returned (for ``info``)."""
        q = x[..., self.q0 : self.q0 + self.nq]
        v = x[..., self.v0 : self.v0 + self.nv]
        lin_err = (command[..., 0] - v[..., 0]) ** 2 + (command[..., 1] - v[..., 1]) ** 2
        yaw_err = (command[..., 2] - v[..., 5]) ** 2
        tau = self.kp * (q_target[..., 7:] - q[..., 7:]) - self.kd * v[..., 6:]
        da = action - last_action
        terms = {
            "track_lin_vel": 1.0 * np.exp(-lin_err / 0.25),
            "track_yaw_rate": 0.5 * np.exp(-yaw_err / 0.25),
            "lin_vel_z": -2.0 * v[..., 2] ** 2,
            "ang_vel_xy": -0.05 * (v[..., 3] ** 2 + v[..., 4] ** 2),
            "torque": -2e-4 * np.sum(tau * tau, axis=-1),
            "action_rate": -0.01 * np.sum(da * da, axis=-1),
        }
        total = terms["track_lin_vel"] + terms["track_yaw_rate"] + terms["lin_vel_z"]
        total = total + terms["ang_vel_xy"] + terms["torque"] + terms["action_rate"]
        return total, terms

    def fallen(self, x: np.ndarray) -> np.ndarray:
        """Base below ``min_height`` (m), or its z axis tilted more than ``max_tilt`` (rad) from vertical."""
        q = x[..., self.q0 : self.q0 + self.nq]
        up_z = -_gravity_in_base(q[..., 3:7])[..., 2]  # cos of the tilt
        return (q[..., 2] < self.min_height) | (up_z < np.cos(self.max_tilt))

    def body_contact(self, world: tumble.World) -> bool:
        """Whether a link other than a foot or a calf touched anything in the world's last step (the
        trunk, a hip, a thigh, a rotor: the knee's). The calves are left out: their collision boxes
        reach down into the foot spheres, and brush the floor when a stepping foot is planted."""
        if not self.terminate_on_body_contact:
            return False
        return any(
            name.startswith(self.link_prefix) and not name.endswith(("_foot", "_calf"))
            for c in world.contacts()
            for name in (c["a"], c["b"])
        )

    def action_space(self) -> spaces.Box:
        return spaces.Box(-1.0, 1.0, shape=(self.nact,), dtype=np.float32)

    def observation_space(self) -> spaces.Box:
        return spaces.Box(-self.obs_high, self.obs_high, dtype=np.float64)


_GO1_DEFAULTS: dict[str, Any] = dict(
    frame_skip=10,
    max_episode_steps=1000,
    action_scale=0.25,
    command_low=(-0.5, -0.3, -1.0),
    command_high=(1.0, 0.3, 1.0),
    kp=60.0,
    kd=2.0,
    min_height=0.15,
    max_tilt=np.pi / 3,
    terminate_on_body_contact=True,
)


class Go1Walk(gymnasium.Env):
    """Unitree Go1 (``scenes/go1_stand.toml``) walking to a commanded velocity.

    - command ``(vx, vy, ω_z)``: base forward and lateral speed (m/s) and yaw rate (rad/s), drawn
      uniformly in ``[command_low, command_high]`` at reset (default vx ∈ [−0.5, 1], vy ∈ [−0.3, 0.3],
      ω_z ∈ [−1, 1]) and held for the episode;
    - action: ``(12,)`` float32 in [−1, 1] (clipped), PD position targets as offsets from the standing
      pose, ``q* = q_stand + action_scale · a`` (0.25 rad per unit), joints in ``GO1_JOINTS`` order;
      PD gains ``kp``, ``kd`` (60 N·m/rad, 2 N·m·s/rad, the scene's), clamped to the URDF's efforts;
    - each action is held for ``frame_skip`` = 10 physics steps of 1 ms: a 100 Hz policy;
    - observation ``(48,)`` float64: gravity direction in the base frame (3), base linear (3, m/s) and
      angular (3, rad/s) velocity in the base frame, joint angles minus the standing pose (12, rad),
      joint speeds (12, rad/s), the last action (12), the command (3); each part clipped to the
      observation space's bounds;
    - reward per action: ``exp(−|v_xy − c_xy|²/0.25) + 0.5 exp(−(ω_z − c_ω)²/0.25) − 2 v_z² −
      0.05 (ω_x² + ω_y²) − 2e-4 |τ|² − 0.01 |a − a_prev|²``, τ the PD torque at the end of the step
      (before clamping); ``info["reward_terms"]`` has each term;
    - terminated when the base falls below ``min_height`` (0.15 m; it stands at 0.26 m) or tilts more
      than ``max_tilt`` (60°) from upright, when a link other than a foot or a calf (the trunk, a
      hip, a thigh, a knee's rotor) touches anything in the last physics step of the action
      (``terminate_on_body_contact``), or when the simulation
      diverges; truncated after ``max_episode_steps`` actions (1000: 10 s).

    Starts standing, 5 mm above the floor, joints within ±0.05 rad of the standing pose.
    """

    metadata = {"render_modes": []}

    def __init__(self, **kwargs: Any) -> None:
        self.task = _Go1Task(**{**_GO1_DEFAULTS, **kwargs})
        self.model = self.task.model
        self.world = tumble.World(self.model)
        self.action_space = self.task.action_space()
        self.observation_space = self.task.observation_space()
        self.max_episode_steps = self.task.max_episode_steps
        self._state = np.empty(self.model.nstate)
        self._last_action = np.zeros(self.task.nact)
        self._command = np.zeros(3)
        self._elapsed = 0

    @property
    def command(self) -> np.ndarray:
        """The episode's command ``(vx, vy, ω_z)`` (m/s, m/s, rad/s)."""
        return self._command.copy()

    def reset(
        self, *, seed: Optional[int] = None, options: Optional[dict[str, Any]] = None
    ) -> tuple[np.ndarray, dict[str, Any]]:
        super().reset(seed=seed)
        x, self._command = self.task.start(self.np_random)
        self.world.reset()
        self.world.set_state(x)
        self.world.set_pd_target(0, self.task.q_stand, kp=self.task.gain_kp, kd=self.task.gain_kd)
        self._last_action = np.zeros(self.task.nact)
        self._elapsed = 0
        self.world.state(out=self._state)
        return self.task.observe(self._state, self._last_action, self._command), {}

    def step(self, action: Any) -> tuple[np.ndarray, float, bool, bool, dict[str, Any]]:
        a = np.clip(np.asarray(action, dtype=np.float64), -1.0, 1.0)
        q_target = self.task.targets(a)
        self.world.set_pd_target(0, q_target)
        info: dict[str, Any] = {}
        diverged = False
        try:
            self.world.step(self.task.frame_skip)
        except tumble.DivergedError as e:
            diverged = True
            info["diverged"] = str(e)
        self._elapsed += 1
        self.world.state(out=self._state)
        # as a batch of one, as the vector environment computes it: NumPy's exp of an array (SIMD)
        # and of a scalar (libm) can differ in the last bit, and the two must agree bit for bit
        rewards, terms = self.task.reward(
            self._state[None], a[None], self._last_action[None], self._command[None], q_target[None]
        )
        reward = rewards[0]
        info["reward_terms"] = {k: float(t[0]) for k, t in terms.items()}
        terminated = diverged or bool(self.task.fallen(self._state)) or self.task.body_contact(self.world)
        truncated = self._elapsed >= self.max_episode_steps
        self._last_action = a
        obs = self.task.observe(self._state, self._last_action, self._command)
        return obs, float(reward), terminated, truncated, info


class Go1WalkVector(VectorEnv):
    """``num_envs`` Go1 walking tasks, one ``tumble.World`` each, advanced together by one
    ``tumble.step_worlds`` call per step (PD targets set in it; ``nthread`` threads, GIL released).

    Same spaces, rewards and episodes as ``Go1Walk``; autoreset on the step after an episode ends
    (``AutoresetMode.NEXT_STEP``). ``reset(seed=s)`` seeds environment ``i`` with ``s + i``, and each
    environment draws its starts from its own generator, as ``Go1Walk(...).reset(seed=s + i)`` then
    plain ``reset()`` at each episode's end would: row ``i`` is that single environment, bit for bit.
    """

    metadata = {"render_modes": [], "autoreset_mode": AutoresetMode.NEXT_STEP}

    def __init__(self, num_envs: int, nthread: Optional[int] = None, **kwargs: Any) -> None:
        self.task = _Go1Task(**{**_GO1_DEFAULTS, **kwargs})
        self.model = self.task.model
        self.num_envs = int(num_envs)
        self.nthread = nthread
        self.max_episode_steps = self.task.max_episode_steps
        self.worlds = [tumble.World(self.model) for _ in range(self.num_envs)]
        self.single_action_space = self.task.action_space()
        self.single_observation_space = self.task.observation_space()
        n = self.num_envs
        self.action_space = spaces.Box(-1.0, 1.0, shape=(n, self.task.nact), dtype=np.float32)
        high = np.tile(self.task.obs_high, (n, 1))
        self.observation_space = spaces.Box(-high, high, dtype=np.float64)
        self._rngs = [np.random.default_rng() for _ in range(n)]
        self._x = np.empty((n, self.model.nstate))
        self._last_action = np.zeros((n, self.task.nact))
        self._command = np.zeros((n, 3))
        self._elapsed = np.zeros(n, dtype=np.int64)
        self._done = np.zeros(n, dtype=bool)

    def _restart(self, i: int) -> None:
        x, self._command[i] = self.task.start(self._rngs[i])
        w = self.worlds[i]
        w.reset()
        w.set_state(x)
        w.set_pd_target(0, self.task.q_stand, kp=self.task.gain_kp, kd=self.task.gain_kd)
        w.state(out=self._x[i])
        self._last_action[i] = 0.0
        self._elapsed[i] = 0

    def reset(
        self, *, seed: Optional[int] = None, options: Optional[dict[str, Any]] = None
    ) -> tuple[np.ndarray, dict[str, Any]]:
        super().reset(seed=seed)
        for i in range(self.num_envs):
            if seed is not None:
                self._rngs[i], _ = seeding.np_random(seed + i)
            self._restart(i)
        self._done[:] = False
        return self.task.observe(self._x, self._last_action, self._command), {}

    def step(self, actions: Any) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, dict[str, Any]]:
        a = np.clip(np.asarray(actions, dtype=np.float64), -1.0, 1.0).reshape(self.num_envs, self.task.nact)
        q_target = self.task.targets(a)
        status = tumble.step_worlds(
            self.worlds, self.task.frame_skip, q_target=q_target, out=self._x, nthread=self.nthread
        )
        diverged = status < self.task.frame_skip
        rewards, _ = self.task.reward(self._x, a, self._last_action, self._command, q_target)
        self._elapsed += 1
        terminated = diverged | self.task.fallen(self._x) | [self.task.body_contact(w) for w in self.worlds]
        truncated = self._elapsed >= self.max_episode_steps
        self._last_action = a
        # the environments whose episode ended on the previous step start again, ignoring their action
        restart = np.flatnonzero(self._done)
        for i in restart:
            self._restart(int(i))
        if restart.size:
            rewards[restart] = 0.0
            terminated[restart] = False
            truncated[restart] = False
        self._done = terminated | truncated
        obs = self.task.observe(self._x, self._last_action, self._command)
        return obs, rewards, terminated, truncated, {}



def _register() -> None:
    for name in ("PendulumSwingUp", "Go1Walk"):
        env_id = f"tumble/{name}-v0"
        if env_id not in gymnasium.registry:
            gymnasium.register(
                id=env_id,
                entry_point=f"tumble.gym:{name}",
                vector_entry_point=f"tumble.gym:{name}Vector",
            )


_register()
