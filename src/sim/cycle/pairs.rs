//! The pair loop over blocks of contact states: geometry and kinematics of each candidate
//! pair, the uniform-particle specialisation, SIMD lanes for steady batches, prefetching.

use super::*;

/// Splits the pairs into about `n` ranges of whole blocks of similar cost (pairs evaluated in
/// the last step count 8, the others 1, times the relative rate measured at their place in
/// the list, `rates` as from [`Balance::rates`]), each with
/// the particle interval that starts at its first pair's first particle; and each range's
/// pair cost (unweighted). Where the split falls changes which particles are summed in the
/// pair loop and which from the slots, not the result.
pub(super) fn pair_ranges(
    hot: &[HotPair],
    np: usize,
    n: usize,
    rates: &[(f64, f64)],
) -> (Vec<PairRange>, Vec<usize>) {
    let cost: Vec<usize> = hot
        .par_chunks(BLOCK)
        .map(|c| c.len() + 7 * c.iter().filter(|h| h.live).count())
        .collect();
    let nb = cost.len().max(1) as f64;
    let rate = |b: usize| {
        let x = (b as f64 + 0.5) / nb;
        rates.iter().find(|r| x < r.0).map_or(1.0, |r| r.1)
    };
    let weight: Vec<f64> = cost
        .iter()
        .enumerate()
        .map(|(b, &c)| c as f64 * rate(b))
        .collect();
    let total = weight.iter().sum::<f64>();
    let n = n.clamp(1, cost.len().max(1));
    let mut ranges = Vec::with_capacity(n);
    let mut costs = Vec::with_capacity(n);
    let (mut b0, mut acc, mut p0) = (0, 0.0, 0);
    for (b, w) in weight.iter().enumerate() {
        acc += w;
        let last = b + 1 == cost.len();
        if last || acc * n as f64 >= total * (ranges.len() + 1) as f64 {
            let end = ((b + 1) * BLOCK).min(hot.len());
            let p1 = if last {
                np
            } else {
                (hot[end].i as usize).clamp(p0, np)
            };
            ranges.push(PairRange {
                pairs: b0 * BLOCK..end,
                parts: p0..p1,
            });
            costs.push(cost[b0..=b].iter().sum());
            (b0, p0) = (b + 1, p1);
        }
    }
    if ranges.is_empty() {
        ranges.push(PairRange {
            pairs: 0..0,
            parts: 0..np,
        });
        costs.push(0);
    }
    (ranges, costs)
}

/// What the pair loop reads of the particles and the scene.
#[derive(Clone, Copy)]
pub(super) struct PairCtx<'a> {
    pub(super) pos: View<'a>,
    pub(super) vel: View<'a>,
    pub(super) spin: View<'a>,
    pub(super) radius: &'a [f64],
    pub(super) mass: &'a [f64],
    pub(super) material: &'a [u16],
    pub(super) model: &'a Model,
    pub(super) laws: &'a Laws<'a>,
    pub(super) size: [f64; 3],
    pub(super) periodic: [bool; 3],
    /// The Lees–Edwards offset of a sheared cell (`sim::cell`; 0 otherwise).
    pub(super) shift: f64,
    /// The deforming cell, whose mean field adds to the pairs' relative velocity (`None`
    /// while it is at rest).
    pub(super) cell: Option<&'a crate::sim::cell::Cell>,
    /// Sum Σ f ⊗ l over the evaluated pairs into `Acc::stress` (the cell's work and servo).
    pub(super) stress: bool,
    /// The particles are all alike: their radius, mass and pair constants.
    pub(super) uni: Option<UniPair>,
    /// Per particle, the dashpot's margin of reach (`Scene::reach_ext`; `None`: none).
    pub(super) ext: Option<&'a [f64]>,
    /// The largest entry of `ext` (0 without): the four-lane reach test's one margin for
    /// every pair (`reach::mask_avx2`).
    pub(super) ext_max: f64,
    /// With adhesion or liquid, a pair is evaluated while its centres are closer than this
    /// times the sum of the radii (`reach::evaluated`, `params::Model::reach`): `1 + 1e-6`
    /// (the round-off allowance of snap-in and bridge formation), more with a law of `SET
    /// NORmal` that attracts across a gap.
    pub(super) reach: f64,
}

/// The constants of a scene whose particles all have the same radius, mass and material
/// ([`params::Uniform`]), for the pair loop: R* and m* computed once, as the pair loop
/// computes them (`r r / (r + r)`), so they have the same bits.
#[derive(Clone, Copy, Default)]
pub(super) struct UniPair {
    pub(super) r: f64,
    pub(super) r_star: f64,
    pub(super) m_star: f64,
    pub(super) pc: params::PairConst,
}

impl UniPair {
    pub(super) fn of(model: &Model) -> Option<UniPair> {
        let u = model.uniform?;
        let (r, m, k) = (u.radius, u.mass, u.material as usize);
        Some(UniPair {
            r,
            r_star: r * r / (r + r),
            m_star: m * m / (m + m),
            pc: *model.pair(k, k),
        })
    }
}

/// The pair loop over one block, in sub-batches of [`lanes::SUB`] pairs and four passes:
/// which pairs are evaluated (near, or with something to remember), decided without a
/// branch per pair; their geometry (steady Hertz contacts with the no-slip law are gathered
/// into a [`lanes::Batch`]); the batch's contact law on arrays (vectorised); then, in pair
/// order, the ledger terms and forces of the batch and the general kernel for every other
/// evaluated pair. The arithmetic and its order are those of one pass
/// with the general kernel, and `emit` gets each force (with the pair's index in the block)
/// in pair order.
#[inline(always)]
pub(super) fn block_forces<const ADH: bool, const LIQ: bool, const UNI: bool>(
    hots: &mut [HotPair],
    pairs: &mut [Pair],
    block: &mut StateBlock,
    c: &PairCtx,
    acc: &mut Acc,
    sc: &mut Scratch,
    mut emit: impl FnMut(usize, &HotPair, PairForce),
) {
    use lanes::SUB;
    let laws = c.laws;
    // The states and the MDR and JKR rows (those of contacts that ended dropped if a list is
    // full).
    let (block, mut rows) = block.for_step(hots.iter().map(|h| h.slot));
    // (Read only when `UNI`.)
    let u = c.uni.unwrap_or_default();
    let batched = batches_steady::<ADH, LIQ>(c);
    let vector_reach = vector_reach(c);
    let Scratch {
        batch,
        kins,
        idx,
        ds,
        dists,
        lane,
    } = sc;
    let mut start = 0;
    while start < hots.len() {
        let end = (start + SUB).min(hots.len());
        // Which pairs are evaluated, without a branch per pair (whether a pair is near is
        // as good as random along the list).
        let m = reach::evaluated::<ADH, LIQ, UNI>(&hots[start..end], start, c, vector_reach, idx);
        prefetch_states(hots, block, &idx[..m]);
        // The distances and normals of the evaluated pairs in a loop of their own: its
        // square roots and divisions overlap, where inside the loop below each pair's
        // waited for the one before.
        for q in 0..m {
            let d = reach::separation(&hots[idx[q] as usize], c);
            let dist = d.norm_squared().sqrt();
            dists[q] = dist;
            ds[q] = d / dist;
        }

        batch.len = 0;
        for q in 0..m {
            let k = idx[q] as usize;
            let h = &mut hots[k];
            {
                let kin = pair_kin::<UNI>(h, &mut pairs[k].slot, block, c, &u, (ds[q], dists[q]));
                lane[q] = u8::MAX;
                if batched {
                    let s = &block[h.slot as usize];
                    let pc = if UNI {
                        &u.pc
                    } else {
                        c.model.pair(
                            c.material[h.i as usize] as usize,
                            c.material[h.j as usize] as usize,
                        )
                    };
                    if lanes::Batch::takes(&kin, pc, s) {
                        lane[q] = batch.push(&kin, pc, s) as u8;
                    }
                }
                // (Only the general kernel reads it back.)
                if lane[q] == u8::MAX {
                    kins[q] = kin;
                }
            }
        }
        if batch.len > 0 {
            lanes::hertz_noslip(batch, laws.dt);
        }
        for q in 0..m {
            let k = idx[q] as usize;
            let h = &mut hots[k];
            let s = &mut block[h.slot as usize];
            let f = if lane[q] != u8::MAX {
                let l = lane[q] as usize;
                let (f, m) = batch.store(l, s);
                acc.damping_contact += batch.e_damp_n[l];
                acc.friction += batch.e_friction[l];
                acc.damping_contact += batch.e_damp_t[l];
                // (`h.live` stays true: the contact was touching, `Batch::takes`, and it
                // still overlaps.)
                PairForce { f, m }
            } else {
                let kin = &kins[q];
                let (i, j) = (h.i as usize, h.j as usize);
                let pc = c.model.pair(c.material[i] as usize, c.material[j] as usize);
                let out = interact_rows::<ADH, LIQ>(kin, pc, laws, s, Some(rows.reborrow()), acc);
                let live = s.live();
                if h.live != live {
                    h.live = live;
                }
                PairForce {
                    f: out.f,
                    m: if c.model.rotation {
                        -kin.n.cross(&out.ft)
                    } else {
                        Vec3::zeros()
                    },
                }
            };
            if c.stress {
                // The average stress's contact part (`sim::stress`), in pair order: the
                // components the cell's work and servo read (σ11 σ22 σ33 and σ12, where
                // the velocity gradient can be non-zero).
                let l = ds[q] * dists[q];
                acc.stress[0] += f.f.x * l.x;
                acc.stress[4] += f.f.y * l.y;
                acc.stress[8] += f.f.z * l.z;
                acc.stress[1] += f.f.x * l.y;
            }
            emit(k, h, f);
        }
        start = end;
    }
}

/// Velocity of B's contact point relative to A's (the pair's `Kin::v_rel`); in a deforming
/// cell the peculiar velocities plus the mean field's difference `G l` across the branch
/// vector `l = n dist` (`sim::cell`).
#[inline(always)]
pub(super) fn rel_velocity(
    c: &PairCtx,
    (i, j): (usize, usize),
    (ri, rj): (f64, f64),
    (n, dist): (&Vec3, f64),
) -> Vec3 {
    let v = c.vel[j] - c.vel[i] - (c.spin[i] * ri + c.spin[j] * rj).cross(n);
    match c.cell {
        Some(cell) => v + cell.field(&(n * dist)),
        None => v,
    }
}

/// Asks the processor to fetch the contact states of a sub-batch's evaluated pairs (`idx`)
/// before their geometry is worked out: the loads of the states then overlap with each
/// other and with the geometry instead of each waiting in turn (all three cache lines a
/// 120-byte state can span). Measured on the AMD EPYC host:
/// S1 10k one thread 0.914 × the time (side by side, 8 pairs; doc/performance.md);
/// prefetching the next sub-batch's states instead (found one sub-batch ahead) was 1.04 ×
/// slower, prefetching the particles' velocities and spins too no gain.
#[inline(always)]
pub(super) fn prefetch_states(hots: &[HotPair], block: &[ContactState], idx: &[u32]) {
    #[cfg(target_arch = "x86_64")]
    for &k in idx {
        let s = hots[k as usize].slot as usize;
        if s < block.len() {
            let p = (&block[s]) as *const ContactState as *const i8;
            // SAFETY: `p`, `p + 64` and `p + 111` lie inside the state `block[s]`; and a
            // prefetch reads no value and never faults, whatever the address.
            unsafe {
                use std::arch::x86_64::{_MM_HINT_T0, _mm_prefetch};
                _mm_prefetch::<_MM_HINT_T0>(p);
                _mm_prefetch::<_MM_HINT_T0>(p.wrapping_add(64));
                _mm_prefetch::<_MM_HINT_T0>(p.wrapping_add(size_of::<ContactState>() - 1));
            }
        }
    }
    #[cfg(not(target_arch = "x86_64"))]
    let _ = (hots, block, idx);
}

/// Whether the reach tests run four candidates at a time (`reach::mask_avx2`): the
/// processor has AVX2.
#[inline(always)]
pub(super) fn vector_reach(c: &PairCtx) -> bool {
    #[cfg(target_arch = "x86_64")]
    {
        let _ = c;
        std::is_x86_feature_detected!("avx2")
    }
    #[cfg(not(target_arch = "x86_64"))]
    {
        let _ = c;
        false
    }
}

/// Whether the steady contacts of this step go through the vectorised kernel
/// ([`lanes::hertz_noslip`]): a dry scene without adhesion, the no-slip law with rotation,
/// no Rayleigh tangential dashpot, a time step (not the states-only pass).
#[inline(always)]
pub(super) fn batches_steady<const ADH: bool, const LIQ: bool>(c: &PairCtx) -> bool {
    let laws = c.laws;
    !ADH && !LIQ
        && laws.tangential == TangentialChoice::NoSlip
        && !(laws.beta > 0.0)
        && laws.rotation
        && c.model.rotation
        && laws.dt > 0.0
}

/// Work arrays of the pair loop's sub-batches, made once per task and step and reused by
/// every block (every entry is written before it is read; made per block, their 12 KB of
/// initial zeros cost a noticeable part of the step).
pub(super) struct Scratch {
    pub(super) batch: lanes::Batch,
    pub(super) kins: [Kin; lanes::SUB],
    pub(super) idx: [u32; lanes::SUB],
    /// The evaluated pairs' normals and distances.
    pub(super) ds: [Vec3; lanes::SUB],
    pub(super) dists: [f64; lanes::SUB],
    /// Lane of each evaluated pair in the batch (u8::MAX: general kernel).
    pub(super) lane: [u8; lanes::SUB],
}

impl Scratch {
    pub(super) fn new() -> Scratch {
        Scratch {
            batch: lanes::Batch::new(),
            kins: [Kin::ZERO; lanes::SUB],
            idx: [0; lanes::SUB],
            ds: [Vec3::zeros(); lanes::SUB],
            dists: [0.0; lanes::SUB],
            lane: [u8::MAX; lanes::SUB],
        }
    }
}

/// The geometry of an evaluated pair. A pair that comes within reach for the first time
/// gets its state appended to its block. `UNI`: the particles are all alike (`u`).
#[inline(always)]
pub(super) fn pair_kin<const UNI: bool>(
    h: &mut HotPair,
    slot: &mut u32,
    block: &mut Vec<ContactState>,
    c: &PairCtx,
    u: &UniPair,
    (n, dist): (Vec3, f64),
) -> Kin {
    let (i, j) = (h.i as usize, h.j as usize);
    if h.slot == NO_STATE {
        h.slot = block.len() as u32;
        *slot = h.slot;
        contacts::grow_block(block);
        block.push(ContactState::default());
    }
    let (ri, rj) = if UNI {
        (u.r, u.r)
    } else {
        (c.radius[i], c.radius[j])
    };
    let v_rel = rel_velocity(c, (i, j), (ri, rj), (&n, dist));
    let (r_star, m_star) = if UNI {
        (u.r_star, u.m_star)
    } else {
        let (mi, mj) = (c.mass[i], c.mass[j]);
        (ri * rj / (ri + rj), mi * mj / (mi + mj))
    };
    Kin {
        n,
        gap: dist - ri - rj,
        v_rel,
        r_star,
        m_star,
        r1: ri,
        r2: rj,
    }
}
