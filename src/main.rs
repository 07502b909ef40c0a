//! The `driftlab` binary: the command line, and (with the `gui` feature) the workbench.

mod cli;

fn main() -> std::process::ExitCode {
    let args = cli::parse();
    // Ctrl-C, `kill` or a closed terminal during a write leaves no temporary file behind. A
    // system that refuses the handlers still runs the command, as before.
    let _ = driftlab::files::atomic::remove_temporaries_on_signals();
    let result = match args.command {
        Some(command) => cli::run(command),
        None => cli::run(cli::Command::Gui(cli::GuiArgs::default())),
    };
    match result {
        Ok(()) => std::process::ExitCode::SUCCESS,
        // The reader of the output is gone; a shell reports 141 for a program a closed pipe
        // stopped, and says nothing.
        Err(cli::CliError::ClosedOutput) => std::process::ExitCode::from(141),
        // The command's verdict (a lot's units not all passing), already printed.
        Err(cli::CliError::Status(code)) => std::process::ExitCode::from(code),
        Err(cli::CliError::Message(message)) => {
            // Standard error full or closed: nothing is left to tell; the status still says it.
            // Nothing in the message a terminal would obey reaches it (cli::write_err).
            cli::write_err(format_args!("error: {message}"));
            std::process::ExitCode::FAILURE
        }
    }
}
