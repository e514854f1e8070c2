//! `FIEld`: the coarse-grained fields' checks of issue 55, as doc/output.md,
//! "Coarse-grained fields" states them: the mass integrates to the particles' mass to round-off; over a homogeneous
//! periodic cell the grid's mean stress is `PRint Stress` within 1 %; in a settled column
//! σ_zz is the weight above within 2 %, with the smooth kernels and in bins whose bottom one
//! holds the floor's contacts; the box kernel is `Window` + `PRint Stress` bin by bin; the
//! `.vti` file reads in VTK with the same values.

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

/// A simple-cubic column of 10 layers of 2 x 2 spheres of radius 1 mm (periodic in x and
/// y, 4 x 4 mm) on a floor (wall 1) under gravity, 20,000 cycles to settle.
fn settled_column() -> String {
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
                    (2 * k + 1) as f64 * 1e-3
                ));
            }
        }
    }
    s.push_str("cycle 20000\n");
    s
}

/// One sphere's mass in [`settled_column`].
const COLUMN_MASS: f64 = 2500.0 * 4.0 / 3.0 * std::f64::consts::PI * 1e-9;

/// [`settled_column`]: σ_zz at the nodes between layers is the weight above per area.
#[test]
fn field_stress_of_a_settled_column_is_the_weight_above() {
    let s = settled_column() + "field 1 1 5 4e-3 lucy\n";
    let run = trubal_json(&s, &[]);
    assert!(run.ok, "{}", run.stderr);
    let fl = &fields(&run)[0];
    let (m, g) = (COLUMN_MASS, 9.81);
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

/// Bins with wall contacts: [`settled_column`] in 10 bins, one layer each (`FIEld 1 1 10
/// BIN`). A bin's σ_zz is, by its definition (doc/output.md, "Bins": each particle with all
/// its contacts, walls included, at the contact points), (F_above + F_below) (R − δ/2) / V
/// for the layer's contacts above and below, V = 2R A: the weight above the bin's mid-plane
/// over the area, (10 − k + ½) 4 m g / A for bin k, within 2 %. In the bottom bin the
/// floor's contacts carry the whole weight: their share, Σ N (R − δ/2) / V from `PRint
/// Contacts`' wall contacts, is half the weight over the area, and the bin without it
/// would hold only the particle pairs' 9 layers: 18 m g / A against 38 m g / A. Each bin's
/// contact stress is also `Window` + `PRint Stress`'s on its box, to 1e-12 (the bottom one
/// with the floor's contacts).
#[test]
fn field_bins_with_wall_contacts_hold_the_weight_above() {
    let mut s = settled_column() + "field 1 1 10 bin\nprint contacts\n";
    for k in 0..10 {
        s.push_str(&format!(
            "window 0 4e-3 0 4e-3 {:?} {:?}\nprint stress\n",
            2.0 * k as f64 * 1e-3,
            2.0 * (k + 1) as f64 * 1e-3
        ));
    }
    let run = trubal_json(&s, &[]);
    assert!(run.ok, "{}", run.stderr);
    let fl = &fields(&run)[0];
    let windows = printed(&run, "stress");
    assert_eq!(windows.len(), 10);
    let scale = f(&windows[0]["window"]["contact"][2][2]);
    for (k, w) in windows.iter().enumerate() {
        assert_eq!(w["window"]["particles"], 4, "bin {}", k + 1);
        for m in 0..9 {
            let (got, want) = (
                f(&fl["stress_contact"][k][m]),
                f(&w["window"]["contact"][m / 3][m % 3]),
            );
            assert!(
                (got - want).abs() <= 1e-12 * scale,
                "bin {} [{m}]: {got:e} {want:e}",
                k + 1
            );
        }
    }
    let (m, g, r, area) = (COLUMN_MASS, 9.81, 1e-3, 4e-3 * 4e-3);
    let szz = |k: usize| f(&fl["stress_contact"][k][8]) + f(&fl["stress_kinetic"][k][8]);
    for k in 0..10 {
        let want = (10.0 - (k + 1) as f64 + 0.5) * 4.0 * m * g / area;
        assert!(
            (szz(k) - want).abs() <= 0.02 * want,
            "bin {}: sigma_zz {:e}, weight above its mid-plane {want:e}",
            k + 1,
            szz(k)
        );
    }
    let contacts = &printed(&run, "contacts")[0]["contacts"];
    let walls: Vec<&serde_json::Value> = contacts
        .as_array()
        .unwrap()
        .iter()
        .filter(|c| c.get("wall").is_some())
        .collect();
    assert_eq!(walls.len(), 4);
    let v = 2.0 * r * area;
    let share: f64 = walls
        .iter()
        .map(|c| f(&c["normal_force"]) * (r - 0.5 * f(&c["overlap"])) / v)
        .sum();
    let half = 40.0 * m * g / (2.0 * area);
    assert!((share - half).abs() <= 0.02 * half, "{share:e} {half:e}");
    let pairs = szz(0) - share;
    let want = 36.0 * m * g / (2.0 * area);
    assert!((pairs - want).abs() <= 0.02 * want, "{pairs:e} {want:e}");
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

/// The 100 spheres of the first test compressed to 20 kPa, then the cell stopped: a dense
/// packing whose particles still move.
const PACKED: &str = "start 1e-3 1e-3 1e-3 100 1000 0\nrad 8e-5 1\ndensity 2600 1\nymd 1e8 1\n\
     pra 0.25 1\nfriction 0.3 1\ndamping restitution 0.2\nrge 100 1 1 0\ngain 2e-2 600\n\
     mode 1\ncycle 3000 s0 2e4\ngrid 0 0 0 0 0 0\n";

/// `AVerage k m` is Weinhart's time average of the m states: density and contact stress
/// the means of the states' fields, the velocity Σ ρV / Σ ρ, the kinetic stress the mean of
/// (σᵏ + ρVV) less ρ̄V̄V̄, all recomputed here from three single `FIEld`s at the same
/// cycles; the samples leave the run's bits alone; `CSV` writes the printed numbers.
#[test]
fn field_average_is_the_time_average_of_the_states() {
    let f3 = "field 3 3 3 3.4e-4";
    let dir = std::env::temp_dir().join(format!("trubal-fields-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    let out = format!("set outdir \"{}\"\n", dir.display());
    let avg = trubal_json(
        &format!("{PACKED}{out}{f3} average 40 3 csv\ncycle 100\nprint balls\n"),
        &[],
    );
    assert!(avg.ok, "{}", avg.stderr);
    // (`set outdir` in both: a SET before a Cycle changes the run's bits.)
    let one = trubal_json(
        &format!("{PACKED}{out}{f3}\ncycle 40\n{f3}\ncycle 40\n{f3}\ncycle 20\nprint balls\n"),
        &[],
    );
    assert!(one.ok, "{}", one.stderr);
    assert_eq!(printed(&avg, "balls"), printed(&one, "balls"));
    let a = &fields(&avg)[0];
    let s = fields(&one);
    assert_eq!(fields(&avg).len(), 1);
    assert_eq!(a["samples"], 3);
    assert_eq!(a["cycle"], s[2]["cycle"]);
    assert!(
        avg.stdout.contains("averaging 3 states every 40 cycles"),
        "{}",
        avg.stdout
    );
    let node = |v: &serde_json::Value, name: &str, k: usize| -> Vec<f64> {
        match &v[name][k] {
            serde_json::Value::Array(x) => x.iter().map(f).collect(),
            x => vec![f(x)],
        }
    };
    let close = |got: f64, want: f64, scale: f64, what: &str| {
        assert!(
            (got - want).abs() <= 1e-12 * scale,
            "{what}: {got:e} against {want:e}"
        );
    };
    let mut moving = 0.0f64;
    for k in 0..27 {
        let rho: Vec<f64> = s.iter().map(|v| node(v, "density", k)[0]).collect();
        let rbar = rho.iter().sum::<f64>() / 3.0;
        close(node(a, "density", k)[0], rbar, rbar, "density");
        let vel: Vec<Vec<f64>> = s.iter().map(|v| node(v, "velocity", k)).collect();
        let vbar: Vec<f64> = (0..3)
            .map(|i| (0..3).map(|m| rho[m] * vel[m][i]).sum::<f64>() / (3.0 * rbar))
            .collect();
        let vscale = vel.iter().flatten().fold(1e-30f64, |x, y| x.max(y.abs()));
        moving = moving.max(vscale);
        for i in 0..3 {
            close(node(a, "velocity", k)[i], vbar[i], vscale, "velocity");
        }
        let sc: Vec<Vec<f64>> = s.iter().map(|v| node(v, "stress_contact", k)).collect();
        let sk: Vec<Vec<f64>> = s.iter().map(|v| node(v, "stress_kinetic", k)).collect();
        let cscale = sc.iter().flatten().fold(1e-30f64, |x, y| x.max(y.abs()));
        // The kinetic stress's own size too: the fluctuation part σᵏ may exceed ρ̄v².
        let kscale = sk
            .iter()
            .flatten()
            .fold(rbar * vscale * vscale, |x, y| x.max(y.abs()));
        for (ij, (i, j)) in (0..3).flat_map(|i| (0..3).map(move |j| (i, j))).enumerate() {
            let c = (0..3).map(|m| sc[m][ij]).sum::<f64>() / 3.0;
            close(
                node(a, "stress_contact", k)[ij],
                c,
                cscale,
                "contact stress",
            );
            let flux = (0..3)
                .map(|m| sk[m][ij] + rho[m] * vel[m][i] * vel[m][j])
                .sum::<f64>()
                / 3.0;
            let want = flux - rbar * vbar[i] * vbar[j];
            close(
                node(a, "stress_kinetic", k)[ij],
                want,
                kscale,
                "kinetic stress",
            );
        }
    }
    assert!(moving > 1e-4, "the packing should still move: {moving:e}");
    // The CSV: a header and a line per node with the printed numbers.
    let name = format!("trubal_field_c{:08}.csv", a["cycle"].as_u64().unwrap());
    let text = std::fs::read_to_string(dir.join(name)).unwrap();
    let lines: Vec<&str> = text.lines().collect();
    assert_eq!(lines.len(), 28);
    assert!(
        lines[0].starts_with("x,y,z,density,vx,vy,vz,sxx,"),
        "{}",
        lines[0]
    );
    for (k, line) in lines[1..].iter().enumerate() {
        let v: Vec<f64> = line.split(',').map(|x| x.parse().unwrap()).collect();
        assert_eq!(v.len(), 36);
        assert_eq!(v[3], node(a, "density", k)[0]);
        assert_eq!(v[4..7], node(a, "velocity", k)[..]);
        assert_eq!(v[16..25], node(a, "stress_contact", k)[..]);
        assert_eq!(v[25..34], node(a, "stress_kinetic", k)[..]);
        assert_eq!(v[34], node(a, "solid_fraction", k)[0]);
        let h = f(&a["spacing"][1]);
        assert!(
            (v[1] - ((k / 3 % 3) as f64 + 0.5) * h).abs() < 1e-15,
            "{line}"
        );
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// Simple shear of a periodic cell (`GRID 0 0 0 ed12 0 0`, Lees–Edwards): the velocity
/// field, averaged over 20 states, is the linear profile V_x = ed12 y, V_y = V_z = 0
/// within 5 % of ed12 L_y at every node, its slope by least squares within 3 %: the
/// particles follow the shear (their peculiar velocities average out) and the field
/// reports the whole velocity, the mean field included (doc/cell.md).
#[test]
fn field_velocity_of_a_simple_shear_cell_is_linear() {
    let rate = 3000.0;
    let run = trubal_json(
        &format!(
            "start 1e-3 1e-3 1e-3 400 1000 0\nrad 6e-5 1\ndensity 2600 1\nymd 1e8 1\n\
             pra 0.25 1\nfriction 0.4 1\ndamping restitution 0.8\nrge 250 1 1 0\n\
             grid 0 0 0 {rate} 0 0\ncycle 2000\nfield 4 8 4 2.5e-4 lucy average 100 20\n\
             cycle 1900\nprint grid\n"
        ),
        &[],
    );
    assert!(run.ok, "{}", run.stderr);
    let fl = &fields(&run)[0];
    assert_eq!(fl["samples"], 20);
    let ly = f(&printed(&run, "grid")[0]["size"][1]);
    let scale = rate * ly;
    let (mut sy, mut sv, mut syy, mut syv, mut n) = (0.0, 0.0, 0.0, 0.0, 0.0);
    for k in 0..128 {
        let y = ((k / 4 % 8) as f64 + 0.5) * ly / 8.0;
        let v: Vec<f64> = (0..3).map(|i| f(&fl["velocity"][k][i])).collect();
        assert!(
            (v[0] - rate * y).abs() <= 0.05 * scale,
            "node {k}: vx {} at y {y:e}",
            v[0]
        );
        assert!(
            v[1].abs() <= 0.05 * scale && v[2].abs() <= 0.05 * scale,
            "node {k}: {v:?}"
        );
        (sy, sv, syy, syv, n) = (sy + y, sv + v[0], syy + y * y, syv + y * v[0], n + 1.0);
    }
    let slope = (n * syv - sy * sv) / (n * syy - sy * sy);
    assert!(
        (slope - rate).abs() <= 0.03 * rate,
        "slope {slope:e}, ed12 {rate:e}"
    );
}

/// Bad averaging input is refused with its place.
#[test]
fn field_refuses_bad_averages() {
    for (line, want) in [
        ("field 2 2 2 1e-3 average 0 3", "`k` must be at least 1"),
        ("field 2 2 2 1e-3 average 5", "needs an integer `m`"),
        ("field 2 2 2 1e-3 csv csv", "given twice"),
        ("field 2 2 2 1e-3 average 5 2 average 5 2", "given twice"),
    ] {
        let run = trubal_json(&format!("start 1e-3 1e-3 1e-3 10 10 1\n{line}\n"), &[]);
        assert!(!run.ok, "{line}");
        assert!(run.stderr.contains("<stdin>:2:"), "{line}: {}", run.stderr);
        assert!(run.stderr.contains(want), "{line}: {}", run.stderr);
    }
}

/// The box kernel is `Window` + `PRint Stress` on every bin: the packing of [`PACKED`]
/// (100 spheres compressed to 20 kPa in a periodic cell, contacts across its sides), then
/// `FIEld 2 3 2 BIN IN …` on a box inside the cell and a `Window` + `PRint Stress` on each
/// of its 12 cells: the contact stress is the window's to round-off (the same particles,
/// contacts, contact points, volume: Pasha 2013 (5.1)); the kinetic stress plus ρVV (the
/// field's is taken about the local mean velocity) is the window's Σ m v v / V; a cell has
/// mass exactly when its window holds particles.
#[test]
fn field_bin_kernel_is_window_and_print_stress_on_each_bin() {
    let (lo, hi, n) = ([0.0, 1e-4, 0.0], [1e-3, 9e-4, 1e-3], [2usize, 3, 2]);
    let mut s = String::from(PACKED);
    s.push_str(&format!(
        "cycle 50\nfield {} {} {} bin in {:?} {:?} {:?} {:?} {:?} {:?}\n",
        n[0], n[1], n[2], lo[0], hi[0], lo[1], hi[1], lo[2], hi[2]
    ));
    let edge = |k: usize, a: usize| lo[k] + a as f64 * (hi[k] - lo[k]) / n[k] as f64;
    for c in 0..n[2] {
        for b in 0..n[1] {
            for a in 0..n[0] {
                s.push_str(&format!(
                    "window {:?} {:?} {:?} {:?} {:?} {:?}\nprint stress\n",
                    edge(0, a),
                    edge(0, a + 1),
                    edge(1, b),
                    edge(1, b + 1),
                    edge(2, c),
                    edge(2, c + 1)
                ));
            }
        }
    }
    let run = trubal_json(&s, &[]);
    assert!(run.ok, "{}", run.stderr);
    let fl = &fields(&run)[0];
    assert_eq!(fl["kernel"], "bin");
    let dv: f64 = (0..3).map(|k| (hi[k] - lo[k]) / n[k] as f64).product();
    let windows = printed(&run, "stress");
    assert_eq!(windows.len(), 12);
    let scale = windows
        .iter()
        .flat_map(|w| (0..9).map(move |k| f(&w["window"]["contact"][k / 3][k % 3]).abs()))
        .fold(0.0, f64::max);
    assert!(scale > 10.0, "{scale}");
    let mut filled = 0;
    for (node, w) in windows.iter().enumerate() {
        let w = &w["window"];
        filled += (w["particles"].as_u64().unwrap() > 0) as usize;
        let rho = f(&fl["density"][node]);
        let v: Vec<f64> = (0..3).map(|k| f(&fl["velocity"][node][k])).collect();
        for k in 0..9 {
            let (i, j) = (k / 3, k % 3);
            let c = f(&fl["stress_contact"][node][k]);
            let want = f(&w["contact"][i][j]);
            assert!(
                (c - want).abs() <= 1e-12 * scale,
                "node {node} [{i}][{j}]: {c:e} {want:e}"
            );
            let kin = f(&fl["stress_kinetic"][node][k]) + rho * v[i] * v[j];
            let want = f(&w["kinetic"][i][j]);
            assert!(
                (kin - want).abs() <= 1e-12 * want.abs().max(1e-300) + 1e-18,
                "node {node} kinetic [{i}][{j}]: {kin:e} {want:e}"
            );
        }
        // Mass in the cell exactly when the window holds particles.
        assert_eq!(
            rho * dv > 0.0,
            w["particles"].as_u64().unwrap() > 0,
            "node {node}"
        );
    }
    assert!(filled >= 6, "{filled} bins hold particles");
}

/// `BIN` and `IN` refused where they do not fit, with their place.
#[test]
fn field_refuses_bad_bins() {
    for (line, want) in [
        (
            "field 2 2 2 1e-3 in 0 1e-3 0 1e-3 0 1e-3",
            "box kernel only",
        ),
        ("field 2 2 2 bin lucy", "one of the two"),
        ("field 2 2 2 bin in 0 1e-3 0 1e-3 0", "needs"),
        (
            "field 2 2 2 bin in 0 1e-3 1e-3 0 0 1e-3",
            "must not be below",
        ),
        ("field 2 2 2 bin in 0 0 0 1e-3 0 1e-3", "positive size"),
        (
            "field 2 2 2 bin in 0 1 0 1 0 1 in 0 1 0 1 0 1",
            "given twice",
        ),
    ] {
        let run = trubal_json(&format!("start 1e-3 1e-3 1e-3 10 10 1\n{line}\n"), &[]);
        assert!(!run.ok, "{line}");
        assert!(run.stderr.contains("<stdin>:2:"), "{line}: {}", run.stderr);
        assert!(run.stderr.contains(want), "{line}: {}", run.stderr);
    }
}
