//! VTK output for ParaView (`VTk`; doc/output.md, "VTK files"): each frame is four XML
//! PolyData files in `SET OUTdir`, `{prefix}_{kind}_c{cycle:08}.vtp` for the kinds of
//! [`KINDS`], and each kind has its series index `{prefix}_{kind}.pvd` listing the frames
//! written so far with their simulated times, those of earlier sessions included
//! ([`resume`]). [`frame`] and [`surfaces`] build the datasets (pure functions of the
//! scene), [`xml`] encodes them; only [`write_frame`], [`write_file`] and [`resume`] touch
//! the file system.

#[cfg(test)]
mod cost;
pub mod frame;
pub mod surfaces;
pub mod xml;

use std::path::{Path, PathBuf};

use crate::sim::Scene;

/// The kinds of file of a frame.
pub const KINDS: [&str; 4] = ["particles", "contacts", "walls", "cell"];

/// The frames of one series (one prefix): (cycle, time), how its files are encoded, the
/// particle and contact arrays its frames hold (a bit per entry of `PARTICLE_ARRAYS`,
/// `CONTACT_ARRAYS`), and whether the points are single precision.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Series {
    pub prefix: String,
    pub frames: Vec<(u64, f64)>,
    pub encoding: xml::Encoding,
    pub arrays: u16,
    pub contacts: u16,
    pub single: bool,
}

impl Series {
    pub fn new(prefix: &str) -> Series {
        Series {
            prefix: prefix.to_string(),
            frames: Vec::new(),
            encoding: xml::Encoding::default(),
            arrays: frame::ALL_ARRAYS,
            contacts: frame::ALL_CONTACT_ARRAYS,
            single: false,
        }
    }
}

/// The frames an index written before (`{prefix}_particles.pvd` in `SET OUTdir`, by an
/// earlier session or before a `RESTart`) lists, read back: each `DataSet` whose file is
/// this prefix's particles file of some cycle and still exists, with its time. Nothing
/// when there is no index (or the directory cannot be made: the frame's write says so).
/// [`write_frame`] then keeps those before the frame's cycle.
pub fn resume(scene: &Scene, prefix: &str) -> Series {
    let mut s = Series::new(prefix);
    let Ok(dir) = out_dir(scene) else { return s };
    let at = |name: &str| match &dir {
        Some(d) => d.join(name),
        None => PathBuf::from(name),
    };
    let Ok(text) = std::fs::read_to_string(at(&format!("{prefix}_particles.pvd"))) else {
        return s;
    };
    let attr = |line: &str, key: &str| -> Option<String> {
        let k = line.find(&format!(" {key}=\""))? + key.len() + 3;
        let e = line[k..].find('"')? + k;
        Some(line[k..e].to_string())
    };
    let head = format!("{}_particles_c", xml::escape(prefix));
    for line in text.lines().filter(|l| l.contains("<DataSet ")) {
        let (Some(file), Some(time)) = (attr(line, "file"), attr(line, "timestep")) else {
            continue;
        };
        let cycle = file
            .strip_prefix(&head)
            .and_then(|r| r.strip_suffix(".vtp"))
            .and_then(|c| c.parse::<u64>().ok());
        if let (Some(c), Ok(t)) = (cycle, time.parse::<f64>())
            && at(&file_name(prefix, "particles", c)).exists()
        {
            s.frames.retain(|&(k, _)| k != c);
            s.frames.push((c, t));
        }
    }
    s.frames.sort_by_key(|&(c, _)| c);
    s
}

/// The file of one kind of a frame.
pub fn file_name(prefix: &str, kind: &str, cycle: u64) -> String {
    format!("{prefix}_{kind}_c{cycle:08}.vtp")
}

/// The bytes of the file of one kind (`KINDS`) for the scene as it is, with the arrays,
/// precision and encoding of the series.
pub fn encode_kind(scene: &Scene, kind: &str, series: &Series) -> Vec<u8> {
    let mut d = match kind {
        "particles" => frame::particles(scene, series.arrays),
        "contacts" => frame::contacts(scene, series.contacts),
        "walls" => surfaces::walls(scene),
        _ => frame::cell_box(scene),
    };
    d.single = series.single;
    xml::encode(&d, series.encoding)
}

/// The `.pvd` index of one kind: a `DataSet` per frame, at its time.
pub fn pvd(series: &Series, kind: &str) -> String {
    let mut s = String::from(
        "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"0.1\" byte_order=\"LittleEndian\">\n  <Collection>\n",
    );
    for &(cycle, time) in &series.frames {
        s.push_str(&format!(
            "    <DataSet timestep=\"{time:e}\" group=\"\" part=\"0\" file=\"{}\"/>\n",
            xml::escape(&file_name(&series.prefix, kind, cycle))
        ));
    }
    s.push_str("  </Collection>\n</VTKFile>\n");
    s
}

/// The directory of `SET OUTdir` (created if missing) and how a file in it is shown.
fn out_dir(scene: &Scene) -> Result<Option<PathBuf>, String> {
    let dir = scene.settings().out_dir.as_str();
    if dir.is_empty() || dir == "." {
        return Ok(None);
    }
    std::fs::create_dir_all(dir)
        .map_err(|e| format!("cannot create the output directory `{dir}` (SET OUTdir): {e}"))?;
    Ok(Some(PathBuf::from(dir)))
}

fn write(dir: &Option<PathBuf>, name: &str, bytes: &[u8]) -> Result<String, String> {
    let path = match dir {
        Some(d) => d.join(name),
        None => Path::new(name).to_path_buf(),
    };
    let shown = path.display().to_string();
    // Written whole under another name, then renamed: a reader (ParaView reloading the
    // series) never sees half a file.
    let tmp = path.with_extension("part");
    std::fs::write(&tmp, bytes)
        .and_then(|_| std::fs::rename(&tmp, &path))
        .map_err(|e| {
            let _ = std::fs::remove_file(&tmp);
            format!("cannot write the VTK file {shown}: {e}")
        })?;
    Ok(shown)
}

/// Writes one file in `SET OUTdir` (created if missing); returns how it is shown.
pub fn write_file(scene: &Scene, name: &str, bytes: &[u8]) -> Result<String, String> {
    write(&out_dir(scene)?, name, bytes)
}

/// Writes the frame of the scene as it is (its four files) and the series' indexes, with
/// the frame added after those of earlier cycles (frames of this cycle or later, of a run
/// that a `RESTart` from an earlier state abandoned, leave the index). Returns the files
/// written, the frame's first. `series` changes only when every file was written.
pub fn write_frame(scene: &Scene, series: &mut Series) -> Result<Vec<String>, String> {
    let dir = out_dir(scene)?;
    let mut next = series.clone();
    next.frames.retain(|&(c, _)| c < scene.cycle());
    next.frames.push((scene.cycle(), scene.time()));
    let mut shown = Vec::new();
    for kind in KINDS {
        let name = file_name(&series.prefix, kind, scene.cycle());
        shown.push(write(&dir, &name, &encode_kind(scene, kind, series))?);
    }
    for kind in KINDS {
        let name = format!("{}_{kind}.pvd", series.prefix);
        shown.push(write(&dir, &name, pvd(&next, kind).as_bytes())?);
    }
    *series = next;
    Ok(shown)
}
