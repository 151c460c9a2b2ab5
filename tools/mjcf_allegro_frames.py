#!/usr/bin/env python3
"""Where the Allegro hand's mass matrix differs from MuJoCo's (docs/mjcf.md, "Not reached").

Usage (from the repository root, with mujoco, numpy and trimesh in a virtualenv):

    venv/bin/python tools/mjcf_allegro_frames.py

The Allegro hand (../shared/menagerie/wonik_allegro/right_hand.xml) has no <inertial>: each body's
inertia comes from one mesh geom (MuJoCo's legacy mesh inertia; the collision primitives have
mass 0). The script

1. computes each mesh's tensor exactly as tumble does (multibody::mjcf::mesh_inertia: pyramids from
   the face centroid, |volume| per triangle), places it in its body, and compares it with MuJoCo's
   compiled body_inertia / body_iquat: mass, centre of mass and principal moments agree to round-off,
   the principal frame does not (the residual off-diagonal of the exact tensor in MuJoCo's frame);
2. replaces every body's inertia frame in MuJoCo's compiled model by the exact principal frame
   (numpy eigh) and recomputes mj_fullM, qacc and qfrc_bias at the fixture's states
   (crates/tumble/tests/fixtures/mjcf/allegro_right.json): the change is the whole gap between
   tumble's figures and MuJoCo's.
"""
import json
import os
import sys

import mujoco
import numpy as np
import trimesh

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.normpath(os.path.join(HERE, ".."))
XML = os.path.normpath(os.path.join(ROOT, "..", "shared", "menagerie", "wonik_allegro", "right_hand.xml"))
FIXTURE = os.path.join(ROOT, "crates", "tumble", "tests", "fixtures", "mjcf", "allegro_right.json")
sys.path.insert(0, HERE)
from mjcf_fixtures import DISABLE  # noqa: E402


def quat_to_mat(q):
    m = np.zeros(9)
    mujoco.mju_quat2Mat(m, np.asarray(q, dtype=float))
    return m.reshape(3, 3)


def mat_to_quat(r):
    q = np.zeros(4)
    mujoco.mju_mat2Quat(q, np.ascontiguousarray(r).flatten())
    return q


def legacy_mesh_inertia(path, scale):
    """Volume, centre of mass and inertia per unit density about it (mesh axes)."""
    mesh = trimesh.load(path, process=False)
    tri = np.asarray(mesh.vertices, dtype=np.float64)[np.asarray(mesh.faces)] * scale

    def faces(t):
        cross = np.cross(t[:, 1] - t[:, 0], t[:, 2] - t[:, 0])
        twice_area = np.linalg.norm(cross, axis=1)
        normal = np.where(twice_area[:, None] > 0, cross / np.where(twice_area > 0, twice_area, 1)[:, None], 0)
        return 0.5 * twice_area, normal, t.sum(axis=1) / 3

    area, normal, centre = faces(tri)
    face_centroid = (area[:, None] * centre).sum(0) / area.sum()
    volume = np.abs(((centre - face_centroid) * normal).sum(1) * area / 3)
    com = (volume[:, None] * (0.75 * centre + 0.25 * face_centroid)).sum(0) / volume.sum()
    x = tri - com
    area, normal, centre = faces(x)
    volume = np.abs((centre * normal).sum(1) * area / 3)
    second = np.zeros((3, 3))
    for r in range(3):
        for s in range(3):
            acc = 2 * (x[:, :, r] * x[:, :, s]).sum(1)
            for i in range(3):
                for j in range(i + 1, 3):
                    acc += x[:, i, r] * x[:, j, s] + x[:, i, s] * x[:, j, r]
            second[r, s] = (volume / 20 * acc).sum()
    return volume.sum(), com, np.trace(second) * np.eye(3) - second


def main():
    m = mujoco.MjModel.from_xml_path(XML)
    spec = mujoco.MjSpec.from_file(XML)
    meshdir = os.path.join(os.path.dirname(XML), spec.meshdir)
    exact = mujoco.MjModel.from_xml_path(XML)
    print(f"{'body':14s} {'mass err':>9s} {'com err':>9s} {'moments err':>11s} {'off-diag in MuJoCo frame':>25s}")
    for b in range(1, m.nbody):
        body = spec.body(m.body(b).name)
        meshes = [g for g in body.geoms if g.type == mujoco.mjtGeom.mjGEOM_MESH and g.group <= 5]
        assert len(meshes) == 1, m.body(b).name
        g = meshes[0]
        mesh = spec.mesh(g.meshname)
        volume, com, unit = legacy_mesh_inertia(os.path.join(meshdir, mesh.file), np.asarray(mesh.scale))
        rot = quat_to_mat(np.asarray(g.quat) / np.linalg.norm(g.quat))
        mass = g.density * volume
        tensor = g.density * rot @ unit @ rot.T
        centre = np.asarray(g.pos) + rot @ com
        moments, axes = np.linalg.eigh(tensor)
        moments, axes = moments[::-1], axes[:, ::-1]
        if np.linalg.det(axes) < 0:
            axes[:, 2] *= -1
        in_mujoco_frame = quat_to_mat(m.body_iquat[b]).T @ tensor @ quat_to_mat(m.body_iquat[b])
        off = np.abs(in_mujoco_frame - np.diag(np.diag(in_mujoco_frame))).max() / moments[0]
        print(f"{m.body(b).name:14s} {abs(mass - m.body_mass[b]) / mass:9.1e} "
              f"{np.abs(centre - m.body_ipos[b]).max():9.1e} "
              f"{np.abs(np.sort(moments) - np.sort(m.body_inertia[b])).max() / moments[0]:11.1e} {off:25.1e}")
        exact.body_inertia[b] = moments
        exact.body_iquat[b] = mat_to_quat(axes)
    m.opt.disableflags |= DISABLE
    exact.opt.disableflags |= DISABLE
    fixture = json.load(open(FIXTURE))
    rel = lambda a, b: np.abs(a - b).max() / np.abs(b).max()
    for k, s in enumerate(fixture["states"]):
        out = []
        for model in (m, exact):
            d = mujoco.MjData(model)
            d.qpos[:], d.qvel[:] = s["qpos"], s["qvel"]
            mujoco.mj_forward(model, d)
            full = np.zeros((model.nv, model.nv))
            mujoco.mj_fullM(model, d, full)
            out.append((full, d.qacc.copy(), d.qfrc_bias.copy()))
        print(f"state {k}: MuJoCo with exact inertia frames against MuJoCo as compiled: "
              f"M {rel(out[1][0], out[0][0]):.1e}, qacc {rel(out[1][1], out[0][1]):.1e}, bias {rel(out[1][2], out[0][2]):.1e}")


if __name__ == "__main__":
    main()
