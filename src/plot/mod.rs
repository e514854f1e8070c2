//! PNG pictures of the scene (`PLot`).

use crate::lang::command::PlotItem;
use crate::sim::Scene;

/// Draws the items on one picture and returns the file name.
pub fn plot(_scene: &Scene, items: &[PlotItem]) -> Result<String, String> {
    Err(format!(
        "PLot {items:?}: drawing is being built (issue 6); PLot SAve works"
    ))
}
