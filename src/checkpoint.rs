//! Checkpoints (`SAve`/`RESTart`): bincode 2 through serde. Layout: the magic bytes
//! `TRUBALCK`, a little-endian u32 format version, a u64 length and an FNV-1a 64 checksum of
//! the payload, then the payload (the whole [`Scene`]). A file is refused with a reason when
//! the magic, the version, the length or the checksum does not match, and the current state is
//! untouched. Saving writes a temporary file and renames it over the target.

use std::io::Write;
use std::path::Path;

use crate::sim::Scene;

pub const MAGIC: &[u8; 8] = b"TRUBALCK";
pub const VERSION: u32 = 1;
const HEADER: usize = 8 + 4 + 8 + 8;

fn fnv1a(data: &[u8]) -> u64 {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for &b in data {
        h ^= b as u64;
        h = h.wrapping_mul(0x0000_0100_0000_01b3);
    }
    h
}

/// Serialises a scene to bytes.
pub fn to_bytes(scene: &Scene) -> Result<Vec<u8>, String> {
    let payload = bincode::serde::encode_to_vec(scene, bincode::config::standard())
        .map_err(|e| format!("cannot encode the state: {e}"))?;
    let mut out = Vec::with_capacity(HEADER + payload.len());
    out.extend_from_slice(MAGIC);
    out.extend_from_slice(&VERSION.to_le_bytes());
    out.extend_from_slice(&(payload.len() as u64).to_le_bytes());
    out.extend_from_slice(&fnv1a(&payload).to_le_bytes());
    out.extend_from_slice(&payload);
    Ok(out)
}

/// Reads a scene from bytes, refusing anything that is not a complete checkpoint of a
/// version this program reads.
pub fn from_bytes(data: &[u8]) -> Result<Scene, String> {
    if data.is_empty() {
        return Err("the file is empty".into());
    }
    if data.len() < 8 || &data[..8] != MAGIC {
        return Err("not a trubal checkpoint (no TRUBALCK header)".into());
    }
    if data.len() < HEADER {
        return Err("the checkpoint is truncated (incomplete header)".into());
    }
    let version = u32::from_le_bytes(data[8..12].try_into().expect("4 bytes"));
    if version > VERSION {
        return Err(format!(
            "the checkpoint has format version {version}, newer than this program's version {VERSION}: use a newer trubal"
        ));
    }
    if version < 1 {
        return Err(format!(
            "the checkpoint has format version {version}, which no trubal wrote (this program reads 1..={VERSION})"
        ));
    }
    let len = u64::from_le_bytes(data[12..20].try_into().expect("8 bytes")) as usize;
    let sum = u64::from_le_bytes(data[20..28].try_into().expect("8 bytes"));
    let payload = &data[HEADER..];
    if payload.len() != len {
        return Err(format!(
            "the checkpoint is truncated or padded: {} payload bytes, header says {len}",
            payload.len()
        ));
    }
    if fnv1a(payload) != sum {
        return Err("the checkpoint is corrupt (checksum mismatch)".into());
    }
    let (scene, used): (Scene, usize) =
        bincode::serde::decode_from_slice(payload, bincode::config::standard())
            .map_err(|e| format!("the checkpoint is corrupt: {e}"))?;
    if used != payload.len() {
        return Err("the checkpoint has trailing bytes".into());
    }
    Ok(scene)
}

/// Writes atomically: temporary file in the same directory, then rename.
pub fn save(scene: &Scene, path: &Path) -> Result<(), String> {
    let bytes = to_bytes(scene)?;
    let tmp = path.with_extension(format!(
        "{}tmp",
        path.extension()
            .map(|e| format!("{}.", e.to_string_lossy()))
            .unwrap_or_default()
    ));
    let write = || -> std::io::Result<()> {
        let mut f = std::fs::File::create(&tmp)?;
        f.write_all(&bytes)?;
        f.sync_all()?;
        std::fs::rename(&tmp, path)
    };
    write().map_err(|e| {
        let _ = std::fs::remove_file(&tmp);
        format!("cannot save to {}: {e}", path.display())
    })
}

pub fn load(path: &Path) -> Result<Scene, String> {
    let data = std::fs::read(path).map_err(|e| format!("cannot read {}: {e}", path.display()))?;
    from_bytes(&data).map_err(|e| format!("{}: {e}", path.display()))
}
