"""Shared fixtures: the repository's scenes, loaded models, the CLI binary."""

import os
import shutil
from pathlib import Path

import numpy as np
import pytest

import tumble

REPO = Path(__file__).resolve().parents[3]
SCENES = REPO / "scenes"


@pytest.fixture(scope="session")
def demo() -> tumble.Model:
    return tumble.Model.from_file(SCENES / "demo.toml")


@pytest.fixture(scope="session")
def pendulum() -> tumble.Model:
    return tumble.Model.from_file(SCENES / "double_pendulum.toml")


@pytest.fixture(scope="session")
def projectile() -> tumble.Model:
    return tumble.Model.from_file(SCENES / "projectile.toml")


def tumble_cli() -> Path:
    """The `tumble` binary: $TUMBLE_CLI (tools/test.sh sets it; then it must exist), else
    target/release/tumble under $CARGO_TARGET_DIR or the repository, else on PATH."""
    given = os.environ.get("TUMBLE_CLI")
    if given:
        path = Path(given)
        assert path.is_file(), f"TUMBLE_CLI={given} does not exist"
        return path
    target = Path(os.environ.get("CARGO_TARGET_DIR", REPO / "target"))
    for candidate in [target / "release" / "tumble", shutil.which("tumble")]:
        if candidate and Path(candidate).is_file():
            return Path(candidate)
    pytest.skip("the tumble CLI is not built (cargo build --release), and TUMBLE_CLI is not set")


def step_rows(model: tumble.Model, x0: np.ndarray, nstep: int, control=None) -> np.ndarray:
    """The reference for rollout: one World per row, stepped from Python."""
    out = np.empty((x0.shape[0], nstep, model.nstate))
    for b, x in enumerate(x0):
        w = tumble.World(model)
        w.set_state(x)
        for t in range(nstep):
            if control is not None:
                k = 0
                for r, name in enumerate(model.robot_names):
                    nv = model.nv(name)
                    w.set_torque(r, control[b, t, k : k + nv])
                    k += nv
            w.step()
            w.state(out=out[b, t])
    return out
