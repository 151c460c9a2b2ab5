"""docs/python.md: its first example and the Go1 random-policy example run, from the repository's root."""

import re
import subprocess
import sys

from conftest import REPO


def test_first_example_runs():
    text = (REPO / "docs" / "python.md").read_text()
    example = re.search(r"## A first example\n\n```python\n(.*?)```", text, re.S).group(1)
    done = subprocess.run([sys.executable, "-c", example], cwd=REPO, capture_output=True, text=True, timeout=120)
    assert done.returncode == 0, done.stderr
    assert "t = 1.000 s" in done.stdout and "after 10 s the shoulder angles spread" in done.stdout


def test_go1_random_policy_example_runs():
    text = (REPO / "docs" / "python.md").read_text()
    example = re.search(r"A random policy:\n\n```python\n(.*?)```", text, re.S).group(1)
    done = subprocess.run([sys.executable, "-c", example], cwd=REPO, capture_output=True, text=True, timeout=120)
    assert done.returncode == 0, done.stderr
    assert "steps, return" in done.stdout and "vector env: (16, 48)" in done.stdout
