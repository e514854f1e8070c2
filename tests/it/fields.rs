//! `FIEld`: the coarse-grained fields' checks of issue 55, as doc/output.md,
//! "Coarse-grained fields" states them: the mass integrates to the particles' mass to round-off; over a homogeneous
//! periodic cell the grid's mean stress is `PRint Stress` within 1 %; in a settled column
//! σ_zz is the weight above within 2 %; the `.vti` file reads in VTK with the same values.

use crate::common::{printed, trubal_json};

/// The JSON objects of `FIEld` in a run.
fn fields(run: &crate::common::Run) -> Vec<serde_json::Value> {
    printed(run, "field")
}

fn f(v: &serde_json::Value) -> f64 {
    v.as_f64().unwrap()
}

/// 100 spheres compressed by the stress servo to a mean stress of 20 kPa in a periodic cell
/// (the packing of `tests/it/cell.rs`), then the fields with both kernels.
#[test]
fn field_mass_is_exact_and_the_mean_stress_of_a_periodic_cell_is_print_stress() {
    let run = trubal_json(
        "start 1e-3 1e-3 1e-3 100 1000 0\nrad 8e-5 1\ndensity 2600 1\nymd 1e8 1\npra 0.25 1\n\
         friction 0.3 1\ndamping restitution 0.2\nrge 100 1 1 0\ngain 2e-2 600\nmode 1\n\
         cycle 20000 s0 2e4\nprint stress\nfield 3 3 3 3.4e-4\nfield 4 5 6 2.5e-4 lucy\n",
        &[],
    );
    assert!(run.ok, "{}", run.stderr);
    let stress = &printed(&run, "stress")[0]["stress"];
    let sigma: Vec<f64> = (0..9).map(|k| f(&stress[k / 3][k % 3])).collect();
    let scale = sigma.iter().fold(0.0f64, |a, &b| a.max(b.abs()));
    assert!(scale > 1e4, "{sigma:?}");
    let fs = fields(&run);
    assert_eq!(fs.len(), 2);
    for fl in &fs {
        let (m, gm) = (f(&fl["mass"]), f(&fl["grid_mass"]));
        assert!((gm - m).abs() <= 1e-12 * m, "mass {m:e} on the grid {gm:e}");
        // The density's own sum, from the printed nodes.
        let h: Vec<f64> = (0..3).map(|k| f(&fl["spacing"][k])).collect();
        let sum: f64 = fl["density"].as_array().unwrap().iter().map(f).sum();
        assert!((sum * h[0] * h[1] * h[2] - m).abs() <= 1e-12 * m);
        for k in 0..9 {
            let d = (f(&fl["mean_stress"][k]) - sigma[k]).abs();
            assert!(
                d <= 0.01 * scale,
                "{} component {k}: {d:e} of {scale:e}",
                fl["kernel"]
            );
        }
    }
}

/// A simple-cubic column of 10 layers of 2 x 2 spheres (periodic in x and y) settled on a
/// floor under gravity: σ_zz at the nodes between layers is the weight above per area.
#[test]
fn field_stress_of_a_settled_column_is_the_weight_above() {
    let (r, rho, g) = (1e-3, 2500.0, 9.81);
    let mut s = String::from(
        "start 4e-3 4e-3 20e-3 10 100 1\nset open z\nrad 1e-3 1\ndensity 2500 1\nymd 1e8 1\n\
         pra 0.3 1\nfriction 0.3 1\ndamping restitution 0.1\ngravity 0 0 -9.81\n\
         dwall p 0 0 1 0\n",
    );
    for k in 0..10 {
        for x in [1e-3, 3e-3] {
            for y in [1e-3, 3e-3] {
                s.push_str(&format!(
                    "create {x} {y} {} 0 0 0 0 0 0 1 1\n",
                    (2 * k + 1) as f64 * r
                ));
            }
        }
    }
    s.push_str("cycle 20000\nfield 1 1 5 4e-3 lucy\n");
    let run = trubal_json(&s, &[]);
    assert!(run.ok, "{}", run.stderr);
    let fl = &fields(&run)[0];
    let m = rho * 4.0 / 3.0 * std::f64::consts::PI * r * r * r;
    // Nodes at z = 2, 6, 10, 14, 18 mm: between layers.
    for (node, z) in [2.0, 6.0, 10.0, 14.0, 18.0].into_iter().enumerate() {
        let above = (0..10).filter(|&k| (2 * k + 1) as f64 > z).count() as f64 * 4.0;
        let want = above * m * g / (4e-3 * 4e-3);
        let got = f(&fl["stress_contact"][node][8]) + f(&fl["stress_kinetic"][node][8]);
        assert!(
            (got - want).abs() <= 0.02 * want,
            "z = {z} mm: sigma_zz {got:e}, weight above {want:e}"
        );
    }
}

/// Bad grids are refused with their place, and nothing is written.
#[test]
fn field_refuses_bad_grids() {
    for (line, want) in [
        ("field 0 1 1 1e-3", "`n1` must be between 1"),
        ("field 2 2 2 1e-9", "at least the largest node spacing"),
        ("field 2 2 2 -1", "must be positive"),
        ("field 2 2 2 1e-3 lucy lucy", "given twice"),
        ("field 4096 4096 4096 1", "at most"),
        ("field 100 100 100 1", "reaches about"),
    ] {
        let run = trubal_json(&format!("start 1e-3 1e-3 1e-3 10 10 1\n{line}\n"), &[]);
        assert!(!run.ok, "{line}");
        assert!(run.stderr.contains("<stdin>:2:"), "{line}: {}", run.stderr);
        assert!(run.stderr.contains(want), "{line}: {}", run.stderr);
    }
}
