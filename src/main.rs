//! The `hemilab` command: parse the command line, run the command, print the error chain and exit
//! with its status (2 for bad input, 130 after Ctrl-C). The stages are the library's; `app` holds one thin file per
//! command.

mod app;
mod cli;

use clap::Parser;

fn main() {
    // Before any thread starts: signals are then taken by a thread of their own (see `interrupt`).
    hemilab::interrupt::install();
    let cli = cli::Cli::parse();
    if let Err(e) = app::run(cli) {
        match &e {
            hemilab::error::Error::Interrupted(what) => eprintln!("{what}"),
            _ => eprintln!("error: {e}"),
        }
        std::process::exit(e.exit_code());
    }
}
