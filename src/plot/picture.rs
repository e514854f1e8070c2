//! A picture as plain data: what to draw, in view coordinates (metres; `u` to the right, `v`
//! up), before any pixel exists. [`super::build`] makes one from a scene, [`super::render`]
//! turns it into a PNG. Tests look at this, not at pixels.

use serde::Serialize;

/// An sRGB colour.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
pub struct Rgb(pub u8, pub u8, pub u8);

impl Rgb {
    /// Mixes toward `other` by `t` (0 = self, 1 = other).
    pub fn mix(self, other: Rgb, t: f64) -> Rgb {
        let t = t.clamp(0.0, 1.0);
        let f = |a: u8, b: u8| (a as f64 + (b as f64 - a as f64) * t).round() as u8;
        Rgb(f(self.0, other.0), f(self.1, other.1), f(self.2, other.2))
    }
}

/// The colours of the pictures (thesis conventions where the thesis has one).
pub mod colour {
    use super::Rgb;
    pub const BLACK: Rgb = Rgb(0, 0, 0);
    pub const WHITE: Rgb = Rgb(255, 255, 255);
    pub const GREY: Rgb = Rgb(128, 128, 128);
    pub const LIGHT_GREY: Rgb = Rgb(200, 200, 200);
    /// Force networks (Lian 1994 Fig. 6.1b, 7.1b): compressive green, tensile blue.
    pub const COMPRESSIVE: Rgb = Rgb(0, 160, 0);
    pub const TENSILE: Rgb = Rgb(0, 0, 230);
    /// Contact connection diagrams (Fig. 7.8, 7.9): broken red, new blue, existing cyan.
    pub const BROKEN: Rgb = Rgb(220, 0, 0);
    pub const NEW: Rgb = Rgb(0, 0, 230);
    pub const KEPT: Rgb = Rgb(0, 190, 210);
    /// The particles of `PLot ... GROup name`.
    pub const HIGHLIGHT: Rgb = Rgb(255, 105, 0);
    /// Vector plots: the line, and the red dot at its forward end (Fig. 6.1c).
    pub const VECTOR: Rgb = Rgb(40, 40, 40);
    pub const TIP: Rgb = Rgb(220, 0, 0);
    /// Rotation / couple arcs: anticlockwise and clockwise as seen in the picture.
    pub const ANTICLOCKWISE: Rgb = Rgb(200, 0, 0);
    pub const CLOCKWISE: Rgb = Rgb(0, 0, 200);
    /// Clusters by size (Lian 1994 §6.2.1): 1 green, 2–10 cyan, 11–50 black, 51–200 blue,
    /// 201–600 yellow, > 600 red.
    pub const CLUSTER: [Rgb; 6] = [
        Rgb(0, 170, 0),
        Rgb(0, 200, 220),
        Rgb(0, 0, 0),
        Rgb(0, 0, 230),
        Rgb(235, 210, 0),
        Rgb(220, 0, 0),
    ];
    /// Particles without cluster colouring, by material type 1, 2, ...
    pub const MATERIAL: [Rgb; 5] = [
        Rgb(205, 175, 120),
        Rgb(130, 160, 210),
        Rgb(190, 120, 160),
        Rgb(140, 190, 120),
        Rgb(170, 170, 170),
    ];
}

/// Size classes of clusters, with their colour and label.
pub const CLUSTER_CLASSES: [(usize, usize, &str); 6] = [
    (1, 1, "1 (singlets)"),
    (2, 10, "2-10"),
    (11, 50, "11-50"),
    (51, 200, "51-200"),
    (201, 600, "201-600"),
    (601, usize::MAX, "> 600"),
];

/// Index into [`CLUSTER_CLASSES`] / [`colour::CLUSTER`] of a cluster of `n` particles.
pub fn cluster_class(n: usize) -> usize {
    CLUSTER_CLASSES
        .iter()
        .position(|&(lo, hi, _)| lo <= n && n <= hi)
        .unwrap_or(0)
}

/// How a disc is shaded.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
pub enum Shade {
    /// Sphere-like: dark rim, highlight up and to the left (`BALl`).
    Sphere,
    /// Flat fill with an outline (`DISks`).
    Flat,
}

/// A particle seen from the viewer.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Disc {
    pub id: u32,
    pub centre: [f64; 2],
    pub radius: f64,
    /// Distance from the viewer along the view direction (larger = farther).
    pub depth: f64,
    pub fill: Rgb,
    pub shade: Shade,
}

/// What a line belongs to (for the legend, the drawing order and the tests).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
pub enum Layer {
    /// Work-space outline (`BOU`, `GRId`).
    Boundary,
    /// Walls (`WALL`).
    Wall,
    /// Contact forces: total (`FORces`), solid (`MFOrces`) or liquid bridge (`LFOrces`).
    Force(ForceSet),
    /// Contact connection diagram: solid contacts (`CND`) or liquid bridges (`LCNd`).
    Cnd(BondSet),
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
pub enum ForceSet {
    Total,
    Solid,
    Bridge,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
pub enum BondSet {
    Contacts,
    Bridges,
}

/// The meaning of a line.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
pub enum Mark {
    Plain,
    /// Dashed (periodic sides of the work-space).
    Dashed,
    /// Short marks on the far side of a plane wall.
    Hatch,
    Compressive,
    Tensile,
    Kept,
    New,
    Broken,
}

/// Which pair a line belongs to.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
pub enum Tag {
    None,
    /// Particle–particle pair by stable ids (a < b).
    Pair(u32, u32),
    /// Particle id and wall index (0-based).
    WallContact(u32, usize),
    /// Wall index (0-based).
    Wall(usize),
}

/// A straight line; `width` in metres (the renderer draws at least one pixel).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Segment {
    pub a: [f64; 2],
    pub b: [f64; 2],
    pub width: f64,
    pub colour: Rgb,
    pub layer: Layer,
    pub mark: Mark,
    pub tag: Tag,
    /// The quantity drawn (force in N for force lines, 0 otherwise).
    pub value: f64,
}

/// What a vector shows.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
pub enum VectorKind {
    Velocity,
    Displacement,
}

/// A vector from a particle centre, ending in a dot (thesis style).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Arrow {
    pub id: u32,
    pub from: [f64; 2],
    pub to: [f64; 2],
    pub kind: VectorKind,
    /// The in-plane magnitude drawn (m/s or m).
    pub value: f64,
}

/// What an arc shows.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
pub enum ArcKind {
    Rotation,
    Couple,
}

/// A circular arc around a particle, with an arrow head at its end: the sense (sign of
/// `sweep`, anticlockwise positive as seen) and size (|sweep| ∝ value) of a rotation or a
/// moment about the viewing axis.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Arc {
    pub id: u32,
    pub centre: [f64; 2],
    pub radius: f64,
    /// Start angle (rad, from the +u axis, anticlockwise).
    pub start: f64,
    /// Signed sweep (rad).
    pub sweep: f64,
    pub colour: Rgb,
    pub kind: ArcKind,
    /// Depth of the particle (drawn with it, so that nearer discs hide it).
    pub depth: f64,
    /// The signed quantity about the viewing axis (rad or N m).
    pub value: f64,
}

/// A circle (spherical walls); `fill` is drawn translucent.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Ring {
    pub centre: [f64; 2],
    pub radius: f64,
    pub colour: Rgb,
    pub fill: Option<Rgb>,
    pub tag: Tag,
}

/// The sample drawn beside a legend text.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub enum Swatch {
    Disc(Rgb),
    Line(Rgb),
    Vector,
    Arc(Rgb),
    None,
}

#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct LegendEntry {
    pub swatch: Swatch,
    pub text: String,
}

/// A horizontal bar of a round length.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ScaleBar {
    pub length: f64,
    pub label: String,
}

/// The visible region in view coordinates.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Bounds {
    pub umin: f64,
    pub umax: f64,
    pub vmin: f64,
    pub vmax: f64,
}

impl Bounds {
    pub fn empty() -> Self {
        Bounds {
            umin: f64::INFINITY,
            umax: f64::NEG_INFINITY,
            vmin: f64::INFINITY,
            vmax: f64::NEG_INFINITY,
        }
    }
    pub fn is_empty(&self) -> bool {
        !(self.umin <= self.umax && self.vmin <= self.vmax)
    }
    pub fn add(&mut self, p: [f64; 2], r: f64) {
        if p.iter().all(|x| x.is_finite()) && r.is_finite() {
            self.umin = self.umin.min(p[0] - r);
            self.umax = self.umax.max(p[0] + r);
            self.vmin = self.vmin.min(p[1] - r);
            self.vmax = self.vmax.max(p[1] + r);
        }
    }
    pub fn width(&self) -> f64 {
        self.umax - self.umin
    }
    pub fn height(&self) -> f64 {
        self.vmax - self.vmin
    }
    pub fn contains(&self, p: [f64; 2]) -> bool {
        self.umin <= p[0] && p[0] <= self.umax && self.vmin <= p[1] && p[1] <= self.vmax
    }
}

/// A scene picture.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Picture {
    pub title: String,
    /// Names of the horizontal and vertical axes ("x", "z", ...).
    pub axes: [&'static str; 2],
    pub bounds: Bounds,
    /// Far first.
    pub discs: Vec<Disc>,
    pub rings: Vec<Ring>,
    /// In drawing order.
    pub segments: Vec<Segment>,
    pub arcs: Vec<Arc>,
    pub arrows: Vec<Arrow>,
    pub legend: Vec<LegendEntry>,
    /// Messages shown under the legend ("no particles", scales, ...).
    pub notes: Vec<String>,
    pub scale_bar: Option<ScaleBar>,
}

/// One curve of a chart.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Series {
    pub name: String,
    pub colour: Rgb,
    pub points: Vec<(f64, f64)>,
}

/// One panel (shared x axis: cycle).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Panel {
    pub title: String,
    pub y_label: String,
    pub series: Vec<Series>,
}

/// A chart of time series (`PLot HIStory`).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Chart {
    pub title: String,
    pub x_label: String,
    pub panels: Vec<Panel>,
}
