//! Checkpoints (`SAve`/`RESTart`): bincode 2 through serde. Layout: the magic bytes
//! `TRUBALCK`, a little-endian u32 format version, a u64 length and an FNV-1a 64 checksum of
//! the payload, then the payload (the whole [`Scene`]). A file is refused with a reason when
//! the magic, the version, the length, the checksum or the consistency of the decoded state
//! does not match, and the current state is untouched. Saving writes a temporary file next to
//! the target and renames it over the target, so an existing file survives a failed save.
//! Neither direction holds the file in memory: [`save`] encodes the state twice (once for the
//! header's length and checksum, once into the file), [`load`] reads the file twice (the
//! checksum, then the state), and the contact pairs go into their blocks as they are decoded.
//!
//! # Format evolution
//!
//! bincode is not self-describing: the payload is the fields of [`Scene`] (and of every type
//! inside it) in declaration order. **Any** change of those types — a field added, removed,
//! re-ordered or re-typed, an enum variant added in the middle — changes the format. Then:
//!
//! 1. bump [`VERSION`];
//! 2. keep reading the old version: copy the old definitions of the changed types into a
//!    module `v{OLD}` here (unchanged types can be reused), decode the payload with them in
//!    `decode_payload` and convert to the current [`Scene`] (new fields get the value that
//!    reproduces the old behaviour). Only if that is impossible raise [`OLDEST_READABLE`]: the
//!    file is then refused with a message naming both versions;
//! 3. add a fixture of the new version under `tests/fixtures/` (the `#[ignore]`d test
//!    `write_fixture` in `tests/it/checkpoint.rs` writes it) and keep the old ones.
//!
//! `tests/it/checkpoint.rs` fails when the fixture of the current version no longer decodes to
//! the same bytes, i.e. when the layout changed without a version bump.
//!
//! History: version 1 held every contact state in one flat layout; version 2 (slim contact
//! state: the JKR, Mindlin–Deresiewicz and liquid-return fields behind one optional pointer,
//! the never-read contact normal dropped); version 3 adds the contact state's `v_prev` (the
//! second-order dashpot's history), each wall's `travel` since the last rebuild, and the
//! settings `tunnel` (SET TUNnel) and `auto_step` (FRAction AUTO); version 4 adds Walton's
//! law state (`walton`) to the law-specific part of the contact state, the setting
//! `SET TANgential WALTON` (a new last variant, which older files never hold), the periodic
//! cell's deformation (`Scene::cell`, read as at rest from older files) and seven history
//! columns (the stress, the temperature and the cell's strains, read as 0); version 5 adds
//! the state of the laws of `SET NORmal` and `SET ROLling` (`laws`: the normal law's
//! history, the rolling spring) to the law-specific part of the contact state, and the scene's contact laws per material pair (`Scene::laws`, read as Hertz/JKR
//! without rolling friction from older files); version 6 adds the friction and restitution
//! of single material pairs (`SET PAIr`, `ContactLaws::pair_values`, read as none from
//! older files), and may hold the new last variants `NormalLaw::Nguyen` (`SET NORmal
//! NGUYEN`) and `NormalHistory::Nguyen`, which older files never hold. Versions 1 to 5
//! are read through `sim::contacts::old` (contact states), `scene::old_walls`,
//! `scene::old_cell`, `scene::old_laws` and
//! `scene::old_settings`, which read the types that changed in the layout of the version
//! being decoded.

use std::fs::File;
use std::io::{BufReader, BufWriter, Read, Seek, SeekFrom, Write};
use std::path::Path;

use crate::sim::Scene;

pub const MAGIC: &[u8; 8] = b"TRUBALCK";
/// Format version written by this program.
pub const VERSION: u32 = 6;
/// Oldest format version this program still reads.
pub const OLDEST_READABLE: u32 = 1;
/// Bytes before the payload: magic, version, length, checksum.
pub const HEADER: usize = 8 + 4 + 8 + 8;

/// FNV-1a 64 of the payload (detects any single changed byte).
pub fn fnv1a(data: &[u8]) -> u64 {
    let mut h = Fnv::default();
    h.update(data);
    h.0
}

/// FNV-1a 64 fed piece by piece (the same value as [`fnv1a`] of the pieces laid end to end).
#[derive(Clone, Copy, Debug, PartialEq)]
struct Fnv(u64);

impl Default for Fnv {
    fn default() -> Fnv {
        Fnv(0xcbf2_9ce4_8422_2325)
    }
}

impl Fnv {
    fn update(&mut self, data: &[u8]) {
        let mut h = self.0;
        for &b in data {
            h ^= b as u64;
            h = h.wrapping_mul(0x0000_0100_0000_01b3);
        }
        self.0 = h;
    }
}

/// A writer that counts and hashes what goes through it (to `inner`, or nowhere).
struct Hashing<W> {
    inner: W,
    hash: Fnv,
    count: u64,
}

impl<W> Hashing<W> {
    fn new(inner: W) -> Hashing<W> {
        Hashing {
            inner,
            hash: Fnv::default(),
            count: 0,
        }
    }
}

impl<W: Write> Write for Hashing<W> {
    fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
        let n = self.inner.write(buf)?;
        self.hash.update(&buf[..n]);
        self.count += n as u64;
        Ok(n)
    }
    fn flush(&mut self) -> std::io::Result<()> {
        self.inner.flush()
    }
}

impl<R: Read> Read for Hashing<R> {
    fn read(&mut self, buf: &mut [u8]) -> std::io::Result<usize> {
        let n = self.inner.read(buf)?;
        self.hash.update(&buf[..n]);
        self.count += n as u64;
        Ok(n)
    }
}

/// The header of a checkpoint, `prefix` being its first `min(total, HEADER)` bytes of
/// `total`: (version, payload length, checksum) once the magic, the version and the length
/// are those of a complete checkpoint this program reads.
fn read_header(prefix: &[u8], total: u64) -> Result<(u32, u64, u64), String> {
    if total == 0 {
        return Err("the file is empty".into());
    }
    if total < 8 && MAGIC.starts_with(prefix) {
        return Err("the checkpoint is truncated (incomplete header)".into());
    }
    if total < 8 || prefix.len() < 8 || &prefix[..8] != MAGIC {
        return Err("not a trubal checkpoint (no TRUBALCK header)".into());
    }
    if total < HEADER as u64 || prefix.len() < HEADER {
        return Err("the checkpoint is truncated (incomplete header)".into());
    }
    let version = u32::from_le_bytes(prefix[8..12].try_into().expect("4 bytes"));
    if version > VERSION {
        return Err(format!(
            "the checkpoint has format version {version}, newer than this program's version {VERSION}: use a newer trubal"
        ));
    }
    if version < OLDEST_READABLE {
        return Err(format!(
            "the checkpoint has format version {version}, which this program (format version {VERSION}) no longer reads (it reads versions {OLDEST_READABLE} to {VERSION}): load it with an older trubal"
        ));
    }
    let len = u64::from_le_bytes(prefix[12..20].try_into().expect("8 bytes"));
    let sum = u64::from_le_bytes(prefix[20..28].try_into().expect("8 bytes"));
    let have = total - HEADER as u64;
    if have != len {
        return Err(format!(
            "the checkpoint is truncated or padded: {have} payload bytes, header says {len}"
        ));
    }
    Ok((version, len, sum))
}

/// The header for a payload of `len` bytes with checksum `sum`.
fn header(len: u64, sum: u64) -> [u8; HEADER] {
    let mut h = [0u8; HEADER];
    h[..8].copy_from_slice(MAGIC);
    h[8..12].copy_from_slice(&VERSION.to_le_bytes());
    h[12..20].copy_from_slice(&len.to_le_bytes());
    h[20..28].copy_from_slice(&sum.to_le_bytes());
    h
}

/// Serialises a scene to bytes.
pub fn to_bytes(scene: &Scene) -> Result<Vec<u8>, String> {
    let mut out = vec![0u8; HEADER];
    bincode::serde::encode_into_std_write(scene, &mut out, bincode::config::standard())
        .map_err(|e| format!("cannot encode the state: {e}"))?;
    let payload = &out[HEADER..];
    let h = header(payload.len() as u64, fnv1a(payload));
    out[..HEADER].copy_from_slice(&h);
    Ok(out)
}

/// Reads a scene from bytes, refusing anything that is not a complete checkpoint of a
/// version this program reads.
pub fn from_bytes(data: &[u8]) -> Result<Scene, String> {
    let (version, _, sum) = read_header(&data[..data.len().min(HEADER)], data.len() as u64)?;
    let payload = &data[HEADER..];
    if fnv1a(payload) != sum {
        return Err("the checkpoint is corrupt (checksum mismatch)".into());
    }
    let mut r = payload;
    let scene = decode_payload(version, &mut r)?;
    if !r.is_empty() {
        return Err("the checkpoint is corrupt: trailing bytes after the state".into());
    }
    check_consistency(&scene).map_err(|e| format!("the checkpoint is inconsistent: {e}"))?;
    Ok(scene)
}

/// Decodes the payload of a given (readable) format version into the current [`Scene`],
/// reading no more than the state's bytes from `r`.
fn decode_payload<R: Read>(version: u32, r: &mut R) -> Result<Scene, String> {
    let mut scene = decode_version(version, r)?;
    scene.particles.shrink_to_fit();
    Ok(scene)
}

fn decode_version<R: Read>(version: u32, r: &mut R) -> Result<Scene, String> {
    match version {
        VERSION => decode_all::<Scene, R>(r, version),
        // Versions 1 to 4 differ in the layout of the contact state (sim::contacts::old; for
        // version 3 the law-specific part had no `walton`, for 4 no `normal`), have no
        // contact laws (scene::old_laws), the walls and settings of 1 and 2
        // (scene::old_walls, old_settings), and have no cell (scene::old_cell).
        // Version 5 differs in the contact laws only (no `pair_values`, scene::old_laws).
        5 => crate::sim::contacts::old::reading(version, || decode_all::<Scene, R>(r, version)),
        1..=4 => crate::sim::contacts::old::reading(version, || decode_all::<Scene, R>(r, version))
            .map(|mut s| {
                // Their history rows have the first 10 columns: the stress, temperature and
                // strain columns of format 4 read as 0.
                for row in &mut s.history.rows {
                    row.resize(crate::sim::history::COLUMNS.len(), 0.0);
                }
                s
            }),
        // Older versions: decode with their frozen types and convert (see "Format evolution").
        v => Err(format!(
            "the checkpoint has format version {v}, for which this program (format version {VERSION}) has no reader"
        )),
    }
}

fn decode_all<T: serde::de::DeserializeOwned, R: Read>(
    r: &mut R,
    version: u32,
) -> Result<T, String> {
    bincode::serde::decode_from_std_read(r, bincode::config::standard()).map_err(|e| {
        format!(
            "the checkpoint is corrupt, or was written by an incompatible build (its checksum \
                 is intact but the state does not decode as format version {version}): {e}"
        )
    })
}

/// The invariants the simulation relies on (array lengths, indices, ids), so that a file that
/// passed the checksum but holds an impossible state is refused instead of making a later
/// command panic.
pub fn check_consistency(scene: &Scene) -> Result<(), String> {
    use crate::sim::scene::{MAX_MATERIALS, MAX_SIZES};
    let p = &scene.particles;
    let n = p.len();
    let lens = [
        p.pos.len(),
        p.vel.len(),
        p.spin.len(),
        p.rot.len(),
        p.force.len(),
        p.moment.len(),
        p.radius.len(),
        p.mass.len(),
        p.size.len(),
        p.material.len(),
        p.agg.len(),
        p.fixed.len(),
        p.disp.len(),
    ];
    if lens.iter().any(|&l| l != n) {
        return Err(format!(
            "particle arrays of unequal length ({n} ids, {lens:?})"
        ));
    }
    if scene.sizes.len() > MAX_SIZES || scene.materials.len() > MAX_MATERIALS {
        return Err("too many size or material types".into());
    }
    let mut ids = p.id.clone();
    ids.sort_unstable();
    if ids.windows(2).any(|w| w[0] == w[1]) {
        return Err("two particles share an id".into());
    }
    if ids.last().is_some_and(|&m| m >= scene.next_id) {
        return Err("a particle id is not below the next id".into());
    }
    for i in 0..n {
        let s = p.size[i] as usize;
        let m = p.material[i] as usize;
        if s == 0 || s > scene.sizes.len() || m == 0 || m > scene.materials.len() {
            return Err(format!(
                "particle {} has size type {s} or material type {m} out of range",
                p.id[i]
            ));
        }
        if !(p.radius[i] > 0.0 && p.mass[i] > 0.0) || p.agg[i] > 2 {
            return Err(format!(
                "particle {} has a bad radius, mass or agglomerate",
                p.id[i]
            ));
        }
    }
    for w in &scene.walls {
        if w.material == 0 || w.material > scene.materials.len() {
            return Err(format!(
                "a wall has material type {} out of range",
                w.material
            ));
        }
    }
    let c = &scene.contacts;
    for (k, pair) in c.pairs().iter().enumerate() {
        let (i, j) = (pair.i as usize, pair.j as usize);
        if i >= n || j >= n || pair.ida >= pair.idb {
            return Err("a contact refers to a particle that does not exist".into());
        }
        if !c.is_stale() && (p.id[i] != pair.ida || p.id[j] != pair.idb) {
            return Err("a contact's particle indices do not match its ids".into());
        }
        if k > 0 && (c.pairs()[k - 1].ida, c.pairs()[k - 1].idb) >= (pair.ida, pair.idb) {
            return Err("the contacts are not sorted by ids".into());
        }
    }
    for (k, wp) in c.wall_pairs.iter().enumerate() {
        if wp.i as usize >= n || wp.wall as usize >= scene.walls.len() {
            return Err("a wall contact refers to a particle or wall that does not exist".into());
        }
        if !c.is_stale() && p.id[wp.i as usize] != wp.id {
            return Err("a wall contact's particle index does not match its id".into());
        }
        if k > 0 && (c.wall_pairs[k - 1].id, c.wall_pairs[k - 1].wall) >= (wp.id, wp.wall) {
            return Err("the wall contacts are not sorted by ids".into());
        }
    }
    if let Some(r) = &scene.reference
        && (r.pos.len() != r.ids.len() || r.rot.len() != r.ids.len())
    {
        return Err("the reference state (PLot SAve) has arrays of unequal length".into());
    }
    let cols = crate::sim::history::COLUMNS.len();
    if scene.history.rows.iter().any(|r| r.len() != cols) {
        return Err("a history row has the wrong number of columns".into());
    }
    check_numbers(scene)
}

/// Every number of a decoded state is one the program could have written: finite, and
/// positive or within its range where the program keeps it so (a damaged payload with a
/// recomputed checksum can hold anything). The message names the first bad field.
fn check_numbers(scene: &Scene) -> Result<(), String> {
    check_scene_values(scene)?;
    check_particle_values(scene)?;
    check_wall_values(scene)?;
    check_contact_values(scene)?;
    check_ledger_values(scene)
}

fn fin(x: f64) -> bool {
    x.is_finite()
}

fn fin3(v: &[f64]) -> bool {
    v.iter().all(|x| x.is_finite())
}

fn bad(what: String) -> Result<(), String> {
    Err(what)
}

/// Part of [`check_numbers`]: the scene's own values: work-space, time, gravity, damping, liquid, settings, sizes, materials, regions.
fn check_scene_values(scene: &Scene) -> Result<(), String> {
    if !(scene.size.iter().all(|&x| x > 0.0 && x.is_finite())) {
        return bad("the work-space size is not positive and finite".into());
    }
    if !(scene.time >= 0.0 && fin(scene.time)) {
        return bad("the time is not finite".into());
    }
    if !fin3(&scene.gravity) || !fin3(&scene.cgravity) || !fin(scene.fmm) {
        return bad("gravity or its mass factor (FMM) is not finite".into());
    }
    for d in [&scene.damping_pp, &scene.damping_pw] {
        if !(d.alpha >= 0.0 && fin(d.alpha) && d.beta >= 0.0 && fin(d.beta)) {
            return bad("a damping coefficient is negative or not finite".into());
        }
    }
    if let Some(l) = &scene.liquid
        && !(l.pvol >= 0.0
            && fin(l.pvol)
            && l.gamma >= 0.0
            && fin(l.gamma)
            && fin(l.theta)
            && l.eta >= 0.0
            && fin(l.eta))
    {
        return bad("the liquid's parameters are negative or not finite".into());
    }
    let st = &scene.settings;
    for (name, v) in [
        ("TOL", st.tol),
        ("XRES", st.xres),
        ("SMIN", st.smin),
        ("FRAction", st.fraction),
        ("FRAgment", st.fragment_eps),
    ] {
        if let Some(x) = v
            && !(x > 0.0 && fin(x))
        {
            return bad(format!(
                "the setting {name} is {x}: not positive and finite"
            ));
        }
    }
    if let Some(x) = st.auto_step
        && !(x >= 0.0 && fin(x))
    {
        return bad(format!("the step of FRAction AUTO is {x}"));
    }
    if !(st.gen_overlap >= 0.0 && st.gen_overlap < 0.1) || st.window.is_some_and(|w| !fin3(&w)) {
        return bad("the setting GENoverlap or Window is out of range".into());
    }
    for (k, &r) in scene.sizes.iter().enumerate() {
        if !(r >= 0.0 && fin(r)) {
            return bad(format!("size type {} has radius {r}", k + 1));
        }
    }
    for (k, m) in scene.materials.iter().enumerate() {
        let ok = [m.density, m.young, m.friction, m.gamma, m.gamma_base]
            .iter()
            .all(|&x| x >= 0.0 && fin(x))
            && fin(m.poisson)
            && m.poisson < 0.5 + 1e-12
            && m.poisson > -1.0
            && m.restitution.is_none_or(|e| (0.0..=1.0).contains(&e));
        if !ok {
            return bad(format!("material type {} has a value out of range", k + 1));
        }
    }
    for (k, r) in scene.regions.iter().enumerate() {
        if let Some(r) = r
            && !(fin3(&r.centre) && r.radius > 0.0 && fin(r.radius))
        {
            return bad(format!("agglomerate region {} is not finite", k + 1));
        }
    }
    Ok(())
}

/// Part of [`check_numbers`]: the particles' vectors, radii, masses and liquid.
fn check_particle_values(scene: &Scene) -> Result<(), String> {
    let p = &scene.particles;
    for i in 0..p.len() {
        let named =
            |what: &str| Err::<(), String>(format!("particle {} has a non-finite {what}", p.id[i]));
        for (what, v) in [
            ("position", &p.pos[i]),
            ("velocity", &p.vel[i]),
            ("angular velocity", &p.spin[i]),
            ("rotation", &p.rot[i]),
            ("force", &p.force[i]),
            ("moment", &p.moment[i]),
            ("displacement", &p.disp[i]),
        ] {
            if !v.iter().all(|x| x.is_finite()) {
                return named(what);
            }
        }
        if !fin(p.radius[i]) || !fin(p.mass[i]) {
            return named("radius or mass");
        }
        if p.liquid.get(i).is_some_and(|&l| !(l >= 0.0 && fin(l))) {
            return named("liquid");
        }
    }
    Ok(())
}

/// Part of [`check_numbers`]: the walls' geometry, motion, servo and forces.
fn check_wall_values(scene: &Scene) -> Result<(), String> {
    for (k, w) in scene.walls.iter().enumerate() {
        use crate::sim::model::WallGeom;
        let geom_ok = match w.geom {
            WallGeom::Plane { normal, d } => {
                fin3(&normal) && normal.iter().any(|&x| x != 0.0) && fin(d)
            }
            WallGeom::Sphere { centre, radius } | WallGeom::Obstacle { centre, radius } => {
                fin3(&centre) && radius >= 0.0 && fin(radius)
            }
            WallGeom::Cylinder {
                point,
                axis,
                radius,
            } => {
                fin3(&point)
                    && fin3(&axis)
                    && axis.iter().any(|&x| x != 0.0)
                    && radius >= 0.0
                    && fin(radius)
            }
        };
        let servo_ok = w.servo.is_none_or(|s| {
            fin(s.force) && s.vmax >= 0.0 && fin(s.vmax) && s.gain >= 0.0 && fin(s.gain)
        });
        if !(geom_ok
            && servo_ok
            && fin3(&w.vel)
            && fin(w.vr)
            && fin3(&w.force)
            && fin(w.normal_force)
            && fin3(&w.disp)
            && w.travel >= 0.0
            && fin(w.travel))
        {
            return bad(format!(
                "wall {} has a geometry, motion or force out of range",
                k + 1
            ));
        }
    }
    Ok(())
}

/// Part of [`check_numbers`]: the contact states of particle pairs and particle–wall pairs, and the list's TOL.
fn check_contact_values(scene: &Scene) -> Result<(), String> {
    let state_ok = |s: &crate::sim::contacts::ContactState| {
        let e = s.ext();
        let t = &e.tang;
        let w = &e.walton;
        let ext_ok = [
            e.a_s,
            e.gamma,
            e.tdelta,
            t.t,
            t.stored,
            e.released[0],
            e.released[1],
            w.t_star,
            w.fn_prev,
            w.stored,
        ]
        .iter()
        .all(|x| x.is_finite())
            && e.delta.iter().all(|x| x.is_finite())
            && t.tp.iter().all(|x| x.is_finite())
            && (t.n_tp as usize) <= t.tp.len();
        let bridge_ok = s.bridge.as_deref().is_none_or(|b| {
            [
                b.volume, b.s_c, b.f_static, b.f_visc, b.gap, b.work, b.share[0], b.share[1],
            ]
            .iter()
            .all(|x| x.is_finite())
                && b.volume >= 0.0
                && b.f_tang.iter().all(|x| x.is_finite())
        });
        [s.overlap, s.normal_force, s.damp_force, s.tang_energy, s.a]
            .iter()
            .all(|x| x.is_finite())
            && s.a >= 0.0
            && (s.v_prev.is_finite() || s.v_prev.is_infinite())
            && s.tforce.iter().all(|x| x.is_finite())
            && s.tdamp.iter().all(|x| x.is_finite())
            && ext_ok
            && bridge_ok
    };
    for c in scene.contacts.iter() {
        if !state_ok(c.s) {
            return bad(format!(
                "the contact of particles {} and {} holds a value that is not finite",
                c.ida, c.idb
            ));
        }
    }
    for c in &scene.contacts.wall_pairs {
        if !state_ok(&c.s) {
            return bad(format!(
                "the contact of particle {} and wall {} holds a value that is not finite",
                c.id,
                c.wall + 1
            ));
        }
    }
    if !(scene.contacts.tol() >= 0.0 && fin(scene.contacts.tol())) {
        return bad("the candidate list's TOL is not finite".into());
    }
    Ok(())
}

/// Part of [`check_numbers`]: the energy ledger, the reference state and the history rows.
fn check_ledger_values(scene: &Scene) -> Result<(), String> {
    let l = &scene.ledger;
    if ![
        l.commands,
        l.gravity,
        l.walls,
        l.friction,
        l.damping_mass,
        l.damping_contact,
        l.viscous,
        l.adhesion,
        l.rupture,
    ]
    .iter()
    .all(|x| x.is_finite())
    {
        return bad("the energy ledger holds a value that is not finite".into());
    }
    if let Some(r) = &scene.reference
        && !(r.pos.iter().chain(&r.rot).all(|v| fin3(v)) && fin(r.kinetic))
    {
        return bad("the reference state (PLot SAve) holds a value that is not finite".into());
    }
    if scene
        .history
        .rows
        .iter()
        .any(|r| !r.iter().all(|x| x.is_finite()))
    {
        return bad("a history row holds a value that is not finite".into());
    }
    Ok(())
}

/// Writes atomically: a temporary file (`NAME.tmp`, or `NAME.EXT.tmp`) in the same directory,
/// flushed to disk, then renamed over the target. If anything fails the target is untouched.
/// The state is encoded twice, once to learn the length and checksum the header holds and
/// once into the file, so that no copy of the file is held in memory (the settled S1 bed of
/// 50,000 spheres: a 36 MB file).
pub fn save(scene: &Scene, path: &Path) -> Result<(), String> {
    let cfg = bincode::config::standard();
    let mut probe = Hashing::new(std::io::sink());
    bincode::serde::encode_into_std_write(scene, &mut probe, cfg)
        .map_err(|e| format!("cannot encode the state: {e}"))?;
    let (len, sum) = (probe.count, probe.hash);
    let tmp = path.with_extension(format!(
        "{}tmp",
        path.extension()
            .map(|e| format!("{}.", e.to_string_lossy()))
            .unwrap_or_default()
    ));
    let mut created = false;
    let mut write = || -> std::io::Result<()> {
        let f = File::create(&tmp)?;
        created = true;
        let mut w = BufWriter::with_capacity(1 << 16, f);
        w.write_all(&header(len, sum.0))?;
        let mut body = Hashing::new(&mut w);
        bincode::serde::encode_into_std_write(scene, &mut body, cfg)
            .map_err(|e| std::io::Error::other(format!("cannot encode the state: {e}")))?;
        if body.count != len || body.hash != sum {
            return Err(std::io::Error::other(
                "the state encoded to different bytes the second time",
            ));
        }
        let f = w.into_inner().map_err(|e| e.into_error())?;
        f.sync_all()
    };
    if let Err(e) = write() {
        if created {
            let _ = std::fs::remove_file(&tmp);
        }
        return Err(format!(
            "cannot save to {}: cannot write the temporary file {}: {e} (the old file, if any, is untouched)",
            path.display(),
            tmp.display()
        ));
    }
    std::fs::rename(&tmp, path).map_err(|e| {
        let _ = std::fs::remove_file(&tmp);
        format!(
            "cannot save to {}: cannot rename {} over it: {e} (the old file, if any, is untouched)",
            path.display(),
            tmp.display()
        )
    })
}

/// Reads a checkpoint file. A regular file is read twice: its checksum is verified in a
/// first pass and the state decoded in a second, so that the file's bytes are never held in
/// memory next to the decoded state (the settled S1 bed of 50,000 spheres: a 36 MB file;
/// `RESTart` peaked at 89 MB against the 61 MB of the run that saved it). The second pass is
/// checked against the checksum too: a file that changed between the passes is refused.
pub fn load(path: &Path) -> Result<Scene, String> {
    load_between(path, || {})
}

/// [`load`] with `between` run after the checksum pass and before the decoding pass (for
/// the test of a file that changes between them).
#[doc(hidden)]
pub fn load_between(path: &Path, between: impl FnOnce()) -> Result<Scene, String> {
    let at = |e: String| format!("{}: {e}", path.display());
    let cannot = |e: std::io::Error| format!("cannot read {}: {e}", path.display());
    let mut f = File::open(path).map_err(cannot)?;
    let meta = f.metadata().map_err(cannot)?;
    if !meta.is_file() {
        // A pipe or a device: read it whole.
        let mut data = Vec::new();
        f.read_to_end(&mut data).map_err(cannot)?;
        return from_bytes(&data).map_err(at);
    }
    let total = meta.len();
    let mut prefix = vec![0u8; total.min(HEADER as u64) as usize];
    f.read_exact(&mut prefix).map_err(cannot)?;
    let (version, len, sum) = read_header(&prefix, total).map_err(at)?;
    let changed = || at("the checkpoint changed while it was read: read it again".into());
    let mut check = Hashing::new(std::io::sink());
    std::io::copy(&mut (&mut f).take(len), &mut check).map_err(cannot)?;
    if check.count != len {
        return Err(changed());
    }
    if check.hash.0 != sum {
        return Err(at("the checkpoint is corrupt (checksum mismatch)".into()));
    }
    between();
    f.seek(SeekFrom::Start(HEADER as u64)).map_err(cannot)?;
    let mut r = Hashing::new(BufReader::with_capacity(1 << 16, (&mut f).take(len)));
    let scene = decode_payload(version, &mut r).map_err(at)?;
    let used = r.count;
    std::io::copy(&mut r, &mut std::io::sink()).map_err(cannot)?;
    if r.count != len || r.hash.0 != sum {
        return Err(changed());
    }
    if used != len {
        return Err(at(
            "the checkpoint is corrupt: trailing bytes after the state".into(),
        ));
    }
    check_consistency(&scene).map_err(|e| at(format!("the checkpoint is inconsistent: {e}")))?;
    Ok(scene)
}
