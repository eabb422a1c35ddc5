//! The `dalembert` binary: a thin front over the library (contract.md).

fn main() {
    // arguments as OS strings: a byte that is not UTF-8 is refused by name, never a panic
    let code = dalembert::cli::run_os(std::env::args_os().collect());
    std::process::exit(code);
}
