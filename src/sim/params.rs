//! Per-material-pair constants and the time step, computed once per `Cycle` command (the hot
//! loop only looks them up), and the scene checks that must pass before cycling.

use super::scene::Scene;
use crate::physics::{dashpot, hertz};
use crate::sim::model::NormalLaw;

/// Constants of a material pair (particle–particle or particle–wall).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct PairConst {
    /// E* (3.16) and G* (3.95).
    pub e_star: f64,
    pub g_star: f64,
    /// Smaller of the two friction coefficients (TRUBAL rule), or the pair's own (`SET PAIr`).
    pub mu: f64,
    /// Surface energy sqrt(γ1 γ2) (doc/spec/DECISIONS.md).
    pub gamma: f64,
    /// The same for contacts made after an impact.
    pub gamma_base: f64,
    /// Dimensionless dashpot ζ = C/sqrt(m* K) of the restitution damping (0 = none).
    pub zeta: f64,
    /// ζ sqrt(4/3 E*): the dashpot's force is this times (m*² R* α)^{1/4} α'
    /// (`physics::dashpot`).
    pub dash: f64,
    /// The pair's normal law of `SET NORmal`: 0 for Hertz/JKR, else 1 + its index in
    /// [`Model::laws`] (`Laws::pair_laws`).
    pub law: u16,
    /// The dashpot may pull a non-adhesive contact (`SET DASHpot LIGGGHTS`: no tension
    /// clamp; such contacts take the scalar kernel, not `lanes`).
    pub pull: bool,
}

/// A normal law of `SET NORmal` other than Hertz/JKR, as a material pair uses it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PairLaw {
    pub law: NormalLaw,
    /// Restitution coefficient of the linear laws' dashpot (Pasha 2013 (4.24)–(4.25); 0:
    /// none). The other laws keep the pair's Hertzian dashpot (`PairConst::zeta`).
    pub restitution: f64,
    /// The law as particle–wall contacts use it ([`Model::wall_laws`]; LIGGGHTS' JKR acts at
    /// a wall only at a positive overlap, `physics::jkr_nguyen`).
    pub wall: bool,
}

/// All particles have the same radius, mass and material, bit for bit (a monodisperse bed,
/// a lattice agglomerate): the pair loop takes them as constants instead of loading them
/// per pair (`cycle::block_forces`; the same arithmetic on the same values, so the same bits).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Uniform {
    pub radius: f64,
    pub mass: f64,
    pub material: u16,
}

impl Uniform {
    /// The particles' common radius, mass and material, if they have one.
    pub fn of(p: &super::scene::Particles) -> Option<Uniform> {
        let (&radius, &mass, &material) = (p.radius.first()?, p.mass.first()?, p.material.first()?);
        let same = |a: &[f64], x: f64| a.iter().all(|y| y.to_bits() == x.to_bits());
        (same(&p.radius, radius)
            && same(&p.mass, mass)
            && p.material.iter().all(|&m| m == material))
        .then_some(Uniform {
            radius,
            mass,
            material,
        })
    }
}

/// The table for all material pairs, plus what the scene needs.
#[derive(Clone, Debug, Default)]
pub struct Model {
    pub nmat: usize,
    pub table: Vec<PairConst>,
    /// Some pair has friction or adhesion: tangential forces and rotations are needed.
    pub rotation: bool,
    pub adhesion: bool,
    /// The normal laws of `SET NORmal` other than Hertz/JKR that pairs in use follow
    /// (`PairConst::law`); a scene with any goes through the adhesive kernel.
    pub laws: Vec<PairLaw>,
    /// The same, as particle–wall contacts use them (`PairLaw::wall`; the same indices).
    pub wall_laws: Vec<PairLaw>,
    /// Particle pairs are evaluated while their centres are closer than this times the sum
    /// of their radii in the adhesive and liquid kernels (`interact::Laws::reach`): 1 + 1e-6,
    /// or enough for the largest gap across which a pair with LIGGGHTS' JKR attracts.
    pub reach: f64,
    /// Rolling friction coefficient μ_r of every material pair (`SET ROLling`; None: no
    /// pair has one, `sim::rolling` does nothing).
    pub rolling: Option<Vec<f64>>,
    /// The step in use (with `FRAction AUTO` it follows the fastest contact, see
    /// `sim::contact_time`).
    pub dt: f64,
    /// The step of the scene's FRAction, with the limits of its viscous and Rayleigh
    /// dashpots.
    pub dt_base: f64,
    /// The FRAction in use.
    pub fraction: f64,
    /// The share of the default FRAction that `fraction` is, for a pair with a heavy dashpot
    /// (`physics::dashpot::heavy_step_share`); 1 otherwise.
    pub heavy_share: f64,
    /// The default FRAction is [`DEFAULT_FRACTION_ELASTIC`](super::scene::DEFAULT_FRACTION_ELASTIC):
    /// the scene dissipates nothing (see [`dissipation_free`]).
    pub elastic_default: bool,
    /// Rayleigh critical step of the scene.
    pub dt_rayleigh: f64,
    /// The particles' common radius, mass and material (no command changes them during a
    /// `Cycle`; particles lost through an open side leave the rest uniform).
    pub uniform: Option<Uniform>,
    /// How the `Cycle` runs (threads, parallel regions, vector instructions): decided once
    /// per `Cycle`, never changes a result.
    pub plan: crate::sim::parallel::plan::ExecPlan,
}

impl Model {
    #[inline]
    pub fn pair(&self, a: usize, b: usize) -> &PairConst {
        &self.table[(a - 1) * self.nmat + (b - 1)]
    }
}

/// The materials in use have a Young's modulus, a Poisson's ratio in (−1, 0.5) and a density.
fn check_materials(scene: &Scene, used: &[bool]) -> Result<(), String> {
    for (k, m) in scene.materials.iter().enumerate() {
        if !used[k] {
            continue;
        }
        let name = k + 1;
        if !(m.young > 0.0) {
            return Err(format!(
                "material {name} has no Young's modulus: give `YMD ymod {name}` (must be > 0)"
            ));
        }
        if !(-1.0 < m.poisson && m.poisson < 0.5) {
            return Err(format!(
                "material {name}: Poisson's ratio must be in (-1, 0.5)"
            ));
        }
        if !(m.density > 0.0) {
            return Err(format!(
                "material {name} has no density: give `Density d {name}` (must be > 0)"
            ));
        }
    }
    Ok(())
}

/// [`Model::reach`]: `1 + 1e-6`, or with LIGGGHTS' JKR (`SET NORmal NGUYEN`) `1 + |α_s|/(2r)`
/// with `α_s` (Lian (3.38)) at `R* = r`, `r` the smallest radius, the largest γ and the
/// smallest E* of the pairs with that law: since `|α_s| ∝ R*^{1/3}` and `R* ≤ min(r_i, r_j)
/// ≤ (r_i + r_j)/2`, every such pair with a gap below its `|α_s|` is within the reach.
fn reach_of(scene: &Scene, table: &[PairConst], laws: &[PairLaw]) -> f64 {
    let base: f64 = 1.0 + 1e-6;
    let rmin = scene
        .particles
        .radius
        .iter()
        .copied()
        .fold(f64::INFINITY, f64::min);
    let mut reach = base;
    for pc in table {
        if pc.law == 0 || laws[pc.law as usize - 1].law != NormalLaw::Nguyen || !(rmin > 0.0) {
            continue;
        }
        let j = crate::physics::jkr::Jkr {
            e_star: pc.e_star,
            r_star: rmin,
            gamma: pc.gamma.max(pc.gamma_base),
        };
        let r = 1.0 + 1.001 * (-j.alpha_s()) / (2.0 * rmin);
        if r.is_finite() {
            reach = reach.max(r);
        }
    }
    reach
}

/// The constants of every material pair in use, and what they ask of the scene.
struct PairTable {
    table: Vec<PairConst>,
    /// Some pair has friction or rolling friction (the particles rotate).
    rotation: bool,
    /// Some pair has a surface energy.
    adhesion: bool,
    laws: Vec<PairLaw>,
    /// The stiffest linear law, and whether every pair in use has one (the step).
    k_lin: f64,
    all_linear: bool,
    rolling: Vec<f64>,
    /// The share of the default step the heaviest dashpot asks for
    /// (`dashpot::heavy_step_share`; 1: none is heavy).
    heavy: f64,
    /// Every pair in use is Hertz without a dashpot, friction, adhesion or rolling spring.
    elastic: bool,
}

/// The pair table of [`build`]: E*, G*, μ, γ, the dashpot and the law of every pair of
/// materials in use (`used`).
fn pair_table(scene: &Scene, used: &[bool]) -> PairTable {
    let nmat = scene.materials.len();
    let mut table = vec![PairConst::default(); nmat * nmat];
    let mut rotation = false;
    let mut adhesion = false;
    let mut laws: Vec<PairLaw> = Vec::new();
    let mut k_lin: f64 = 0.0;
    let mut all_linear = true;
    let mut rolling = vec![0.0; nmat * nmat];
    let mut heavy: f64 = 1.0;
    let mut elastic = true;
    for a in 0..nmat {
        for b in 0..nmat {
            let (ma, mb) = (&scene.materials[a], &scene.materials[b]);
            if !(used[a] && used[b]) {
                continue;
            }
            let e_star = hertz::e_star(ma.young, ma.poisson, mb.young, mb.poisson);
            let g_star = hertz::g_star(ma.shear(), ma.poisson, mb.shear(), mb.poisson);
            // TRUBAL's rule, unless `SET PAIr` gave the pair its own values.
            let given = scene.laws.values_of(a + 1, b + 1);
            let mu = given.friction.unwrap_or(ma.friction.min(mb.friction));
            let gamma = (ma.gamma * mb.gamma).sqrt();
            let gamma_base = (ma.gamma_base * mb.gamma_base).sqrt();
            // Restitution: the pair uses the smaller e set on either material.
            let e = match (ma.restitution, mb.restitution) {
                (Some(x), Some(y)) => Some(x.min(y)),
                (x, y) => x.or(y),
            };
            let e = given.restitution.or(e);
            let form = scene.laws.dashpot_of(a + 1, b + 1);
            let zeta = e.map(|e| form.zeta(e)).unwrap_or(0.0);
            rotation |= mu > 0.0;
            adhesion |= gamma > 0.0 || gamma_base > 0.0;
            let law = scene.laws.normal_of(a + 1, b + 1);
            rolling[a * nmat + b] = scene.laws.rolling_of(a + 1, b + 1);
            rotation |= rolling[a * nmat + b] > 0.0;
            let linear = match law {
                NormalLaw::PashaFull { k_e, .. } | NormalLaw::PashaSimplified { k_e, .. } => {
                    k_lin = k_lin.max(k_e);
                    true
                }
                _ => false,
            };
            all_linear &= linear;
            let index = if law == NormalLaw::Hertz {
                0
            } else {
                let l = PairLaw {
                    law,
                    restitution: if linear { e.unwrap_or(0.0) } else { 0.0 },
                    wall: false,
                };
                match laws.iter().position(|x| *x == l) {
                    Some(k) => k + 1,
                    None => {
                        laws.push(l);
                        laws.len()
                    }
                }
            };
            // The linear laws have their own dashpot (PairLaw::restitution).
            let zeta = if linear { 0.0 } else { zeta };
            if let Some(e) = e
                && zeta > 0.0
                && e < dashpot::HEAVY_E
            {
                let zeta_ref = form.zeta(dashpot::HEAVY_REFERENCE_E);
                heavy = heavy.min(dashpot::heavy_step_share(e, zeta, zeta_ref));
            }
            elastic &= law == NormalLaw::Hertz
                && zeta == 0.0
                && mu == 0.0
                && gamma == 0.0
                && gamma_base == 0.0
                && rolling[a * nmat + b] == 0.0;
            table[a * nmat + b] = PairConst {
                e_star,
                g_star,
                mu,
                gamma,
                gamma_base,
                zeta,
                dash: zeta * (4.0 / 3.0 * e_star).sqrt(),
                law: index as u16,
                pull: form.pulls(),
            };
        }
    }
    PairTable {
        table,
        rotation,
        adhesion,
        laws,
        k_lin,
        all_linear,
        rolling,
        heavy,
        elastic,
    }
}

/// A scene that dissipates nothing: every pair in use is Hertz without a dashpot, friction,
/// adhesion or rolling spring (`elastic` of the pair table), and the scene has no liquid and
/// no Rayleigh or mass damping. Its contacts take the corrections of their edges
/// (`physics::hertz_edge`), and what is left of the leap-frog's energy error then is a slow
/// fall: −1.07e-4 of the energy per 10⁶ steps at FRAction 0.2 (an elastic gas of 1000
/// spheres: −1.2e-3 after 10⁷ steps), −7.8e-5 at 0.1, which holds 10⁷ steps within 1e-3
/// (issue 49 item 4; doc/limits.md, "Energy drift of an elastic gas"). Such a scene takes
/// the default FRAction [`DEFAULT_FRACTION_ELASTIC`](super::scene::DEFAULT_FRACTION_ELASTIC).
fn dissipation_free(scene: &Scene, elastic_pairs: bool) -> bool {
    elastic_pairs && undamped_dry(scene)
}

/// The scene has no liquid and no Rayleigh or mass damping (its elastic Hertz contacts take
/// the corrections of their edges, `interact::edges`).
pub(super) fn undamped_dry(scene: &Scene) -> bool {
    scene.liquid.is_none()
        && scene.damping_pp == Default::default()
        && scene.damping_pw == Default::default()
}

/// The step `dt` (FRAction × the Rayleigh step `dt_r`) bounded by the linear laws' own
/// critical step (`lin` = the stiffest linear law and whether every pair has one), the
/// stiffest viscous bridge and Rayleigh's stiffness damping.
fn step_limits(
    scene: &Scene,
    mut dt: f64,
    dt_r: f64,
    fraction: f64,
    (k_lin, all_linear): (f64, bool),
) -> Result<f64, String> {
    let p = &scene.particles;
    // The linear laws: FRAction × (m_min/k_max)^{1/2}, Pasha 2013 (4.29)–(4.31) (FRAction
    // 0.2 is his rule); the Rayleigh step still bounds the Hertzian pairs of a mixed scene.
    if k_lin > 0.0 {
        let mmin = p.mass.iter().copied().fold(f64::INFINITY, f64::min);
        let dt_lin = fraction * (mmin / k_lin).sqrt();
        dt = if all_linear { dt_lin } else { dt.min(dt_lin) };
        if scene.settings.auto_step.is_some() {
            return Err(
                "FRAction AUTO follows Hertzian contacts; give a FRAction with the linear laws of SET NORmal PASHA/PFULL".into(),
            );
        }
    }
    // Stability of the strongest viscous bridge dashpot (explicit update of a dashpot c on a
    // particle of mass m with up to 14 such neighbours: dt < 2 m / (14 c)); half of it.
    if let Some(l) = &scene.liquid
        && l.eta > 0.0
        && !p.is_empty()
    {
        // The strongest dashpot: the largest R*²/S_min, i.e. the largest pair (R*/100
        // by default, R*/1000 for Olsson's model) or a wall bridge (R* = R).
        let rmax = scene.max_radius();
        let rstar = if scene.walls.is_empty() || !scene.settings.wall_bridges {
            0.5 * rmax
        } else {
            rmax
        };
        let smin = scene
            .settings
            .smin
            .unwrap_or(rstar * crate::sim::model::smin_ratio(scene.settings.bridge));
        let c = 6.0 * std::f64::consts::PI * l.eta * rstar * rstar / smin;
        let mmin = p.mass.iter().copied().fold(f64::INFINITY, f64::min);
        dt = dt.min(mmin / (14.0 * c));
    }
    // Rayleigh contact damping: the stiffness term β k adds a dashpot; keep β ≤ dt/2... by
    // shrinking dt when β is large: the explicit limit of a damped spring needs dt ≤ 2/ω·(√(1+ζ²)−ζ).
    let beta = scene.damping_pp.beta.max(scene.damping_pw.beta);
    if beta > 0.0 {
        // With ω_max ≈ 2/dt_crit and ζ = β ω / 2.
        let w = std::f64::consts::PI / dt_r.max(1e-300) * 2.0;
        let z = 0.5 * beta * w;
        let lim = 2.0 / w * ((1.0 + z * z).sqrt() - z);
        dt = dt.min(lim);
    }
    Ok(dt)
}

/// Builds the pair table and the time step. Fails with a message when a material or size in
/// use lacks a value, or a value is unphysical.
pub fn build(scene: &Scene) -> Result<Model, String> {
    let nmat = scene.materials.len();
    let mut used = vec![false; nmat];
    for &m in &scene.particles.material {
        used[m as usize - 1] = true;
    }
    for w in &scene.walls {
        if w.material > nmat {
            return Err(format!("wall material {} is not defined", w.material));
        }
        used[w.material - 1] = true;
    }
    check_materials(scene, &used)?;
    let pairs = pair_table(scene, &used);
    let PairTable {
        table,
        laws,
        k_lin,
        all_linear,
        rolling,
        heavy,
        elastic,
        ..
    } = pairs;
    let rotation = pairs.rotation
        || scene.particles.spin.iter().any(|w| w.norm_squared() > 0.0)
        || (crate::sim::model::tangential_viscous(scene.settings.goldman, scene.settings.bridge)
            && scene.liquid.is_some_and(|l| l.eta > 0.0));
    let adhesion = pairs.adhesion;
    // Rayleigh critical step over the sizes and materials present.
    let p = &scene.particles;
    let mut dt_r = f64::INFINITY;
    for i in 0..p.len() {
        let m = &scene.materials[p.material[i] as usize - 1];
        let rho = p.mass[i] / (4.0 / 3.0 * std::f64::consts::PI * p.radius[i].powi(3));
        dt_r = dt_r.min(hertz::rayleigh_dt(p.radius[i], rho, m.shear(), m.poisson));
    }
    // The default FRAction, shortened for a heavy dashpot (not under FRAction AUTO, which
    // follows the fastest contact).
    let heavy = if scene.settings.fraction.is_none() && scene.settings.auto_step.is_none() {
        heavy
    } else {
        1.0
    };
    // A scene that dissipates nothing takes the elastic default (not under AUTO either).
    let elastic_default = scene.settings.fraction.is_none()
        && scene.settings.auto_step.is_none()
        && dissipation_free(scene, elastic);
    let fraction = scene.settings.fraction.unwrap_or_else(|| {
        let f = if elastic_default {
            super::scene::DEFAULT_FRACTION_ELASTIC
        } else {
            super::scene::default_fraction(adhesion || !laws.is_empty())
        };
        if heavy < 1.0 { f * heavy } else { f }
    });
    let dt = step_limits(scene, fraction * dt_r, dt_r, fraction, (k_lin, all_linear))?;
    let wall_laws = laws.iter().map(|l| PairLaw { wall: true, ..*l }).collect();
    Ok(Model {
        reach: reach_of(scene, &table, &laws),
        wall_laws,
        nmat,
        table,
        rotation,
        adhesion,
        laws,
        rolling: rolling.iter().any(|&m| m > 0.0).then_some(rolling),
        dt,
        dt_base: dt,
        fraction,
        heavy_share: heavy,
        elastic_default,
        dt_rayleigh: dt_r,
        uniform: Uniform::of(p),
        plan: crate::sim::parallel::plan::ExecPlan::detect(),
    })
}
