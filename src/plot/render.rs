//! [`Picture`] and [`Chart`] → RGB pixels → PNG bytes, with plotters' bitmap backend and the
//! bundled DejaVu Sans font (no system fonts).

use std::collections::HashMap;
use std::f64::consts::PI;
use std::sync::OnceLock;

use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::FontStyle;

use super::picture::{Arc, Chart, Layer, Mark, Picture, Rgb, Shade, Swatch, colour};

/// The bundled font (assets/DejaVuSans.ttf; licence in assets/DejaVu-LICENSE).
static FONT: &[u8] = include_bytes!("../../assets/DejaVuSans.ttf");
pub(crate) const FAMILY: &str = "sans-serif";

/// Registers the bundled font once.
pub(crate) fn font() -> Result<(), String> {
    static DONE: OnceLock<Result<(), String>> = OnceLock::new();
    DONE.get_or_init(|| {
        plotters::style::register_font(FAMILY, FontStyle::Normal, FONT)
            .map_err(|_| "the bundled font assets/DejaVuSans.ttf is not a valid font".to_string())
    })
    .clone()
}

/// Width of the drawing region and of the legend column, in pixels.
pub const PLOT_W: f64 = 1100.0;
pub const PLOT_H_MAX: f64 = 1100.0;
pub const LEGEND_W: u32 = 380;
const PAD: u32 = 30;
const TITLE_H: u32 = 56;
const BOTTOM_H: u32 = 70;
const LINE_H: i32 = 26;
/// Characters per line of legend text.
const LEGEND_CHARS: usize = 34;

/// Width of the scene pictures (pixels).
pub const WIDTH: u32 = PAD + PLOT_W as u32 + PAD + LEGEND_W;
/// Size of the history charts (pixels).
pub const CHART_SIZE: (u32, u32) = (1400, 1000);

fn rgb(c: Rgb) -> RGBColor {
    RGBColor(c.0, c.1, c.2)
}

fn err<E: std::fmt::Display>(e: E) -> String {
    format!("drawing the picture failed: {e}")
}

/// Wraps text at about `n` characters.
fn wrap(text: &str, n: usize) -> Vec<String> {
    let mut lines = Vec::new();
    let mut cur = String::new();
    for w in text.split_whitespace() {
        if !cur.is_empty() && cur.chars().count() + 1 + w.chars().count() > n {
            lines.push(std::mem::take(&mut cur));
        }
        if !cur.is_empty() {
            cur.push(' ');
        }
        cur.push_str(w);
    }
    if !cur.is_empty() {
        lines.push(cur);
    }
    lines
}

/// Pixel layout of a picture.
struct Layout {
    scale: f64,
    x0: f64,
    y0: f64,
    pw: u32,
    ph: u32,
    height: u32,
}

fn layout(pic: &Picture) -> Layout {
    let b = &pic.bounds;
    let (w, h) = (b.width().max(1e-300), b.height().max(1e-300));
    let scale = (PLOT_W / w).min(PLOT_H_MAX / h);
    let pw = (w * scale).round().clamp(1.0, PLOT_W) as u32;
    let ph = (h * scale).round().clamp(1.0, PLOT_H_MAX) as u32;
    let x0 = PAD as f64 + (PLOT_W - pw as f64) / 2.0;
    let y0 = TITLE_H as f64;
    let legend_lines: usize = pic
        .legend
        .iter()
        .map(|e| wrap(&e.text, LEGEND_CHARS).len().max(1))
        .sum::<usize>()
        + pic.notes.iter().map(|n| wrap(n, 40).len()).sum::<usize>()
        + 3;
    let legend_h = TITLE_H + (legend_lines as u32) * LINE_H as u32 + PAD;
    let height = (TITLE_H + ph + BOTTOM_H).max(legend_h).max(600);
    Layout {
        scale,
        x0,
        y0,
        pw,
        ph,
        height,
    }
}

/// Renders a scene picture; returns (width, height, RGB bytes).
pub fn picture_pixels(pic: &Picture) -> Result<(u32, u32, Vec<u8>), String> {
    font()?;
    let l = layout(pic);
    let (w, h) = (WIDTH, l.height);
    let mut buf = vec![255u8; (w as usize) * (h as usize) * 3];
    {
        let root = BitMapBackend::with_buffer(&mut buf, (w, h)).into_drawing_area();
        root.fill(&WHITE).map_err(err)?;
        draw_picture(&root, pic, &l)?;
        root.present().map_err(err)?;
    }
    Ok((w, h, buf))
}

fn draw_picture(
    root: &DrawingArea<BitMapBackend<'_>, Shift>,
    pic: &Picture,
    l: &Layout,
) -> Result<(), String> {
    let b = pic.bounds;
    let s = l.scale;
    let area = root
        .clone()
        .shrink((l.x0.round() as i32, l.y0.round() as i32), (l.pw, l.ph));
    let px = |p: [f64; 2]| -> (f64, f64) { ((p[0] - b.umin) * s, (b.vmax - p[1]) * s) };
    let ipx = |p: [f64; 2]| -> (i32, i32) {
        let (x, y) = px(p);
        (x.round() as i32, y.round() as i32)
    };
    // Frame.
    root.draw(&Rectangle::new(
        [
            (l.x0 as i32 - 1, l.y0 as i32 - 1),
            ((l.x0 as i32) + l.pw as i32, (l.y0 as i32) + l.ph as i32),
        ],
        ShapeStyle::from(&rgb(colour::LIGHT_GREY)).stroke_width(1),
    ))
    .map_err(err)?;

    let seg = |layer_filter: &dyn Fn(Layer) -> bool| -> Result<(), String> {
        for sg in pic.segments.iter().filter(|sg| layer_filter(sg.layer)) {
            let min_px = match (sg.layer, sg.mark) {
                (_, Mark::Hatch) => 1.0,
                (Layer::Boundary, _) => 2.0,
                (Layer::Wall, _) => 3.0,
                (Layer::Cnd(_), _) => 2.0,
                _ => 1.0,
            };
            let wpx = (sg.width * s).max(min_px);
            let style = ShapeStyle::from(&rgb(sg.colour)).stroke_width(wpx.round().max(1.0) as u32);
            let (a, e) = (px(sg.a), px(sg.b));
            if sg.mark == Mark::Dashed {
                let len = ((e.0 - a.0).powi(2) + (e.1 - a.1).powi(2)).sqrt();
                let (on, off) = (12.0, 8.0);
                let mut t = 0.0;
                while t < len {
                    let t1 = (t + on).min(len);
                    let p0 = (a.0 + (e.0 - a.0) * t / len, a.1 + (e.1 - a.1) * t / len);
                    let p1 = (a.0 + (e.0 - a.0) * t1 / len, a.1 + (e.1 - a.1) * t1 / len);
                    area.draw(&PathElement::new(
                        vec![
                            (p0.0.round() as i32, p0.1.round() as i32),
                            (p1.0.round() as i32, p1.1.round() as i32),
                        ],
                        style,
                    ))
                    .map_err(err)?;
                    t += on + off;
                }
            } else {
                area.draw(&PathElement::new(vec![ipx(sg.a), ipx(sg.b)], style))
                    .map_err(err)?;
            }
        }
        Ok(())
    };

    seg(&|l| l == Layer::Boundary)?;
    // Arcs belong to their particle: drawn right after its disc, so nearer discs hide them.
    let mut arcs_of: HashMap<u32, Vec<&Arc>> = HashMap::new();
    for a in &pic.arcs {
        arcs_of.entry(a.id).or_default().push(a);
    }
    for d in &pic.discs {
        draw_disc(&area, ipx(d.centre), d.radius * s, d.fill, d.shade)?;
        for a in arcs_of.remove(&d.id).unwrap_or_default() {
            draw_arc(&area, a, s, px(a.centre))?;
        }
    }
    let mut rest: Vec<&Arc> = arcs_of.into_values().flatten().collect();
    rest.sort_by(|a, b| b.depth.total_cmp(&a.depth).then(a.id.cmp(&b.id)));
    for r in &pic.rings {
        let c = ipx(r.centre);
        let rp = (r.radius * s).round().max(1.0) as i32;
        if let Some(f) = r.fill {
            area.draw(&Circle::new(c, rp, rgb(f).mix(0.25).filled()))
                .map_err(err)?;
        }
        area.draw(&Circle::new(
            c,
            rp,
            ShapeStyle::from(&rgb(r.colour)).stroke_width(3),
        ))
        .map_err(err)?;
    }
    seg(&|l| l == Layer::Wall)?;
    seg(&|l| !matches!(l, Layer::Boundary | Layer::Wall))?;
    for a in rest {
        draw_arc(&area, a, s, px(a.centre))?;
    }
    for a in &pic.arrows {
        area.draw(&PathElement::new(
            vec![ipx(a.from), ipx(a.to)],
            ShapeStyle::from(&rgb(colour::VECTOR)).stroke_width(1),
        ))
        .map_err(err)?;
        area.draw(&Circle::new(ipx(a.to), 3, rgb(colour::TIP).filled()))
            .map_err(err)?;
    }

    titles(root, pic, l)?;
    legend(root, pic, l)
}

/// The title, the scale bar and the axes' names under the plot.
fn titles(
    root: &DrawingArea<BitMapBackend<'_>, Shift>,
    pic: &Picture,
    l: &Layout,
) -> Result<(), String> {
    let s = l.scale;
    // Title, scale bar, axes.
    let title = (FAMILY, 22).into_font().color(&BLACK);
    let text = (FAMILY, 17).into_font().color(&BLACK);
    root.draw_text(&pic.title, &title, (PAD as i32, 16))
        .map_err(err)?;
    let yb = (l.y0 as i32) + l.ph as i32 + 35;
    if let Some(bar) = &pic.scale_bar {
        let len = (bar.length * s).round() as i32;
        let x = l.x0 as i32;
        let st = ShapeStyle::from(&BLACK).stroke_width(3);
        root.draw(&PathElement::new(vec![(x, yb), (x + len, yb)], st))
            .map_err(err)?;
        for xe in [x, x + len] {
            root.draw(&PathElement::new(vec![(xe, yb - 7), (xe, yb + 7)], st))
                .map_err(err)?;
        }
        root.draw_text(&bar.label, &text, (x + len + 12, yb - 9))
            .map_err(err)?;
    }
    let axes = format!("{} →   {} ↑", pic.axes[0], pic.axes[1]);
    root.draw_text(&axes, &text, ((l.x0 as i32) + l.pw as i32 - 110, yb - 9))
        .map_err(err)?;

    Ok(())
}

/// The legend and the notes beside the plot.
fn legend(
    root: &DrawingArea<BitMapBackend<'_>, Shift>,
    pic: &Picture,
    l: &Layout,
) -> Result<(), String> {
    let text = (FAMILY, 17).into_font().color(&BLACK);
    let small = (FAMILY, 15).into_font().color(&RGBColor(60, 60, 60));
    // Legend and notes.
    let lx = (PAD + PLOT_W as u32 + PAD) as i32;
    let mut y = l.y0 as i32 + 4;
    for e in &pic.legend {
        let cy = y + 9;
        match e.swatch {
            Swatch::Disc(c) => draw_disc(root, (lx + 14, cy), 9.0, c, Shade::Sphere)?,
            Swatch::Line(c) => root
                .draw(&PathElement::new(
                    vec![(lx, cy), (lx + 30, cy)],
                    ShapeStyle::from(&rgb(c)).stroke_width(4),
                ))
                .map_err(err)?,
            Swatch::Vector => {
                root.draw(&PathElement::new(
                    vec![(lx, cy), (lx + 28, cy)],
                    ShapeStyle::from(&rgb(colour::VECTOR)).stroke_width(1),
                ))
                .map_err(err)?;
                root.draw(&Circle::new((lx + 28, cy), 3, rgb(colour::TIP).filled()))
                    .map_err(err)?;
            }
            Swatch::Arc(c) => {
                let sweep = if c == colour::CLOCKWISE {
                    -1.5 * PI
                } else {
                    1.5 * PI
                };
                let pts = arc_points(((lx + 14) as f64, cy as f64), 8.0, 0.5 * PI, sweep);
                root.draw(&PathElement::new(
                    pts,
                    ShapeStyle::from(&rgb(c)).stroke_width(2),
                ))
                .map_err(err)?;
            }
            Swatch::None => {}
        }
        let x = if e.swatch == Swatch::None {
            lx
        } else {
            lx + 40
        };
        for line in wrap(&e.text, LEGEND_CHARS) {
            root.draw_text(&line, &text, (x, y)).map_err(err)?;
            y += LINE_H;
        }
    }
    y += LINE_H / 2;
    for n in &pic.notes {
        for line in wrap(n, 40) {
            root.draw_text(&line, &small, (lx, y)).map_err(err)?;
            y += LINE_H - 4;
        }
        y += 4;
    }
    Ok(())
}

/// A rotation or couple arc with its arrow head; `c` is its centre in pixels.
fn draw_arc<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    a: &Arc,
    s: f64,
    c: (f64, f64),
) -> Result<(), String> {
    let e = |x: DrawingAreaErrorKind<DB::ErrorType>| format!("drawing the picture failed: {x:?}");
    let (cx, cy) = c;
    let rp = (a.radius * s).max(3.0);
    let pts = arc_points((cx, cy), rp, a.start, a.sweep);
    let col = rgb(a.colour);
    area.draw(&PathElement::new(
        pts,
        ShapeStyle::from(&col).stroke_width(2),
    ))
    .map_err(e)?;
    // Arrow head along the tangent at the end (pixel y points down).
    let end = a.start + a.sweep;
    let sign = a.sweep.signum();
    let (ex, ey) = (cx + rp * end.cos(), cy - rp * end.sin());
    let (tx, ty) = (-end.sin() * sign, -end.cos() * sign);
    let hs = (rp * 0.5).clamp(3.0, 8.0);
    let (nx, ny) = (-ty, tx);
    let r = |p: (f64, f64)| (p.0.round() as i32, p.1.round() as i32);
    let head = vec![
        r((ex + tx * hs, ey + ty * hs)),
        r((ex + nx * hs * 0.6, ey + ny * hs * 0.6)),
        r((ex - nx * hs * 0.6, ey - ny * hs * 0.6)),
    ];
    area.draw(&Polygon::new(head, col.filled())).map_err(e)?;
    Ok(())
}

/// Points of an arc in pixel coordinates (y down), angles anticlockwise as seen.
fn arc_points(c: (f64, f64), r: f64, start: f64, sweep: f64) -> Vec<(i32, i32)> {
    let n = ((sweep.abs() / (PI / 24.0)).ceil() as usize).clamp(2, 96);
    (0..=n)
        .map(|k| {
            let a = start + sweep * k as f64 / n as f64;
            (
                (c.0 + r * a.cos()).round() as i32,
                (c.1 - r * a.sin()).round() as i32,
            )
        })
        .collect()
}

/// A particle: sphere-like shading (dark rim, highlight up-left) or a flat disc.
fn draw_disc<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    c: (i32, i32),
    rp: f64,
    fill: Rgb,
    shade: Shade,
) -> Result<(), String> {
    let e = |x: DrawingAreaErrorKind<DB::ErrorType>| format!("drawing the picture failed: {x:?}");
    if rp < 2.0 {
        let r = rp.round().max(1.0) as i32;
        return area.draw(&Circle::new(c, r, rgb(fill).filled())).map_err(e);
    }
    match shade {
        Shade::Flat => {
            area.draw(&Circle::new(c, rp.round() as i32, rgb(fill).filled()))
                .map_err(e)?;
            area.draw(&Circle::new(
                c,
                rp.round() as i32,
                ShapeStyle::from(&rgb(fill.mix(colour::BLACK, 0.5))).stroke_width(1),
            ))
            .map_err(e)?;
        }
        Shade::Sphere => {
            let n = ((rp / 2.0).round() as usize).clamp(2, 10);
            area.draw(&Circle::new(
                c,
                rp.round() as i32,
                rgb(fill.mix(colour::BLACK, 0.45)).filled(),
            ))
            .map_err(e)?;
            for k in 1..=n {
                let t = k as f64 / n as f64;
                let col = if t < 0.35 {
                    fill.mix(colour::BLACK, 0.35 * (1.0 - t / 0.35))
                } else {
                    fill.mix(colour::WHITE, 0.65 * ((t - 0.35) / 0.65).powi(2))
                };
                let r = rp * (1.0 - 0.88 * t) - 0.06 * rp;
                let off = 0.3 * rp * t;
                let cc = (
                    (c.0 as f64 - off).round() as i32,
                    (c.1 as f64 - off).round() as i32,
                );
                if r >= 0.5 {
                    area.draw(&Circle::new(cc, r.round() as i32, rgb(col).filled()))
                        .map_err(e)?;
                }
            }
        }
    }
    Ok(())
}

/// Renders a history chart; returns (width, height, RGB bytes).
pub fn chart_pixels(chart: &Chart) -> Result<(u32, u32, Vec<u8>), String> {
    font()?;
    // Taller with the panels of recorded groups: at least 250 pixels a panel.
    let (w, h) = (
        CHART_SIZE.0,
        CHART_SIZE.1.max(250 * chart.panels.len() as u32),
    );
    let mut buf = vec![255u8; (w as usize) * (h as usize) * 3];
    {
        let root = BitMapBackend::with_buffer(&mut buf, (w, h)).into_drawing_area();
        root.fill(&WHITE).map_err(err)?;
        let root = root
            .titled(&chart.title, (FAMILY, 24).into_font())
            .map_err(err)?;
        let areas = root.split_evenly((chart.panels.len().max(1), 1));
        let fmt_y = |v: &f64| {
            if *v == 0.0 {
                "0".to_string()
            } else if v.abs() >= 1e-2 && v.abs() < 1e5 {
                format!("{v:.3}")
                    .trim_end_matches('0')
                    .trim_end_matches('.')
                    .to_string()
            } else {
                format!("{v:.2e}")
            }
        };
        let fmt_x = |v: &f64| format!("{}", v.round());
        for (panel, area) in chart.panels.iter().zip(areas.iter()) {
            let pts = panel.series.iter().flat_map(|s| s.points.iter());
            let (mut x0, mut x1, mut y0, mut y1) =
                (f64::INFINITY, f64::NEG_INFINITY, 0.0f64, f64::NEG_INFINITY);
            for &(x, y) in pts {
                x0 = x0.min(x);
                x1 = x1.max(x);
                y0 = y0.min(y);
                y1 = y1.max(y);
            }
            if !(x0 <= x1) {
                (x0, x1) = (0.0, 1.0);
            }
            if x1 - x0 <= 0.0 {
                (x0, x1) = (x0 - 1.0, x1 + 1.0);
            }
            if !(y1 > y0) {
                y1 = y0 + 1.0;
            }
            let pad = 0.06 * (y1 - y0);
            let (y0, y1) = (if y0 < 0.0 { y0 - pad } else { y0 }, y1 + pad);
            let mut c = ChartBuilder::on(area)
                .caption(&panel.title, (FAMILY, 20).into_font())
                .margin(18)
                .x_label_area_size(50)
                .y_label_area_size(110)
                .build_cartesian_2d(x0..x1, y0..y1)
                .map_err(err)?;
            c.configure_mesh()
                .x_desc(chart.x_label.as_str())
                .y_desc(panel.y_label.as_str())
                .x_label_formatter(&fmt_x)
                .y_label_formatter(&fmt_y)
                .label_style((FAMILY, 15))
                .axis_desc_style((FAMILY, 17))
                .draw()
                .map_err(err)?;
            for s in &panel.series {
                let col = rgb(s.colour);
                c.draw_series(LineSeries::new(
                    s.points.iter().copied(),
                    ShapeStyle::from(&col).stroke_width(2),
                ))
                .map_err(err)?
                .label(s.name.as_str())
                .legend(move |(x, y)| {
                    PathElement::new(
                        vec![(x, y), (x + 24, y)],
                        ShapeStyle::from(&col).stroke_width(3),
                    )
                });
                if s.points.len() <= 200 {
                    c.draw_series(
                        s.points
                            .iter()
                            .map(|&(x, y)| Circle::new((x, y), 3, col.filled())),
                    )
                    .map_err(err)?;
                }
            }
            c.configure_series_labels()
                .position(SeriesLabelPosition::UpperLeft)
                .label_font((FAMILY, 16))
                .background_style(WHITE.mix(0.85))
                .border_style(BLACK)
                .draw()
                .map_err(err)?;
        }
        root.present().map_err(err)?;
    }
    Ok((w, h, buf))
}

/// Encodes RGB pixels as PNG.
pub fn encode_png(w: u32, h: u32, rgb: &[u8]) -> Result<Vec<u8>, String> {
    let mut out = Vec::new();
    {
        let mut enc = png::Encoder::new(&mut out, w, h);
        enc.set_color(png::ColorType::Rgb);
        enc.set_depth(png::BitDepth::Eight);
        enc.set_compression(png::Compression::Best);
        enc.set_adaptive_filter(png::AdaptiveFilterType::Adaptive);
        let mut wr = enc
            .write_header()
            .map_err(|e| format!("PNG encoding failed: {e}"))?;
        wr.write_image_data(rgb)
            .map_err(|e| format!("PNG encoding failed: {e}"))?;
    }
    Ok(out)
}
