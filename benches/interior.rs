//! `cargo bench --bench interior`: the same measurement as
//! `refract bench interior` (rays/s per thread, BVH/linear ratio).

fn main() {
    let quick = std::env::args().any(|a| a == "--quick");
    match refract::bench::interior(quick) {
        Ok(table) => print!("{table}"),
        Err(e) => {
            eprintln!("bench failed: {e:#}");
            std::process::exit(1);
        }
    }
}
