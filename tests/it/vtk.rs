//! `VTk`: the files read by the VTK library itself and checked against the JSON output of
//! the same state (`tests/vtk/check.py`, with the Python of `.ci/vtk-venv`, which `.ci/run`
//! installs and names in `TRUBAL_VTK_PYTHON`), and rendered off-screen by VTK into a
//! picture that is not empty (`tests/vtk/render.py`); the schedule leaves the run's bits alone;
//! bad input is refused with its place and writes nothing.

use std::path::{Path, PathBuf};

/// A fresh folder for one test's run.
fn folder(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("trubal-vtk-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// Runs `trubal --json in.tru` in `dir`; its output goes to `dir/out.jsonl`.
fn run_in(dir: &Path, script: &str) -> (bool, String) {
    std::fs::write(dir.join("in.tru"), script).unwrap();
    let out = crate::common::trubal()
        .current_dir(dir)
        .args(["--json", "in.tru"])
        .output()
        .unwrap();
    std::fs::write(dir.join("out.jsonl"), &out.stdout).unwrap();
    (
        out.status.success(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

/// The Python with the `vtk` wheel, or `None` outside CI when none was installed (a
/// developer's `cargo test` without `.ci/run`); in CI its absence is a failure.
fn vtk_python() -> Option<String> {
    match std::env::var("TRUBAL_VTK_PYTHON") {
        Ok(p) if !p.is_empty() => Some(p),
        _ if std::env::var_os("CI").is_some() => {
            panic!("TRUBAL_VTK_PYTHON is not set: .ci/run installs the VTK reader (.ci/vtk-venv)")
        }
        _ => {
            eprintln!("vtk: TRUBAL_VTK_PYTHON not set (run .ci/vtk-venv): the files are not read");
            None
        }
    }
}

fn check_with_vtk(dir: &Path, prefix: &str) {
    check_with_vtk_args(&[dir.as_os_str(), prefix.as_ref()]);
}

/// `tests/vtk/check.py` with these arguments, which must pass.
fn check_with_vtk_args(args: &[&std::ffi::OsStr]) {
    let Some(py) = vtk_python() else { return };
    let script = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/vtk/check.py");
    let dir = args.iter().find(|a| Path::new(a).is_dir()).map(Path::new);
    let dir = dir.unwrap_or(Path::new("."));
    let out = std::process::Command::new(py)
        .arg(script)
        .args(args)
        .output()
        .unwrap();
    let text = format!(
        "{}{}",
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(out.status.success(), "{}: {text}", dir.display());
    assert!(text.contains("VTK check passed"), "{text}");
}

/// A frame and a field rendered off-screen by VTK (`tests/vtk/render.py`: spheres by
/// radius, contact tubes by force; a slice of the density): the pictures are not empty.
fn render(dir: &Path) {
    let Some(py) = vtk_python() else { return };
    let script = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/vtk/render.py");
    let out = dir.join("out");
    let runs: [Vec<std::ffi::OsString>; 2] = [
        vec![
            "network".into(),
            out.clone().into(),
            "imp".into(),
            "1201".into(),
            dir.join("network.png").into(),
        ],
        vec![
            "field".into(),
            out.join("imp_field_c00001201.vti").into(),
            "density".into(),
            dir.join("field.png").into(),
        ],
    ];
    for args in runs {
        let r = std::process::Command::new(&py)
            .arg(&script)
            .args(&args)
            .output()
            .unwrap();
        let text = String::from_utf8_lossy(&r.stdout).into_owned();
        assert!(
            r.status.success() && text.contains("render check passed"),
            "{text}{}",
            String::from_utf8_lossy(&r.stderr)
        );
    }
}

/// A JKR agglomerate (58 spheres) pressed onto a plane inside a sphere and a cylinder, with
/// an obstacle aside: particle pairs, wall contacts, broken bonds (clusters), displacements
/// since `PLot SAve`, every kind of wall; frames every 500 cycles and one at the end, and
/// the coarse-grained fields of the last as a `.vti`.
const AGGLOMERATE: &str = "start 1e-3 1e-3 1e-3 1000 200 4
fraction 0.2
set open all
rad 30e-6 1
density 2650 1
ymd 70e9 1
pra 0.3 1
friction 0.3 1
cohesion 0.5 1
agglomerate 1 5.1961524227066318e-4 5.1961524227066318e-4 5.1961524227066318e-4 150e-6
agen 1 1 1 0 0 0 69.28203230275509e-6 69.28203230275509e-6 69.28203230275509e-6
agen 1 1 1 34.641016151377545e-6 34.641016151377545e-6 34.641016151377545e-6 69.28203230275509e-6 69.28203230275509e-6 69.28203230275509e-6
rad 30.0021e-6 1
cycle 1
plot save
print balls
velocity 0 0 -0.2 0
dwall p 0 0 1 0.38569e-3
dwall ob 0.9e-3 0.9e-3 0.9e-3 0.05e-3
dwall cy 0.5e-3 0.5e-3 0 0 0 1 0.49e-3
dwall sp 0.5e-3 0.5e-3 0.5e-3 0.49e-3
set outdir \"out\"
vtk every 500 file imp
cycle 1200
vtk
print balls contacts walls grid clusters
field 4 4 4 2.5e-4 file imp
";

/// Two wet spheres whose bridge crosses the periodic x side (the line goes to B's image)
/// and a third alone; no walls.
const PERIODIC_BRIDGE: &str = "start 0.0078125 0.0078125 0.0078125 100 10 2
set periodic x
rad 9.765625e-4 1
ymd 1e9 1
pra 0.3 1
density 2500 1
liquid 1 0.072 0 0
create 0.00048828125 0.00390625 0.00390625 0.2 0 0 0 0 0 1 1
create 0.00634765625 0.00390625 0.00390625 -0.2 0 0 0 0 0 1 1
create 0.00390625 0.00390625 0.00390625 0 0 0 0 0 0 1 1
set outdir \"out\"
cycle 100
vtk file b raw
print balls contacts walls grid clusters
";

/// A periodic cell sheared the negative way (as `cell::a_small_negative_offset_prints_as_negative`):
/// the cell file's `offset` is `PRint Grid`'s, a small negative number.
const SHEARED_CELL: &str = "start 1e-3 1e-3 1e-3 400 1000 0
rad 6e-5 1
density 2600 1
ymd 1e8 1
pra 0.25 1
rge 50 1 1 0
grid 0 0 0 -3000 0 0
set outdir \"out\"
cycle 30
vtk file s raw
print balls contacts walls grid clusters
";

#[test]
fn vtk_files_read_by_vtk_match_the_json_output() {
    for (name, script, prefix, frames) in [
        (
            "agglomerate",
            AGGLOMERATE,
            "imp",
            [1u64, 500, 1000, 1201].as_slice(),
        ),
        ("periodic", PERIODIC_BRIDGE, "b", [100].as_slice()),
        ("sheared", SHEARED_CELL, "s", [30].as_slice()),
    ] {
        let dir = folder(name);
        let (ok, err) = run_in(&dir, script);
        assert!(ok, "{name}: {err}");
        for kind in ["particles", "contacts", "walls", "cell"] {
            assert!(dir.join(format!("out/{prefix}_{kind}.pvd")).exists());
            for c in frames {
                let f = dir.join(format!("out/{prefix}_{kind}_c{c:08}.vtp"));
                let bytes = std::fs::read(&f).unwrap();
                // zlib by default; the periodic case's `raw` uncompressed: both read below.
                let zlib = String::from_utf8_lossy(&bytes[..300])
                    .contains("compressor=\"vtkZLibDataCompressor\"");
                assert_eq!(zlib, prefix == "imp", "{}", f.display());
            }
        }
        check_with_vtk(&dir, prefix);
        if prefix == "imp" {
            render(&dir);
        }
        let _ = std::fs::remove_dir_all(&dir);
    }
}

/// The frames of `VTk EVery` cut a Cycle in runs: the particles end with the same bits
/// as without them, and as after one `Cycle` of the whole length.
#[test]
fn vtk_schedule_leaves_the_bits_alone() {
    let base = AGGLOMERATE.split("set outdir").next().unwrap().to_string();
    let end = "cycle 300\nprint balls contacts\n";
    let mut outs = Vec::new();
    for extra in ["", "vtk every 7\n", "vtk every 100\ncycle 50\nvtk off\n"] {
        let dir = folder("bits");
        let script = if extra.contains("cycle 50") {
            format!("{base}{extra}cycle 250\nprint balls contacts\n")
        } else {
            format!("{base}{extra}{end}")
        };
        let (ok, err) = run_in(&dir, &script);
        assert!(ok, "{err}");
        let text = std::fs::read_to_string(dir.join("out.jsonl")).unwrap();
        outs.push(
            text.lines()
                .filter(|l| l.starts_with('{'))
                .map(String::from)
                .collect::<Vec<_>>(),
        );
        if extra.contains("every 7") {
            // Cycle 1 (the command), then 7, 14, ..., 301.
            let pvd = std::fs::read_to_string(dir.join("trubal_particles.pvd")).unwrap();
            assert_eq!(pvd.matches("<DataSet").count(), 1 + 301 / 7, "{pvd}");
        }
        let _ = std::fs::remove_dir_all(&dir);
    }
    assert_eq!(outs[0], outs[1]);
    assert_eq!(outs[0], outs[2]);
}

/// Bad input: a located error, no file written, the session going on.
#[test]
fn vtk_refuses_bad_input_and_writes_nothing() {
    let dir = folder("bad");
    let cases = [
        ("vtk every 0", "`k` must be at least 1"),
        ("vtk every 2.5", "whole number"),
        ("vtk file \"a/b\"", "letters, digits"),
        ("vtk off every 5", "stands alone"),
        ("vtk every 3 every 4", "given twice"),
        ("vtk file", "needs `prefix`"),
        ("vtk now", "unexpected `now`"),
    ];
    for (line, want) in cases {
        let (ok, err) = run_in(&dir, &format!("start 1e-3 1e-3 1e-3 10 10 1\n{line}\n"));
        assert!(!ok, "{line}");
        assert!(err.contains("in.tru:2:"), "{line}: {err}");
        assert!(err.contains(want), "{line}: {err}");
    }
    let (ok, err) = run_in(&dir, "vtk\n");
    assert!(
        !ok && err.contains("in.tru:1:1: error: no problem is defined"),
        "{err}"
    );
    // An output directory that cannot be made: refused, and no schedule left behind.
    std::fs::write(dir.join("plain"), "a file").unwrap();
    let (ok, err) = run_in(
        &dir,
        "start 1e-3 1e-3 1e-3 10 10 1\nset outdir plain\nvtk every 2\n",
    );
    assert!(
        !ok && err.contains("in.tru:3:1: error: cannot create the output directory"),
        "{err}"
    );
    let written: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .flatten()
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .filter(|n| n.ends_with(".vtp") || n.ends_with(".pvd"))
        .collect();
    assert!(written.is_empty(), "{written:?}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// The cycles an index lists, from its file names, with its times.
fn listed(pvd: &Path) -> Vec<(u64, f64)> {
    let text = std::fs::read_to_string(pvd).unwrap();
    text.lines()
        .filter(|l| l.contains("<DataSet"))
        .map(|l| {
            let at = |key: &str| {
                let k = l.find(key).unwrap() + key.len();
                l[k..k + l[k..].find('"').unwrap()].to_string()
            };
            let file = at("file=\"");
            let c = &file[file.len() - 12..file.len() - 4];
            (c.parse().unwrap(), at("timestep=\"").parse().unwrap())
        })
        .collect()
}

/// The series goes on across sessions: a session restarted from a SAve keeps the frames
/// before its cycle and rewrites the later ones with the same bits (the run is the same);
/// a restart that stops earlier drops the abandoned frames from the index; a frame whose
/// file is gone is not listed; a new problem (`STArt`) starts the series anew.
#[test]
fn vtk_series_goes_on_across_sessions() {
    let dir = folder("series");
    let base = PERIODIC_BRIDGE.split("set outdir").next().unwrap();
    let (ok, err) = run_in(
        &dir,
        &format!(
            "{base}set outdir \"out\"\nvtk every 50 file s\ncycle 100\nsave s.sav\ncycle 100\n"
        ),
    );
    assert!(ok, "{err}");
    let pvd = dir.join("out/s_particles.pvd");
    let cycles = |v: Vec<(u64, f64)>| v.into_iter().map(|f| f.0).collect::<Vec<_>>();
    assert_eq!(cycles(listed(&pvd)), [0, 50, 100, 150, 200]);
    let first = listed(&pvd);
    let c200 = std::fs::read(dir.join("out/s_particles_c00000200.vtp")).unwrap();
    let saved = ["s.sav", "out/s.sav"]
        .into_iter()
        .find(|p| dir.join(p).exists())
        .expect("the checkpoint");
    // A new session from the checkpoint: frames 0 and 50 kept, 100 to 200 written again.
    std::fs::remove_file(dir.join("out/s_particles_c00000200.vtp")).unwrap();
    let (ok, err) = run_in(
        &dir,
        &format!("restart {saved}\nset outdir \"out\"\nvtk every 50 file s\ncycle 100\n"),
    );
    assert!(ok, "{err}");
    assert_eq!(listed(&pvd), first);
    for kind in ["contacts", "walls", "cell"] {
        let k = dir.join(format!("out/s_{kind}.pvd"));
        assert_eq!(cycles(listed(&k)), [0, 50, 100, 150, 200], "{kind}");
    }
    let again = std::fs::read(dir.join("out/s_particles_c00000200.vtp")).unwrap();
    assert!(
        again == c200,
        "the frame of cycle 200 differs after SAve/RESTart"
    );
    let text = std::fs::read_to_string(dir.join("out.jsonl")).unwrap();
    assert!(text.contains("the series holds 2 earlier frames"), "{text}");
    // A restart that runs less: the frames after its last leave the index.
    let (ok, err) = run_in(
        &dir,
        &format!(
            "restart {saved}\nset outdir \"out\"\nvtk every 50 file s\ncycle 20\nvtk file s\n"
        ),
    );
    assert!(ok, "{err}");
    assert_eq!(cycles(listed(&pvd)), [0, 50, 100, 120]);
    std::fs::remove_file(dir.join("out/s_particles_c00000050.vtp")).unwrap();
    let (ok, err) = run_in(
        &dir,
        &format!("restart {saved}\nset outdir \"out\"\nvtk file s\n"),
    );
    assert!(ok, "{err}");
    assert_eq!(cycles(listed(&pvd)), [0, 100]);
    let (ok, err) = run_in(
        &dir,
        &format!("{base}set outdir \"out\"\ncycle 10\nvtk file s\n"),
    );
    assert!(ok, "{err}");
    assert_eq!(cycles(listed(&pvd)), [10]);
    let _ = std::fs::remove_dir_all(&dir);
}

/// The names of the point arrays of a particles file, from its XML header.
fn point_arrays(file: &Path) -> Vec<String> {
    let bytes = std::fs::read(file).unwrap();
    let text = String::from_utf8_lossy(&bytes);
    let head = &text[..text.find("<AppendedData").unwrap()];
    let pd = &head[head.find("<PointData").unwrap()..head.find("</PointData>").unwrap()];
    pd.split("Name=\"")
        .skip(1)
        .map(|r| r[..r.find('"').unwrap()].to_string())
        .collect()
}

/// `VTk ARRays` (`CONtacts`, `SINgle`): the frames of the command and of its schedule hold
/// the positions and the arrays named and no others (read by VTK, checked against `PRint
/// Balls Contacts Grid`; single-precision points equal to the JSON's rounded to single
/// precision), smaller than the whole frame; a later `VTk` without them writes every array
/// in double precision again.
#[test]
fn vtk_arrays_chooses_the_particle_arrays() {
    let base = PERIODIC_BRIDGE.split("set outdir").next().unwrap();
    for (lean_words, contacts, single) in [
        ("arrays vel id radius", None, false),
        (
            "single contacts nor bridge a arrays vel id radius",
            Some("a,normal_force,bridge"),
            true,
        ),
    ] {
        let dir = folder("arrays");
        let (ok, err) = run_in(
            &dir,
            &format!(
                "{base}set outdir \"out\"\nvtk every 50 file lean {lean_words}\ncycle 100\nprint balls contacts grid\nvtk file full\n"
            ),
        );
        assert!(ok, "{err}");
        let lean = ["id", "radius", "velocity"];
        for c in [0, 50, 100] {
            let f = dir.join(format!("out/lean_particles_c{c:08}.vtp"));
            assert_eq!(point_arrays(&f), lean, "{}", f.display());
        }
        let full = dir.join("out/full_particles_c00000100.vtp");
        let all = [
            "id",
            "radius",
            "velocity",
            "spin",
            "force",
            "moment",
            "material",
            "size_type",
            "agglomerate",
            "coordination",
            "cluster",
        ];
        assert_eq!(point_arrays(&full), all);
        let size = |f: &Path| std::fs::metadata(f).unwrap().len();
        for kind in ["particles", "contacts"] {
            let lean = size(&dir.join(format!("out/lean_{kind}_c00000100.vtp")));
            let full = size(&dir.join(format!("out/full_{kind}_c00000100.vtp")));
            assert!(lean < full || kind == "contacts" && contacts.is_none());
        }
        let mut args: Vec<&std::ffi::OsStr> = vec![
            "--arrays".as_ref(),
            dir.as_os_str(),
            "lean".as_ref(),
            "id,radius,velocity".as_ref(),
        ];
        if let Some(c) = contacts {
            args.push("--contacts".as_ref());
            args.push(c.as_ref());
        }
        if single {
            args.push("--single".as_ref());
        }
        check_with_vtk_args(&args);
        let _ = std::fs::remove_dir_all(&dir);
    }
}

/// Bad `ARRays`: a located error, no frame written, no schedule set.
#[test]
fn vtk_arrays_refuses_bad_names() {
    let dir = folder("bad-arrays");
    let cases = [
        ("vtk arrays", "name the particle arrays"),
        ("vtk arrays colour", "unknown particle array `colour`"),
        ("vtk arrays id radius id", "given twice"),
        ("vtk arrays r", "too short"),
        ("vtk off arrays id", "stands alone"),
        ("vtk arrays id arrays radius", "given twice"),
        (
            "vtk every 5 arrays velocity 3",
            "unknown particle array `3`",
        ),
        ("vtk contacts", "name the contact arrays"),
        ("vtk contacts colour", "unknown contact array `colour`"),
        ("vtk contacts nor normal_force", "given twice"),
        ("vtk contacts t", "too short"),
        ("vtk single raw single", "given twice"),
        ("vtk off single", "stands alone"),
        ("vtk off contacts a", "stands alone"),
    ];
    for (line, want) in cases {
        let (ok, err) = run_in(
            &dir,
            &format!("start 1e-3 1e-3 1e-3 10 10 1\n{line}\ncycle 10\n"),
        );
        assert!(!ok, "{line}");
        assert!(err.contains("in.tru:2:"), "{line}: {err}");
        assert!(err.contains(want), "{line}: {err}");
        let written: Vec<_> = std::fs::read_dir(&dir)
            .unwrap()
            .flatten()
            .map(|e| e.file_name().to_string_lossy().into_owned())
            .filter(|n| n.ends_with(".vtp") || n.ends_with(".pvd"))
            .collect();
        assert!(written.is_empty(), "{line}: {written:?}");
    }
    let _ = std::fs::remove_dir_all(&dir);
}
