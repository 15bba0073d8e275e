use clap::Parser;

fn main() {
    let cli = hemilab::cli::Cli::parse();
    if let Err(e) = hemilab::app::run(cli) {
        eprintln!("error: {e}");
        std::process::exit(e.exit_code());
    }
}
