//! Candidate pair keys from the search: parted by lower id and sorted by counting sort.

use super::*;

/// Candidate keys as the search emits them, parted by the lower id: part `t` holds the keys
/// with `bounds[t] <= ida < bounds[t + 1]`, in no particular order, in one or more lists (the
/// search's blocks, not copied into one). The parts are sorted on their own, in parallel,
/// each reading only its own keys, and laid end to end ([`KeyParts::into_sorted`]).
#[derive(Clone, Debug, Default)]
pub struct KeyParts {
    pub bounds: Vec<u32>,
    pub parts: Vec<Vec<Vec<PairKey>>>,
}

impl KeyParts {
    /// The bounds of `parts` ranges of equal width covering ids `0..=max_id`.
    pub fn bounds(max_id: u32, parts: usize) -> Vec<u32> {
        let parts = parts.clamp(1, 64) as u64;
        let end = max_id as u64 + 1;
        (0..=parts)
            .map(|t| (t * end / parts).min(u32::MAX as u64) as u32)
            .collect()
    }

    /// The part of a key's lower id (`bounds` as from [`KeyParts::bounds`]).
    #[inline]
    pub fn part_of(bounds: &[u32], ida: u32) -> usize {
        bounds[1..bounds.len() - 1]
            .iter()
            .filter(|&&b| ida >= b)
            .count()
    }

    /// Keys in one list, parted for `parts` threads.
    pub fn split(keys: Vec<PairKey>, parts: usize) -> KeyParts {
        let max_id = keys.iter().map(|k| k.ida).max().unwrap_or(0);
        let bounds = KeyParts::bounds(max_id, parts);
        if bounds.len() == 2 {
            return KeyParts {
                bounds,
                parts: vec![vec![keys]],
            };
        }
        let mut out = vec![Vec::new(); bounds.len() - 1];
        for k in keys {
            out[KeyParts::part_of(&bounds, k.ida)].push(k);
        }
        KeyParts {
            bounds,
            parts: out.into_iter().map(|p| vec![p]).collect(),
        }
    }

    /// All keys, part after part, unsorted.
    pub fn into_flat(self) -> Vec<PairKey> {
        self.parts.into_iter().flatten().flatten().collect()
    }

    /// All keys sorted by their ids (ida, idb). The id pairs are unique, so any correct sort
    /// gives this one order, whatever the parts (and so the number of threads).
    ///
    /// Each part is sorted into its place in the output, in parallel: where its ids are dense
    /// (a range at most a few times its number of keys, as usual) by one counting sort by the
    /// lower id `ida`, which puts each particle's forward partners together, then each such
    /// bucket (a handful of keys) by `idb` in place; sparse ids take the radix sort.
    pub fn into_sorted(self) -> Vec<PairKey> {
        let KeyParts { bounds, parts } = self;
        let len = |p: &Vec<Vec<PairKey>>| p.iter().map(Vec::len).sum::<usize>();
        let n: usize = parts.iter().map(len).sum();
        let mut out = Vec::with_capacity(n);
        out.par_extend(rayon::iter::repeat_n(PairKey::default(), n));
        let mut pieces: Vec<&mut [PairKey]> = Vec::with_capacity(parts.len());
        let mut rest: &mut [PairKey] = &mut out;
        for p in &parts {
            let (piece, tail) = rest.split_at_mut(len(p));
            pieces.push(piece);
            rest = tail;
        }
        pieces
            .into_par_iter()
            .zip(parts)
            .enumerate()
            .with_max_len(1)
            .for_each(|(t, (piece, lists))| {
                if !counting_sort_keys(&lists, bounds[t], piece) {
                    let mut keys: Vec<PairKey> = lists.into_iter().flatten().collect();
                    radix_sort_keys(&mut keys);
                    piece.copy_from_slice(&keys);
                }
            });
        out
    }
}

/// The counting sort of [`KeyParts::into_sorted`]: the keys of `lists` (all with
/// `ida >= lo`) sorted into `out` (of their number); false, with `out` untouched, if their
/// ids are too sparse for it (more than 4 n + 4096 buckets).
pub(super) fn counting_sort_keys(lists: &[Vec<PairKey>], lo: u32, out: &mut [PairKey]) -> bool {
    let n = out.len();
    let keys = || lists.iter().flatten();
    let Some(max_ida) = keys().map(|k| k.ida).max() else {
        return true;
    };
    let nb = (max_ida - lo) as usize + 1;
    if nb > 4 * n + 4096 {
        return false;
    }
    let mut start = vec![0u32; nb + 1];
    for k in keys() {
        start[(k.ida - lo) as usize + 1] += 1;
    }
    for b in 0..nb {
        start[b + 1] += start[b];
    }
    let mut fill = start.clone();
    for k in keys() {
        let d = (k.ida - lo) as usize;
        out[fill[d] as usize] = *k;
        fill[d] += 1;
    }
    // Each bucket by idb (insertion sort: buckets hold a few keys).
    for w in start.windows(2) {
        let bucket = &mut out[w[0] as usize..w[1] as usize];
        for x in 1..bucket.len() {
            let k = bucket[x];
            let mut y = x;
            while y > 0 && bucket[y - 1].idb > k.idb {
                bucket[y] = bucket[y - 1];
                y -= 1;
            }
            bucket[y] = k;
        }
    }
    true
}

impl From<Vec<PairKey>> for KeyParts {
    /// Keys in one part.
    fn from(keys: Vec<PairKey>) -> KeyParts {
        KeyParts {
            bounds: vec![0, u32::MAX],
            parts: vec![vec![keys]],
        }
    }
}

/// Sorts candidate keys by their ids (ida, idb): a least-significant-digit radix sort on
/// the id pair packed into one integer (11-bit digits, as many passes as the ids need), for
/// sparse ids.
pub(super) fn radix_sort_keys(keys: &mut Vec<PairKey>) {
    pub(super) const D: u32 = 11;
    let max_id = keys.iter().map(|k| k.idb).max().unwrap_or(0);
    let bits = 32 - max_id.leading_zeros();
    let packed = |k: &PairKey| ((k.ida as u64) << bits) | k.idb as u64;
    let mut buf = keys.clone();
    let mut shift = 0;
    while shift < 2 * bits {
        let digit = |k: &PairKey| ((packed(k) >> shift) & ((1 << D) - 1)) as usize;
        let mut start = [0usize; 1 << D];
        for k in keys.iter() {
            start[digit(k)] += 1;
        }
        let mut sum = 0;
        for c in start.iter_mut() {
            (*c, sum) = (sum, sum + *c);
        }
        for k in keys.iter() {
            let d = digit(k);
            buf[start[d]] = *k;
            start[d] += 1;
        }
        std::mem::swap(keys, &mut buf);
        shift += D;
    }
}
