"""tumble.distributed: a batch spread over a Ray cluster of two worker nodes (on this machine) gives the
local numbers bit for bit; each task sizes its thread pool from its CPUs."""

import os

import numpy as np
import pytest

os.environ.setdefault("RAY_USAGE_STATS_ENABLED", "0")
ray = pytest.importorskip("ray")
from ray.cluster_utils import Cluster  # noqa: E402

import tumble  # noqa: E402
import tumble.distributed  # noqa: E402


@pytest.fixture(scope="module")
def cluster():
    c = Cluster(initialize_head=True, head_node_args={"num_cpus": 0, "include_dashboard": False})
    workers = [c.add_node(num_cpus=1) for _ in range(2)]
    c.wait_for_nodes()
    ray.init(address=c.address, log_to_driver=False)
    yield c, workers
    ray.shutdown()
    c.shutdown()


def test_ray_rollout_equals_local(cluster, pendulum):
    _, workers = cluster
    rng = np.random.default_rng(7)
    x0 = np.column_stack([rng.uniform(-3, 3, (24, 2)), rng.uniform(-1, 1, (24, 2))])
    u = rng.normal(0, 1, (24, 300, pendulum.nu))
    local = tumble.rollout(pendulum, x0, 300, u)
    states, status, details = tumble.distributed.rollout(pendulum, x0, 300, u, chunks=4, return_details=True)
    assert np.array_equal(states, local)
    assert status.tolist() == [300] * 24
    assert [d["rows"] for d in details] == [(0, 6), (6, 12), (12, 18), (18, 24)]
    # one CPU per task: Ray sets OMP_NUM_THREADS = 1 there, and the pool follows it
    assert all(d["nthread"] == 1 for d in details)
    assert {d["node"] for d in details} == {w.node_id for w in workers}
