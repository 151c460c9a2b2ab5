#!/usr/bin/env python3
"""Solo-12, Go1 and ANYmal C standing and trotting, tumble beside MuJoCo in one run: contact quality and time per step.

    python tools/legged_mujoco_bench.py [--pairs N] [--tumble PATH] [--json OUT.json] [--quick]

    --tumble PATH   the tumble binary (default /work/bin/tumble if it exists, else target/release/tumble)
    --pairs N       interleaved timing rounds (default 7)
    --json OUT.json every figure printed, and each round's times, as JSON
    --quick         1 round and 1 s of simulated time per scene (a smoke test; the quality window is
                    then [0.5, 1] s instead of [1, 5] s)

Run it with the virtualenv that has MuJoCo (`/work/venv/bin/python`, or `pip install mujoco numpy`).

The scenes are scenes/{solo12,go1,anymal_c}_{stand,trot}.toml (written by tools/quadruped_scenes.py): a
robot of example-robot-data on a floating base, let go 5 mm above its SRDF standing pose, held by PD, on a
plane, friction 0.9 on the floor and on the links, dt = 1e-3 s, 5 s, semi-implicit Euler. The trot
scenes swing the hip-flexion and knee targets, `q*(t) = target + amplitude sin(2 pi frequency t + phase)`,
evaluated at the start of each step (t_n = n dt) and held over the step; the velocity target is 0, so
`tau = kp (q*(t_n) - q) - kd v`.

The script READS each scene (tomllib) and builds the same model in MuJoCo:
- the SAME URDF, `mujoco.MjSpec.from_file`, with MuJoCo's URDF defaults `discardvisual` (tumble ignores
  <visual>: only the <collision> geometry is kept, checked by counting) and `fusestatic` (links on fixed
  joints merged into their parent, as tumble does); the `package://` mesh files (Solo-12's STL collision
  meshes) resolved as tumble does (the URDF's parent directories, then the scene's `package_paths`) and
  given to MuJoCo as absolute paths; MuJoCo collides a mesh through its convex hull, tumble too;
- `inertiafromgeom = false` (a link without <inertial> stays massless, as in tumble); where the scene says
  `balance_inertia = true`, the link inertias that are not physical are replaced before compiling by the
  tensor tumble uses (the nearest physical one in the Frobenius norm: same axes, principal moments
  projected onto the triangle inequalities; see crates/tumble/src/multibody/balance.rs), and MuJoCo's
  `balanceinertia` is set too (it then has nothing left to do); the total masses are checked equal;
- the URDF's <dynamics damping friction> (which MuJoCo would read, and Go1 has) set to 0 unless the scene
  asks for damping: tumble ignores them by default; armature 0;
- a free joint on the root link, initial base position and orientation and joint angles from the scene,
  zero velocity; a ground plane at z = 0; gravity and timestep from the scene;
- PD as position actuators (kp, kv = kd), `ctrl = q*(t_n)` at each step (mujoco.rollout's control array);
  the URDF `effort` (when > 0) as each joint's `actuatorfrcrange`, as tumble's `effort_limits` (default on)
  clamps the commanded torque to it; the URDF joint ranges kept as limits (tumble's `joint_limits`, default
  on; MuJoCo's are soft constraints, tumble's hard);
- friction: tumble combines two materials as sqrt(mu_a mu_b) (0.9 and 0.9 give 0.9), MuJoCo takes the larger
  of the two geoms' values: every geom gets tumble's pair value; condim 3; no self-collision (tumble's
  `self_collision = false` default): the robot's geoms have conaffinity 0, the ground contype 0;
- MuJoCo's default contact otherwise: soft constraints, solref (0.02, 1), solimp (0.9, 0.95, 0.001, 0.5, 2),
  margin 0, Newton solver; the cone PYRAMIDAL (default) and ELLIPTIC (like tumble's friction disc) both run.
Not the same, and left so: tumble's restitution (the world default 0.5, Stronge's law, for impacts faster
than its `impact_speed`) has no MuJoCo counterpart (its contact is a critically damped spring, so a landing
foot does not bounce); tumble's contacts and joint limits are hard, MuJoCo's soft (a standing foot sinks by
the spring's deflection, about 0.5-1 mm here); MuJoCo's mesh-plane contact gives up to 4 points per
Solo-12 foot, tumble's parry manifold up to 4 too (2 where the hull touches along an edge).
Integrators compared: tumble `semi_implicit_euler` (the scenes') with MuJoCo `Euler`, and tumble `rk4`
(`--integrator rk4`) with MuJoCo `RK4`.

Quality (one run of every variant, sampled every 10 steps as the scene's trajectory is, the trot every step
(its landings come at a fixed phase of a 500-step stride, and tumble's impact spikes, the impulse over one
step, would be caught at every stride or never); tumble's from
`--out T.csv --contacts C.jsonl`, its link rows `robot/link` being the link frames; MuJoCo's from a copy of
the data at each sample, `mj_forward` on it with the control of the step just taken, then
`data.contact.dist` and `mj_contactForce`). The window is
t in [1, 5] s, after the landing:
- drift: the largest displacement of the base link's origin from where it was at t = 1 s (mm), 3-D, and
  its horizontal and vertical parts (each its own largest);
- sink: the deepest penetration of any contact (mm);
- Fn/W: the sum of the contacts' normal forces over the robot's weight, its mean and its largest relative
  deviation from 1 (%); tumble's force is the step's impulse over dt (impacts included);
- slide: the largest horizontal displacement of a foot link's origin from where it was at t = 1 s (mm);
  feet are the links whose name contains "foot" (MuJoCo: a site at the link origin);
- other: the number of samples in the window with a contact on a link that is not a foot.
For the trot: base height min and max over the window (m), the mean of Fn/W, the horizontal drift.

Speed: PAIRS interleaved rounds (the machine's speed drifts, and another job shares it: ratios are taken
within a round, and the median and range of the rounds' ratios are reported). In a round, for every
scene, each variant runs three times back to back and keeps its shortest time; the tumble variant and the
MuJoCo variants it is compared with are neighbours, and the order is reversed every other round. tumble:
`tumble run SCENE --quiet --summary S.json --out T.csv --sample-every 5000` (`wall_time_s` / steps: the step
loop, not the process start or the scene load); MuJoCo: all the steps in one `mujoco.rollout.rollout` call
with one MjData (one thread, the loop in C) and the per-step control array (nbatch 1, nstep, nu). The
table gives, per robot, motion and integrator pair, tumble's µs per step, each MuJoCo cone's µs per step
(medians over the rounds) and the ratio tumble / MuJoCo, median [min, max] over the rounds (> 1: tumble is
slower).
"""
import argparse
import csv
import json
import math
import os
import subprocess
import sys
import tempfile
import time
import tomllib

import numpy as np
import mujoco
from mujoco import rollout

ROOT = os.path.normpath(os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
ROBOTS = ["solo12", "go1", "anymal_c"]
MOTIONS = ["stand", "trot"]
BEST = 3                 # runs of each variant in a round, the shortest kept
WINDOW_START = 1.0       # s: quality figures over [WINDOW_START, duration]
TIMING_SAMPLE_EVERY = 5000
DEFAULT_FRICTION = 0.5   # tumble's default material friction (docs/scene-format.md)
DEFAULT_RESTITUTION = 0.5  # tumble's world default restitution (docs/scene-format.md)
PAIRS = [("semi_implicit_euler", "Euler"), ("rk4", "RK4")]
CONES = ["pyramidal", "elliptic"]
SUPPORTED_ROBOT_KEYS = {"name", "urdf", "base", "position", "orientation", "q", "friction", "balance_inertia",
                        "pd", "collision", "self_collision", "joint_limits", "effort_limits", "package_paths",
                        "damping", "restitution"}


# ---------------------------------------------------------------------------------------------- the scene

def quat_to_mat(q):
    w, x, y, z = q
    return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
                     [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
                     [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)]])


def project_on_triangle_cone(lam):
    """Euclidean projection of principal moments onto {l_i + l_j >= l_k} (tumble's balance_inertia)."""
    normals = [np.array([1.0, 1.0, -1.0]), np.array([1.0, -1.0, 1.0]), np.array([-1.0, 1.0, 1.0])]

    def feasible(x):
        return all(n @ x >= -1e-12 * np.max(np.abs(x)) for n in normals)

    if feasible(lam):
        return lam
    best, best_d = np.zeros(3), lam @ lam
    candidates = [lam - n * (n @ lam / 3.0) for n in normals]
    for a, b in [(0, 1), (0, 2), (1, 2)]:
        ra, rb = normals[a] @ lam, normals[b] @ lam
        ya, yb = (3 * ra + rb) / 8.0, (ra + 3 * rb) / 8.0
        candidates.append(lam - normals[a] * ya - normals[b] * yb)
    for x in candidates:
        d = (x - lam) @ (x - lam)
        if d < best_d and feasible(x):
            best, best_d = x, d
    return best


def inertia_is_physical(mass, tensor):
    lam = np.linalg.eigvalsh(tensor)
    if mass == 0.0:
        return not np.any(tensor)
    tol = 1e-9 * np.max(np.abs(lam))
    return bool(np.all(lam >= -tol) and lam.sum() - 2 * lam.max() >= -tol)


def resolve_mesh(uri, urdf, package_paths):
    """package://NAME/rest as tumble looks it up: the URDF's parent directories, then package_paths."""
    if uri.startswith("file://"):
        uri = uri[len("file://"):]
    if not uri.startswith("package://"):
        return uri if os.path.isabs(uri) else os.path.join(os.path.dirname(urdf), uri)
    name, _, rest = uri[len("package://"):].partition("/")
    tried = []
    d = os.path.dirname(os.path.abspath(urdf))
    while True:
        tried += [os.path.join(d, rest)] if os.path.basename(d) == name else []
        tried.append(os.path.join(d, name, rest))
        parent = os.path.dirname(d)
        if parent == d:
            break
        d = parent
    tried += [os.path.join(p, name, rest) for p in package_paths]
    for t in tried:
        if os.path.isfile(t):
            return t
    raise FileNotFoundError(f"{uri}: none of {tried[:4]}...")


class Scene:
    def __init__(self, robot, motion, duration=None):
        self.key = f"{robot}_{motion}"
        self.robot_key, self.motion = robot, motion
        self.path = os.path.join(ROOT, "scenes", self.key + ".toml")
        with open(self.path, "rb") as f:
            doc = tomllib.load(f)
        here = os.path.dirname(self.path)
        w = doc["world"]
        self.dt = float(w["dt"])
        self.scene_duration = float(w["duration"])
        self.duration = float(duration) if duration is not None else self.scene_duration
        self.nstep = int(round(self.duration / self.dt))
        self.integrator = w.get("integrator", "semi_implicit_euler")
        self.gravity = [float(g) for g in w.get("gravity", [0.0, 0.0, -9.81])]
        self.sample_every = int(w.get("sample_every", 10))
        # the trot's feet land at a fixed phase of the 0.5 s gait (500 steps, a multiple of 10): sampled
        # every 10 steps, tumble's impact spikes are caught at the same phase of every stride or never,
        # and the mean normal force is off by several % (ANYmal: 1.063 W every 10 steps, 0.9999 W every
        # step): the trot's quality runs sample every step
        self.quality_every = self.sample_every if motion == "stand" else 1
        bodies = doc.get("body", [])
        assert len(bodies) == 1 and bodies[0]["shape"]["type"] == "plane" and bodies[0].get("fixed"), bodies
        ground = bodies[0]
        assert all(float(p) == 0.0 for p in ground.get("position", [0, 0, 0])) and "orientation" not in ground
        self.ground_name = ground["name"]
        self.ground_friction = float(ground.get("friction", DEFAULT_FRICTION))
        assert len(doc["robot"]) == 1
        r = doc["robot"][0]
        unknown = set(r) - SUPPORTED_ROBOT_KEYS
        if unknown:
            raise SystemExit(f"{self.path}: robot keys not modelled here: {sorted(unknown)}")
        assert r.get("base") == "floating" and r.get("collision", True) and not r.get("self_collision", False)
        self.name = r["name"]
        self.urdf = os.path.normpath(os.path.join(here, r["urdf"]))
        self.package_paths = [os.path.normpath(os.path.join(here, p)) for p in r.get("package_paths", [])]
        self.position = [float(x) for x in r.get("position", [0, 0, 0])]
        self.orientation = [float(x) for x in r.get("orientation", [1, 0, 0, 0])]
        self.q0 = {k: float(v) for k, v in r.get("q", {}).items()}
        self.link_friction = float(r.get("friction", DEFAULT_FRICTION))
        self.mu = math.sqrt(self.ground_friction * self.link_friction)
        default_e = float(w.get("restitution", DEFAULT_RESTITUTION))
        self.restitution = max(float(ground.get("restitution", default_e)), float(r.get("restitution", default_e)))
        self.balance = bool(r.get("balance_inertia", False))
        self.joint_limits = bool(r.get("joint_limits", True))
        self.effort_limits = bool(r.get("effort_limits", True))
        self.damping = r.get("damping", None)
        self.pd = r.get("pd", {})
        self.ctrl = self.control(self.nstep)

    def control(self, nstep):
        """q*(t_n) for n = 0 .. nstep-1, (nstep, nu), actuators in the order of [robot.pd]."""
        t = np.arange(nstep) * self.dt
        cols = []
        for j, g in self.pd.items():
            assert float(g.get("velocity", 0.0)) == 0.0, "velocity targets are not modelled"
            a = float(g.get("amplitude", 0.0))
            cols.append(float(g["target"]) + a * np.sin(2 * np.pi * float(g.get("frequency", 0.0)) * t
                                                         + float(g.get("phase", 0.0))))
        return np.stack(cols, axis=1)

    # ------------------------------------------------------------------------------------------ MuJoCo

    def mujoco_model(self, integrator, cone):
        spec = mujoco.MjSpec.from_file(self.urdf)
        c = spec.compiler
        assert c.discardvisual and c.fusestatic
        c.inertiafromgeom = mujoco.mjtInertiaFromGeom.mjINERTIAFROMGEOM_FALSE
        c.balanceinertia = self.balance
        for m in spec.meshes:
            m.file = resolve_mesh(m.file, self.urdf, self.package_paths)
        self.balanced = []
        for b in spec.bodies[1:]:
            if self.balance:
                self._balance(b)
        root = spec.worldbody.first_body()
        self.root = root.name
        root.add_freejoint()
        self.links_with_geoms = {}
        for b in spec.bodies[1:]:
            for k, g in enumerate(b.geoms):
                g.name = f"{b.name}#{k}"
                self.links_with_geoms.setdefault(b.name, []).append(g.name)
            if "foot" in b.name.lower() and b.geoms:
                b.add_site(name=f"{b.name}@origin", pos=[0.0, 0.0, 0.0])
        self.feet = sorted(n for n in self.links_with_geoms if "foot" in n.lower())
        for g in spec.geoms:
            g.friction = [self.mu, 0.005, 0.0001]
            g.condim = 3
            g.contype, g.conaffinity = 1, 0
        spec.worldbody.add_geom(name=self.ground_name, type=mujoco.mjtGeom.mjGEOM_PLANE, size=[0, 0, 1],
                                friction=[self.mu, 0.005, 0.0001], condim=3, contype=0, conaffinity=1)
        for j in spec.joints:
            if j.type == mujoco.mjtJoint.mjJNT_FREE:
                continue
            j.damping = [0.0, 0.0, 0.0]  # MuJoCo 4: linear, then higher-order coefficients
            j.frictionloss, j.armature = 0.0, 0.0
            if self.damping is not None:
                if self.damping == "urdf":
                    raise SystemExit("damping = \"urdf\": the URDF damping is not read back here")
                j.damping = [float(self.damping.get(j.name, 0.0) if isinstance(self.damping, dict) else self.damping), 0.0, 0.0]
            if not self.joint_limits:
                j.limited = mujoco.mjtLimited.mjLIMITED_FALSE
            effort = float(j.actfrcrange[1])
            if self.effort_limits and effort > 0:
                j.actfrclimited = mujoco.mjtLimited.mjLIMITED_TRUE
                j.actfrcrange = [-effort, effort]
            else:
                j.actfrclimited = mujoco.mjtLimited.mjLIMITED_FALSE
        for jn, g in self.pd.items():
            a = spec.add_actuator(name=jn, target=jn, trntype=mujoco.mjtTrn.mjTRN_JOINT)
            a.set_to_position(kp=float(g["kp"]), kv=float(g.get("kd", 0.0)))
        spec.option.timestep = self.dt
        spec.option.gravity = self.gravity
        spec.option.integrator = getattr(mujoco.mjtIntegrator, "mjINT_" + integrator.upper())
        spec.option.cone = getattr(mujoco.mjtCone, "mjCONE_" + cone.upper())
        ncollision = sum(1 for b in spec.bodies[1:] for _ in b.geoms)
        model = spec.compile()
        assert model.ngeom == ncollision + 1
        data = mujoco.MjData(model)
        data.qpos[:3] = self.position
        data.qpos[3:7] = self.orientation
        for jn, q in self.q0.items():
            data.joint(jn).qpos = q
        data.ctrl[:] = self.ctrl[0]
        mujoco.mj_forward(model, data)
        return model, data

    def _balance(self, body):
        """Replace a link inertia that is not physical by the tensor tumble's balance_inertia gives."""
        if not body.explicitinertial:
            return
        fi = np.array(body.fullinertia)
        if np.any(np.isnan(fi)) or not np.any(fi):
            tensor = np.diag(np.array(body.inertia))
            rot = quat_to_mat(body.iquat)
            tensor = rot @ tensor @ rot.T
        else:
            xx, yy, zz, xy, xz, yz = fi
            tensor = np.array([[xx, xy, xz], [xy, yy, yz], [xz, yz, zz]])
        if inertia_is_physical(body.mass, tensor):
            return
        lam, axes = np.linalg.eigh(tensor)
        after = np.zeros(3) if body.mass == 0.0 else project_on_triangle_cone(lam)
        bal = axes @ np.diag(after) @ axes.T
        bal = 0.5 * (bal + bal.T)
        body.fullinertia = [bal[0, 0], bal[1, 1], bal[2, 2], bal[0, 1], bal[0, 2], bal[1, 2]]
        self.balanced.append((body.name, lam.tolist(), after.tolist()))

    # ------------------------------------------------------------------------------------------ tumble

    def tumble_mass(self, tumble):
        out = subprocess.run([tumble, "check", self.path], capture_output=True, text=True, check=True).stdout
        for line in out.splitlines():
            if line.startswith(f"robot `{self.name}`") and " mass " in line:
                return float(line.split(" mass ")[1].split()[0])
        raise RuntimeError("no mass in `tumble check`")

    def tumble_args(self, integrator):
        args = [] if integrator == self.integrator else ["--integrator", integrator]
        if self.duration != self.scene_duration:
            args += ["--duration", repr(self.duration)]
        return args


# ---------------------------------------------------------------------------------------------- quality

def mujoco_quality(scene, integrator, cone):
    model, data = scene.mujoco_model(integrator, cone)
    base = model.body(scene.root).id
    foot_sites = [model.site(f + "@origin").id for f in scene.feet]
    geom_link = [(mujoco.mj_id2name(model, mujoco.mjtObj.mjOBJ_GEOM, g) or "").split("#")[0]
                 for g in range(model.ngeom)]
    weight = model.body_mass.sum() * abs(scene.gravity[2])
    force = np.zeros(6)
    samples = []
    probe = mujoco.MjData(model)
    for step in range(scene.nstep + 1):
        if step % scene.quality_every == 0 or step == scene.nstep:
            mujoco.mj_copyData(probe, model, data)
            mujoco.mj_forward(model, probe)
            fn, depth, other = 0.0, 0.0, set()
            for i in range(probe.ncon):
                con = probe.contact[i]
                mujoco.mj_contactForce(model, probe, i, force)
                fn += force[0]
                depth = max(depth, -con.dist)
                other |= {geom_link[g] for g in (con.geom1, con.geom2)} - set(scene.feet) - {scene.ground_name}
            samples.append(dict(t=step * scene.dt, base=probe.xpos[base].copy(), feet=probe.site_xpos[foot_sites].copy(),
                                fn=fn / weight, depth=depth, other=other))
        if step < scene.nstep:
            data.ctrl[:] = scene.ctrl[step]
            mujoco.mj_step(model, data)
    if not np.all(np.isfinite(data.qpos)):
        raise RuntimeError(f"MuJoCo {integrator} {cone} diverged on {scene.key}")
    return figures(scene, samples), float(data.qpos[2]), model.body_mass.sum()


def tumble_quality(scene, tumble, tmp, integrator):
    traj, contacts = os.path.join(tmp, "q.csv"), os.path.join(tmp, "c.jsonl")
    subprocess.run([tumble, "run", scene.path, "--quiet", "--out", traj, "--contacts", contacts,
                    "--sample-every", str(scene.quality_every)] + scene.tumble_args(integrator), check=True)
    base_name = f"{scene.name}/{scene.root}"
    feet = [f"{scene.name}/{f}" for f in scene.feet]
    rows = {}
    with open(traj) as f:
        for row in csv.DictReader(f):
            if row["body"] == base_name or row["body"] in feet:
                rows.setdefault(row["t"], {})[row["body"]] = np.array([float(row[k]) for k in ("x", "y", "z")])
    weight = scene.mass * abs(scene.gravity[2])
    samples = []
    with open(contacts) as f:
        for line, (t, links) in zip(f, rows.items()):
            con = json.loads(line)
            assert abs(con["t"] - float(t)) < 1e-9, (con["t"], t)
            fn = sum(float(np.dot(c["force"], c["normal"])) for c in con["contacts"])
            depth = max([c["depth"] for c in con["contacts"]], default=0.0)
            other = {n.split("/", 1)[-1] for c in con["contacts"] for n in (c["a"], c["b"])} - set(scene.feet) - {scene.ground_name}
            samples.append(dict(t=float(t), base=links[base_name], feet=np.array([links[n] for n in feet]),
                                fn=fn / weight, depth=depth, other=other))
    assert len(samples) == len(rows)
    return figures(scene, samples), float(samples[-1]["base"][2])


def figures(scene, samples):
    start = min(WINDOW_START, scene.duration / 2)
    win = [s for s in samples if s["t"] >= start - 1e-9]
    base0, feet0 = win[0]["base"], win[0]["feet"]
    d = np.array([s["base"] - base0 for s in win])
    fn = np.array([s["fn"] for s in win])
    z = np.array([s["base"][2] for s in win])
    slide = max(float(np.max(np.linalg.norm((s["feet"] - feet0)[:, :2], axis=1))) for s in win)
    return {
        "window_s": [start, scene.duration],
        "drift_mm": float(np.max(np.linalg.norm(d, axis=1))) * 1e3,
        "drift_horizontal_mm": float(np.max(np.linalg.norm(d[:, :2], axis=1))) * 1e3,
        "drift_vertical_mm": float(np.max(np.abs(d[:, 2]))) * 1e3,
        "sink_mm": max(s["depth"] for s in win) * 1e3,
        "sink_whole_run_mm": max(s["depth"] for s in samples) * 1e3,
        "fn_over_weight_mean": float(fn.mean()),
        "fn_over_weight_max_deviation_pct": float(np.max(np.abs(fn - 1.0))) * 100,
        "slide_mm": slide * 1e3,
        "samples_with_non_foot_contact": int(sum(bool(s["other"]) for s in win)),
        "non_foot_links": sorted(set().union(*(s["other"] for s in win))),
        "base_z_min": float(z.min()), "base_z_max": float(z.max()),
        "base_z_start": float(samples[0]["base"][2]), "base_z_end": float(z[-1]),
    }


# ---------------------------------------------------------------------------------------------- speed

def tumble_time(scene, tumble, tmp, integrator):
    summary = os.path.join(tmp, "s.json")
    subprocess.run([tumble, "run", scene.path, "--quiet", "--summary", summary, "--out", os.path.join(tmp, "t.csv"),
                    "--sample-every", str(TIMING_SAMPLE_EVERY)] + scene.tumble_args(integrator), check=True)
    with open(summary) as f:
        s = json.load(f)
    assert s["steps"] == scene.nstep and s["stopped"] == "completed", s
    return s["wall_time_s"] / s["steps"]


class MujocoTimer:
    """All the steps from the initial state in one mujoco.rollout.rollout call, one MjData (one thread)."""

    def __init__(self, scene, integrator, cone):
        self.model, data = scene.mujoco_model(integrator, cone)
        spec = mujoco.mjtState.mjSTATE_FULLPHYSICS
        self.x0 = np.empty((1, mujoco.mj_stateSize(self.model, spec)))
        mujoco.mj_getState(self.model, data, self.x0[0], spec)
        self.ctrl = np.ascontiguousarray(scene.ctrl[None, :, :])
        self.data = mujoco.MjData(self.model)
        self.nstep = scene.nstep
        self.state = np.empty((1, self.nstep, self.x0.shape[1]))

    def run(self):
        t0 = time.perf_counter()
        rollout.rollout(self.model, self.data, self.x0, self.ctrl, nstep=self.nstep, state=self.state)
        return (time.perf_counter() - t0) / self.nstep

    def base_z(self):
        return float(self.state[0, -1, 1 + 2])  # FULLPHYSICS: time, then qpos


# ---------------------------------------------------------------------------------------------- main

def med(x):
    x = np.asarray(x)
    return {"median": float(np.median(x)), "min": float(x.min()), "max": float(x.max())}


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    default_tumble = "/work/bin/tumble" if os.path.exists("/work/bin/tumble") else os.path.join(ROOT, "target", "release", "tumble")
    ap.add_argument("--tumble", default=default_tumble)
    ap.add_argument("--pairs", type=int, default=7)
    ap.add_argument("--json", default=None)
    ap.add_argument("--quick", action="store_true")
    args = ap.parse_args()
    pairs = 1 if args.quick else args.pairs
    duration = 1.0 if args.quick else None
    tumble = args.tumble
    scenes = [Scene(r, m, duration) for r in ROBOTS for m in MOTIONS]
    mj = f"MuJoCo {mujoco.__version__}"
    out = {"tumble": tumble, "mujoco": mujoco.__version__, "pairs": pairs, "quick": args.quick, "scenes": {}}

    with tempfile.TemporaryDirectory() as tmp:
        # ---- quality
        print(f"Quality: tumble ({tumble}) and {mj}; standing sampled every 10 steps, trotting every step")
        for sc in scenes:
            sc.mujoco_model("Euler", "pyramidal")  # sets root, feet, balanced
            sc.mass = sc.tumble_mass(tumble)
            res = {"balanced_links": sc.balanced, "feet": sc.feet, "root": sc.root, "mass_kg": sc.mass,
                   "mu": sc.mu, "quality": {}}
            for ti, mi in PAIRS:
                res["quality"][f"tumble {ti}"], _ = tumble_quality(sc, tumble, tmp, ti)
                for cone in CONES:
                    q, _, mass = mujoco_quality(sc, mi, cone)
                    assert abs(mass - sc.mass) < 1e-5 * sc.mass, (sc.key, mass, sc.mass)
                    res["quality"][f"MuJoCo {mi} {cone}"] = q
            out["scenes"][sc.key] = res
        w0 = min(WINDOW_START, scenes[0].duration / 2)
        print()
        print(f"Standing, over t in [{w0:g}, {scenes[0].duration:g}] s. drift: largest displacement of the base from t = {w0:g} s "
              "(3-D | horizontal | vertical);")
        print("sink: deepest penetration; Fn/W: sum of normal forces / weight, mean and largest |Fn/W - 1|; slide: "
              "largest horizontal move of a foot; nf: samples with a non-foot contact")
        hdr = "%-9s %-30s %9s %9s %9s %8s %8s %8s %9s %4s" % (
            "robot", "engine", "drift mm", "horiz mm", "vert mm", "sink mm", "Fn/W", "max dev%", "slide mm", "nf")
        print(hdr)
        for sc in scenes:
            if sc.motion != "stand":
                continue
            for name, q in out["scenes"][sc.key]["quality"].items():
                print("%-9s %-30s %9.3f %9.3f %9.3f %8.3f %8.4f %8.2f %9.3f %4d" % (
                    sc.robot_key, name, q["drift_mm"], q["drift_horizontal_mm"], q["drift_vertical_mm"], q["sink_mm"],
                    q["fn_over_weight_mean"], q["fn_over_weight_max_deviation_pct"], q["slide_mm"],
                    q["samples_with_non_foot_contact"]))
        print()
        print(f"Trotting, over t in [{w0:g}, {scenes[0].duration:g}] s: base height min and max, mean Fn/W, horizontal drift "
              "of the base, sink, non-foot contact samples")
        print("%-9s %-30s %9s %9s %8s %9s %8s %4s" % ("robot", "engine", "z min m", "z max m", "Fn/W", "horiz mm",
                                                      "sink mm", "nf"))
        for sc in scenes:
            if sc.motion != "trot":
                continue
            for name, q in out["scenes"][sc.key]["quality"].items():
                print("%-9s %-30s %9.4f %9.4f %8.4f %9.2f %8.3f %4d" % (
                    sc.robot_key, name, q["base_z_min"], q["base_z_max"], q["fn_over_weight_mean"],
                    q["drift_horizontal_mm"], q["sink_mm"], q["samples_with_non_foot_contact"]))
        for sc in scenes:
            for name, q in out["scenes"][sc.key]["quality"].items():
                if q["non_foot_links"]:
                    print(f"{sc.key}, {name}: contacts on links other than the feet: " + ", ".join(q["non_foot_links"]))
        print("restitution (tumble, max of the pair): " + ", ".join(f"{sc.key} {sc.restitution:g}" for sc in scenes)
              + "; MuJoCo has none (its contacts are damped springs, solref (0.02, 1): critically damped)")
        for sc in scenes:
            if sc.balanced and sc.motion == "stand":
                print(f"{sc.robot_key}: inertias balanced as tumble does: " + ", ".join(b[0] for b in sc.balanced))
        print(flush=True)

        # ---- speed
        variants = []  # (scene, label, fn) in the order of a round
        timers = {}
        for sc in scenes:
            for ti, mi in PAIRS:
                variants.append((sc, f"tumble {ti}", lambda sc=sc, ti=ti: tumble_time(sc, tumble, tmp, ti)))
                for cone in CONES:
                    t = MujocoTimer(sc, mi, cone)
                    t.run()  # warm up; the rollout ends where the stepped run did
                    zq = out["scenes"][sc.key]["quality"][f"MuJoCo {mi} {cone}"]["base_z_end"]
                    if abs(t.base_z() - zq) > 1e-9:
                        print(f"note: {sc.key} MuJoCo {mi} {cone}: rollout base z {t.base_z():.9f} vs stepped {zq:.9f}")
                    timers[(sc.key, mi, cone)] = t
                    variants.append((sc, f"MuJoCo {mi} {cone}", t.run))
        for sc in scenes:
            for ti, _ in PAIRS:
                tumble_time(sc, tumble, tmp, ti)  # warm up (page cache)
        times = {(sc.key, label): [] for sc, label, _ in variants}
        for k in range(pairs):
            order = variants[::-1] if k % 2 else variants
            for sc, label, fn in order:
                times[(sc.key, label)].append(min(fn() for _ in range(BEST)))
            print("round %d/%d (µs/step): " % (k + 1, pairs) + "  ".join(
                "%s %s %.1f" % (sc.key, label.replace("tumble ", "t-").replace("MuJoCo ", "mj-")
                                .replace("semi_implicit_euler", "sie").replace("pyramidal", "pyr").replace("elliptic", "ell"),
                                times[(sc.key, label)][-1] * 1e6)
                for sc, label, _ in variants), flush=True)

    print()
    print(f"Speed: µs per step, median of {pairs} interleaved rounds (best of {BEST} in each); "
          "ratio = tumble / MuJoCo within a round, median [min, max] over the rounds")
    print("%-9s %-6s %-26s %9s %10s %22s %10s %22s" % ("robot", "motion", "integrators (tumble / MuJoCo)", "tumble",
                                                      "MuJoCo pyr", "ratio", "MuJoCo ell", "ratio"))
    for sc in scenes:
        speed = {}
        for ti, mi in PAIRS:
            tu = np.array(times[(sc.key, f"tumble {ti}")]) * 1e6
            row = {"tumble_us": med(tu), "tumble_us_rounds": tu.tolist()}
            cells = []
            for cone in CONES:
                mu = np.array(times[(sc.key, f"MuJoCo {mi} {cone}")]) * 1e6
                r = tu / mu
                row[f"mujoco_{cone}_us"] = med(mu)
                row[f"mujoco_{cone}_us_rounds"] = mu.tolist()
                row[f"ratio_{cone}"] = med(r)
                cells.append("%10.1f %8.2f [%5.2f, %5.2f]" % (np.median(mu), np.median(r), r.min(), r.max()))
            speed[f"{ti} / {mi}"] = row
            print("%-9s %-6s %-26s %9.1f %s %s" % (sc.robot_key, sc.motion, f"{ti} / {mi}", np.median(tu), *cells))
        out["scenes"][sc.key]["speed"] = speed
    if args.json:
        with open(args.json, "w") as f:
            json.dump(out, f, indent=1)
        print(f"wrote {args.json}")


if __name__ == "__main__":
    main()
