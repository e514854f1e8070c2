//! The overlap index that generation keeps between `CReate` commands (`sim::generate` builds
//! and searches it; `Derived::create_index`).

use std::collections::HashMap;
use std::hash::{BuildHasherDefault, Hasher};

use super::Vec3;

/// A multiplicative hash for the index's integer cell keys (the standard SipHash took over
/// half of `RGEnerate`'s time; the keys are not chosen by an adversary).
#[derive(Clone, Copy, Debug, Default)]
pub(in crate::sim) struct CellHasher(u64);

impl Hasher for CellHasher {
    fn finish(&self) -> u64 {
        self.0
    }
    fn write(&mut self, bytes: &[u8]) {
        for &b in bytes {
            self.write_u64(b as u64);
        }
    }
    fn write_u64(&mut self, x: u64) {
        self.0 = (self.0.rotate_left(5) ^ x).wrapping_mul(0x517c_c1b7_2722_0a95);
    }
    fn write_i64(&mut self, x: i64) {
        self.write_u64(x as u64);
    }
}

/// Spatial hash of particles (the scene's, then the ones being generated) for the overlap
/// check. Entry k is particle k of the scene for k < the scene's count at creation.
#[derive(Clone, Debug)]
pub struct OverlapIndex {
    pub(in crate::sim) h: f64,
    pub(in crate::sim) cells: HashMap<(i64, i64, i64), Vec<usize>, BuildHasherDefault<CellHasher>>,
    pub(in crate::sim) rmax: f64,
    pub(in crate::sim) pos: Vec<Vec3>,
    pub(in crate::sim) radius: Vec<f64>,
    /// Bounding box of the indexed centres (the periodic images that cannot reach it are
    /// not searched).
    pub(in crate::sim) lo: Vec3,
    pub(in crate::sim) hi: Vec3,
}

/// The overlap index of a run of `CReate` commands, for the scene of `n` particles it was
/// last brought up to date with (kept in `Derived::create_index`; any other command drops
/// it, so it never sees particles moved, removed or changed).
#[derive(Clone, Debug)]
pub struct CreateIndex {
    pub n: usize,
    pub index: OverlapIndex,
    /// The scene's kinetic energy (`sim::energy::kinetic`) with these `n` particles, for
    /// the ledger's booking of the next CReate (a sum over all particles per command made N
    /// CReate lines O(N²) as well).
    pub kinetic: Option<f64>,
}
