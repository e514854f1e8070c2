//! The validation tables kept honest (issue 53 item 1): a reduced version of each table of
//! doc/validation.md (the same command files and measures, fewer particles, shorter runs) is
//! run by `scripts/ci_tables.py --check CASE` with this build, and every measure must lie
//! within the run-to-run scatter measured over other samples (other random seeds, or the
//! impact speed perturbed by 1e-6) of the reference figures in `doc/data/ci_tables.json`. A
//! change that moves a validated result fails here until the tables are run again and the
//! reference regenerated (`python3 scripts/ci_tables.py --regenerate`, doc/validation.md).

use std::process::Command;

fn check(case: &str) {
    let out = Command::new("python3")
        .args(["scripts/ci_tables.py", "--check", case])
        .env("TRUBAL_BIN", env!("CARGO_BIN_EXE_trubal"))
        .env("PYTHONDONTWRITEBYTECODE", "1")
        .output()
        .expect("python3 runs (CI needs Python 3 for these checks)");
    let text = format!(
        "{}{}",
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(out.status.success(), "{case}:\n{text}");
    // Every measure was compared (an empty reference would pass silently otherwise).
    assert!(text.contains("(ok)"), "{case}: nothing compared:\n{text}");
}

#[test]
fn lian6_reduced_impact_within_scatter() {
    check("lian6");
}

#[test]
fn lian7_reduced_collision_within_scatter() {
    check("lian7");
}

#[test]
fn olsson_reduced_dry_impact_within_scatter() {
    check("olsson");
}

#[test]
fn lun_shear_reduced_within_scatter() {
    check("lun_shear");
}

#[test]
fn shang_shear_reduced_within_scatter() {
    check("shang_shear");
}

#[test]
fn pasha_single_particle_within_scatter() {
    check("pasha4");
}

#[test]
fn pasha_reduced_indentation_within_scatter() {
    check("pasha5");
}

#[test]
fn triaxial_reduced_within_scatter() {
    check("triaxial");
}

/// Every case of the script has its reference figures and the provenance of the build that
/// made them (version, git describe, command, date).
#[test]
fn the_reference_figures_record_their_provenance() {
    let text = std::fs::read_to_string("doc/data/ci_tables.json").expect("doc/data/ci_tables.json");
    let v: serde_json::Value = serde_json::from_str(&text).expect("JSON");
    for case in [
        "lian6",
        "lian7",
        "olsson",
        "lun_shear",
        "shang_shear",
        "pasha4",
        "pasha5",
        "triaxial",
    ] {
        let c = &v[case];
        for key in ["version", "git", "command", "date"] {
            assert!(
                c[key].as_str().is_some_and(|s| !s.is_empty()),
                "{case}: no {key}"
            );
        }
        let m = c["measures"].as_object().expect("measures");
        assert!(!m.is_empty(), "{case}: no measures");
        for (name, r) in m {
            let tol = r["tolerance"].as_f64().expect("tolerance");
            let sd = r["scatter_sd"].as_f64().expect("scatter");
            assert!(
                tol >= 3.0 * sd && tol > 0.0,
                "{case} {name}: tolerance {tol} below 3 sd {sd}"
            );
            assert_eq!(
                r["samples"].as_array().map(Vec::len),
                Some(5),
                "{case} {name}"
            );
        }
    }
}
