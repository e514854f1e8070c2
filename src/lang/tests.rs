//! Parser tests: every command of Appendix B parses from the thesis's own spellings.

use super::command::*;
use super::parse_line;

fn one(line: &str) -> Command {
    let v = parse_line(line).unwrap_or_else(|e| panic!("{line}: {e:?}"));
    assert_eq!(v.len(), 1, "{line}");
    v.into_iter().next().unwrap().command
}

#[test]
fn thesis_examples_parse() {
    assert_eq!(
        one("start 0.1 0.1 0.1 1000 2000 2 log"),
        Command::Start {
            size: [0.1; 3],
            nbox: 1000,
            nball: 2000,
            nwall: 2,
            log: true
        }
    );
    assert_eq!(
        one("rad 0.004330127 1"),
        Command::Radius {
            r: 0.004330127,
            size: 1,
            dist: SizeDist::Fixed
        }
    );
    assert!(matches!(
        one("agen 1 1 1 0.005 0.005 0.005 0.01 0.01 0.01"),
        Command::Agenerate { .. }
    ));
    let v = parse_line("plot save cycle 200 plot bou rdisp").unwrap();
    assert_eq!(v.len(), 3);
    assert_eq!(
        v[1].command,
        Command::Cycle {
            n: 200,
            servo: vec![]
        }
    );
    assert_eq!(
        one("Print G C I"),
        Command::Print {
            items: vec![
                PrintItem::Grid,
                PrintItem::Contacts(ContactsFilter::Loaded),
                PrintItem::Info
            ],
            ranges: vec![]
        }
    );
    assert_eq!(
        one("Pr cO"),
        Command::Print {
            items: vec![PrintItem::Contacts(ContactsFilter::Loaded)],
            ranges: vec![]
        }
    );
    assert_eq!(one("RGE Seed 5"), Command::RgenerateSeed { n: 5 });
    assert_eq!(
        one("pr c all"),
        Command::Print {
            items: vec![PrintItem::Contacts(ContactsFilter::All)],
            ranges: vec![]
        }
    );
}

#[test]
fn every_command_parses() {
    let lines = [
        "2-d",
        "agg 1 0.5 0.5 0.5 0.1",
        "age 1 1 1 0 0 0 0.1 0.1 0.1",
        "awa 1 p 0 0 1 0.5 v 0 0 -1 m 1 se 10 1 0.1",
        "coh 0.4 1",
        "cr 0.5 0.5 0.5 0 0 0 0 0 0 1 1",
        "c 100",
        "c 100 s0 1e5",
        "da 0.1 1000 0 1 1",
        "da res 0.5",
        "da res 0.5 2",
        "d 2650 1",
        "dwa p 0 1 0 0.001 v 0 0 0 m 1",
        "dwa sp 0.5 0.5 0.5 0.4 v 0 0 0 -0.1",
        "dwa ob 0.5 0.5 0.5 0.1 m 1",
        "f 1 1 1 0 0 0 3",
        "f 1 1 1 1 1 1 all",
        "fmm 0.5",
        "fro",
        "fra 0.2",
        "fr 0.3 1",
        "gain 0.1 1e-3",
        "gra 0 0 -9.81",
        "grid 0 0 0 0 0 0",
        "i 1 2",
        "liq 0.1 0.025 0 0.01",
        "l on",
        "l off",
        "m 1",
        "n",
        "pl bal for",
        "pra 0.3 1",
        "pr b cont gap ene ent g i m par st set w bon clu his ch",
        "pro e11",
        "ra 30e-6 1",
        "rese",
        "rest saved.bin",
        "rest",
        "rge 100 1 1 0",
        "rs 1.0 5",
        "sa",
        "sa out.sav",
        "set tol 1e-6",
        "set tol default",
        "set bri tor",
        "set tan noslip",
        "set liq conserve",
        "set ope z",
        "set per all",
        "sta 1 1 1 1 1 1",
        "sto",
        "vel 0 -1 0 1",
        "vel 0 -1 0 0 1 0 0",
        "vmu 0.5",
        "w 0 1 0 1 0 1",
        "ymd 70e9 1",
        "z 1",
        "rad 30e-6 1 normal 3e-6",
        "rad 16.5e-6 2 uniform 11e-6 22e-6",
        "mov 1 1e-4 0 0",
        "rel 1e-15 1e-6 10000",
        "set fra 7e-5",
        "set gen 1e-4",
        "cgr 1 9.81",
        "help",
        "help pr",
    ];
    for l in lines {
        parse_line(l).unwrap_or_else(|e| panic!("`{l}`: {}", e.message));
    }
}

#[test]
fn clashes_are_settled_by_the_rule() {
    for (w, want) in [
        ("s", "too short"),
        ("st", "too short"),
        ("r", "too short"),
        ("res", "too short"),
    ] {
        let e = parse_line(w).unwrap_err();
        assert!(e.message.contains(want), "{w}: {}", e.message);
    }
    // `p` alone is PRint (Appendix B.1: `p c` = Print Contacts); `pl` is PLot.
    assert!(matches!(one("p c"), Command::Print { .. }));
    assert!(matches!(one("pl bal"), Command::Plot { .. }));
    assert_eq!(
        one("sta 1 1 1 1 1 1"),
        Command::Start {
            size: [1.0; 3],
            nbox: 1,
            nball: 1,
            nwall: 1,
            log: false
        }
    );
    assert_eq!(one("sto"), Command::Stop);
    assert_eq!(one("rese"), Command::Reset);
    let e = parse_line("pr e").unwrap_err();
    assert!(
        e.message.contains("ENErgy") && e.message.contains("ENTries"),
        "{}",
        e.message
    );
}

#[test]
fn comments_and_separators() {
    assert_eq!(
        one("rad(0.1,1) ; radius"),
        Command::Radius {
            r: 0.1,
            size: 1,
            dist: SizeDist::Fixed
        }
    );
    assert_eq!(
        one("rad 0.1/1 # x"),
        Command::Radius {
            r: 0.1,
            size: 1,
            dist: SizeDist::Fixed
        }
    );
    assert!(parse_line("; only a comment").unwrap().is_empty());
}

#[test]
fn error_columns() {
    let e = parse_line("rad 0.1 x").unwrap_err();
    assert_eq!((e.start, e.end), (8, 9));
    let e = parse_line("cycle").unwrap_err();
    assert!(e.message.contains("Cycle needs"), "{}", e.message);
    assert_eq!(e.start, 5);
}

#[test]
fn unquoted_paths_get_a_hint() {
    let e = parse_line("save /tmp/x.sav").unwrap_err();
    assert!(e.message.contains("must be quoted"), "{}", e.message);
    // Quoted, the path is one word.
    assert!(parse_line("save \"/tmp/x.sav\"").is_ok());
    // No hint where no slash was involved.
    let e = parse_line("cycle 10 20").unwrap_err();
    assert!(!e.message.contains("quoted"), "{}", e.message);
}
