//! The pair loop's reach tests: which candidate pairs of a sub-batch are evaluated —
//! within reach, or live (a solid contact or a bridge to remember).
//!
//! The tests of a sub-batch first make a bit mask (bit k: candidate k is evaluated), then
//! the mask is turned into the list of evaluated candidates. Writing each candidate's index
//! at the position counted so far (the earlier form) made every store's address wait for
//! the comparison before it, and the loop ran at ~13 cycles a candidate with its data in L1;
//! with the mask the tests are independent of each other. Without a periodic axis and with
//! AVX2 four candidates share the arithmetic: a candidate's two positions are one masked
//! vector load each (x, y, z; the fourth lane is not read), the separations are transposed
//! into x, y, z of four pairs, and the squared distances and the comparisons are vector
//! operations — the same operations in the same order on each lane as the scalar test, so
//! the same pairs are evaluated. In the falling S1 50k bed the scalar tests were a quarter
//! of the one-thread run (a second pass over the same, cached candidates took 1.27 × the
//! time; doc/performance.md).
//!
//! Only the evaluated pairs' separations are then worked out, by [`separation`] (the
//! pair loop), which is the separation the tests used, bit for bit.

#[cfg(target_arch = "x86_64")]
use std::arch::x86_64::*;

use super::super::cell::nearest_image;
use super::super::contacts::HotPair;
use super::super::lanes::SUB;
use super::super::scene::Vec3;
use super::{EXT_GROUP, PairCtx};

// One bit a candidate of a sub-batch.
const _: () = assert!(SUB <= 32);

/// The separation A → B of a candidate pair (the nearest image along periodic axes).
#[inline(always)]
pub(super) fn separation(h: &HotPair, c: &PairCtx) -> Vec3 {
    let d = c.pos[h.j as usize] - c.pos[h.i as usize];
    if c.periodic == [false; 3] {
        d
    } else {
        nearest_image(d, c.size, c.periodic, c.shift)
    }
}

/// The reach tests of one sub-batch of candidates `hots` (at most [`SUB`], the first at
/// `start` in its block): the evaluated pairs' indices in pair order into `idx`; returns
/// how many. `vector`: the four-lane tests may be used (the processor has AVX2,
/// `cycle::vector_reach`). A pair is evaluated when it is live or
/// !(d² > reach²) (so also when d² is NaN, whose force then shows the blow-up). With
/// adhesion or liquid the reach includes the round-off allowance of bridge formation and of
/// JKR snap-in (gap ≤ 1e-6 R, interact.rs), so pairs that touch exactly (lattices) are
/// evaluated, and the gap across which LIGGGHTS' JKR attracts (`PairCtx::reach`). Without them the reach is the touching distance: a pair with a gap gets no
/// force from the dry non-adhesive laws (Hertz needs α > 0), and a contact that just opened
/// is still evaluated once, being live. `UNI`: every radius is the scene's common one.
#[inline(never)]
pub(super) fn evaluated<const ADH: bool, const LIQ: bool, const UNI: bool>(
    hots: &[HotPair],
    start: usize,
    c: &PairCtx,
    vector: bool,
    idx: &mut [u32; SUB],
) -> usize {
    let hots = &hots[..hots.len().min(SUB)];
    let ur = c.uni.map_or(0.0, |u| u.r);
    let allow = if ADH || LIQ { c.reach } else { 1.0 };
    let radius = (!UNI).then_some(c.radius);
    let scalar = || {
        if c.periodic == [false; 3] {
            mask_scalar::<false>(hots, c, radius, (ur, allow))
        } else {
            mask_scalar::<true>(hots, c, radius, (ur, allow))
        }
    };
    #[cfg(target_arch = "x86_64")]
    let mask = if vector {
        // SAFETY: `vector` says the processor has AVX2.
        unsafe { four_lanes::<UNI>(hots, c, (ur, allow)) }
    } else {
        scalar()
    };
    #[cfg(not(target_arch = "x86_64"))]
    let mask = {
        let _ = vector;
        scalar()
    };
    let (mask, zone) = mask;
    // Within the dashpot's margin only the pairs that may approach within half a step (the
    // four lanes have tested their own candidates of the zone unless the scene has a
    // periodic axis or a deforming cell).
    let mask = if zone != 0 {
        mask | approaching(hots, c, zone, (ur, allow), radius)
    } else {
        mask
    };
    compact(mask, start, idx)
}

/// The positions of the bits of each 4-bit value, in order (the rest: unused).
const NIBBLE_BITS: [[u32; 4]; 16] = {
    let mut t = [[0u32; 4]; 16];
    let mut v = 0;
    while v < 16 {
        let (mut n, mut b) = (0, 0);
        while b < 4 {
            if (v >> b) & 1 == 1 {
                t[v][n] = b as u32;
                n += 1;
            }
            b += 1;
        }
        v += 1;
    }
    t
};

/// The indices `start + k` of the set bits k of `mask` into `idx`, in order; returns how
/// many. Four bits at a time from a table, without a branch: each group writes four
/// entries at the count so far (at most 4 × its number, so inside `idx`), of which the
/// later groups overwrite the ones past its count (a loop over the 32 bits was ~6
/// instructions a candidate).
#[inline(always)]
fn compact(mask: u32, start: usize, idx: &mut [u32; SUB]) -> usize {
    let mut m = 0;
    for g in 0..SUB / 4 {
        let nib = ((mask >> (4 * g)) & 0xf) as usize;
        let base = (start + 4 * g) as u32;
        let row = &NIBBLE_BITS[nib];
        let out = &mut idx[m..][..4];
        for t in 0..4 {
            out[t] = base + row[t];
        }
        // The number of bits of `nib` (one hexadecimal digit per value).
        m += ((0x4332_3221_3221_2110u64 >> (4 * nib)) & 0xf) as usize;
    }
    m
}

/// The largest margin of a table of margins (`PairCtx::ext_max`; 0 for none).
pub(super) fn largest(ext: &[f64]) -> f64 {
    ext.iter().fold(0.0f64, |m, &e| if e > m { e } else { m })
}

/// Whether a candidate beyond the reach `r` (times `allow`) lies within its own zone
/// `r + e` (`e`: the sum of its particles' margins `PairCtx::ext`, as [`reach2`] tests it)
/// and may approach within half a step (`half` = Δt/2): the kernel treats a pair as
/// approaching when `v_n < 0` and `gap < −v_n Δt/2` (`interact`). With `d` the separation,
/// `R` the sum of the radii, `e` the margins and `dv` the relative velocity of the centres,
/// `gap |d| = d² − R |d|`, and for `R ≤ |d| ≤ R + e`, `gap |d| ≥ R (d² − R²)/(2R + e)`; so a
/// pair with `R (d² − R²) ≥ −(dv·d) Δt/2 (2R + e)` (plus a round-off allowance: the
/// kernel's `v_n` has the spins' part too, zero up to round-off) cannot be approaching and
/// is left out. No square root; `dv` is read only for a candidate in its own zone.
#[inline(always)]
fn may_approach(d: Vec3, dv: impl FnOnce() -> Vec3, r: f64, e: f64, half: f64) -> bool {
    let z = r + e;
    if !(d.norm_squared() <= z * z) {
        return false;
    }
    let dv = dv();
    let lhs = r * (d.norm_squared() - r * r);
    let rhs = -dv.dot(&d) * half * (2.0 * r + e);
    lhs < rhs + 1e-9 * r * r * r
}

/// Of the candidates in the dashpot's margin (bits of `zone`: beyond the reach, and within
/// it plus the largest margin of all, `PairCtx::ext_max`, or within it plus the pair's
/// particles' margins), the ones that may approach within half a step
/// ([`may_approach`]), as bits. The rare candidates in the margin only.
#[inline(never)]
fn approaching(
    hots: &[HotPair],
    c: &PairCtx,
    zone: u32,
    (ur, allow): (f64, f64),
    radius: Option<&[f64]>,
) -> u32 {
    let Some(ext) = c.ext else { return 0 };
    let half = 0.5 * c.laws.dt;
    let mut keep = 0u32;
    let mut bits = zone;
    while bits != 0 {
        let k = bits.trailing_zeros() as usize;
        bits &= bits - 1;
        let h = &hots[k];
        let (i, j) = (h.i as usize, h.j as usize);
        let d = separation(h, c);
        let r = match radius {
            Some(r) => r[i] + r[j],
            None => ur + ur,
        } * allow;
        let e = ext[i / EXT_GROUP] + ext[j / EXT_GROUP];
        let dv = || match c.cell {
            Some(cell) => c.vel[j] - c.vel[i] + cell.field(&d),
            None => c.vel[j] - c.vel[i],
        };
        if may_approach(d, dv, r, e, half) {
            keep |= 1 << k;
        }
    }
    keep
}

/// [`may_approach`] for the candidates of a group of four in the zone (bits of `zone`),
/// in the four-lane test of a scene without a periodic axis or a deforming cell: the
/// separation `pos[j] − pos[i]` (as [`separation`] gives it), `reach` each lane's.
#[inline(always)]
fn approaching_lanes(
    four: &[HotPair],
    zone: u32,
    c: &PairCtx,
    ext: &[f64],
    reach: [f64; 4],
) -> u32 {
    let half = 0.5 * c.laws.dt;
    let mut keep = 0u32;
    let mut bits = zone;
    while bits != 0 {
        let l = bits.trailing_zeros() as usize;
        bits &= bits - 1;
        let (i, j) = (four[l].i as usize, four[l].j as usize);
        let d = c.pos[j] - c.pos[i];
        let e = ext[i / EXT_GROUP] + ext[j / EXT_GROUP];
        if may_approach(d, || c.vel[j] - c.vel[i], reach[l], e, half) {
            keep |= 1 << l;
        }
    }
    keep
}

/// The reach (R_A + R_B, times `allow`) of a pair and that plus the particles' margins for
/// the dashpot (`ext`; the same without), squared.
#[inline(always)]
fn reach2(
    h: &HotPair,
    radius: Option<&[f64]>,
    ext: Option<&[f64]>,
    (ur, allow): (f64, f64),
) -> (f64, f64) {
    let (i, j) = (h.i as usize, h.j as usize);
    let reach = match radius {
        Some(r) => (r[i] + r[j]) * allow,
        None => (ur + ur) * allow,
    };
    let zone = match ext {
        Some(e) => reach + (e[i / EXT_GROUP] + e[j / EXT_GROUP]),
        None => reach,
    };
    (reach * reach, zone * zone)
}

/// The periodic axes of the four-lane reach test.
#[cfg(target_arch = "x86_64")]
struct Images {
    periodic: [bool; 3],
    size: [f64; 3],
    shift: f64,
}

#[cfg(target_arch = "x86_64")]
impl Images {
    fn of(c: &PairCtx) -> Images {
        Images {
            periodic: c.periodic,
            size: c.size,
            shift: c.shift,
        }
    }

    /// The nearest image of four separations (y first when the cell is sheared).
    #[target_feature(enable = "avx2")]
    fn nearest(&self, x: __m256d, y: __m256d, z: __m256d) -> (__m256d, __m256d, __m256d) {
        const NEAREST: i32 = _MM_FROUND_TO_NEAREST_INT | _MM_FROUND_NO_EXC;
        let reduce = |v: __m256d, l: f64| {
            let n = _mm256_round_pd::<NEAREST>(_mm256_div_pd(v, _mm256_set1_pd(l)));
            (_mm256_sub_pd(v, _mm256_mul_pd(_mm256_set1_pd(l), n)), n)
        };
        let (mut x, mut y, mut z) = (x, y, z);
        let sheared = self.shift != 0.0 && self.periodic[1];
        if sheared {
            let (ry, n) = reduce(y, self.size[1]);
            y = ry;
            x = _mm256_sub_pd(x, _mm256_mul_pd(_mm256_set1_pd(self.shift), n));
        }
        if self.periodic[0] {
            x = reduce(x, self.size[0]).0;
        }
        if self.periodic[1] && !sheared {
            y = reduce(y, self.size[1]).0;
        }
        if self.periodic[2] {
            z = reduce(z, self.size[2]).0;
        }
        (x, y, z)
    }
}

/// Bit k: candidate k is evaluated (`PER`: the scene has a periodic axis).
#[inline(always)]
fn mask_scalar<const PER: bool>(
    hots: &[HotPair],
    c: &PairCtx,
    radius: Option<&[f64]>,
    ur_allow: (f64, f64),
) -> (u32, u32) {
    let mut mask = 0u32;
    let mut zone = 0u32;
    for (k, h) in hots.iter().enumerate() {
        // (Nothing is stored in the hot pair: its line stays clean and is not written
        // back to memory.)
        let d = c.pos[h.j as usize] - c.pos[h.i as usize];
        let d = if PER {
            nearest_image(d, c.size, c.periodic, c.shift)
        } else {
            d
        };
        let d2 = d.norm_squared();
        let (r2, z2) = reach2(h, radius, c.ext, ur_allow);
        let near = h.live | !(d2 > r2);
        mask |= (near as u32) << k;
        zone |= ((!near & (d2 <= z2)) as u32) << k;
    }
    (mask, zone)
}

/// The four-lane test without the dashpot's margin.
const NO_ZONE: u8 = 0;
/// The four-lane test returns its candidates in the dashpot's zone as bits, for
/// [`approaching`] (a periodic axis or a deforming cell).
const ZONE_BITS: u8 = 1;
/// The four-lane test keeps its candidates of the zone that may approach
/// ([`approaching_lanes`]).
const ZONE_HERE: u8 = 2;

/// [`mask_avx2`] made for the scene (radii, periodic axes, margins), so that its loop
/// tests none of them per group.
///
/// # Safety
/// The processor has AVX2.
#[cfg(target_arch = "x86_64")]
#[inline(always)]
unsafe fn four_lanes<const UNI: bool>(
    hots: &[HotPair],
    c: &PairCtx,
    ur_allow: (f64, f64),
) -> (u32, u32) {
    let per = c.periodic != [false; 3];
    let zone = match c.ext {
        None => NO_ZONE,
        Some(_) if per || c.cell.is_some() => ZONE_BITS,
        Some(_) => ZONE_HERE,
    };
    // SAFETY: the caller's contract (AVX2).
    unsafe {
        match (per, zone) {
            (false, NO_ZONE) => mask_avx2::<UNI, false, NO_ZONE>(hots, c, ur_allow),
            (false, ZONE_BITS) => mask_avx2::<UNI, false, ZONE_BITS>(hots, c, ur_allow),
            (false, _) => mask_avx2::<UNI, false, ZONE_HERE>(hots, c, ur_allow),
            (true, NO_ZONE) => mask_avx2::<UNI, true, NO_ZONE>(hots, c, ur_allow),
            (true, _) => mask_avx2::<UNI, true, ZONE_BITS>(hots, c, ur_allow),
        }
    }
}

/// [`mask_scalar`] four candidates at a time (`UNI`: every radius the common one; `PER`:
/// the scene has a periodic axis; `ZONE`: what is done with the dashpot's zone), and with
/// `ZONE_HERE` the candidates of the zone that may approach within half a step.
///
/// # Safety
/// The processor has AVX2.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
unsafe fn mask_avx2<const UNI: bool, const PER: bool, const ZONE: u8>(
    hots: &[HotPair],
    c: &PairCtx,
    ur_allow: (f64, f64),
) -> (u32, u32) {
    let radius = (!UNI).then_some(c.radius);
    let (base, len) = c.pos.parts();
    let base = base as *const f64;
    // x, y, z of a particle; the fourth lane is not read (so no neighbour's element is
    // touched, which another task may be writing in the one-region step).
    let xyz = _mm256_set_epi64x(0, -1, -1, -1);
    let (ur, allow) = ur_allow;
    let uni_reach = (ur + ur) * allow;
    let uni_r2 = _mm256_set1_pd(uni_reach * uni_reach);
    // The dashpot's zone with the largest margin of all, for every pair: it holds every
    // pair's own zone (`reach + (e_i + e_j)`, rounding is monotonic), which
    // `may_approach` then tests for the few candidates in it; so no margin is read per
    // candidate here.
    let ext2 = c.ext_max + c.ext_max;
    let uni_zone = uni_reach + ext2;
    let uni_z2 = _mm256_set1_pd(uni_zone * uni_zone);
    let full = hots.len() / 4 * 4;
    let mut mask = 0u32;
    let mut zones = 0u32;
    let per = Images::of(c);
    // (`ZONE_HERE` is chosen only with margins.)
    let ext = c.ext.unwrap_or_default();
    for (g, four) in hots[..full].chunks_exact(4).enumerate() {
        let mut d = [_mm256_setzero_pd(); 4];
        let mut live = 0u32;
        let mut reach = [0.0f64; 4];
        for (l, h) in four.iter().enumerate() {
            let (i, j) = (h.i as usize, h.j as usize);
            assert!(i < len && j < len, "pair ({i}, {j}) of {len} particles");
            // SAFETY: i, j < len (just checked): the three elements loaded are particle
            // i's (j's) x, y, z, inside the array the view reads (its contract: not
            // written while read).
            let (a, b) = unsafe {
                (
                    _mm256_maskload_pd(base.add(3 * i), xyz),
                    _mm256_maskload_pd(base.add(3 * j), xyz),
                )
            };
            d[l] = _mm256_sub_pd(b, a);
            live |= (h.live as u32) << l;
            if !UNI {
                reach[l] = (c.radius[i] + c.radius[j]) * allow;
            }
        }
        let (r2, z2) = if !UNI {
            let r = _mm256_set_pd(reach[3], reach[2], reach[1], reach[0]);
            let z = _mm256_add_pd(r, _mm256_set1_pd(ext2));
            (_mm256_mul_pd(r, r), _mm256_mul_pd(z, z))
        } else {
            (uni_r2, uni_z2)
        };
        // Transpose [x y z 0] × 4 into x, y, z of the four pairs.
        let t0 = _mm256_unpacklo_pd(d[0], d[1]); // x0 x1 z0 z1
        let t1 = _mm256_unpackhi_pd(d[0], d[1]); // y0 y1 0 0
        let t2 = _mm256_unpacklo_pd(d[2], d[3]); // x2 x3 z2 z3
        let t3 = _mm256_unpackhi_pd(d[2], d[3]); // y2 y3 0 0
        let x = _mm256_permute2f128_pd::<0x20>(t0, t2);
        let y = _mm256_permute2f128_pd::<0x20>(t1, t3);
        let z = _mm256_permute2f128_pd::<0x31>(t0, t2);
        // The nearest image along the periodic axes (`cell::nearest_image`): the same
        // distance to the bit, but for a separation of exactly half the cell, where the two
        // images are equally far (rounding half to even here, away from zero there: the
        // sign of the component differs, its square does not).
        let (x, y, z) = if PER { per.nearest(x, y, z) } else { (x, y, z) };
        // (x² + y²) + z², as nalgebra's norm_squared; no fused multiply-add.
        let d2 = _mm256_add_pd(
            _mm256_add_pd(_mm256_mul_pd(x, x), _mm256_mul_pd(y, y)),
            _mm256_mul_pd(z, z),
        );
        // !(d² > reach²): true for NaN too, as in the scalar test.
        let near = _mm256_movemask_pd(_mm256_cmp_pd::<_CMP_NGT_UQ>(d2, r2)) as u32 | live;
        mask |= near << (4 * g);
        if ZONE != NO_ZONE {
            let inside = _mm256_movemask_pd(_mm256_cmp_pd::<_CMP_LE_OQ>(d2, z2)) as u32;
            let zone = inside & !near & 0xf;
            if ZONE == ZONE_BITS {
                zones |= zone << (4 * g);
            } else if zone != 0 {
                let reach = if UNI { [uni_reach; 4] } else { reach };
                mask |= approaching_lanes(four, zone, c, ext, reach) << (4 * g);
            }
        }
    }
    let (rest, rest_zone) = if PER {
        mask_scalar::<true>(&hots[full..], c, radius, ur_allow)
    } else {
        mask_scalar::<false>(&hots[full..], c, radius, ur_allow)
    };
    (
        mask | rest.checked_shl(full as u32).unwrap_or(0),
        zones | rest_zone.checked_shl(full as u32).unwrap_or(0),
    )
}

#[cfg(test)]
mod tests {
    use super::super::fused::View;
    use super::super::{PairCtx, UniPair};
    use super::*;
    use crate::sim::interact::Laws;
    use crate::sim::model::TangentialChoice;
    use crate::sim::rng::Rng;
    use crate::sim::scene::{Material, Scene};

    /// The four-lane reach test and the scalar one pick the same candidates, with and
    /// without periodic axes, in a sheared cell, with and without the dashpot's margins
    /// (the four lanes take the largest margin for every pair, the scalar test the pair's
    /// own), and for every length of the last group (the lanes' remainder goes through the
    /// scalar test).
    #[test]
    fn the_four_lane_test_is_the_scalar_test() {
        if !std::is_x86_feature_detected!("avx2") {
            return;
        }
        let mut sc = Scene::new([1e-3; 3], 10, 200, 0);
        sc.materials[0] = Material {
            density: 2600.0,
            young: 1e8,
            poisson: 0.3,
            ..Default::default()
        };
        let mut r = Rng::new(11);
        for k in 0..200 {
            let x = Vec3::new(r.uniform(), r.uniform(), r.uniform()) * 1e-3;
            let rad = 6e-5 * (1.0 + 0.3 * r.uniform());
            let v = Vec3::new(r.normal(), r.normal(), r.normal()) * 500.0;
            sc.particles
                .push(k + 1, x, v, Vec3::zeros(), rad, 1e-9, 1, 1, 0);
        }
        // Margins of the four groups of 64 particles, unlike each other.
        let margins = [2e-5, 9e-5, 1.3e-4, 4e-5];
        let model = crate::sim::params::build(&sc).unwrap();
        let laws = Laws::dry(1e-7, TangentialChoice::NoSlip);
        // Every pair, so that many are near (and many across the sides).
        let all: Vec<HotPair> = (0..200u32)
            .flat_map(|i| {
                (i + 1..200).map(move |j| HotPair {
                    i,
                    j,
                    ..Default::default()
                })
            })
            .collect();
        let p = &sc.particles;
        let mut counts = [0usize; 2];
        for ((periodic, shift), ext) in [
            ([false; 3], 0.0),
            ([true; 3], 0.0),
            ([true, true, false], 0.0),
            ([true; 3], 3.7e-4),
        ]
        .into_iter()
        .flat_map(|p| [(p, None), (p, Some(&margins[..]))])
        {
            let c = PairCtx {
                pos: View::of(&p.pos),
                vel: View::of(&p.vel),
                spin: View::of(&p.spin),
                radius: &p.radius,
                mass: &p.mass,
                material: &p.material,
                model: &model,
                laws: &laws,
                size: sc.size,
                periodic,
                shift,
                cell: None,
                stress: false,
                uni: UniPair::of(&model),
                ext,
                ext_max: ext.map_or(0.0, largest),
                reach: model.reach,
            };
            let mut near = 0;
            for len in 1..=SUB {
                for start in (0..all.len() - SUB).step_by(997) {
                    let hots = &all[start..start + len];
                    let (mut a, mut b) = ([0u32; SUB], [0u32; SUB]);
                    let na = evaluated::<false, false, false>(hots, start, &c, true, &mut a);
                    let nb = evaluated::<false, false, false>(hots, start, &c, false, &mut b);
                    assert_eq!(a[..na], b[..nb], "{periodic:?} {shift} len {len}");
                    near += na;
                }
            }
            assert!(near > 0);
            counts[ext.is_some() as usize] += near;
        }
        // The margins bring pairs in (approaching within half a step).
        assert!(counts[1] > counts[0], "{counts:?}");
    }

    /// The table-driven compaction of a mask is the loop over its bits.
    #[test]
    fn compact_lists_the_set_bits_in_order() {
        let mut r = Rng::new(3);
        for t in 0..2000 {
            let mask = match t {
                0 => 0,
                1 => u32::MAX,
                _ => (r.uniform() * 4294967296.0) as u32 & (r.uniform() * 4294967296.0) as u32,
            };
            let mut idx = [0u32; SUB];
            let m = compact(mask, 77, &mut idx);
            let want: Vec<u32> = (0..32)
                .filter(|k| mask >> k & 1 == 1)
                .map(|k| 77 + k)
                .collect();
            assert_eq!(idx[..m], want[..]);
        }
    }
}
