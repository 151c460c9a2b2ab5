//! The contacts overlay of the replay: `tumble view --contacts FILE.jsonl`, and `tumble run --view
//! --contacts` with the run's own file.
//!
//! The file is the one `tumble run --contacts` writes (the contract's "Robots in contact"): one
//! JSON object per sample, `{"t", "contacts": [{"a", "b", "point", "normal", "depth", "force"}]}`,
//! world frame, `force` the force on `b` (N). The page gets, for each frame it keeps, the contacts
//! of the sample nearest in time (the same sample when the contacts and the trajectory come from
//! one run): `frames[k]` is a flat list of `px, py, pz, fx, fy, fz` per contact (m, N). The file is
//! read line by line and only the samples chosen are kept, so memory is that of the page.
//!
//! **Page size.** At most about [`MAX_CONTACTS`] contacts (summed over the frames) are written: past
//! that, only every `stride`-th frame carries its contacts (the others are `null`), and the page
//! shows those of the nearest frame that has them.
//!
//! The arrows are scaled in the page against `reference` (N): the weight of the robots (their
//! total mass times |g|), else that of the moving bodies, else (no gravity) the largest force of the
//! file, so that this force is a readable length; the legend says the scale.

use std::io::BufRead;
use std::path::Path;
use tumble::World;

/// Contacts written to a page, about (each is 6 numbers, some 60 bytes).
pub const MAX_CONTACTS: usize = 30_000;

/// The overlay: per frame kept, the contacts of the nearest sample; the force that sets the scale.
#[derive(Debug, Clone, PartialEq)]
pub struct Overlay {
    /// Per frame: `px, py, pz, fx, fy, fz` per contact (m, world frame; N, on `b`); `None` for the
    /// frames left out (see `stride`).
    pub frames: Vec<Option<Vec<f64>>>,
    /// Only every `stride`-th frame carries its contacts (1: all).
    pub stride: usize,
    /// The force an arrow's length is scaled against (N), and what it is.
    pub reference: f64,
    pub reference_of: &'static str,
    /// The most contacts in one frame.
    pub most: usize,
}

/// One sample of the file: its time and its contacts (flat, as [`Overlay::frames`]).
struct Sample {
    t: f64,
    contacts: Vec<f64>,
}

/// Reads the contacts file `path` for the frames at `times` (s, increasing) of a replay of `world`.
/// A bad line is an error naming the line and the field; a last line cut short (a run stopped) is
/// dropped, and the second value says so.
pub fn read(path: &Path, times: &[f64], world: &World) -> Result<(Overlay, Option<String>), String> {
    let name = path.display();
    let file = std::fs::File::open(path).map_err(|e| format!("cannot read '{name}': {e}"))?;
    let mut reader = std::io::BufReader::new(file);
    let mut frames: Vec<Vec<f64>> = Vec::with_capacity(times.len());
    let mut previous: Option<Sample> = None;
    let mut line = String::new();
    let mut number = 0;
    let mut cut_short = None;
    let mut largest: f64 = 0.0;
    loop {
        line.clear();
        let n = reader.read_line(&mut line).map_err(|e| format!("cannot read '{name}': {e}"))?;
        if n == 0 {
            break;
        }
        number += 1;
        if line.trim().is_empty() {
            continue;
        }
        let sample = match parse(&line) {
            Ok(sample) => sample,
            Err(_) if !line.ends_with('\n') => {
                cut_short = Some(format!("{name}:{number}: the last line is cut short (dropped)"));
                break;
            }
            Err(why) => return Err(format!("{name}:{number}: {why}")),
        };
        if previous.as_ref().is_some_and(|p| sample.t < p.t) {
            return Err(format!("{name}:{number}: `t` = {} goes back in time", sample.t));
        }
        for f in sample.contacts.chunks(6) {
            largest = largest.max((f[3] * f[3] + f[4] * f[4] + f[5] * f[5]).sqrt());
        }
        // the frames at or before this sample take the nearer of it and the one before
        while frames.len() < times.len() && times[frames.len()] <= sample.t {
            let t = times[frames.len()];
            let chosen = match &previous {
                Some(p) if t - p.t < sample.t - t => p,
                _ => &sample,
            };
            frames.push(chosen.contacts.clone());
        }
        previous = Some(sample);
    }
    // frames after the last sample take the last one (none: no contacts)
    let last = previous.map(|p| p.contacts).unwrap_or_default();
    frames.resize(times.len(), last);
    let most = frames.iter().map(|f| f.len() / 6).max().unwrap_or(0);
    let total: usize = frames.iter().map(|f| f.len() / 6).sum();
    let stride = total.div_ceil(MAX_CONTACTS).max(1);
    let frames = frames.into_iter().enumerate().map(|(k, f)| (k % stride == 0).then_some(f)).collect();
    let g = world.config.gravity.length();
    let robots: f64 = world.robots.iter().map(|r| r.model.total_mass).sum();
    let bodies: f64 = world.free_bodies().map(|b| b.mass.mass).sum();
    let (reference, reference_of) = if g > 0.0 && robots > 0.0 {
        (robots * g, "the robots' weight")
    } else if g > 0.0 && bodies > 0.0 {
        (bodies * g, "the moving bodies' weight")
    } else {
        (largest, "the largest contact force")
    };
    Ok((Overlay { frames, stride, reference, reference_of, most }, cut_short))
}

/// One line of the file.
fn parse(line: &str) -> Result<Sample, String> {
    let value: serde_json::Value = serde_json::from_str(line).map_err(|e| format!("not a JSON object: {e}"))?;
    let t = value.get("t").and_then(serde_json::Value::as_f64).ok_or("no number `t`")?;
    let list = value.get("contacts").and_then(serde_json::Value::as_array).ok_or("no array `contacts`")?;
    let mut contacts = Vec::with_capacity(6 * list.len());
    for (i, c) in list.iter().enumerate() {
        for field in ["point", "force"] {
            let v = c
                .get(field)
                .and_then(serde_json::Value::as_array)
                .filter(|a| a.len() == 3)
                .and_then(|a| a.iter().map(serde_json::Value::as_f64).collect::<Option<Vec<f64>>>())
                .filter(|a| a.iter().all(|x| x.is_finite()))
                .ok_or_else(|| format!("`contacts[{i}].{field}` is not three finite numbers"))?;
            contacts.extend(v);
        }
    }
    Ok(Sample { t, contacts })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn world() -> World {
        World::new(tumble::WorldConfig::default(), Vec::new())
    }

    fn line(t: f64, x: f64) -> String {
        format!(
            "{{\"t\":{t},\"contacts\":[{{\"a\":\"floor\",\"b\":\"ball\",\"point\":[{x},0,0],\"normal\":[0,0,1],\
             \"depth\":0,\"force\":[0,0,2]}}]}}\n"
        )
    }

    #[test]
    fn each_frame_takes_the_nearest_sample() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("c.jsonl");
        let text: String = (0..10).map(|k| line(k as f64 * 0.1, k as f64)).collect();
        std::fs::write(&path, text).unwrap();
        let (overlay, cut) = read(&path, &[0.0, 0.24, 0.26, 0.9, 2.0], &world()).unwrap();
        assert_eq!(cut, None);
        let xs: Vec<f64> = overlay.frames.iter().map(|f| f.as_ref().unwrap()[0]).collect();
        assert_eq!(overlay.stride, 1);
        assert_eq!(xs, [0.0, 2.0, 3.0, 9.0, 9.0]);
        assert_eq!(overlay.most, 1);
        assert_eq!((overlay.reference, overlay.reference_of), (2.0, "the largest contact force"));
    }

    #[test]
    fn many_contacts_are_written_for_every_stride_th_frame() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("c.jsonl");
        // 10 frames of 7,000 contacts each: 70,000, so every third frame is kept
        let contact =
            "{\"a\":\"floor\",\"b\":\"ball\",\"point\":[0,0,0],\"normal\":[0,0,1],\"depth\":0,\"force\":[0,0,1]}";
        let many = vec![contact; 7_000].join(",");
        let text: String = (0..10).map(|k| format!("{{\"t\":{k},\"contacts\":[{many}]}}\n")).collect();
        std::fs::write(&path, text).unwrap();
        let times: Vec<f64> = (0..10).map(f64::from).collect();
        let (overlay, _) = read(&path, &times, &world()).unwrap();
        assert_eq!(overlay.stride, 3);
        let kept: Vec<bool> = overlay.frames.iter().map(Option::is_some).collect();
        assert_eq!(kept, [true, false, false, true, false, false, true, false, false, true]);
        assert_eq!(overlay.frames[3].as_ref().unwrap().len(), 6 * 7_000);
    }

    #[test]
    fn a_bad_line_is_named_and_a_cut_last_line_dropped() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("c.jsonl");
        std::fs::write(&path, format!("{}{{\"t\":0.1,\"contacts\":[{{\"point\":[0,0]}}]}}\n", line(0.0, 1.0))).unwrap();
        let e = read(&path, &[0.0], &world()).unwrap_err();
        assert!(e.ends_with("c.jsonl:2: `contacts[0].point` is not three finite numbers"), "{e}");
        std::fs::write(&path, format!("{}{{\"t\":0.1,\"cont", line(0.0, 1.0))).unwrap();
        let (overlay, cut) = read(&path, &[0.0, 0.1], &world()).unwrap();
        assert!(cut.unwrap().ends_with("c.jsonl:2: the last line is cut short (dropped)"));
        let contact = vec![1.0, 0.0, 0.0, 0.0, 0.0, 2.0];
        assert_eq!(overlay.frames, [Some(contact.clone()), Some(contact)]);
    }
}
