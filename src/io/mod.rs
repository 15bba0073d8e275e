//! All filesystem access of hemilab. Every error names the path; every write is atomic
//! (temporary file in the same directory, then rename), so a crash never leaves a half-written file.

use crate::error::{Error, Result};
use crate::image::{self, Channel, Image};
use std::fs;
use std::io::Write;
use std::path::{Path, PathBuf};

mod machine;
pub use machine::{Runnable, cpu_model, host_tag, hostname, load_average};

pub fn read_string(path: &Path) -> Result<String> {
    String::from_utf8(read_bytes(path)?).map_err(|e| {
        Error::io(path, std::io::Error::other(format!("is not UTF-8 text ({})", e.utf8_error())))
    })
}

/// A regular file's bytes. Every file hemilab reads is one the user names (a spec, a scene, a mesh,
/// a texture, a point set): a device, FIFO or socket (`/dev/zero`, `/dev/stdin`) has no end, so it
/// is refused rather than read forever, and the read stops at the size the file had when opened.
pub fn read_bytes(path: &Path) -> Result<Vec<u8>> {
    use std::io::Read;
    let file = fs::File::open(path).map_err(|e| Error::io(path, e))?;
    let meta = file.metadata().map_err(|e| Error::io(path, e))?;
    if !meta.is_file() {
        let what =
            if meta.is_dir() { "a directory" } else { "not a regular file (a device, FIFO or socket)" };
        let e = std::io::Error::new(std::io::ErrorKind::InvalidInput, format!("is {what}; name a file"));
        return Err(Error::io(path, e));
    }
    let mut bytes = Vec::new();
    file.take(meta.len()).read_to_end(&mut bytes).map_err(|e| Error::io(path, e))?;
    Ok(bytes)
}

pub fn exists(path: &Path) -> bool {
    path.exists()
}

pub fn is_dir(path: &Path) -> bool {
    path.is_dir()
}

/// Proves that `dir` can be created and written (by creating and removing a probe file in it, or
/// in its nearest existing ancestor), so an unusable output directory fails before any rendering.
/// Nothing is left behind: a run that stops early for another reason creates no empty directories.
pub fn ensure_writable_dir(dir: &Path) -> Result<()> {
    let mut existing = dir;
    while !existing.as_os_str().is_empty() && fs::symlink_metadata(existing).is_err() {
        existing = existing.parent().unwrap_or(Path::new(""));
    }
    let base = if existing.as_os_str().is_empty() { Path::new(".") } else { existing };
    // A directory made right under `/` is almost always a slip (`--output /out/x.exr` for
    // `out/x.exr`, or a relative path typed while the current directory is `/`): refused, so that
    // it is made on purpose or not at all.
    let root = absolute(base).parent().is_none();
    if root && base != dir {
        let made = absolute(dir);
        let shown = if made == dir { String::new() } else { format!(" (as {})", made.display()) };
        let what = format!(
            "would be created directly under the filesystem root{shown}; create it first if that is \
             meant, or give a path under an existing directory (a relative path is relative to the \
             current directory)"
        );
        return Err(Error::io(dir, std::io::Error::new(std::io::ErrorKind::NotFound, what)));
    }
    if !base.is_dir() {
        let what = if base == dir {
            "exists and is not a directory".to_string()
        } else {
            format!("cannot be created: {} is not a directory", base.display())
        };
        return Err(Error::io(dir, std::io::Error::new(std::io::ErrorKind::NotADirectory, what)));
    }
    let probe = base.join(format!(".hemilab-probe-{}", std::process::id()));
    fs::write(&probe, b"").map_err(|e| Error::io(dir, e))?;
    fs::remove_file(&probe).map_err(|e| Error::io(&probe, e))
}

/// `path` made absolute against the current directory, with `.` and `..` resolved in the text (as
/// `mkdir -p` would walk it), so that `a/../b` never makes `a` and messages say where a file went.
pub fn absolute(path: &Path) -> PathBuf {
    use std::path::Component;
    let full = std::path::absolute(path).unwrap_or_else(|_| path.to_path_buf());
    let mut out = PathBuf::new();
    for c in full.components() {
        match c {
            Component::ParentDir => {
                out.pop();
            }
            Component::CurDir => {}
            c => out.push(c),
        }
    }
    out
}

/// Creates `dir` and its parents if missing.
pub fn create_dir_all(dir: &Path) -> Result<()> {
    fs::create_dir_all(dir).map_err(|e| Error::io(dir, e))
}

/// Refuses an output file that is an existing directory, before any work, so a command that writes
/// several files never writes some and then fails on the next.
pub fn ensure_writable_file(path: &Path) -> Result<()> {
    if path.is_dir() {
        let e = std::io::Error::new(std::io::ErrorKind::IsADirectory, "is a directory; name a file");
        return Err(Error::io(path, e));
    }
    Ok(())
}

/// Writes `bytes` to `path` atomically: a temporary sibling, fsync, then rename over the target.
pub fn write_atomic(path: &Path, bytes: &[u8]) -> Result<()> {
    let dir = match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
        _ => PathBuf::from("."),
    };
    fs::create_dir_all(&dir).map_err(|e| Error::io(&dir, e))?;
    let name = path.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default();
    // Host and process in the name: on a shared filesystem two machines' writers may have one pid.
    let tmp = dir.join(format!(".{name}.tmp-{}-{}", host_tag(), std::process::id()));
    let result = (|| {
        let mut f = fs::File::create(&tmp)?;
        f.write_all(bytes)?;
        f.sync_all()?;
        fs::rename(&tmp, path)
    })();
    if let Err(e) = result {
        let _ = fs::remove_file(&tmp);
        return Err(Error::io(path, e));
    }
    Ok(())
}

/// Appends `bytes` to `path` (created if missing) and flushes them to the OS: a journal line that a
/// killed process has written is on disk for the next one (a cut-off last line is its reader's to
/// drop).
pub fn append(path: &Path, bytes: &[u8]) -> Result<()> {
    let mut f =
        fs::OpenOptions::new().create(true).append(true).open(path).map_err(|e| Error::io(path, e))?;
    f.write_all(bytes).and_then(|()| f.flush()).map_err(|e| Error::io(path, e))
}

/// Removes the temporary files that `write_atomic` and `link_or_copy` of a process that is gone left
/// in `dir` (a `kill -9`, a power cut: `.NAME.tmp-HOST-PID`, `.NAME.link-HOST-PID`), and returns
/// them. Only that pattern, and only where no writer can still be at work: on this host, a PID that
/// is not running (or is this process, which has not written yet when it cleans up); on another
/// host (a shared filesystem), a file untouched for `STALE_ELSEWHERE_S`.
pub fn remove_stale_temp_files(dir: &Path) -> Result<Vec<PathBuf>> {
    let here = host_tag();
    let mut removed = Vec::new();
    for path in list_dir(dir)? {
        let Some((host, pid)) = path.file_name().and_then(|n| temp_owner(&n.to_string_lossy())) else {
            continue;
        };
        let stale = if host == here {
            pid == std::process::id() || !process_runs(pid)
        } else {
            fs::metadata(&path)
                .and_then(|m| m.modified())
                .ok()
                .and_then(|t| t.elapsed().ok())
                .is_some_and(|age| age.as_secs() >= STALE_ELSEWHERE_S)
        };
        if stale && fs::symlink_metadata(&path).is_ok_and(|m| m.is_file()) {
            remove_file_if_exists(&path)?;
            removed.push(path);
        }
    }
    Ok(removed)
}

/// A temporary file of another host is stale after a day: no single write takes that long.
const STALE_ELSEWHERE_S: u64 = 24 * 3600;

/// The writer (host tag, PID) of a temporary file name `write_atomic` or `link_or_copy` makes.
fn temp_owner(name: &str) -> Option<(String, u32)> {
    let rest = name.strip_prefix('.')?;
    let (_, tail) = rest.rsplit_once(".tmp-").or_else(|| rest.rsplit_once(".link-"))?;
    let (host, pid) = tail.rsplit_once('-')?;
    let valid = !host.is_empty()
        && host.chars().all(|c| c.is_ascii_alphanumeric() || c == '-' || c == '.' || c == '_');
    Some((host.to_string(), pid.parse().ok()?)).filter(|_| valid && pid.bytes().all(|b| b.is_ascii_digit()))
}

/// Whether a process with this PID runs on this host (`kill(pid, 0)`: EPERM means it runs, as
/// another user's).
fn process_runs(pid: u32) -> bool {
    let Ok(pid) = libc::pid_t::try_from(pid) else { return false };
    // SAFETY: signal 0 sends nothing; it only checks that the process exists.
    unsafe { libc::kill(pid, 0) == 0 || std::io::Error::last_os_error().raw_os_error() == Some(libc::EPERM) }
}

/// Puts a copy of `from` at `to` atomically: a hard link where the filesystem allows (no bytes
/// copied), else a copy; either way through a temporary sibling and a rename.
pub fn link_or_copy(from: &Path, to: &Path) -> Result<()> {
    let dir = to.parent().filter(|p| !p.as_os_str().is_empty()).unwrap_or(Path::new("."));
    fs::create_dir_all(dir).map_err(|e| Error::io(dir, e))?;
    let name = to.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default();
    let tmp = dir.join(format!(".{name}.link-{}-{}", host_tag(), std::process::id()));
    let _ = fs::remove_file(&tmp);
    if fs::hard_link(from, &tmp).is_ok() {
        return fs::rename(&tmp, to).map_err(|e| {
            let _ = fs::remove_file(&tmp);
            Error::io(to, e)
        });
    }
    write_atomic(to, &read_bytes(from)?)
}

/// Swaps two directories in one step, where the system can (Linux `renameat2` with
/// `RENAME_EXCHANGE`): whoever looks at either path sees the old directory or the new one, never
/// neither or a mix. Elsewhere, or on a filesystem without it, two renames through a third name
/// (`a` must not exist for that moment; a crash between them leaves both under their other names).
pub fn exchange_dirs(a: &Path, b: &Path) -> Result<()> {
    #[cfg(target_os = "linux")]
    {
        use std::ffi::CString;
        use std::os::unix::ffi::OsStrExt;
        let c = |p: &Path| CString::new(p.as_os_str().as_bytes()).map_err(|e| Error::io(p, e.into()));
        let (ca, cb) = (c(a)?, c(b)?);
        // SAFETY: two valid NUL-terminated paths; the call reads them and touches no memory of ours.
        let rc = unsafe {
            libc::renameat2(libc::AT_FDCWD, ca.as_ptr(), libc::AT_FDCWD, cb.as_ptr(), libc::RENAME_EXCHANGE)
        };
        if rc == 0 {
            return Ok(());
        }
        let e = std::io::Error::last_os_error();
        if !matches!(e.raw_os_error(), Some(libc::EINVAL) | Some(libc::ENOSYS) | Some(libc::EOPNOTSUPP)) {
            return Err(Error::io(b, e));
        }
    }
    let aside = a.with_extension("swap");
    fs::rename(b, &aside).map_err(|e| Error::io(b, e))?;
    fs::rename(a, b).map_err(|e| Error::io(a, e))?;
    fs::rename(&aside, a).map_err(|e| Error::io(&aside, e))
}

/// Renames `from` to `to` (a directory or a file; `to` must not be a non-empty directory).
pub fn rename(from: &Path, to: &Path) -> Result<()> {
    fs::rename(from, to).map_err(|e| Error::io(from, e))
}

/// Removes a directory and everything in it; nothing when it does not exist.
pub fn remove_dir_all_if_exists(dir: &Path) -> Result<()> {
    match fs::remove_dir_all(dir) {
        Ok(()) => Ok(()),
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => Ok(()),
        Err(e) => Err(Error::io(dir, e)),
    }
}

pub fn write_exr(path: &Path, channels: &[Channel]) -> Result<()> {
    write_exr_with(path, channels, None)
}

/// `write_exr` with the image's provenance in its header (`image::Provenance`).
pub fn write_exr_with(
    path: &Path,
    channels: &[Channel],
    provenance: Option<&image::Provenance>,
) -> Result<()> {
    let bytes = image::encode_exr_with(channels, provenance)
        .map_err(|e| Error::input(path, format!("cannot encode EXR: {e}")))?;
    write_atomic(path, &bytes)
}

pub fn read_exr(path: &Path) -> Result<Vec<(String, Image)>> {
    let bytes = read_bytes(path)?;
    image::decode_exr(&bytes).map_err(|e| Error::input(path, format!("not a readable EXR: {e}")))
}

/// The entries of `dir`, sorted by name; empty when `dir` does not exist.
pub fn list_dir(dir: &Path) -> Result<Vec<PathBuf>> {
    let entries = match fs::read_dir(dir) {
        Ok(e) => e,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(Vec::new()),
        Err(e) => return Err(Error::io(dir, e)),
    };
    let mut out = entries
        .map(|e| e.map(|e| e.path()))
        .collect::<std::io::Result<Vec<_>>>()
        .map_err(|e| Error::io(dir, e))?;
    out.sort();
    Ok(out)
}

/// A new, empty file at `path` (an existing one is truncated): where a child process's stdout or
/// stderr goes (`denoise_command`), so that it can be read back after the child exits.
pub fn create_file(path: &Path) -> Result<fs::File> {
    fs::File::create(path).map_err(|e| Error::io(path, e))
}

pub fn remove_file_if_exists(path: &Path) -> Result<()> {
    match fs::remove_file(path) {
        Ok(()) => Ok(()),
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => Ok(()),
        Err(e) => Err(Error::io(path, e)),
    }
}

/// An exclusive lock on a file, held until dropped. It is the operating system's advisory lock
/// (`flock`; over NFS the kernel maps it to a lock the server keeps), so it is released when the
/// process ends however it ends: a killed job leaves no stale lock behind. The lock file is removed
/// when the lock is dropped, and by `remove_held_locks` when a signal ends the command at once, so
/// no `.lock` file stays beside the references. Removing it is safe because the holder unlinks it
/// while still holding it, and a taker checks after locking that the file it locked is still the
/// one at the path (else it locked a removed file, and tries again on the new one).
pub struct Lock {
    _file: fs::File,
    path: PathBuf,
}

/// The lock files this process holds, for `remove_held_locks`.
static HELD: std::sync::Mutex<Vec<PathBuf>> = std::sync::Mutex::new(Vec::new());

impl Drop for Lock {
    fn drop(&mut self) {
        // Unlinked while still locked (the file is closed, and unlocked, after this).
        let _ = fs::remove_file(&self.path);
        if let Ok(mut held) = HELD.lock() {
            held.retain(|p| p != &self.path);
        }
    }
}

/// Removes the lock files this process holds: for a signal's exit at once, which runs no `Drop`.
/// The locks themselves go with the process.
pub fn remove_held_locks() {
    if let Ok(held) = HELD.lock() {
        for p in held.iter() {
            let _ = fs::remove_file(p);
        }
    }
}

/// Whether the open `file` is the file now at `path` (not one removed since it was opened).
fn still_at(file: &fs::File, path: &Path) -> bool {
    use std::os::unix::fs::MetadataExt;
    match (file.metadata(), fs::metadata(path)) {
        (Ok(a), Ok(b)) => a.dev() == b.dev() && a.ino() == b.ino(),
        _ => false,
    }
}

/// Takes the exclusive lock on `path` (creating the file), waiting while another process holds it;
/// `waiting` is told who holds it (the note the holder wrote: host, pid, since when) before the wait.
/// `Ok(Err(why))` when the lock cannot be taken here at all (a read-only directory, a filesystem
/// without locks): the caller decides whether to go on without it.
pub fn lock(path: &Path, waiting: impl FnOnce(&str)) -> Result<std::result::Result<Lock, String>> {
    let mut waiting = Some(waiting);
    let mut file = loop {
        let open = fs::OpenOptions::new().read(true).write(true).create(true).truncate(false).open(path);
        let file = match open {
            Ok(f) => f,
            Err(e) => return Ok(Err(format!("cannot create {}: {e}", path.display()))),
        };
        match file.try_lock() {
            Ok(()) => {}
            Err(fs::TryLockError::WouldBlock) => {
                let holder = fs::read_to_string(path).unwrap_or_default();
                let holder = holder.trim();
                if let Some(tell) = waiting.take() {
                    tell(if holder.is_empty() { "another process" } else { holder });
                }
                if let Err(e) = file.lock() {
                    return Err(Error::io(path, e));
                }
            }
            Err(fs::TryLockError::Error(e)) => {
                return Ok(Err(format!("cannot lock {}: {e}", path.display())));
            }
        }
        // The holder we waited for removed the file on its way out: lock the one at the path now.
        if still_at(&file, path) {
            break file;
        }
    };
    let since = std::time::SystemTime::now().duration_since(std::time::UNIX_EPOCH).map_or(0, |d| d.as_secs());
    let note = format!("hemilab on host {} pid {} since unix time {since}\n", hostname(), std::process::id());
    // The note is for the message of whoever waits next; the lock does not depend on it.
    let _ = file.set_len(0).and_then(|()| {
        use std::io::Seek;
        file.seek(std::io::SeekFrom::Start(0))?;
        file.write_all(note.as_bytes())
    });
    if let Ok(mut held) = HELD.lock() {
        held.push(path.to_path_buf());
    }
    Ok(Ok(Lock { _file: file, path: path.to_path_buf() }))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_lock_waits_for_its_holder_and_names_it() {
        let dir = std::env::temp_dir().join(format!("hemilab-lock-{}", std::process::id()));
        fs::create_dir_all(&dir).unwrap();
        let path = dir.join("x.lock");
        let held = lock(&path, |_| panic!("nobody holds it yet")).unwrap().unwrap();
        let (tx, rx) = std::sync::mpsc::channel();
        let p2 = path.clone();
        let waiter = std::thread::spawn(move || {
            let mut told = String::new();
            let l = lock(&p2, |h| told = h.to_string()).unwrap().unwrap();
            tx.send(()).unwrap();
            drop(l);
            told
        });
        std::thread::sleep(std::time::Duration::from_millis(200));
        assert!(rx.try_recv().is_err(), "the second lock waits while the first is held");
        drop(held);
        rx.recv_timeout(std::time::Duration::from_secs(10)).expect("released on drop");
        let told = waiter.join().unwrap();
        assert!(told.contains(&format!("pid {}", std::process::id())), "{told}");
        // The waiter locked the file anew after the holder removed it, and removed it in turn.
        assert!(!path.exists(), "no lock file stays once its locks are dropped");
        let _ = fs::remove_dir_all(&dir);
    }

    #[test]
    fn stale_temp_files_of_dead_writers_go_and_nothing_else() {
        let dir = std::env::temp_dir().join(format!("hemilab-stale-{}", std::process::id()));
        let _ = fs::remove_dir_all(&dir);
        fs::create_dir_all(&dir).unwrap();
        let host = host_tag();
        // PID 4194304 is above Linux's largest (pid_max is at most 2^22): never running.
        let dead = [format!(".a.exr.tmp-{host}-4194304"), format!(".results.json.link-{host}-4194304")];
        let me = format!(".b.exr.tmp-{host}-{}", std::process::id());
        let keep = [
            format!(".c.exr.tmp-{host}-1"), // PID 1 always runs
            ".d.exr.tmp-other-host-4194304".to_string(),
            "a.exr".to_string(),
            format!("x.tmp-{host}-4194304"),
            format!(".e.exr.tmp-{host}-12x"),
        ];
        for n in dead.iter().chain([&me]).chain(&keep) {
            fs::write(dir.join(n), b"").unwrap();
        }
        let mut gone: Vec<String> = remove_stale_temp_files(&dir)
            .unwrap()
            .iter()
            .map(|p| p.file_name().unwrap().to_string_lossy().into_owned())
            .collect();
        gone.sort();
        let mut want = vec![dead[0].clone(), dead[1].clone(), me];
        want.sort();
        assert_eq!(gone, want);
        for n in &keep {
            assert!(dir.join(n).exists(), "{n} kept");
        }
        assert_eq!(temp_owner(".x.tmp-my-host.lan-77"), Some(("my-host.lan".into(), 77)));
        let _ = fs::remove_dir_all(&dir);
    }

    #[test]
    fn machine_description_is_not_empty() {
        assert!(!hostname().is_empty());
        assert!(cpu_model().contains("CPUs)"));
    }
}
