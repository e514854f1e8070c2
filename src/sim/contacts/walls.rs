//! Particle–wall pairs and the per-block output of the wall loop (forces in pair order,
//! grouped by particle chunk; each wall's force summed per block).

use super::*;

/// A candidate particle–wall pair found by the search.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub struct WallKey {
    pub id: u32,
    pub wall: u32,
    pub i: u32,
}

/// A candidate particle–wall pair.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct WallPair {
    pub i: u32,
    pub id: u32,
    pub wall: u32,
    #[serde(deserialize_with = "old::deserialize_state")]
    pub s: ContactState,
}

/// Force of an evaluated particle–wall pair in the current step: on the wall (`f`; the
/// particle `i` gets −f) and the moment on the particle.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct WallForce {
    pub f: Vec3,
    pub m: Vec3,
    pub i: u32,
}

/// The wall contacts' output of the current step (derived; not saved): made by the force
/// step, one piece per task (each task evaluates the wall pairs of about its own particles,
/// so that the core that updates a particle has its wall forces in its cache), applied to
/// the particles by the particle update, chunk by chunk (`cycle::move_all`).
#[derive(Clone, Debug, Default)]
pub struct WallOut {
    /// Per task, in order: its stretch of the wall pairs' output (stretches of whole blocks
    /// of [`WALL_BLOCK`] pairs).
    pub pieces: Vec<WallPiece>,
    /// The force on each wall: per block of [`WALL_BLOCK`] wall pairs the sum of its pairs'
    /// forces in pair order, then these in block order (so for any number of threads).
    pub on_wall: Vec<[f64; 3]>,
}

/// Wall pairs per block: the energy increments and the wall forces of the wall contacts are
/// summed per block, then in block order.
pub const WALL_BLOCK: usize = 256;

/// One task's stretch of the wall pairs' output ([`WallOut`]).
#[derive(Clone, Debug, Default)]
pub struct WallPiece {
    /// The evaluated wall pairs' forces, in pair order.
    pub forces: Vec<WallForce>,
    /// Indices into `forces` grouped by the update's chunk of their particle (in pair order
    /// within a chunk, so each particle gets its wall forces in pair order): chunk `c` has
    /// `order[start[c]..start[c + 1]]`.
    pub order: Vec<u32>,
    pub start: Vec<u32>,
    /// Per block of wall pairs, the force on each wall (`walls` entries per block).
    pub sums: Vec<[f64; 3]>,
}

impl WallPiece {
    /// The entries of chunk `c`.
    pub fn of_chunk(&self, c: usize) -> impl Iterator<Item = &WallForce> + '_ {
        let r = match (self.start.get(c), self.start.get(c + 1)) {
            (Some(&a), Some(&b)) => a as usize..b as usize,
            _ => 0..0,
        };
        self.order[r].iter().map(|&e| &self.forces[e as usize])
    }
}

impl WallOut {
    /// The entries of chunk `c` in `pieces` (all of a step's, or those of one task whose
    /// chunk has no entries in the others), in pair order.
    pub fn of_chunk(pieces: &[WallPiece], c: usize) -> impl Iterator<Item = &WallForce> + '_ {
        pieces.iter().flat_map(move |p| p.of_chunk(c))
    }

    /// `on_wall` from the pieces' block sums, for `walls` walls.
    pub fn sum_walls(&mut self, walls: usize) {
        self.on_wall.clear();
        self.on_wall.resize(walls, [0.0; 3]);
        if walls == 0 {
            return;
        }
        for p in &self.pieces {
            for block in p.sums.chunks(walls) {
                for (w, b) in self.on_wall.iter_mut().zip(block) {
                    for (wk, bk) in w.iter_mut().zip(b) {
                        *wk += bk;
                    }
                }
            }
        }
    }
}
