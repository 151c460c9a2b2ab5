#!/usr/bin/env python3
"""`tumble dynamics --balance-inertia` against Pinocchio on the same repaired robots.

For each example-robot-data URDF that needs `--balance-inertia`, every link inertia that is not
physical is replaced here, in Python, by the nearest physical tensor as docs/multibody.md defines it
(eigenvectors kept, eigenvalues projected onto {l_i + l_j >= l_k}; mass 0: the zero tensor). The
repaired URDF is loaded by Pinocchio; the original is loaded by `tumble dynamics --balance-inertia
--joint-order name` (Pinocchio's joint order). The mass matrix and the bias at random states must
agree to round-off. The difference between Pinocchio on the original file and on the repaired one is
printed too: it is what the repair changes.

    /tmp/erd/bin/python tools/erd_compare_repaired.py [--tumble target/release/tumble]
"""

import argparse
import itertools
import json
import os
import subprocess
import sys
import tempfile
import xml.etree.ElementTree as ET

import numpy as np
import pinocchio as pin

from erd_load_all import robots_dir  # tools/ is the script's directory, first on sys.path

# (URDF, floating base): a defective link fixed to a fixed base changes nothing in M or the bias
ROBOTS = [
    ("anymal_c_simple_description/urdf/anymal.urdf", False),
    ("anymal_c_simple_description/urdf/anymal.urdf", True),
    ("pr2_description/urdf/pr2.urdf", False),
    ("tiago_description/robots/tiago_dual.urdf", False),
    ("tiago_description/robots/tiago_dual.urdf", True),
    ("allegro_hand_description/urdf/allegro_left_hand.urdf", False),
    ("icub_description/robots/icub.urdf", True),
    ("bolt_description/robots/bolt.urdf", True),
    ("romeo_description/urdf/romeo_small.urdf", True),
]
TOL = 1e-9
KEYS = ["ixx", "ixy", "ixz", "iyy", "iyz", "izz"]


def physical(lam):
    lam = np.asarray(lam)
    largest = np.abs(lam).max()
    return all(lam[i] + lam[j] - lam[k] >= -TOL * largest for i, j, k in [(0, 1, 2), (0, 2, 1), (1, 2, 0)])


def project(lam):
    """Nearest point of {l_i + l_j >= l_k} to lam: the nearest feasible projection onto the span of a
    set of active constraints."""
    normals = np.array([[1, 1, -1], [1, -1, 1], [-1, 1, 1]], dtype=float)
    best, best_d = np.zeros(3), np.dot(lam, lam)
    for size in (1, 2):
        for active in itertools.combinations(range(3), size):
            n = normals[list(active)]
            x = lam - n.T @ np.linalg.solve(n @ n.T, n @ lam)
            if np.all(normals @ x >= -1e-12 * np.abs(x).max()) and np.dot(x - lam, x - lam) < best_d:
                best, best_d = x, np.dot(x - lam, x - lam)
    return best


def repair(path, out):
    tree = ET.parse(path)
    changed = []
    for link in tree.getroot().findall("link"):
        inertial = link.find("inertial")
        if inertial is None or inertial.find("inertia") is None:
            continue
        node = inertial.find("inertia")
        v = {k: float(node.get(k, "0")) for k in KEYS}
        t = np.array([[v["ixx"], v["ixy"], v["ixz"]], [v["ixy"], v["iyy"], v["iyz"]], [v["ixz"], v["iyz"], v["izz"]]])
        mass = float(inertial.find("mass").get("value"))
        if not t.any():
            continue
        lam, p = np.linalg.eigh(t)
        if mass != 0 and physical(lam):
            continue
        new = np.zeros((3, 3)) if mass == 0 else p @ np.diag(project(lam)) @ p.T
        for k, (i, j) in zip(KEYS, [(0, 0), (0, 1), (0, 2), (1, 1), (1, 2), (2, 2)]):
            node.set(k, repr(float(new[i, j])))
        changed.append(link.get("name"))
    tree.write(out)
    return changed


def tumble_q(model, q):
    out = []
    for j in model.joints[1:]:
        if j.shortname() == "JointModelFreeFlyer":
            x, y, z, w = q[j.idx_q + 3:j.idx_q + 7]
            out.extend(q[j.idx_q:j.idx_q + 3].tolist() + [float(w), float(x), float(y), float(z)])
        elif j.shortname().startswith("JointModelRUB"):
            out.append(float(np.arctan2(q[j.idx_q + 1], q[j.idx_q])))
        else:
            out.extend(q[j.idx_q:j.idx_q + j.nq].tolist())
    return out


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--tumble", default=os.path.join(os.path.dirname(__file__), "..", "target", "release", "tumble"))
    args = parser.parse_args()
    root = robots_dir()
    rng = np.random.default_rng(11)
    worst = 0.0
    print("%-62s %4s %6s %-9s %-9s %-9s" % ("robot", "nv", "links", "M", "bias", "repair's effect"))
    for rel, floating in ROBOTS:
        path = os.path.join(root, rel)
        with tempfile.TemporaryDirectory() as d:
            fixed = os.path.join(d, "repaired.urdf")
            changed = repair(path, fixed)
            build = (lambda f: pin.buildModelFromUrdf(f, pin.JointModelFreeFlyer())) if floating else pin.buildModelFromUrdf
            m_raw, m_fix = build(path), build(fixed)
            d_raw, d_fix = m_raw.createData(), m_fix.createData()
            states, ref, raw = [], [], []
            for _ in range(3):
                q = pin.randomConfiguration(m_fix, -np.ones(m_fix.nq), np.ones(m_fix.nq))  # unit quaternion
                v = rng.uniform(-1, 1, m_fix.nv)
                states.append({"q": tumble_q(m_fix, q), "v": v.tolist()})
                for model, data, into in ((m_fix, d_fix, ref), (m_raw, d_raw, raw)):
                    m = pin.crba(model, data, q).copy()
                    m = np.triu(m) + np.triu(m, 1).T
                    into.append((m, pin.rnea(model, data, q, v, np.zeros(model.nv)).copy()))
            inp, out = os.path.join(d, "in.jsonl"), os.path.join(d, "out.jsonl")
            with open(inp, "w") as f:
                f.writelines(json.dumps(s) + "\n" for s in states)
            cmd = [args.tumble, "dynamics", path, "--balance-inertia", "--joint-order", "name"]
            cmd += ["--floating"] if floating else []
            r = subprocess.run(cmd + ["--input", inp, "--out", out], capture_output=True, text=True)
            if r.returncode != 0:
                sys.exit("%s: %s" % (rel, r.stderr.strip().splitlines()[-1]))
            with open(out) as f:
                got = [json.loads(line) for line in f]
        dm = db = effect = 0.0
        for g, (m, b), (m0, b0) in zip(got, ref, raw):
            scale_m, scale_b = max(1.0, np.abs(m).max()), max(1.0, np.abs(b).max())
            dm = max(dm, np.abs(np.array(g["mass_matrix"]) - m).max() / scale_m)
            db = max(db, np.abs(np.array(g["bias"]) - b).max() / scale_b)
            effect = max(effect, np.abs(m - m0).max() / scale_m, np.abs(b - b0).max() / scale_b)
        worst = max(worst, dm, db)
        name = rel + (" (floating)" if floating else "")
        print("%-62s %4d %6d %-9.2e %-9.2e %-9.2e" % (name, m_fix.nv, len(changed), dm, db, effect))
    print("largest difference tumble - Pinocchio (relative to max(1, largest entry)): %.2e" % worst)
    return 0 if worst < 1e-9 else 1


if __name__ == "__main__":
    sys.exit(main())
