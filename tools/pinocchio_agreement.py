#!/usr/bin/env python3
"""Measures how closely `tumble dynamics` reproduces the Pinocchio fixtures.

    python tools/pinocchio_agreement.py [PATH/TO/tumble]   (default: target/release/tumble)

For each fixture of crates/tumble/tests/fixtures/robots it feeds the fixture's states to
`tumble dynamics --joint-order name` (Pinocchio's numbering) and prints, per quantity, the largest
difference relative to max(1, largest reference entry), over all states.
"""
import json
import os
import subprocess
import sys
import tempfile

import numpy as np

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..")
FIXTURES = os.path.join(ROOT, "crates", "tumble", "tests", "fixtures", "robots")
NAMES = ["double_pendulum", "double_pendulum_continuous", "ur5", "panda", "solo12", "talos_reduced"]


def main():
    tumble = sys.argv[1] if len(sys.argv) > 1 else os.path.join(ROOT, "target", "release", "tumble")
    with tempfile.TemporaryDirectory() as tmp:
        src, dst = os.path.join(tmp, "in.jsonl"), os.path.join(tmp, "out.jsonl")
        for name in NAMES:
            fixture = json.load(open(os.path.join(FIXTURES, name + ".json")))
            with open(src, "w") as f:
                for s in fixture["states"]:
                    f.write(json.dumps({"q": s["q"], "v": s["v"], "tau": s["tau_in"], "a": s["a"]}) + "\n")
            args = [tumble, "dynamics", os.path.join(FIXTURES, fixture["urdf"]), "--input", src, "--out", dst,
                    "--joint-order", "name"] + (["--floating"] if fixture["floating"] else [])
            subprocess.run(args, check=True)
            worst = {}
            for line, s in zip(open(dst), fixture["states"]):
                out = json.loads(line)
                for key in ("mass_matrix", "bias", "qdd", "tau"):
                    a, b = np.array(out[key]), np.array(s[key])
                    worst[key] = max(worst.get(key, 0.0), np.max(np.abs(a - b)) / max(1.0, np.max(np.abs(b))))
            print("%-28s nv=%2d  " % (name, fixture["nv"]) + "  ".join("%s %.1e" % kv for kv in worst.items()))


if __name__ == "__main__":
    main()
