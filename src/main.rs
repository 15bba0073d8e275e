//! The `hemilab` command: the library's command line (`hemilab::main_with`) on the process's
//! arguments, exiting with its status (2 for bad input, 130 after Ctrl-C). The stages are the
//! library's; `app` holds one thin file per command.

fn main() {
    std::process::exit(hemilab::main_with(std::env::args_os()));
}
