"""tumble: rigid-body dynamics in f64 — free bodies, contacts, robots from URDF.

- ``Model``: an immutable scene (``Model.from_file``, ``Model.from_str``, ``Model.from_urdf``);
  picklable, shareable between threads.
- ``World(model)``: one simulation; ``step(n)`` releases the GIL; ``state(out=None)`` and
  ``set_state(x)`` in the layout of the trajectory CSV rows, then each robot's ``q`` and ``v``.
- ``rollout(model, x0, nstep, control=None, nthread=None)``: a batch of simulations on a thread pool,
  ``(B, nstep, nstate)``, bit-identical to stepping one ``World`` per row.
- ``step_worlds(worlds, n, q_target=None, out=None, nthread=None)``: many ``World``s advanced in one
  call (PD targets set first), on threads with the GIL released; each as if stepped alone.
- ``rnea``, ``bias``, ``crba``, ``aba``: multibody dynamics on numpy arrays.
- ``tumble.gym``: Gymnasium tasks; ``tumble.distributed``: rollouts spread over a Ray cluster.

Errors are ``TumbleError`` (a ``ValueError``); a diverging step raises ``DivergedError`` (a
``TumbleError``). The guide: ``docs/python.md``.
"""

from ._tumble import (
    DivergedError,
    Model,
    TumbleError,
    World,
    __version__,
    aba,
    bias,
    crba,
    default_nthread,
    rnea,
    rollout,
    step_worlds,
)

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
