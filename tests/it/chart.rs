//! `trubal chart` through the binary: a PNG of the size promised is written, and bad input
//! (a missing file, a wrong column name, a cell that is not a number, an option without its
//! value, a value that a log axis cannot take) is a one-line error with no panic.

use crate::common::trubal;

fn scratch(tag: &str) -> std::path::PathBuf {
    let d = std::env::temp_dir().join(format!("trubal-chart-{tag}-{}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    d
}

const CSV: &str = "# Olsson-like table: ours and the thesis, by liquid content\n\
                   liquid,v,ours,thesis\n\
                   dry,0.5,0,0.025\n\
                   dry,1,0.1,2.6\n\
                   dry,2,3,38.5\n\
                   0.1,2,0.1,\n\
                   0.1,3,0.2,1.4\n\
                   0.1,5.2,10,17\n";

fn run(dir: &std::path::Path, args: &[&str]) -> (bool, String, String) {
    let out = trubal()
        .current_dir(dir)
        .arg("chart")
        .args(args)
        .output()
        .unwrap();
    (
        out.status.success(),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

#[test]
fn a_chart_is_written() {
    let dir = scratch("ok");
    std::fs::write(dir.join("t.csv"), CSV).unwrap();
    let (ok, out, err) = run(
        &dir,
        &[
            "t.csv",
            "--x",
            "v",
            "--y",
            "ours",
            "--ref",
            "thesis",
            "--by",
            "liquid",
            "--keys",
            "dry,0.1",
            "--label",
            "ours=trubal",
            "--label",
            "thesis=Olsson",
            "--xlabel",
            "v [m/s]",
            "--ylabel",
            "fragmentation [%]",
            "--hline",
            "3,20,50",
            "--out",
            "sub/t.png",
        ],
    );
    assert!(ok, "{err}");
    assert!(
        out.contains("wrote sub/t.png (4 series, 11 points)"),
        "{out}"
    );
    let png = std::fs::read(dir.join("sub/t.png")).unwrap();
    assert_eq!(&png[1..4], b"PNG");
    // IHDR: width and height.
    let w = u32::from_be_bytes(png[16..20].try_into().unwrap());
    let h = u32::from_be_bytes(png[20..24].try_into().unwrap());
    assert_eq!((w, h), trubal::plot::xy::SIZE);
    let (ok, out, _) = run(&dir, &["--help"]);
    assert!(ok && out.contains("--ref COL"), "{out}");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn bad_input_is_a_clear_error() {
    let dir = scratch("bad");
    std::fs::write(dir.join("t.csv"), CSV).unwrap();
    std::fs::write(dir.join("b.csv"), "v,y\n1,2\n2,two\n").unwrap();
    let cases: [(&[&str], &str); 6] = [
        (
            &["none.csv", "--x", "v", "--y", "y", "--out", "o.png"],
            "cannot read none.csv",
        ),
        (
            &["t.csv", "--x", "speed", "--y", "ours", "--out", "o.png"],
            "t.csv has no column `speed` (its columns: liquid, v, ours, thesis)",
        ),
        (
            &["b.csv", "--x", "v", "--y", "y", "--out", "o.png"],
            "b.csv line 3: column `y` holds `two`, not a number",
        ),
        (
            &["t.csv", "--x", "v", "--y", "ours", "--out"],
            "--out needs a value",
        ),
        (
            &[
                "t.csv", "--x", "v", "--y", "ours", "--logy", "--out", "o.png",
            ],
            "cannot be drawn on a log axis",
        ),
        (
            &["t.csv", "--x", "v", "--out", "o.png"],
            "--y COL (or --ref COL) is required",
        ),
    ];
    for (args, want) in cases {
        let (ok, _, err) = run(&dir, args);
        assert!(!ok, "{args:?} succeeded");
        assert!(
            err.starts_with("trubal chart: ") && err.contains(want),
            "{args:?}: {err}"
        );
        assert!(!err.contains("panicked"), "{args:?}: {err}");
    }
    assert!(!dir.join("o.png").exists());
    let _ = std::fs::remove_dir_all(&dir);
}
