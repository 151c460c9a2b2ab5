#!/usr/bin/env python3
"""The Gymnasium Ant and Humanoid dropped on their floor, in tumble and in MuJoCo, side by side:
under zero control and under a sinusoidal control.

    cargo build --release -p tumble-cli   # (not needed: the Python package is used)
    python3 -m venv venv && venv/bin/pip install mujoco gymnasium numpy crates/tumble-py
    venv/bin/python tools/mjcf_drop_compare.py [--seconds 4]

Both engines load the same file (gymnasium's ant.xml and humanoid.xml as committed under
crates/tumble/tests/fixtures/mjcf/gymnasium/): tumble by `tumble.Model.from_mjcf` (its `<option>`:
the same dt, gravity and integrator; its floor plane; the actuators driven by `World.set_ctrl`),
MuJoCo by `MjModel.from_xml_path`, both from `qpos0` (the torso where the file puts it). The
control is zero, or `ctrl_i(t) = 0.5 sin(2π · 1 Hz · t + i)` on actuator `i`, held over each step
in both. Printed every half second: the torso's height, the sum of the contacts' normal forces on
the robot (tumble: `World.contacts()`; MuJoCo: `mj_contactForce`), the deepest penetration, and
tumble's mechanical energy. Trajectories are expected to differ once contacts act (MuJoCo's
contacts are soft, tumble's are impulses with Coulomb friction); the figures show how they compare.

Checks (tumble, zero control): no NaN, the deepest penetration under 2 mm over the whole run (the
landing included), and the mechanical energy never above its lowest value so far (a passive system
only loses energy), to 1e-6 J: the robot's `energy()` plus what the springs of its soft contact and
limit rows store (`contact_elastic_energy()`), which they give back as an overlap or an overshoot
shrinks.
"""
import argparse
import math
import os
import sys

import mujoco
import numpy as np

import tumble

ROOT = os.path.normpath(os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
MODELS = os.path.join(ROOT, "crates", "tumble", "tests", "fixtures", "mjcf", "gymnasium")


def control(t, n, sinus):
    if not sinus:
        return np.zeros(n)
    return 0.5 * np.sin(2.0 * math.pi * t + np.arange(n))


def run(name, seconds, sinus):
    path = os.path.join(MODELS, name + ".xml")
    tm = tumble.Model.from_mjcf(path)
    tw = tumble.World(tm)
    mm = mujoco.MjModel.from_xml_path(path)
    md = mujoco.MjData(mm)
    mujoco.mj_forward(mm, md)
    assert abs(tm.dt - mm.opt.timestep) < 1e-15, (tm.dt, mm.opt.timestep)
    n_act = len(tm.actuator_names())
    assert n_act == mm.nu
    steps = int(round(seconds / tm.dt))
    every = int(round(0.5 / tm.dt))
    e0 = tw.energy()
    e_min = e0 + tw.contact_elastic_energy()
    worst = {"nan": False, "energy_rise": 0.0, "depth": 0.0}
    weight = float(np.sum(mm.body_mass)) * 9.81
    print(f"\n{name}, {'sinusoidal' if sinus else 'zero'} control, dt = {tm.dt} s, {tm.integrator} / "
          f"{['Euler', 'RK4', 'implicit', 'implicitfast'][mm.opt.integrator]}, weight {weight:.1f} N")
    print(f"{'t (s)':>6} {'z tumble':>9} {'z MuJoCo':>9} {'Fn tumble':>10} {'Fn MuJoCo':>10} "
          f"{'depth tumble':>13} {'depth MuJoCo':>13} {'E tumble − E0':>14}")
    force = np.zeros(6)
    for k in range(1, steps + 1):
        t = (k - 1) * tm.dt
        u = control(t, n_act, sinus)
        if n_act:
            tw.set_ctrl(0, u)
        md.ctrl[:] = u
        tw.step()
        mujoco.mj_step(mm, md)
        x = tw.state()
        if not np.all(np.isfinite(x)):
            worst["nan"] = True
            break
        contacts = tw.contacts()
        depth_t = max([c["depth"] for c in contacts], default=0.0)
        worst["depth"] = max(worst["depth"], depth_t)
        if not sinus:
            # a rise above the lowest energy so far: energy gained
            e = tw.energy() + tw.contact_elastic_energy()
            worst["energy_rise"] = max(worst["energy_rise"], e - e_min)
            e_min = min(e_min, e)
        if k % every == 0:
            fn_t = sum(np.dot(c["force"], c["normal"]) for c in contacts)
            fn_m, depth_m = 0.0, 0.0
            for i in range(md.ncon):
                mujoco.mj_contactForce(mm, md, i, force)
                fn_m += force[0]
                depth_m = max(depth_m, -md.contact[i].dist)
            print(f"{k * tm.dt:6.2f} {x[2]:9.4f} {md.qpos[2]:9.4f} {fn_t:10.1f} {fn_m:10.1f} "
                  f"{depth_t * 1e3:10.3f} mm {depth_m * 1e3:10.3f} mm {tw.energy() - e0:14.3e}")
    return worst


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--seconds", type=float, default=4.0)
    args = ap.parse_args()
    ok = True
    for name in ("ant", "humanoid"):
        for sinus in (False, True):
            w = run(name, args.seconds, sinus)
            if not sinus:
                good = not w["nan"] and w["depth"] < 2e-3 and w["energy_rise"] <= 1e-6
                ok &= good
                print(f"  checks: NaN {w['nan']}, deepest over the run {w['depth'] * 1e3:.3f} mm (< 2), "
                      f"largest energy gain {w['energy_rise']:.2e} J (≤ 1e-6): {'ok' if good else 'FAILED'}")
    sys.exit(0 if ok else 1)


if __name__ == "__main__":
    main()
