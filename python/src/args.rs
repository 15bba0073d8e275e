//! Python keyword arguments read by the command line's own parser: each function builds the
//! `hemilab` command line its call stands for and lets `hemilab::cli` parse it, so defaults, ranges
//! and names are the flags' own and a bad value is refused with the flag's message.

use clap::Parser;
use hemilab::cli::{Cli, Command};
use pyo3::PyResult;

/// A command line as `--flag=value` pairs (`=` keeps a negative number a value, not a flag).
#[derive(Default)]
pub struct Line {
    words: Vec<String>,
    positional: Vec<String>,
}

impl Line {
    pub fn new(command: &str) -> Self {
        Self { words: vec!["hemilab".into(), command.into()], positional: Vec::new() }
    }

    /// `--name=value`.
    pub fn flag(mut self, name: &str, value: impl ToString) -> Self {
        self.words.push(format!("--{name}={}", value.to_string()));
        self
    }

    /// `--name=value` when there is a value.
    pub fn opt(self, name: &str, value: Option<impl ToString>) -> Self {
        match value {
            Some(v) => self.flag(name, v),
            None => self,
        }
    }

    /// A bare `--name` when `on`.
    pub fn switch(mut self, name: &str, on: bool) -> Self {
        if on {
            self.words.push(format!("--{name}"));
        }
        self
    }

    /// A positional argument (after `--`, so that a path may start with '-').
    pub fn arg(mut self, value: impl ToString) -> Self {
        self.positional.push(value.to_string());
        self
    }

    /// The parsed command, or `hemilab.Error` with clap's message (without its "error: " and
    /// its usage lines: the Python call has no `--help`).
    pub fn parse(self) -> PyResult<Command> {
        let mut words = self.words;
        if !self.positional.is_empty() {
            words.push("--".into());
            words.extend(self.positional);
        }
        match Cli::try_parse_from(words) {
            Ok(cli) => Ok(cli.command),
            Err(e) => {
                let text = e.render().to_string();
                let text = text.split("\n\n").next().unwrap_or(&text).trim();
                Err(crate::error(text.strip_prefix("error: ").unwrap_or(text)))
            }
        }
    }
}

/// `WxH`, as `--resolution` is written.
pub fn resolution(r: Option<(u32, u32)>) -> Option<String> {
    r.map(|(w, h)| format!("{w}x{h}"))
}
