//! The wall pairs' clearance: how far every wall pair's centre was from its wall's surface
//! at the last check, so that the check for centres behind a wall (`after_step`) can be
//! left out while no centre can have reached its wall since.
//!
//! A centre at distance `d = gap + R` in front of a wall's surface (`gap < −R` is behind it)
//! reaches the surface only after the particle and the wall have moved, relative to each
//! other, by `d` at least: the distance to a plane, a sphere's or a cylinder's surface
//! changes by at most the displacement of the point (each is 1-Lipschitz in the point),
//! and by at most the surface's own travel (its centre's or plane's displacement plus the
//! change of its radius). In a step the particle moves by `|v| Δt ≤ v_max Δt` and a wall by
//! at most `(|v_w| + |v_r|) Δt` (`walls::advance`). While the travel summed since the check
//! stays below half the smallest clearance of the wall pairs, no wall pair's centre is
//! behind its wall, and the check would have found none: leaving it out keeps every output
//! bit (the factor 2 leaves the round-off of the gaps, ~1e-16 of the coordinates, far
//! behind; a clearance below 1e-6 of the smallest radius is not used).
//!
//! The bound holds for the list of wall pairs it was taken on: a rebuild of the candidates,
//! a change in the number of particles or of wall pairs, a periodic axis (a particle
//! wrapped through a periodic side jumps by the cell's length) or a deforming cell (which
//! maps the positions, `cell::deform`) takes the check again.

use super::*;

/// What the last check of the wall pairs left: the list it held for, its smallest
/// clearance, the relative travel since.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct Clearance {
    /// (rebuilds of the candidate list, particles, wall pairs) at the check.
    key: (u64, usize, usize),
    /// The smallest `gap + R` over the wall pairs at the check (m).
    least: f64,
    /// The largest particle travel plus the largest wall travel, summed over the steps since.
    travel: f64,
}

/// The identity of the list of wall pairs a clearance holds for.
fn key(scene: &Scene) -> (u64, usize, usize) {
    (
        scene.contacts.rebuilds(),
        scene.particles.len(),
        scene.contacts.wall_pairs.len(),
    )
}

/// Whether the wall pairs need no check after a step in which particles moved by at most
/// `step` (m), with `last` the clearance of the last check (updated with this step's travel).
/// `rmin`: the smallest radius.
pub(super) fn wall_pairs_clear(
    scene: &Scene,
    last: &mut Option<Clearance>,
    step: f64,
    dt: f64,
    rmin: f64,
) -> bool {
    let Some(c) = last.as_mut() else {
        return false;
    };
    if c.key != key(scene) || scene.settings.periodic != [false; 3] || scene.cell.is_active() {
        *last = None;
        return false;
    }
    let walls = scene.walls.iter().map(surface_speed).fold(0.0f64, f64::max);
    c.travel += step + walls * dt;
    let clear = 2.0 * c.travel < c.least && c.least > 1e-6 * rmin;
    if !clear {
        *last = None;
    }
    clear
}

/// The wall pairs whose centre is behind their wall's surface (`behind_walls` over the wall
/// pairs) and, when there is none, the clearance the next steps may count on (`None` with a
/// non-finite gap).
pub(super) fn behind_with_clearance(scene: &Scene) -> (Vec<(usize, usize)>, Option<Clearance>) {
    let p = &scene.particles;
    let shapes: Vec<WallShape> = scene.walls.iter().map(|w| WallShape::of(&w.geom)).collect();
    let mut least = f64::INFINITY;
    let mut out: Vec<(usize, usize)> = Vec::new();
    for c in &scene.contacts.wall_pairs {
        let (i, w) = (c.i as usize, c.wall as usize);
        let (gap, _) = shapes[w].gap(&p.pos[i], p.radius[i]);
        // (NaN is not "behind": a non-finite state is the blow-up check's; it leaves no
        // clearance.)
        if gap < -p.radius[i] {
            out.push((i, w));
        }
        let d = gap + p.radius[i];
        least = if d < least { d } else { least };
        if d.is_nan() {
            least = f64::NEG_INFINITY;
        }
    }
    out.sort_unstable();
    let clearance = (out.is_empty() && least > 0.0).then(|| Clearance {
        key: key(scene),
        least,
        travel: 0.0,
    });
    (out, clearance)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The distance of a point to a plane, a sphere's surface and a cylinder's changes by no
    /// more than the point's displacement plus the surface's own travel (its centre's
    /// displacement and the change of its radius): the bound the clearance counts on,
    /// checked on random points and moves against the walls' gap functions themselves.
    #[test]
    fn the_gap_changes_by_no_more_than_the_travel() {
        let mut r = crate::sim::rng::Rng::new(11);
        let mut v = || Vec3::new(r.normal(), r.normal(), r.normal());
        for _ in 0..2000 {
            let (x, dx, dc) = (v(), v() * 0.1, v() * 0.1);
            let dr = 0.05 * dx.x;
            let geoms = [
                (
                    WallGeom::Plane {
                        normal: [0.3, -1.0, 0.2],
                        d: 0.4,
                    },
                    0.0,
                ),
                (
                    WallGeom::Sphere {
                        centre: [0.1, 0.2, 0.3],
                        radius: 3.0,
                    },
                    dr,
                ),
                (
                    WallGeom::Obstacle {
                        centre: [0.1, 0.2, 0.3],
                        radius: 0.5,
                    },
                    dr,
                ),
                (
                    WallGeom::Cylinder {
                        point: [0.0, 0.1, 0.0],
                        axis: [0.2, 0.1, 1.0],
                        radius: 2.5,
                    },
                    dr,
                ),
            ];
            for (g, dr) in geoms {
                let mut wall = crate::sim::scene::Wall {
                    geom: g,
                    vel: [dc.x, dc.y, dc.z],
                    vr: dr,
                    material: 0,
                    servo: None,
                    force: [0.0; 3],
                    normal_force: 0.0,
                    disp: [0.0; 3],
                    travel: 0.0,
                };
                let before = WallShape::of(&wall.geom).gap(&x, 0.01).0;
                crate::sim::walls::advance(&mut wall, 1.0);
                let after = WallShape::of(&wall.geom).gap(&(x + dx), 0.01).0;
                let bound = dx.norm() + dc.norm() + dr.abs();
                assert!(
                    (after - before).abs() <= bound * (1.0 + 1e-12),
                    "{g:?}: {before} → {after}, travel {bound}"
                );
            }
        }
    }
}
