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
//! NGUYEN`) and `NormalHistory::Nguyen`, which older files never hold; version 7 may hold
//! the new last variant `NormalLaw::ModifiedJkrEdem` (`SET NORmal MJKR EDEM [ROLling]`), which older
//! files never hold, and reads version 6 with the same types; version 8 may hold the new last
//! variant `TangentialChoice::HertzMindlin` (`SET TANgential HM`), and reads 6 and 7 with
//! the same types; version 9 adds the ledger's `unbooked` (the residual commands left, which
//! the energy audit of every Cycle measures from; read as unknown from older files), the
//! spring row of `SET TANgential MDR` (`mdr`) to the law-specific part of the contact state
//! (read as none from older files, through `sim::contacts::old`), and may hold the new last
//! variant `TangentialChoice::Mdr`, which older files never hold; version 10 adds the named
//! groups (`GROup`, `Scene::groups`, read as none from older files), the dashpot forms of
//! the material pairs (`SET DASHpot`, `ContactLaws::dashpot`, read as trubal's everywhere from
//! older files) and, after the scene, the command language's state
//! (`session::script::ScriptState`: the variables and procedures; read as none from older
//! files); version 11 adds the last evaluated point of a JKR contact's step path (`end`,
//! `physics::jkr::PathEnd`) to the law-specific part of the contact state (read as none
//! from older files: the next step solves (3.29) at the start of its path, as before);
//! version 12 adds the setting `wall_bridges` (`SET WALlbridges`, read as on from older
//! files, which always made particle–wall bridges); version 13 adds a group's standing Fix
//! (`Fix ... GROup name` over a dynamic group, `sim::range::StandingFix`; read as none from
//! formats 10 to 12, through `scene::old_groups`); version 14 adds what the last `Cycle`
//! handed on to the next (`Scene::carried`, `scene::Carried`: the energy audit's reference,
//! the work in flight at its end, the walls' velocities of their last step and the stress
//! servo it ended with), so that a command or a servo `Cycle` after a RESTart does what it
//! does in the uninterrupted session (read from older files as `Carried::unknown`, through
//! `scene::old_carried`: the audit's reference taken at the RESTart, nothing in flight).
//! Versions 1 to 13
//! are read through `sim::contacts::old` (contact states), `scene::old_walls`,
//! `scene::old_cell`, `scene::old_laws` and
//! `scene::old_settings`, which read the types that changed in the layout of the version
//! being decoded.

use std::fs::File;
use std::io::{BufReader, BufWriter, Read, Seek, SeekFrom, Write};
use std::path::Path;

use crate::session::script::ScriptState;
use crate::sim::Scene;

pub const MAGIC: &[u8; 8] = b"TRUBALCK";
/// Format version written by this program.
pub const VERSION: u32 = 14;
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
    // (Invariant: `prefix` holds at least HEADER bytes, checked above; the slices below are
    // of fixed length.)
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

/// Serialises a scene to bytes (without variables or procedures).
pub fn to_bytes(scene: &Scene) -> Result<Vec<u8>, String> {
    let mut out = vec![0u8; HEADER];
    let state = (scene, &ScriptState::default());
    bincode::serde::encode_into_std_write(state, &mut out, bincode::config::standard())
        .map_err(|e| format!("cannot encode the state: {e}"))?;
    let payload = &out[HEADER..];
    let h = header(payload.len() as u64, fnv1a(payload));
    out[..HEADER].copy_from_slice(&h);
    Ok(out)
}

/// Reads a scene from bytes, refusing anything that is not a complete checkpoint of a
/// version this program reads.
pub fn from_bytes(data: &[u8]) -> Result<Scene, String> {
    from_bytes_with(data).map(|(s, _)| s)
}

/// [`from_bytes`] with the command language's state.
pub fn from_bytes_with(data: &[u8]) -> Result<(Scene, ScriptState), String> {
    let (version, _, sum) = read_header(&data[..data.len().min(HEADER)], data.len() as u64)?;
    let payload = &data[HEADER..];
    if fnv1a(payload) != sum {
        return Err("the checkpoint is corrupt (checksum mismatch)".into());
    }
    let mut r = payload;
    let (mut scene, script) = decode_payload(version, &mut r)?;
    if !r.is_empty() {
        return Err("the checkpoint is corrupt: trailing bytes after the state".into());
    }
    scene
        .check_consistency()
        .map_err(|e| format!("the checkpoint is inconsistent: {e}"))?;
    scene.resume_audit();
    Ok((scene, script))
}

/// Decodes the payload of a given (readable) format version into the current [`Scene`],
/// reading no more than the state's bytes from `r`.
fn decode_payload<R: Read>(version: u32, r: &mut R) -> Result<(Scene, ScriptState), String> {
    let mut scene = decode_version(version, r)?;
    scene.shrink_to_fit();
    let script = if version >= 10 {
        decode_all::<ScriptState, R>(r, version)?
    } else {
        ScriptState::default()
    };
    Ok((scene, script))
}

fn decode_version<R: Read>(version: u32, r: &mut R) -> Result<Scene, String> {
    match version {
        // Version 6 differs only in never holding `NormalLaw::ModifiedJkrEdem`, 6 and 7 in
        // never holding `TangentialChoice::HertzMindlin`.
        VERSION => decode_all::<Scene, R>(r, version),
        // Version 13 differs in having nothing carried from the last Cycle
        // (scene::old_carried), as all older ones; 12 also in the groups (no standing Fix,
        // scene::old_groups), 11 also in the settings (no `wall_bridges`,
        // scene::old_settings).
        11..=13 => {
            crate::sim::contacts::old::reading(version, || decode_all::<Scene, R>(r, version))
        }
        // Version 10 differs in the contact state (no `end`, sim::contacts::old); version 9
        // also in having no groups (scene::old_groups) and no dashpot forms in the contact
        // laws (scene::old_laws).
        9 | 10 => {
            crate::sim::contacts::old::reading(version, || decode_all::<Scene, R>(r, version))
        }
        // Versions 6 to 8 differ in the ledger (no `unbooked`, scene::old_ledger) and the
        // contact state (no `mdr`, sim::contacts::old).
        6..=8 => crate::sim::contacts::old::reading(version, || decode_all::<Scene, R>(r, version)),
        // Versions 1 to 4 differ in the layout of the contact state (sim::contacts::old; for
        // version 3 the law-specific part had no `walton`, for 4 no `normal`), have no
        // contact laws (scene::old_laws), the walls and settings of 1 and 2
        // (scene::old_walls, old_settings), and have no cell (scene::old_cell).
        // Version 5 differs in the contact laws (no `pair_values`, scene::old_laws), and as
        // 6 to 8.
        5 => crate::sim::contacts::old::reading(version, || decode_all::<Scene, R>(r, version)),
        1..=4 => crate::sim::contacts::old::reading(version, || decode_all::<Scene, R>(r, version))
            .map(|mut s| {
                // Their history rows have the first 10 columns: the stress, temperature and
                // strain columns of format 4 read as 0.
                s.pad_history_rows();
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

/// Writes atomically: a temporary file (`NAME.tmp`, or `NAME.EXT.tmp`) in the same directory,
/// flushed to disk, then renamed over the target. If anything fails the target is untouched.
/// The state is encoded twice, once to learn the length and checksum the header holds and
/// once into the file, so that no copy of the file is held in memory (the settled S1 bed of
/// 50,000 spheres: a 36 MB file).
pub fn save(scene: &Scene, path: &Path) -> Result<(), String> {
    save_with(scene, &ScriptState::default(), path)
}

/// [`save`] with the command language's variables and procedures.
pub fn save_with(scene: &Scene, script: &ScriptState, path: &Path) -> Result<(), String> {
    let scene = &(scene, script);
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
    load_between(path, || {}).map(|(s, _)| s)
}

/// [`load`] with the command language's variables and procedures (none from a file of
/// version 9 or older).
pub fn load_with(path: &Path) -> Result<(Scene, ScriptState), String> {
    load_between(path, || {})
}

/// [`load`] with `between` run after the checksum pass and before the decoding pass (for
/// the test of a file that changes between them).
#[doc(hidden)]
pub fn load_between(path: &Path, between: impl FnOnce()) -> Result<(Scene, ScriptState), String> {
    let at = |e: String| format!("{}: {e}", path.display());
    let cannot = |e: std::io::Error| format!("cannot read {}: {e}", path.display());
    let mut f = File::open(path).map_err(cannot)?;
    let meta = f.metadata().map_err(cannot)?;
    if !meta.is_file() {
        // A pipe or a device: read it whole.
        let mut data = Vec::new();
        f.read_to_end(&mut data).map_err(cannot)?;
        return from_bytes_with(&data).map_err(at);
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
    let (mut scene, script) = decode_payload(version, &mut r).map_err(at)?;
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
    scene
        .check_consistency()
        .map_err(|e| at(format!("the checkpoint is inconsistent: {e}")))?;
    scene.resume_audit();
    Ok((scene, script))
}
