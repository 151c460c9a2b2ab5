#!/usr/bin/env python3
"""Checks that every URDF of example-robot-data loads in `tumble model` and `tumble dynamics`.

For each URDF (found under the installed package's `robots/` directory, or `--robots DIR`), tries
`tumble model --json` with no flag, then `--balance-inertia`, `--massless fuse`, and both, and
records the first set of flags that loads. With those flags, `tumble dynamics` is run on three
states (neutral, and two seeded random ones, with torques) and its output must be finite. When
Pinocchio is importable, its nv and total mass are printed beside tumble's (tumble's nv is smaller
by the joints that `--massless fuse` held).

    python3 -m venv /tmp/erd && /tmp/erd/bin/pip install example-robot-data==6.0.0 pin
    cargo build --release -p tumble-cli
    /tmp/erd/bin/python tools/erd_load_all.py [--tumble target/release/tumble] [--json OUT.json] \
        [--fixture crates/tumble/tests/fixtures/robots/example_robot_data.json]

Exit status 0 when every URDF loads and gives finite dynamics, 1 otherwise.
"""

import argparse
import json
import math
import os
import random
import subprocess
import sys
import tempfile

FLAG_SETS = [[], ["--balance-inertia"], ["--massless", "fuse"], ["--balance-inertia", "--massless", "fuse"]]


def robots_dir():
    for p in sys.path:
        d = os.path.join(p, "cmeel.prefix", "share", "example-robot-data", "robots")
        if os.path.isdir(d):
            return d
    sys.exit("example-robot-data not found: install it (see the docstring) or pass --robots DIR")


def run(cmd):
    return subprocess.run(cmd, capture_output=True, text=True)


def pinocchio_numbers(urdf):
    try:
        import pinocchio
    except ImportError:
        return None
    try:
        model = pinocchio.buildModelFromUrdf(urdf)
    except Exception as e:  # noqa: BLE001 - report whatever Pinocchio says
        return {"error": str(e).splitlines()[0]}
    mass = sum(model.inertias[i].mass for i in range(model.njoints))  # 0: what is fixed to the world
    return {"nq": model.nq, "nv": model.nv, "mass": mass}


def dynamics(tumble, urdf, flags, layout, rng):
    nq, nv = layout["nq"], layout["nv"]
    states = [{"q": [0.0] * nq, "v": [0.0] * nv, "tau": [0.0] * nv}]
    for _ in range(2):
        states.append(
            {
                "q": [rng.uniform(-0.5, 0.5) for _ in range(nq)],
                "v": [rng.uniform(-1, 1) for _ in range(nv)],
                "tau": [rng.uniform(-1, 1) for _ in range(nv)],
            }
        )
    with tempfile.TemporaryDirectory() as d:
        inp, out = os.path.join(d, "in.jsonl"), os.path.join(d, "out.jsonl")
        with open(inp, "w") as f:
            for s in states:
                f.write(json.dumps(s) + "\n")
        r = run([tumble, "dynamics", urdf, *flags, "--input", inp, "--out", out])
        if r.returncode != 0:
            return "exit %d: %s" % (r.returncode, r.stderr.strip().splitlines()[-1])
        with open(out) as f:
            lines = [json.loads(line) for line in f]
    if len(lines) != len(states):
        return "%d lines for %d states" % (len(lines), len(states))
    for line in lines:
        for key in ("mass_matrix", "bias", "qdd"):
            values = line[key]
            flat = [x for row in values for x in row] if key == "mass_matrix" else values
            if not all(isinstance(x, float | int) and math.isfinite(x) for x in flat):
                return "%s not finite" % key
    return None


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--tumble", default=os.path.join(os.path.dirname(__file__), "..", "target", "release", "tumble"))
    parser.add_argument("--robots", default=None)
    parser.add_argument("--json", default=None, help="write the results here")
    parser.add_argument("--fixture", default=None,
                        help="write what each URDF needs and Pinocchio's nv and mass here (the Rust test's fixture)")
    args = parser.parse_args()
    root = args.robots or robots_dir()
    urdfs = sorted(
        os.path.join(d, f) for d, _, files in os.walk(root) for f in files if f.endswith(".urdf")
    )
    rng = random.Random(11)
    results, failures = [], 0
    for urdf in urdfs:
        name = os.path.relpath(urdf, root)
        row = {"urdf": name, "flags": None}
        errors = []
        for flags in FLAG_SETS:
            r = run([args.tumble, "model", urdf, "--json", *flags])
            if r.returncode == 0:
                layout = json.loads(r.stdout)
                row.update(flags=flags, nq=layout["nq"], nv=layout["nv"], mass=layout["total_mass"])
                row["warnings"] = [w for w in r.stderr.splitlines() if "inertia balanced" in w or "fused" in w]
                row["dynamics_error"] = dynamics(args.tumble, urdf, flags, layout, rng)
                break
            errors.append(r.stderr.strip())
        else:
            row["error"] = errors[0]
        row["pinocchio"] = pinocchio_numbers(urdf)
        ok = row["flags"] is not None and row.get("dynamics_error") is None
        failures += not ok
        pin = row["pinocchio"] or {}
        print(
            "%-4s %-62s %-32s nv %-4s mass %-10s pinocchio nv %-4s mass %s%s"
            % (
                "ok" if ok else "FAIL",
                name,
                " ".join(row["flags"]) if row["flags"] is not None else "-",
                row.get("nv", "-"),
                "%.6g" % row["mass"] if "mass" in row else "-",
                pin.get("nv", "-"),
                "%.6g" % pin["mass"] if "mass" in pin else pin.get("error", "-"),
                "" if ok else "  " + (row.get("dynamics_error") or row.get("error", "")),
            )
        )
        results.append(row)
    print("%d URDFs: %d load with finite dynamics, %d fail" % (len(urdfs), len(urdfs) - failures, failures))
    if args.fixture:
        import pinocchio
        rows = [
            {
                "urdf": r["urdf"],
                "balance_inertia": "--balance-inertia" in (r["flags"] or []),
                "massless_fuse": "fuse" in (r["flags"] or []),
                "pinocchio_nv": (r["pinocchio"] or {}).get("nv"),
                "pinocchio_mass": (r["pinocchio"] or {}).get("mass"),
            }
            for r in results
        ]
        with open(args.fixture, "w") as f:
            json.dump({"package": "example-robot-data 6.0.0", "generator": "tools/erd_load_all.py, pinocchio %s"
                       % pinocchio.__version__, "robots": rows}, f, indent=1)
            f.write("\n")
    if args.json:
        with open(args.json, "w") as f:
            json.dump(results, f, indent=1)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
