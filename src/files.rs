//! How aa-lab touches the file system for the user: bounded reads of the files a user names
//! (OBJ, MTL, render records, images) and atomic writes of everything it produces.
//!
//! # Reading
//! [`read_bounded`] reads only regular files (so `/dev/zero`, a FIFO or a directory named
//! as a scene is refused up front instead of being read until memory runs out) and only up to
//! a stated size, which the error message quotes. [`read_head`] reads the first bytes of a
//! regular file and never more (a glTF buffer is read no further than its declared length,
//! whatever the size of the file it names).
//!
//! # Writing, and the overwrite policy
//! Every output is written to a temporary file in the destination's folder and renamed into
//! place ([`write_atomic`], [`PendingFile`]), so a failed write (a full disk, a killed process)
//! never leaves a truncated output or a destroyed earlier file. The temporary file is removed
//! when the write fails or is abandoned (the [`PendingFile`] is dropped), and, through a
//! registry of the temporary files that exist, when the process is interrupted
//! ([`remove_temporaries_and_exit`], which the command line's SIGINT/SIGTERM handler calls);
//! only a process killed outright (SIGKILL, a power cut) leaves one behind. Scratch space for
//! a large output ([`anonymous_scratch`]) has no name at all.
//!
//! One policy for every command ([`Overwrite`]): the command line never replaces an existing
//! file unless `--force` is given, and never writes over one of the command's own inputs, even
//! with `--force`. Without `--force` the file is moved into place with a hard link, which
//! fails atomically when the name is taken, so a file appearing meanwhile is not clobbered
//! either. The viewer's export never replaces anything: it picks the next free numbered name.

use std::fs::File;
use std::io::{self, BufWriter, Read, Write};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::{Mutex, MutexGuard, PoisonError};

/// Errors of reading a user's file or writing an output.
#[derive(Debug, thiserror::Error)]
pub enum FileError {
    /// The file could not be opened or read.
    #[error("cannot read {}: {source}", path.display())]
    Read {
        /// The path.
        path: PathBuf,
        /// The operating system's error.
        source: io::Error,
    },
    /// The path names a directory, device, FIFO or socket.
    #[error("cannot read {}: it is {kind}, not a regular file", path.display())]
    NotAFile {
        /// The path.
        path: PathBuf,
        /// What it is instead (`a directory`, `a device`, ...).
        kind: &'static str,
    },
    /// The file is larger than what aa-lab reads for its purpose.
    #[error(
        "cannot read {}: it has {size} bytes, more than the {limit} bytes aa-lab reads for {what}",
        path.display()
    )]
    TooLarge {
        /// The path.
        path: PathBuf,
        /// Its size (or a lower bound, for a file that grew while being read).
        size: u64,
        /// The limit.
        limit: u64,
        /// What the file was read as (`an OBJ file`, ...).
        what: &'static str,
    },
    /// The output exists and the policy forbids replacing it.
    #[error("{} exists; aa-lab replaces existing files only with --force", path.display())]
    Exists {
        /// The path.
        path: PathBuf,
    },
    /// The output is one of the command's inputs.
    #[error(
        "refusing to write {}: it is an input of this command (choose another output path)",
        path.display()
    )]
    IsInput {
        /// The path.
        path: PathBuf,
    },
    /// Creating, writing or renaming the output failed.
    #[error("cannot write {}: {source}", path.display())]
    Write {
        /// The output path.
        path: PathBuf,
        /// The operating system's error.
        source: io::Error,
    },
}

/// What a file system object is, for messages about things that are not regular files.
fn kind_of(metadata: &std::fs::Metadata) -> &'static str {
    let kind = metadata.file_type();
    if kind.is_dir() {
        "a directory"
    } else if kind.is_symlink() {
        "a symbolic link"
    } else {
        #[cfg(unix)]
        {
            use std::os::unix::fs::FileTypeExt;
            if kind.is_fifo() {
                return "a FIFO";
            }
            if kind.is_socket() {
                return "a socket";
            }
            if kind.is_block_device() || kind.is_char_device() {
                return "a device";
            }
        }
        "not a regular file"
    }
}

/// Largest image file read (compressed size on disk): images, textures and the images a
/// scene file names.
pub const MAX_IMAGE_FILE_BYTES: u64 = 1 << 30;

/// Checks that `path` is a regular file (following links) of at most `limit` bytes and
/// returns its size. `what` names its purpose in the error.
pub fn check_regular(path: &Path, limit: u64, what: &'static str) -> Result<u64, FileError> {
    let metadata = std::fs::metadata(path).map_err(|source| FileError::Read {
        path: path.to_owned(),
        source,
    })?;
    if !metadata.is_file() {
        return Err(FileError::NotAFile {
            path: path.to_owned(),
            kind: kind_of(&metadata),
        });
    }
    if metadata.len() > limit {
        return Err(FileError::TooLarge {
            path: path.to_owned(),
            size: metadata.len(),
            limit,
            what,
        });
    }
    Ok(metadata.len())
}

/// Reads a whole regular file of at most `limit` bytes (see the module docs).
pub fn read_bounded(path: &Path, limit: u64, what: &'static str) -> Result<Vec<u8>, FileError> {
    let size = check_regular(path, limit, what)?;
    // The file may grow between the check and the read: never take more than the limit.
    let bytes = read_at_most(path, limit.saturating_add(1), size)?;
    if bytes.len() as u64 > limit {
        return Err(FileError::TooLarge {
            path: path.to_owned(),
            size: bytes.len() as u64,
            limit,
            what,
        });
    }
    Ok(bytes)
}

/// The first `length` bytes of a regular file (fewer when the file is shorter): the rest of
/// the file is never read. `what` names its purpose in the error.
pub fn read_head(path: &Path, length: u64, what: &'static str) -> Result<Vec<u8>, FileError> {
    check_regular(path, u64::MAX, what)?;
    read_at_most(path, length, 0)
}

/// Reads at most `length` bytes from the start of `path` (already checked to be a regular
/// file), reserving `expected` bytes up front.
fn read_at_most(path: &Path, length: u64, expected: u64) -> Result<Vec<u8>, FileError> {
    let read_error = |source| FileError::Read {
        path: path.to_owned(),
        source,
    };
    let file = File::open(path).map_err(read_error)?;
    let mut bytes = Vec::with_capacity(usize::try_from(expected.min(length)).unwrap_or(0));
    file.take(length)
        .read_to_end(&mut bytes)
        .map_err(read_error)?;
    Ok(bytes)
}

/// Whether existing outputs may be replaced, and which paths are inputs (never written).
#[derive(Clone, Debug, Default)]
pub struct Overwrite {
    /// Replace existing files (`--force`).
    pub force: bool,
    /// The command's inputs, as given and canonicalised.
    inputs: Vec<PathBuf>,
}

impl Overwrite {
    /// The policy of a command line with or without `--force`.
    pub fn new(force: bool) -> Self {
        Self {
            force,
            inputs: Vec::new(),
        }
    }

    /// Adds an input of the command: it is never written, even with `--force`.
    #[must_use]
    pub fn with_input(mut self, path: &Path) -> Self {
        self.inputs
            .push(std::fs::canonicalize(path).unwrap_or_else(|_| path.to_owned()));
        self
    }

    /// Whether `path` is one of the inputs (compared after resolving links and `..`).
    fn is_input(&self, path: &Path) -> bool {
        let resolved = std::fs::canonicalize(path).unwrap_or_else(|_| path.to_owned());
        self.inputs.contains(&resolved)
    }

    /// Checks that `path` may be written under this policy, before any work is done; returns
    /// whether it exists (and will be replaced).
    pub fn check(&self, path: &Path) -> Result<bool, FileError> {
        if self.is_input(path) {
            return Err(FileError::IsInput {
                path: path.to_owned(),
            });
        }
        match std::fs::symlink_metadata(path) {
            Ok(metadata) if metadata.is_dir() => Err(FileError::Write {
                path: path.to_owned(),
                source: io::Error::new(io::ErrorKind::IsADirectory, "it is a directory"),
            }),
            Ok(_) if !self.force => Err(FileError::Exists {
                path: path.to_owned(),
            }),
            Ok(_) => Ok(true),
            Err(_) => Ok(false),
        }
    }

    /// [`Overwrite::check`] for every path; none is written when one fails.
    pub fn check_all<'p>(
        &self,
        paths: impl IntoIterator<Item = &'p Path>,
    ) -> Result<(), FileError> {
        for path in paths {
            self.check(path)?;
        }
        Ok(())
    }
}

/// The temporary file's path next to `path`: hidden, unique to this process and call.
fn temporary_path(path: &Path) -> PathBuf {
    static COUNTER: AtomicU64 = AtomicU64::new(0);
    let name = path
        .file_name()
        .map_or_else(|| "output".into(), |n| n.to_string_lossy());
    let serial = COUNTER.fetch_add(1, Ordering::Relaxed);
    path.with_file_name(format!(
        ".{name}.aa-lab-tmp-{}-{serial}",
        std::process::id()
    ))
}

/// The temporary files of outputs being written ([`PendingFile`]), so that an interrupted
/// process can remove them ([`remove_temporaries_and_exit`]). A file is created and
/// registered, and moved into place and unregistered, under the lock: an interruption sees
/// every temporary file that exists, and never one half moved into place.
static LIVE_TEMPORARIES: Mutex<Vec<PathBuf>> = Mutex::new(Vec::new());

fn live_temporaries() -> MutexGuard<'static, Vec<PathBuf>> {
    LIVE_TEMPORARIES
        .lock()
        .unwrap_or_else(PoisonError::into_inner)
}

/// Removes the temporary file of every output being written and ends the process with `code`
/// (what the command line's SIGINT/SIGTERM handler does): nothing half written is left
/// behind, and no existing output is touched. Holds the registry's lock until the process has
/// ended, so no output is moved into place meanwhile.
pub fn remove_temporaries_and_exit(code: i32) -> ! {
    let live = live_temporaries();
    for temporary in live.iter() {
        let _ = std::fs::remove_file(temporary);
    }
    std::process::exit(code)
}

/// An output being written (see the module docs): the bytes go to a hidden temporary file in
/// the destination's folder, which [`PendingFile::commit`] flushes to disk and moves into
/// place. Dropped without a commit (an error, a cancelled export, an unwinding panic), it
/// removes the temporary file; an interrupted process removes it too
/// ([`remove_temporaries_and_exit`]).
pub struct PendingFile {
    path: PathBuf,
    temporary: PathBuf,
    force: bool,
    existed: bool,
    writer: BufWriter<File>,
}

impl PendingFile {
    /// Checks `path` against `policy` and creates its temporary file.
    pub fn create(path: &Path, policy: &Overwrite) -> Result<Self, FileError> {
        let existed = policy.check(path)?;
        let temporary = temporary_path(path);
        let file = {
            let mut live = live_temporaries();
            let file = File::options()
                .write(true)
                .create_new(true)
                .open(&temporary)
                .map_err(|source| FileError::Write {
                    path: path.to_owned(),
                    source,
                })?;
            live.push(temporary.clone());
            file
        };
        Ok(Self {
            path: path.to_owned(),
            temporary,
            force: policy.force,
            existed,
            writer: BufWriter::new(file),
        })
    }

    /// The destination.
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// The temporary file (for a program that writes the contents itself, as ffmpeg does;
    /// [`PendingFile::commit`] then flushes it to disk and moves it into place).
    pub fn temporary_path(&self) -> &Path {
        &self.temporary
    }

    /// Where the contents go.
    pub fn writer(&mut self) -> &mut BufWriter<File> {
        &mut self.writer
    }

    /// The error of this output for a failed write.
    pub fn write_error(&self, source: io::Error) -> FileError {
        FileError::Write {
            path: self.path.clone(),
            source,
        }
    }

    /// Flushes the contents to disk and moves them to the destination (replacing a file there
    /// only under `--force`); returns whether an existing file was replaced.
    pub fn commit(mut self) -> Result<bool, FileError> {
        let synced = self
            .writer
            .flush()
            .and_then(|()| self.writer.get_ref().sync_all());
        if let Err(source) = synced {
            return Err(self.write_error(source));
        }
        let mut live = live_temporaries();
        let placed = if self.force {
            std::fs::rename(&self.temporary, &self.path)
        } else {
            // A hard link fails when the name is taken, even if the file appeared after the check.
            match std::fs::hard_link(&self.temporary, &self.path) {
                Ok(()) => std::fs::remove_file(&self.temporary),
                Err(err) if err.kind() == io::ErrorKind::AlreadyExists => {
                    drop(live);
                    return Err(FileError::Exists {
                        path: self.path.clone(),
                    });
                }
                // File systems without hard links: the check above is all there is.
                Err(_) => std::fs::rename(&self.temporary, &self.path),
            }
        };
        match placed {
            Ok(()) => {
                live.retain(|t| *t != self.temporary);
                Ok(self.existed)
            }
            Err(source) => {
                drop(live);
                Err(self.write_error(source))
            }
        }
    }
}

impl Drop for PendingFile {
    fn drop(&mut self) {
        let mut live = live_temporaries();
        if let Some(index) = live.iter().position(|t| *t == self.temporary) {
            let _ = std::fs::remove_file(&self.temporary);
            live.swap_remove(index);
        }
    }
}

/// Writes a file atomically under `policy`: `fill` writes the contents to a temporary file in
/// the same folder, which is flushed to disk and then moved to `path` (see the module docs).
/// Returns whether an existing file was replaced.
pub fn write_atomic(
    path: &Path,
    policy: &Overwrite,
    fill: impl FnOnce(&mut dyn Write) -> io::Result<()>,
) -> Result<bool, FileError> {
    let mut pending = PendingFile::create(path, policy)?;
    if let Err(source) = fill(pending.writer()) {
        return Err(pending.write_error(source));
    }
    pending.commit()
}

/// A scratch file in the folder of `beside` (the same file system as the output it helps
/// to write) whose name is removed as soon as it is created: it lives only as long as the
/// returned handle, and nothing of it is left behind however the process ends.
pub fn anonymous_scratch(beside: &Path) -> Result<File, FileError> {
    let path = temporary_path(beside);
    let error = |source| FileError::Write {
        path: beside.to_owned(),
        source,
    };
    let file = File::options()
        .read(true)
        .write(true)
        .create_new(true)
        .open(&path)
        .map_err(error)?;
    std::fs::remove_file(&path).map_err(error)?;
    Ok(file)
}

/// [`write_atomic`] of bytes already in memory.
pub fn write_bytes(path: &Path, policy: &Overwrite, bytes: &[u8]) -> Result<bool, FileError> {
    write_atomic(path, policy, |w| w.write_all(bytes))
}

/// The line a command prints for a written file: `wrote PATH` or `replaced PATH`.
pub fn wrote_line(path: &Path, replaced: bool) -> String {
    format!(
        "{} {}",
        if replaced { "replaced" } else { "wrote" },
        path.display()
    )
}

/// The first name `stem`, `stem-2`, `stem-3`... for which none of the set's files exist.
pub fn free_stem(dir: &Path, stem: &str, suffixes: &[String]) -> String {
    (1..)
        .map(|n| {
            if n == 1 {
                stem.to_owned()
            } else {
                format!("{stem}-{n}")
            }
        })
        .find(|candidate| {
            suffixes
                .iter()
                .all(|s| !dir.join(format!("{candidate}{s}")).exists())
        })
        .unwrap_or_else(|| stem.to_owned())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn free_stem_never_reuses_a_taken_name() {
        let dir = tempfile::tempdir().unwrap();
        let suffixes = vec!["-none.png".to_owned(), ".json".to_owned()];
        assert_eq!(free_stem(dir.path(), "atrium-f3", &suffixes), "atrium-f3");
        std::fs::write(dir.path().join("atrium-f3.json"), "{}").unwrap();
        assert_eq!(free_stem(dir.path(), "atrium-f3", &suffixes), "atrium-f3-2");
        std::fs::write(dir.path().join("atrium-f3-2-none.png"), "").unwrap();
        assert_eq!(free_stem(dir.path(), "atrium-f3", &suffixes), "atrium-f3-3");
    }

    fn leftovers(dir: &Path) -> Vec<String> {
        std::fs::read_dir(dir)
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .filter(|n| n.contains("aa-lab-tmp"))
            .collect()
    }

    #[test]
    fn existing_files_are_kept_without_force_and_replaced_with_it() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("a.txt");
        assert!(!write_bytes(&path, &Overwrite::new(false), b"one").unwrap());
        let err = write_bytes(&path, &Overwrite::new(false), b"two").unwrap_err();
        assert!(matches!(err, FileError::Exists { .. }), "{err}");
        assert!(err.to_string().contains("--force"), "{err}");
        assert_eq!(std::fs::read(&path).unwrap(), b"one");
        assert!(write_bytes(&path, &Overwrite::new(true), b"two").unwrap());
        assert_eq!(std::fs::read(&path).unwrap(), b"two");
        assert!(leftovers(dir.path()).is_empty());
    }

    #[test]
    fn a_failed_write_leaves_the_old_file_and_no_temporary() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("a.png");
        std::fs::write(&path, b"precious").unwrap();
        let err = write_atomic(&path, &Overwrite::new(true), |w| {
            w.write_all(b"half")?;
            Err(io::Error::new(io::ErrorKind::StorageFull, "disk full"))
        })
        .unwrap_err();
        assert!(err.to_string().contains("disk full"), "{err}");
        assert_eq!(std::fs::read(&path).unwrap(), b"precious");
        assert!(leftovers(dir.path()).is_empty());
    }

    #[test]
    fn a_pending_file_dropped_without_commit_leaves_nothing_and_keeps_the_old_file() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("clip.png");
        std::fs::write(&path, b"precious").unwrap();
        let mut pending = PendingFile::create(&path, &Overwrite::new(true)).unwrap();
        pending.writer().write_all(b"half a clip").unwrap();
        pending.writer().flush().unwrap();
        assert_eq!(
            leftovers(dir.path()).len(),
            1,
            "the temporary file exists meanwhile"
        );
        let scratch = anonymous_scratch(&path).unwrap();
        drop(pending);
        assert!(
            leftovers(dir.path()).is_empty(),
            "{:?}",
            leftovers(dir.path())
        );
        assert_eq!(std::fs::read(&path).unwrap(), b"precious");
        drop(scratch);
        assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 1);
    }

    #[test]
    fn inputs_are_never_written_even_with_force() {
        let dir = tempfile::tempdir().unwrap();
        let input = dir.path().join("ref.png");
        std::fs::write(&input, b"reference").unwrap();
        let policy = Overwrite::new(true).with_input(&input);
        // The same file under another spelling.
        let other = dir.path().join(".").join("ref.png");
        let err = write_bytes(&other, &policy, b"heatmap").unwrap_err();
        assert!(matches!(err, FileError::IsInput { .. }), "{err}");
        assert_eq!(std::fs::read(&input).unwrap(), b"reference");
    }

    #[test]
    fn bounded_reads_refuse_devices_directories_and_large_files() {
        let dir = tempfile::tempdir().unwrap();
        let err = read_bounded(dir.path(), 100, "a test").unwrap_err();
        assert!(err.to_string().contains("a directory"), "{err}");
        #[cfg(unix)]
        {
            let err = read_bounded(Path::new("/dev/zero"), 100, "a test").unwrap_err();
            assert!(err.to_string().contains("a device"), "{err}");
        }
        let path = dir.path().join("big");
        std::fs::write(&path, [b'x'; 101]).unwrap();
        let err = read_bounded(&path, 100, "a test").unwrap_err();
        assert!(err.to_string().contains("100 bytes"), "{err}");
        assert_eq!(read_bounded(&path, 101, "a test").unwrap().len(), 101);
    }

    #[test]
    fn head_reads_stop_at_the_length_and_refuse_what_is_not_a_file() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("big");
        std::fs::write(&path, [b'x'; 101]).unwrap();
        assert_eq!(read_head(&path, 10, "a test").unwrap().len(), 10);
        assert_eq!(read_head(&path, 1000, "a test").unwrap().len(), 101);
        let err = read_head(dir.path(), 10, "a test").unwrap_err();
        assert!(err.to_string().contains("a directory"), "{err}");
        #[cfg(unix)]
        {
            let err = read_head(Path::new("/dev/zero"), 10, "a test").unwrap_err();
            assert!(err.to_string().contains("a device"), "{err}");
        }
    }
}
