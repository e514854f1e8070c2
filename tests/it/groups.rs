//! Ranges and groups (doc/groups.md), through the binary: which particles each condition
//! selects (against the positions, ids and types `PRint Balls` shows), the sums and averages
//! of `PRint GROup` against closed forms (masses from the densities, a rigid translation, a
//! bed's weight on its floor, spins' kinetic energy), static against dynamic groups, the
//! commands that act on a range (Fix, DELete, VELocity, PROperty), the history's group
//! columns, SAve/RESTart bitwise, and located errors that change nothing.

use crate::common::*;
use serde_json::Value;
use std::f64::consts::PI;

/// 125 spheres of radius 0.2 mm on a 5 × 5 × 5 lattice of step 2 mm (centres at 1, 3, 5, 7,
/// 9 mm), at rest, none touching; material 2 is steel-dense.
const LATTICE: &str = "start 0.01 0.01 0.01 10 200 2\nset open z\nrad 2e-4 1\nymd 1e8 1\n\
    pra 0.3 1\ndensity 2500 1\nymd 1e8 2\npra 0.3 2\ndensity 7800 2\n\
    agenerate 1 1 0 1e-3 1e-3 1e-3 2e-3 2e-3 2e-3\n";

const R: f64 = 2e-4;

fn num(v: &Value) -> f64 {
    v.as_f64().unwrap_or_else(|| panic!("not a number: {v}"))
}

fn mass(rho: f64) -> f64 {
    rho * 4.0 / 3.0 * PI * R.powi(3)
}

/// (id, position, material) of every particle of a `PRint Balls` object.
fn balls(b: &Value) -> Vec<(u64, [f64; 3], u64)> {
    b["balls"]
        .as_array()
        .unwrap()
        .iter()
        .map(|p| {
            let x = &p["pos"];
            (
                p["id"].as_u64().unwrap(),
                [num(&x[0]), num(&x[1]), num(&x[2])],
                p["material"].as_u64().unwrap(),
            )
        })
        .collect()
}

fn run_ok(script: &str) -> Run {
    let run = trubal_json(script, &[]);
    assert!(run.ok, "{}\n{}", run.stderr, run.stdout);
    run
}

#[test]
fn each_condition_selects_the_particles_its_geometry_and_types_say() {
    let script = format!(
        "{LATTICE}property material 2 id 1 to 25\n\
         group b box 0 0.004 0 0.01 0.002 0.006\n\
         group s sphere 0.005 0.005 0.005 0.0025\n\
         group c cylinder 0.005 0.005 0 0 0 1 0.0015\n\
         group i id 3 7 to 9 100\n\
         group m material 2\n\
         group n not box 0 0.004 0 1 0 1 or id 1\n\
         group x group s not group c\n\
         group y size 1 not material 2\n\
         print balls group all\n"
    );
    let run = run_ok(&script);
    let all = balls(&printed(&run, "balls")[0]);
    assert_eq!(all.len(), 125);
    let groups = &printed(&run, "groups")[0]["groups"];
    let c = [0.005, 0.005, 0.005];
    let d2 = move |x: &[f64; 3], k: std::ops::Range<usize>| -> f64 {
        k.map(|k| (x[k] - c[k]).powi(2)).sum()
    };
    type Test = Box<dyn Fn(u64, &[f64; 3], u64) -> bool>;
    let in_box = |x: &[f64; 3]| x[0] <= 0.004 && x[2] >= 0.002 && x[2] <= 0.006;
    let sphere = move |x: &[f64; 3]| d2(x, 0..3) <= 0.0025f64.powi(2);
    let cyl = move |x: &[f64; 3]| d2(x, 0..2) <= 0.0015f64.powi(2);
    let want: Vec<(&str, Test)> = vec![
        ("b", Box::new(move |_, x, _| in_box(x))),
        ("s", Box::new(move |_, x, _| sphere(x))),
        ("c", Box::new(move |_, x, _| cyl(x))),
        ("i", Box::new(|id, _, _| [3, 7, 8, 9, 100].contains(&id))),
        ("m", Box::new(|_, _, m| m == 2)),
        ("n", Box::new(|id, x, _| x[0] > 0.004 || id == 1)),
        ("x", Box::new(move |_, x, _| sphere(x) && !cyl(x))),
        ("y", Box::new(|_, _, m| m != 2)),
    ];
    for (k, (name, test)) in want.iter().enumerate() {
        let g = &groups[k];
        assert_eq!(g["name"], *name);
        let sel: Vec<_> = all.iter().filter(|(id, x, m)| test(*id, x, *m)).collect();
        assert!(!sel.is_empty() && sel.len() < 125, "{name}: {}", sel.len());
        assert_eq!(g["count"].as_u64().unwrap() as usize, sel.len(), "{name}");
        // The mass from the two densities, and the centre of mass from the positions.
        let m = |mat: u64| mass(if mat == 2 { 7800.0 } else { 2500.0 });
        let total: f64 = sel.iter().map(|(_, _, mat)| m(*mat)).sum();
        assert!(rel(num(&g["mass"]), total) < 1e-12, "{name}: {g}");
        for k in 0..3 {
            let mx: f64 = sel.iter().map(|(_, x, mat)| m(*mat) * x[k]).sum::<f64>() / total;
            assert!(
                (num(&g["centre"][k]) - mx).abs() < 1e-15,
                "{name} centre {k}: {g}"
            );
        }
        assert_eq!(g["kinetic"], 0.0);
    }
    // The cylinder is infinitely long: a whole column of 5 above and below its centre.
    assert_eq!(groups[2]["count"], 5);
    // Material 2 is the first 25 ids: the lattice's first 25 sites.
    assert_eq!(groups[4]["count"], 25);
}

/// A rigid translation at 1 m/s down: a static group keeps its particles and its centre of
/// mass moves as z0 - t, a dynamic box loses each layer as its centre leaves the box.
#[test]
fn a_static_group_follows_its_particles_and_a_dynamic_one_its_box() {
    let script = format!(
        "{LATTICE}group top box 0 0.01 0 0.01 0.006 0.01\n\
         group topd dynamic box 0 0.01 0 0.01 0.006 0.01\n\
         velocity 0 0 -1 id 1 to 125\n\
         set history 100\ngroup top history\ngroup topd history\n\
         cycle 2500\nprint group top group topd history\n"
    );
    let run = run_ok(&script);
    assert!(run.stdout.contains("velocity set for 125 particles"));
    let st = &printed(&run, "group")[0];
    let dy = &printed(&run, "group")[1];
    assert_eq!(
        (st["kind"].as_str(), dy["kind"].as_str()),
        (Some("static"), Some("dynamic"))
    );
    let h = &printed(&run, "history")[0];
    let cols: Vec<&str> = h["columns"]
        .as_array()
        .unwrap()
        .iter()
        .map(|c| c.as_str().unwrap())
        .collect();
    let col = |name: &str| cols.iter().position(|c| *c == name).unwrap();
    let rows = h["rows"].as_array().unwrap();
    assert_eq!(rows.len(), 25);
    let mut lost = Vec::new();
    for r in rows {
        let t = num(&r[col("time")]);
        assert_eq!(num(&r[col("top.count")]), 50.0);
        // Layers at 7 and 9 mm start in the box [6, 10] mm.
        let z = 8e-3 - t;
        assert!(
            (num(&r[col("top.z")]) - z).abs() < 1e-12,
            "t {t}: {}",
            num(&r[col("top.z")])
        );
        assert_eq!(num(&r[col("top.vz")]), -1.0);
        assert!(rel(num(&r[col("top.kinetic")]), 0.5 * 50.0 * mass(2500.0)) < 1e-12);
        if (t - 1e-3).abs() > 1e-9 && (t - 3e-3).abs() > 1e-9 {
            let layers = [7e-3, 9e-3].iter().filter(|&&z0| z0 - t >= 6e-3).count();
            assert_eq!(num(&r[col("topd.count")]), 25.0 * layers as f64, "t {t}");
        }
        lost.push(num(&r[col("topd.count")]) as u32);
    }
    // The run passes t = 1 mm / (1 m/s): the lower layer leaves the dynamic box.
    assert_eq!((lost[0], *lost.last().unwrap()), (50, 25), "{lost:?}");
    assert_eq!(st["count"], 50);
    assert_eq!(dy["count"], 25);
}

/// Three spheres resting on a floor under gravity: their contact force sum carries their
/// weight (3 m g), and the floor feels the opposite.
#[test]
fn the_force_sum_of_a_resting_group_carries_its_weight() {
    let script = "start 0.004 0.004 0.004 10 20 2\nset open z\nrad 2e-4 1\nymd 1e8 1\n\
        pra 0.3 1\ndensity 2500 1\ndamping restitution 0.2 1\ngravity 0 0 -9.81\n\
        dwall p 0 0 1 0\n\
        create 0.001 0.001 0.0002 0 0 0 0 0 0 1 1\n\
        create 0.002 0.002 0.0002 0 0 0 0 0 0 1 1\n\
        create 0.003 0.003 0.0002 0 0 0 0 0 0 1 1\n\
        create 0.003 0.001 0.003 0 0 0 0 0 0 1 1\n\
        group rest id 1 to 3\ncycle 20000\nprint group rest walls\n";
    let run = run_ok(script);
    let g = &printed(&run, "group")[0];
    let w = 3.0 * mass(2500.0) * 9.81;
    assert!(rel(num(&g["force"][2]), w) < 1e-3, "{g} vs {w}");
    assert!(num(&g["force"][0]).abs() < 1e-9 * w && num(&g["force"][1]).abs() < 1e-9 * w);
    // (The fourth sphere is still falling: only the three push on the floor.)
    let walls = &printed(&run, "walls")[0]["walls"][0];
    assert!(
        rel(-num(&walls["force"][2]), num(&g["force"][2])) < 1e-9,
        "{walls}"
    );
    assert_eq!(g["coordination"], 0.0);
}

/// A chain of three touching spheres: the middle one has two neighbours, the ends one.
#[test]
fn coordination_counts_touching_neighbours_in_or_out_of_the_group() {
    let script = "start 0.004 0.004 0.004 10 20 2\nrad 2e-4 1\nymd 1e8 1\npra 0.3 1\n\
        density 2500 1\n\
        create 0.001 0.002 0.002 0 0 0 0 0 0 1 1\n\
        create 0.0014 0.002 0.002 0 0 0 0 0 0 1 1\n\
        create 0.0018 0.002 0.002 0 0 0 0 0 0 1 1\n\
        print range id 2 range id 1 range id 1 to 3 chist\n";
    let run = run_ok(script);
    let r = printed(&run, "range");
    assert_eq!(r.len(), 3);
    assert_eq!(r[0]["coordination"], 2.0);
    assert_eq!(r[1]["coordination"], 1.0);
    assert!((num(&r[2]["coordination"]) - 4.0 / 3.0).abs() < 1e-15);
    assert_eq!(r[2]["range"], "ID 1 TO 3");
    assert_eq!(r[2]["name"], Value::Null);
}

/// Fix over a group under gravity: its particles stay where they are, the others fall as
/// ½ g t²; DELete, PROperty MATerial and SPIn over groups change what they say.
#[test]
fn fix_delete_and_properties_act_on_the_range() {
    let script = format!(
        "{LATTICE}gravity 0 0 -9.81\ngroup held box 0 0.01 0 0.01 0 0.002\n\
         group free not group held\nfix 1 1 1 1 1 1 group held\n\
         print group held group free\ncycle 1000\nprint group held group free info\n\
         property material 2 group held\nproperty spin 0 0 100 group held\n\
         print group held\ndelete group free\nprint info group all\n"
    );
    let run = run_ok(&script);
    let g = printed(&run, "group");
    let (h0, f0, h1, f1, h2) = (&g[0], &g[1], &g[2], &g[3], &g[4]);
    assert_eq!(
        (h0["count"].as_u64(), f0["count"].as_u64()),
        (Some(25), Some(100))
    );
    assert_eq!(h0["centre"], h1["centre"]);
    assert_eq!(h1["velocity"], serde_json::json!([0.0, 0.0, 0.0]));
    let t = num(&printed(&run, "info")[0]["time"]);
    let fall = num(&f0["centre"][2]) - num(&f1["centre"][2]);
    let free_fall = 0.5 * 9.81 * t * t;
    assert!(rel(fall, free_fall) < 2e-3, "fell {fall}, ½gt² {free_fall}");
    // Steel-dense now: 7800/2500 of the mass; spinning at 100 rad/s about z.
    assert!(rel(num(&h2["mass"]), 25.0 * mass(7800.0)) < 1e-12);
    let spin = 25.0 * 0.5 * 0.4 * mass(7800.0) * R * R * 1e4;
    assert!(rel(num(&h2["kinetic"]), spin) < 1e-12, "{h2}");
    assert!(run.stdout.contains("deleted 100 particles; 25 remain"));
    let info = &printed(&run, "info")[1];
    assert_eq!(info["balls"], 25);
    let all = &printed(&run, "groups")[0]["groups"];
    assert_eq!(all[0]["count"], 25);
    assert_eq!(all[1]["count"], 0);
    assert_eq!(all[1]["centre"], serde_json::json!([null, null, null]));
}

/// Groups are saved: the same run continued and restarted prints the same bits (the
/// group columns of the history included).
#[test]
fn groups_continue_bitwise_across_save_and_restart() {
    let script = format!(
        "{LATTICE}gravity 0 0 -9.81\ndwall p 0 0 1 0\nset history 50\n\
         group low box 0 0.01 0 0.01 0 0.004\ngroup lowd dynamic box 0 0.01 0 0.01 0 0.004\n\
         group low history\ngroup lowd history\ncycle 300\nsave g.sav\ncycle 300\n\
         print group all history\nnew\nrestart g.sav\ncycle 300\nprint group all history\n"
    );
    let run = run_ok(&script);
    let g = printed(&run, "groups");
    let h = printed(&run, "history");
    assert_eq!(g.len(), 2);
    assert_eq!(g[0], g[1]);
    assert_eq!(h[0], h[1]);
    assert_eq!(h[0]["columns"].as_array().unwrap().len(), 21 + 2 * 13);
}

/// Bad ranges and groups are refused at their line and column, and change nothing.
#[test]
fn bad_ranges_are_refused_where_they_are_and_change_nothing() {
    let mut s = session(&format!(
        "{LATTICE}group a box 0 0.01 0 0.01 0 0.002\ngroup d dynamic group a\n"
    ));
    let before = |s: &trubal::session::Session| {
        let sc = s.scene.as_ref().unwrap();
        (
            format!("{:?}", sc.groups()),
            sc.particles().len(),
            format!("{:?}{:?}", sc.particles().fixed, sc.particles().vel),
        )
    };
    let b0 = before(&s);
    for (line, col, want) in [
        ("group a box 0 1 0 1 1 0", 23, "`z2` must not be below `z1`"),
        (
            "fix 1 1 1 0 0 0 group nope",
            1,
            "group `nope` is not defined",
        ),
        ("group 9x id 1", 7, "is not a group name"),
        ("group all id 1", 7, "`ALL` is not a group name"),
        ("group b not", 9, "NOT needs a condition"),
        ("group b or id 1", 9, "OR needs a condition before it"),
        ("group b id 1 or", 14, "OR needs a condition after it"),
        ("group b id 5 to 2", 17, "the last id is below the first"),
        ("group b cylinder 0 0 0 0 0 0 1", 24, "the axis"),
        ("group b sphere 0 0 0 -1", 22, "must be positive"),
        ("group b material 99", 18, "between 1 and 64"),
        ("group b", 8, "needs a range here"),
        (
            "group a dynamic group d",
            1,
            "would contain itself: a -> d -> a",
        ),
        ("group a forget", 1, "named by the dynamic group(s) d"),
        (
            "delete sphere 0.5 0.5 0.5 0.001",
            1,
            "no particle is in the range",
        ),
        (
            "property material 2 id 999",
            1,
            "no particle is in the range",
        ),
        (
            "property material 3 id 1",
            1,
            "material type 3 is not defined",
        ),
        ("property colour 1 id 1", 10, "unknown property"),
        ("velocity 0 0 1 group zz", 1, "group `zz` is not defined"),
        ("print info group nope", 1, "group `nope` is not defined"),
        ("group b box 0 1 0 1 0 1 cycle x", 31, "expected an integer"),
    ] {
        let e = s.run_line(line).expect_err(line);
        assert!(e.message.contains(want), "{line}: {}", e.message);
        let at = line[..e.start].chars().count() + 1;
        assert_eq!(at, col, "{line}: {}", e.message);
        assert_eq!(before(&s), b0, "{line} changed the scene");
    }
    // Through the binary: the file, line and column.
    let run = trubal_json(&format!("{LATTICE}\nfix 1 1 1 0 0 0 group nope\n"), &[]);
    assert!(!run.ok);
    assert!(
        run.stderr
            .contains(":12:1: error: group `nope` is not defined"),
        "{}",
        run.stderr
    );
    // A PRint that fails prints nothing of its other items.
    let run = trubal_json(&format!("{LATTICE}print info range group nope\n"), &[]);
    assert!(printed(&run, "info").is_empty(), "{}", run.stdout);
}

/// Redefining a group keeps its place and its history rows; forgetting it frees its name.
#[test]
fn a_group_redefined_keeps_its_place_and_forgotten_is_gone() {
    let script = format!(
        "{LATTICE}group a id 1\ngroup b id 2\ngroup a id 1 to 10\nprint group all\n\
         group a forget\nprint group all\n"
    );
    let run = run_ok(&script);
    let g = printed(&run, "groups");
    let names = |v: &Value| -> Vec<String> {
        v["groups"]
            .as_array()
            .unwrap()
            .iter()
            .map(|g| g["name"].as_str().unwrap().to_string())
            .collect()
    };
    assert_eq!(names(&g[0]), ["a", "b"]);
    assert_eq!(g[0]["groups"][0]["count"], 10);
    assert_eq!(names(&g[1]), ["b"]);
}

/// Recording groups in the history keeps the forces of the steps it records in the particle
/// arrays: the run is the same to the bit as without the groups.
#[test]
fn recording_groups_changes_no_result() {
    let base = format!(
        "{LATTICE}damping restitution 0.5 1\ngravity 0 0 -1000\ndwall p 0 0 1 0\nset history 7\n"
    );
    let tail = "cycle 2000\nprint balls energy\n";
    let plain = run_ok(&format!("{base}{tail}"));
    let grouped = run_ok(&format!(
        "{base}group low box 0 0.01 0 0.01 0 0.004\ngroup lowd dynamic box 0 0.01 0 0.01 0 0.004\n\
         group low history\ngroup lowd history\n{tail}"
    ));
    assert_eq!(printed(&plain, "balls"), printed(&grouped, "balls"));
    assert_eq!(printed(&plain, "energy"), printed(&grouped, "energy"));
    // (The lowest layer has reached the floor by then: contact forces act in the run.)
    let e = &printed(&grouped, "energy")[0];
    assert!(e["dissipated"]["total"].as_f64().unwrap() > 0.0, "{e}");
}

/// `PLot BALl GROup name`: the group's particles, and only they, in the highlight colour, a
/// legend line naming it, the file named after it; a plot without particles refuses it.
#[test]
fn plot_highlights_a_group() {
    use trubal::lang::command::PlotItem;
    use trubal::plot::picture::colour::HIGHLIGHT;
    let s = session(&format!(
        "{LATTICE}group top box 0 0.01 0 0.01 0.006 0.01\n"
    ));
    let sc = s.scene.as_ref().unwrap();
    let members = sc
        .members(&trubal::sim::range::Range::group("top"))
        .unwrap();
    let ids: Vec<u32> = members.iter().map(|&i| sc.particles().id[i]).collect();
    assert_eq!(ids.len(), 50);
    let m = trubal::plot::Marked {
        label: "top".into(),
        ids: ids.clone(),
    };
    let pic = trubal::plot::picture_marked(sc, &[PlotItem::Ball], Some(&m)).unwrap();
    assert_eq!(pic.discs.len(), 125);
    for d in &pic.discs {
        assert_eq!(
            d.fill == HIGHLIGHT,
            ids.contains(&d.id),
            "particle {}",
            d.id
        );
    }
    assert!(pic.legend.iter().any(|l| l.text == "top: 50 particles"));
    // Through the binary: the file name, and the errors.
    let run = run_ok(&format!(
        "{LATTICE}group top box 0 0.01 0 0.01 0.006 0.01\nplot ball group top\nplot ball id 1 to 3\n"
    ));
    assert!(
        run.stdout
            .contains("plot written to plot_c00000000_ball_top.png"),
        "{}",
        run.stdout
    );
    assert!(
        run.stdout
            .contains("plot written to plot_c00000000_ball_range.png"),
        "{}",
        run.stdout
    );
    let run = trubal_json(&format!("{LATTICE}plot save ball group top\n"), &[]);
    assert!(
        run.stderr
            .contains(":11:1: error: group `top` is not defined"),
        "{}",
        run.stderr
    );
    let run = trubal_json(&format!("{LATTICE}group a id 1\nplot bou group a\n"), &[]);
    assert!(
        run.stderr.contains("give BALl, DISks, CLUster or LCLuster"),
        "{}",
        run.stderr
    );
}

/// `sum(q, g)` and `avg(q, g)` in an expression (doc/language.md) take a group's members:
/// the bottom layer of the lattice (25 spheres) set moving at −2 m/s, the rest at rest; the
/// layer's z are all 1 mm; a group that does not exist is an error naming it.
#[test]
fn expressions_sum_and_average_over_a_group() {
    let run = run_ok(&format!(
        "{LATTICE}group low box 0 0.01 0 0.01 0 0.002\nvelocity 0 0 -2 group low\n\
         show [avg(vz, low)] [sum(vz, low)] [avg(vz)] [sum(z, low)] [avg(m, low)]\n"
    ));
    let shown: Vec<f64> = run
        .stdout
        .lines()
        .filter_map(|l| serde_json::from_str::<Value>(l).ok())
        .find_map(|v| v.get("show").and_then(|s| s.as_array().cloned()))
        .expect("a SHow line")
        .iter()
        .map(num)
        .collect();
    assert_eq!(shown[0], -2.0);
    assert_eq!(shown[1], -50.0);
    assert_eq!(shown[2], -50.0 / 125.0);
    assert!((shown[3] - 25.0 * 1e-3).abs() < 1e-15, "{}", shown[3]);
    assert!(
        (shown[4] / mass(2500.0) - 1.0).abs() < 1e-12,
        "{}",
        shown[4]
    );
    let bad = trubal_json(&format!("{LATTICE}show [avg(vz, nope)]\n"), &[]);
    assert!(!bad.ok);
    assert!(
        bad.stderr.contains("avg(vz, nope)") && bad.stderr.contains("nope"),
        "{}",
        bad.stderr
    );
}

/// The values of every `SHow` line, in order.
fn shown(run: &Run) -> Vec<Vec<f64>> {
    run.stdout
        .lines()
        .filter_map(|l| serde_json::from_str::<Value>(l).ok())
        .filter_map(|v| v.get("show").and_then(|s| s.as_array().cloned()))
        .map(|row| row.iter().filter_map(|v| v.as_f64()).collect())
        .collect()
}

/// A Fix over a dynamic group stands: a sphere falling from rest under g into a dynamic box
/// fixed before it arrives keeps the velocity it entered with, −√(2 g Δz), while its centre
/// is in the box, then falls freely again, its velocity changing by −g t from the exit
/// (t_exit = t_entry + height / speed); a SAve and RESTart while it is in the box continues
/// with the same bits (the standing Fix is in the checkpoint).
#[test]
fn a_fix_over_a_dynamic_group_fixes_the_particles_that_enter_it() {
    let (z0, top, bottom, g): (f64, f64, f64, f64) = (0.038, 0.032, 0.028, 9.81);
    let base = "start 0.01 0.01 0.04 10 10 1\nrad 2e-4 1\nymd 1e8 1\npra 0.3 1\n\
        density 2500 1\nfraction 0.2\ncreate 0.005 0.005 0.038 0 0 0 0 0 0 1 1\ngravity 0 0 -9.81\n\
        group zone dynamic box 0 0.01 0 0.01 0.028 0.032\nfix 1 1 1 1 1 1 group zone\n\
        let saved = 0\n";
    let straight =
        format!("{base}loop k 1 120\n  cycle 500\n  show [time] [ball_z(1)] [ball_vz(1)]\nend\n");
    let a = run_ok(&straight);
    assert!(
        a.stdout
            .contains("the Fix stands on the dynamic group zone"),
        "{}",
        a.stdout
    );
    let rows = shown(&a);
    assert_eq!(rows.len(), 120);
    let t_in = (2.0 * (z0 - top) / g).sqrt();
    let v_in = g * t_in;
    let inside: Vec<&Vec<f64>> = rows
        .iter()
        .filter(|r| r[1] < top - 1e-4 && r[1] > bottom + 1e-4)
        .collect();
    assert!(inside.len() >= 10, "{} records in the box", inside.len());
    for r in &inside {
        assert_eq!(r[2].to_bits(), inside[0][2].to_bits(), "fixed: {r:?}");
    }
    let v = -inside[0][2];
    assert!((v - v_in).abs() < 5e-3 * v_in, "entry speed {v} vs {v_in}");
    let t_out = t_in + (top - bottom) / v;
    let mut before = 0;
    let mut after = 0;
    for r in &rows {
        if r[1] > top + 1e-4 {
            before += 1;
            assert!((r[2] + g * r[0]).abs() < 5e-3 * g * r[0], "free fall {r:?}");
        } else if r[1] < bottom - 1e-4 {
            after += 1;
            let want = -v - g * (r[0] - t_out);
            assert!(
                (r[2] - want).abs() < 5e-3 * want.abs(),
                "after the box {r:?} vs {want}"
            );
        }
    }
    assert!(
        before >= 10 && after >= 10,
        "{before} before, {after} after"
    );
    // SAve and RESTart in the box: the same rows to the bit.
    let restarted = format!(
        "{base}loop k 1 120\n  cycle 500\n  show [time] [ball_z(1)] [ball_vz(1)]\n  \
         if ball_z(1) < 0.031 and saved == 0\n    let saved = 1\n    save \"mid.sav\"\n    \
         new\n    restart \"mid.sav\"\n  end\nend\n"
    );
    let b = run_ok(&restarted);
    let rows_b = shown(&b);
    assert_eq!(rows_b.len(), rows.len());
    for (x, y) in rows.iter().zip(&rows_b) {
        let bits = |r: &Vec<f64>| r.iter().map(|v| v.to_bits()).collect::<Vec<_>>();
        assert_eq!(bits(x), bits(y));
    }
    // All zeros ends the standing Fix.
    let freed = run_ok(&format!(
        "{base}fix 0 0 0 0 0 0 group zone\ncycle 40000\nshow [ball_vz(1)] [time]\n"
    ));
    let r = &shown(&freed)[0];
    assert!((r[0] + g * r[1]).abs() < 5e-3 * g * r[1], "{r:?}");
}

/// In a periodic cell a range wraps across the sides: a sphere, box or cylinder on the side
/// x = 0 of a cell periodic in x selects the particles near x = 0 and those near x = L (their
/// images are near 0); with x open it selects only those inside the cell's side.
#[test]
fn ranges_wrap_across_the_sides_of_a_periodic_cell() {
    let scene = |axis: &str| {
        format!(
            "start 0.01 0.01 0.01 10 20 2\nset {axis} x\nrad 2e-4 1\nymd 1e8 1\npra 0.3 1\n\
             density 2500 1\ncreate 0.0005 0.005 0.005 0 0 0 0 0 0 1 1\n\
             create 0.0095 0.005 0.005 0 0 0 0 0 0 1 1\n\
             create 0.005 0.005 0.005 0 0 0 0 0 0 1 1\n\
             create 0.0085 0.005 0.005 0 0 0 0 0 0 1 1\n\
             group s sphere 0 0.005 0.005 0.001\n\
             group b box -0.001 0.001 0 0.01 0 0.01\n\
             group c cylinder 0 0.005 0 0 0 1 0.001\n\
             group d dynamic sphere 0.01 0.005 0.005 0.001\n\
             print group s group b group c group d\n"
        )
    };
    // The distance of each centre's nearest image from the side x = 0 (or L).
    let xs = [0.0005f64, 0.0095, 0.005, 0.0085];
    let near = |l: f64| xs.iter().filter(|&&x| x.min(l - x) <= 0.001).count() as u64;
    assert_eq!(near(0.01), 2);
    for (axis, want) in [("periodic", near(0.01)), ("open", 1)] {
        let run = run_ok(&scene(axis));
        let g = printed(&run, "group");
        assert_eq!(g.len(), 4, "{axis}");
        for k in 0..4 {
            assert_eq!(
                g[k]["count"].as_u64(),
                Some(want),
                "{axis} {}",
                g[k]["name"]
            );
        }
        // Periodic: the centre of mass of the two is the mean of their positions as the
        // scene holds them (inside the cell), 5 mm.
        if axis == "periodic" {
            assert!((num(&g[0]["centre"][0]) - 0.005).abs() < 1e-15);
        }
    }
}

/// `PLot HIStory` charts the columns of the groups recorded in the history: for a lattice
/// falling freely, the panels of group `top` carry its recorded rows, whose velocity of the
/// centre of mass is −g t and whose last row is `PRint GROup`'s aggregate of the end.
#[test]
fn plot_history_charts_the_group_columns() {
    let s = session(&format!(
        "{LATTICE}gravity 0 0 -9.81\nset history 10\ngroup top box 0 0.01 0 0.01 0.006 0.01\n\
         group top history\ncycle 100\n"
    ));
    let sc = s.scene.as_ref().unwrap();
    let chart = trubal::plot::chart::history_chart(sc).unwrap();
    let titles: Vec<&str> = chart.panels.iter().map(|p| p.title.as_str()).collect();
    assert_eq!(titles.len(), 2 + 5, "{titles:?}");
    assert!(titles.contains(&"group top: velocity of the centre of mass"));
    let series = |name: &str| {
        chart
            .panels
            .iter()
            .flat_map(|p| p.series.iter())
            .find(|s| s.name == name)
            .unwrap_or_else(|| panic!("no series {name}"))
            .points
            .clone()
    };
    let vz = series("top.vz");
    assert_eq!(vz.len(), 10);
    let dt = sc.time() / 100.0;
    for &(cycle, v) in &vz {
        let t = cycle * dt;
        assert!((v + 9.81 * t).abs() < 0.02 * 9.81 * t, "{cycle}: {v}");
    }
    let now = trubal::sim::aggregate::of_group(sc, "top").unwrap();
    assert_eq!(series("top.z").last().unwrap().1, now.value("z").unwrap());
    assert_eq!(series("top.count").last().unwrap().1, 50.0);
    // The picture: at least 250 pixels a panel.
    let png = trubal::plot::png_bytes(sc, &[trubal::lang::command::PlotItem::History]).unwrap();
    let h = u32::from_be_bytes([png[20], png[21], png[22], png[23]]);
    assert!(h >= 7 * 250, "{h}");
}
