//! The `metabezier` command; all the work is in the library.

fn main() -> std::process::ExitCode {
    metabezier::cli::main()
}
