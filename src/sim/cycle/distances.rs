//! Search distances of the step: TOL and XRES (automatic or set), the rebuild of the
//! candidate list, and the reach margins that let a pair approaching within a step be
//! evaluated (`physics::dashpot`).

use super::*;

/// Search distances in use: TOL (gap below which pairs are candidates) and XRES.
pub fn search_distances(scene: &Scene, model: &Model) -> (f64, f64) {
    let p = &scene.particles;
    let rmean = if p.is_empty() {
        0.0
    } else {
        p.radius.iter().sum::<f64>() / p.len() as f64
    };
    let mut need: f64 = 0.0;
    // Live bonds must stay in the candidate list: JKR down to α_s, bridges up to S_c.
    if model.adhesion {
        for i in 0..model.nmat {
            for j in 0..model.nmat {
                let pc = &model.table[i * model.nmat + j];
                let g = pc.gamma.max(pc.gamma_base);
                if g > 0.0 {
                    let rmax = scene.max_radius();
                    let jk = crate::physics::jkr::Jkr {
                        e_star: pc.e_star,
                        r_star: rmax,
                        gamma: g,
                    };
                    need = need.max(-jk.alpha_s());
                }
            }
        }
    }
    // The laws of `SET NORmal`: a Thornton–Ning contact breaks at most |α_s| of its
    // unloading curve beyond α_p ≥ 0 (R_p* < 10 R* taken as the bound), a linear one at
    // α_fp ≥ −(2 f_0p + 2 f_ce)/k_e − (13/9)²(162/137)πΓR*/(2k_e) (the full model's lowest
    // α_p − 13/9 f_cp/k_e); modified JKR at α = 0.
    for pl in &model.laws {
        let rmax = scene.max_radius();
        let g = (0..model.table.len())
            .filter(|&k| model.table[k].law as usize > 0)
            .map(|k| model.table[k].gamma)
            .fold(0.0, f64::max);
        let e_star = model
            .table
            .iter()
            .map(|p| p.e_star)
            .filter(|&e| e > 0.0)
            .fold(f64::INFINITY, f64::min);
        use crate::sim::model::NormalLaw;
        let fce = 3.0 * std::f64::consts::PI * g * rmax;
        let reach = match pl.law {
            NormalLaw::ThorntonNing { .. } => -crate::physics::jkr::Jkr {
                e_star,
                r_star: 10.0 * rmax,
                gamma: g,
            }
            .alpha_s(),
            NormalLaw::PashaFull { k_e, .. } => {
                (2.0 * fce
                    + (13.0f64 / 9.0).powi(2) * 162.0 / 137.0 * std::f64::consts::PI * g * rmax)
                    / k_e
            }
            NormalLaw::PashaSimplified { k_e, f_0p, .. } => (2.0 * f_0p + 2.0 * fce) / k_e,
            _ => 0.0,
        };
        need = need.max(reach);
    }
    if let Some(l) = &scene.liquid
        && l.pvol > 0.0
    {
        for c in scene.contacts.iter() {
            if let Some(b) = &c.s.bridge {
                need = need.max(b.s_c);
            }
        }
        // Bridges not formed yet: the largest possible volume (two largest spheres).
        let rmax = scene.max_radius();
        let v = l.pvol / 100.0 * 4.0 / 3.0 * std::f64::consts::PI * rmax.powi(3);
        let b = crate::physics::bridge::Bridge {
            r1: rmax,
            r2: rmax,
            volume: v,
            gamma: l.gamma,
            theta: l.theta,
        };
        need = need.max(crate::physics::bridge::rupture_distance(&b));
        if scene.settings.bridge == crate::sim::model::BridgeChoice::Rabinovich {
            // Willett's (52) is longer than Lian's (4.37) by the V*^{2/3} term.
            let m = crate::physics::bridge::BridgeModel::Rabinovich;
            need = need.max(crate::physics::bridge::model_rupture_distance(m, &b));
        }
    }
    let auto = (0.35 * rmean).max(1.5 * need);
    let tol = scene.settings.tol.unwrap_or(auto).max(1.5 * need);
    let xres = scene
        .settings
        .xres
        .map(|x| x.min(xres_of(tol)))
        .unwrap_or(xres_of(tol));
    (tol, xres)
}

/// The candidate list of a fast scene is made with up to this many times the automatic
/// TOL ([`rebuild_tol`]).
pub(super) const TOL_GROWTH: f64 = 2.0;

/// The number of steps the candidate list of a fast scene should last at least, at the
/// speed of its fastest particle ([`rebuild_tol`]).
pub(super) const LIST_STEPS: f64 = 50.0;

/// XRES for a TOL: just below TOL/(2√3) (Lian 1994 §5: no two particles can then have
/// closed a gap of TOL since the last rebuild without some displacement component
/// exceeding XRES).
pub fn xres_of(tol: f64) -> f64 {
    tol / (2.0 * 3f64.sqrt()) * 0.999
}

/// Whether TOL and XRES are both automatic, so that the rebuilds may use a larger TOL
/// ([`rebuild_tol`]).
pub(super) fn auto_search(scene: &Scene) -> bool {
    scene.settings.tol.is_none() && scene.settings.xres.is_none()
}

/// The TOL of a rebuild when TOL and XRES are automatic: large enough that the list lasts
/// [`LIST_STEPS`] steps at the fastest particle's largest velocity component v (XRES ≥
/// LIST_STEPS · v Δt), between the automatic `base` and [`TOL_GROWTH`] × `base`. A falling
/// or flowing scene then rebuilds its list up to half as often, for more candidate pairs
/// to test in each step; a settled one keeps `base`. The candidate list may be any list
/// that holds every pair with a gap below its TOL: the forces and positions are the same
/// bits for any TOL. The TOL used is kept with the list (`ContactStore::tol`, saved in
/// checkpoints) and the re-mapping test uses its XRES, so a restarted run rebuilds at the
/// same steps with the same TOL. Measured (doc/performance.md,
/// "What was tried"), S1 one thread side by side: the 50k bed (falling through its 5000 steps)
/// 0.92 × the time with LIST_STEPS 50 (0.97 × with 20; 0.86 × with twice the TOL
/// throughout), the 10k bed (settled after ~2000 steps) 1.03 × (0.98 × with 20).
pub(super) fn rebuild_tol(scene: &Scene, base: f64, dt: f64) -> f64 {
    if !auto_search(scene) {
        return base;
    }
    let vmax = scene
        .particles
        .vel
        .iter()
        .fold(0.0f64, |m, v| m.max(v.amax()));
    let want = 2.0 * 3f64.sqrt() * LIST_STEPS * vmax * dt / 0.999;
    // (NaN or a step of zero: the base.)
    if want > base {
        want.min(TOL_GROWTH * base)
    } else {
        base
    }
}

/// XRES of the re-mapping test: that of the TOL the list was made with when the search
/// distances are automatic (see [`rebuild_tol`]), else the user's (`xres`).
pub(super) fn xres_in_use(scene: &Scene, xres: f64) -> f64 {
    if auto_search(scene) {
        xres_of(scene.contacts.tol())
    } else {
        xres
    }
}

/// Whether the list made with TOL `made` serves a scene whose automatic TOL is `base`.
pub(super) fn tol_serves(scene: &Scene, made: f64, base: f64) -> bool {
    made == base || (auto_search(scene) && made >= base && made <= TOL_GROWTH * base)
}

/// Rebuilds the candidate lists.
pub fn rebuild(scene: &mut Scene, tol: f64) -> search::GridInfo {
    let parts = rayon::current_num_threads();
    // The hot list is derived from the list being replaced (`merge` makes it anew): freed
    // before the search, whose key lists made the rebuild's peak of memory with it (valgrind
    // massif, S1 50k, two threads: peak RSS 68.3-68.8 -> 66.9-67.2 MB).
    scene.contacts.step.hot = Vec::new();
    let (pairs, walls, info) = search::candidates_in_parts(scene, tol, parts);
    scene.contacts.merge(pairs, walls);
    scene.contacts.set_tol(tol);
    scene
        .particles
        .disp
        .par_chunks_mut(CHUNK)
        .for_each(|d| d.fill(Vec3::zeros()));
    for w in scene.walls.iter_mut() {
        w.travel = 0.0;
    }
    scene.cell.travel = 0.0;
    scene.contacts.step.max_disp = Some(0.0);
    info
}

/// Particles per entry of [`Scene::reach_ext`]: the margin of reach is kept per group of
/// consecutive particles (neighbours in space, the numbering follows it), so that the reach
/// tests read it from a table that stays in the cache (the update keeps each group's
/// largest velocity component, [`Speeds`]).
pub const EXT_GROUP: usize = leapfrog::GROUP;

/// Each group's margin of reach `Δt × its particles' largest velocity component` into `ext`
/// ([`EXT_GROUP`]); the largest velocity component (any thread count: the same value).
pub(super) fn reach_margins(vel: &[Vec3], dt: f64, ext: &mut Vec<f64>) -> f64 {
    ext.resize(vel.len().div_ceil(EXT_GROUP), 0.0);
    vel.par_chunks(CHUNK)
        .zip(ext.par_chunks_mut(CHUNK / EXT_GROUP))
        .map(|(v, e)| {
            let mut vmax = 0.0f64;
            for (v, e) in v.chunks(EXT_GROUP).zip(e.iter_mut()) {
                let a = largest_component(v);
                *e = a * dt;
                vmax = if a > vmax { a } else { vmax };
            }
            vmax
        })
        .reduce(|| 0.0, f64::max)
}

/// The fastest particles as the update leaves them ([`Speeds`]): kept by [`finish_move`]
/// from the chunks' sums, read by [`set_margins`] and `after_step`.
impl Speeds {
    /// From the chunks' sums of an update of `n` particles (chunk order).
    pub(super) fn set(&mut self, parts: &[ChunkSums], n: usize) {
        let per = CHUNK / EXT_GROUP;
        self.groups.clear();
        self.speed2 = 0.0;
        for (c, s) in parts.iter().enumerate() {
            let k = n.div_ceil(EXT_GROUP).saturating_sub(c * per).min(per);
            self.groups.extend_from_slice(&s.groups[..k]);
            self.speed2 = if s.speed2 > self.speed2 {
                s.speed2
            } else {
                self.speed2
            };
        }
        self.fresh = true;
    }

    /// The largest `|v|²` if fresh.
    pub(super) fn fastest(&self) -> Option<f64> {
        self.fresh.then_some(self.speed2)
    }
}

/// The largest of `f(x)` over `v` (0 for none) as `v.iter().fold(0.0, |m, x| m.max(f(x)))`
/// gives it: a NaN value is passed over, as `f64::max` passes it over (`if a > m` is false
/// for NaN), and the largest of a set does not depend on the order it is taken in. Four
/// accumulators, so that each comparison does not wait for the one before (the fold's chain
/// of `max` made these serial passes over the velocities, every step, latency-bound).
#[inline(always)]
fn largest_of(v: &[Vec3], f: impl Fn(&Vec3) -> f64) -> f64 {
    let mut m = [0.0f64; 4];
    let mut fours = v.chunks_exact(4);
    for x in &mut fours {
        for k in 0..4 {
            let a = f(&x[k]);
            m[k] = if a > m[k] { a } else { m[k] };
        }
    }
    for x in fours.remainder() {
        let a = f(x);
        m[0] = if a > m[0] { a } else { m[0] };
    }
    m.iter().fold(0.0f64, |a, &b| if b > a { b } else { a })
}

/// The largest absolute velocity component (nalgebra's `amax` of each vector) of `v`.
#[inline(always)]
pub(super) fn largest_component(v: &[Vec3]) -> f64 {
    largest_of(v, |x| x.amax())
}

/// The largest `|v|²` of `v` (the step's fastest particle, `after_step`).
#[inline(always)]
pub(super) fn largest_norm_squared(v: &[Vec3]) -> f64 {
    largest_of(v, |x| x.norm_squared())
}

/// The largest displacement component since the last rebuild (kept by the update; worked
/// out when not known).
pub(super) fn max_disp(scene: &mut Scene) -> f64 {
    if let Some(d) = scene.contacts.step.max_disp {
        return d;
    }
    let d = scene
        .particles
        .disp
        .par_chunks(CHUNK)
        .map(|d| d.iter().fold(0.0f64, |m, d| m.max(d.amax())))
        .reduce(|| 0.0, f64::max);
    scene.contacts.step.max_disp = Some(d);
    d
}

/// The margins of this step ([`ContactStore::margins`], [`Scene::reach_ext`]): pairs
/// approaching within half a step's travel get their share of the restitution dashpot
/// (physics::dashpot), so they are evaluated within Δt × (a bound of their relative speed)
/// of touching: |v_B − v_A|/2 ≤ (|v_A| + |v_B|)/2 < the sum of the two particles' largest
/// velocity components (the reach tests keep of those only the ones that may approach); a
/// particle–wall pair within its particle's margin plus the fastest wall's travel in a step
/// (`margins[1]`). Zero without a dashpot. Returns whether the candidate
/// list still holds every pair within those margins (gap at the last rebuild below TOL:
/// closed since by at most 2√3 × the largest displacement component, and a wall by its
/// travel).
pub(super) fn set_margins(scene: &mut Scene, model: &Model, dt: f64) -> bool {
    if !(dt > 0.0) || !model.table.iter().any(|p| p.zeta > 0.0) || scene.particles.is_empty() {
        scene.contacts.step.margins = [0.0; 2];
        scene.derived.reach_ext = Vec::new();
        return true;
    }
    let n = scene.particles.len();
    let v = match &scene.derived.speeds {
        // (The same values as the pass: the largest of the same sets.)
        s if s.fresh && s.groups.len() == n.div_ceil(EXT_GROUP) => {
            let ext = &mut scene.derived.reach_ext;
            ext.clear();
            ext.extend(s.groups.iter().map(|a| a * dt));
            s.groups
                .iter()
                .fold(0.0f64, |m, &a| if a > m { a } else { m })
        }
        _ => reach_margins(&scene.particles.vel, dt, &mut scene.derived.reach_ext),
    };
    let d = max_disp(scene);
    let walls = scene
        .walls
        .iter()
        .fold(0.0f64, |m, w| m.max(Vec3::from(w.vel).norm() + w.vr.abs()));
    let travel = scene.walls.iter().fold(0.0f64, |m, w| m.max(w.travel));
    // (Positive with a dashpot even when nothing moves: it also says "evaluate within the
    // margins", e.g. a wall that approaches particles at rest.)
    let m = [(2.0 * v * dt).max(f64::MIN_POSITIVE), walls * dt];
    scene.contacts.step.margins = m;
    let tol = scene.contacts.tol();
    let s3 = 3f64.sqrt();
    2.0 * s3 * d + m[0] < tol && s3 * d + travel + v * dt + m[1] < tol
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sim::rng::Rng;

    /// The four-accumulator maxima against the folds they replace (their definition): every
    /// length up to 9, signed zeros, NaN components and whole NaN vectors, bit for bit.
    #[test]
    fn the_largest_component_and_speed_are_the_folds() {
        let mut r = Rng::new(5);
        let mut cases = Vec::new();
        for n in 0..10 {
            for trial in 0..40 {
                let v: Vec<Vec3> = (0..n)
                    .map(|k| {
                        let mut x = Vec3::new(r.normal(), r.normal(), r.normal()) * 1e-2;
                        match (trial + k) % 7 {
                            0 => x.y = f64::NAN,
                            3 => x.z = f64::NAN,
                            1 => x = Vec3::repeat(f64::NAN),
                            2 => x = Vec3::new(-0.0, 0.0, -0.0),
                            _ => {}
                        }
                        x
                    })
                    .collect();
                cases.push(v);
            }
        }
        for v in &cases {
            let comp = v.iter().fold(0.0f64, |m, v| m.max(v.amax()));
            let speed = v.iter().fold(0.0f64, |m, v| m.max(v.norm_squared()));
            assert_eq!(largest_component(v).to_bits(), comp.to_bits(), "{v:?}");
            assert_eq!(largest_norm_squared(v).to_bits(), speed.to_bits(), "{v:?}");
        }
    }
}
