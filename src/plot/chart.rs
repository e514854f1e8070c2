//! `PLot HIStory`: the recorded time series as a [`Chart`] (pure data): the fixed columns of
//! `SET HIStory`, then the columns of each group recorded with them (`GROup name HIStory`,
//! doc/groups.md).

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

/// The panels of a recorded group: its quantities (`sim::range::QUANTITIES`) by unit. The
/// mass is not charted: it changes only with the members, which the count shows.
const GROUP_PANELS: &[(&str, &str, &[(&str, Rgb)])] = &[
    (
        "centre of mass",
        "position (m)",
        &[
            ("x", Rgb(220, 0, 0)),
            ("y", Rgb(0, 150, 0)),
            ("z", Rgb(0, 0, 230)),
        ],
    ),
    (
        "velocity of the centre of mass",
        "velocity (m/s)",
        &[
            ("vx", Rgb(220, 0, 0)),
            ("vy", Rgb(0, 150, 0)),
            ("vz", Rgb(0, 0, 230)),
        ],
    ),
    (
        "force sum",
        "force (N)",
        &[
            ("fx", Rgb(220, 0, 0)),
            ("fy", Rgb(0, 150, 0)),
            ("fz", Rgb(0, 0, 230)),
        ],
    ),
    (
        "kinetic energy",
        "energy (J)",
        &[("kinetic", Rgb(220, 0, 0))],
    ),
    (
        "particles and coordination",
        "number",
        &[("count", Rgb(0, 0, 0)), ("coordination", Rgb(0, 150, 0))],
    ),
];

/// The panels of the groups with recorded rows, in the order the groups were defined: each
/// group's columns `name.q` against the cycle (a row's first value), NaN (an empty group's
/// means) left out.
fn group_panels(scene: &Scene) -> Vec<Panel> {
    use crate::sim::range::QUANTITIES;
    let mut panels = Vec::new();
    for g in scene.groups().list.iter().filter(|g| !g.rows.is_empty()) {
        for (title, y_label, names) in GROUP_PANELS {
            let series = names
                .iter()
                .map(|(q, colour)| {
                    // Column 0 is the cycle; the quantities follow in QUANTITIES' order.
                    let c = 1 + QUANTITIES.iter().position(|n| n == q).unwrap_or(0);
                    Series {
                        name: format!("{}.{q}", g.name),
                        colour: *colour,
                        points: g
                            .rows
                            .iter()
                            .filter_map(|r| Some((*r.first()?, *r.get(c)?)))
                            .filter(|(x, y)| x.is_finite() && y.is_finite())
                            .collect(),
                    }
                })
                .collect();
            panels.push(Panel {
                title: format!("group {}: {title}", g.name),
                y_label: y_label.to_string(),
                series,
            });
        }
    }
    panels
}

/// The chart of the history recorded by `SET HIStory n`, with the groups recorded in it.
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
    panels.extend(group_panels(scene));
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
