//! The simulation state: work-space, material and size tables, particles (structure of
//! arrays), walls, contacts, settings and the energy ledger. Plain data; no I/O.

use nalgebra::Vector3;
use serde::{Deserialize, Serialize};

use super::contacts::ContactStore;
use super::rng::Rng;
use crate::sim::model::{BridgeChoice, LiquidMode, Servo, TangentialChoice, View, WallGeom};

mod access;
mod carried;
pub(in crate::sim) mod cell;
mod check;
mod edit;
mod groups;
mod ledger;
mod old;
mod overlap;
mod reference;
pub use carried::{Carried, KeptServo};
pub use ledger::Ledger;
pub use overlap::{CreateIndex, OverlapIndex};
pub use reference::Reference;
pub mod touch;

pub type Vec3 = Vector3<f64>;

/// Number of size types and material types (TRUBAL had 10 and 5; the tables grow on demand up
/// to these limits, which only bound typos).
pub const MAX_SIZES: usize = 64;
pub const MAX_MATERIALS: usize = 64;

/// One material type. Unset values are 0 and are refused when they are needed.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Material {
    pub density: f64,
    pub young: f64,
    pub poisson: f64,
    pub friction: f64,
    /// Surface energy per surface γ (J/m²): `COHesion`.
    pub gamma: f64,
    /// Surface energy of contacts made after an impact (`VELocity ... 1`).
    pub gamma_base: f64,
    /// Restitution coefficient for the viscoelastic dashpot, if `DAmping REStitution` set it.
    pub restitution: Option<f64>,
}

impl Material {
    pub fn shear(&self) -> f64 {
        self.young / (2.0 * (1.0 + self.poisson))
    }
}

/// An agglomerate region (`AGGlomerate`).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Region {
    pub centre: [f64; 3],
    pub radius: f64,
}

/// Particles as a structure of arrays; index order may change (open boundaries, sorting),
/// `id` is the stable identity (1-based creation number).
#[derive(Clone, Debug, Default, Serialize, Deserialize)]
pub struct Particles {
    pub id: Vec<u32>,
    pub pos: Vec<Vec3>,
    pub vel: Vec<Vec3>,
    pub spin: Vec<Vec3>,
    /// Accumulated rotation (RESet zeroes it).
    pub rot: Vec<Vec3>,
    /// Out-of-balance force and moment of the last step.
    pub force: Vec<Vec3>,
    pub moment: Vec<Vec3>,
    pub radius: Vec<f64>,
    pub mass: Vec<f64>,
    pub size: Vec<u16>,
    pub material: Vec<u16>,
    /// Agglomerate number (0 = none).
    pub agg: Vec<u8>,
    /// Fixed degrees of freedom: bit k for component k (x y z rx ry rz).
    pub fixed: Vec<u8>,
    /// Displacement since the last mapping into the search grid.
    pub disp: Vec<Vec3>,
    /// Free liquid carried by the particle (liquid-conserving mode), m³.
    pub liquid: Vec<f64>,
}

impl Particles {
    /// Frees the arrays' spare capacity (a decoded checkpoint's arrays grew by doubling:
    /// up to twice the room their particles need).
    pub fn shrink_to_fit(&mut self) {
        let Particles {
            id,
            pos,
            vel,
            spin,
            rot,
            force,
            moment,
            radius,
            mass,
            size,
            material,
            agg,
            fixed,
            disp,
            liquid,
        } = self;
        id.shrink_to_fit();
        for v in [pos, vel, spin, rot, force, moment, disp] {
            v.shrink_to_fit();
        }
        for v in [radius, mass, liquid] {
            v.shrink_to_fit();
        }
        for v in [size, material] {
            v.shrink_to_fit();
        }
        agg.shrink_to_fit();
        fixed.shrink_to_fit();
    }
    pub fn len(&self) -> usize {
        self.id.len()
    }
    pub fn is_empty(&self) -> bool {
        self.id.is_empty()
    }

    #[allow(clippy::too_many_arguments)]
    pub fn push(
        &mut self,
        id: u32,
        pos: Vec3,
        vel: Vec3,
        spin: Vec3,
        radius: f64,
        mass: f64,
        size: usize,
        material: usize,
        agg: usize,
    ) {
        self.id.push(id);
        self.pos.push(pos);
        self.vel.push(vel);
        self.spin.push(spin);
        self.rot.push(Vec3::zeros());
        self.force.push(Vec3::zeros());
        self.moment.push(Vec3::zeros());
        self.radius.push(radius);
        self.mass.push(mass);
        self.size.push(size as u16);
        self.material.push(material as u16);
        self.agg.push(agg as u8);
        self.fixed.push(0);
        self.disp.push(Vec3::zeros());
        self.liquid.push(0.0);
    }

    /// Removes particle `i` (order of the rest is kept).
    pub fn remove(&mut self, i: usize) {
        self.id.remove(i);
        self.pos.remove(i);
        self.vel.remove(i);
        self.spin.remove(i);
        self.rot.remove(i);
        self.force.remove(i);
        self.moment.remove(i);
        self.radius.remove(i);
        self.mass.remove(i);
        self.size.remove(i);
        self.material.remove(i);
        self.agg.remove(i);
        self.fixed.remove(i);
        self.disp.remove(i);
        self.liquid.remove(i);
    }

    /// Reorders particles `start..` so that the k-th of them is the old `start + order[k]`
    /// (`order` a permutation of `0..len - start`).
    pub fn permute_tail(&mut self, start: usize, order: &[usize]) {
        fn tail<T: Copy>(v: &mut [T], start: usize, order: &[usize]) {
            let old: Vec<T> = v[start..].to_vec();
            for (k, &o) in order.iter().enumerate() {
                v[start + k] = old[o];
            }
        }
        tail(&mut self.id, start, order);
        tail(&mut self.pos, start, order);
        tail(&mut self.vel, start, order);
        tail(&mut self.spin, start, order);
        tail(&mut self.rot, start, order);
        tail(&mut self.force, start, order);
        tail(&mut self.moment, start, order);
        tail(&mut self.radius, start, order);
        tail(&mut self.mass, start, order);
        tail(&mut self.size, start, order);
        tail(&mut self.material, start, order);
        tail(&mut self.agg, start, order);
        tail(&mut self.fixed, start, order);
        tail(&mut self.disp, start, order);
        tail(&mut self.liquid, start, order);
    }

    pub fn inertia(&self, i: usize) -> f64 {
        0.4 * self.mass[i] * self.radius[i] * self.radius[i]
    }

    /// The kinetic energies of translation and rotation, Σ ½ m v² and Σ ½ I ω² (J, with the
    /// half-step velocities of the leap-frog scheme), each summed in particle order.
    pub fn kinetic_parts(&self) -> (f64, f64) {
        let (mut translation, mut rotation) = (0.0, 0.0);
        for i in 0..self.len() {
            translation += 0.5 * self.mass[i] * self.vel[i].norm_squared();
            rotation += 0.5 * self.inertia(i) * self.spin[i].norm_squared();
        }
        (translation, rotation)
    }
}

/// A rigid, massive wall with prescribed (or servo-controlled) motion.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Wall {
    pub geom: WallGeom,
    pub vel: [f64; 3],
    /// Radial velocity of a spherical wall.
    pub vr: f64,
    pub material: usize,
    pub servo: Option<Servo>,
    /// Force exerted by the particles on the wall in the last step (global frame).
    pub force: [f64; 3],
    /// Normal (plane) or radial (sphere) component of that force.
    pub normal_force: f64,
    /// Accumulated displacement.
    pub disp: [f64; 3],
    /// How far the wall's surface moved since the last rebuild of the candidate list (a
    /// plane along its normal; a sphere by its centre and radius): the rebuild trigger
    /// counts it like a particle's displacement.
    pub travel: f64,
}

/// Rayleigh damping parameters for one contact set (Lian §5.8; doc/spec/DECISIONS.md).
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Rayleigh {
    /// Mass-proportional coefficient α_R = frac·2π·freq (1/s).
    pub alpha: f64,
    /// Stiffness-proportional coefficient β_R = frac/(2π·freq) (s).
    pub beta: f64,
}

/// Settings changed by `SET` and friends.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Settings {
    /// User TOL (None = automatic).
    pub tol: Option<f64>,
    pub xres: Option<f64>,
    pub smin: Option<f64>,
    pub bridge: BridgeChoice,
    pub tangential: TangentialChoice,
    pub liquid_mode: LiquidMode,
    pub periodic: [bool; 3],
    pub out_dir: String,
    pub view: View,
    pub snapshot_every: u64,
    pub history_every: u64,
    pub two_d: bool,
    /// FRAction given by the user (None: the default for the scene, see [`default_fraction`]).
    pub fraction: Option<f64>,
    pub window: Option<[f64; 6]>,
    /// Overlap allowed between generated particles (fraction of R_i + R_j).
    pub gen_overlap: f64,
    /// Neighbour radius of Olsson's DBSCAN fragments (None: 4 × mean radius).
    pub fragment_eps: Option<f64>,
    /// Tangential viscous force of liquid bridges (Goldman), off by default.
    pub goldman: bool,
    /// What a particle whose centre crossed a wall's surface does to the run (`SET TUNnel`).
    pub tunnel: TunnelAction,
    /// `FRAction AUTO`: the step follows the scene's fastest approach
    /// (`sim::contact_time::auto_step`): `Some(the step in use since the last rebuild)`, 0
    /// before the first; `None`: the FRAction step.
    pub auto_step: Option<f64>,
    /// Liquid bridges between particles and walls (`SET WALlbridges ON|OFF`, on by default):
    /// off, a wall contact is the dry contact of its law, as Lian 1994's smooth elastic wall
    /// (§6.1) with bridges only between particles.
    pub wall_bridges: bool,
}

/// `SET TUNnel STOP|DELETE`: a particle whose centre crossed a wall's surface (by a fast
/// approach, a moving wall, a wrap) stops the run with the last good state kept (`Stop`, the
/// default), or is deleted and its energy booked as leaving with it (`Delete`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub enum TunnelAction {
    Stop,
    Delete,
}

impl Default for Settings {
    fn default() -> Self {
        Settings {
            tol: None,
            xres: None,
            smin: None,
            bridge: BridgeChoice::Fit,
            tangential: TangentialChoice::Mdr,
            liquid_mode: LiquidMode::Lian,
            periodic: [true; 3],
            out_dir: ".".into(),
            view: View::Xz,
            snapshot_every: 1000,
            history_every: 0,
            two_d: false,
            fraction: None,
            window: None,
            gen_overlap: 1e-9,
            fragment_eps: None,
            goldman: false,
            tunnel: TunnelAction::Stop,
            auto_step: None,
            wall_bridges: true,
        }
    }
}

/// Default FRAction (see doc/performance.md for the speed/accuracy study behind it).
pub const DEFAULT_FRACTION: f64 = 0.2;
/// Default FRAction of a scene with adhesion: the JKR snap-in and detachment are force jumps
/// that the explicit scheme resolves to O(Δt); 0.1 keeps the sticking threshold within ~1 %.
pub const DEFAULT_FRACTION_ADHESIVE: f64 = 0.1;
/// Default FRAction of a scene that dissipates nothing (`params::dissipation_free`: Hertz
/// pairs without dashpot, friction, adhesion, liquid or damping): at 0.2 an elastic gas loses
/// 1.2e-3 of its energy in 10⁷ steps, at 0.1 7e-4 (doc/limits.md, "Energy drift of an
/// elastic gas"; issue 49 item 4).
pub const DEFAULT_FRACTION_ELASTIC: f64 = 0.1;

/// The FRAction a scene uses when the user gave none (doc/performance.md, time-step study).
pub fn default_fraction(adhesive: bool) -> f64 {
    if adhesive {
        DEFAULT_FRACTION_ADHESIVE
    } else {
        DEFAULT_FRACTION
    }
}

/// Liquid parameters of `LIQuid` (None when no liquid).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Liquid {
    pub pvol: f64,
    pub gamma: f64,
    pub theta: f64,
    pub eta: f64,
}

/// The whole state of a problem.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Scene {
    pub(in crate::sim) size: [f64; 3],
    pub(in crate::sim) nbox: usize,
    pub(in crate::sim) nball: usize,
    pub(in crate::sim) nwall: usize,
    pub(in crate::sim) sizes: Vec<f64>,
    /// Radius distribution of each size type.
    pub(in crate::sim) size_dist: Vec<crate::sim::model::SizeDist>,
    pub(in crate::sim) materials: Vec<Material>,
    pub(in crate::sim) regions: [Option<Region>; 2],
    pub(in crate::sim) particles: Particles,
    pub(in crate::sim) next_id: u32,
    #[serde(deserialize_with = "old::old_walls")]
    pub(in crate::sim) walls: Vec<Wall>,
    pub(in crate::sim) contacts: ContactStore,
    #[serde(deserialize_with = "old::old_settings")]
    pub(in crate::sim) settings: Settings,
    pub(in crate::sim) gravity: [f64; 3],
    /// Centripetal gravity per agglomerate (m/s², 0 = off).
    pub(in crate::sim) cgravity: [f64; 2],
    pub(in crate::sim) fmm: f64,
    pub(in crate::sim) zero_always: bool,
    pub(in crate::sim) damping_pp: Rayleigh,
    pub(in crate::sim) damping_pw: Rayleigh,
    pub(in crate::sim) liquid: Option<Liquid>,
    /// Surface energy used for contacts made after an impact (`VELocity ... 1`), per material.
    pub(in crate::sim) impact: bool,
    pub(in crate::sim) rng: Rng,
    pub(in crate::sim) cycle: u64,
    pub(in crate::sim) time: f64,
    #[serde(deserialize_with = "old::old_ledger")]
    pub(in crate::sim) ledger: Ledger,
    /// Particles removed through open sides.
    pub(in crate::sim) lost: u64,
    /// Reference state (`PLot SAve`).
    pub(in crate::sim) reference: Option<Reference>,
    pub(in crate::sim) history: super::history::History,
    /// The periodic cell's deformation (`GRID`, stress servo), [`super::cell`]; checkpoints
    /// before format 4 have none (read as at rest).
    #[serde(deserialize_with = "old::old_cell")]
    pub(in crate::sim) cell: cell::Cell,
    /// The contact laws per material pair (`SET NORmal`, `SET ROLling`); checkpoints before
    /// format 5 have none (Hertz/JKR everywhere, no rolling friction).
    #[serde(deserialize_with = "old::old_laws")]
    pub(in crate::sim) laws: crate::sim::model::ContactLaws,
    /// The named groups (`GROup`, `sim::range`); checkpoints before format 10 have none.
    #[serde(deserialize_with = "old::old_groups")]
    pub(in crate::sim) groups: crate::sim::range::Groups,
    /// What the last `Cycle` handed on to the next (the audit's reference, the work in
    /// flight, the walls' last velocities, the stress servo: [`Carried`]); checkpoints
    /// before format 14 have none (read as [`Carried::unknown`]).
    #[serde(deserialize_with = "old::old_carried")]
    pub(in crate::sim) carried: Carried,
    /// What a `Cycle` and the commands derive and keep between steps or commands, never
    /// saved (see [`Derived`]).
    #[serde(skip)]
    pub(in crate::sim) derived: Derived,
}

/// The scene's derived state: kept between steps or between commands for speed or for the
/// session, rebuilt when missing, never saved (a RESTart starts from the default), so that a
/// checkpoint holds only what the physics needs.
#[derive(Clone, Debug)]
pub struct Derived {
    /// The stress servo of the running Cycle (`Cycle n S0 σ`, set by the session for the
    /// Cycle; derived, not saved).
    pub servo: Option<cell::Servo>,
    /// Some particle may be outside the work-space (derived, not saved: set at the start of
    /// every `Cycle` and by the integration step; saves a scan per step when false).
    pub maybe_outside: bool,
    /// What a `Cycle` has to tell that is not an error (a particle deleted after crossing a
    /// wall, a step too long for the fastest approach): the session prints these as warnings
    /// and empties the list (derived, not saved).
    pub notes: Vec<String>,
    /// Per group of `cycle::EXT_GROUP` consecutive particles, how far beyond touching their
    /// pairs are evaluated in the current step: Δt × their largest velocity component, so
    /// that a pair approaching within half a step's travel gets its share of the restitution
    /// dashpot (`physics::dashpot`); empty without a dashpot (derived, not saved: set by
    /// `cycle::one_step`).
    pub reach_ext: Vec<f64>,
    /// The velocities' largest values as the last step's update left them
    /// ([`Speeds`]; derived, not saved).
    pub speeds: Speeds,
    /// The particles the last command placed, if it was an AGEnerate (derived, not saved;
    /// any other command forgets them, SAve included, so a RESTart sees the same): the next
    /// AGEnerate into the same agglomerate orders them with its own (a BCC lattice is two
    /// AGEnerate commands; see `sim::place::layer_order`).
    pub lattice_run: Option<LatticeRun>,
    /// The overlap index kept between consecutive `CReate` commands (derived, not saved;
    /// dropped by any other command before it runs: `Session::execute`).
    pub create_index: Option<CreateIndex>,
}

impl Default for Derived {
    fn default() -> Self {
        Derived {
            servo: None,
            maybe_outside: true,
            notes: Vec::new(),
            reach_ext: Vec::new(),
            speeds: Default::default(),
            lattice_run: None,
            create_index: None,
        }
    }
}

/// The velocities' largest values as the last step's update left them (`cycle::move_all`, the
/// fused step: each chunk while it is in the cache), so that neither the next step's margins
/// (`cycle::set_margins`) nor the check after the step (`after_step`) passes over the velocities
/// again: per group of `cycle::EXT_GROUP` particles the largest velocity component, and the
/// largest `|v|²`. `fresh` from the end of a step whose update left finite velocities that
/// nothing changed since (not with `zero_always`, the deforming cell or its servo) until the
/// next update, a deletion or the end of the `Cycle` (derived, not saved).
#[derive(Clone, Debug, Default)]
pub struct Speeds {
    pub groups: Vec<f64>,
    pub speed2: f64,
    pub fresh: bool,
}

/// A run of particles placed by AGEnerate: `start..` of the particle list, agglomerate
/// `nagg`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LatticeRun {
    pub start: usize,
    pub nagg: usize,
}

impl Scene {
    pub fn new(size: [f64; 3], nbox: usize, nball: usize, nwall: usize) -> Self {
        Scene {
            size,
            nbox,
            nball,
            nwall,
            sizes: vec![0.0; 10],
            size_dist: vec![Default::default(); 10],
            materials: vec![Material::default(); 5],
            regions: [None, None],
            particles: Particles::default(),
            next_id: 1,
            walls: Vec::new(),
            contacts: ContactStore::default(),
            settings: Settings::default(),
            gravity: [0.0; 3],
            cgravity: [0.0; 2],
            fmm: 1.0,
            zero_always: false,
            damping_pp: Rayleigh::default(),
            damping_pw: Rayleigh::default(),
            liquid: None,
            impact: false,
            rng: Rng::new(0),
            cycle: 0,
            time: 0.0,
            ledger: Ledger::default(),
            lost: 0,
            reference: None,
            history: Default::default(),
            cell: Default::default(),
            laws: Default::default(),
            groups: Default::default(),
            carried: Carried::default(),
            derived: Derived::default(),
        }
    }

    /// Radius of a size type, if set.
    pub fn radius_of(&self, size: usize) -> Option<f64> {
        self.sizes
            .get(size.wrapping_sub(1))
            .copied()
            .filter(|r| *r > 0.0)
    }

    pub fn material(&self, m: usize) -> &Material {
        &self.materials[m - 1]
    }

    /// Draws a radius for a new particle of a size type (the nominal radius for Fixed).
    pub fn draw_radius(&mut self, size: usize) -> Option<f64> {
        use crate::sim::model::SizeDist;
        let r = self.radius_of(size)?;
        Some(match self.size_dist.get(size - 1) {
            None | Some(SizeDist::Fixed) => r,
            Some(&SizeDist::Normal { sd }) => loop {
                let z = self.rng.normal();
                if z.abs() <= 3.0 {
                    break r + sd * z;
                }
            },
            Some(&SizeDist::Uniform { min, max }) => min + (max - min) * self.rng.uniform(),
            Some(SizeDist::Table { radius, freq }) => {
                // Inverse of the cumulative frequencies: the first entry whose running sum
                // exceeds u Σf (one uniform number per particle). (A table read from a
                // damaged checkpoint, empty or of unequal lengths, gives the nominal r.)
                let pairs = || radius.iter().zip(freq);
                let u = self.rng.uniform() * pairs().map(|(_, f)| f).sum::<f64>();
                let mut acc = 0.0;
                // (u Σf rounded up to Σf: the last entry drawn at all.)
                let mut pick = pairs().rfind(|(_, f)| **f > 0.0).map(|(r, _)| *r);
                for (rk, f) in pairs() {
                    acc += f;
                    if u < acc {
                        pick = Some(*rk);
                        break;
                    }
                }
                pick.unwrap_or(r)
            }
        })
    }

    /// Largest radius a size type can produce.
    pub fn max_radius_of(&self, size: usize) -> Option<f64> {
        use crate::sim::model::SizeDist;
        let r = self.radius_of(size)?;
        Some(match self.size_dist.get(size - 1) {
            None | Some(SizeDist::Fixed) => r,
            Some(&SizeDist::Normal { sd }) => r + 3.0 * sd,
            Some(&SizeDist::Uniform { max, .. }) => max,
            Some(SizeDist::Table { radius, .. }) => radius.iter().copied().fold(0.0, f64::max),
        })
    }

    /// Largest particle radius present (0 if none).
    pub fn max_radius(&self) -> f64 {
        self.particles.radius.iter().copied().fold(0.0, f64::max)
    }

    pub fn min_radius(&self) -> f64 {
        self.particles
            .radius
            .iter()
            .copied()
            .fold(f64::INFINITY, f64::min)
    }
}
