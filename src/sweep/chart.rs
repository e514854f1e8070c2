//! The chart of a sweep: one measure against one parameter, a line per value of a second
//! (plotters' bitmap backend, the bundled font of `plot::render`).

use plotters::prelude::*;

use crate::plot::render::{FAMILY, encode_png, font};

const SIZE: (u32, u32) = (1200, 800);
const COLOURS: [(u8, u8, u8); 8] = [
    (200, 30, 30),
    (30, 90, 200),
    (20, 150, 40),
    (220, 140, 0),
    (140, 40, 170),
    (0, 150, 160),
    (120, 120, 120),
    (0, 0, 0),
];

fn err<E: std::fmt::Debug>(e: E) -> String {
    format!("the chart cannot be drawn: {e:?}")
}

fn tick(v: f64) -> String {
    if v == 0.0 {
        "0".into()
    } else if v.abs() >= 1e-3 && v.abs() < 1e5 {
        let s = format!("{v:.4}");
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        format!("{v:.2e}")
    }
}

/// The PNG bytes of the chart. Each series is sorted by x; series are ordered by their label
/// (numerically when the labels end in numbers).
pub fn xy_png(
    title: &str,
    x_label: &str,
    y_label: &str,
    series: &mut [(String, Vec<(f64, f64)>)],
    logx: bool,
) -> Result<Vec<u8>, String> {
    font()?;
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
    let fx = |x: f64| if logx { x.log10() } else { x };
    let pts = series.iter().flat_map(|(_, p)| p.iter());
    let (mut x0, mut x1, mut y0, mut y1) =
        (f64::INFINITY, f64::NEG_INFINITY, 0.0f64, f64::NEG_INFINITY);
    for &(x, y) in pts {
        x0 = x0.min(fx(x));
        x1 = x1.max(fx(x));
        y0 = y0.min(y);
        y1 = y1.max(y);
    }
    if !(x1 > x0) {
        (x0, x1) = (x0 - 1.0, x1 + 1.0);
    }
    if !(y1 > y0) {
        y1 = y0 + 1.0;
    }
    let (padx, pady) = (0.05 * (x1 - x0), 0.06 * (y1 - y0));
    let (x0, x1) = (x0 - padx, x1 + padx);
    let (y0, y1) = (if y0 < 0.0 { y0 - pady } else { y0 }, y1 + pady);
    let (w, h) = SIZE;
    let mut buf = vec![255u8; (w as usize) * (h as usize) * 3];
    {
        let root = BitMapBackend::with_buffer(&mut buf, (w, h)).into_drawing_area();
        root.fill(&WHITE).map_err(err)?;
        let mut c = ChartBuilder::on(&root)
            .caption(title, (FAMILY, 26).into_font())
            .margin(24)
            .x_label_area_size(60)
            .y_label_area_size(110)
            .build_cartesian_2d(x0..x1, y0..y1)
            .map_err(err)?;
        let fmt_x = |v: &f64| tick(if logx { 10f64.powf(*v) } else { *v });
        let fmt_y = |v: &f64| tick(*v);
        let x_desc = if logx {
            format!("{x_label} (log scale)")
        } else {
            x_label.to_string()
        };
        c.configure_mesh()
            .x_desc(x_desc)
            .y_desc(y_label)
            .x_label_formatter(&fmt_x)
            .y_label_formatter(&fmt_y)
            .label_style((FAMILY, 16))
            .axis_desc_style((FAMILY, 18))
            .draw()
            .map_err(err)?;
        for (k, (label, pts)) in series.iter().enumerate() {
            let (r, g, b) = COLOURS[k % COLOURS.len()];
            let col = RGBColor(r, g, b);
            let line: Vec<(f64, f64)> = pts.iter().map(|&(x, y)| (fx(x), y)).collect();
            c.draw_series(LineSeries::new(
                line.iter().copied(),
                ShapeStyle::from(&col).stroke_width(2),
            ))
            .map_err(err)?
            .label(label.as_str())
            .legend(move |(x, y)| {
                PathElement::new(
                    vec![(x, y), (x + 24, y)],
                    ShapeStyle::from(&col).stroke_width(3),
                )
            });
            c.draw_series(line.iter().map(|&p| Circle::new(p, 4, col.filled())))
                .map_err(err)?;
        }
        c.configure_series_labels()
            .position(SeriesLabelPosition::UpperLeft)
            .label_font((FAMILY, 16))
            .background_style(WHITE.mix(0.85))
            .border_style(BLACK)
            .draw()
            .map_err(err)?;
        root.present().map_err(err)?;
    }
    encode_png(w, h, &buf)
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
