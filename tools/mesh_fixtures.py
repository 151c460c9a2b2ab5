#!/usr/bin/env python3
"""Writes the mesh fixtures of tumble's tests: meshes, malformed meshes, and trimesh's mass properties.

Usage (from the repository root, in a virtualenv with `pip install trimesh numpy scipy`):

    python3 tools/mesh_fixtures.py

Writes crates/tumble/tests/fixtures/meshes/. Every mesh file is written here with full precision
(OBJ: shortest round-trip decimal; STL: single precision, as the format holds), then read back with
trimesh, and trimesh's mass properties *of the file as read* go to trimesh_expected.json, so both
tools see the same numbers. Deterministic: a fixed seed; re-running rewrites the same bytes.
"""

import json
import struct
from pathlib import Path

import numpy as np
import trimesh

OUT = Path(__file__).resolve().parent.parent / "crates" / "tumble" / "tests" / "fixtures" / "meshes"


def rigid(mesh, angle, axis, offset):
    """The mesh rotated by `angle` (rad) about `axis`, then moved by `offset` (m)."""
    m = mesh.copy()
    m.apply_transform(trimesh.transformations.rotation_matrix(angle, axis))
    m.apply_translation(offset)
    return m


def write_obj(path, vertices, faces):
    with open(path, "w") as f:
        f.write("# written by tools/mesh_fixtures.py\n")
        for v in vertices:
            f.write("v {} {} {}\n".format(*(repr(float(x)) for x in v)))
        for t in faces:
            f.write("f {} {} {}\n".format(*(int(i) + 1 for i in t)))


def write_stl_binary(path, vertices, faces, header=b"tumble fixture"):
    tris = np.asarray(vertices, dtype=np.float32)[np.asarray(faces)]
    with open(path, "wb") as f:
        f.write(header.ljust(80, b"\0")[:80])
        f.write(struct.pack("<I", len(tris)))
        for t in tris:
            n = np.cross(t[1] - t[0], t[2] - t[0])
            f.write(struct.pack("<3f", *n))
            f.write(t.astype("<f4").tobytes())
            f.write(b"\0\0")


def write_stl_ascii(path, vertices, faces):
    tris = np.asarray(vertices, dtype=np.float32)[np.asarray(faces)]
    with open(path, "w") as f:
        f.write("solid fixture\n")
        for t in tris:
            f.write("  facet normal 0 0 0\n    outer loop\n")
            for v in t:
                # the shortest decimal of the single-precision value: reads back to it in f32 and f64
                f.write("      vertex {} {} {}\n".format(*(repr(float(x)) for x in v)))
            f.write("    endloop\n  endfacet\n")
        f.write("endsolid fixture\n")


def peers():
    """Meshes compared with trimesh: non-convex, off-origin, rotated, in every format."""
    rng = np.random.default_rng(20261121)
    meshes = {
        "torus.obj": rigid(trimesh.creation.torus(0.8, 0.25, 48, 24), 0.7, [1, 2, 3], [0.3, -1.2, 2.5]),
        "annulus.obj": rigid(trimesh.creation.annulus(0.3, 0.9, 0.4, sections=40), 1.1, [0, 1, 1], [5, 4, -3]),
        "capsule.stl": rigid(trimesh.creation.capsule(1.2, 0.35, count=[24, 24]), 0.4, [1, 0, 0], [0.1, 0.2, 0.3]),
        "box.stl": rigid(trimesh.creation.box([0.5, 1.0, 2.0]), 2.0, [1, -1, 0.5], [-0.7, 0.25, 1.5]),
        "hull_ascii.stl": trimesh.convex.convex_hull(rng.normal(size=(200, 3)) * [1.0, 0.6, 0.3] + [0.2, 0.1, -0.4]),
    }
    expected = {}
    for name, mesh in meshes.items():
        assert mesh.is_watertight and mesh.is_winding_consistent and mesh.volume > 0, name
        path = OUT / name
        if name.endswith(".obj"):
            write_obj(path, mesh.vertices, mesh.faces)
        elif "ascii" in name:
            write_stl_ascii(path, mesh.vertices, mesh.faces)
        else:
            write_stl_binary(path, mesh.vertices, mesh.faces)
        read = trimesh.load(path, force="mesh")
        assert read.is_watertight and read.is_winding_consistent, name
        p = read.mass_properties
        expected[name] = {
            "triangles": int(len(read.faces)),
            "volume": float(p["volume"]),
            "center_of_mass": [float(x) for x in p["center_mass"]],
            "inertia": [[float(x) for x in row] for row in p["inertia"]],
            "principal_moments": [float(x) for x in read.principal_inertia_components],
            "principal_axes": [[float(x) for x in row] for row in read.principal_inertia_vectors],
        }
    meta = {"density": 1.0, "trimesh": trimesh.__version__, "numpy": np.__version__}
    with open(OUT / "trimesh_expected.json", "w") as f:
        json.dump({"meta": meta, "meshes": expected}, f, indent=1)
        f.write("\n")


CUBE_V = [[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0], [0, 0, 1], [1, 0, 1], [1, 1, 1], [0, 1, 1]]
# outward, counter-clockwise seen from outside; the last two are the top face (z = 1)
CUBE_F = [[0, 2, 1], [0, 3, 2], [0, 1, 5], [0, 5, 4], [1, 2, 6], [1, 6, 5],
          [2, 3, 7], [2, 7, 6], [3, 0, 4], [3, 4, 7], [4, 5, 6], [4, 6, 7]]


def malformed():
    """Small files, one fault each (the tests name the fault they expect)."""
    write_obj(OUT / "cube.obj", CUBE_V, CUBE_F)
    write_obj(OUT / "open_box.obj", CUBE_V, CUBE_F[:-2])
    flipped = [list(t) for t in CUBE_F]
    flipped[4] = [flipped[4][0], flipped[4][2], flipped[4][1]]
    write_obj(OUT / "flipped_face.obj", CUBE_V, flipped)
    write_stl_ascii(OUT / "inside_out.stl", CUBE_V, [[t[0], t[2], t[1]] for t in CUBE_F])
    write_obj(OUT / "degenerate.obj", CUBE_V, CUBE_F + [[1, 1, 6]])
    text = (OUT / "cube.obj").read_text().replace("v 1.0 1.0 1.0\n", "v 1.0 nan 1.0\n")
    (OUT / "nan.obj").write_text(text)
    (OUT / "empty.stl").write_bytes(b"")
    (OUT / "empty.obj").write_bytes(b"")
    write_stl_binary(OUT / "cube.stl", CUBE_V, CUBE_F)
    (OUT / "truncated.stl").write_bytes((OUT / "cube.stl").read_bytes()[:-20])
    write_stl_binary(OUT / "solid_header.stl", CUBE_V, CUBE_F, header=b"solid exported by a CAD tool")
    (OUT / "bad_index.obj").write_text((OUT / "cube.obj").read_text() + "f 1 2 99\n")


if __name__ == "__main__":
    OUT.mkdir(parents=True, exist_ok=True)
    peers()
    malformed()
    print("wrote", OUT)
