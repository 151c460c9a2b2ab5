"""Rollouts spread over a Ray cluster: one Ray task per chunk of rows.

``rollout(model, x0, nstep, control=None, chunks=None, cpus_per_task=1)`` cuts the batch into
``chunks`` pieces of consecutive rows, runs ``tumble.rollout`` on each in a Ray task that asks for
``cpus_per_task`` CPUs — chunk i on node i mod N of the nodes that have them — and puts the pieces
back in order. Rows share nothing, so the result is the
local ``tumble.rollout``'s, bit for bit, whichever node ran which chunk.

Threads: inside a task Ray sets ``OMP_NUM_THREADS`` to the task's CPUs, and ``tumble.rollout``
sizes its pool from it (``tumble.default_nthread()``), so the tasks of a node never start more
threads than it has CPUs.

The model travels as its scene text (``pickle``): its URDF files, if any, are read again by each
worker, at the same path, so they must be on every node (a shared file system, or the same checkout).

Start Ray first (``ray.init()`` or ``ray.init(address=...)``); this module only submits tasks.
"""

from __future__ import annotations

from typing import Any, Optional

import numpy as np
import ray
from ray.util.scheduling_strategies import NodeAffinitySchedulingStrategy

import tumble

__all__ = ["rollout"]


@ray.remote
def _rollout_chunk(model: tumble.Model, x0: np.ndarray, nstep: int, control: Optional[np.ndarray]) -> Any:
    states, status = tumble.rollout(model, x0, nstep, control, return_status=True)
    return states, status, tumble.default_nthread(), ray.get_runtime_context().get_node_id()


def rollout(
    model: tumble.Model,
    x0: np.ndarray,
    nstep: int,
    control: Optional[np.ndarray] = None,
    chunks: Optional[int] = None,
    cpus_per_task: int = 1,
    return_details: bool = False,
) -> Any:
    """``tumble.rollout`` over a Ray cluster: returns ``(states, status)`` as the local call with
    ``return_status=True`` does — states (B, nstep, nstate), steps done per row (B,).

    ``chunks``: number of tasks (default: the cluster's CPUs divided by ``cpus_per_task``, at most
    one per row). ``return_details``: also return, per task, the rows it ran, the thread count it
    used and its node id.
    """
    x0 = np.asarray(x0)
    if x0.ndim != 2:
        raise tumble.TumbleError(f"x0: shape {x0.shape}, expected (B, nstate)")
    batch = x0.shape[0]
    if chunks is None:
        cpus = int(ray.cluster_resources().get("CPU", 1))
        chunks = max(1, cpus // max(1, cpus_per_task))
    chunks = max(1, min(int(chunks), batch))
    bounds = np.linspace(0, batch, chunks + 1).astype(int)
    model_ref = ray.put(model)
    # chunk i goes to node i mod N among the live nodes with the CPUs (soft: elsewhere if that one is
    # busy or gone), so a batch spreads over the cluster rather than queueing on the first free node
    nodes = [n["NodeID"] for n in ray.nodes() if n["Alive"] and n["Resources"].get("CPU", 0) >= cpus_per_task]
    refs = []
    for i, (a, b) in enumerate(zip(bounds[:-1], bounds[1:])):
        strategy = NodeAffinitySchedulingStrategy(nodes[i % len(nodes)], soft=True) if nodes else "DEFAULT"
        task = _rollout_chunk.options(num_cpus=cpus_per_task, scheduling_strategy=strategy)
        refs.append(task.remote(model_ref, x0[a:b], nstep, None if control is None else control[a:b]))
    parts = ray.get(refs)
    states = np.concatenate([p[0] for p in parts]) if parts else np.zeros((0, nstep, model.nstate))
    status = np.concatenate([p[1] for p in parts]) if parts else np.zeros(0, dtype=np.int64)
    if return_details:
        details = [
            {"rows": (int(a), int(b)), "nthread": p[2], "node": p[3]}
            for (a, b), p in zip(zip(bounds[:-1], bounds[1:]), parts)
        ]
        return states, status, details
    return states, status
