//! Coarse-grained continuum fields on a regular grid (`FIEld`), as doc/output.md,
//! "Coarse-grained fields" describes them, after Goldhirsch 2010 and Weinhart et al. 2012:
//! with a kernel φ of width w,
//!
//! - density ρ(r) = Σ_i m_i φ(r − r_i) (Weinhart 2012 (2.2));
//! - momentum p(r) = Σ_i m_i v_i φ(r − r_i) and velocity V = p/ρ (Weinhart 2012 (2.3));
//! - kinetic stress σᵏ(r) = Σ_i m_i (v_i − V)(v_i − V) φ(r − r_i)
//!   = Σ_i m_i v_i v_i φ − ρ V V (Weinhart 2012 (2.6), compression positive);
//! - contact stress σᶜ(r) = Σ_c f_c ⊗ l_c ∫₀¹ φ(r − r_A − s l_c) ds, f_c the force on B and
//!   l_c the branch A → B (B a wall: l_c to the contact point), the line integral of
//!   Goldhirsch 2010 (eq. 26), Weinhart 2012 (2.9), by 4-point Gauss–Legendre quadrature; the
//!   sign and the order (force, branch) of `PRint Stress` (`sim::stress`);
//! - solid fraction Σ_i (4/3)π R_i³ φ(r − r_i), and coordination Σ_i z_i φ / Σ_i φ.
//!
//! The kernel is a Gaussian exp(−d²/2w²) cut at 3w, or Lucy's (1 + 3q)(1 − q)³, q = d/w
//! (Lucy 1977, w its range). It is normalised on the grid itself: each point's weights over the
//! nodes sum to 1/ΔV (ΔV the volume of a node's cell), so the integral of every field over
//! the grid is the particles' sum to round-off: the mass Σ ρ ΔV = Σ m_i, the stress
//! Σ σᶜ ΔV = Σ f ⊗ l. Near an open side this is the usual boundary correction (a particle's
//! mass stays in the work-space); on a periodic axis the distances are to the nearest image.

use crate::sim::Scene;
use crate::sim::scene::Vec3;
use crate::sim::stress::pair_force;
use crate::sim::walls::wall_gap;

#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Kernel {
    Gauss,
    Lucy,
    /// The box kernel: 1/ΔV on the cell around a node, Pasha's bins (see [`sample`]).
    Bin,
}

impl Kernel {
    /// The kernel of `FIEld`'s words: `BIN`, `LUCy`, else the Gaussian.
    pub fn of(bin: bool, lucy: bool) -> Kernel {
        match (bin, lucy) {
            (true, _) => Kernel::Bin,
            (_, true) => Kernel::Lucy,
            _ => Kernel::Gauss,
        }
    }
}

/// The grid and kernel of a `FIEld`; `region`: the box [x1, x2, y1, y2, z1, z2] the grid
/// covers (`IN`, box kernel only), the work-space when `None`.
#[derive(Clone, Copy, Debug)]
pub struct Spec {
    pub nodes: [usize; 3],
    pub width: f64,
    pub kernel: Kernel,
    pub region: Option<[f64; 6]>,
}

impl Spec {
    /// The grid's corner and extent.
    fn frame(&self, scene: &Scene) -> ([f64; 3], [f64; 3]) {
        match self.region {
            Some(b) => ([b[0], b[2], b[4]], [b[1] - b[0], b[3] - b[2], b[5] - b[4]]),
            None => ([0.0; 3], scene.size()),
        }
    }
}

/// The fields at every node (x fastest, then y, then z); tensors row-major, row i the force
/// component, column j the branch component. `velocity` is the whole velocity: the
/// coarse-grained peculiar velocity plus the mean field G r of a deforming cell at the node.
#[derive(Clone, Debug, Default)]
pub struct Fields {
    pub nodes: [usize; 3],
    pub spacing: [f64; 3],
    /// The grid's corner (the first node is at origin + spacing/2).
    pub origin: [f64; 3],
    /// States averaged (1: the scene as it is).
    pub samples: usize,
    pub density: Vec<f64>,
    pub velocity: Vec<[f64; 3]>,
    pub stress_contact: Vec<[f64; 9]>,
    pub stress_kinetic: Vec<[f64; 9]>,
    pub solid_fraction: Vec<f64>,
    pub coordination: Vec<f64>,
}

/// Nodes at most (a guard against a grid that would not fit in memory).
pub const MAX_NODES: usize = 1 << 20;

/// Nodes within a kernel's reach at most (a width far above the spacing would make every
/// particle and contact visit the whole grid).
pub const MAX_REACH: usize = 1 << 15;

/// Checks a grid against the scene: nodes per axis, width at least the largest node
/// spacing (a point must reach a node on every axis).
pub fn check(scene: &Scene, spec: &Spec) -> Result<(), String> {
    let n = spec.nodes;
    if n.contains(&0)
        || n.iter()
            .try_fold(1usize, |a, &b| a.checked_mul(b))
            .is_none_or(|t| t > MAX_NODES)
    {
        return Err(format!(
            "FIEld: {} x {} x {} nodes: each at least 1, at most {MAX_NODES} in all",
            n[0], n[1], n[2]
        ));
    }
    let (_, size) = spec.frame(scene);
    if spec.kernel == Kernel::Bin {
        return Ok(());
    }
    let h = (0..3).map(|k| size[k] / n[k] as f64).fold(0.0, f64::max);
    if !(spec.width >= h && spec.width.is_finite()) {
        return Err(format!(
            "FIEld: the kernel width {} m must be at least the largest node spacing, {h:e} m",
            spec.width
        ));
    }
    let cut = cut_of(spec);
    let reach: f64 = (0..3)
        .map(|k| (2.0 * cut * n[k] as f64 / size[k] + 1.0).min(n[k] as f64))
        .product();
    if reach > MAX_REACH as f64 {
        return Err(format!(
            "FIEld: a kernel of width {} m reaches about {reach:.0} nodes of this grid; at most {MAX_REACH} (a smaller w, or fewer nodes)",
            spec.width
        ));
    }
    Ok(())
}

/// Where the kernel is cut.
fn cut_of(spec: &Spec) -> f64 {
    match spec.kernel {
        Kernel::Gauss => 3.0 * spec.width,
        Kernel::Lucy => spec.width,
        Kernel::Bin => 0.0,
    }
}

/// The grid: node spacing and how a point spreads over the nodes.
struct Grid {
    n: [usize; 3],
    h: [f64; 3],
    origin: [f64; 3],
    periodic: [bool; 3],
    cut: f64,
    spec: Spec,
    dv: f64,
}

impl Grid {
    fn kernel(&self, d2: f64) -> f64 {
        let w = self.spec.width;
        match self.spec.kernel {
            Kernel::Gauss => (-d2 / (2.0 * w * w)).exp(),
            Kernel::Lucy => {
                let q = d2.sqrt() / w;
                if q < 1.0 {
                    (1.0 + 3.0 * q) * (1.0 - q).powi(3)
                } else {
                    0.0
                }
            }
            Kernel::Bin => 1.0,
        }
    }

    /// The node whose cell holds `y` (box kernel): a cell holds its lower bounds, the last
    /// one its upper bounds too (a particle on the box's side is in, as `Window` has it);
    /// `None` outside the grid.
    fn cell(&self, y: &Vec3) -> Option<usize> {
        let mut ix = [0usize; 3];
        for k in 0..3 {
            let (n, h) = (self.n[k] as i64, self.h[k]);
            let t = y[k] - self.origin[k];
            let mut a = (t / h).floor() as i64;
            if self.periodic[k] {
                a = a.rem_euclid(n);
            } else if a == n && t <= n as f64 * h {
                a = n - 1;
            }
            if !(0..n).contains(&a) {
                return None;
            }
            ix[k] = a as usize;
        }
        Some(ix[0] + self.n[0] * (ix[1] + self.n[1] * ix[2]))
    }

    /// The nodes within reach of `y` on one axis: (index, distance from y).
    fn axis(&self, k: usize, y: f64) -> Vec<(usize, f64)> {
        let (n, h) = (self.n[k] as i64, self.h[k]);
        let y = y - self.origin[k];
        let lo = ((y - self.cut) / h - 0.5).ceil() as i64;
        let hi = ((y + self.cut) / h - 0.5).floor() as i64;
        let mut out = Vec::new();
        if self.periodic[k] {
            let (lo, hi) = if hi - lo + 1 >= n {
                // The kernel spans the cell: each node once, at its nearest image.
                let l = (y / h - 0.5 - n as f64 / 2.0).ceil() as i64;
                (l, l + n - 1)
            } else {
                (lo, hi)
            };
            for a in lo..=hi {
                out.push((a.rem_euclid(n) as usize, (a as f64 + 0.5) * h - y));
            }
        } else {
            for a in lo.max(0)..=hi.min(n - 1) {
                out.push((a as usize, (a as f64 + 0.5) * h - y));
            }
        }
        out
    }

    /// Calls `f(node, φ)` for every node within reach of `y`, φ normalised so that
    /// Σ φ ΔV = 1. Nothing when no node is within reach.
    fn spread(&self, y: &Vec3, mut f: impl FnMut(usize, f64)) {
        if self.spec.kernel == Kernel::Bin {
            if let Some(node) = self.cell(y) {
                f(node, 1.0 / self.dv);
            }
            return;
        }
        let ax: Vec<Vec<(usize, f64)>> = (0..3).map(|k| self.axis(k, y[k])).collect();
        let mut w = Vec::with_capacity(ax[0].len() * ax[1].len() * ax[2].len());
        let mut sum = 0.0;
        for &(c, dz) in &ax[2] {
            for &(b, dy) in &ax[1] {
                for &(a, dx) in &ax[0] {
                    let g = self.kernel(dx * dx + dy * dy + dz * dz);
                    if g > 0.0 {
                        w.push((a + self.n[0] * (b + self.n[1] * c), g));
                        sum += g;
                    }
                }
            }
        }
        if sum > 0.0 {
            let s = 1.0 / (sum * self.dv);
            for (node, g) in w {
                f(node, g * s);
            }
        }
    }
}

/// 4-point Gauss–Legendre nodes and weights on [0, 1].
const GL4: [(f64, f64); 4] = [
    (0.069_431_844_202_973_71, 0.173_927_422_568_726_93),
    (0.330_009_478_207_571_87, 0.326_072_577_431_273_07),
    (0.669_990_521_792_428_1, 0.326_072_577_431_273_07),
    (0.930_568_155_797_026_3, 0.173_927_422_568_726_93),
];

fn outer(f: &Vec3, l: &Vec3) -> [f64; 9] {
    let mut t = [0.0; 9];
    for i in 0..3 {
        for j in 0..3 {
            t[3 * i + j] = f[i] * l[j];
        }
    }
    t
}

/// The kernel-weighted sums of one state, or of several added up ([`Sums::add`]): what a
/// time average averages (Weinhart et al. 2012, §2.4: the fields' sums are averaged, then
/// the velocity and the kinetic stress are made of the averages).
#[derive(Clone, Debug)]
pub struct Sums {
    pub nodes: [usize; 3],
    pub spacing: [f64; 3],
    pub origin: [f64; 3],
    pub samples: usize,
    density: Vec<f64>,
    /// Σ m C φ, C the stored (peculiar) velocity.
    momentum: Vec<[f64; 3]>,
    /// Σ m C ⊗ C φ.
    flux: Vec<[f64; 9]>,
    contact: Vec<[f64; 9]>,
    solid: Vec<f64>,
    /// Σ z φ and Σ φ (coordination).
    zphi: Vec<f64>,
    phi: Vec<f64>,
    /// The mean field's velocity G r at each node (doc/cell.md).
    mean_field: Vec<[f64; 3]>,
}

impl Sums {
    /// Adds the sums of another state on the same grid.
    pub fn add(&mut self, o: &Sums) {
        fn plus<const N: usize>(a: &mut [[f64; N]], b: &[[f64; N]]) {
            for (x, y) in a.iter_mut().zip(b) {
                for k in 0..N {
                    x[k] += y[k];
                }
            }
        }
        for (a, b) in [
            (&mut self.density, &o.density),
            (&mut self.solid, &o.solid),
            (&mut self.zphi, &o.zphi),
            (&mut self.phi, &o.phi),
        ] {
            for (x, y) in a.iter_mut().zip(b) {
                *x += y;
            }
        }
        plus(&mut self.momentum, &o.momentum);
        plus(&mut self.flux, &o.flux);
        plus(&mut self.contact, &o.contact);
        plus(&mut self.mean_field, &o.mean_field);
        self.spacing = o.spacing;
        self.origin = o.origin;
        self.samples += o.samples;
    }

    /// The fields of the averages: ρ, p, Σ m C C φ, σᶜ averaged over the samples; the
    /// velocity p/ρ plus the mean field; the kinetic stress Σ m C C φ − ρ (p/ρ)(p/ρ) of the
    /// averages (so it holds the velocity's fluctuations in time as well as among the
    /// particles).
    pub fn finish(&self) -> Fields {
        let s = 1.0 / self.samples.max(1) as f64;
        let total = self.density.len();
        let mut f = Fields {
            nodes: self.nodes,
            spacing: self.spacing,
            origin: self.origin,
            samples: self.samples,
            density: self.density.iter().map(|x| x * s).collect(),
            velocity: vec![[0.0; 3]; total],
            stress_contact: self.contact.iter().map(|t| t.map(|x| x * s)).collect(),
            stress_kinetic: self.flux.iter().map(|t| t.map(|x| x * s)).collect(),
            solid_fraction: self.solid.iter().map(|x| x * s).collect(),
            coordination: vec![0.0; total],
        };
        for node in 0..total {
            let rho = f.density[node];
            let u = self.mean_field[node].map(|x| x * s);
            let mut vel = [0.0; 3];
            if rho > 0.0 {
                vel = self.momentum[node].map(|x| x * s / rho);
                for i in 0..3 {
                    for j in 0..3 {
                        f.stress_kinetic[node][3 * i + j] -= rho * vel[i] * vel[j];
                    }
                }
            }
            f.velocity[node] = [0, 1, 2].map(|k| vel[k] + u[k]);
            if self.phi[node] > 0.0 {
                f.coordination[node] = self.zphi[node] / self.phi[node];
            }
        }
        f
    }
}

/// The fields of the scene as it is (`check` first).
pub fn compute(scene: &Scene, spec: &Spec) -> Fields {
    sample(scene, spec).finish()
}

/// The sums of the scene as it is, one sample (`check` first).
pub fn sample(scene: &Scene, spec: &Spec) -> Sums {
    let (origin, size) = spec.frame(scene);
    let n = spec.nodes;
    let total = n[0] * n[1] * n[2];
    let h = [0, 1, 2].map(|k| size[k] / n[k] as f64);
    let periodic = scene.settings().periodic;
    let grid = Grid {
        n,
        h,
        origin,
        // A box of `IN` is not the cell: no images.
        periodic: periodic.map(|p| p && spec.region.is_none()),
        cut: cut_of(spec),
        spec: *spec,
        dv: h[0] * h[1] * h[2],
    };
    let p = scene.particles();
    let z = crate::output::vtk::frame::coordination(scene);
    let mut f = Sums {
        nodes: n,
        spacing: h,
        origin,
        samples: 1,
        density: vec![0.0; total],
        momentum: vec![[0.0; 3]; total],
        flux: vec![[0.0; 9]; total],
        contact: vec![[0.0; 9]; total],
        solid: vec![0.0; total],
        zphi: vec![0.0; total],
        phi: vec![0.0; total],
        mean_field: vec![[0.0; 3]; total],
    };
    for i in 0..p.len() {
        let (m, v) = (p.mass[i], p.vel[i]);
        let mvv = outer(&(v * m), &v);
        let vol = 4.0 / 3.0 * std::f64::consts::PI * p.radius[i].powi(3);
        grid.spread(&p.pos[i], |node, phi| {
            f.density[node] += m * phi;
            for k in 0..3 {
                f.momentum[node][k] += m * v[k] * phi;
            }
            for k in 0..9 {
                f.flux[node][k] += mvv[k] * phi;
            }
            f.solid[node] += vol * phi;
            f.zphi[node] += z[i] as f64 * phi;
            f.phi[node] += phi;
        });
    }
    // The mean field u = G r of a deforming cell (doc/cell.md: ed11 x + ed12 y, ed22 y,
    // ed33 z, from the cell's corner).
    let r = scene.cell().rate;
    for (node, u) in f.mean_field.iter_mut().enumerate() {
        let ix = [node % n[0], (node / n[0]) % n[1], node / (n[0] * n[1])];
        let x = [0, 1, 2].map(|k| origin[k] + (ix[k] as f64 + 0.5) * h[k]);
        *u = [r[0] * x[0] + r[3] * x[1], r[1] * x[1], r[2] * x[2]];
    }
    if spec.kernel == Kernel::Bin {
        bin_stress(scene, &grid, &mut f.contact);
    } else {
        contact_stress(scene, &grid, &mut f.contact);
    }
    f
}

/// The contact stress of the box kernel: each particle's moment (`sim::stress::
/// particle_moments`: its contacts' forces at their contact points, walls included) in the
/// cell of its centre, over the cell's volume: `Window` + `PRint Stress` on every cell.
fn bin_stress(scene: &Scene, grid: &Grid, out: &mut [[f64; 9]]) {
    let p = scene.particles();
    let moments = crate::sim::stress::particle_moments(scene);
    for (i, m) in moments.iter().enumerate() {
        grid.spread(&p.pos[i], |node, phi| {
            for a in 0..3 {
                for b in 0..3 {
                    out[node][3 * a + b] += m[a][b] * phi;
                }
            }
        });
    }
}

/// The contact stress: every particle pair and wall contact's f ⊗ l along its branch.
fn contact_stress(scene: &Scene, grid: &Grid, out: &mut [[f64; 9]]) {
    let p = scene.particles();
    // The branch in pieces no longer than a quarter of the kernel's width, each by
    // 4-point Gauss–Legendre: the normalised kernel is only piecewise smooth.
    let mut add = |a: &Vec3, l: &Vec3, force: &Vec3| {
        let t = outer(force, l);
        let pieces = ((4.0 * l.norm() / grid.spec.width).ceil() as usize).clamp(1, 64);
        for k in 0..pieces {
            for (s, wgl) in GL4 {
                let s = (k as f64 + s) / pieces as f64;
                let wgl = wgl / pieces as f64;
                grid.spread(&(a + l * s), |node, phi| {
                    for m in 0..9 {
                        out[node][m] += t[m] * wgl * phi;
                    }
                });
            }
        }
    };
    for c in scene.contacts().iter() {
        let s = c.s;
        if !s.touching && s.damp_force == 0.0 && s.bridge.is_none() {
            continue;
        }
        let a = p.pos[c.i as usize];
        let l = scene.branch(&a, &p.pos[c.j as usize]);
        let d = l.norm();
        if d > 0.0 {
            add(&a, &l, &pair_force(s, &(l / d)));
        }
    }
    for c in scene.contacts().wall_pairs() {
        let s = &c.s;
        if !s.touching && s.damp_force == 0.0 && s.bridge.is_none() {
            continue;
        }
        let Some(w) = scene.walls().get(c.wall as usize) else {
            continue;
        };
        let i = c.i as usize;
        let (gap, n) = wall_gap(&w.geom, &p.pos[i], p.radius[i]);
        let l = n * (gap + p.radius[i]);
        add(&p.pos[i], &l, &pair_force(s, &n));
    }
}

/// The particles' total mass and the grid's (Σ ρ ΔV), and the grid's mean stress
/// (Σ (σᶜ + σᵏ) ΔV / V, row-major): the checks of doc/output.md.
pub fn totals(scene: &Scene, f: &Fields) -> (f64, f64, [f64; 9]) {
    let dv = f.spacing[0] * f.spacing[1] * f.spacing[2];
    let grid_mass: f64 = f.density.iter().sum::<f64>() * dv;
    let mass: f64 = scene.particles().mass.iter().sum();
    let mut mean = [0.0; 9];
    for (c, k) in f.stress_contact.iter().zip(&f.stress_kinetic) {
        for m in 0..9 {
            mean[m] += c[m] + k[m];
        }
    }
    let nodes = f.density.len() as f64;
    (mass, grid_mass, mean.map(|x| x / nodes))
}

/// `FIEld` as text (a summary) and as JSON (every node).
pub fn report(scene: &Scene, spec: &Spec, f: &Fields) -> (String, serde_json::Value) {
    let (mass, grid_mass, mean) = totals(scene, f);
    let kernel = match spec.kernel {
        Kernel::Gauss => "gauss",
        Kernel::Lucy => "lucy",
        Kernel::Bin => "bin",
    };
    let avg = if f.samples > 1 {
        format!(" (the average of {} samples)", f.samples)
    } else {
        String::new()
    };
    let text = format!(
        "FIEld at cycle {}{avg}: {} x {} x {} nodes, {kernel} kernel{}; mass on the grid {grid_mass:.6e} kg (particles {mass:.6e} kg); mean stress of the grid (Pa) xx {:.6e} yy {:.6e} zz {:.6e} xy {:.6e} yz {:.6e} zx {:.6e}\n",
        scene.cycle(),
        f.nodes[0],
        f.nodes[1],
        f.nodes[2],
        match spec.kernel {
            Kernel::Bin => format!(
                " (cells of {:e} x {:e} x {:e} m from ({:e}, {:e}, {:e}))",
                f.spacing[0], f.spacing[1], f.spacing[2], f.origin[0], f.origin[1], f.origin[2]
            ),
            _ => format!(" of width {:e} m", spec.width),
        },
        mean[0],
        mean[4],
        mean[8],
        mean[1],
        mean[5],
        mean[6]
    );
    let origin = [0, 1, 2].map(|k| f.origin[k] + f.spacing[k] / 2.0);
    let j = serde_json::json!({
        "print": "field", "cycle": scene.cycle(), "time": scene.time(),
        "nodes": f.nodes, "spacing": f.spacing,
        "origin": origin,
        "kernel": kernel, "width": spec.width, "samples": f.samples,
        "mass": mass, "grid_mass": grid_mass, "mean_stress": mean,
        "density": f.density, "velocity": f.velocity,
        "stress_contact": f.stress_contact, "stress_kinetic": f.stress_kinetic,
        "solid_fraction": f.solid_fraction, "coordination": f.coordination,
    });
    (text, j)
}

/// The columns of [`csv`]: the node's centre, then the fields.
pub const CSV_COLUMNS: &str = "x,y,z,density,vx,vy,vz,\
sxx,sxy,sxz,syx,syy,syz,szx,szy,szz,\
scxx,scxy,scxz,scyx,scyy,scyz,sczx,sczy,sczz,\
skxx,skxy,skxz,skyx,skyy,skyz,skzx,skzy,skzz,solid_fraction,coordination";

/// The fields as CSV: a header line ([`CSV_COLUMNS`]: s the whole stress, sc its contact
/// part, sk its kinetic part, row-major) and a line per node (x fastest), each number the
/// shortest decimal that reads back to the same double.
pub fn csv(f: &Fields) -> String {
    use std::fmt::Write;
    let mut out = String::from(CSV_COLUMNS);
    out.push('\n');
    let n = f.nodes;
    for node in 0..f.density.len() {
        let ix = [node % n[0], (node / n[0]) % n[1], node / (n[0] * n[1])];
        let mut row: Vec<f64> = (0..3)
            .map(|k| f.origin[k] + (ix[k] as f64 + 0.5) * f.spacing[k])
            .collect();
        row.push(f.density[node]);
        row.extend(f.velocity[node]);
        let (c, k) = (f.stress_contact[node], f.stress_kinetic[node]);
        row.extend((0..9).map(|m| c[m] + k[m]));
        row.extend(c);
        row.extend(k);
        row.push(f.solid_fraction[node]);
        row.push(f.coordination[node]);
        let line: Vec<String> = row.iter().map(|x| format!("{x:?}")).collect();
        let _ = writeln!(out, "{}", line.join(","));
    }
    out
}

/// The fields as a VTK ImageData file (`.vti`): a point per node.
pub fn vti(scene: &Scene, f: &Fields) -> Vec<u8> {
    use super::vtk::xml::{Array, Values, encode_image};
    let flat9 = |v: &[[f64; 9]]| Values::F64(v.iter().flatten().copied().collect());
    let total: Vec<[f64; 9]> = f
        .stress_contact
        .iter()
        .zip(&f.stress_kinetic)
        .map(|(c, k)| std::array::from_fn(|m| c[m] + k[m]))
        .collect();
    let arrays = [
        Array::new("density", 1, Values::F64(f.density.clone())),
        Array::new(
            "velocity",
            3,
            Values::F64(f.velocity.iter().flatten().copied().collect()),
        ),
        Array::new("stress", 9, flat9(&total)),
        Array::new("stress_contact", 9, flat9(&f.stress_contact)),
        Array::new("stress_kinetic", 9, flat9(&f.stress_kinetic)),
        Array::new("solid_fraction", 1, Values::F64(f.solid_fraction.clone())),
        Array::new("coordination", 1, Values::F64(f.coordination.clone())),
    ];
    encode_image(
        f.nodes,
        [0, 1, 2].map(|k| f.origin[k] + f.spacing[k] / 2.0),
        f.spacing,
        &arrays,
        &super::vtk::frame::time_fields(scene),
        super::vtk::xml::Encoding::Zlib,
    )
}
