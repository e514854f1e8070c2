//! The model choices of a scene: wall geometry and servo, size distributions, the contact
//! and liquid laws chosen with `SET`, the plot view. They belong to the simulation (the
//! command language maps its words onto them, `lang::command` re-exports them), and they
//! are serialised in checkpoints: the order of variants and fields is part of the
//! checkpoint format (`checkpoint::VERSION`), so a change here needs a new format version
//! and a reader of the old one.

use serde::{Deserialize, Serialize};

/// Radius distribution of a size type: every generated particle draws its radius.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub enum SizeDist {
    /// All particles have radius r.
    #[default]
    Fixed,
    /// Normal with standard deviation sd, truncated at ±3 sd (Lian ch. 7: 30 ± 3 µm).
    Normal { sd: f64 },
    /// Uniform in [rmin, rmax] (Olsson's size ranges).
    Uniform { min: f64, max: f64 },
    /// A discrete distribution given by a number-frequency table (Pasha 2013, Table 5.1):
    /// radius `radius[k]` is drawn with probability `freq[k] / Σ freq` (the frequencies as
    /// typed, in any unit: per cent, counts).
    Table { radius: Vec<f64>, freq: Vec<f64> },
}

/// Geometry of a wall: a plane `a x + b y + c z = d`, a spherical container (particles inside),
/// a spherical obstacle/indenter (particles outside) or a cylindrical die (particles inside).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub enum WallGeom {
    Plane {
        normal: [f64; 3],
        d: f64,
    },
    Sphere {
        centre: [f64; 3],
        radius: f64,
    },
    Obstacle {
        centre: [f64; 3],
        radius: f64,
    },
    /// An infinitely long circular cylinder, particles inside (a die): its axis passes
    /// through `point` along the unit vector `axis` (made unit by `DWAll`).
    Cylinder {
        point: [f64; 3],
        axis: [f64; 3],
        radius: f64,
    },
}

/// Servo control of a wall: target force, maximum speed and gain (`SE F vmax g`).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Servo {
    pub force: f64,
    pub vmax: f64,
    pub gain: f64,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub enum BridgeChoice {
    Fit,
    Toroidal,
    Laplace,
    /// Olsson (2017): Rabinovich force, Willett rupture, Nase viscous forces
    /// (`physics::bridge::rabinovich`); appended last (checkpoint format).
    Rabinovich,
}

/// The tangential law (`SET TANgential`); new variants go at the end (checkpoint format).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub enum TangentialChoice {
    /// Mindlin–Deresiewicz with Thornton's θ factors (Lian 1994), `physics::tangential`.
    Md,
    /// Mindlin no-slip spring with a Coulomb cap, `physics::tangential::noslip_spring`.
    NoSlip,
    /// Walton's incremental Mindlin–Deresiewicz (Shang 1998 (2.28)–(2.38)), `physics::walton`.
    Walton,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub enum LiquidMode {
    Lian,
    Conserve,
}

/// Projection of plots: looking along an axis.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub enum View {
    /// Side view: x to the right, z up (looking along +y).
    Xz,
    /// Side view: y to the right, z up.
    Yz,
    /// Top view: x to the right, y up.
    Xy,
}
