//! "Touching": the one definition that every output uses (`PRint INFo`, `PRint Contacts`,
//! `PRint CHist`, `PRint CLUsters`, `PRint BONds`, the bond plots and their JSON).
//!
//! A particle pair touches when its solid contact is made (the contact law's own state:
//! Hertz at an overlap above 0, JKR until the neck breaks) or when the gap between the two
//! surfaces is at most [`TOUCH_GAP`] of the smaller radius; a particle touches a wall
//! likewise, with its own radius. The allowance is round-off: the spheres of a lattice built
//! to touch are a few 1e-11 m apart (Lian's BCC lattice, a = 4R/√3 with R given to 7
//! digits: 4e-11 m in a 0.1 m cell), carry no force, and are the contacts a reader of the
//! thesis counts (8000 in `scripts/bcc_example.tru`).

use super::*;
use crate::sim::contacts::ContactState;
use crate::sim::walls::WallShape;

/// Surfaces this close, as a fraction of the smaller radius, touch.
pub const TOUCH_GAP: f64 = 1e-6;

impl Scene {
    /// The gap between the surfaces of particles `i` and `j` now (negative: an overlap;
    /// minimum image across periodic sides); +∞ for an index out of range.
    pub fn pair_gap(&self, i: usize, j: usize) -> f64 {
        let p = &self.particles;
        match (p.pos.get(i), p.pos.get(j)) {
            (Some(a), Some(b)) => self.branch(a, b).norm() - p.radius[i] - p.radius[j],
            _ => f64::INFINITY,
        }
    }

    /// The gap between particle `i` and wall `w` now (negative: an overlap); +∞ for an
    /// index out of range.
    pub fn wall_gap(&self, i: usize, w: usize) -> f64 {
        match (self.particles.pos.get(i), self.walls.get(w)) {
            (Some(x), Some(wall)) => WallShape::of(&wall.geom).gap(x, self.particles.radius[i]).0,
            _ => f64::INFINITY,
        }
    }

    /// Whether the pair of particles `i` and `j` with contact state `s` touches (the
    /// module's definition).
    pub fn pair_touches(&self, s: &ContactState, i: usize, j: usize) -> bool {
        s.touching || self.touch_by_gap(i, j)
    }

    /// Whether particle `i` with contact state `s` touches wall `w`.
    pub fn wall_touches(&self, s: &ContactState, i: usize, w: usize) -> bool {
        s.touching
            || self
                .particles
                .radius
                .get(i)
                .is_some_and(|&r| self.wall_gap(i, w) <= TOUCH_GAP * r)
    }

    fn touch_by_gap(&self, i: usize, j: usize) -> bool {
        let r = &self.particles.radius;
        match (r.get(i), r.get(j)) {
            (Some(a), Some(b)) => self.pair_gap(i, j) <= TOUCH_GAP * a.min(*b),
            _ => false,
        }
    }

    /// The contact states are those of the scene as it is: no command changed it since the
    /// last `Cycle` evaluated them.
    pub fn contacts_current(&self) -> bool {
        !self.contacts.is_stale()
    }

    /// The particle pairs (indices, the lower id first) and particle–wall pairs (particle,
    /// wall) whose gap now is within [`TOUCH_GAP`], found from the positions (a fresh search,
    /// so also in a scene that commands changed since the last `Cycle`).
    pub fn touching_by_gap(&self) -> (Vec<(usize, usize)>, Vec<(usize, usize)>) {
        if self.particles.is_empty() {
            return (Vec::new(), Vec::new());
        }
        let tol = TOUCH_GAP * self.max_radius();
        let (pairs, walls, _) = crate::sim::search::candidates(self, tol);
        let mut pairs: Vec<_> = pairs
            .iter()
            .filter(|k| self.touch_by_gap(k.i as usize, k.j as usize))
            .collect();
        pairs.sort_unstable_by_key(|k| (k.ida, k.idb));
        let pairs = pairs.iter().map(|k| (k.i as usize, k.j as usize)).collect();
        let walls = walls
            .iter()
            .map(|k| (k.i as usize, k.wall as usize))
            .filter(|&(i, w)| self.wall_gap(i, w) <= TOUCH_GAP * self.particles.radius[i])
            .collect();
        (pairs, walls)
    }

    /// The touching particle pairs (indices) and particle–wall pairs (particle, wall): over
    /// the contact list of the last `Cycle` while its states are current
    /// ([`Self::contacts_current`]; its candidate pairs reach beyond [`TOUCH_GAP`]), by the
    /// positions alone otherwise ([`Self::touching_by_gap`]).
    pub fn touching_pairs(&self) -> (Vec<(usize, usize)>, Vec<(usize, usize)>) {
        if !self.contacts_current() {
            return self.touching_by_gap();
        }
        let pairs = self
            .contacts
            .iter()
            .filter(|c| self.pair_touches(c.s, c.i as usize, c.j as usize))
            .map(|c| (c.i as usize, c.j as usize))
            .collect();
        let walls = self
            .contacts
            .wall_pairs()
            .iter()
            .filter(|c| self.wall_touches(&c.s, c.i as usize, c.wall as usize))
            .map(|c| (c.i as usize, c.wall as usize))
            .collect();
        (pairs, walls)
    }

    /// Each particle's number of touching particle pairs (the coordination number of
    /// `PRint CHist` and of the VTK frames).
    pub fn coordination(&self) -> Vec<usize> {
        let mut z = vec![0; self.particles.len()];
        for (i, j) in self.touching_pairs().0 {
            z[i] += 1;
            z[j] += 1;
        }
        z
    }

    /// The numbers of touching particle pairs and particle–wall pairs
    /// ([`Self::touching_pairs`]).
    pub fn touching_counts(&self) -> (usize, usize) {
        let (pairs, walls) = self.touching_pairs();
        (pairs.len(), walls.len())
    }

    /// Bonds now, as sorted id pairs: the touching pairs (`bridges` false,
    /// [`Self::touching_pairs`]) or the live liquid bridges (`bridges` true).
    pub fn bonded_pairs(&self, bridges: bool) -> Vec<(u32, u32)> {
        let id = &self.particles.id;
        let mut v: Vec<(u32, u32)> = if bridges {
            self.contacts
                .iter()
                .filter(|c| c.s.bridge.is_some())
                .map(|c| (c.ida, c.idb))
                .collect()
        } else if self.contacts_current() {
            self.contacts
                .iter()
                .filter(|c| self.pair_touches(c.s, c.i as usize, c.j as usize))
                .map(|c| (c.ida, c.idb))
                .collect()
        } else {
            self.touching_by_gap()
                .0
                .iter()
                .map(|&(i, j)| (id[i].min(id[j]), id[i].max(id[j])))
                .collect()
        };
        v.sort_unstable();
        v
    }
}
