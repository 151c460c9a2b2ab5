//! The replay in a real browser: headless Chromium (Debian's `chromium`, installed by `.ci/run`)
//! opens the page `tumble run --view` wrote, with no network.
//!
//! - the page's script ran to the end (the DOM says `data-ready="1"`, no `data-error`);
//! - screenshots at two times (the `#t=` fragment): the bodies are drawn (the middle of the scene is
//!   not the background colour) and they moved (the two pictures differ there);
//! - a trajectory cut short is replayed as far as it goes, with a note;
//! - robots (the double pendulum and the Panda, links drawn as their inertia boxes): drawn, and moved
//!   between two times;
//! - the page asks for no resource: the browser is given a proxy (a listener in this test) that sees
//!   every request for the network; no request is the page's. Chromium's own housekeeping requests
//!   (its update and time services, on Google's domains) are told apart by host. A control page with
//!   one external image shows that the listener sees a page's requests.
//!
//! Without Chromium the test fails, saying how to install it; `TUMBLE_SKIP_BROWSER=1` skips it with
//! a message. `TUMBLE_CHROMIUM` names another browser binary.

mod common;

use assert_cmd::prelude::*;
use common::tumble;
use std::io::{BufRead, BufReader, Read};
use std::net::TcpListener;
use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

/// The background colour of the scene (`gl.clearColor(0.114, 0.129, 0.149)`), sRGB 0..255.
const BACKGROUND: [u8; 3] = [29, 33, 38];
const WIDTH: u32 = 900;
const HEIGHT: u32 = 700;
/// Bar (36 px) and energy plot (150 px) under the scene.
const UNDER_SCENE: u32 = 186;

fn chromium() -> Option<PathBuf> {
    if let Some(path) = std::env::var_os("TUMBLE_CHROMIUM") {
        return Some(PathBuf::from(path));
    }
    let path = std::env::var_os("PATH").unwrap_or_default();
    ["chromium", "chromium-browser"]
        .iter()
        .flat_map(|name| std::env::split_paths(&path).map(move |dir| dir.join(name)))
        .find(|candidate| candidate.is_file())
}

/// Hosts of Chromium's own services (updates, time, accounts): requests to them are the browser's,
/// not the page's.
const BROWSER_SERVICE_DOMAINS: [&str; 5] =
    ["google.com", "googleapis.com", "gvt1.com", "gstatic.com", "googleusercontent.com"];

/// A proxy that records the first line of every request and answers none (every load fails).
/// Connections on which nothing is asked are not recorded.
struct Proxy {
    port: u16,
    requests: Arc<Mutex<Vec<String>>>,
}

impl Proxy {
    fn start() -> Proxy {
        let listener = TcpListener::bind("127.0.0.1:0").unwrap();
        let port = listener.local_addr().unwrap().port();
        let requests = Arc::new(Mutex::new(Vec::new()));
        let seen = Arc::clone(&requests);
        std::thread::spawn(move || {
            for stream in listener.incoming().flatten() {
                let mut line = String::new();
                let _ = stream.set_read_timeout(Some(Duration::from_secs(2)));
                let _ = BufReader::new(&stream).read_line(&mut line);
                // A connection that sent no request line before it closed or went quiet is the
                // browser opening a socket ahead of need (a preconnect to the proxy), not a request.
                let line = line.trim();
                if line.is_empty() {
                    eprintln!("proxy: a connection without a request");
                } else {
                    seen.lock().unwrap().push(line.to_string());
                }
            }
        });
        Proxy { port, requests }
    }

    /// The requests so far that are not to the browser's own services.
    fn page_requests(&self) -> Vec<String> {
        let requests = self.requests.lock().unwrap();
        requests.iter().filter(|r| !is_browser_service(&host_of(r))).cloned().collect()
    }
}

/// The host of a proxied request line: `GET http://host/path HTTP/1.1` or `CONNECT host:443 HTTP/1.1`.
fn host_of(request: &str) -> String {
    let target = request.split_whitespace().nth(1).unwrap_or("");
    let rest = target.split_once("://").map_or(target, |(_, r)| r);
    rest.split(['/', ':']).next().unwrap_or("").to_ascii_lowercase()
}

fn is_browser_service(host: &str) -> bool {
    BROWSER_SERVICE_DOMAINS.iter().any(|d| host == *d || host.ends_with(&format!(".{d}")))
}

/// Chromium, headless, software WebGL, a fresh profile in `dir`, every network request through
/// `proxy`.
fn browser(binary: &Path, dir: &Path, profile: &str, proxy: &Proxy) -> Command {
    let mut command = Command::new(binary);
    command.args([
        "--headless",
        "--no-sandbox",
        "--disable-gpu",
        "--use-gl=swiftshader",
        "--enable-unsafe-swiftshader",
        "--disable-background-networking",
        "--disable-component-update",
        "--no-first-run",
        "--hide-scrollbars",
        // loopback goes through the proxy too
        "--proxy-bypass-list=<-loopback>",
        &format!("--window-size={WIDTH},{HEIGHT}"),
        "--virtual-time-budget=3000",
    ]);
    command.arg(format!("--user-data-dir={}", dir.join(profile).display()));
    command.arg(format!("--proxy-server=127.0.0.1:{}", proxy.port));
    command
}

/// Longest a browser run may take: a hung browser fails the test instead of stalling it.
const BROWSER_TIMEOUT: Duration = Duration::from_secs(120);

fn run(mut command: Command, what: &str) -> Output {
    command.stdout(Stdio::piped()).stderr(Stdio::piped());
    let mut child = command.spawn().unwrap_or_else(|e| panic!("{what}: cannot start the browser: {e}"));
    // read both pipes while waiting, so that a full pipe never blocks the browser
    let mut out = child.stdout.take().unwrap();
    let mut err = child.stderr.take().unwrap();
    let out = std::thread::spawn(move || {
        let mut buffer = Vec::new();
        let _ = out.read_to_end(&mut buffer);
        buffer
    });
    let err = std::thread::spawn(move || {
        let mut buffer = Vec::new();
        let _ = err.read_to_end(&mut buffer);
        buffer
    });
    let start = Instant::now();
    let status = loop {
        if let Some(status) = child.try_wait().unwrap() {
            break status;
        }
        if start.elapsed() > BROWSER_TIMEOUT {
            let _ = child.kill();
            let _ = child.wait();
            panic!("{what}: the browser did not finish within {BROWSER_TIMEOUT:?}");
        }
        std::thread::sleep(Duration::from_millis(50));
    };
    let output = Output { status, stdout: out.join().unwrap(), stderr: err.join().unwrap() };
    assert!(output.status.success(), "{what}: {:?}\n{}", output.status, String::from_utf8_lossy(&output.stderr));
    output
}

fn screenshot(binary: &Path, dir: &Path, proxy: &Proxy, page: &Path, fragment: &str, name: &str) -> image::RgbImage {
    let file = dir.join(name);
    let mut command = browser(binary, dir, &format!("profile-{name}"), proxy);
    command.arg(format!("--screenshot={}", file.display()));
    command.arg(format!("file://{}#{fragment}", page.display()));
    run(command, name);
    let picture = image::open(&file).unwrap_or_else(|e| panic!("{}: {e}", file.display())).to_rgb8();
    assert_eq!(picture.dimensions(), (WIDTH, HEIGHT));
    picture
}

/// The middle of the scene: clear of the legend (top left), the notes (top right, bottom right)
/// and the controls under it.
fn middle(picture: &image::RgbImage) -> impl Iterator<Item = [u8; 3]> + '_ {
    let scene_height = HEIGHT - UNDER_SCENE;
    let (x0, x1, y0, y1) = (WIDTH / 5, WIDTH * 4 / 5, scene_height / 6, scene_height * 5 / 6);
    (y0..y1).flat_map(move |y| (x0..x1).map(move |x| picture.get_pixel(x, y).0))
}

fn differs(a: [u8; 3], b: [u8; 3], by: i32) -> bool {
    a.iter().zip(b).any(|(&x, y)| (x as i32 - y as i32).abs() > by)
}

/// The browser to test with, or `None` when `TUMBLE_SKIP_BROWSER=1` skips the test; without one,
/// the test fails saying how to install it.
fn browser_binary() -> Option<PathBuf> {
    if std::env::var("TUMBLE_SKIP_BROWSER").as_deref() == Ok("1") {
        eprintln!("skipped: TUMBLE_SKIP_BROWSER=1 (the replay is not checked in a browser)");
        return None;
    }
    let Some(binary) = chromium() else {
        panic!(
            "Chromium is not installed: the replay cannot be checked in a browser.\n\
             Install it (`apt-get install -y chromium`, as .ci/run does), name it with TUMBLE_CHROMIUM, \
             or skip this test with TUMBLE_SKIP_BROWSER=1"
        );
    };
    Some(binary)
}

/// The page's script ran to the end: `data-ready="1"` and no `data-error` in the DOM.
fn assert_ready(binary: &Path, dir: &Path, proxy: &Proxy, page: &Path, profile: &str) {
    let mut dom = browser(binary, dir, profile, proxy);
    dom.arg("--dump-dom").arg(format!("file://{}#t=1", page.display()));
    let dom = String::from_utf8_lossy(&run(dom, profile).stdout).into_owned();
    assert!(dom.contains("data-ready=\"1\""), "the page did not finish setting up:\n{}", &dom[..dom.len().min(2000)]);
    assert!(!dom.contains("data-error"), "the page reported an error");
}

/// Screenshots of `page` at `t0` and `t1` (s), without the grid and the axes (so what is not the
/// background is a body): at least `1/drawn_part` of the middle of the scene is drawn at each time,
/// and at least `1/moved_part` of it changed between them.
#[allow(clippy::too_many_arguments)]
fn assert_drawn_and_moved(
    binary: &Path,
    dir: &Path,
    proxy: &Proxy,
    page: &Path,
    (t0, t1): (f64, f64),
    drawn_part: usize,
    moved_part: usize,
    name: &str,
) {
    let early = screenshot(binary, dir, proxy, page, &format!("t={t0}&axes=0&grid=0"), &format!("{name}-early.png"));
    let late = screenshot(binary, dir, proxy, page, &format!("t={t1}&axes=0&grid=0"), &format!("{name}-late.png"));
    let total = middle(&early).count();
    for (when, picture) in [(t0, &early), (t1, &late)] {
        let drawn = middle(picture).filter(|&p| differs(p, BACKGROUND, 12)).count();
        eprintln!("{name}, t = {when} s: {drawn} of {total} pixels in the middle of the scene are not the background");
        assert!(
            drawn * drawn_part > total,
            "{name}, t = {when} s: only {drawn} of {total} pixels are not the background"
        );
    }
    let moved = middle(&early).zip(middle(&late)).filter(|&(a, b)| differs(a, b, 30)).count();
    eprintln!("{name}: {moved} of {total} pixels changed between t = {t0} s and t = {t1} s");
    assert!(moved * moved_part > total, "{name}: only {moved} of {total} pixels changed between t = {t0} s and {t1} s");
}

#[test]
fn the_replay_draws_and_moves_the_bodies_and_loads_nothing() {
    let Some(binary) = browser_binary() else { return };
    let dir = tempfile::tempdir().unwrap();
    tumble(dir.path())
        .args(["run", "--duration", "4", "--out", "demo.csv", "--view", "demo.html", "-q"])
        .assert()
        .success();
    let page = dir.path().join("demo.html");
    let proxy = Proxy::start();

    // the script ran to the end
    assert_ready(&binary, dir.path(), &proxy, &page, "dom");

    // bodies drawn, and moved between t = 0.5 s and t = 2 s (the flipper turns by 7.5 rad)
    assert_drawn_and_moved(&binary, dir.path(), &proxy, &page, (0.5, 2.0), 20, 50, "demo");

    // a trajectory cut short: the page shows what is there, and says so
    let text = std::fs::read_to_string(dir.path().join("demo.csv")).unwrap();
    std::fs::write(dir.path().join("cut.csv"), &text[..text.len() / 2]).unwrap();
    let scene = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes/demo.toml");
    tumble(dir.path())
        .args(["view", "cut.csv", "--scene", scene.to_str().unwrap(), "--out", "cut.html"])
        .assert()
        .success();
    let mut dom = browser(&binary, dir.path(), "cut", &proxy);
    dom.arg("--dump-dom").arg(format!("file://{}", dir.path().join("cut.html").display()));
    let dom = String::from_utf8_lossy(&run(dom, "cut").stdout).into_owned();
    assert!(dom.contains("data-ready=\"1\"") && !dom.contains("data-error"), "the cut replay did not set up");
    // the note element, not only the data (which holds the same words)
    assert!(dom.contains("id=\"note\">the trajectory ends early"), "no note that the trajectory was cut short");

    // nothing asked of the network by the page
    assert_eq!(proxy.page_requests(), Vec::<String>::new(), "the replay made network requests");
    // ... and the listener does see a page's requests
    let control = dir.path().join("control.html");
    std::fs::write(&control, "<!DOCTYPE html><img src=\"http://example.invalid/x.png\">").unwrap();
    let mut command = browser(&binary, dir.path(), "control", &proxy);
    command.arg("--dump-dom").arg(format!("file://{}", control.display()));
    run(command, "control");
    let seen = proxy.page_requests();
    assert!(seen.iter().any(|r| r.contains("example.invalid")), "the control page's request was not seen: {seen:?}");
}

#[test]
fn robot_replays_draw_and_move_their_links() {
    let Some(binary) = browser_binary() else { return };
    let dir = tempfile::tempdir().unwrap();
    let scenes = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes");
    let proxy = Proxy::start();
    // the two thin 1 m links (8 cm thick boxes), released at 1 rad and −0.5 rad, swing through the
    // bottom by t = 0.7 s; the Panda's PD control moves it to another pose by t = 2 s
    for (name, scene, duration, times, drawn_part, moved_part) in [
        ("pendulum", "double_pendulum.toml", "2", (0.0, 0.7), 400, 1000),
        ("panda", "panda.toml", "3", (0.0, 2.0), 50, 200),
    ] {
        let page = dir.path().join(format!("{name}.html"));
        tumble(dir.path())
            .args(["run", scenes.join(scene).to_str().unwrap(), "--duration", duration, "-q"])
            .args(["--out", &format!("{name}.csv"), "--view", page.to_str().unwrap()])
            .assert()
            .success();
        assert_ready(&binary, dir.path(), &proxy, &page, &format!("{name}-dom"));
        assert_drawn_and_moved(&binary, dir.path(), &proxy, &page, times, drawn_part, moved_part, name);
    }
    assert_eq!(proxy.page_requests(), Vec::<String>::new(), "the replay made network requests");
}

/// A robot drawn from its URDF geometry (a mirrored STL cube and a cylinder) beside a ball resting
/// on the floor, with `--contacts`: the page sets up, and the contact's dot and force arrow are
/// drawn (the picture with the overlay differs from the one without it, `#contacts=0`).
#[test]
fn urdf_geometry_and_contacts_are_drawn() {
    let Some(binary) = browser_binary() else { return };
    let dir = tempfile::tempdir().unwrap();
    let fixture = Path::new(env!("CARGO_MANIFEST_DIR")).join("../tumble/tests/fixtures/meshes/cube.stl");
    std::fs::copy(&fixture, dir.path().join("cube.stl")).unwrap();
    let urdf = r#"<?xml version="1.0"?>
<robot name="m">
  <link name="base"><visual><geometry><cylinder radius="0.05" length="0.6"/></geometry></visual></link>
  <link name="block">
    <inertial><mass value="1"/><inertia ixx="0.01" iyy="0.01" izz="0.01"/></inertial>
    <visual><geometry><mesh filename="cube.stl" scale="0.2 -0.2 0.2"/></geometry></visual>
  </link>
  <joint name="turn" type="revolute"><parent link="base"/><child link="block"/><origin xyz="0 0 0.3"/>
    <axis xyz="0 0 1"/><limit lower="-10" upper="10" effort="10" velocity="5"/></joint>
</robot>
"#;
    std::fs::write(dir.path().join("m.urdf"), urdf).unwrap();
    let scene = "version = 1\n[world]\nduration = 1.0\n\n[[body]]\nname = \"floor\"\nfixed = true\n\
                 shape = { type = \"plane\" }\n\n[[body]]\nname = \"ball\"\ndensity = 800.0\n\
                 shape = { type = \"sphere\", radius = 0.1 }\nposition = [0.0, 0.0, 0.1]\n\n\
                 [[robot]]\nname = \"r\"\nurdf = \"m.urdf\"\nbase = \"fixed\"\nposition = [0.6, 0.0, 0.3]\n\
                 collision = false\nv = { turn = 2.0 }\n";
    std::fs::write(dir.path().join("s.toml"), scene).unwrap();
    let page = dir.path().join("g.html");
    tumble(dir.path())
        .args(["run", "s.toml", "--out", "g.csv", "--contacts", "c.jsonl", "--view", "g.html", "-q"])
        .assert()
        .success();
    let proxy = Proxy::start();
    assert_ready(&binary, dir.path(), &proxy, &page, "geometry-dom");
    let with = screenshot(&binary, dir.path(), &proxy, &page, "t=0.9&axes=0&grid=0", "contacts-on.png");
    let without = screenshot(&binary, dir.path(), &proxy, &page, "t=0.9&axes=0&grid=0&contacts=0", "contacts-off.png");
    let drawn = middle(&without).filter(|&p| differs(p, BACKGROUND, 12)).count();
    let overlay = middle(&with).zip(middle(&without)).filter(|&(a, b)| differs(a, b, 30)).count();
    eprintln!("geometry and contacts: {drawn} pixels of bodies, {overlay} pixels of the contacts overlay");
    assert!(drawn > 2_000, "the ball and the robot are drawn: {drawn} pixels");
    assert!(overlay > 30, "the contact's dot and arrow are drawn: {overlay} pixels differ");
    assert_eq!(proxy.page_requests(), Vec::<String>::new(), "the replay made network requests");
}
