//! `SET PAIr m1 m2 FRIction mu RESTitution e`: one material pair's own friction and
//! restitution instead of TRUBAL's rule (the smaller of the two materials' values), as
//! Olsson (2017) gave his particle–wall pair (0.35, 0.3). Checked on an oblique impact on a
//! wall against the closed forms of the calibrated dashpot (the rebound speed is e v_n) and of
//! full sliding (Walton's law: Δv_t = μ(1 + e)v_n); bad input refused with its place, nothing
//! changed; kept across SAve/RESTart.

use crate::common;
use common::*;

const HEAD: &str = "start 1e-3 1e-3 1e-3 10 10 2
set open all
rad 50e-6 1
ymd 1e8 1
pra 0.3 1
density 2500 1
friction 0.1 1
damping restitution 0.25 1
ymd 7e10 2
pra 0.3 2
density 2500 2
friction 0.5 2
damping restitution 0.9 2
set tangential walton
";

/// A sphere hits the wall at v_n = 0.5 m/s with v_t = 1 m/s (sliding throughout); returns
/// (restitution, Δv_t / ((1 + e) v_n)) — the latter is μ for full sliding.
fn impact(pair: &str, after: &str) -> (f64, f64) {
    let script = format!(
        "{HEAD}{pair}dwall p 0 0 1 1e-4 m 2\ncreate 5e-4 5e-4 1.5001e-4 1 0 -0.5 0 0 0 1 1\n{after}cycle 200\nprint balls\n"
    );
    let run = trubal_json(&script, &[]);
    assert!(run.stdout.contains("balls"), "{}", run.stderr);
    let b = &printed(&run, "balls")[0]["balls"][0];
    let v = |k: usize| b["vel"][k].as_f64().unwrap();
    let e = v(2) / 0.5;
    (e, (1.0 - v(0)) / ((1.0 + e) * 0.5))
}

#[test]
fn a_pair_gets_its_own_friction_and_restitution() {
    // TRUBAL's rule: the smaller of the materials' values, 0.25 and 0.1.
    let (e, mu) = impact("", "");
    assert!((e - 0.25).abs() < 0.01 * 0.25, "{e}");
    assert!(mu < 0.1 * 1.0001, "{mu}");
    // Olsson's pair values.
    let (e, mu) = impact("set pair 1 2 friction 0.35 restitution 0.6\n", "");
    assert!((e - 0.6).abs() < 0.01 * 0.6, "{e}");
    assert!(mu > 0.9 * 0.35 && mu < 0.35 * 1.0001, "{mu}");
    // One value at a time: a later SET PAIr keeps what it does not give; the order of the
    // materials does not matter; DEFault returns to the rule.
    let (e, mu) = impact(
        "set pair 1 2 friction 0.35\nset pair 2 1 restitution 0.6\n",
        "",
    );
    assert!((e - 0.6).abs() < 0.01 * 0.6 && mu > 0.9 * 0.35, "{e} {mu}");
    let (e, _) = impact("set pair 1 2 restitution 0.6\nset pair 1 2 default\n", "");
    assert!((e - 0.25).abs() < 0.01 * 0.25, "{e}");
    // Kept across SAve/RESTart (checkpoint format 6).
    let (e, mu) = impact(
        "set pair 1 2 friction 0.35 restitution 0.6\n",
        "save pv.sav\nnew\nrestart pv.sav\n",
    );
    assert!((e - 0.6).abs() < 0.01 * 0.6 && mu > 0.9 * 0.35, "{e} {mu}");
}

#[test]
fn bad_pair_input_is_refused_with_its_place_and_changes_nothing() {
    for (line, col, msg) in [
        (
            "set pair 1 2 restitution 1.5",
            26,
            "restitution e must be in (0, 1]",
        ),
        (
            "set pair 1 2 restitution 0",
            26,
            "restitution e must be in (0, 1]",
        ),
        ("set pair 1 2 friction -1", 23, "must not be negative"),
        ("set pair 1 2", 13, "FRIction, RESTitution or DEFault"),
        ("set pair 1", 11, "m2"),
        ("set pair 1 2 default friction 0.3", 34, "give it alone"),
        (
            "set pair 1 9 friction 0.3",
            1,
            "material type 9 is not defined",
        ),
        ("set pair 1 2 friction 0.3 junk", 27, "junk"),
    ] {
        let run = trubal_json(
            &format!("{HEAD}set pair 1 2 restitution 0.6\n{line}\n"),
            &[],
        );
        let want = format!("<stdin>:16:{col}: error");
        assert!(
            run.stderr.contains(&want) && run.stderr.contains(msg),
            "{line}: {}",
            run.stderr
        );
    }
    // Nothing changed: the earlier values still hold after each refusal (--keep-going).
    let script = format!(
        "{HEAD}set pair 1 2 restitution 0.6\nset pair 1 2 restitution 1.5\nset pair 1 9 friction 0.3\n\
         dwall p 0 0 1 1e-4 m 2\ncreate 5e-4 5e-4 1.5001e-4 1 0 -0.5 0 0 0 1 1\ncycle 200\nprint balls\n"
    );
    let run = trubal_json(&script, &["--keep-going"]);
    let b = &printed(&run, "balls")[0]["balls"][0];
    let e = b["vel"][2].as_f64().unwrap() / 0.5;
    assert!((e - 0.6).abs() < 0.01 * 0.6, "{e}: {}", run.stderr);
}
