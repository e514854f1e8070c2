//! PNG pictures of the scene (`PLot`); see doc/plots.md.
//!
//! Geometry and drawing are separate: [`build::picture`] turns the scene and the items into a
//! [`picture::Picture`] (plain data in view coordinates: discs, lines, vectors, arcs, legend),
//! [`chart::history_chart`] turns the recorded history into a [`picture::Chart`], and
//! [`render`] draws either into pixels and a PNG. Only [`plot`] touches the file system.

pub mod build;
pub mod chart;
pub mod picture;
pub mod render;
pub mod xy;

use std::path::Path;

use crate::lang::command::PlotItem;
use crate::sim::Scene;

/// The file name of a plot: `plot_c{cycle:08}_{items}.png`, items in lower case joined by `_`
/// in the order given (repeats and `save` left out).
pub fn file_name(cycle: u64, items: &[PlotItem]) -> String {
    let names: Vec<&str> = build::drawn_items(items)
        .into_iter()
        .map(build::item_name)
        .collect();
    format!("plot_c{cycle:08}_{}.png", names.join("_"))
}

/// The PNG bytes of the picture of the items (no file is written).
pub fn png_bytes(scene: &Scene, items: &[PlotItem]) -> Result<Vec<u8>, String> {
    let items = build::drawn_items(items);
    build::check_items(scene, &items)?;
    let (w, h, px) = if items == [PlotItem::History] {
        render::chart_pixels(&chart::history_chart(scene)?)?
    } else {
        render::picture_pixels(&build::picture(scene, &items)?)?
    };
    render::encode_png(w, h, &px)
}

/// Draws the items on one picture in `SET OUTdir` (created if missing) and returns the path
/// of the file written.
pub fn plot(scene: &Scene, items: &[PlotItem]) -> Result<String, String> {
    let bytes = png_bytes(scene, items)?;
    let dir = scene.settings().out_dir.as_str();
    let name = file_name(scene.cycle(), items);
    let (path, shown) = if dir.is_empty() || dir == "." {
        (Path::new(&name).to_path_buf(), name.clone())
    } else {
        let p = Path::new(dir).join(&name);
        let shown = p.display().to_string();
        std::fs::create_dir_all(dir)
            .map_err(|e| format!("cannot create the output directory `{dir}` (SET OUTdir): {e}"))?;
        (p, shown)
    };
    std::fs::write(&path, bytes).map_err(|e| format!("cannot write the plot file {shown}: {e}"))?;
    Ok(shown)
}

#[cfg(test)]
mod tests;
