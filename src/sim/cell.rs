//! The deforming periodic cell (TRUBAL's `GRID`, doc/spec/physics-lian1994.md §7;
//! Lees–Edwards images for simple shear, doc/spec/shang1998.md §2.4).
//!
//! The work-space `Scene::size` is the cell. A velocity gradient `G` (1/s; `G[i][j] =
//! ∂v_i/∂x_j`, the six numbers of `GRID ed11 ed22 ed33 ed12 ed23 ed31`, of which TRUBAL uses
//! the diagonal and `ed12`) defines the mean field `u(x) = G x` (origin at the cell's corner):
//! - `ed11`, `ed22`, `ed33` stretch (> 0) or compress (< 0) the cell: each step every length
//!   along axis k and every particle coordinate `x_k` is multiplied by `exp(ed_kk Δt)`, so a
//!   cell without particles deforms exactly as `L_k(t) = L_k(0) exp(∫ ed_kk dt)`;
//! - `ed12` shears without distorting the cell: the images above it (`y + L_y`) slide along x
//!   by `shift`, which grows by `ed12 L_y Δt` per step and stretches with the cell's x
//!   (`× exp(ed11 Δt)`, as the images do), taken modulo `L_x`; a particle leaving
//!   through `y = L_y` re-enters through `y = 0` at its image, `x − shift`, and one leaving
//!   through `y = 0` at `x + shift` (Lees–Edwards). Every particle moves with the field too:
//!   `x += ed12 y Δt`.
//!
//! **Velocities are stored relative to the mean field** (the peculiar velocity `C = c − G x`,
//! what `PRint Balls` shows while a `GRID` is set). They follow the SLLOD equations
//! `dC/dt = F/m − G C` (Evans & Morriss 1990), which for these gradients are Newton's
//! equations for the total velocity `c` written in the moving frame (exactly so for simple
//! shear, where `G² = 0`); a particle crossing a sheared side keeps its `C`, so its total
//! x-velocity changes by `∓ ed12 L_y` as Lees–Edwards requires. The relative velocity of a
//! contact adds the mean-field difference `G l` across its branch vector `l`
//! (`cycle::pairs::rel_velocity`). Spins are total.
//!
//! Work: the cell puts in `−V σ:G Δt` per step (σ the average stress, compression positive,
//! kinetic part included: [`super::stress`]), booked as `Cell::work`, an input of the
//! energy books.
//!
//! Where the rest is: the cell's state (`Cell`, and the stress servo's targets `Servo`) is
//! the scene's (`scene/cell.rs`, re-exported here); the step books the work and calls the
//! servo's rule each step (`cycle::update`); `PRObe` cycles the cell (`sim::probe`).
pub use super::scene::cell::{Cell, HUNTING_STEPS, Servo, StressTarget};
use super::scene::{Scene, Vec3};

impl Servo {
    /// The servo of `targets` in a cell: σii adjusts ed_ii; the means adjust the axes they
    /// average over that no σii target holds and whose rate was 0 when the Cycle started
    /// (so a prescribed `GRID` rate stays: a constant-mean-stress triaxial test is `GRID 0 0
    /// −ε̇ 0 0 0` and `Cycle n S0 σ`), or all those axes if every one had a rate.
    pub fn new(cell: &Cell, targets: &[(StressTarget, f64)]) -> Servo {
        let held: Vec<usize> = targets
            .iter()
            .filter_map(|t| match t.0 {
                StressTarget::Axis(k) => Some(k),
                _ => None,
            })
            .collect();
        let targets = targets
            .iter()
            .map(|&(t, v)| {
                let over: &[usize] = match t {
                    StressTarget::Mean => &[0, 1, 2],
                    StressTarget::Mean12 | StressTarget::Ring => &[0, 1],
                    StressTarget::Axis(k) => {
                        let mut a = [false; 4];
                        a[k] = true;
                        return (t, v, a);
                    }
                };
                let mut free = [false; 4];
                if t == StressTarget::Ring {
                    // ed11 − ed22 on the axes no σii target holds; ed12 unless GRID
                    // prescribes a shear rate.
                    for &k in over {
                        free[k] = !held.contains(&k);
                    }
                    free[3] = cell.rate[3] == 0.0;
                    return (t, v, free);
                }
                for &k in over {
                    free[k] = !held.contains(&k) && cell.rate[k] == 0.0;
                }
                if free == [false; 4] {
                    for &k in over {
                        free[k] = !held.contains(&k);
                    }
                }
                (t, v, free)
            })
            .collect();
        Servo {
            targets,
            base: cell.rate,
            flips: 0,
        }
    }
}

/// The measured value of a servo's stress (compression positive).
pub fn measured(t: StressTarget, s: &[[f64; 3]; 3]) -> f64 {
    match t {
        StressTarget::Mean => (s[0][0] + s[1][1] + s[2][2]) / 3.0,
        StressTarget::Mean12 => (s[0][0] + s[1][1]) / 2.0,
        StressTarget::Axis(k) => s[k][k],
        StressTarget::Ring => principal_angle(s),
    }
}

/// The angle (degrees, in [0, 180)) of the major principal stress in the x–y plane,
/// measured from x towards y: `tan 2θ = 2 σ12 / (σ11 − σ22)` with σ compression positive,
/// so the major (most compressive) direction. σ12 is the `[0][1]` entry (force x, branch
/// y), the component the pair loop sums.
pub fn principal_angle(s: &[[f64; 3]; 3]) -> f64 {
    let t = 0.5 * (2.0 * s[0][1]).atan2(s[0][0] - s[1][1]).to_degrees();
    if t < 0.0 { t + 180.0 } else { t }
}

/// The error of a ring-shear servo holding the major principal stress at θ* (degrees): the
/// component of the x–y stress deviator `d = (½(σ11 − σ22), σ12) = r (cos 2θ, sin 2θ)`
/// normal to the target direction `(cos 2θ*, sin 2θ*)`,
/// `e = σ12 cos 2θ* − ½(σ11 − σ22) sin 2θ* = r sin 2(θ − θ*)` (Pa): zero at the target,
/// stable there, and measured as a stress so that `GAIN` means the same as for the other
/// targets.
pub fn ring_error(theta: f64, s: &[[f64; 3]; 3]) -> f64 {
    let (sn, cs) = (2.0 * theta.to_radians()).sin_cos();
    s[0][1] * cs - 0.5 * (s[0][0] - s[1][1]) * sn
}

/// One servo update after a step (TRUBAL's `GAIN g edmax`, `Mode`): with the error
/// `e = target − measured` (compression positive), mode 0 (velocity-increment control)
/// changes each adjusted rate by `−g e`, mode 1 (velocity control) sets it to `−g e`; the
/// rate is kept within ±edmax. A compressive error compresses (ed < 0).
///
/// `RING θ*` turns the x–y strain-rate deviator `q = (½(ed11 − ed22), ½ ed12)` along the
/// normal `n⊥ = (−sin 2θ*, cos 2θ*)` of its target by `g e_R` ([`ring_error`]): a deviatoric
/// strain rate q changes the stress deviator by about `−2G q Δt` (compression positive, G
/// the shear modulus), so e_R relaxes. ed12 gets `2 g e_R cos 2θ*` (unless GRID prescribes
/// a shear rate, which then stays); `−2 g e_R sin 2θ*` goes to ed11 − ed22, split equally
/// between them when no S11/S22 target holds either (the mean is then untouched), else all
/// on the free one. In mode 1 the rates it adjusts alone are the Cycle's starting rates
/// plus its part.
pub fn servo_step(cell: &mut Cell, servo: &mut Servo, s: &[[f64; 3]; 3]) {
    let [g, edmax] = cell.gain;
    let mut flipped = false;
    let mut set = |rate: &mut f64, ed: f64| {
        let old = *rate;
        *rate = ed.clamp(-edmax, edmax);
        flipped |= old.abs() == edmax && *rate == -old;
    };
    // Rates some stress target (not the ring) sets this step.
    let mut by_stress = [false; 4];
    for &(t, target, axes) in &servo.targets {
        if t == StressTarget::Ring {
            continue;
        }
        let e = target - measured(t, s);
        for k in 0..3 {
            if axes[k] {
                let old = cell.rate[k];
                let ed = if cell.mode == 0 { old - g * e } else { -g * e };
                set(&mut cell.rate[k], ed);
                by_stress[k] = true;
            }
        }
    }
    for &(t, theta, axes) in &servo.targets {
        if t != StressTarget::Ring {
            continue;
        }
        let e = ring_error(theta, s);
        let (sn, cs) = (2.0 * theta.to_radians()).sin_cos();
        let diff = -2.0 * g * e * sn;
        let mut part = [0.0; 4];
        match (axes[0], axes[1]) {
            (true, true) => (part[0], part[1]) = (0.5 * diff, -0.5 * diff),
            (true, false) => part[0] = diff,
            (false, true) => part[1] = -diff,
            (false, false) => {}
        }
        part[3] = 2.0 * g * e * cs;
        for k in [0, 1, 3] {
            if !axes[k] {
                continue;
            }
            // In mode 1 a rate no stress target set this step starts from the Cycle's.
            let from = if cell.mode == 0 || by_stress[k] {
                cell.rate[k]
            } else {
                servo.base[k]
            };
            set(&mut cell.rate[k], from + part[k]);
        }
    }
    servo.flips = if flipped { servo.flips + 1 } else { 0 };
}

/// Σ m C ⊗ C over the particles, in particle order (`stress::kinetic_part` times V).
pub fn kinetic_sum(p: &super::scene::Particles) -> [[f64; 3]; 3] {
    let mut k = Kinetic::default();
    for i in 0..p.len() {
        k.add(p.mass[i], &p.vel[i]);
    }
    k.tensor()
}

/// Σ m c ⊗ c as its six distinct sums (xx yy zz xy yz zx), kept in registers through a loop.
#[derive(Clone, Copy, Default)]
struct Kinetic([f64; 6]);

impl Kinetic {
    #[inline(always)]
    fn add(&mut self, m: f64, c: &Vec3) {
        let (mx, my, mz) = (m * c.x, m * c.y, m * c.z);
        let k = &mut self.0;
        k[0] += mx * c.x;
        k[1] += my * c.y;
        k[2] += mz * c.z;
        k[3] += mx * c.y;
        k[4] += my * c.z;
        k[5] += mz * c.x;
    }

    fn tensor(self) -> [[f64; 3]; 3] {
        let [xx, yy, zz, xy, yz, zx] = self.0;
        [[xx, xy, zx], [xy, yy, yz], [zx, yz, zz]]
    }
}

/// Why a `GRID` cannot be used in this work-space (None: it can).
pub fn grid_refusal(rates: &[f64; 6], periodic: [bool; 3]) -> Option<String> {
    if rates.iter().any(|r| !r.is_finite()) {
        return Some("GRID: the strain rates must be finite numbers".into());
    }
    if rates[4] != 0.0 || rates[5] != 0.0 {
        return Some(
            "GRID: ed23 and ed31 are not used (as in TRUBAL): enter 0; shear the cell with ed12 (∂v_x/∂y)"
                .into(),
        );
    }
    let names = ["x", "y", "z"];
    for k in 0..3 {
        if rates[k] != 0.0 && !periodic[k] {
            return Some(format!(
                "GRID: ed{0}{0} strains the {1} axis, which is open; the cell deforms only along periodic axes (SET PERiodic {1})",
                k + 1,
                names[k]
            ));
        }
    }
    if rates[3] != 0.0 && !(periodic[0] && periodic[1]) {
        return Some(
            "GRID: ed12 shears the cell with Lees–Edwards images, which needs the x and y axes periodic (SET PERiodic x y)"
                .into(),
        );
    }
    None
}

/// Why `n` steps of `dt` at the current rates would shrink the cell below twice the largest
/// diameter along some axis (None: they would not).
pub fn shrink_refusal(scene: &Scene, n: u64, dt: f64) -> Option<String> {
    let dmax = 2.0 * scene.max_radius();
    let names = ["x", "y", "z"];
    for k in 0..3 {
        let ed = scene.cell.rate[k];
        if ed < 0.0 {
            let end = scene.size[k] * (ed * dt * n as f64).exp();
            if end < 2.0 * dmax {
                return Some(format!(
                    "GRID ed{0}{0} = {ed:e} 1/s for {n} cycles would shrink the cell along {1} from {2:e} m to {end:e} m, below twice the largest diameter ({3:e} m); use fewer cycles or a smaller rate",
                    k + 1,
                    names[k],
                    scene.size[k],
                    2.0 * dmax
                ));
            }
        }
    }
    None
}

/// The cell's share of a step, after the particles moved with their peculiar velocities:
/// the cell and the particles' positions follow the mean field, the peculiar velocities lose
/// `G C Δt` (SLLOD), the Lees–Edwards offset advances, the particles are wrapped into the new
/// cell. Returns Σ m C ⊗ C of the velocities before (the kinetic stress times V).
///
/// The re-mapping rule: the mean field moves the cell's images with it, so it changes the
/// branch vector `l` of any pair (across a side or the sheared side included) by exactly
/// `G l Δt`; for the pairs that can come within reach before the next rebuild, `|l|` is at
/// most about `4 R_max`. So the field's share of the particles' motion is not counted as
/// their displacement (`Particles::disp`: the peculiar motion only); the bound
/// `max_k Σ_j |G_kj| 4 R_max Δt` of its relative share is added to `Cell::travel`.
pub fn deform(scene: &mut Scene, dt: f64) -> [[f64; 3]; 3] {
    let r = scene.cell.rate;
    let f = [(r[0] * dt).exp(), (r[1] * dt).exp(), (r[2] * dt).exp()];
    let shear = r[3] * dt;
    for k in 0..3 {
        scene.size[k] *= f[k];
        scene.cell.strain[k] += r[k] * dt;
    }
    scene.cell.strain[3] += r[3] * dt;
    // The images above the cell sit at `(shift, L_y)` from the particles: the field maps that
    // lattice vector as every other, `shift → f₁₁ shift + ed12 L_y Δt`, so that a pair across
    // the sheared side moves by `G l Δt` like any other (the re-mapping rule above).
    if r[3] != 0.0 || (r[0] != 0.0 && scene.cell.shift != 0.0) {
        let (lx, step) = (scene.size[0], r[3] * scene.size[1] * dt);
        scene.cell.shift = (scene.cell.shift * f[0] + step).rem_euclid(lx);
    }
    // One pass: the kinetic sum of the velocities before, the field's share of the motion,
    // SLLOD, and the wrap into the new cell ([`wrap_one`]).
    let (size, periodic, shift) = (scene.size, scene.settings.periodic, scene.cell.shift);
    let sheared = periodic[1] && shift != 0.0;
    let p = &mut scene.particles;
    let inv = [1.0 / f[0], 1.0 / f[1], 1.0 / f[2]];
    let shift = sheared.then_some(shift);
    let (kin, rmax) = if r[..3] == [0.0; 3] {
        // Simple shear: no scaling (a factor of exactly 1, so the same bits).
        field_pass::<false>(p, f, inv, shear, size, periodic, shift)
    } else {
        field_pass::<true>(p, f, inv, shear, size, periodic, shift)
    };
    let row = (r[0].abs() + r[3].abs()).max(r[1].abs()).max(r[2].abs());
    scene.cell.travel += row * (4.0 * rmax) * dt;
    kin.tensor()
}

/// The particle pass of [`deform`]: returns Σ m C ⊗ C of the velocities before it and the
/// largest radius. `SCALE`: whether a diagonal rate is set (else `f` and `inv` are 1).
#[inline(always)]
fn field_pass<const SCALE: bool>(
    p: &mut super::scene::Particles,
    f: [f64; 3],
    inv: [f64; 3],
    shear: f64,
    size: [f64; 3],
    periodic: [bool; 3],
    shift: Option<f64>,
) -> (Kinetic, f64) {
    let mut kin = Kinetic::default();
    let mut rmax = 0.0f64;
    let (lo, hi) = bounds(size, periodic);
    let parts = p.pos.iter_mut().zip(p.vel.iter_mut());
    for ((x, v), (&m, &r)) in parts.zip(p.mass.iter().zip(p.radius.iter())) {
        let c = *v;
        kin.add(m, &c);
        rmax = rmax.max(r);
        let mut y = if SCALE {
            Vec3::new(x.x * f[0], x.y * f[1], x.z * f[2])
        } else {
            *x
        };
        y.x += shear * x.y;
        if outside(&y, &lo, &hi) {
            wrap_one(&mut y, size, periodic, shift);
        }
        *x = y;
        *v = if SCALE {
            Vec3::new(c.x * inv[0] - shear * c.y, c.y * inv[1], c.z * inv[2])
        } else {
            Vec3::new(c.x - shear * c.y, c.y, c.z)
        };
    }
    (kin, rmax)
}

/// Brings every particle back into the cell through the periodic sides; across y with the
/// Lees–Edwards offset (`shift`, x displacement of the images above), before x is wrapped.
pub fn wrap(scene: &mut Scene) {
    let (size, periodic, shift) = (scene.size, scene.settings.periodic, scene.cell.shift);
    if periodic == [false; 3] {
        return;
    }
    let sheared = (periodic[1] && shift != 0.0).then_some(shift);
    let (lo, hi) = bounds(size, periodic);
    for x in scene.particles.pos.iter_mut() {
        if outside(x, &lo, &hi) {
            wrap_one(x, size, periodic, sheared);
        }
    }
}

/// The cell's bounds on its periodic axes, unbounded on the others: [`outside`] is one test
/// per particle of whether [`wrap_one`] has anything to do.
fn bounds(size: [f64; 3], periodic: [bool; 3]) -> ([f64; 3], [f64; 3]) {
    let lo = periodic.map(|q| if q { 0.0 } else { f64::NEG_INFINITY });
    let hi = std::array::from_fn(|k| if periodic[k] { size[k] } else { f64::INFINITY });
    (lo, hi)
}

/// Whether `x` lies outside the bounds of [`bounds`] (the conditions of [`wrap_one`],
/// evaluated without branches).
#[inline(always)]
fn outside(x: &Vec3, lo: &[f64; 3], hi: &[f64; 3]) -> bool {
    (x.x < lo[0]) | (x.x >= hi[0]) | (x.y < lo[1]) | (x.y >= hi[1]) | (x.z < lo[2]) | (x.z >= hi[2])
}

/// One particle into the cell: across a sheared y side first (at the image, `shift`), then
/// along each periodic axis.
#[inline(always)]
fn wrap_one(x: &mut Vec3, size: [f64; 3], periodic: [bool; 3], shift: Option<f64>) {
    if let Some(shift) = shift
        && (x.y < 0.0 || x.y >= size[1])
    {
        let l = size[1];
        let n = (x.y / l).floor();
        x.y -= n * l;
        x.x -= n * shift;
        if x.y >= l {
            // (Rounding: y − n l may land on l.)
            x.y = 0.0;
        }
    }
    for k in 0..3 {
        if periodic[k] {
            let l = size[k];
            if x[k] < 0.0 || x[k] >= l {
                x[k] = x[k].rem_euclid(l);
            }
        }
    }
}

/// The scene's branch vectors through the periodic images.
impl Scene {
    /// Minimum-image separation vector b − a for the periodic axes (with the Lees–Edwards
    /// offset of a sheared cell).
    #[inline]
    pub fn branch(&self, a: &Vec3, b: &Vec3) -> Vec3 {
        nearest_image(b - a, self.size, self.settings.periodic, self.cell.shift)
    }
}

/// The nearest periodic image of the branch vector `d` (unchanged along open axes). One test
/// for the usual scene without periodic axes: in the pair loop, a test per component cost 7 %
/// of the S1 run. `shift`: the Lees–Edwards offset of a sheared cell (above): an image
/// one cell up in y is `shift` further along x, so y is reduced first.
#[inline(always)]
pub fn nearest_image(mut d: Vec3, size: [f64; 3], periodic: [bool; 3], shift: f64) -> Vec3 {
    if periodic != [false; 3] {
        let sheared = shift != 0.0 && periodic[1];
        if sheared {
            let n = images(d.y / size[1]);
            d.y -= size[1] * n;
            d.x -= shift * n;
        }
        for k in 0..3 {
            if periodic[k] && !(sheared && k == 1) {
                let l = size[k];
                d[k] -= l * images(d[k] / l);
            }
        }
    }
    d
}

/// `q.round()`, without the call to the C library's `round` that the baseline x86-64 build
/// makes (no rounding instruction before SSE4.1) in the usual case `|q| < 0.5` (two
/// particles of the work-space closer than half its width), where it is ±0 with the sign of
/// `q`, as `round` gives: the same bits for every input.
#[inline(always)]
fn images(q: f64) -> f64 {
    if q.abs() < 0.5 {
        0.0f64.copysign(q)
    } else {
        q.round()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn only_the_used_rates_on_periodic_axes_are_accepted() {
        assert!(grid_refusal(&[-1.0, 0.0, 0.0, 5.0, 0.0, 0.0], [true; 3]).is_none());
        assert!(grid_refusal(&[0.0, 0.0, 0.0, 0.0, 1.0, 0.0], [true; 3]).is_some());
        assert!(grid_refusal(&[0.0, 0.0, -1.0, 0.0, 0.0, 0.0], [true, true, false]).is_some());
        assert!(grid_refusal(&[0.0, 0.0, 0.0, 1.0, 0.0, 0.0], [true, false, true]).is_some());
        assert!(grid_refusal(&[f64::NAN, 0.0, 0.0, 0.0, 0.0, 0.0], [true; 3]).is_some());
    }

    #[test]
    fn the_field_is_the_gradient_times_the_branch() {
        let c = Cell {
            rate: [1.0, 2.0, 3.0, 4.0, 0.0, 0.0],
            ..Default::default()
        };
        let l = Vec3::new(1.0, 10.0, 100.0);
        let g = c.gradient();
        let want = Vec3::new(
            g[0][0] * l.x + g[0][1] * l.y + g[0][2] * l.z,
            g[1][0] * l.x + g[1][1] * l.y + g[1][2] * l.z,
            g[2][0] * l.x + g[2][1] * l.y + g[2][2] * l.z,
        );
        assert_eq!(c.field(&l), want);
    }

    /// A stress tensor whose major principal direction in x–y is at θ (degrees): σ1 along
    /// (cos θ, sin θ), σ2 across it (compression positive, σ1 > σ2).
    fn rotated(s1: f64, s2: f64, theta: f64) -> [[f64; 3]; 3] {
        let (sn, cs) = theta.to_radians().sin_cos();
        let xx = s1 * cs * cs + s2 * sn * sn;
        let yy = s1 * sn * sn + s2 * cs * cs;
        let xy = (s1 - s2) * sn * cs;
        [[xx, xy, 0.0], [xy, yy, 0.0], [0.0, 0.0, 0.5 * (s1 + s2)]]
    }

    #[test]
    fn the_principal_angle_and_the_ring_error_of_a_rotated_stress() {
        for theta in [0.0, 10.0, 45.0, 89.0, 90.0, 120.0, 135.0, 170.0] {
            let s = rotated(3e4, 1e4, theta);
            assert!((principal_angle(&s) - theta).abs() < 1e-9, "{theta}");
            assert!(ring_error(theta, &s).abs() < 1e-9 * 3e4, "{theta}");
            // Off the target, the error is r sin 2(θ − θ*), r = (σ1 − σ2)/2.
            let e = ring_error(theta + 10.0, &s);
            let want = 1e4 * (2.0 * (-10.0f64).to_radians()).sin();
            assert!((e - want).abs() < 1e-9 * 3e4, "{theta}: {e} vs {want}");
        }
    }

    /// The ring servo's sign: on a linear visco-elastic cell (σ = σ₀ − 2G ε − 2η D in x–y,
    /// compression positive, ε the cell's strain, D its rate; the viscosity stands for the
    /// dashpots that damp mode 0's integral loop) it turns the major principal stress to
    /// its target, in both modes, from both sides, with or without a held σ22.
    #[test]
    fn the_ring_servo_turns_an_elastic_cell_to_its_target() {
        let (g_mod, eta, dt) = (1e7, 20.0, 1e-6);
        for (mode, gain) in [(0u8, 1e-4), (1, 1e-2)] {
            for (theta, start) in [(120.0, 135.0), (120.0, 100.0), (30.0, 70.0), (160.0, 135.0)] {
                for hold22 in [false, true] {
                    let s0 = rotated(3e4, 1e4, start);
                    let mut cell = Cell {
                        gain: [gain, 1e3],
                        mode,
                        ..Default::default()
                    };
                    let mut targets = vec![(StressTarget::Ring, theta)];
                    if hold22 {
                        targets.push((StressTarget::Axis(1), s0[1][1]));
                    }
                    let mut servo = Servo::new(&cell, &targets);
                    let mut strain = [0.0; 4];
                    let mut s = s0;
                    for _ in 0..20000 {
                        servo_step(&mut cell, &mut servo, &s);
                        for (k, e) in strain.iter_mut().enumerate() {
                            *e += cell.rate[k] * dt;
                        }
                        let r = &cell.rate;
                        s = s0;
                        s[0][0] -= 2.0 * g_mod * strain[0] + 2.0 * eta * r[0];
                        s[1][1] -= 2.0 * g_mod * strain[1] + 2.0 * eta * r[1];
                        s[0][1] -= g_mod * strain[3] + eta * r[3];
                        s[1][0] = s[0][1];
                    }
                    let got = principal_angle(&s);
                    assert!(
                        (got - theta).abs() < 0.1,
                        "mode {mode}, {start} -> {theta}, hold22 {hold22}: {got}"
                    );
                    if hold22 {
                        assert!((s[1][1] - s0[1][1]).abs() < 1e-3 * s0[1][1]);
                    }
                }
            }
        }
    }
}

#[cfg(test)]
mod image_tests {
    use super::images;

    #[test]
    fn images_is_round_to_the_bit() {
        let mut xs = vec![
            0.0,
            -0.0,
            0.49999999999999994,
            -0.49999999999999994,
            0.5,
            -0.5,
            1.5,
            -1.5,
            2.5,
            1e300,
            f64::MIN_POSITIVE,
            -f64::MIN_POSITIVE,
            f64::INFINITY,
            f64::NEG_INFINITY,
            f64::NAN,
        ];
        let mut r = crate::sim::rng::Rng::new(5);
        xs.extend((0..10_000).map(|_| r.normal()));
        for x in xs {
            assert_eq!(images(x).to_bits(), x.round().to_bits(), "{x:e}");
        }
    }
}
