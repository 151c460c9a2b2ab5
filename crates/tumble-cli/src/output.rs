//! Output files.
//!
//! A regular output file is written as `<name>.partial` beside its target and renamed into place when
//! the run ends (completed, diverged or interrupted), so that a failure never destroys a previous
//! file, and a killed run leaves a `.partial` whose whole rows are valid. A special file (a device such
//! as `/dev/null`, a FIFO) is written directly. The file is opened before the simulation starts, so
//! an output that cannot be written is reported before any work is done.

use std::ffi::OsString;
use std::fs::{self, File, OpenOptions};
use std::io;
use std::path::{Path, PathBuf};

/// An output file being written.
#[derive(Debug)]
pub struct OutputFile {
    /// The path as the user gave it (for messages).
    path: PathBuf,
    /// Where the data goes when committed (the path, or the file a symbolic link points to).
    target: PathBuf,
    /// The file being written, when it is not the target itself.
    partial: Option<PathBuf>,
}

impl OutputFile {
    /// Opens an output for `path` and returns it with the open file.
    pub fn create(path: &Path) -> io::Result<(OutputFile, File)> {
        let metadata = fs::metadata(path); // follows symbolic links
        match metadata {
            Ok(m) if m.is_dir() => Err(io::Error::new(io::ErrorKind::IsADirectory, "it is a directory")),
            Ok(m) if !m.is_file() => {
                let file = OpenOptions::new().write(true).open(path)?;
                Ok((OutputFile { path: path.to_path_buf(), target: path.to_path_buf(), partial: None }, file))
            }
            _ => {
                let target = follow_links(path);
                let partial = partial_path(&target);
                let file = File::create(&partial)?;
                Ok((OutputFile { path: path.to_path_buf(), target, partial: Some(partial) }, file))
            }
        }
    }

    /// The path as the user gave it.
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// Where the data is while it is written (`<name>.partial`, or the path itself).
    pub fn partial(&self) -> &Path {
        self.partial.as_deref().unwrap_or(&self.path)
    }

    /// Moves the written file into place.
    pub fn commit(self) -> io::Result<()> {
        match &self.partial {
            Some(partial) => fs::rename(partial, &self.target),
            None => Ok(()),
        }
    }

    /// Removes what was written (the target, if it existed, is untouched).
    pub fn discard(self) {
        if let Some(partial) = &self.partial {
            let _ = fs::remove_file(partial);
        }
    }
}

/// The file that `path` names after following symbolic links (which may not exist yet).
fn follow_links(path: &Path) -> PathBuf {
    let mut path = path.to_path_buf();
    // a bound on the chain, as the kernel's (40)
    for _ in 0..40 {
        match fs::read_link(&path) {
            Ok(target) => path = path.parent().unwrap_or(Path::new("")).join(target),
            Err(_) => break,
        }
    }
    path
}

/// `<path>.partial`.
pub fn partial_path(path: &Path) -> PathBuf {
    let mut name: OsString = path.as_os_str().to_owned();
    name.push(".partial");
    PathBuf::from(name)
}

/// Whether two paths name the same file: the same inode when both exist, else the same absolute
/// path (with the parent directory resolved).
pub fn same_file(a: &Path, b: &Path) -> bool {
    if let (Ok(ma), Ok(mb)) = (fs::metadata(a), fs::metadata(b)) {
        use std::os::unix::fs::MetadataExt;
        return ma.dev() == mb.dev() && ma.ino() == mb.ino();
    }
    match (resolved(a), resolved(b)) {
        (Some(ra), Some(rb)) => ra == rb,
        _ => a == b,
    }
}

/// The absolute path of `path` with its parent directory canonicalised.
fn resolved(path: &Path) -> Option<PathBuf> {
    let name = path.file_name()?;
    let parent = match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p,
        _ => Path::new("."),
    };
    Some(fs::canonicalize(parent).ok()?.join(name))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_regular_file_is_written_beside_and_renamed_into_place() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("a.csv");
        fs::write(&path, "previous").unwrap();
        let (out, file) = OutputFile::create(&path).unwrap();
        use std::io::Write;
        writeln!(&file, "new").unwrap();
        drop(file);
        assert_eq!(fs::read_to_string(&path).unwrap(), "previous", "untouched until committed");
        assert_eq!(out.partial(), dir.path().join("a.csv.partial"));
        out.commit().unwrap();
        assert_eq!(fs::read_to_string(&path).unwrap(), "new\n");
        assert!(!dir.path().join("a.csv.partial").exists());
    }

    #[test]
    fn a_discarded_output_leaves_the_previous_file() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("a.csv");
        fs::write(&path, "previous").unwrap();
        let (out, _file) = OutputFile::create(&path).unwrap();
        out.discard();
        assert_eq!(fs::read_dir(dir.path()).unwrap().count(), 1);
        assert_eq!(fs::read_to_string(&path).unwrap(), "previous");
    }

    #[test]
    fn a_symbolic_link_is_followed_and_kept() {
        let dir = tempfile::tempdir().unwrap();
        let real = dir.path().join("real.csv");
        let link = dir.path().join("link.csv");
        std::os::unix::fs::symlink(&real, &link).unwrap();
        let (out, file) = OutputFile::create(&link).unwrap();
        drop(file);
        out.commit().unwrap();
        assert!(real.is_file());
        assert!(fs::symlink_metadata(&link).unwrap().file_type().is_symlink());
    }

    #[test]
    fn a_device_is_written_directly() {
        let (out, _file) = OutputFile::create(Path::new("/dev/null")).unwrap();
        assert_eq!(out.partial(), Path::new("/dev/null"));
        out.commit().unwrap();
        use std::os::unix::fs::FileTypeExt;
        assert!(fs::metadata("/dev/null").unwrap().file_type().is_char_device(), "not replaced by a file");
    }

    #[test]
    fn unwritable_paths_fail_at_once() {
        let dir = tempfile::tempdir().unwrap();
        let file = dir.path().join("file.txt");
        fs::write(&file, "x").unwrap();
        for path in [dir.path().join("missing/a.csv"), file.join("a.csv"), dir.path().to_path_buf()] {
            assert!(OutputFile::create(&path).is_err(), "{}", path.display());
        }
    }

    #[test]
    fn same_file_sees_through_links_and_relative_paths() {
        let dir = tempfile::tempdir().unwrap();
        let scene = dir.path().join("scene.toml");
        fs::write(&scene, "").unwrap();
        let link = dir.path().join("link.csv");
        std::os::unix::fs::symlink(&scene, &link).unwrap();
        assert!(same_file(&scene, &link));
        fs::create_dir(dir.path().join("sub")).unwrap();
        assert!(same_file(&dir.path().join("x.csv"), &dir.path().join("sub/../x.csv")));
        assert!(!same_file(&scene, &dir.path().join("other.csv")));
        assert!(!same_file(&dir.path().join("a.json"), &dir.path().join("b.json")));
    }
}
