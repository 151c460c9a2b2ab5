#!/usr/bin/env python3
"""Where a legged robot's step goes: `tumble run --profile` on the quadruped scenes of
example-robot-data, a markdown table of µs per step per stage.

    cargo build --release -p tumble-cli
    python3 tools/legged_profile.py [--tumble target/release/tumble] [--runs 3] [--integrator rk4]
                                    [--baseline OLD/tumble]

With `--baseline`, an older build runs interleaved with this one (run for run, scene by scene, so
that the machine's drift falls on both alike) and its table is printed first, then this one's and
the ratio of the steps.

Scenes: scenes/{solo12,go1,anymal_c}_{stand,trot}.toml (tools/quadruped_scenes.py), 5 s at
dt = 1e-3, sampled every 5000 steps (the step loop alone). Each scene runs `--runs` times; per scene
the run with the shortest step is kept (the machine's other load only adds time). The stages are
those of `tumble::world::Profile`; "rows" is the robots' contact rows (M, a0, J, the contact space),
"dynamics" the robots' own step, "kinematics" their forward kinematics, energy and momentum after it.
"""
import argparse
import json
import os
import subprocess
import tempfile

ROOT = os.path.normpath(os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
SCENES = [f"{r}_{m}" for r in ("solo12", "go1", "anymal_c") for m in ("stand", "trot")]
COLUMNS = [("broad_phase_us", "broad"), ("link_detect_us", "link shapes, contacts"),
           ("link_rows_us", "rows: M, a0, J, G"), ("collisions_us", "collisions"),
           ("resting_us", "resting (substeps)"), ("robot_dynamics_us", "dynamics"),
           ("robot_bookkeeping_us", "kinematics, energy"), ("step_us", "step")]


def profile(tumble, scene, integrator, runs):
    best = None
    with tempfile.TemporaryDirectory() as tmp:
        for _ in range(runs):
            summary = os.path.join(tmp, "s.json")
            cmd = [tumble, "run", os.path.join(ROOT, "scenes", scene + ".toml"), "--quiet", "--profile",
                   "--summary", summary, "--out", os.path.join(tmp, "t.csv"), "--sample-every", "5000"]
            if integrator:
                cmd += ["--integrator", integrator]
            subprocess.run(cmd, check=True, stderr=subprocess.DEVNULL)
            with open(summary) as f:
                p = json.load(f)["profile"]
            p["collisions_us"] = p["impacts_us"] - p["link_rows_us"]
            if best is None or p["step_us"] < best["step_us"]:
                best = p
    return best


def table(title, rows):
    print(f"\n{title}\n")
    print("| scene | contacts | " + " | ".join(name for _, name in COLUMNS) + " |")
    print("|---|---|" + "---|" * len(COLUMNS))
    for scene, p in rows.items():
        cells = [f"{p[key]:.2f}" for key, _ in COLUMNS]
        cells[-1] = f"**{cells[-1]}**"
        print(f"| {scene} | {p['link_contacts']:.1f} | " + " | ".join(cells) + " |")


def main():
    ap = argparse.ArgumentParser()
    default = os.path.join(ROOT, "target", "release", "tumble")
    ap.add_argument("--tumble", default=default)
    ap.add_argument("--baseline", default=None)
    ap.add_argument("--runs", type=int, default=3)
    ap.add_argument("--integrator", default=None)
    ap.add_argument("--json", default=None)
    args = ap.parse_args()
    rows, base = {}, {}
    for scene in SCENES:
        for _ in range(args.runs):
            for binary, out in ([(args.baseline, base)] if args.baseline else []) + [(args.tumble, rows)]:
                p = profile(binary, scene, args.integrator, 1)
                if scene not in out or p["step_us"] < out[scene]["step_us"]:
                    out[scene] = p
    if args.baseline:
        table(f"baseline ({args.baseline})", base)
    table(f"this build ({args.tumble})", rows)
    if args.baseline:
        print("\n| scene | step before (µs) | step after (µs) | after / before |\n|---|---|---|---|")
        for scene in SCENES:
            b, a = base[scene]["step_us"], rows[scene]["step_us"]
            print(f"| {scene} | {b:.2f} | {a:.2f} | {a / b:.2f} |")
    if args.json:
        with open(args.json, "w") as f:
            json.dump({"this": rows, "baseline": base}, f, indent=1)


if __name__ == "__main__":
    main()
