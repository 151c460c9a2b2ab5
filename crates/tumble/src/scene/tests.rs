//! Unit tests of the scene loader.
use super::*;

#[test]
fn scratch() {
    let cases = [
        "version = 1\n[[body]]\nname = \"a\"\nmass = \"heavy\"\n",
        "version = 1\n[[body]]\nname = \"a\"\nmas = 1.0\n",
        "version = 1\n[[body]]\nname = \"a\"\nmass = nan\ninertia=[1,1,1]\n",
        "version = 1\n[[body]]\nname = \"a\"\n",
        "version = 1\n[[body]]\nname = \"a\"\nmass = 1.0\nshape = { type = \"box\", half_extents = [1, 2] }\n",
        "version = 1\n[[bodies]\n",
        "version = 1\n[world]\ngravtiy = [0,0,0]\n",
        "version = 1\n[world]\nintegrator = \"rk5\"\n",
        "version = 1\n[world]\ndt = 0.0\n",
        "version = 1\n[[body]]\nname = \"a\"\nmass=1.0\ninertia=[1,1,5]\n",
        "version = 1\n[[body]]\nname = \"a\"\nmass=1.0\ninertia=[1,1,1]\n[[body]]\nname = \"a\"\nmass=1.0\ninertia=[1,1,1]\n",
        "version = 1\n[[body]]\nname = \"a\"\nmass=1.0\ninertia=[1,1,1]\norientation=[1,0,0,0.1]\n",
        "version = 1\n[[grid]]\ncount=[100000,100000,100]\nspacing=[1,1,1]\n[grid.body]\nname=\"r\"\nmass=1.0\ninertia=[1,1,1]\n",
        "version = 1\n[[body]]\nname = \"a\"\nmass=1.0\nx=2\ninertia=[1,1,1]\n[body.shape]\ntype=\"sphere\"\nradius=-1\n",
    ];
    for c in cases {
        match from_str(c, "x.toml", Format::Toml) {
            Ok(s) => println!("OK {:?}\n", s.warnings),
            Err(e) => println!("{e}\n"),
        }
    }
    let j = [
        "{\"version\":1,\"body\":[{\"name\":\"a\",\"mass\":\"heavy\"}]}",
        "{\"version\":1,\"body\":[{\"name\":\"a\",\"mas\":1}]}",
        "{\"version\":1,\"body\":[{\"name\":\"a\",\"mass\":-1, \"inertia\":[1,1,1]}]}",
        "{\"version\":1,}",
    ];
    for c in j {
        match from_str(c, "x.json", Format::Json) {
            Ok(s) => println!("OK {:?}\n", s.warnings),
            Err(e) => println!("{e}\n"),
        }
    }
    println!("{}", demo().describe());
}
