//! Bitwise determinism across thread counts: the same command file run with 1 and 2 worker
//! threads prints exactly the same JSON (forces are summed in a fixed order, energy partial
//! sums per fixed chunk).

use std::process::Command;

fn run(threads: &str) -> String {
    let out = Command::new(env!("CARGO_BIN_EXE_trubal"))
        .args([
            "scripts/dry_agglomerate_impact.tru",
            "--json",
            "--threads",
            threads,
            "--set",
            "v=2",
            "--set",
            "n=300",
        ])
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8(out.stdout).unwrap()
}

#[test]
fn one_and_two_threads_give_the_same_bits() {
    let a = run("1");
    let b = run("2");
    assert!(a.contains("\"damage_ratio\""), "{a}");
    assert_eq!(a, b);
}
