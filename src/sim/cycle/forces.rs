//! The force half of a step: contacts between particles (serial, or in parallel tasks over
//! balanced pair ranges), liquid bridges and walls; the per-chunk sums that keep the
//! results bitwise independent of the thread count.

use super::*;

/// Step 1 of a cycle: all contact forces at the current positions (dt = 0: states only).
pub(super) fn forces(scene: &mut Scene, model: &Model, dt: f64) -> Acc {
    forces_or_fused(scene, model, dt, None).0
}

/// Steps 1 and 2 of a cycle in one parallel region (several threads, see `fused`): the
/// energy increments and the update's chunk sums.
pub(super) fn forces_fused(
    scene: &mut Scene,
    model: &Model,
    mv: &Mover,
    keep: bool,
) -> (Acc, Vec<ChunkSums>) {
    let (acc, parts) = forces_or_fused(scene, model, model.dt, Some((mv, keep)));
    (acc, parts.unwrap_or_default())
}

pub(super) fn forces_or_fused(
    scene: &mut Scene,
    model: &Model,
    dt: f64,
    fuse: Option<(&Mover, bool)>,
) -> (Acc, Option<Vec<ChunkSums>>) {
    // The kernel for what the scene has: adhesion, liquid (see `interact`).
    // (The laws of `SET NORmal` other than Hertz/JKR go through the adhesive kernel.)
    match (
        model.adhesion || !model.laws.is_empty(),
        scene.liquid.is_some(),
    ) {
        (false, false) => forces_with::<false, false>(scene, model, dt, fuse),
        (false, true) => forces_with::<false, true>(scene, model, dt, fuse),
        (true, false) => forces_with::<true, false>(scene, model, dt, fuse),
        (true, true) => forces_with::<true, true>(scene, model, dt, fuse),
    }
}

/// The contact forces (`fuse`: with the update, in one region, see `fused`).
pub(super) fn forces_with<const ADH: bool, const LIQ: bool>(
    scene: &mut Scene,
    model: &Model,
    dt: f64,
    fuse: Option<(&Mover, bool)>,
) -> (Acc, Option<Vec<ChunkSums>>) {
    let liquid = scene.liquid;
    let laws_pp = Laws {
        dt,
        tangential: scene.settings.tangential,
        rotation: model.rotation,
        beta: scene.damping_pp.beta,
        liquid: liquid.as_ref(),
        bridge: scene.settings.bridge,
        smin: scene.settings.smin,
        impact: scene.impact,
        liquid_share: (scene.settings.liquid_mode == crate::sim::model::LiquidMode::Conserve)
            .then_some(crate::sim::liquid::OLSSON_SHARE),
        goldman: scene.settings.goldman,
        pair_laws: &model.laws,
        edges: dt > 0.0 && crate::sim::params::undamped_dry(scene),
        // (Only in a step, with the margins of its particles: not while priming.)
        margin: if dt > 0.0
            && scene.derived.reach_ext.len() == scene.particles.len().div_ceil(EXT_GROUP)
        {
            scene.contacts.step.margins[0]
        } else {
            0.0
        },
    };

    let shapes: Vec<WallShape> = scene.walls.iter().map(|w| WallShape::of(&w.geom)).collect();
    // The same laws for particle–wall contacts; Rayleigh contact damping has its own
    // particle–wall set; without wall bridges (`SET WALlbridges OFF`) no liquid.
    let laws_pw = Laws {
        beta: scene.damping_pw.beta,
        liquid: liquid.as_ref().filter(|_| scene.settings.wall_bridges),
        pair_laws: &model.wall_laws,
        margin: if laws_pp.margin > 0.0 {
            scene.contacts.step.margins[1]
        } else {
            0.0
        },
        ..laws_pp
    };
    let (pair_acc, wall_acc, parts) = if let Some((mv, keep)) = fuse {
        let (pair_acc, wall_acc, parts) = fused::forces_and_moves::<ADH, LIQ>(
            scene,
            (model, &laws_pp, &laws_pw, &shapes),
            mv,
            keep,
        );
        (pair_acc, wall_acc, Some(parts))
    } else {
        let (pair_acc, wall_acc) =
            contact_forces::<ADH, LIQ>(scene, model, (&laws_pp, &laws_pw), &shapes);
        (pair_acc, wall_acc, None)
    };
    let mut acc = Acc::default();
    acc.add(&pair_acc);
    for a in &wall_acc {
        acc.add(a);
    }
    // ---- particle–wall contacts -------------------------------------------------------
    // The tasks have made the walls' forces (summed per block of wall pairs, then in block
    // order) and the energy increments (per block). The particles get theirs in the update
    // (`move_all` or, in one region, `fused`, chunk by chunk), after their moments are
    // scaled by the radius and, with several threads, after the shared particles' sums.
    scene.contacts.step.wall_out.sum_walls(scene.walls.len());
    for (w, f) in scene
        .walls
        .iter_mut()
        .zip(&scene.contacts.step.wall_out.on_wall)
    {
        w.force = *f;
    }
    scene.contacts.step.deferred = parts.is_none();
    (acc, parts)
}

/// The contact forces of the two-region step ([`pair_forces`]): the pairs' energy
/// increments (per block in block order) and the wall pairs' (per block).
pub(super) fn contact_forces<const ADH: bool, const LIQ: bool>(
    scene: &mut Scene,
    model: &Model,
    (laws_pp, laws_pw): (&Laws, &Laws),
    shapes: &[WallShape],
) -> (Acc, Vec<Acc>) {
    // ---- particle–particle contacts ---------------------------------------------------
    // Each pair's force goes onto its two particles in pair order. With one thread that is
    // done in the pair loop; with several, each task (a range of whole blocks) does it for
    // the particles whose pairs all lie in its range, and the few others are summed from
    // the pairs' slots afterwards, also in pair order. Either way every particle sums its
    // pairs in the same order, and the energy partial sums are added per block in block
    // order (then the wall contacts' per chunk): the result does not depend on the number
    // of threads.
    let ctx = PairCtx {
        pos: View::of(&scene.particles.pos),
        vel: View::of(&scene.particles.vel),
        spin: View::of(&scene.particles.spin),
        radius: &scene.particles.radius,
        mass: &scene.particles.mass,
        material: &scene.particles.material,
        model,
        laws: laws_pp,
        size: scene.size,
        periodic: scene.settings.periodic,
        shift: scene.cell.shift,
        cell: scene.cell.is_active().then_some(&scene.cell),
        stress: scene.cell.needs_stress() || scene.derived.servo.is_some(),
        uni: UniPair::of(model),
        ext: (laws_pp.margin > 0.0).then_some(&scene.derived.reach_ext[..]),
        ext_max: reach::largest(&scene.derived.reach_ext[..]),
        reach: model.reach,
    };
    let wall_ctx = PairCtx {
        laws: laws_pw,
        ..ctx
    };
    let zeroed = std::mem::take(&mut scene.contacts.step.zeroed);
    let StepParts {
        hot,
        pairs,
        blocks,
        out,
        scatter,
        wall_pairs,
        wall_out,
    } = scene.contacts.step_parts();
    let force = &mut scene.particles.force;
    let moment = &mut scene.particles.moment;
    let walls = (&scene.walls[..], shapes);
    pair_forces::<ADH, LIQ>(
        (hot, pairs, blocks, out, scatter),
        (force, moment, zeroed),
        &ctx,
        (wall_pairs, wall_out, walls, &wall_ctx),
    )
}

/// What the force step left to the update (see [`ContactStore::deferred`]), for the
/// particles of chunk `c` (`force`, `moment`: the chunk's): with several threads the shared
/// particles' sums from their pairs' slots, in pair order; the moments (summed per unit
/// radius) times the radius; then each particle's wall forces in pair order. The same sums
/// in the same order for any number of threads, done where the update reads the chunk
/// anyway (one pass over the moments less per step).
pub(super) fn finish_chunk(
    left: Left<'_>,
    c: usize,
    (force, moment): (&mut [Vec3], &mut [Vec3]),
    radius: &[f64],
    rotation: bool,
) {
    let lo = c * CHUNK;
    let hi = lo + force.len();
    if let Some((inc, hot, out)) = left.scatter {
        let list = &inc.shared_list;
        let first = list.partition_point(|&q| (q as usize) < lo);
        let last = list.partition_point(|&q| (q as usize) < hi);
        for (s, &q) in list.iter().enumerate().take(last).skip(first) {
            let q = q as usize;
            let (mut f, mut m) = (Vec3::zeros(), Vec3::zeros());
            for &k in inc.of_shared(s) {
                let h = &hot[k as usize];
                // (A pair not evaluated in this step left its slot at zero, which adds
                // nothing: the sum starts at +0 and never becomes −0.)
                let o = &out[inc.slot[k as usize] as usize];
                // Force −f on the pair's first particle (A), +f on B.
                if h.i as usize == q {
                    f -= o.f;
                } else {
                    f += o.f;
                }
                if rotation {
                    m += o.m;
                }
            }
            force[q - lo] = f;
            moment[q - lo] = m;
        }
    }
    if rotation {
        for (m, r) in moment.iter_mut().zip(&radius[lo..hi]) {
            *m *= *r;
        }
    }
    for o in WallOut::of_chunk(left.walls, c) {
        let i = o.i as usize - lo;
        force[i] -= o.f;
        if rotation {
            moment[i] += o.m;
        }
    }
    if let Some(roll) = left.roll {
        for (m, r) in moment.iter_mut().zip(&roll[lo..hi]) {
            *m += r;
        }
    }
}

/// The deferred part of the force step without the update (after `prime`, whose force step
/// ran `model`'s plan).
pub(super) fn finish_deferred(scene: &mut Scene, model: &Model) {
    let rotation = model.rotation;
    if !std::mem::take(&mut scene.contacts.step.deferred) {
        return;
    }
    let contacts = &scene.contacts;
    let left = Left {
        scatter: split_step(model).then_some((
            &contacts.step.scatter,
            &contacts.step.hot,
            &contacts.step.out,
        )),
        walls: &contacts.step.wall_out.pieces,
        roll: None,
    };
    let p = &mut scene.particles;
    let radius = &p.radius;
    p.force
        .par_chunks_mut(CHUNK)
        .zip(p.moment.par_chunks_mut(CHUNK))
        .enumerate()
        .for_each(|(c, (f, m))| finish_chunk(left, c, (f, m), radius, rotation));
}

/// The particle–particle forces (see [`forces_with`]): each pair's force goes onto its two
/// particles in pair order; the moments are summed per unit radius (the update scales them,
/// `finish_chunk`). The wall contacts are evaluated alongside: with several threads each task
/// takes the stretch of wall pairs (whole blocks of [`WALL_BLOCK`]) that begins about where
/// its particles do, before its pairs ([`wall_forces`], one piece of `wall_out` per task), so
/// that the core that updates a particle has its wall forces in its cache.
/// Returns the energy increments, the pairs' summed per block in block order, and the wall
/// pairs' per block, in block order.
#[allow(clippy::type_complexity)]
pub(super) fn pair_forces<const ADH: bool, const LIQ: bool>(
    (hot, pairs, blocks, out, scatter): (
        &mut [HotPair],
        &mut [Pair],
        &mut [StateBlock],
        &mut Vec<PairForce>,
        &mut Incidence,
    ),
    (force, moment, zeroed): (&mut Vec<Vec3>, &mut Vec<Vec3>, bool),
    ctx: &PairCtx,
    (wall_pairs, wall_out, walls, wall_ctx): (
        &mut [WallPair],
        &mut WallOut,
        (&[Wall], &[WallShape]),
        &PairCtx,
    ),
) -> (Acc, Vec<Acc>) {
    let ctx = *ctx;
    let rotation = ctx.model.rotation;
    let np = force.len();
    let acc;
    let wall_acc;
    {
        if ctx.model.plan.threads == 1 {
            wall_out.pieces.resize_with(1, WallPiece::default);
            wall_acc =
                wall_forces::<ADH, LIQ>(wall_pairs, &mut wall_out.pieces[0], walls, wall_ctx, np);
            if !zeroed {
                force.fill(Vec3::zeros());
                moment.fill(Vec3::zeros());
            }
            // (The blocks' increments are the whole of `acc` on one thread.)
            let parts = (hot, pairs, blocks);
            acc = if ctx.uni.is_some() {
                serial_pairs::<ADH, LIQ, true>(parts, (force, moment), &ctx, rotation)
            } else {
                serial_pairs::<ADH, LIQ, false>(parts, (force, moment), &ctx, rotation)
            };
        } else {
            split_if_needed(scatter, hot, np, ctx.model.plan.threads);
            out.resize(scatter.slots, PairForce::default());
            let inc = &*scatter;
            let ranges = &inc.ranges;
            let wall_cut = wall_cuts(ranges, wall_pairs);
            wall_out
                .pieces
                .resize_with(ranges.len(), WallPiece::default);
            // Each task takes a range of whole blocks and the particles it owns: those of
            // its particle interval whose pairs all lie in its blocks. Their forces are summed
            // in the pair loop, in pair order, as with one thread; every other particle's
            // share is left in the pair's slot and summed below, also in pair order.
            let mut tasks = Vec::with_capacity(ranges.len());
            {
                let (mut hot, mut pairs, mut blocks, mut out) =
                    (&mut hot[..], &mut pairs[..], &mut blocks[..], &mut out[..]);
                let (mut force, mut moment) = (&mut force[..], &mut moment[..]);
                let mut wall_rest = &mut wall_pairs[..];
                let mut pieces = &mut wall_out.pieces[..];
                for (t, (r, slots)) in ranges.iter().zip(&inc.task_slots).enumerate() {
                    let (h, rest) = hot.split_at_mut(r.pairs.len());
                    hot = rest;
                    let (p, rest) = pairs.split_at_mut(r.pairs.len());
                    pairs = rest;
                    let (b, rest) = blocks.split_at_mut(r.pairs.len().div_ceil(BLOCK));
                    blocks = rest;
                    let (o, rest) = out.split_at_mut(slots.len());
                    out = rest;
                    let (f, rest) = force.split_at_mut(r.parts.len());
                    force = rest;
                    let (m, rest) = moment.split_at_mut(r.parts.len());
                    moment = rest;
                    let (w, rest) = wall_rest.split_at_mut(wall_cut[t + 1] - wall_cut[t]);
                    wall_rest = rest;
                    let (piece, rest) = pieces.split_at_mut(1);
                    pieces = rest;
                    let walls_of = (w, &mut piece[0]);
                    tasks.push((r.clone(), slots.start, h, p, b, o, f, m, walls_of));
                }
            }
            let task_acc: Vec<(Vec<Acc>, Vec<Acc>, f64)> = tasks
                .into_par_iter()
                .with_max_len(1)
                .map(
                    |(r, slot0, hots, pairs, blocks, outs, force, moment, (wp, piece))| {
                        let t0 = std::time::Instant::now();
                        let wall_accs = wall_forces::<ADH, LIQ>(wp, piece, walls, wall_ctx, np);
                        let accs = task_pairs::<ADH, LIQ>(
                            (&r, slot0, inc),
                            (hots, pairs, blocks, outs),
                            (force, moment, zeroed),
                            &ctx,
                        );
                        (accs, wall_accs, t0.elapsed().as_secs_f64())
                    },
                )
                .collect();
            (acc, wall_acc) = task_sums(&task_acc, &mut scatter.balance);
            // The particles no task owned are summed from their pairs' slots by the
            // update (`finish_chunk`).
        }
    }

    (acc, wall_acc)
}

/// The pair loop on one thread: each pair's force onto its two particles in pair order; the
/// energy increments per block, added in block order. `UNI`: the particles are all alike
/// (chosen here, once, so that the loop and its force closure are compiled once per choice
/// and stay inlined).
pub(super) fn serial_pairs<const ADH: bool, const LIQ: bool, const UNI: bool>(
    (hot, pairs, blocks): (&mut [HotPair], &mut [Pair], &mut [StateBlock]),
    (force, moment): (&mut [Vec3], &mut [Vec3]),
    ctx: &PairCtx,
    rotation: bool,
) -> Acc {
    let mut acc = Acc::default();
    let mut sc = Scratch::new();
    for ((hots, pairs), block) in hot
        .chunks_mut(BLOCK)
        .zip(pairs.chunks_mut(BLOCK))
        .zip(blocks.iter_mut())
    {
        let mut a = Acc::default();
        block_forces::<ADH, LIQ, UNI>(hots, pairs, block, ctx, &mut a, &mut sc, |_, h, o| {
            let (i, j) = (h.i as usize, h.j as usize);
            force[i] -= o.f;
            force[j] += o.f;
            if rotation {
                moment[i] += o.m;
                moment[j] += o.m;
            }
        });
        acc.add(&a);
    }
    acc
}

/// The tasks' results (per task: the energy increments of its pair blocks, of its wall
/// blocks, and its time) as one sum of the pair blocks in block order and the wall blocks'
/// list in block order; each task's time is added to its share of `balance`.
pub(super) fn task_sums(
    results: &[(Vec<Acc>, Vec<Acc>, f64)],
    balance: &mut Balance,
) -> (Acc, Vec<Acc>) {
    let mut acc = Acc::default();
    let mut wall_acc = Vec::new();
    for (accs, wall_accs, _) in results {
        for a in accs {
            acc.add(a);
        }
        wall_acc.extend_from_slice(wall_accs);
    }
    for (t, (_, _, secs)) in balance.tasks.iter_mut().zip(results) {
        t.2 += secs;
    }
    (acc, wall_acc)
}

/// With several threads, once per rebuild: one task per thread (measured: more tasks make
/// more particles shared), balanced on the contacts of this step and on what the tasks took
/// since the last split.
pub(super) fn split_if_needed(
    scatter: &mut Incidence,
    hot: &mut [HotPair],
    np: usize,
    threads: usize,
) {
    if scatter.needs_split(np, threads) {
        let rates = scatter.balance.rates().unwrap_or_default();
        let (ranges, costs) = pair_ranges(hot, np, threads, &rates);
        let n = hot.len().max(1) as f64;
        scatter.balance = Balance {
            tasks: (ranges.iter().zip(costs))
                .map(|(r, c)| (r.pairs.end as f64 / n, c, 0.0))
                .collect(),
        };
        scatter.split(hot, np, ranges, threads);
    }
}

/// Where each task's stretch of wall pairs begins (and, last, their number): whole blocks,
/// from the block boundary nearest to the first wall pair of its particle interval (wall
/// pairs are in id order, which is mostly index order). Where the cut falls changes no sum.
pub(super) fn wall_cuts(ranges: &[PairRange], wall_pairs: &[WallPair]) -> Vec<usize> {
    let mut wall_cut = vec![0; ranges.len() + 1];
    for (t, r) in ranges.iter().enumerate().skip(1) {
        let k = wall_pairs.partition_point(|w| (w.i as usize) < r.parts.start);
        let k = (k + WALL_BLOCK / 2) / WALL_BLOCK * WALL_BLOCK;
        wall_cut[t] = k.clamp(wall_cut[t - 1], wall_pairs.len());
    }
    wall_cut[ranges.len()] = wall_pairs.len();
    wall_cut
}

/// One task's pairs with several threads (task range `r`, its first force slot `slot0`):
/// the forces of the particles it owns (those of its interval `force`, `moment` that no
/// other task's pairs touch) summed in pair order, as with one thread; every other
/// particle's share left in the pair's slot (`outs`; the slots of pairs not evaluated in this
/// step stay zero: they are cleared here, on the core that writes them). Returns the energy
/// increments per block.
pub(super) fn task_pairs<const ADH: bool, const LIQ: bool>(
    task: (&PairRange, usize, &Incidence),
    lists: (
        &mut [HotPair],
        &mut [Pair],
        &mut [StateBlock],
        &mut [PairForce],
    ),
    sums: (&mut [Vec3], &mut [Vec3], bool),
    ctx: &PairCtx,
) -> Vec<Acc> {
    // The choice for uniform scenes once per task (not per block: two copies of the block
    // loop in one function left its force closure out of line, a call per pair, 15 % slower
    // on two threads).
    if ctx.uni.is_some() {
        task_pairs_of::<ADH, LIQ, true>(task, lists, sums, ctx)
    } else {
        task_pairs_of::<ADH, LIQ, false>(task, lists, sums, ctx)
    }
}

pub(super) fn task_pairs_of<const ADH: bool, const LIQ: bool, const UNI: bool>(
    (r, slot0, inc): (&PairRange, usize, &Incidence),
    (hots, pairs, blocks, outs): (
        &mut [HotPair],
        &mut [Pair],
        &mut [StateBlock],
        &mut [PairForce],
    ),
    (force, moment, zeroed): (&mut [Vec3], &mut [Vec3], bool),
    ctx: &PairCtx,
) -> Vec<Acc> {
    let rotation = ctx.model.rotation;
    let lo = r.parts.start;
    outs.fill(PairForce::default());
    if !zeroed {
        force.fill(Vec3::zeros());
        moment.fill(Vec3::zeros());
    }
    let mut accs = Vec::with_capacity(blocks.len());
    let mut sc = Scratch::new();
    for (b, ((hots, pairs), block)) in hots
        .chunks_mut(BLOCK)
        .zip(pairs.chunks_mut(BLOCK))
        .zip(blocks.iter_mut())
        .enumerate()
    {
        let base = r.pairs.start + b * BLOCK;
        let mut a = Acc::default();
        block_forces::<ADH, LIQ, UNI>(hots, pairs, block, ctx, &mut a, &mut sc, |k, h, o| {
            let (i, j) = (h.i as usize, h.j as usize);
            // A particle this task's pairs touch is its own unless shared.
            let (oi, oj) = (h.shared & 1 == 0, h.shared & 2 == 0);
            if oi {
                force[i - lo] -= o.f;
                if rotation {
                    moment[i - lo] += o.m;
                }
            }
            if oj {
                force[j - lo] += o.f;
                if rotation {
                    moment[j - lo] += o.m;
                }
            }
            if !(oi && oj) {
                outs[inc.slot[base + k] as usize - slot0] = o;
            }
        });
        accs.push(a);
    }
    accs
}

/// Whether the step's force step was split among tasks (its plan has several threads): the
/// shared particles' sums are then in the pairs' slots, for the update to add. A step the
/// Cycle's thread runs alone on the one-thread plan (`Pacer::asleep`) leaves the slots of
/// the last split step in place, which the update must not read.
pub(super) fn split_step(model: &Model) -> bool {
    model.plan.threads > 1
}
