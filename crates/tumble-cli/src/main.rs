//! The `tumble` command-line tool: see `tumble --help` and the `tumble_cli` library.

fn main() -> std::process::ExitCode {
    tumble_cli::main()
}
