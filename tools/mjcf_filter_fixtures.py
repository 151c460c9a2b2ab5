"""MuJoCo's contact filter on small models whose geoms all overlap at the origin: every pair that
MuJoCo reports as a contact after mj_forward is a pair its filter allows (contype/conaffinity, one
weld body, parent and child, <exclude>). Writes crates/tumble/tests/fixtures/mjcf/filter/*.xml and
filter.json ({model: [[geom, geom], ...]}), read by crates/tumble/tests/mjcf_world.rs.

    /work/venv/bin/python tools/mjcf_filter_fixtures.py
"""
import json
import pathlib

import mujoco

OUT = pathlib.Path(__file__).resolve().parent.parent / "crates/tumble/tests/fixtures/mjcf/filter"

CHAIN = """<mujoco model="{name}">
  <worldbody>
    <geom name="ground" type="sphere" size="0.5"/>
    <body name="A">
      <joint name="hA" type="hinge"/>
      <geom name="a" type="sphere" size="0.5" {a}/>
      <body name="W">
        <geom name="w" type="sphere" size="0.5" {w}/>
        <body name="C">
          <joint name="hC" type="hinge"/>
          <joint name="sC" type="slide"/>
          <geom name="c" type="sphere" size="0.5" {c}/>
          <body name="D">
            <joint name="hD" type="hinge"/>
            <geom name="d" type="sphere" size="0.5" {d}/>
          </body>
        </body>
      </body>
    </body>
    <body name="F">
      <freejoint/>
      <geom name="f" type="sphere" size="0.5" {f}/>
      <geom name="f2" type="box" size="0.2 0.2 0.2" {f}/>
    </body>
  </worldbody>
  {extra}
</mujoco>
"""

MODELS = {
    "chain": dict(a="", w="", c="", d="", f="", extra=""),
    "chain_exclude": dict(
        a="", w="", c="", d="", f="",
        extra='<contact><exclude body1="W" body2="D"/><exclude body1="F" body2="world"/></contact>',
    ),
    "chain_masks": dict(
        a='contype="2" conaffinity="0"',
        w='contype="0" conaffinity="2"',
        c='contype="4" conaffinity="4"',
        d='contype="1" conaffinity="0"',
        f='contype="2" conaffinity="1"',
        extra="",
    ),
}


def main():
    OUT.mkdir(parents=True, exist_ok=True)
    pairs = {}
    for name, parts in MODELS.items():
        xml = CHAIN.format(name=name, **parts)
        (OUT / f"{name}.xml").write_text(xml)
        m = mujoco.MjModel.from_xml_string(xml)
        d = mujoco.MjData(m)
        mujoco.mj_forward(m, d)
        found = sorted({tuple(sorted((m.geom(c.geom1).name, m.geom(c.geom2).name))) for c in d.contact[: d.ncon]})
        pairs[name] = [list(p) for p in found]
        print(name, found)
    pairs["mujoco"] = mujoco.__version__
    (OUT / "filter.json").write_text(json.dumps(pairs, indent=1) + "\n")


if __name__ == "__main__":
    main()
