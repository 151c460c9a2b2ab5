"""Timing on a shared machine: samples during which other processes used the CPUs are discarded.

During each sample the machine's busy CPU time (/proc/stat) is compared with this process's own
(and its children's, `os.times`); a sample where others used more than 5 % of one core is taken
again, up to `attempts` times. Linux only.
"""

import os
import time

_TICK = os.sysconf("SC_CLK_TCK")


def _busy() -> float:
    with open("/proc/stat") as f:
        fields = [int(x) for x in f.readline().split()[1:]]
    idle = fields[3] + fields[4]  # idle, iowait
    return (sum(fields[:8]) - idle) / _TICK


def _own() -> float:
    t = os.times()
    return t.user + t.system + t.children_user + t.children_system


def best(f, repeat=5, attempts=40):
    """The shortest of `repeat` quiet runs of `f` (seconds), and whether all of them were quiet."""
    quiet, noisy = [], []
    for _ in range(attempts):
        b0, o0, t0 = _busy(), _own(), time.perf_counter()
        f()
        dt = time.perf_counter() - t0
        others = (_busy() - b0) - (_own() - o0)
        (quiet if others < 0.05 * dt + 0.02 else noisy).append(dt)
        if len(quiet) >= repeat:
            break
    if quiet:
        return min(quiet), len(quiet) >= repeat
    return min(noisy), False
