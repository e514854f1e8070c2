//! `PLot` through a session: files in `SET OUTdir`, the message naming them, PNG headers, and
//! errors that leave the session going.

use std::io::Write;
use std::sync::{Arc, Mutex};

use trubal::session::Session;

/// Output captured from the session.
#[derive(Clone, Default)]
struct Shared(Arc<Mutex<Vec<u8>>>);

impl Write for Shared {
    fn write(&mut self, b: &[u8]) -> std::io::Result<usize> {
        self.0.lock().expect("the sink's lock").extend_from_slice(b);
        Ok(b.len())
    }
    fn flush(&mut self) -> std::io::Result<()> {
        Ok(())
    }
}

impl Shared {
    fn take(&self) -> String {
        String::from_utf8_lossy(&std::mem::take(
            &mut *self.0.lock().expect("the sink's lock"),
        ))
        .into_owned()
    }
}

fn session() -> (Session, Shared) {
    let out = Shared::default();
    (
        crate::common::session_with(Box::new(out.clone()), false)
            .with_diagnostics(Box::new(std::io::sink())),
        out,
    )
}

fn run(s: &mut Session, lines: &str) {
    for l in lines.lines() {
        if let Err(e) = s.run_line(l) {
            panic!("`{l}`: {}", e.message);
        }
    }
}

/// `SET OUTdir` by hand: the language splits words at slashes, so an absolute path cannot be
/// typed (a relative name without slashes can).
fn set_out(s: &mut Session, dir: &std::path::Path) {
    s.scene
        .as_mut()
        .expect("a scene")
        .unchecked()
        .settings
        .out_dir = dir.display().to_string();
}

fn tmp(tag: &str) -> std::path::PathBuf {
    let d = std::env::temp_dir().join(format!("trubal-plot-{tag}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    d
}

/// Checks the PNG signature and reads (width, height) from the IHDR chunk.
fn png_size(b: &[u8]) -> (u32, u32) {
    assert!(b.len() > 33, "too short for a PNG");
    assert_eq!(&b[..8], b"\x89PNG\r\n\x1a\n", "PNG signature");
    assert_eq!(&b[12..16], b"IHDR");
    let be = |k: usize| u32::from_be_bytes([b[k], b[k + 1], b[k + 2], b[k + 3]]);
    (be(16), be(20))
}

/// Two wet spheres pressed together and a third one moving, in an open box with a floor.
const SCENE: &str = "start 0.01 0.01 0.01 100 10 2
set open all
rad 5e-4 1
density 2500 1
ymd 1e8 1
pra 0.3 1
friction 0.3 1
cr 0.004 0.005 0.005  0.1 0 0  0 0 0  1 1
cr 0.005002 0.005 0.005  -0.1 0 0  0 0 0  1 1
cr 0.007 0.005 0.005  0 0 -0.2  0 0 0  1 1
liquid 1 0.07 0 0
dwall p 0 0 1 0.004";

#[test]
fn plot_writes_named_pngs_in_the_output_directory() {
    let dir = tmp("session");
    let (mut s, out) = session();
    run(&mut s, SCENE);
    set_out(&mut s, &dir);
    run(&mut s, "set history 5");
    // The thesis's own example on one line.
    run(&mut s, "plot save cycle 20 plot bou rdisp");
    let text = out.take();
    let want = dir.join("plot_c00000020_bou_rdisp.png");
    assert!(
        text.contains(&format!("plot written to {}", want.display())),
        "{text}"
    );
    let (w, h) = png_size(&std::fs::read(&want).expect("the file"));
    assert!(w >= 1000 && h > 0, "{w} x {h}");
    for items in [
        "ball wall forces",
        "disks lfo mfo",
        "cnd lcnd",
        "lcluster velocity rotation",
        "cluster couple grid",
    ] {
        run(&mut s, &format!("plot {items}"));
        let text = out.take();
        let name = format!("plot_c00000020_{}.png", expand(items).join("_"));
        assert!(text.contains(&name), "{items}: {text}");
        let (w, _) = png_size(&std::fs::read(dir.join(&name)).expect("the file"));
        assert!(w >= 1000);
    }
    for view in ["xy", "yz", "xz"] {
        run(&mut s, &format!("set view {view}\nplot ball"));
        assert!(out.take().contains("plot_c00000020_ball.png"));
    }
    run(&mut s, "plot history");
    let (w, h) = png_size(
        &std::fs::read(dir.join("plot_c00000020_history.png")).expect("the history chart"),
    );
    assert!(w >= 1000 && h >= 600);
    let _ = std::fs::remove_dir_all(&dir);
}

fn expand(items: &str) -> Vec<&'static str> {
    items
        .split_whitespace()
        .map(|w| match w {
            "ball" => "ball",
            "wall" => "wall",
            "forces" => "forces",
            "disks" => "disks",
            "lfo" => "lforces",
            "mfo" => "mforces",
            "cnd" => "cnd",
            "lcnd" => "lcnd",
            "lcluster" => "lcluster",
            "velocity" => "velocity",
            "rotation" => "rotation",
            "cluster" => "cluster",
            "couple" => "couple",
            "grid" => "grid",
            other => panic!("{other}"),
        })
        .collect()
}

#[test]
fn plot_errors_are_clear_and_the_session_goes_on() {
    let dir = tmp("errors");
    let (mut s, out) = session();
    run(&mut s, SCENE);
    set_out(&mut s, &dir);
    for (line, words) in [
        ("plot bou rdisp", "PLot SAVe"),
        ("plot rotation", "PLot SAVe"),
        ("plot cnd", "PLot SAVe"),
        ("plot lcnd", "PLot SAVe"),
        ("plot history", "SET HIStory"),
        ("plot history ball", "alone"),
        ("plot cluster lcluster", "one of them"),
    ] {
        let e = s.run_line(line).expect_err(line);
        assert!(e.message.contains(words), "{line}: {}", e.message);
    }
    // Unwritable output directory: under a regular file.
    std::fs::create_dir_all(&dir).expect("dir");
    let file = dir.join("a-file");
    std::fs::write(&file, b"not a directory").expect("file");
    set_out(&mut s, &file.join("sub"));
    let e = s.run_line("plot ball").expect_err("unwritable");
    assert!(e.message.contains("output directory"), "{}", e.message);
    // The session goes on, and the scene is intact.
    set_out(&mut s, &dir);
    out.take();
    run(&mut s, "plot ball");
    assert!(out.take().contains("plot_c00000000_ball.png"));
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn an_empty_scene_gives_a_picture_with_a_message() {
    let dir = tmp("empty");
    let (mut s, out) = session();
    run(&mut s, "start 0.1 0.1 0.1 10 10 1");
    set_out(&mut s, &dir);
    run(&mut s, "plot ball bou");
    assert!(out.take().contains("plot_c00000000_ball_bou.png"));
    let (w, _) = png_size(&std::fs::read(dir.join("plot_c00000000_ball_bou.png")).expect("file"));
    assert!(w >= 1000);
    let _ = std::fs::remove_dir_all(&dir);
}

/// `scripts/plot_examples.tru` (with fewer cycles) runs and writes its four pictures.
#[test]
fn the_example_script_runs() {
    let dir = tmp("examples");
    std::fs::create_dir_all(&dir).expect("dir");
    let script = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/scripts/plot_examples.tru"
    ))
    .expect("the script")
    .replace("cycle 1000\n", "cycle 200\n")
    .replace("cycle 12000\n", "cycle 200\n");
    let file = dir.join("examples.tru");
    std::fs::write(&file, script).expect("write");
    let out = crate::common::trubal()
        .arg(&file)
        .current_dir(&dir)
        .output()
        .expect("run");
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "{text}\n{}",
        String::from_utf8_lossy(&out.stderr)
    );
    for name in [
        "plot_c00000200_forces_wall.png",
        "plot_c00000400_lcluster_wall.png",
        "plot_c00000400_lcnd.png",
        "plot_c00000400_history.png",
    ] {
        assert!(
            text.contains(&format!("plot written to img/{name}")),
            "{text}"
        );
        let (w, _) = png_size(&std::fs::read(dir.join("img").join(name)).expect("file"));
        assert!(w >= 1000);
    }
    let _ = std::fs::remove_dir_all(&dir);
}
