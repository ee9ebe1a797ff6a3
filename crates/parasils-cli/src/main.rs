//! The `parasils` command.

fn main() -> std::process::ExitCode {
    parasils_cli::cli::main()
}
