#!/usr/bin/env python3
"""How MuJoCo 4.0.1 compiles the Allegro hand's mesh inertia frames (docs/mjcf.md, "Agreement").

Usage (from the repository root, with mujoco, numpy and trimesh in a virtualenv):

    venv/bin/python tools/mjcf_allegro_frames.py

The Allegro hand (../shared/menagerie/wonik_allegro/right_hand.xml) has no <inertial>: each body's
inertia comes from one mesh geom (MuJoCo's legacy mesh inertia; the collision primitives have
mass 0). MuJoCo's compiler (mjCMesh::Process) turns each mesh to its principal axes with its 3x3
Jacobi eigen-solver (mjuu_eig3), which in 4.0.1 takes a relative tolerance; for meshes it is
called with 1e-7 (read from libmujoco.so.4.0.1: the constant loaded before the call in
mjCMesh::Process; the body and fullinertia call sites pass 4e-15). The solver rotates about the
largest off-diagonal of R^T I R until it is at most reltol * max|I_kl|. The geom gets R as its
frame and diag(R^T I R) as its moments, so MuJoCo's tensor is I less the off-diagonal left.
The script

1. computes each mesh's tensor exactly as tumble does (multibody::mjcf::mesh_inertia: pyramids from
   the face centroid, |volume| per triangle), runs that Jacobi solver on it (mujoco_eig3 below, a
   re-implementation), and compares the frame with MuJoCo's compiled mesh_quat, with
   mju_eig3Tol(..., 1e-7) from the library itself, and with the old solver in the public source
   (absolute 1e-12 stop and cosine test, which does not match 4.0.1);
2. places each body's mesh in its body and compares mass, centre of mass, body_iquat, body_inertia
   and the tensor R diag(d) R^T with MuJoCo's compiled model. It also prints the off-diagonal the
   exact tensor keeps in MuJoCo's frame;
3. replaces every body's inertia frame in MuJoCo's compiled model by the exact principal frame
   (numpy eigh) and recomputes mj_fullM, qacc and qfrc_bias at the fixture's states
   (crates/tumble/tests/fixtures/mjcf/allegro_right.json). That change (3e-10 in M) is what tumble
   was off by while it used the exact tensor; multibody::mjcf::mesh_inertia::mujoco_principal_tensor
   now makes the same truncation.
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


def mujoco_eig3(mat, reltol, old=False):
    """MuJoCo's 3x3 Jacobi eigen-solver as its compiler runs it: (diagonal, quaternion w x y z).

    Rotations about the largest off-diagonal element (ties: (0,1) only if strictly largest, then
    (0,2) if strictly larger than (1,2)), the smaller angle, accumulated in a quaternion; stop when
    that element is at most max(4e-15, reltol) * max|mat| (4.0.1), or, with old=True, as in the
    public source up to 3.12.0: below an absolute 1e-12, or when the rotation's cosine exceeds
    1 - 1e-12. The moments are then sorted in decreasing order by quarter turns (which do not
    change the tensor R diag(d) R^T).
    """
    mat = np.asarray(mat, dtype=float).reshape(3, 3)
    tol = 1e-12 if old else max(4e-15, reltol) * np.abs(mat).max()
    q = np.array([1.0, 0.0, 0.0, 0.0])
    for _ in range(500):
        r = quat_to_mat(q)
        d = r.T @ mat @ r
        a01, a02, a12 = abs(d[0, 1]), abs(d[0, 2]), abs(d[1, 2])
        i, j, k = (0, 1, 2) if a01 > a02 and a01 > a12 else (0, 2, 1) if a02 > a12 else (1, 2, 0)
        b = d[i, j]
        if (abs(b) < tol) if old else (abs(b) <= tol):
            break
        tau = (d[j, j] - d[i, i]) / (2 * b)
        root = np.sqrt(1 + tau * tau)
        t = 1 / (tau + root) if tau >= 0 else -1 / (root - tau)
        if old and 1 / np.sqrt(1 + t * t) > 1 - 1e-12:
            break
        # new axes e_i' = c e_i - s e_j: a turn by -theta about e_k, +theta when (i, j, k) = (0, 2, 1)
        h = t / (1 + np.sqrt(1 + t * t))
        c = 1 / np.sqrt(1 + h * h)
        turn = np.array([c, 0.0, 0.0, 0.0])
        turn[k + 1] = (h if k == 1 else -h) * c
        mujoco.mju_mulQuat(q, q.copy(), turn)
        q /= np.linalg.norm(q)
    # moments in decreasing order (bubble sort over the pairs (0,1), (1,2), (0,1)), each swap a
    # quarter turn about the third axis; below the tolerance they count as equal
    moments = np.diag(d).copy()
    sort_tol = 1e-12 if old else max(1e-12, reltol) * np.abs(mat).max()
    for j in (0, 1, 0):
        if moments[j] + sort_tol < moments[j + 1]:
            moments[[j, j + 1]] = moments[[j + 1, j]]
            turn = np.zeros(4)
            turn[0] = turn[(j + 2) % 3 + 1] = np.sqrt(0.5)
            mujoco.mju_mulQuat(q, q.copy(), turn)
            q /= np.linalg.norm(q)
    return moments, q


def library_eig3tol(mat, reltol):
    """mju_eig3Tol of libmujoco itself (exported), or None if it is not there."""
    import ctypes
    import glob
    libs = glob.glob(os.path.join(os.path.dirname(mujoco.__file__), "libmujoco.so*"))
    if not libs:
        return None
    lib = ctypes.CDLL(libs[0])
    if not hasattr(lib, "mju_eig3Tol"):
        return None
    w, v, q = (ctypes.c_double * 3)(), (ctypes.c_double * 9)(), (ctypes.c_double * 4)()
    lib.mju_eig3Tol(w, v, q, (ctypes.c_double * 9)(*np.asarray(mat, float).flatten()), ctypes.c_double(reltol))
    return np.array(list(q))


def same_quat(a, b):
    return np.abs(np.sign(np.dot(a, b)) * np.asarray(a) - np.asarray(b)).max()


def main():
    m = mujoco.MjModel.from_xml_path(XML)
    spec = mujoco.MjSpec.from_file(XML)
    meshdir = os.path.join(os.path.dirname(XML), spec.meshdir)
    exact = mujoco.MjModel.from_xml_path(XML)
    unit_of = {}
    print("1. mesh frames against MuJoCo's mesh_quat (reltol 1e-7; library mju_eig3Tol; old public solver)")
    for i in range(m.nmesh):
        mesh = spec.meshes[i]
        volume, com, unit = legacy_mesh_inertia(os.path.join(meshdir, mesh.file), np.asarray(mesh.scale))
        unit_of[mesh.name] = (volume, com, unit)
        _, q = mujoco_eig3(unit, 1e-7)
        lib = library_eig3tol(unit, 1e-7)
        _, q_old = mujoco_eig3(unit, 0, old=True)
        print(f"  {m.mesh(i).name:16s} mesh_quat {same_quat(q, m.mesh_quat[i]):8.1e}  "
              f"mesh_pos {np.abs(com - m.mesh_pos[i]).max():8.1e}  "
              f"vs mju_eig3Tol {same_quat(q, lib) if lib is not None else float('nan'):8.1e}  "
              f"old solver {same_quat(q_old, m.mesh_quat[i]):8.1e}")
    print("2. bodies against MuJoCo's compiled body_* (relative to the largest moment)")
    print(f"  {'body':14s} {'mass':>8s} {'com':>8s} {'iquat':>8s} {'inertia':>8s} {'tensor':>8s} {'exact off-diag':>15s}")
    for b in range(1, m.nbody):
        body = spec.body(m.body(b).name)
        meshes = [g for g in body.geoms if g.type == mujoco.mjtGeom.mjGEOM_MESH and g.group <= 5]
        assert len(meshes) == 1, m.body(b).name
        g = meshes[0]
        volume, com, unit = unit_of[g.meshname]
        moments_unit, q = mujoco_eig3(unit, 1e-7)
        geom_quat = np.asarray(g.quat, float) / np.linalg.norm(g.quat)
        iquat = np.zeros(4)
        mujoco.mju_mulQuat(iquat, geom_quat, q)
        rot = quat_to_mat(geom_quat)
        mass = g.density * volume
        moments = g.density * moments_unit
        centre = np.asarray(g.pos) + rot @ com
        frame = quat_to_mat(iquat)
        tensor = frame @ np.diag(moments) @ frame.T
        mj_frame = quat_to_mat(m.body_iquat[b])
        mj_tensor = mj_frame @ np.diag(m.body_inertia[b]) @ mj_frame.T
        exact_tensor = g.density * rot @ unit @ rot.T
        in_mujoco_frame = mj_frame.T @ exact_tensor @ mj_frame
        big = moments.max()
        off = np.abs(in_mujoco_frame - np.diag(np.diag(in_mujoco_frame))).max() / big
        print(f"  {m.body(b).name:14s} {abs(mass - m.body_mass[b]) / mass:8.1e} "
              f"{np.abs(centre - m.body_ipos[b]).max():8.1e} {same_quat(iquat, m.body_iquat[b]):8.1e} "
              f"{np.abs(moments - m.body_inertia[b]).max() / big:8.1e} "
              f"{np.abs(tensor - mj_tensor).max() / big:8.1e} {off:15.1e}")
        w, axes = np.linalg.eigh(exact_tensor)
        w, axes = w[::-1], axes[:, ::-1]
        if np.linalg.det(axes) < 0:
            axes[:, 2] *= -1
        exact.body_inertia[b] = w
        exact.body_iquat[b] = mat_to_quat(axes)
    print("3. MuJoCo with exact inertia frames against MuJoCo as compiled")
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
        print(f"  state {k}: "
              f"M {rel(out[1][0], out[0][0]):.1e}, qacc {rel(out[1][1], out[0][1]):.1e}, bias {rel(out[1][2], out[0][2]):.1e}")


if __name__ == "__main__":
    main()
