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

/// The particles a picture highlights (`PLot ... GROup name`, doc/groups.md): a label (the
/// group's name, or `range`) and their ids, sorted.
pub struct Marked {
    pub label: String,
    pub ids: Vec<u32>,
}

/// The PNG bytes of the picture of the items (no file is written).
pub fn png_bytes(scene: &Scene, items: &[PlotItem]) -> Result<Vec<u8>, String> {
    png_bytes_marked(scene, items, None)
}

/// [`png_bytes`], with the particles of `marked` in the highlight colour.
pub fn png_bytes_marked(
    scene: &Scene,
    items: &[PlotItem],
    marked: Option<&Marked>,
) -> Result<Vec<u8>, String> {
    let items = build::drawn_items(items);
    build::check_items(scene, &items)?;
    let (w, h, px) = if items == [PlotItem::History] {
        render::chart_pixels(&chart::history_chart(scene)?)?
    } else {
        render::picture_pixels(&picture_marked(scene, &items, marked)?)?
    };
    render::encode_png(w, h, &px)
}

/// The picture of the items with the particles of `marked` in the highlight colour.
pub fn picture_marked(
    scene: &Scene,
    items: &[PlotItem],
    marked: Option<&Marked>,
) -> Result<picture::Picture, String> {
    let mut pic = build::picture(scene, items)?;
    if let Some(m) = marked {
        mark(&mut pic, items, m)?;
    }
    Ok(pic)
}

/// Whether the items draw the particles a group is highlighted among.
pub fn check_mark(items: &[PlotItem]) -> Result<(), String> {
    use PlotItem::*;
    if !items
        .iter()
        .any(|it| matches!(it, Ball | Disks | Cluster | LCluster))
    {
        return Err("PLot: a group is highlighted among the particles drawn: give BALl, DISks, CLUster or LCLuster with it".into());
    }
    Ok(())
}

/// Colours the discs of the marked particles and names them in the legend.
fn mark(pic: &mut picture::Picture, items: &[PlotItem], m: &Marked) -> Result<(), String> {
    check_mark(items)?;
    let mut n = 0;
    for d in &mut pic.discs {
        if m.ids.binary_search(&d.id).is_ok() {
            d.fill = picture::colour::HIGHLIGHT;
            n += 1;
        }
    }
    pic.legend.push(picture::LegendEntry {
        swatch: picture::Swatch::Disc(picture::colour::HIGHLIGHT),
        text: format!("{}: {n} particles", m.label),
    });
    Ok(())
}

/// Draws the items on one picture in `SET OUTdir` (created if missing) and returns the path
/// of the file written.
pub fn plot(scene: &Scene, items: &[PlotItem]) -> Result<String, String> {
    plot_marked(scene, items, None)
}

/// [`plot`], with the particles of `marked` highlighted (the file name ends in `_LABEL`).
pub fn plot_marked(
    scene: &Scene,
    items: &[PlotItem],
    marked: Option<&Marked>,
) -> Result<String, String> {
    let bytes = png_bytes_marked(scene, items, marked)?;
    let dir = scene.settings().out_dir.as_str();
    let mut name = file_name(scene.cycle(), items);
    if let Some(m) = marked {
        name = format!("{}_{}.png", name.trim_end_matches(".png"), m.label);
    }
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
