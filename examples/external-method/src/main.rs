//! The whole `scatterbench` command line over the built-in methods plus this crate's.
fn main() -> std::process::ExitCode {
    scatterbench::main_with(&external_method::registry())
}
