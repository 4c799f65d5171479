//! The `softway` command line: the library's [`softway::cli`].

fn main() -> std::process::ExitCode {
    softway::cli::main()
}
