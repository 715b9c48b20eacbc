//! The `aa-lab` binary: parses the command line and hands over to the library; SIGINT and SIGTERM
//! remove the temporary files of outputs being written before the process ends. Without a
//! subcommand it opens the viewer; errors are printed once, with their causes, and exit 1.

fn main() -> std::process::ExitCode {
    env_logger::Builder::from_env(env_logger::Env::default().default_filter_or("warn")).init();
    let cli = aa_lab::cli::parse();
    if let Err(err) = aa_lab::cli::remove_temporaries_on_interrupt() {
        log::warn!(
            "cannot watch for SIGINT/SIGTERM: {err}; an interrupted export may leave a temporary file"
        );
    }
    match aa_lab::cli::run(cli) {
        Ok(()) => std::process::ExitCode::SUCCESS,
        Err(err) => {
            eprintln!("error: {}", aa_lab::cli::error_message(&err));
            std::process::ExitCode::FAILURE
        }
    }
}
