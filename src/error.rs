//! User-facing errors: each names the file, key or job it concerns, so the message alone says what
//! to fix. Every variant but one is a bad input or an unusable environment, and exits with status 2;
//! `Interrupted` is a signal's stop, with the shell's status for it (130 for Ctrl-C).

use std::path::{Path, PathBuf};

#[derive(Debug, thiserror::Error)]
pub enum Error {
    /// A file whose content is not acceptable (spec, scene, mesh): `what` says where and what is allowed.
    #[error("{}: {what}", path.display())]
    Input { path: PathBuf, what: String },
    /// The filesystem refused: a missing file, a directory that cannot be written.
    #[error("{}: {source}", path.display())]
    Io { path: PathBuf, source: std::io::Error },
    /// A command-line value that is not acceptable.
    #[error("{0}")]
    Usage(String),
    /// The work could not be done as asked (e.g. a reference that does not match and may not be rebuilt).
    #[error("{0}")]
    Refused(String),
    /// SIGINT or SIGTERM stopped the work: what is saved, and how to resume (`interrupt`).
    #[error("{0}")]
    Interrupted(String),
}

impl Error {
    pub fn input(path: &Path, what: impl Into<String>) -> Self {
        Error::Input { path: path.to_path_buf(), what: what.into() }
    }

    pub fn io(path: &Path, source: std::io::Error) -> Self {
        Error::Io { path: path.to_path_buf(), source }
    }

    /// Everything but a signal's stop is the user's to fix, so it exits with 2 (clap's usage code
    /// too); a stop exits with 128 + the signal's number, as a killed command does.
    pub fn exit_code(&self) -> i32 {
        match self {
            Error::Interrupted(_) => crate::interrupt::exit_code(),
            _ => 2,
        }
    }
}

pub type Result<T, E = Error> = std::result::Result<T, E>;
