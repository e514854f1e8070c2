//! `--json`: every PRint item is one JSON object per line, with exactly the keys documented in
//! doc/output.md, and numbers read back to the very same f64 bits.

use std::collections::{BTreeMap, BTreeSet};

use serde_json::Value;
use trubal::lang::command::{ContactsFilter, PrintItem};
use trubal::output::print;
use trubal::sim::{Scene, Vec3, energy};

/// A wet scene with a wall, a reference state and history rows (see tests/it/checkpoint.rs).
const SCENE: &str = "start 0.004 0.004 0.004 100 10 2
set open z
set history 5
rad 100e-6 1
rad 80e-6 2
ymd 1e8 1
pra 0.3 1
density 2500 1
friction 0.3 1
ymd 2e8 2
pra 0.25 2
density 7800 2
friction 0.5 2
damping restitution 0.7 1
liquid 1 0.072 20 0.001
gravity 0 0 -9.81
create 0.0019 0.002 0.0011 0.01 0.05 0 0 0 0 1 1
create 0.0021000001 0.002 0.0011 -0.01 -0.05 0 0 0 0 1 1
create 0.003 0.001 0.00028 0.02 0 -0.01 0 0 300 2 1
create 0.001 0.003 0.0030 0 0 0 100 0 0 1 1
dwall p 0 0 1 0.0002 m 2 se -1e-4 0.001 1e-2";

/// The JSON `print` name of every item (an exhaustive match: a new item must be added here,
/// to doc/output.md and to the documented-keys test).
fn json_name(it: PrintItem) -> &'static str {
    match it {
        PrintItem::Balls => "balls",
        PrintItem::Chist => "chist",
        PrintItem::Contacts(_) => "contacts",
        PrintItem::Energy => "energy",
        PrintItem::Entries => "entries",
        PrintItem::Grid => "grid",
        PrintItem::Info => "info",
        PrintItem::Map => "map",
        PrintItem::Partitions => "partitions",
        PrintItem::Stress => "stress",
        PrintItem::Settings => "settings",
        PrintItem::Walls => "walls",
        PrintItem::Bonds => "bonds",
        PrintItem::Clusters => "clusters",
        PrintItem::History => "history",
        // `PRint GROup name` (`RANge range`: "range"; `GROup ALL`: "groups").
        PrintItem::Range => "group",
    }
}

const ALL_ITEMS: &[PrintItem] = &[
    PrintItem::Info,
    PrintItem::Balls,
    PrintItem::Contacts(ContactsFilter::Loaded),
    PrintItem::Contacts(ContactsFilter::All),
    PrintItem::Contacts(ContactsFilter::Gap),
    PrintItem::Energy,
    PrintItem::Entries,
    PrintItem::Map,
    PrintItem::Stress,
    PrintItem::Partitions,
    PrintItem::Settings,
    PrintItem::Walls,
    PrintItem::Chist,
    PrintItem::Grid,
    PrintItem::Bonds,
    PrintItem::Clusters,
    PrintItem::History,
    PrintItem::Range,
];

/// The words of the PRint command's keyword list, as typed (All/Gap qualify Contacts).
fn print_keywords() -> Vec<&'static str> {
    let def = trubal::lang::table::COMMANDS
        .iter()
        .find(|d| d.name == "PRint")
        .expect("PRint in the table");
    def.keywords.to_vec()
}

fn run_json(script: &str) -> String {
    let dir = std::env::temp_dir().join(format!(
        "trubal-json-{}-{}",
        std::process::id(),
        script.len()
    ));
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(dir.join("run.tru"), script).unwrap();
    let out = crate::common::trubal()
        .args(["run.tru", "--json"])
        .current_dir(&dir)
        .output()
        .unwrap();
    let _ = std::fs::remove_dir_all(&dir);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8(out.stdout).unwrap()
}

/// The lines of output that are JSON (the rest are command messages such as "wall 1 defined").
fn json_lines(out: &str) -> Vec<Value> {
    out.lines()
        .filter(|l| l.starts_with('{'))
        .map(|l| {
            let v: Value = serde_json::from_str(l).unwrap_or_else(|e| panic!("{e}: {l}"));
            assert!(v.is_object(), "{l}");
            v
        })
        .collect()
}

/// Documented fields per table row of doc/output.md, keyed by the `print:"NAME"` values of
/// the row: the lower-case words inside backticks of the fields column, quoted values removed.
fn documented() -> Vec<(Vec<String>, BTreeSet<String>)> {
    let doc =
        std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/doc/output.md")).unwrap();
    let mut rows = Vec::new();
    for line in doc.lines().filter(|l| l.starts_with("| `PRint")) {
        let cells: Vec<&str> = line.split(" | ").collect();
        let fields = cells[1];
        let mut names = Vec::new();
        let mut words = BTreeSet::new();
        for (k, span) in fields.split('`').enumerate() {
            if k % 2 == 0 {
                continue; // outside backticks
            }
            // Drop quoted values (`print:"info"`, `"bridges"`): they are not keys.
            let mut rest = String::new();
            let mut in_q = false;
            for ch in span.chars() {
                if ch == '"' {
                    in_q = !in_q;
                } else if !in_q {
                    rest.push(ch);
                }
            }
            for w in rest.split(|c: char| !(c.is_ascii_alphanumeric() || c == '_')) {
                if w.starts_with(|c: char| c.is_ascii_lowercase()) {
                    words.insert(w.to_string());
                }
            }
        }
        // The item names: `print:"NAME"`, possibly followed by `/`"OTHER"`.
        if let Some(at) = fields.find("print:\"") {
            let rest = &fields[at + 7..];
            let end = rest.find('"').unwrap();
            names.push(rest[..end].to_string());
            if let Some(other) = rest[end..].strip_prefix("\"`/`\"") {
                names.push(other[..other.find('"').unwrap()].to_string());
            }
        }
        assert!(
            !names.is_empty(),
            "doc/output.md row without print:\"NAME\": {line}"
        );
        rows.push((names, words));
    }
    rows
}

/// All object keys in a JSON value (recursively; `geometry` is documented as one opaque value).
fn keys(v: &Value, out: &mut BTreeSet<String>) {
    match v {
        Value::Object(m) => {
            for (k, x) in m {
                out.insert(k.clone());
                if k != "geometry" {
                    keys(x, out);
                }
            }
        }
        Value::Array(a) => a.iter().for_each(|x| keys(x, out)),
        _ => {}
    }
}

#[test]
fn every_print_item_is_one_json_object_per_line_with_the_documented_keys() {
    // Every keyword of PRint, alone, gives exactly one JSON line with its name.
    let kws = print_keywords();
    let items: Vec<&str> = kws
        .iter()
        .copied()
        .filter(|k| !["All", "Gap", "GROup", "RANge"].contains(k))
        .collect();
    // (GROup and RANge take a group or a range: printed below, one item for both.)
    assert_eq!(
        items.len() + 3,
        ALL_ITEMS.len(),
        "PRint keywords vs ALL_ITEMS: {kws:?}"
    );
    let mut script = format!("{SCENE}\nprint bonds\nplot save\ncycle 40\n");
    for k in &items {
        script.push_str(&format!("print {k}\n"));
    }
    script.push_str("print contacts all\nprint contacts gap\n");
    // Several items on one command: one line each.
    script.push_str("print info balls energy\n");
    // PRint Stress with a Window adds the bin's stress (`window`).
    script.push_str("window -1 1 -1 1 -1 1\nprint stress\n");
    // The sums and averages over a group, a range, every group (doc/groups.md).
    script.push_str(
        "group g box -1 1 -1 1 -1 1\nprint group g\nprint range id 1 to 2\nprint group all\n",
    );
    let out = run_json(&script);
    let lines = json_lines(&out);
    let mut expected: Vec<String> = vec!["bonds".into()];
    for k in &items {
        let it = trubal::lang::parse::parse_line(&format!("print {k}")).unwrap();
        let trubal::lang::command::Command::Print { items, .. } = &it[0].command else {
            panic!()
        };
        expected.push(json_name(items[0]).into());
    }
    expected
        .extend(["contacts", "contacts", "info", "balls", "energy", "stress"].map(String::from));
    expected.extend(["group", "range", "groups"].map(String::from));
    let got: Vec<String> = lines
        .iter()
        .map(|v| v["print"].as_str().unwrap().to_string())
        .collect();
    assert_eq!(got, expected, "one object per item, in order:\n{out}");
    // No other non-JSON output than the messages of DWAll/Cycle-less commands.
    for l in out.lines().filter(|l| !l.starts_with('{')) {
        assert!(
            l.starts_with("wall 1 defined") || l.starts_with("group g: "),
            "unexpected line: {l}"
        );
    }

    // Keys: the union over all lines of a row equals the documented fields of that row.
    let mut got_keys: BTreeMap<String, BTreeSet<String>> = BTreeMap::new();
    for v in &lines {
        let name = v["print"].as_str().unwrap().to_string();
        keys(v, got_keys.entry(name).or_default());
    }
    let rows = documented();
    for name in ALL_ITEMS.iter().map(|&i| json_name(i)) {
        let (names, doc_words) = rows
            .iter()
            .find(|(n, _)| n.iter().any(|x| x == name))
            .unwrap_or_else(|| panic!("`{name}` is not documented in doc/output.md"));
        let mut union = BTreeSet::new();
        for n in names {
            union.extend(got_keys.get(n).cloned().unwrap_or_default());
        }
        let undocumented: Vec<_> = union.difference(doc_words).collect();
        let missing: Vec<_> = doc_words.difference(&union).collect();
        assert!(
            undocumented.is_empty() && missing.is_empty(),
            "{names:?}: keys not in doc/output.md {undocumented:?}; documented but not produced {missing:?}"
        );
    }
}

// ---- exact numbers ------------------------------------------------------------------------

fn scene() -> Scene {
    let mut s = crate::common::session_with(Box::new(std::io::sink()), true)
        .with_diagnostics(Box::new(std::io::sink()));
    for l in format!("{SCENE}\nplot save\ncycle 40").lines() {
        s.run_line(l).unwrap();
    }
    s.scene.unwrap()
}

fn json_of(sc: &Scene, it: PrintItem) -> Value {
    // Through the text, as a reader of the output sees it.
    let text = print::item(sc, it).1.to_string();
    assert!(!text.contains('\n'));
    serde_json::from_str(&text).unwrap()
}

fn bits(v: &Value) -> u64 {
    v.as_f64()
        .unwrap_or_else(|| panic!("not a number: {v}"))
        .to_bits()
}

fn same3(v: &Value, x: &Vec3, what: &str) {
    for k in 0..3 {
        assert_eq!(
            bits(&v[k]),
            x[k].to_bits(),
            "{what}[{k}]: {} vs {}",
            v[k],
            x[k]
        );
    }
}

#[test]
fn numbers_round_trip_exactly() {
    let sc = scene();
    let p = &sc.particles();

    let b = json_of(&sc, PrintItem::Balls);
    assert_eq!(bits(&b["time"]), sc.time().to_bits());
    let arr = b["balls"].as_array().unwrap();
    assert_eq!(arr.len(), p.len());
    for (i, ball) in arr.iter().enumerate() {
        assert_eq!(ball["id"], p.id[i]);
        same3(&ball["pos"], &p.pos[i], "pos");
        same3(&ball["vel"], &p.vel[i], "vel");
        same3(&ball["spin"], &p.spin[i], "spin");
        same3(&ball["force"], &p.force[i], "force");
        assert_eq!(bits(&ball["radius"]), p.radius[i].to_bits());
    }

    let e = json_of(&sc, PrintItem::Energy);
    let st = energy::stored(&sc);
    let l = &sc.ledger();
    for (key, x) in [
        ("kinetic_translation", st.kinetic_translation),
        ("kinetic_rotation", st.kinetic_rotation),
        ("strain_normal", st.strain_normal),
        ("strain_tangential", st.strain_tangential),
        ("bridge", st.bridge),
        ("residual", energy::residual(&sc)),
    ] {
        assert_eq!(bits(&e[key]), x.to_bits(), "{key}");
    }
    for (key, x) in [
        ("commands", l.commands),
        ("gravity", l.gravity),
        ("walls", l.walls),
    ] {
        assert_eq!(bits(&e["inputs"][key]), x.to_bits(), "{key}");
    }
    for (key, x) in [
        ("friction", l.friction),
        ("damping_mass", l.damping_mass),
        ("damping_contact", l.damping_contact),
        ("viscous", l.viscous),
        ("adhesion", l.adhesion),
        ("rupture", l.rupture),
    ] {
        assert_eq!(bits(&e["dissipated"][key]), x.to_bits(), "{key}");
    }

    let c = json_of(&sc, PrintItem::Contacts(ContactsFilter::All));
    let cs = c["contacts"].as_array().unwrap();
    let all: Vec<_> = sc
        .contacts()
        .iter()
        .map(|x| x.s)
        .chain(sc.contacts().wall_pairs().iter().map(|x| &x.s))
        .collect();
    assert_eq!(cs.len(), all.len());
    let mut bridges = 0;
    for (j, s) in cs.iter().zip(all) {
        assert_eq!(bits(&j["overlap"]), s.overlap.to_bits());
        assert_eq!(
            bits(&j["normal_force"]),
            (s.normal_force + s.damp_force).to_bits()
        );
        assert_eq!(bits(&j["contact_radius"]), s.a.to_bits());
        if let Some(br) = &s.bridge {
            bridges += 1;
            assert_eq!(bits(&j["bridge"]["volume"]), br.volume.to_bits());
            assert_eq!(bits(&j["bridge"]["static_force"]), br.f_static.to_bits());
            assert_eq!(bits(&j["bridge"]["gap"]), br.gap.to_bits());
        }
    }
    assert!(bridges > 0);

    let w = json_of(&sc, PrintItem::Walls);
    for (k, wall) in sc.walls().iter().enumerate() {
        let j = &w["walls"][k];
        assert_eq!(bits(&j["normal_force"]), wall.normal_force.to_bits());
        same3(&j["force"], &Vec3::from(wall.force), "wall force");
        same3(&j["velocity"], &Vec3::from(wall.vel), "wall velocity");
    }

    let h = json_of(&sc, PrintItem::History);
    let rows = h["rows"].as_array().unwrap();
    assert_eq!(rows.len(), sc.history().rows.len());
    for (r, row) in rows.iter().zip(&sc.history().rows) {
        for (x, y) in r.as_array().unwrap().iter().zip(row) {
            assert_eq!(bits(x), y.to_bits());
        }
    }
}

/// The same through the binary: the JSON written at a moment equals, bit for bit, the state
/// SAve'd at that moment.
#[test]
fn binary_json_equals_the_saved_state() {
    let dir = std::env::temp_dir().join(format!("trubal-json-save-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(
        dir.join("run.tru"),
        format!("{SCENE}\ncycle 57\nprint balls energy\nsave now.sav\n"),
    )
    .unwrap();
    let out = crate::common::trubal()
        .args(["run.tru", "--json"])
        .current_dir(&dir)
        .output()
        .unwrap();
    assert!(out.status.success());
    let sc = trubal::checkpoint::load(&dir.join("now.sav")).unwrap();
    let _ = std::fs::remove_dir_all(&dir);
    let lines = json_lines(&String::from_utf8(out.stdout).unwrap());
    let p = &sc.particles();
    for (i, ball) in lines[0]["balls"].as_array().unwrap().iter().enumerate() {
        same3(&ball["pos"], &p.pos[i], "pos");
        same3(&ball["vel"], &p.vel[i], "vel");
        same3(&ball["spin"], &p.spin[i], "spin");
    }
    assert_eq!(
        bits(&lines[1]["dissipated"]["friction"]),
        sc.ledger().friction.to_bits()
    );
    assert_eq!(bits(&lines[1]["time"]), sc.time().to_bits());
}

/// A scene without particles: every item still gives one valid JSON object on its own line.
#[test]
fn print_lines_are_valid_json_for_an_empty_scene() {
    let out = run_json(
        "start 1 1 1 10 10 1\nprint info balls contacts energy entries map stress partitions settings walls chist grid bonds clusters history\n",
    );
    assert_eq!(json_lines(&out).len(), 15, "{out}");
}
