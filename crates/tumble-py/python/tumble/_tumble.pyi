"""Type stubs of the Rust extension ``tumble._tumble`` (written by hand; checked by ``mypy.stubtest``)."""

import os
from typing import Any, Literal, Optional, Union, final, overload

import numpy as np
import numpy.typing as npt

_F64 = npt.NDArray[np.float64]
_ArrayLike = Union[_F64, list[float], tuple[float, ...]]
_Robot = Union[str, int]
_Path = Union[str, os.PathLike[str]]

__version__: str

__all__ = [
    "DivergedError",
    "Model",
    "TumbleError",
    "World",
    "__version__",
    "aba",
    "bias",
    "crba",
    "default_nthread",
    "rnea",
    "rollout",
    "step_worlds",
]

class TumbleError(ValueError):
    """Bad input to tumble (a scene, a file, an array), or a simulation that diverged."""

class DivergedError(TumbleError):
    """A step produced a non-finite or absurd state; the world is left at its last finite state."""

@final
class Model:
    """An immutable scene: bodies, robots and settings. Shareable between threads; picklable."""

    @staticmethod
    def from_file(path: _Path) -> Model:
        """Loads a scene file (``.toml`` or ``.json``); URDF paths are relative to the file."""
    @staticmethod
    def from_str(text: str, format: str = "toml", base_dir: Optional[_Path] = None) -> Model:
        """Parses a scene from text; URDF paths are relative to ``base_dir`` (default: the current directory)."""
    @staticmethod
    def from_urdf(path: _Path, floating: bool = False) -> Model:
        """A model of one robot read from a URDF file, at its neutral configuration, default world."""
    @staticmethod
    def from_mjcf(path: _Path) -> Model:
        """A MuJoCo MJCF file as a whole world, as `tumble run X.xml` reads it: its option, worldbody
        planes, and the tree as one robot at MuJoCo's qpos0, its actuators at ctrl = 0."""
    def actuator_names(self, robot: _Robot | None = None) -> list[str]:
        """Names of a robot's MJCF actuators, in the order of `World.set_ctrl` (empty for URDF)."""
    def ctrl_torque(self, ctrl: _ArrayLike, robot: _Robot | None = None) -> _F64:
        """The joint forces (..., nv) that actuator controls (..., n_actuators) add: what set_ctrl
        applies, and a one-robot model's rollout control that drives the actuators by ctrl."""
    @classmethod
    def _from_pickle(cls, text: str, format: str, origin: str) -> Model: ...
    def __reduce__(self) -> tuple[Any, tuple[str, str, str]]: ...
    @property
    def nstate(self) -> int:
        """Length of the state vector: 13 per moving body, then ``nq + nv`` per robot."""
    @property
    def nu(self) -> int:
        """Width of a rollout's control: the robots' velocity coordinates, in robot order."""
    @property
    def dt(self) -> float:
        """The time step (s)."""
    @property
    def duration(self) -> float:
        """The scene's ``duration`` (s)."""
    @property
    def integrator(self) -> str:
        """The integrator's name (``rk4``, ``splitting``, ...)."""
    @property
    def body_names(self) -> list[str]:
        """Names of the moving bodies, in state order."""
    @property
    def robot_names(self) -> list[str]:
        """Names of the robots, in state and control order."""
    @property
    def state_names(self) -> list[str]:
        """A label per state entry: ``body.x`` ... ``body.wz``, then ``robot.q[i]``, ``robot.v[i]``."""
    @property
    def warnings(self) -> list[str]:
        """What the loader noticed but accepted."""
    @property
    def text(self) -> str:
        """The scene text the model was built from."""
    def nq(self, robot: Optional[_Robot] = None) -> int:
        """Configuration coordinates of a robot (name or index; default: the only robot)."""
    def nv(self, robot: Optional[_Robot] = None) -> int:
        """Velocity coordinates of a robot (name or index; default: the only robot)."""
    def link_names(self, robot: Optional[_Robot] = None) -> list[str]:
        """The moving links of a robot, ``robot/link``, in the order of ``World.link_states``."""

@final
class World:
    """One simulation of a model, at ``t = 0`` when created. One thread at a time."""

    def __new__(cls, model: Model) -> World: ...
    @property
    def model(self) -> Model:
        """The model this world simulates."""
    @property
    def time(self) -> float:
        """Simulated time (s)."""
    @property
    def steps(self) -> int:
        """Steps taken since the start."""
    def step(self, n: int = 1) -> None:
        """Advances ``n`` steps (GIL released); raises ``DivergedError`` at a diverging step."""
    def state(self, out: Optional[_F64] = None) -> _F64:
        """The state (nstate,); written into ``out`` without allocation when given."""
    def set_state(self, x: _ArrayLike) -> None:
        """Sets the state (nstate,), checked: shape, float64, finite, unit quaternions."""
    def reset(self) -> None:
        """Back to the model's initial state at ``t = 0``."""
    def energy(self) -> float:
        """Kinetic plus gravitational potential energy (J)."""
    def contact_elastic_energy(self) -> float:
        """Energy stored in the springs of the soft rows holding the robots at the end of the last step (J)."""
    def linear_momentum(self) -> _F64:
        """Total linear momentum, world frame (kg·m/s), shape (3,)."""
    def angular_momentum(self) -> _F64:
        """Total angular momentum about the world origin, world frame (kg·m²/s), shape (3,)."""
    def set_torque(self, robot: _Robot, tau: _ArrayLike) -> None:
        """Joint forces of a robot (nv,), added to the scene's from the next step on (clamped with
        them to the URDF efforts unless the scene says `effort_limits = false`)."""
    def set_ctrl(self, robot: _Robot, ctrl: _ArrayLike) -> None:
        """Controls of a robot's MJCF actuators (one per actuator, clamped to each ctrlrange); each
        adds gear × gain × ctrl to its joint's force, replacing what set_torque gave."""
    def set_pd_target(
        self,
        robot: _Robot,
        q_target: _ArrayLike,
        kp: Optional[_ArrayLike] = None,
        kd: Optional[_ArrayLike] = None,
        v_target: Optional[_ArrayLike] = None,
    ) -> None:
        """PD targets of a robot: ``τ += kp (q* − q) + kd (v* − v)``."""
    def link_states(self, robot: Optional[_Robot] = None) -> _F64:
        """Poses and velocities of a robot's moving links, (nlink, 13), world frame."""
    def contacts(self) -> list[dict[str, Any]]:
        """The active contacts of the last step, the bodies' then the robot links': ``a``, ``b`` (body
        names, or ``robot/link``), ``point``, ``normal`` (from ``a`` to ``b``), ``depth`` (> 0: overlap)
        and ``force`` (N, on ``b``: the step's impulse over dt)."""
    def collisions(self) -> int:
        """Collisions resolved since the start."""
    def asleep(self) -> int:
        """Free bodies asleep now: islands at rest on a fixed body (``[world] sleep``); they wake
        when touched, or when ``set_state`` or a force changes one of them."""

@overload
def rollout(
    model: Model,
    x0: _ArrayLike,
    nstep: int,
    control: Optional[_F64] = None,
    nthread: Optional[int] = None,
    *,
    out: Optional[_F64] = None,
    return_status: Literal[False] = False,
) -> _F64: ...
@overload
def rollout(
    model: Model,
    x0: _ArrayLike,
    nstep: int,
    control: Optional[_F64] = None,
    nthread: Optional[int] = None,
    *,
    out: Optional[_F64] = None,
    return_status: Literal[True],
) -> tuple[_F64, npt.NDArray[np.int64]]: ...
def step_worlds(
    worlds: list[World],
    n: int = 1,
    *,
    robot: Optional[_Robot] = None,
    q_target: Optional[_ArrayLike] = None,
    out: Optional[_F64] = None,
    nthread: Optional[int] = None,
) -> npt.NDArray[np.int64]:
    """Advances every world by ``n`` steps on ``nthread`` threads, the GIL released; with
    ``q_target`` (B, nq) first sets each world's PD position targets of ``robot``; with ``out``
    (B, nstate) writes the states after the steps there. Returns the steps each world completed
    (B,) int64, fewer than ``n`` for a world that diverged. Bit-identical to stepping each alone."""

def default_nthread() -> int:
    """Threads used when ``nthread`` is not given: ``OMP_NUM_THREADS``, else the cores."""

def rnea(model: Model, q: _ArrayLike, v: _ArrayLike, a: _ArrayLike, robot: Optional[_Robot] = None) -> _F64:
    """Inverse dynamics ``τ = M(q) a + C(q, v) v + g(q)``, shape (nv,)."""

def bias(model: Model, q: _ArrayLike, v: _ArrayLike, robot: Optional[_Robot] = None) -> _F64:
    """Bias forces ``C(q, v) v + g(q)``, shape (nv,)."""

def crba(model: Model, q: _ArrayLike, robot: Optional[_Robot] = None) -> _F64:
    """The mass matrix ``M(q)``, shape (nv, nv)."""

def aba(model: Model, q: _ArrayLike, v: _ArrayLike, tau: _ArrayLike, robot: Optional[_Robot] = None) -> _F64:
    """Forward dynamics ``a = M(q)⁻¹ (τ − C(q, v) v − g(q))``, shape (nv,)."""
