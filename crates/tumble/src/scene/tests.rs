//! Unit tests of the scene loader.
use super::*;

#[test]
fn scratch() {
    let deep = format!("version = 1\na = {}{}\n", "[".repeat(100000), "]".repeat(100000));
    let cases = [
        "version = 1\n[[body]]\nname = \"a\"\nmass = 1e400\n".to_string(),
        "version = 1\n[[body]]\nname = \"a\"\nmass = 1.0\nmass = 2.0\n".to_string(),
        "version = 1\n[[body]]\nname = \"a\"\ninertia = 5\n".to_string(),
        "version = 1\n[[grid]]\ncount = [1e5, 1e5, 100]\n".to_string(),
        "version = 1\n[[grid]]\ncount = [-1, 1, 1]\n".to_string(),
        "version = 1\n[[grid]]\ncount = [1, 1, 1]\n".to_string(),
        "version = 1\nbodies = []\n".to_string(),
        "version = 1\n[[body]]\nname = \"a\"\nmass=1.0\nshape = {type = \"sphere\", raduis = 1.0}\n".to_string(),
        deep,
    ];
    for c in &cases {
        match from_str(c, "x.toml", Format::Toml) {
            Ok(s) => println!("OK {:?}\n", s.warnings),
            Err(e) => println!("{}\n", &e.to_string()[..e.to_string().len().min(600)]),
        }
    }
    let jdeep = "[".repeat(100000);
    let j = [
        "\u{feff}{\"version\":1}",
        "{\"version\":1, // c\n}",
        &jdeep,
        "{\"version\":1,\"version\":1}",
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
}
