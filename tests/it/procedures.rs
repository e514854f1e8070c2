//! Procedures written in the command language (doc/language.md, issue 54 item 7), against
//! what they replace: Pasha's ball indentation (`scripts/pasha_indent_lang.tru`) against the
//! hardness `scripts/pasha_indent.py` gave on the same small case (its JSON summaries in
//! doc/data, with provenance), and Lian's ch. 6 velocity loop
//! (`scripts/lian_ch6_velocities.tru`) against the single-velocity file
//! (`scripts/lian_ch6_impact.tru`) run once per velocity.

use std::path::{Path, PathBuf};

use serde_json::Value;

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// A fresh, empty directory.
fn fresh(tag: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("trubal-proc-{}-{tag}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// `trubal --json scripts/FILE --set k=v ...` in `dir`: its standard output; panics with the
/// standard error if it fails.
fn run_script(dir: &Path, file: &str, sets: &[(&str, String)]) -> String {
    let mut c = crate::common::trubal();
    c.current_dir(dir).arg("--json");
    for (k, v) in sets {
        c.arg("--set").arg(format!("{k}={v}"));
    }
    let o = c.arg(root().join("scripts").join(file)).output().unwrap();
    let (out, err) = (
        String::from_utf8_lossy(&o.stdout).into_owned(),
        String::from_utf8_lossy(&o.stderr).into_owned(),
    );
    assert!(o.status.success(), "{file}: {err}\n{out}");
    out
}

/// The JSON lines of a run.
fn objects(out: &str) -> impl Iterator<Item = Value> + '_ {
    out.lines()
        .filter_map(|l| serde_json::from_str::<Value>(l).ok())
}

/// The numbers of every `SHow` line whose first item is the text `label`.
fn shown(out: &str, label: &str) -> Vec<Vec<f64>> {
    objects(out)
        .filter_map(|v| v.get("show").and_then(|s| s.as_array().cloned()))
        .filter(|row| row.first().and_then(|v| v.as_str()) == Some(label))
        .map(|row| {
            row[1..]
                .iter()
                .map(|v| v.as_f64().unwrap_or(f64::NAN))
                .collect()
        })
        .collect()
}

/// The small case of both drivers: Pasha's particles (Table 5.1, d_p = 1 mm) in an 8 mm die,
/// a 4 mm bed (182 particles), a 4 mm indenter, E / 1000, 10 / s, modified JKR with EDEM's
/// friction bound and rolling friction 0.1, settled under 5 g, consolidated to 10 kPa and
/// unloaded at once (Pasha's procedure, `--hold 0`).
const SMALL: &[(&str, &str)] = &[
    ("scale", "1"),
    ("soften", "1000"),
    ("d", "4e-3"),
    ("rate", "10"),
    ("sigma", "1e4"),
    ("hmax", "0.6"),
    ("die", "8e-3"),
    ("bed", "4e-3"),
    ("law", "mjkr edem"),
    ("mur", "0.1"),
    ("gsettle", "5"),
    ("hold", "0"),
    ("unload", "10"),
];

/// The seeds of the reference runs (doc/data/pasha_indent_small_s{K}.json; `--seed K`
/// discards K x 10^7 random numbers). Seed 1's generation placed 147 of the 182 particles
/// (RGEnerate gave up): another case, not a reference.
const SEEDS: &[u32] = &[0, 2, 3, 4, 5, 6];

/// The command file gives the hardness of `pasha_indent.py` on the same case: within three
/// standard deviations of the scatter over the script's seeds (the two do not cycle in the
/// same pieces, so their beds part at the first rounding and are two draws of one bed).
#[test]
fn the_indentation_command_file_gives_the_script_s_hardness() {
    let refs: Vec<Value> = SEEDS
        .iter()
        .map(|k| {
            let p = root().join(format!("doc/data/pasha_indent_small_s{k}.json"));
            let text = std::fs::read_to_string(&p).unwrap_or_else(|e| panic!("{p:?}: {e}"));
            serde_json::from_str(&text).unwrap()
        })
        .collect();
    // The references are this case.
    for r in &refs {
        assert_eq!(r["d"], 0.004);
        assert_eq!(r["die"], 0.008);
        assert_eq!(r["soften"], 1000.0);
        assert_eq!(r["rate"], 10.0);
        assert_eq!(r["law"], "mjkr edem");
        assert_eq!(r["hold"], 0);
        assert_eq!(
            r["particles"], 182,
            "every reference bed has the case's particles"
        );
    }
    let h: Vec<f64> = refs
        .iter()
        .map(|r| r["hardness_plateau_kpa"].as_f64().unwrap())
        .collect();
    let n = h.len() as f64;
    let mean = h.iter().sum::<f64>() / n;
    let sd = (h.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / (n - 1.0)).sqrt();
    assert!(mean > 0.0 && sd > 0.0, "{h:?}");

    let dir = fresh("pasha");
    let mut sets: Vec<(&str, String)> = SMALL.iter().map(|(k, v)| (*k, v.to_string())).collect();
    sets.push(("seed", "0".into()));
    let out = run_script(&dir, "pasha_indent_lang.tru", &sets);
    // The same particles as the script's (the count is arithmetic of the same table).
    let bed = &shown(&out, "bed")[0];
    assert_eq!(bed[0], refs[0]["particles"].as_f64().unwrap());
    // The piston reached 10 kPa x the die's area.
    let area = std::f64::consts::PI * 0.004f64.powi(2);
    let cons = &shown(&out, "consolidated")[0];
    assert!(cons[0] >= 1e4 * area, "{cons:?}");
    let hard = &shown(&out, "hardness_kpa")[0];
    assert!(hard[2] >= 5.0, "records in the plateau: {hard:?}");
    assert!(
        (hard[0] - mean).abs() <= 3.0 * sd,
        "H = {} kPa from the command file; pasha_indent.py {h:?} kPa: mean {mean}, sd {sd}",
        hard[0]
    );
    // The indenter came back up to no load.
    assert_eq!(shown(&out, "unload_depth").len(), 1);
    assert!(dir.join("pasha_consolidation_lang.csv").exists());
    let _ = std::fs::remove_dir_all(&dir);
}

/// The velocity loop gives, velocity by velocity, the bits of the single-velocity file on
/// the same prepared state and wall: the loop's RESTart, commands and Cycle are those of
/// `lian_ch6_impact.tru` (one Cycle of 4 n in pieces where the file has four of n: the same
/// bits, doc/language.md), and the velocities v1 + k dv are the numbers the file reads.
#[test]
fn the_velocity_loop_gives_the_single_impacts_bits() {
    let dir = fresh("lian");
    // A reduced agglomerate (274 particles), prepared once.
    let prep = [
        ("ra", "250e-6".to_string()),
        ("state", "prep.sav".into()),
        ("box", "2.2e-3".into()),
        ("nbox", "27000".into()),
        ("centre", "1.0478907385791707e-3".into()),
    ];
    run_script(&dir, "lian_ch6_prepare.tru", &prep);
    let common = [
        ("state", "prep.sav".to_string()),
        ("eta", "0".into()),
        ("frac", "0.5".into()),
        ("n", "2000".into()),
    ];
    let mut sets = common.to_vec();
    sets.extend([
        ("v1", "0.5".into()),
        ("v2", "2.5".into()),
        ("dv", "1".into()),
    ]);
    let out = run_script(&dir, "lian_ch6_velocities.tru", &sets);
    let wall = shown(&out, "wall")[0][0];
    let rows = shown(&out, "impact");
    assert_eq!(rows.len(), 3);
    let mut ratios = Vec::new();
    for (k, row) in rows.iter().enumerate() {
        let v = 0.5 + k as f64;
        assert_eq!(row[0], v);
        let mut one = common.to_vec();
        one.extend([("wall", format!("{wall}")), ("v", format!("{v}"))]);
        let single = run_script(&dir, "lian_ch6_impact.tru", &one);
        let last = |kind: &str| {
            objects(&single)
                .filter(|o| o["print"] == kind)
                .last()
                .unwrap_or_else(|| panic!("no PRint {kind}"))
        };
        let want = [
            last("bonds")["damage_ratio"].as_f64().unwrap(),
            last("clusters")["largest"].as_f64().unwrap(),
            last("info")["lost"].as_f64().unwrap(),
            last("energy")["kinetic"].as_f64().unwrap(),
        ];
        for (j, w) in want.iter().enumerate() {
            assert_eq!(
                row[j + 1].to_bits(),
                w.to_bits(),
                "v = {v}, item {j}: {row:?} vs {want:?}"
            );
        }
        // Its history of the damage ratio: every n / 10 cycles, 40 rows in 4 n.
        let csv = std::fs::read_to_string(dir.join(format!("lian_ch6_v{v}.csv"))).unwrap();
        assert_eq!(csv.lines().count(), 1 + 40, "{csv}");
        ratios.push(row[1]);
    }
    // Lian's threshold (0.35-0.98 m/s for the full agglomerate): more damage the faster.
    assert!(ratios[0] < ratios[1] && ratios[1] < ratios[2], "{ratios:?}");
    let _ = std::fs::remove_dir_all(&dir);
}
