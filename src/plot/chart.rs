//! `PLot HIStory`: the recorded time series as a [`Chart`] (pure data).

use super::picture::{Chart, Panel, Rgb, Series};
use crate::sim::Scene;
use crate::sim::history::COLUMNS;

/// Energies (upper panel) and counts (lower panel) against the cycle number.
const PANELS: &[(&str, &str, &[(&str, Rgb)])] = &[
    (
        "energy",
        "energy (J)",
        &[
            ("kinetic", Rgb(220, 0, 0)),
            ("strain", Rgb(0, 150, 0)),
            ("input", Rgb(0, 0, 0)),
            ("dissipated", Rgb(0, 0, 230)),
        ],
    ),
    (
        "contacts and liquid bridges",
        "number",
        &[("contacts", Rgb(0, 150, 0)), ("bridges", Rgb(0, 0, 230))],
    ),
];

/// The chart of the history recorded by `SET HIStory n`.
pub fn history_chart(scene: &Scene) -> Result<Chart, String> {
    let rows = &scene.history().rows;
    if rows.is_empty() {
        return Err(
            "PLot HIStory: no history recorded yet: give `SET HIStory n` (record every n cycles), then Cycle"
                .into(),
        );
    }
    let col = |name: &str| {
        COLUMNS
            .iter()
            .position(|c| *c == name)
            .ok_or_else(|| format!("PLot HIStory: the history has no column `{name}`"))
    };
    let xc = col("cycle")?;
    let mut panels = Vec::new();
    for (title, y_label, names) in PANELS {
        let mut series = Vec::new();
        for (name, colour) in names.iter() {
            let c = col(name)?;
            let points = rows
                .iter()
                .filter_map(|r| Some((*r.get(xc)?, *r.get(c)?)))
                .filter(|(x, y)| x.is_finite() && y.is_finite())
                .collect();
            series.push(Series {
                name: name.to_string(),
                colour: *colour,
                points,
            });
        }
        panels.push(Panel {
            title: title.to_string(),
            y_label: y_label.to_string(),
            series,
        });
    }
    Ok(Chart {
        title: format!(
            "trubal history: {} records up to cycle {}",
            rows.len(),
            scene.cycle()
        ),
        x_label: "cycle".into(),
        panels,
    })
}
