//! `HIStory name EVery k expr`: the value of any expression recorded during cycling at every
//! cycle that is a multiple of k (the Cycle runs in pieces that end there, as for `VTk
//! EVery`: the same bits as one piece), next to the fixed columns of `SET HIStory`. Printed
//! with `PRint HIStory` (a table, or one JSON object per history), written to CSV with
//! `HIStory WRIte file`, charted with `PLot HIStory`. Part of the checkpoint.

use serde::{Deserialize, Serialize};
use serde_json::json;

use super::query::Names;
use crate::lang::expr;
use crate::session::{Flow, Session};

/// One user history: its expression (as written; read again at every record) and its rows.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct UserHistory {
    pub name: String,
    pub every: u64,
    pub expr: String,
    /// (cycle, time, value).
    pub rows: Vec<(u64, f64, f64)>,
}

/// Most rows a history keeps (its oldest are dropped beyond; the fixed history's rule).
pub const MAX_ROWS: usize = 1_000_000;

impl Session {
    /// `HIStory name EVery k expr` (the expression checked now), or `HIStory name OFF`.
    pub(super) fn history_define(
        &mut self,
        name: &str,
        every: Option<u64>,
        text: Option<&str>,
    ) -> Result<Flow, String> {
        let hs = &mut self.script.state.histories;
        let (Some(every), Some(text)) = (every, text) else {
            let before = hs.len();
            hs.retain(|h| h.name != name);
            if hs.len() == before {
                return Err(format!("no history `{name}` to stop"));
            }
            self.emit(&format!("HIStory: {name} stopped (its rows are dropped)"));
            return Ok(Flow::Continue);
        };
        expr::parse(text, 0).map_err(|e| format!("{} (in `{text}`)", e.message))?;
        let h = UserHistory {
            name: name.to_string(),
            every,
            expr: text.to_string(),
            rows: Vec::new(),
        };
        match hs.iter_mut().find(|h| h.name == name) {
            Some(old) => *old = h,
            None => hs.push(h),
        }
        self.emit(&format!(
            "HIStory: {name} = {text}, recorded every {every} cycles"
        ));
        Ok(Flow::Continue)
    }

    /// The next piece of a Cycle ends at the next multiple of a history's interval.
    pub(in crate::session) fn history_piece(&self, cycle: u64, m: u64) -> u64 {
        self.script
            .state
            .histories
            .iter()
            .fold(m, |m, h| m.min(h.every - cycle % h.every))
    }

    /// After a piece: the histories due at this cycle record their value. An expression
    /// that cannot be read now (a particle gone) records nothing; its first such failure is
    /// a warning.
    pub(in crate::session) fn history_record(&mut self) {
        let Some(scene) = self.scene.as_ref() else {
            return;
        };
        let (cycle, time) = (scene.cycle(), scene.time());
        let mut warn = Vec::new();
        let mut values = Vec::new();
        {
            let names = Names {
                vars: &self.script.state.vars,
                scene: Some(scene),
            };
            for (k, h) in self.script.state.histories.iter().enumerate() {
                if !cycle.is_multiple_of(h.every) {
                    continue;
                }
                match expr::parse(&h.expr, 0).and_then(|e| expr::eval(&e, &names)) {
                    Ok(v) => values.push((k, v)),
                    Err(e) => warn.push(format!(
                        "HIStory {} not recorded at cycle {cycle}: {}",
                        h.name, e.message
                    )),
                }
            }
        }
        for (k, v) in values {
            let rows = &mut self.script.state.histories[k].rows;
            if rows.len() >= MAX_ROWS {
                rows.remove(0);
            }
            rows.push((cycle, time, v));
        }
        for w in warn {
            self.emit_err(&format!("warning: {w}"));
        }
    }

    /// What `PRint HIStory` adds: each history as a table (or JSON object).
    pub(in crate::session) fn history_print(&self) -> String {
        let mut out = String::new();
        for h in &self.script.state.histories {
            if self.json {
                out.push_str(
                    &json!({"print": "history", "name": h.name, "expr": h.expr, "every": h.every,
                        "columns": ["cycle", "time", &h.name], "rows": h.rows.iter().map(|r| json!([r.0, r.1, r.2])).collect::<Vec<_>>()})
                    .to_string(),
                );
                out.push('\n');
            } else {
                out.push_str(&format!(
                    "HIStory {} = {} (every {} cycles)\n",
                    h.name, h.expr, h.every
                ));
                out.push_str(&csv(h));
            }
        }
        out
    }

    /// `HIStory WRIte file`: every history in one CSV file, one row per record (name, cycle,
    /// time, value).
    pub(super) fn history_write(&mut self, file: &str) -> Result<Flow, String> {
        let mut s = String::from("name,cycle,time,value\n");
        for h in &self.script.state.histories {
            for r in &h.rows {
                s.push_str(&format!("{},{},{:e},{:e}\n", h.name, r.0, r.1, r.2));
            }
        }
        let path = crate::session::join(&self.dir, file);
        std::fs::write(&path, s).map_err(|e| format!("cannot write {file}: {e}"))?;
        let n: usize = self
            .script
            .state
            .histories
            .iter()
            .map(|h| h.rows.len())
            .sum();
        self.emit(&format!("HIStory: {n} rows written to {file}"));
        Ok(Flow::Continue)
    }

    /// What `PLot HIStory` adds: one chart of the histories against time (written next to
    /// the other pictures); `None` when there are none.
    pub(in crate::session) fn history_plot(&self) -> Result<Option<String>, String> {
        use crate::plot::xy::{AxisSpec, Style, XyChart, XySeries};
        let hs = &self.script.state.histories;
        if hs.iter().all(|h| h.rows.is_empty()) {
            return Ok(None);
        }
        let Some(scene) = self.scene.as_ref() else {
            return Ok(None);
        };
        let chart = XyChart {
            title: "HIStory".into(),
            x: AxisSpec {
                label: "time (s)".into(),
                ..AxisSpec::default()
            },
            y: AxisSpec {
                label: hs
                    .iter()
                    .map(|h| h.name.as_str())
                    .collect::<Vec<_>>()
                    .join(", "),
                ..AxisSpec::default()
            },
            series: hs
                .iter()
                .enumerate()
                .map(|(k, h)| XySeries {
                    label: format!("{} = {}", h.name, h.expr),
                    colour: k,
                    style: Style::Line,
                    points: h.rows.iter().map(|r| (r.1, r.2)).collect(),
                })
                .collect(),
            hlines: Vec::new(),
            hline_label: String::new(),
        };
        let png = crate::plot::xy::xy_png(&chart)?;
        let name = format!("plot_c{:08}_histories.png", scene.cycle());
        let shown = crate::output::vtk::write_file(scene, &name, &png)?;
        Ok(Some(shown))
    }
}

/// A history as CSV: cycle, time, value.
fn csv(h: &UserHistory) -> String {
    let mut s = format!("cycle,time,{}\n", h.name);
    for r in &h.rows {
        s.push_str(&format!("{},{:e},{:e}\n", r.0, r.1, r.2));
    }
    s
}

impl Session {
    /// `PLot ... HIStory ...` with histories recorded: their chart is drawn, and the items
    /// left for the other pictures are returned (HIStory among them only if `SET HIStory`
    /// recorded rows). `None`: no history of HIStory has rows.
    pub(in crate::session) fn plot_histories(
        &mut self,
        items: &[crate::lang::command::PlotItem],
    ) -> Result<Option<Vec<crate::lang::command::PlotItem>>, String> {
        let Some(file) = self.history_plot()? else {
            return Ok(None);
        };
        self.emit(&format!("plot written to {file}"));
        let fixed = self
            .scene
            .as_ref()
            .is_some_and(|s| !s.history().rows.is_empty());
        Ok(Some(
            items
                .iter()
                .copied()
                .filter(|&i| fixed || i != crate::lang::command::PlotItem::History)
                .collect(),
        ))
    }
}
