//! Line charts of y against x (`trubal chart`, `trubal sweep --chart`): the axes with round
//! ticks ([`axis`]), a fixed colour-blind-safe palette, series solid with markers or dashed
//! (a reference: the thesis, a theory), the legend in a column of its own at the right so that
//! it covers no data and is never cut. plotters' bitmap backend and the bundled font of
//! [`super::render`].

use std::ops::Range;

use plotters::coord::ranged1d::{DefaultFormatting, KeyPointHint};
use plotters::coord::{CoordTranslate, Shift};
use plotters::element::DashedPathElement;
use plotters::prelude::*;

use super::picture::Rgb;
use super::render::{FAMILY, encode_png, font};

/// Okabe & Ito's colour-blind-safe palette without its yellow (too pale on white), then grey.
pub const PALETTE: [Rgb; 8] = [
    Rgb(0, 114, 178),
    Rgb(213, 94, 0),
    Rgb(0, 158, 115),
    Rgb(204, 121, 167),
    Rgb(230, 159, 0),
    Rgb(86, 180, 233),
    Rgb(0, 0, 0),
    Rgb(120, 120, 120),
];

/// How a series is drawn.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Style {
    /// A solid line with a marker at each point (our results).
    Line,
    /// A dashed line without markers (a reference: the thesis, a theory).
    Dashed,
    /// Markers only.
    Points,
    /// A solid line without markers (what [`Style::Line`] becomes over more than
    /// [`MAX_MARKERS`] points: a dense curve).
    Solid,
}

/// The most points of a series drawn with markers.
pub const MAX_MARKERS: usize = 60;

/// One series: its legend text, its colour (an index into [`PALETTE`]; the marker's shape
/// follows it too), its style and its points (drawn in the order given).
#[derive(Clone, Debug, PartialEq)]
pub struct XySeries {
    pub label: String,
    pub colour: usize,
    pub style: Style,
    pub points: Vec<(f64, f64)>,
}

/// One axis as asked for: its name (with units), log scale, fixed ends.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct AxisSpec {
    pub label: String,
    pub log: bool,
    pub min: Option<f64>,
    pub max: Option<f64>,
}

/// A chart as plain data.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct XyChart {
    pub title: String,
    pub x: AxisSpec,
    pub y: AxisSpec,
    pub series: Vec<XySeries>,
    /// Thin grey horizontal lines (borders, a theory's constant), with their legend text.
    pub hlines: Vec<f64>,
    pub hline_label: String,
}

/// An axis as drawn: its ends and ticks in data units.
#[derive(Clone, Debug, PartialEq)]
pub struct Axis {
    pub lo: f64,
    pub hi: f64,
    pub ticks: Vec<f64>,
    /// The distance of the linear ticks (0 on a log axis).
    pub step: f64,
    pub log: bool,
}

/// Size of a chart (pixels).
pub const SIZE: (u32, u32) = (1200, 750);

/// The round step for about `n` intervals over `span`: 1, 2, 2.5 or 5 times a power of ten.
pub fn round_step(span: f64, n: f64) -> f64 {
    let raw = (span / n).abs();
    if !(raw > 0.0) || !raw.is_finite() {
        return 1.0;
    }
    let p = 10f64.powf(raw.log10().floor());
    let m = [1.0, 2.0, 2.5, 5.0, 10.0]
        .into_iter()
        .find(|m| m * p >= raw * (1.0 - 1e-9))
        .unwrap_or(10.0);
    m * p
}

/// Rounds away the binary noise of `k × step` (0.30000000000000004 → 0.3).
fn clean(v: f64) -> f64 {
    if v == 0.0 {
        return 0.0;
    }
    let digits = 12 - v.abs().log10().floor() as i32;
    let f = 10f64.powi(digits.clamp(-300, 300));
    let r = (v * f).round() / f;
    if r.is_finite() { r } else { v }
}

/// The axis over data from `lo` to `hi` (or the fixed ends given): linear, ends and ticks at
/// multiples of a round step; log, ticks at 1, 2, 5 × 10^k (every decade over wide ranges),
/// ends at ticks. `lo`, `hi` must be finite (and positive on a log axis).
pub fn axis(lo: f64, hi: f64, spec: &AxisSpec) -> Axis {
    let (mut lo, mut hi) = (spec.min.unwrap_or(lo), spec.max.unwrap_or(hi));
    if spec.log {
        return log_axis(lo, hi, spec);
    }
    if !(hi > lo) {
        let d = if lo == 0.0 { 1.0 } else { 0.1 * lo.abs() };
        (lo, hi) = (lo - d, hi + d);
    }
    let step = round_step(hi - lo, 7.0);
    let a = if spec.min.is_some() {
        lo
    } else {
        clean((lo / step + 1e-9).floor() * step)
    };
    let b = if spec.max.is_some() {
        hi
    } else {
        clean((hi / step - 1e-9).ceil() * step)
    };
    let first = (a / step - 1e-9).ceil() as i64;
    let last = (b / step + 1e-9).floor() as i64;
    let ticks = (first..=last).map(|k| clean(k as f64 * step)).collect();
    Axis {
        lo: a,
        hi: b,
        ticks,
        step,
        log: false,
    }
}

fn log_axis(lo: f64, hi: f64, spec: &AxisSpec) -> Axis {
    let (mut lo, mut hi) = (lo, hi);
    if !(hi > lo) {
        (lo, hi) = (lo / 2.0, hi * 2.0);
    }
    // The ends a little outside the data (4 % of the decades shown, at least 5 %).
    let pad = (hi / lo).powf(0.04).max(1.05);
    let a = spec.min.unwrap_or(lo / pad);
    let b = spec.max.unwrap_or(hi * pad);
    let decades = (b / a).log10();
    let mantissas: &[f64] = if decades > 3.0 {
        &[1.0]
    } else if decades > 0.7 {
        &[1.0, 2.0, 5.0]
    } else {
        &[1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0, 8.0, 9.0]
    };
    let (e0, e1) = (a.log10().floor() as i32, b.log10().ceil() as i32);
    let ticks = (e0..=e1)
        .flat_map(|e| mantissas.iter().map(move |m| clean(m * 10f64.powi(e))))
        .filter(|t| *t >= a && *t <= b)
        .collect();
    Axis {
        lo: a,
        hi: b,
        ticks,
        step: 0.0,
        log: true,
    }
}

/// The text of a tick: as many decimals as the step needs; very large and very small
/// numbers as `2.5e-6`.
pub fn tick_text(v: f64, step: f64) -> String {
    if v == 0.0 {
        return "0".into();
    }
    let a = v.abs();
    if !(1e-3..1e5).contains(&a) {
        let s = format!("{:e}", clean(v));
        let (m, e) = s.split_once('e').unwrap_or((&s, "0"));
        return format!("{m}e{e}");
    }
    let decimals = if step > 0.0 {
        let p = -(step.log10().floor() as i32);
        let quarter = ((step / 10f64.powi(-p)) - 2.5).abs() < 1e-6;
        (p + quarter as i32).clamp(0, 9) as usize
    } else {
        9
    };
    let s = format!("{:.*}", decimals, clean(v));
    if step > 0.0 || !s.contains('.') {
        s
    } else {
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    }
}

/// The text of a tick of axis `a`: on a log axis that reaches 1e5 or 1e-3, every tick as
/// `1e4` (not `1000`, `10000`, `1e5` side by side).
pub fn axis_text(a: &Axis, v: f64) -> String {
    let big = a.ticks.iter().any(|t| t.abs() >= 1e5 || t.abs() < 1e-3);
    if a.log && big && v != 0.0 {
        let s = format!("{:e}", clean(v));
        let (m, e) = s.split_once('e').unwrap_or((&s, "0"));
        return format!("{m}e{e}");
    }
    tick_text(v, a.step)
}

fn rgb(c: Rgb) -> RGBColor {
    RGBColor(c.0, c.1, c.2)
}

fn err<E: std::fmt::Debug>(e: E) -> String {
    format!("the chart cannot be drawn: {e:?}")
}

/// The data's range on one axis (points outside a fixed end left out of nothing: they are
/// clipped when drawn).
fn data_range(ch: &XyChart, pick: impl Fn(&(f64, f64)) -> f64) -> (f64, f64) {
    let mut v: Vec<f64> = ch
        .series
        .iter()
        .flat_map(|s| s.points.iter().map(&pick))
        .collect();
    if pick(&(0.0, 1.0)) == 1.0 {
        v.extend(ch.hlines.iter().copied());
    }
    let lo = v.iter().copied().fold(f64::INFINITY, f64::min);
    let hi = v.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    if lo.is_finite() { (lo, hi) } else { (0.0, 1.0) }
}

/// Both axes of a chart; an error if a log axis has a value ≤ 0 or there is nothing to draw.
pub fn axes(ch: &XyChart) -> Result<(Axis, Axis), String> {
    if ch.series.iter().all(|s| s.points.is_empty()) {
        return Err("the chart has no point to draw".into());
    }
    for s in &ch.series {
        for &(x, y) in &s.points {
            if !x.is_finite() || !y.is_finite() {
                return Err(format!(
                    "series `{}`: the point ({x}, {y}) is not finite",
                    s.label
                ));
            }
            for (log, v, name) in [(ch.x.log, x, "x"), (ch.y.log, y, "y")] {
                if log && v <= 0.0 {
                    return Err(format!(
                        "series `{}`: {name} = {v} cannot be drawn on a log axis",
                        s.label
                    ));
                }
            }
        }
    }
    let (x0, x1) = data_range(ch, |p| p.0);
    let (y0, y1) = data_range(ch, |p| p.1);
    Ok((axis(x0, x1, &ch.x), axis(y0, y1, &ch.y)))
}

/// The PNG bytes of the chart.
pub fn xy_png(ch: &XyChart) -> Result<Vec<u8>, String> {
    font()?;
    let mut ch = ch.clone();
    for s in &mut ch.series {
        if s.style == Style::Line && s.points.len() > MAX_MARKERS {
            s.style = Style::Solid;
        }
    }
    let ch = &ch;
    let (xa, ya) = axes(ch)?;
    let (w, h) = SIZE;
    let mut buf = vec![255u8; (w as usize) * (h as usize) * 3];
    {
        let root = BitMapBackend::with_buffer(&mut buf, (w, h)).into_drawing_area();
        root.fill(&WHITE).map_err(err)?;
        let root = if ch.title.is_empty() {
            root
        } else {
            root.titled(&ch.title, (FAMILY, 24).into_font())
                .map_err(err)?
        };
        let entries = legend_entries(ch);
        let label_font: TextStyle = (FAMILY, 17).into_font().into();
        let mut widest = 0;
        for (text, _, _) in &entries {
            widest = widest.max(root.estimate_text_size(text, &label_font).map_err(err)?.0);
        }
        let legend_w = (widest + 80).min(w / 2);
        let (plot, side) = root.split_horizontally(w - legend_w);
        draw_plot(&plot, ch, &xa, &ya)?;
        draw_legend(&side, &entries)?;
        root.present().map_err(err)?;
    }
    encode_png(w, h, &buf)
}

/// A linear coordinate with the ticks given (plotters' own choice is not round enough).
struct Ticked(Range<f64>, Vec<f64>);

impl Ranged for Ticked {
    type ValueType = f64;
    type FormatOption = DefaultFormatting;
    fn range(&self) -> Range<f64> {
        self.0.clone()
    }
    fn map(&self, v: &f64, limit: (i32, i32)) -> i32 {
        let t = (v - self.0.start) / (self.0.end - self.0.start);
        let n = limit.1 - limit.0;
        if n == 0 || !t.is_finite() {
            return limit.1;
        }
        limit.0 + (n as f64 * t + 1e-3).floor() as i32
    }
    fn key_points<H: KeyPointHint>(&self, hint: H) -> Vec<f64> {
        if hint.weight().allow_light_points() {
            Vec::new()
        } else {
            self.1.clone()
        }
    }
}

/// Where a value sits on the drawn (linear) coordinate: log10 on a log axis.
fn at(a: &Axis, v: f64) -> f64 {
    if a.log { v.log10() } else { v }
}

fn draw_plot(
    area: &DrawingArea<BitMapBackend, Shift>,
    ch: &XyChart,
    xa: &Axis,
    ya: &Axis,
) -> Result<(), String> {
    let pad = |a: &Axis| 0.015 * (at(a, a.hi) - at(a, a.lo));
    let (px, py) = (pad(xa), pad(ya));
    let xr = (at(xa, xa.lo) - px)..(at(xa, xa.hi) + px);
    let yr = (at(ya, ya.lo) - py)..(at(ya, ya.hi) + py);
    let xk: Vec<f64> = xa.ticks.iter().map(|t| at(xa, *t)).collect();
    let yk: Vec<f64> = ya.ticks.iter().map(|t| at(ya, *t)).collect();
    let tick_font: TextStyle = (FAMILY, 17).into_font().into();
    let mut y_tick_w = 0;
    for t in &ya.ticks {
        let s = tick_text(*t, ya.step);
        y_tick_w = y_tick_w.max(area.estimate_text_size(&s, &tick_font).map_err(err)?.0);
    }
    let mut c = ChartBuilder::on(area)
        .margin(20)
        .margin_right(10)
        .x_label_area_size(64)
        .y_label_area_size(y_tick_w + 52)
        .build_cartesian_2d(Ticked(xr, xk), Ticked(yr, yk))
        .map_err(err)?;
    let label = |a: &Axis, v: f64| {
        let v = if a.log { 10f64.powf(v) } else { v };
        let near = a.ticks.iter().copied().find(|t| {
            let d = (t - v).abs();
            d <= 1e-9 * t.abs().max(v.abs()) || d == 0.0
        });
        axis_text(a, near.unwrap_or(v))
    };
    let fx = |v: &f64| label(xa, *v);
    let fy = |v: &f64| label(ya, *v);
    c.configure_mesh()
        .x_desc(ch.x.label.as_str())
        .y_desc(ch.y.label.as_str())
        .x_label_formatter(&fx)
        .y_label_formatter(&fy)
        .label_style((FAMILY, 17))
        .axis_desc_style((FAMILY, 19))
        .bold_line_style(RGBColor(225, 225, 225))
        .light_line_style(WHITE)
        .draw()
        .map_err(err)?;
    let grey = RGBColor(110, 110, 110);
    for &yv in &ch.hlines {
        let y = at(ya, yv);
        c.draw_series(DashedLineSeries::new(
            [(xr_lo(xa, px), y), (at(xa, xa.hi) + px, y)],
            4,
            4,
            ShapeStyle::from(&grey).stroke_width(1),
        ))
        .map_err(err)?;
    }
    // References first: our points on top of them.
    let mut order: Vec<&XySeries> = ch.series.iter().collect();
    order.sort_by_key(|s| s.style != Style::Dashed);
    for s in order {
        let col = rgb(PALETTE[s.colour % PALETTE.len()]);
        let pts: Vec<(f64, f64)> = s
            .points
            .iter()
            .map(|&(x, y)| (at(xa, x), at(ya, y)))
            .collect();
        match s.style {
            Style::Dashed => {
                c.draw_series(DashedLineSeries::new(
                    pts,
                    12,
                    7,
                    ShapeStyle::from(&col).stroke_width(3),
                ))
                .map_err(err)?;
            }
            Style::Line | Style::Points | Style::Solid => {
                if s.style != Style::Points {
                    c.draw_series(LineSeries::new(
                        pts.iter().copied(),
                        ShapeStyle::from(&col).stroke_width(2),
                    ))
                    .map_err(err)?;
                }
                if s.style != Style::Solid {
                    markers(c.plotting_area(), &pts, s.colour, col)?;
                }
            }
        }
    }
    Ok(())
}

fn xr_lo(xa: &Axis, px: f64) -> f64 {
    at(xa, xa.lo) - px
}

/// Markers at the points: circle, square, triangle, diamond by the colour's index.
fn markers<DB: DrawingBackend, CT: CoordTranslate>(
    area: &DrawingArea<DB, CT>,
    pts: &[CT::From],
    index: usize,
    col: RGBColor,
) -> Result<(), String>
where
    CT::From: Clone,
{
    let fill = col.filled();
    let r = 5;
    for p in pts {
        let at = EmptyElement::at(p.clone());
        match (index / PALETTE.len() + index) % 4 {
            0 => area.draw(&(at + Circle::new((0, 0), r, fill))),
            1 => area.draw(&(at + Rectangle::new([(1 - r, 1 - r), (r - 1, r - 1)], fill))),
            2 => area.draw(&(at + Polygon::new(vec![(0, -r - 1), (r + 1, r), (-r - 1, r)], fill))),
            _ => area.draw(
                &(at + Polygon::new(vec![(0, -r - 1), (r + 1, 0), (0, r + 1), (-r - 1, 0)], fill)),
            ),
        }
        .map_err(err)?;
    }
    Ok(())
}

/// The legend's lines: text, colour index, style (`None`: the horizontal lines).
fn legend_entries(ch: &XyChart) -> Vec<(String, usize, Option<Style>)> {
    let mut out: Vec<(String, usize, Option<Style>)> = ch
        .series
        .iter()
        .filter(|s| !s.points.is_empty() && !s.label.is_empty())
        .map(|s| (s.label.clone(), s.colour, Some(s.style)))
        .collect();
    if !ch.hlines.is_empty() && !ch.hline_label.is_empty() {
        out.push((ch.hline_label.clone(), 0, None));
    }
    out
}

fn draw_legend(
    area: &DrawingArea<BitMapBackend, Shift>,
    entries: &[(String, usize, Option<Style>)],
) -> Result<(), String> {
    let text = (FAMILY, 17).into_font().color(&BLACK);
    let line_h = 28;
    let top = 40;
    let sw = 44;
    for (k, (label, colour, style)) in entries.iter().enumerate() {
        let y = top + line_h * k as i32;
        let col = rgb(PALETTE[colour % PALETTE.len()]);
        match style {
            Some(Style::Dashed) => area
                .draw(&DashedPathElement::new(
                    vec![(4, y), (4 + sw, y)],
                    12,
                    7,
                    ShapeStyle::from(&col).stroke_width(3),
                ))
                .map_err(err)?,
            Some(s) => {
                if *s != Style::Points {
                    area.draw(&PathElement::new(
                        vec![(4, y), (4 + sw, y)],
                        ShapeStyle::from(&col).stroke_width(2),
                    ))
                    .map_err(err)?;
                }
                if *s != Style::Solid {
                    markers(area, &[(4 + sw / 2, y)], *colour, col)?;
                }
            }
            None => area
                .draw(&DashedPathElement::new(
                    vec![(4, y), (4 + sw, y)],
                    4,
                    4,
                    ShapeStyle::from(&RGBColor(110, 110, 110)).stroke_width(1),
                ))
                .map_err(err)?,
        }
        area.draw(&Text::new(label.clone(), (sw + 14, y - 10), text.clone()))
            .map_err(err)?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn lin() -> AxisSpec {
        AxisSpec::default()
    }

    /// Every tick a whole multiple of a 1-2-2.5-5 step, the ends on ticks around the data.
    fn check_round(lo: f64, hi: f64) {
        let a = axis(lo, hi, &lin());
        let m = a.step / 10f64.powf(a.step.log10().floor());
        assert!(
            [1.0, 2.0, 2.5, 5.0].iter().any(|r| (m - r).abs() < 1e-9),
            "{lo}..{hi}: step {}",
            a.step
        );
        assert!(
            (4..=12).contains(&a.ticks.len()),
            "{lo}..{hi}: {:?}",
            a.ticks
        );
        for t in &a.ticks {
            let k = t / a.step;
            assert!((k - k.round()).abs() < 1e-6, "{lo}..{hi}: tick {t}");
        }
        assert!(a.lo <= lo && a.hi >= hi, "{lo}..{hi}: {a:?}");
        assert_eq!((a.ticks[0], *a.ticks.last().unwrap()), (a.lo, a.hi));
    }

    #[test]
    fn linear_ticks_are_round() {
        // The old charts' ticks at 0.265, 1.3, 2.33, 3.37: now 0, 0.5, ..., 3.5.
        let a = axis(0.265, 3.37, &lin());
        assert_eq!(a.ticks, [0.0, 0.5, 1.0, 1.5, 2.0, 2.5, 3.0, 3.5]);
        assert_eq!(tick_text(1.5, a.step), "1.5");
        assert_eq!(tick_text(1.0, a.step), "1.0");
        let a = axis(0.0, 4.0, &lin());
        assert_eq!(a.ticks, [0.0, 1.0, 2.0, 3.0, 4.0]);
        assert_eq!(tick_text(1.0, a.step), "1");
        let a = axis(0.0, 69.5, &lin());
        assert_eq!(a.ticks, [0.0, 10.0, 20.0, 30.0, 40.0, 50.0, 60.0, 70.0]);
        assert_eq!(tick_text(20.0, a.step), "20");
        let a = axis(0.0, 0.9, &lin());
        assert_eq!(a.step, 0.2);
        assert_eq!(tick_text(a.ticks[3], a.step), "0.6");
        for (lo, hi) in [
            (0.0, 1.0),
            (-3.2, 7.9),
            (1e-7, 3.3e-6),
            (512.0, 4100.0),
            (0.55, 1.0),
        ] {
            check_round(lo, hi);
        }
        assert_eq!(tick_text(2.5e-6, 5e-7), "2.5e-6");
        assert_eq!(tick_text(-0.25, 0.25), "-0.25");
        // A single value, fixed ends.
        let a = axis(5.0, 5.0, &lin());
        assert!(a.lo < 5.0 && a.hi > 5.0);
        let fixed = AxisSpec {
            min: Some(0.0),
            max: Some(90.0),
            ..lin()
        };
        let a = axis(5.0, 85.0, &fixed);
        assert_eq!((a.lo, a.hi), (0.0, 90.0));
        assert_eq!(a.ticks, [0.0, 20.0, 40.0, 60.0, 80.0]);
    }

    #[test]
    fn log_ticks_are_one_two_five() {
        let log = AxisSpec { log: true, ..lin() };
        let a = axis(0.2, 8.0, &log);
        assert_eq!(a.ticks, [0.2, 0.5, 1.0, 2.0, 5.0]);
        assert!(
            a.lo < 0.2 && a.lo > 0.16 && a.hi > 8.0 && a.hi < 9.5,
            "{a:?}"
        );
        let texts: Vec<String> = a.ticks.iter().map(|t| tick_text(*t, a.step)).collect();
        assert_eq!(texts, ["0.2", "0.5", "1", "2", "5"]);
        let a = axis(1200.0, 3.2e6, &log);
        assert_eq!(a.ticks, [1e3, 1e4, 1e5, 1e6]);
        let texts: Vec<String> = a.ticks.iter().map(|t| axis_text(&a, *t)).collect();
        assert_eq!(texts, ["1e3", "1e4", "1e5", "1e6"]);
        let a = axis(1.2, 2.9, &log);
        assert_eq!(a.ticks, [2.0, 3.0]);
        let a = axis(0.9, 3.5, &log);
        assert_eq!(a.ticks, [0.9, 1.0, 2.0, 3.0]);
        assert_eq!(tick_text(1e6, 0.0), "1e6");
    }

    fn chart(points: Vec<(f64, f64)>, logx: bool) -> XyChart {
        XyChart {
            title: "t".into(),
            x: AxisSpec {
                label: "v [m/s]".into(),
                log: logx,
                ..lin()
            },
            y: AxisSpec {
                label: "fragmentation [%]".into(),
                ..lin()
            },
            series: vec![
                XySeries {
                    label: "ours".into(),
                    colour: 0,
                    style: Style::Line,
                    points: points.clone(),
                },
                XySeries {
                    label: "thesis".into(),
                    colour: 0,
                    style: Style::Dashed,
                    points,
                },
            ],
            hlines: vec![3.0],
            hline_label: "border".into(),
        }
    }

    #[test]
    fn draws_a_png_and_refuses_what_it_cannot_draw() {
        let png = xy_png(&chart(vec![(0.5, 1.0), (2.0, 40.0)], true)).unwrap();
        assert_eq!(&png[1..4], b"PNG");
        let e = xy_png(&chart(vec![(0.0, 1.0), (2.0, 40.0)], true)).unwrap_err();
        assert!(e.contains("x = 0 cannot be drawn on a log axis"), "{e}");
        let e = xy_png(&chart(vec![], false)).unwrap_err();
        assert!(e.contains("no point"), "{e}");
    }

    #[test]
    fn the_palette_has_no_pale_colour() {
        // Every colour differs from white by enough to be seen as a thin line (the old
        // charts' yellow did not).
        for c in PALETTE {
            let lum = 0.2126 * c.0 as f64 + 0.7152 * c.1 as f64 + 0.0722 * c.2 as f64;
            assert!(lum < 175.0, "{c:?}: luminance {lum}");
        }
    }
}
