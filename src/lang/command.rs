//! The typed commands: one variant per command of the language, with its parameters.
//!
//! Numbers are already checked for type (real/integer) and sign where the sign is part of the
//! syntax; checks that need the scene (does the material exist, is there room) happen when the
//! session executes the command.

use serde::{Deserialize, Serialize};

/// The model choices are the simulation's (`sim::model`); the language names them.
pub use crate::sim::model::{
    BridgeChoice, LiquidMode, NormalLaw, Pairs, Servo, SizeDist, TangentialChoice, View, WallGeom,
};

/// Options of `DWAll`/`AWAll` after the geometry.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct WallOptions {
    pub geom: Option<WallGeom>,
    /// Translational velocity and, for spheres, radial velocity.
    pub vel: Option<([f64; 3], f64)>,
    pub material: Option<usize>,
    pub servo: Option<Servo>,
}

/// Ranges and groups are the simulation's (`sim::range`, doc/groups.md).
pub use crate::sim::range::Range;

#[derive(Clone, Debug, PartialEq)]
pub enum FixTarget {
    All,
    Particle(usize),
    /// The particles in a range (`Fix ... GROup name`, `Fix ... BOX ...`).
    Range(Range),
}

/// `GROup name ...`: what to do with the group.
#[derive(Clone, Debug, PartialEq)]
pub enum GroupAction {
    /// Define (or redefine) it: static (the ids in the range now) or dynamic.
    Define { range: Range, dynamic: bool },
    /// `FORget`: remove it.
    Forget,
    /// `HIStory [OFF]`: record its quantities with every history row, or no longer.
    Record(bool),
}

/// What `PROPerty` (and `VELocity vx vy vz range`) assigns to the particles of a range.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Property {
    Velocity([f64; 3]),
    Spin([f64; 3]),
    Material(usize),
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum StressServo {
    S0,
    S1ms2,
    S11,
    S22,
    S33,
    Ring,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub enum ContactsFilter {
    Loaded,
    All,
    Gap,
}

/// What `PRint` can print.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PrintItem {
    Balls,
    Chist,
    Contacts(ContactsFilter),
    Energy,
    Entries,
    Grid,
    Info,
    Map,
    Partitions,
    Stress,
    Settings,
    Walls,
    Bonds,
    Clusters,
    History,
    /// `GROup name` or `RANge ...`: the sums and averages over the next of the command's
    /// ranges (`Command::Print::ranges`, in order; `None` there: every group).
    Range,
}

/// What `PLot` can draw.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub enum PlotItem {
    Ball,
    Disks,
    Bou,
    Grid,
    Cluster,
    LCluster,
    Cnd,
    LCnd,
    Couple,
    Forces,
    LForces,
    MForces,
    RDisp,
    Rotation,
    Save,
    Velocity,
    Wall,
    History,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ProbeKind {
    E11,
    E22,
    E33,
    E12,
    E23,
    E31,
    E1m2,
    E2m3,
    E3m1,
}

/// `DAmping`: Rayleigh form (Lian) or restitution-calibrated viscoelastic dashpot.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum DampingSpec {
    Rayleigh {
        frac: f64,
        freq: f64,
        mass_off: bool,
        stiff_off: bool,
        ball_ball: bool,
    },
    /// `DAmping REStitution e [mtyp]`: all materials, or pairs involving `mtyp`.
    Restitution { e: f64, material: Option<usize> },
}

/// A `SET` statement.
#[derive(Clone, Debug, PartialEq)]
pub enum Setting {
    Tol(Option<f64>),
    Xres(Option<f64>),
    Smin(Option<f64>),
    Bridge(BridgeChoice),
    Tangential(TangentialChoice),
    Liquid(LiquidMode),
    /// Make the listed axes periodic (`periodic` true) or open.
    Boundary {
        axes: [bool; 3],
        periodic: bool,
    },
    OutDir(String),
    View(View),
    /// Take a last-good snapshot every n cycles during `Cycle` (0 = only at the start).
    Snapshot(u64),
    /// `SET HIStory n`: record the history every n cycles (0 = off).
    History(u64),
    /// `SET GENoverlap f`: overlap allowed between generated particles, as a fraction of
    /// R_i + R_j (default 1e-9, i.e. touching within round-off).
    GenOverlap(f64),
    /// `SET GOLdman ON|OFF`: tangential viscous force of the bridges (Goldman, Lian (4.76)).
    Goldman(bool),
    /// `SET WALlbridges ON|OFF`: liquid bridges between particles and walls (on by default).
    WallBridges(bool),
    /// `SET FRAgment eps`: neighbour radius of Olsson's DBSCAN fragments (DEFault: 4 R_mean).
    Fragment(Option<f64>),
    /// `SET TUNnel STOP|DELETE`: what a particle whose centre crossed a wall does.
    Tunnel(crate::sim::scene::TunnelAction),
    /// `SET NORmal law [parameters] [m1 [m2]]`: the normal contact law of the material pairs
    /// (doc/contact_laws.md).
    Normal {
        pairs: Pairs,
        law: NormalLaw,
    },
    /// `SET ROLling mu_r [m1 [m2]]`: the rolling friction coefficient of the material pairs.
    Rolling {
        pairs: Pairs,
        mu_r: f64,
    },
    /// `SET DASHpot TRUBAL|LIGGGHTS|EDEM|LIMITFORCE [m1 [m2]]`: the restitution dashpot's form
    /// of the material pairs (doc/contact_laws.md).
    Dashpot {
        pairs: Pairs,
        form: crate::sim::model::DashpotForm,
    },
    /// `SET PAIr m1 m2 [FRIction mu] [RESTitution e] | DEFault`: one material pair's own
    /// friction and restitution (both `None`: back to the smaller of the two materials').
    Pair {
        m1: u16,
        m2: u16,
        values: crate::sim::model::PairValues,
    },
}

/// One command of the language.
#[derive(Clone, Debug, PartialEq)]
pub enum Command {
    Agglomerate {
        nagg: usize,
        centre: [f64; 3],
        radius: f64,
    },
    Agenerate {
        size: usize,
        material: usize,
        nagg: usize,
        origin: [f64; 3],
        step: [f64; 3],
    },
    Awall {
        n: usize,
        opts: WallOptions,
    },
    Cgravity {
        nagg: usize,
        g: f64,
    },
    Cohesion {
        gamma: f64,
        material: usize,
        /// Base surface energy for contacts made after an impact (`VELocity ... 1`).
        base: Option<f64>,
    },
    Create {
        pos: [f64; 3],
        vel: [f64; 3],
        spin: [f64; 3],
        size: usize,
        material: usize,
    },
    Cycle {
        n: u64,
        servo: Vec<(StressServo, f64)>,
    },
    Damping(DampingSpec),
    Density {
        rho: f64,
        material: usize,
    },
    Dwall(WallOptions),
    Fix {
        flags: [bool; 6],
        target: FixTarget,
    },
    Fmm {
        r: f64,
    },
    Fro,
    /// `FRAction f`, or `FRAction AUTO` (`None`: the step follows the fastest contact).
    Fraction {
        f: Option<f64>,
    },
    Friction {
        mu: f64,
        material: usize,
    },
    Gain {
        g: f64,
        edmax: f64,
    },
    Gravity {
        g: [f64; 3],
    },
    Grid {
        rates: [f64; 6],
    },
    Help {
        topic: Option<String>,
        item: Option<String>,
    },
    Iset,
    Liquid {
        pvol: f64,
        gsurf: f64,
        theta_deg: f64,
        eta: f64,
    },
    Log {
        on: bool,
        file: Option<String>,
    },
    Mode {
        n: i64,
    },
    New,
    Plot {
        items: Vec<PlotItem>,
        /// `PLot ... range` (e.g. `GROup name`): its particles drawn in the highlight colour.
        mark: Option<Range>,
    },
    Pra {
        nu: f64,
        material: usize,
    },
    Print {
        items: Vec<PrintItem>,
        /// The ranges of the `PrintItem::Range` items, in order (`None`: `GROup ALL`).
        ranges: Vec<Option<Range>>,
    },
    /// `GROup name [DYNamic] range | FORget`.
    Group {
        name: String,
        action: GroupAction,
    },
    /// `PROperty ... range` (and `VELocity vx vy vz range`).
    Property {
        what: Property,
        range: Range,
    },
    /// `DELete range`: remove the particles in a range.
    DeleteRange {
        range: Range,
    },
    Probe {
        kind: ProbeKind,
    },
    Radius {
        r: f64,
        size: usize,
        dist: SizeDist,
    },
    /// `DELete x1 x2 y1 y2 z1 z2`: remove the particles whose centres lie in the box.
    Delete {
        bounds: [f64; 6],
    },
    /// `MOVe nagg dx dy dz`: translate agglomerate nagg (particles and region).
    Move {
        nagg: usize,
        d: [f64; 3],
    },
    /// `RELax kmax fmax nmax`: cycle until the kinetic energy is below kmax (J) and the largest
    /// contact force below fmax (N), checking every 100 cycles, at most nmax cycles.
    Relax {
        kmax: f64,
        fmax: f64,
        nmax: u64,
    },
    Reset,
    Restart {
        file: Option<String>,
    },
    Rgenerate {
        n: usize,
        size: usize,
        material: usize,
        nagg: usize,
        /// `WAlls`: only on the particles' side of every wall.
        walls: bool,
    },
    RgenerateSeed {
        n: u64,
    },
    Rset,
    Save {
        file: Option<String>,
    },
    Set(Setting),
    Start {
        size: [f64; 3],
        nbox: usize,
        nball: usize,
        nwall: usize,
        log: bool,
    },
    Stop,
    Velocity {
        v1: [f64; 3],
        v2: Option<[f64; 3]>,
        ivd: bool,
    },
    Vmu {
        r: f64,
    },
    Window {
        bounds: [f64; 6],
    },
    Ymd {
        e: f64,
        material: usize,
    },
    Zero {
        always: bool,
    },
    TwoD,
    /// `VTk`: a VTK frame now (`every: None`), or now and every k cycles (`Some(k)`), or the
    /// schedule stopped (`off`); `prefix` names the series.
    /// `FIEld`: coarse-grained fields on n1 x n2 x n3 nodes with a kernel of width `width`.
    Field {
        nodes: [usize; 3],
        width: f64,
        lucy: bool,
        prefix: Option<String>,
        /// `CSV`: also a CSV file.
        csv: bool,
        /// `AVerage k m`: the average of m samples, k cycles apart.
        average: Option<(u64, u64)>,
        /// `BIN`: the box kernel (the cell around each node; `width` unused).
        bin: bool,
        /// `IN x1 x2 y1 y2 z1 z2`: the grid over this box instead of the work-space.
        region: Option<[f64; 6]>,
    },
    Vtk {
        every: Option<u64>,
        off: bool,
        prefix: Option<String>,
        layout: VtkLayout,
    },
    /// The words of the programmable language (`LET`, `IF`, `LOOP`, `DEFine`, ...;
    /// doc/language.md).
    Script(super::script::ScriptCmd),
}

/// What the files of a VTK frame hold and how they are stored (`VTk`'s `RAW`, `SINgle`,
/// `ARRays`, `CONtacts`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct VtkLayout {
    /// `RAW`: uncompressed files.
    pub raw: bool,
    /// `SINgle`: the points in single precision (the arrays are single precision anyway).
    pub single: bool,
    /// `ARRays …`: the particle arrays written, a bit per entry of [`PARTICLE_ARRAYS`]
    /// (all when not given).
    pub arrays: Option<u16>,
    /// `CONtacts …`: the contact arrays written, a bit per entry of [`CONTACT_ARRAYS`]
    /// (all when not given).
    pub contacts: Option<u16>,
}

/// The contact arrays of a VTK frame (`VTk CONtacts`), in the order the file holds them;
/// the lines (and their end points) are always written.
pub const CONTACT_ARRAYS: [&str; 12] = [
    "a",
    "b",
    "wall",
    "force",
    "normal_force_vector",
    "tangential_force_vector",
    "normal_force",
    "tangential_force",
    "overlap",
    "contact_radius",
    "bridge_volume",
    "bridge",
];

/// The particle arrays of a VTK frame (`VTk ARRays`), in the order the file holds them;
/// the points (the centres) are always written.
pub const PARTICLE_ARRAYS: [&str; 12] = [
    "id",
    "radius",
    "velocity",
    "spin",
    "force",
    "moment",
    "material",
    "size_type",
    "agglomerate",
    "coordination",
    "cluster",
    "displacement",
];
