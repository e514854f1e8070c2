//! The cost of a frame against a step, measured in one process (doc/performance.md, the
//! VTK row of its first table): an ignored test, run by hand on checkpoints of the S1 bed,
//! because a timing depends on the machine. For each checkpoint named in `TRUBAL_VTK_COST` (paths separated
//! by `:`), it alternates, `TRUBAL_VTK_COST_REPS` times (default 7): 100 steps (timed,
//! per step), a frame zlib-compressed and a frame raw (each timed, encoding and writing
//! the four files to a temporary folder), and prints the medians, the files' sizes, and
//! the frame's cost as a fraction of 1000 steps. Alternating the three in one process
//! makes the ratio fair on a machine that others load: a slow spell slows all three.
//!
//! `TRUBAL_VTK_COST=a.sav:b.sav cargo test --profile ci --lib output::vtk::cost -- --ignored --nocapture`

#[cfg(test)]
mod tests {
    use super::super::{Series, write_frame, xml::Encoding};
    use std::time::Instant;

    fn median(mut v: Vec<f64>) -> f64 {
        v.sort_by(f64::total_cmp);
        v[v.len() / 2]
    }

    #[test]
    #[ignore = "a timing: run by hand (see the module's doc)"]
    fn frame_cost_against_steps() {
        let paths = std::env::var("TRUBAL_VTK_COST").expect("TRUBAL_VTK_COST: checkpoints");
        let reps: usize = std::env::var("TRUBAL_VTK_COST_REPS")
            .ok()
            .and_then(|r| r.parse().ok())
            .unwrap_or(7);
        let dir = std::env::temp_dir().join(format!("trubal-vtk-cost-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        for path in paths.split(':') {
            let mut scene = crate::checkpoint::load(std::path::Path::new(path)).unwrap();
            scene.unchecked().settings.out_dir = dir.display().to_string();
            let (mut step, mut zlib, mut raw) = (Vec::new(), Vec::new(), Vec::new());
            for _ in 0..reps {
                let t = Instant::now();
                crate::sim::cycle::run(&mut scene, 100).unwrap();
                step.push(t.elapsed().as_secs_f64() / 100.0);
                for (encoding, times) in [(Encoding::Zlib, &mut zlib), (Encoding::Raw, &mut raw)] {
                    let mut s = Series::new(if encoding == Encoding::Raw { "r" } else { "z" });
                    s.encoding = encoding;
                    let t = Instant::now();
                    let files = write_frame(&scene, &mut s).unwrap();
                    times.push(t.elapsed().as_secs_f64());
                    let sizes: Vec<u64> = files[..4]
                        .iter()
                        .map(|f| std::fs::metadata(f).unwrap().len())
                        .collect();
                    println!("  {encoding:?} sizes (particles, contacts, walls, cell) {sizes:?}");
                }
            }
            let (st, z, r) = (median(step), median(zlib), median(raw));
            println!(
                "{path}: cycle {} particles {} candidate pairs {}: step {:.3} ms; frame zlib {:.1} ms = {:.2} % of 1000 steps, raw {:.1} ms = {:.2} %",
                scene.cycle(),
                scene.particles().len(),
                scene.contacts().iter().count(),
                st * 1e3,
                z * 1e3,
                100.0 * z / (1000.0 * st),
                r * 1e3,
                100.0 * r / (1000.0 * st)
            );
        }
        let _ = std::fs::remove_dir_all(&dir);
    }
}
