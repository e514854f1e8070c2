//! Sums and averages over the particles of a range or group (`PRint GROup`, doc/groups.md):
//! the one function every output (and, later, the expressions of the command language) reads
//! a group's quantities through. Sums run in particle order: the same scene gives the same
//! bits.

use super::range::Range;
use super::scene::Scene;

/// The quantities of a range, by the names [`QUANTITIES`] gives them.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Aggregate {
    /// Number of particles.
    pub count: usize,
    /// Σ m (kg).
    pub mass: f64,
    /// Centre of mass Σ m x / Σ m (m); NaN for an empty range.
    pub centre: [f64; 3],
    /// Velocity of the centre of mass Σ m v / Σ m (m/s, the leap-frog's half-step
    /// velocities); NaN for an empty range.
    pub velocity: [f64; 3],
    /// Σ ½ m v² + ½ I ω² (J), as the energy ledger's kinetic energy counts it.
    pub kinetic: f64,
    /// Σ of the contact forces on the particles of the last step (N: particle and wall
    /// contacts, bridges and their dashpots, what `PRint Balls` shows as `force`; gravity and
    /// mass damping act in the update and are not in it). Zero in a scene that has not
    /// cycled since it changed.
    pub force: [f64; 3],
    /// Mean number of touching particle pairs per particle (`PRint CHist`'s coordination,
    /// partners in or out of the range); NaN for an empty range.
    pub coordination: f64,
}

/// The names of the quantities (`sim::range`, where the history's rows are checked).
pub use super::range::QUANTITIES;

impl Aggregate {
    /// The quantities in the order of [`QUANTITIES`].
    pub fn values(&self) -> [f64; 13] {
        let (c, v, f) = (self.centre, self.velocity, self.force);
        [
            self.count as f64,
            self.mass,
            c[0],
            c[1],
            c[2],
            v[0],
            v[1],
            v[2],
            self.kinetic,
            f[0],
            f[1],
            f[2],
            self.coordination,
        ]
    }

    /// One quantity by its name in [`QUANTITIES`] (case-insensitive).
    pub fn value(&self, name: &str) -> Option<f64> {
        let k = QUANTITIES
            .iter()
            .position(|q| q.eq_ignore_ascii_case(name))?;
        Some(self.values()[k])
    }
}

/// The sums and averages over the particles of index `members` (each once).
pub fn over(scene: &Scene, members: &[usize]) -> Aggregate {
    let p = scene.particles();
    let z = if members.is_empty() {
        Vec::new()
    } else {
        scene.coordination()
    };
    let (mut mass, mut kinetic, mut touching) = (0.0, 0.0, 0usize);
    let (mut mx, mut mv, mut force) = ([0.0; 3], [0.0; 3], [0.0; 3]);
    for &i in members {
        let m = p.mass[i];
        mass += m;
        kinetic +=
            0.5 * m * p.vel[i].norm_squared() + 0.5 * p.inertia(i) * p.spin[i].norm_squared();
        for k in 0..3 {
            mx[k] += m * p.pos[i][k];
            mv[k] += m * p.vel[i][k];
            force[k] += p.force[i][k];
        }
        touching += z[i];
    }
    let n = members.len();
    let per_mass = |s: [f64; 3]| {
        if n == 0 {
            [f64::NAN; 3]
        } else {
            s.map(|x| x / mass)
        }
    };
    Aggregate {
        count: n,
        mass,
        centre: per_mass(mx),
        velocity: per_mass(mv),
        kinetic,
        force,
        coordination: if n == 0 {
            f64::NAN
        } else {
            touching as f64 / n as f64
        },
    }
}

/// The sums and averages over the particles in `range` now ([`Scene::members`]); an error
/// names a group the range refers to that is not defined.
pub fn of_range(scene: &Scene, range: &Range) -> Result<Aggregate, String> {
    Ok(over(scene, &scene.members(range)?))
}

/// Appends a row (the cycle, then [`Aggregate::values`]) to every group recorded in the
/// history (`GROup name HIStory`); called with each history row.
pub fn record(scene: &mut Scene) {
    let mut rows = Vec::new();
    for (k, g) in scene.groups.list.iter().enumerate() {
        if g.record
            && let Ok(a) = of_group(scene, &g.name)
        {
            let mut row = vec![scene.cycle as f64];
            row.extend(a.values());
            rows.push((k, row));
        }
    }
    for (k, row) in rows {
        scene.groups.list[k].rows.push(row);
    }
}

/// The sums and averages over the named group now.
pub fn of_group(scene: &Scene, name: &str) -> Result<Aggregate, String> {
    of_range(scene, &Range::group(name))
}
