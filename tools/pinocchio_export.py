#!/usr/bin/env python3
"""Writes a Pinocchio model as plain text for tools/pinocchio_bench.cpp.

    python tools/pinocchio_export.py ROBOT.urdf [--floating] > ROBOT.pinmodel

One line per joint, in Pinocchio's order: its type (Pinocchio's short name, so the benchmark rebuilds
the same specialised joints), parent joint index, placement in the parent (translation, then the
rotation row by row), axis (for unaligned joints, else 0 0 0), the body's mass, centre of mass and
rotational inertia about it (xx xy xz yy yz zz), and the name. The benchmark then needs only
Pinocchio's headers, none of its compiled libraries.
"""
import sys

import pinocchio as pin


def main():
    path = sys.argv[1]
    floating = "--floating" in sys.argv[2:]
    model = pin.buildModelFromUrdf(path, pin.JointModelFreeFlyer()) if floating else pin.buildModelFromUrdf(path)
    for jid in range(1, model.njoints):
        j = model.joints[jid]
        kind = j.shortname()
        m = model.jointPlacements[jid]
        axis = list(j.axis) if hasattr(j, "axis") else [0.0, 0.0, 0.0]
        inertia = model.inertias[jid]
        i = inertia.inertia
        fields = [kind, str(model.parents[jid])]
        fields += [repr(float(x)) for x in m.translation]
        fields += [repr(float(m.rotation[r, c])) for r in range(3) for c in range(3)]
        fields += [repr(float(x)) for x in axis]
        fields += [repr(float(inertia.mass))] + [repr(float(x)) for x in inertia.lever]
        fields += [repr(float(i[0, 0])), repr(float(i[0, 1])), repr(float(i[0, 2])), repr(float(i[1, 1])),
                   repr(float(i[1, 2])), repr(float(i[2, 2]))]
        fields.append(model.names[jid])
        print(" ".join(fields))


if __name__ == "__main__":
    main()
