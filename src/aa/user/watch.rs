//! Noticing that user technique files changed on disk, for the viewer's reload: the files'
//! modification times and sizes, looked at no more than once per [`INTERVAL`] (a few `stat`
//! calls, done on the render thread between frames, never on the UI thread).

use std::path::{Path, PathBuf};
use std::time::{Duration, Instant, SystemTime};

/// How often the files are looked at.
pub const INTERVAL: Duration = Duration::from_secs(1);

/// What identifies a version of a file without reading it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct Stamp {
    modified: Option<SystemTime>,
    len: u64,
}

fn stamp(path: &Path) -> Option<Stamp> {
    let metadata = std::fs::metadata(path).ok()?;
    Some(Stamp {
        modified: metadata.modified().ok(),
        len: metadata.len(),
    })
}

/// The watched files, each under a key of the caller's (the viewer's technique index).
#[derive(Default)]
pub struct Watcher {
    files: Vec<(usize, PathBuf, Option<Stamp>)>,
    last_look: Option<Instant>,
}

impl Watcher {
    /// Watches `path` under `key` from its current state (a key watched already is replaced).
    pub fn watch(&mut self, key: usize, path: &Path) {
        self.files.retain(|(k, _, _)| *k != key);
        self.files.push((key, path.to_owned(), stamp(path)));
    }

    /// Stops watching the file under `key`.
    pub fn unwatch(&mut self, key: usize) {
        self.files.retain(|(k, _, _)| *k != key);
    }

    /// The keys of the files that changed since they were watched or last reported, when
    /// [`INTERVAL`] has passed since the last look at `now` (else none). A file that
    /// disappears is reported when it comes back.
    pub fn changed(&mut self, now: Instant) -> Vec<usize> {
        if self.files.is_empty()
            || self
                .last_look
                .is_some_and(|last| now.duration_since(last) < INTERVAL)
        {
            return Vec::new();
        }
        self.last_look = Some(now);
        let mut changed = Vec::new();
        for (key, path, known) in &mut self.files {
            let current = stamp(path);
            if current.is_some() && current != *known {
                *known = current;
                changed.push(*key);
            }
        }
        changed
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_rewritten_file_is_reported_once_per_change() {
        let dir = std::env::temp_dir().join(format!("aa-lab-watch-{}", std::process::id()));
        std::fs::create_dir_all(&dir).expect("temp dir");
        let path = dir.join("t.wgsl");
        std::fs::write(&path, "a").expect("write");
        let mut watcher = Watcher::default();
        watcher.watch(7, &path);
        let start = Instant::now();
        assert!(watcher.changed(start).is_empty());
        std::fs::write(&path, "longer").expect("write");
        // Within the interval nothing is looked at.
        assert!(watcher.changed(start + INTERVAL / 2).is_empty());
        assert_eq!(watcher.changed(start + INTERVAL * 2), [7]);
        assert!(watcher.changed(start + INTERVAL * 4).is_empty());
        std::fs::remove_dir_all(&dir).expect("clean up");
    }
}
