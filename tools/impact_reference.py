#!/usr/bin/env python3
"""Reference impulses of frictional collisions whose slip curves (the slip direction turns during
the impact, so no closed form exists), for `crates/tumble/tests/contact_impact.rs`.

    python3 -m venv venv && venv/bin/pip install numpy scipy
    venv/bin/python tools/impact_reference.py

Inputs: the 80 foot landings of `crates/tumble/tests/fixtures/impact/landings.txt` (collision
matrices of quadruped feet met in the trotting scenes) and 80 random cases (seeded): a random
symmetric positive definite `K`, an approaching contact velocity, `mu`, `e`. Each is integrated
through the impact as Mirtich 1996 §4 and Stronge's law define it, with the normal impulse `p_z`
as the independent variable: sliding `du/dp_z = K (−mu u_t/|u_t|, 1)` by scipy's DOP853 at rtol
1e-13 (an order-8 method with its own error control, nothing shared with tumble's integrator),
the end of compression (`u_z = 0`), the slip's stop (`|u_t|` below 1e-13 of the velocity scale)
and the end of restitution (`W = (1 − e²) W_c`) as located events; after a stop, stable sticking
(`|ξ| ≤ mu`, `K_tt ξ = −k_tn`) in closed form. Cases whose sticking is not stable (sliding resumes
along a diverging ray) or that could jam (`k_zz ≤ mu |k_zt|`) are left out.

Writes `crates/tumble/tests/fixtures/impact/curved_slides.json`: per case `k` (contact frame
(t1, t2, n), rows, 1/kg), `u0` (m/s), `mu`, `e`, and `p` (N·s, contact frame), with the
reference's own spread (the same integration at rtol 1e-11) as `spread`.
"""
import json
import os

import numpy as np
from scipy.integrate import solve_ivp

ROOT = os.path.normpath(os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
DIR = os.path.join(ROOT, "crates", "tumble", "tests", "fixtures", "impact")


def reference(k, u0, mu, e, rtol):
    """The impulse (p_t1, p_t2, p_z) in the contact frame; None for the cases left out."""
    y = np.array([u0[0], u0[1], u0[2], 0.0, 0.0, 0.0])
    p_z, compressing, w_c = 0.0, True, 0.0
    scale = abs(u0[2]) + np.hypot(u0[0], u0[1])

    def slope(_, y):
        ut = y[:2]
        f = -mu * ut / np.hypot(*ut)
        du = k @ np.array([f[0], f[1], 1.0])
        return [du[0], du[1], du[2], f[0], f[1], y[2]]

    def stick(y, p_z, compressing, w_c):
        a, b, c, d = k[0, 0], k[0, 1], k[1, 0], k[1, 1]
        det = a * d - b * c
        xi = np.array([(d * -k[0, 2] - b * -k[1, 2]) / det, (a * -k[1, 2] - c * -k[0, 2]) / det])
        if np.hypot(*xi) > mu:
            return None
        du = k @ np.array([xi[0], xi[1], 1.0])
        dz = du[2]
        y = y.copy()

        def advance(dp):
            nonlocal p_z
            y[5] += y[2] * dp + 0.5 * dz * dp * dp
            y[0:3] += du * dp
            y[3:5] += xi * dp
            p_z += dp

        if compressing:
            advance(max(-y[2] / dz, 0.0))
            y[2] = 0.0
            w_c = y[5]
        w_end = (1.0 - e * e) * w_c
        disc = max(y[2] ** 2 + 2.0 * dz * (w_end - y[5]), 0.0)
        advance(max((-y[2] + np.sqrt(disc)) / dz, 0.0))
        return np.array([y[3], y[4], p_z])

    if mu == 0.0 or np.hypot(u0[0], u0[1]) == 0.0:
        return None
    while True:
        if compressing:
            def phase(_, y):
                return y[2]
        else:
            def phase(_, y):
                return y[5] - (1.0 - e * e) * w_c
        phase.terminal, phase.direction = True, 1

        def stop(_, y):
            return np.hypot(y[0], y[1]) - 1e-13 * scale
        stop.terminal, stop.direction = True, -1
        s = solve_ivp(slope, (p_z, p_z + 1e3), y, method="DOP853", rtol=rtol, atol=1e-18, events=[phase, stop])
        y, p_z = s.y[:, -1].copy(), s.t[-1]
        if s.t_events[0].size:
            if compressing:
                compressing, w_c = False, y[5]
                continue
            return np.array([y[3], y[4], p_z])
        if not s.t_events[1].size:
            return None
        return stick(y, p_z, compressing, w_c)


def cases():
    with open(os.path.join(DIR, "landings.txt")) as f:
        for line in f:
            if line.startswith("#") or not line.strip():
                continue
            v = [float(x) for x in line.split()]
            yield np.array(v[0:9]).reshape(3, 3), np.array(v[9:12]), v[12], v[13], "landing"
    rng = np.random.default_rng(20261203)
    for _ in range(80):
        a = rng.normal(size=(3, 3))
        k = a @ a.T + 0.05 * np.eye(3)
        u0 = np.array([rng.normal(), rng.normal(), -rng.uniform(0.1, 3.0)])
        yield k, u0, float(rng.uniform(0.1, 1.5)), float(rng.uniform(0.0, 1.0)), "random"


def main():
    out = []
    for k, u0, mu, e, kind in cases():
        if k[2, 2] <= 1.05 * mu * np.hypot(k[2, 0], k[2, 1]):
            continue
        p = reference(k, u0, mu, e, 1e-13)
        if p is None:
            continue
        q = reference(k, u0, mu, e, 1e-11)
        out.append({"kind": kind, "k": k.flatten().tolist(), "u0": u0.tolist(), "mu": mu, "e": e,
                    "p": p.tolist(), "spread": float(np.linalg.norm(p - q) / np.linalg.norm(p))})
    with open(os.path.join(DIR, "curved_slides.json"), "w") as f:
        json.dump(out, f, indent=1)
    kinds = {k: sum(c["kind"] == k for c in out) for k in ("landing", "random")}
    print(f"{len(out)} cases ({kinds}); largest spread {max(c['spread'] for c in out):.1e}")


if __name__ == "__main__":
    main()
