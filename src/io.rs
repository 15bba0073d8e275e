//! All filesystem access of hemilab. Every error names the path; every write is atomic
//! (temporary file in the same directory, then rename), so a crash never leaves a half-written file.

use crate::error::{Error, Result};
use crate::image::{self, Channel, Image};
use std::fs;
use std::io::Write;
use std::path::{Path, PathBuf};

pub fn read_string(path: &Path) -> Result<String> {
    fs::read_to_string(path).map_err(|e| Error::io(path, e))
}

pub fn read_bytes(path: &Path) -> Result<Vec<u8>> {
    fs::read(path).map_err(|e| Error::io(path, e))
}

pub fn exists(path: &Path) -> bool {
    path.exists()
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
    let tmp = dir.join(format!(".{name}.tmp-{}", std::process::id()));
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

pub fn write_exr(path: &Path, channels: &[Channel]) -> Result<()> {
    let bytes =
        image::encode_exr(channels).map_err(|e| Error::input(path, format!("cannot encode EXR: {e}")))?;
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

pub fn remove_file_if_exists(path: &Path) -> Result<()> {
    match fs::remove_file(path) {
        Ok(()) => Ok(()),
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => Ok(()),
        Err(e) => Err(Error::io(path, e)),
    }
}
