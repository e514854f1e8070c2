//! `DELete x1 x2 y1 y2 z1 z2`: the particles whose centres lie in the box go, with their
//! contacts. A settled cohesive bed cut to a height keeps its books closed (the kinetic
//! energy and the contacts' strain energy of the deleted particles leave as work of
//! commands), continues bitwise the same across SAve/Restart, and bad boxes are refused
//! with nothing changed.

use crate::common::*;

/// 153 cohesive spheres (r = 0.2 mm) on a lattice, dropped on a floor under 100 g and
/// left 6,000 steps: the bed touches (136 particle contacts) and still moves.
const BED: &str = "start 0.002 0.002 0.004 10 200 6\nrad 2e-4 1\nymd 1e8 1\npra 0.25 1\n\
    density 2500 1\nfriction 0.3 1\ncohesion 0.05 1\ndamping restitution 0.5 1\n\
    gravity 0 0 -1000\ndwall p 0 0 1 0\n\
    agenerate 1 1 0 2.1e-4 2.1e-4 2.1e-4 4.2e-4 4.2e-4 4.2e-4\ncycle 6000\n";

const CUT: f64 = 1.2e-3;

fn num(v: &serde_json::Value, k: &str) -> f64 {
    v[k].as_f64().unwrap_or_else(|| panic!("{k} in {v}"))
}

#[test]
fn a_bed_cut_to_a_height_keeps_its_books_and_continues_across_a_restart() {
    let deck = format!(
        "{BED}print balls info energy\ndelete 0 0.002 0 0.002 {CUT} 0.004\n\
         print balls info energy\nsave cut.sav\ncycle 3000\nprint balls energy\n\
         new\nrestart cut.sav\ncycle 3000\nprint balls energy\n"
    );
    let run = trubal_json(&deck, &[]);
    assert!(run.ok, "{}", run.stderr);
    let balls = printed(&run, "balls");
    let ids = |b: &serde_json::Value| -> Vec<u64> {
        b["balls"]
            .as_array()
            .unwrap()
            .iter()
            .map(|p| p["id"].as_u64().unwrap())
            .collect()
    };
    // The ones kept are exactly those below the cut, by their printed positions.
    let below: Vec<u64> = balls[0]["balls"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|p| p["pos"][2].as_f64().unwrap() < CUT)
        .map(|p| p["id"].as_u64().unwrap())
        .collect();
    assert!(!below.is_empty() && below.len() < 153, "{}", below.len());
    assert_eq!(ids(&balls[1]), below);
    assert!(
        run.stdout.contains(&format!(
            "deleted {} particles; {} remain",
            153 - below.len(),
            below.len()
        )),
        "{}",
        run.stdout
    );
    let info = printed(&run, "info");
    assert!(num(&info[0], "touching") > num(&info[1], "touching"));
    assert!(num(&info[1], "touching") > 0.0);
    // The cut takes kinetic and strain energy, booked as the command's; the residual moves
    // only by the removed particles' work in flight, ½Δt Σ (F·v + M·ω) with the last step's
    // forces (`Scene::booked_edit`: 7.7e-6 of the input here), two orders below what the
    // cut takes (1e-2 of the input).
    let en = printed(&run, "energy");
    let (e0, e1) = (&en[0], &en[1]);
    let input = num(e0, "input");
    assert!(num(e1, "strain") < 0.9 * num(e0, "strain"));
    assert!(num(e1, "kinetic") < num(e0, "kinetic"));
    let taken = num(e0, "strain") + num(e0, "kinetic") - num(e1, "strain") - num(e1, "kinetic");
    assert!(taken > 1e-3 * input, "taken {taken} of {input}");
    let moved = num(e1, "residual") - num(e0, "residual");
    assert!(
        moved.abs() < 1e-4 * input && moved.abs() < 1e-2 * taken,
        "the residual moved by {moved} (taken {taken}, input {input})"
    );
    assert!(num(&en[2], "residual").abs() < 2e-3 * input);
    // Continued and restarted: the same bits.
    assert_eq!(balls[2]["balls"], balls[3]["balls"]);
    assert_eq!(en[2]["residual"], en[3]["residual"]);
}

#[test]
fn a_bad_or_empty_box_is_refused_and_changes_nothing() {
    let mut s = session(BED);
    let n = s.scene.as_ref().unwrap().particles().len();
    for (line, want) in [
        (
            "delete 0 0.002 0.002 0.001 0 1",
            "`y2` must not be below `y1`",
        ),
        (
            "delete 0 0.002 0 0.002 0.5 0.6",
            "no particle has its centre in the box",
        ),
        ("delete 0 0.002 0 0.002 0", "needs a number `z2`"),
    ] {
        let e = s.run_line(line).expect_err(line);
        assert!(e.message.contains(want), "{line}: {}", e.message);
        assert_eq!(s.scene.as_ref().unwrap().particles().len(), n, "{line}");
    }
    let run = trubal_json("start 1 1 1 10 10 2\n\ndelete 0 1 0.5 0.2 0 1\n", &[]);
    assert!(!run.ok);
    assert!(run.stderr.contains(":3:16:"), "{}", run.stderr);
}
