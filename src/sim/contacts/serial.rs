//! The contact store in a checkpoint: pairs with their states inline, in pair order (the
//! per-step buffers are not saved).

use super::*;

/// The checkpoint layout of the store (field order of format versions 1 and 2).
#[derive(Serialize)]
pub(super) struct StoreOut<'a> {
    pub(super) pairs: PairsOut<'a>,
    pub(super) wall_pairs: &'a Vec<WallPair>,
    pub(super) stale: bool,
    pub(super) remap: bool,
    pub(super) tol: f64,
    pub(super) rebuilds: u64,
}

pub(super) struct PairsOut<'a>(&'a ContactStore);

#[derive(Serialize)]
pub(super) struct PairOut<'a> {
    pub(super) i: u32,
    pub(super) j: u32,
    pub(super) ida: u32,
    pub(super) idb: u32,
    pub(super) s: std::borrow::Cow<'a, ContactState>,
}

impl Serialize for PairsOut<'_> {
    fn serialize<S: serde::Serializer>(&self, ser: S) -> Result<S::Ok, S::Error> {
        ser.collect_seq((0..self.0.pairs.len()).map(|k| {
            let v = self.0.pair(k);
            PairOut {
                i: v.i,
                j: v.j,
                ida: v.ida,
                idb: v.idb,
                // (An MDR row back in `ext.mdr`, where format 9 put it.)
                s: self.0.saved_state(k),
            }
        }))
    }
}

impl Serialize for ContactStore {
    fn serialize<S: serde::Serializer>(&self, ser: S) -> Result<S::Ok, S::Error> {
        StoreOut {
            pairs: PairsOut(self),
            wall_pairs: &self.wall_pairs,
            stale: self.stale,
            remap: self.remap,
            tol: self.tol,
            rebuilds: self.rebuilds,
        }
        .serialize(ser)
    }
}

#[derive(Deserialize)]
pub(super) struct StoreIn {
    pub(super) pairs: PairsIn,
    pub(super) wall_pairs: Vec<WallPair>,
    pub(super) stale: bool,
    pub(super) remap: bool,
    pub(super) tol: f64,
    pub(super) rebuilds: u64,
}

impl<'de> Deserialize<'de> for ContactStore {
    fn deserialize<D: serde::Deserializer<'de>>(de: D) -> Result<Self, D::Error> {
        let s = StoreIn::deserialize(de)?;
        let mut c = s.pairs.0;
        c.wall_pairs = s.wall_pairs;
        c.stale = s.stale;
        c.remap = s.remap;
        c.tol = s.tol;
        c.rebuilds = s.rebuilds;
        Ok(c)
    }
}

/// The pairs of a checkpoint, put into a store's blocks one by one as they are decoded (as
/// [`ContactStore::set_pairs`] would put them), so that a restart never holds them all with
/// inline states: 128 bytes a pair, 20 MB for the settled S1 bed of 50,000 spheres (159,962
/// candidate pairs, three quarters of them without a state).
pub(super) struct PairsIn(ContactStore);

impl<'de> Deserialize<'de> for PairsIn {
    fn deserialize<D: serde::Deserializer<'de>>(de: D) -> Result<Self, D::Error> {
        struct Visit;
        impl<'de> serde::de::Visitor<'de> for Visit {
            type Value = PairsIn;
            fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
                f.write_str("a sequence of pairs with their states")
            }
            fn visit_seq<A: serde::de::SeqAccess<'de>>(
                self,
                mut seq: A,
            ) -> Result<PairsIn, A::Error> {
                let mut c = ContactStore::default();
                // At most what 1 MB holds up front (the count comes from the file).
                let cap = seq
                    .size_hint()
                    .unwrap_or(0)
                    .min((1 << 20) / size_of::<Pair>());
                c.pairs.reserve(cap);
                while let Some(p) = seq.next_element::<PairWithState>()? {
                    c.push(p);
                }
                c.trim_last_block();
                c.pairs.shrink_to_fit();
                Ok(PairsIn(c))
            }
        }
        de.deserialize_seq(Visit)
    }
}
