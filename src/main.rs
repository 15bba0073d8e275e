//! The `hemilab` command: parse the command line, run the command, print the error chain and exit
//! with its status (2 for bad input). The stages are the library's; `app` holds one thin file per
//! command.

mod app;
mod cli;

use clap::Parser;

fn main() {
    let cli = cli::Cli::parse();
    if let Err(e) = app::run(cli) {
        eprintln!("error: {e}");
        std::process::exit(e.exit_code());
    }
}
