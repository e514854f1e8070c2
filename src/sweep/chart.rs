//! The chart of a sweep: one measure against one parameter, a line per value of a second,
//! drawn by [`crate::plot::xy`] (the chart path of `trubal chart`).

use crate::plot::xy::{AxisSpec, Style, XyChart, XySeries, xy_png as draw};

/// The PNG bytes of the chart. Each series is sorted by x; series are ordered by their label
/// (numerically when the labels end in numbers). A log x axis only if every x is positive.
pub fn xy_png(
    title: &str,
    x_label: &str,
    y_label: &str,
    series: &mut [(String, Vec<(f64, f64)>)],
    logx: bool,
) -> Result<Vec<u8>, String> {
    for (_, pts) in series.iter_mut() {
        pts.sort_by(|a, b| a.0.total_cmp(&b.0));
    }
    let key = |l: &str| {
        l.rsplit(' ')
            .next()
            .and_then(crate::lang::lexer::parse_real)
            .unwrap_or(f64::NAN)
    };
    series.sort_by(|a, b| key(&a.0).total_cmp(&key(&b.0)).then(a.0.cmp(&b.0)));
    let logx = logx && series.iter().all(|(_, p)| p.iter().all(|(x, _)| *x > 0.0));
    let chart = XyChart {
        title: title.to_string(),
        x: AxisSpec {
            label: x_label.to_string(),
            log: logx,
            ..AxisSpec::default()
        },
        y: AxisSpec {
            label: y_label.to_string(),
            ..AxisSpec::default()
        },
        series: series
            .iter()
            .enumerate()
            .map(|(k, (label, pts))| XySeries {
                label: label.clone(),
                colour: k,
                style: Style::Line,
                points: pts.clone(),
            })
            .collect(),
        ..XyChart::default()
    };
    draw(&chart)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn draws_a_png() {
        let mut s = vec![
            ("eta = 0.01".to_string(), vec![(2.0, 0.5), (0.5, 0.1)]),
            ("eta = 0".to_string(), vec![(1.0, 0.3)]),
        ];
        let png = xy_png("t", "v", "damage", &mut s, true).unwrap();
        assert_eq!(&png[1..4], b"PNG");
        assert_eq!(s[0].0, "eta = 0");
        assert_eq!(s[1].1, [(0.5, 0.1), (2.0, 0.5)]);
    }
}
