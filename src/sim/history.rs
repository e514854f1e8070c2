//! Time series recorded every n cycles (`SET HIStory n`) for `PRint HIStory`/`PLot HIStory`.

use serde::{Deserialize, Serialize};

/// Names of the recorded quantities, in column order.
pub const COLUMNS: &[&str] = &[
    "cycle",
    "time",
    "kinetic",
    "strain",
    "input",
    "dissipated",
    "residual",
    "contacts",
    "bridges",
    "wall_force",
    "sxx",
    "syy",
    "szz",
    "sxy",
    "syz",
    "szx",
    "temperature",
    "e11",
    "e22",
    "e33",
    "e12",
];

#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct History {
    /// One row per record, columns as in [`COLUMNS`].
    pub rows: Vec<Vec<f64>>,
}
