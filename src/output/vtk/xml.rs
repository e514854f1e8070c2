//! A small writer of VTK XML PolyData (`.vtp`) and ImageData (`.vti`) files with every
//! array in one appended raw block, `<AppendedData encoding="raw">_`, as the VTK
//! file-format document ("VTK XML Formats", appended data; `vtkXMLWriter`) lays it out,
//! headers `header_type="UInt64"`, values in the machine's byte order. Uncompressed, an
//! array is its length in bytes and its bytes. Compressed (`compressor=
//! "vtkZLibDataCompressor"`, [`Encoding::Zlib`]), its bytes are cut in blocks of
//! [`BLOCK`] bytes (the last one shorter), each deflated on its own as a zlib stream, and
//! the array is the header [number of blocks, block size, size of the last block if
//! partial else 0, compressed size of each block] followed by the compressed blocks. The
//! blocks are compressed in parallel; each alone, so the bytes do not depend on the
//! threads. Why a writer of our own rather than a crate, and why zlib at level 1:
//! doc/design.md, "Choices" (VTK output).

use rayon::prelude::*;

/// How the appended block is stored.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Encoding {
    /// zlib (deflate level 1) in blocks: the default.
    #[default]
    Zlib,
    /// The bytes as they are (`VTk … RAW`).
    Raw,
}

/// Uncompressed bytes per compressed block (VTK's own default is 32 KiB; a block costs 8
/// bytes of header and restarts deflate's 32 KiB window, so 64 KiB blocks lose nothing).
pub const BLOCK: usize = 1 << 16;

/// `bytes` as the zlib-compressed array of the appended block: header, then blocks.
fn zlib_array(bytes: &[u8]) -> Vec<u8> {
    use std::io::Write;
    let blocks: Vec<Vec<u8>> = bytes
        .par_chunks(BLOCK)
        .map(|b| {
            let mut z = flate2::write::ZlibEncoder::new(
                Vec::with_capacity(b.len() / 2),
                flate2::Compression::fast(),
            );
            // (Invariant: compressing into a Vec cannot fail.)
            z.write_all(b).expect("writing to memory");
            z.finish().expect("writing to memory")
        })
        .collect();
    let mut out =
        Vec::with_capacity(24 + 8 * blocks.len() + blocks.iter().map(Vec::len).sum::<usize>());
    for h in [blocks.len(), BLOCK, bytes.len() % BLOCK] {
        out.extend_from_slice(&(h as u64).to_le_bytes());
    }
    for b in &blocks {
        out.extend_from_slice(&(b.len() as u64).to_le_bytes());
    }
    for b in &blocks {
        out.extend_from_slice(b);
    }
    out
}

/// The values of one data array.
pub enum Values {
    F64(Vec<f64>),
    F32(Vec<f32>),
    I32(Vec<i32>),
    I64(Vec<i64>),
    U8(Vec<u8>),
}

impl Values {
    fn type_name(&self) -> &'static str {
        match self {
            Values::F64(_) => "Float64",
            Values::F32(_) => "Float32",
            Values::I32(_) => "Int32",
            Values::I64(_) => "Int64",
            Values::U8(_) => "UInt8",
        }
    }
    fn len(&self) -> usize {
        match self {
            Values::F64(v) => v.len(),
            Values::F32(v) => v.len(),
            Values::I32(v) => v.len(),
            Values::I64(v) => v.len(),
            Values::U8(v) => v.len(),
        }
    }
    fn bytes(&self) -> &[u8] {
        match self {
            Values::F64(v) => bytemuck::cast_slice(v),
            Values::F32(v) => bytemuck::cast_slice(v),
            Values::I32(v) => bytemuck::cast_slice(v),
            Values::I64(v) => bytemuck::cast_slice(v),
            Values::U8(v) => v,
        }
    }
}

/// A named array of `components` values per tuple.
pub struct Array {
    pub name: String,
    pub components: usize,
    pub values: Values,
}

impl Array {
    pub fn new(name: &str, components: usize, values: Values) -> Array {
        Array {
            name: name.to_string(),
            components,
            values,
        }
    }
    /// A vector array (3 components) from 3-vectors, in single precision.
    pub fn vectors(name: &str, v: impl Iterator<Item = [f64; 3]>) -> Array {
        let mut out = Vec::new();
        for x in v {
            out.extend(x.iter().map(|&c| c as f32));
        }
        Array::new(name, 3, Values::F32(out))
    }
    /// A scalar array in single precision.
    pub fn scalars(name: &str, v: impl Iterator<Item = f64>) -> Array {
        Array::new(name, 1, Values::F32(v.map(|x| x as f32).collect()))
    }
    fn tuples(&self) -> usize {
        self.values.len() / self.components.max(1)
    }
}

/// Cells of one kind (vertices, lines or polygons): the point indices of every cell in a
/// row, and where each cell ends in that row.
#[derive(Default)]
pub struct Cells {
    pub connectivity: Vec<i64>,
    pub offsets: Vec<i64>,
}

impl Cells {
    /// Appends a cell through these points.
    pub fn push(&mut self, points: &[usize]) {
        self.connectivity.extend(points.iter().map(|&k| k as i64));
        self.offsets.push(self.connectivity.len() as i64);
    }
    pub fn len(&self) -> usize {
        self.offsets.len()
    }
    pub fn is_empty(&self) -> bool {
        self.offsets.is_empty()
    }
}

/// One PolyData piece: points, cells, and the arrays on points, cells and the whole set
/// (field data: the time and cycle of the frame); `single`: the points written in single
/// precision (`VTk SINgle`), else double.
#[derive(Default)]
pub struct PolyData {
    pub points: Vec<[f64; 3]>,
    pub single: bool,
    pub verts: Cells,
    pub lines: Cells,
    pub polys: Cells,
    pub point_data: Vec<Array>,
    pub cell_data: Vec<Array>,
    pub field_data: Vec<Array>,
}

/// Collects the XML header and the appended block as arrays are declared.
struct Out {
    xml: String,
    data: Vec<u8>,
    encoding: Encoding,
}

impl Out {
    fn array(&mut self, indent: &str, a: &Array, field: bool) {
        let tuples = if field {
            format!(" NumberOfTuples=\"{}\"", a.tuples())
        } else {
            String::new()
        };
        self.xml.push_str(&format!(
            "{indent}<DataArray type=\"{}\" Name=\"{}\" NumberOfComponents=\"{}\"{tuples} format=\"appended\" offset=\"{}\"/>\n",
            a.values.type_name(),
            escape(&a.name),
            a.components,
            self.data.len()
        ));
        let bytes = a.values.bytes();
        match self.encoding {
            Encoding::Raw => {
                self.data
                    .extend_from_slice(&(bytes.len() as u64).to_le_bytes());
                self.data.extend_from_slice(bytes);
            }
            Encoding::Zlib => self.data.extend_from_slice(&zlib_array(bytes)),
        }
    }

    /// The cells' connectivity and offsets, as Int32 when every index fits (half the
    /// bytes; VTK reads either type into its cell arrays), else as Int64.
    fn cells(&mut self, tag: &str, c: &Cells) {
        self.xml.push_str(&format!("      <{tag}>\n"));
        let small = c.offsets.last().is_none_or(|&n| n <= i32::MAX as i64)
            && c.connectivity.iter().all(|&k| k <= i32::MAX as i64);
        let values = |v: &[i64]| {
            if small {
                Values::I32(v.iter().map(|&k| k as i32).collect())
            } else {
                Values::I64(v.to_vec())
            }
        };
        let conn = Array::new("connectivity", 1, values(&c.connectivity));
        let offs = Array::new("offsets", 1, values(&c.offsets));
        self.array("        ", &conn, false);
        self.array("        ", &offs, false);
        self.xml.push_str(&format!("      </{tag}>\n"));
    }
}

/// The `<VTKFile …>` line of a file of this type and encoding.
fn head(kind: &str, encoding: Encoding) -> String {
    let order = if cfg!(target_endian = "little") {
        "LittleEndian"
    } else {
        "BigEndian"
    };
    let compressor = match encoding {
        Encoding::Zlib => " compressor=\"vtkZLibDataCompressor\"",
        Encoding::Raw => "",
    };
    format!(
        "<?xml version=\"1.0\"?>\n<VTKFile type=\"{kind}\" version=\"1.0\" byte_order=\"{order}\" header_type=\"UInt64\"{compressor}>\n"
    )
}

/// The whole `.vtp` file.
pub fn encode(p: &PolyData, encoding: Encoding) -> Vec<u8> {
    let mut o = Out {
        xml: head("PolyData", encoding) + "  <PolyData>\n",
        data: Vec::new(),
        encoding,
    };
    if !p.field_data.is_empty() {
        o.xml.push_str("    <FieldData>\n");
        for a in &p.field_data {
            o.array("      ", a, true);
        }
        o.xml.push_str("    </FieldData>\n");
    }
    o.xml.push_str(&format!(
        "    <Piece NumberOfPoints=\"{}\" NumberOfVerts=\"{}\" NumberOfLines=\"{}\" NumberOfStrips=\"0\" NumberOfPolys=\"{}\">\n",
        p.points.len(),
        p.verts.len(),
        p.lines.len(),
        p.polys.len()
    ));
    for (tag, arrays) in [("PointData", &p.point_data), ("CellData", &p.cell_data)] {
        o.xml.push_str(&format!("      <{tag}>\n"));
        for a in arrays {
            o.array("        ", a, false);
        }
        o.xml.push_str(&format!("      </{tag}>\n"));
    }
    o.xml.push_str("      <Points>\n");
    let coords = p.points.iter().flatten().copied();
    let pts = if p.single {
        Array::new("Points", 3, Values::F32(coords.map(|x| x as f32).collect()))
    } else {
        Array::new("Points", 3, Values::F64(coords.collect()))
    };
    o.array("        ", &pts, false);
    o.xml.push_str("      </Points>\n");
    o.cells("Verts", &p.verts);
    o.cells("Lines", &p.lines);
    o.cells("Strips", &Cells::default());
    o.cells("Polys", &p.polys);
    o.xml
        .push_str("    </Piece>\n  </PolyData>\n  <AppendedData encoding=\"raw\">\n   _");
    let mut bytes = o.xml.into_bytes();
    bytes.extend_from_slice(&o.data);
    bytes.extend_from_slice(b"\n  </AppendedData>\n</VTKFile>\n");
    bytes
}

/// A `.vti` file: ImageData of `n` nodes, the first at `origin`, `spacing` apart (x
/// fastest), with its point arrays.
pub fn encode_image(
    n: [usize; 3],
    origin: [f64; 3],
    spacing: [f64; 3],
    point_data: &[Array],
    field_data: &[Array],
    encoding: Encoding,
) -> Vec<u8> {
    let extent = format!("0 {} 0 {} 0 {}", n[0] - 1, n[1] - 1, n[2] - 1);
    let mut o = Out {
        xml: head("ImageData", encoding)
            + &format!(
                "  <ImageData WholeExtent=\"{extent}\" Origin=\"{:e} {:e} {:e}\" Spacing=\"{:e} {:e} {:e}\">\n",
                origin[0], origin[1], origin[2], spacing[0], spacing[1], spacing[2]
            ),
        data: Vec::new(),
        encoding,
    };
    if !field_data.is_empty() {
        o.xml.push_str("    <FieldData>\n");
        for a in field_data {
            o.array("      ", a, true);
        }
        o.xml.push_str("    </FieldData>\n");
    }
    o.xml.push_str(&format!(
        "    <Piece Extent=\"{extent}\">\n      <PointData>\n"
    ));
    for a in point_data {
        o.array("        ", a, false);
    }
    o.xml.push_str(
        "      </PointData>\n      <CellData>\n      </CellData>\n    </Piece>\n  </ImageData>\n  <AppendedData encoding=\"raw\">\n   _",
    );
    let mut bytes = o.xml.into_bytes();
    bytes.extend_from_slice(&o.data);
    bytes.extend_from_slice(b"\n  </AppendedData>\n</VTKFile>\n");
    bytes
}

/// `&`, `<`, `>` and `"` as XML entities (names and file names in attributes).
pub fn escape(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The appended block holds each array as its byte count and its bytes, at the offset
    /// the header names.
    #[test]
    fn arrays_sit_at_their_offsets() {
        let mut p = PolyData {
            points: vec![[1.0, 2.0, 3.0], [4.0, 5.0, 6.0]],
            ..Default::default()
        };
        p.lines.push(&[0, 1]);
        p.cell_data.push(Array::scalars("f", [7.5].into_iter()));
        let bytes = encode(&p, Encoding::Raw);
        let text = String::from_utf8_lossy(&bytes);
        let start = text.find("encoding=\"raw\">\n   _").unwrap() + "encoding=\"raw\">\n   _".len();
        let at = |name: &str| -> usize {
            let k = text.find(&format!("Name=\"{name}\"")).unwrap();
            let o = text[k..].find("offset=\"").unwrap() + k + 8;
            let e = text[o..].find('"').unwrap() + o;
            text[o..e].parse().unwrap()
        };
        let f = start + at("f");
        assert_eq!(u64::from_le_bytes(bytes[f..f + 8].try_into().unwrap()), 4);
        assert_eq!(
            f32::from_le_bytes(bytes[f + 8..f + 12].try_into().unwrap()),
            7.5
        );
        let pt = start + at("Points");
        assert_eq!(
            u64::from_le_bytes(bytes[pt..pt + 8].try_into().unwrap()),
            48
        );
        assert_eq!(
            f64::from_le_bytes(bytes[pt + 32..pt + 40].try_into().unwrap()),
            4.0
        );
    }

    /// The cells' indices as Int32 (they fit), the points as Float32 with `single`: the
    /// types the header names, and the bytes at their offsets.
    #[test]
    fn small_indices_and_single_points() {
        let mut p = PolyData {
            points: vec![[1.0, 2.0, 0.1], [4.0, 5.0, 6.0]],
            single: true,
            ..Default::default()
        };
        p.lines.push(&[0, 1]);
        let bytes = encode(&p, Encoding::Raw);
        let text = String::from_utf8_lossy(&bytes);
        let start = text.find("encoding=\"raw\">\n   _").unwrap() + "encoding=\"raw\">\n   _".len();
        // The first array of this name after `after` (the lines' cells follow the vertices').
        let at = |after: &str, name: &str, ty: &str| -> usize {
            let from = text.find(after).unwrap();
            let k = text[from..].find(&format!("Name=\"{name}\"")).unwrap() + from;
            let tag = &text[text[..k].rfind('<').unwrap()..];
            assert!(
                tag.starts_with(&format!("<DataArray type=\"{ty}\"")),
                "{name}"
            );
            let o = text[k..].find("offset=\"").unwrap() + k + 8;
            let e = text[o..].find('"').unwrap() + o;
            start + text[o..e].parse::<usize>().unwrap()
        };
        let pt = at("<Points>", "Points", "Float32");
        assert_eq!(
            u64::from_le_bytes(bytes[pt..pt + 8].try_into().unwrap()),
            24
        );
        let x = f32::from_le_bytes(bytes[pt + 16..pt + 20].try_into().unwrap());
        assert_eq!(x, 0.1f32);
        let c = at("<Lines>", "connectivity", "Int32");
        let word = |k: usize| i32::from_le_bytes(bytes[k..k + 4].try_into().unwrap());
        assert_eq!(u64::from_le_bytes(bytes[c..c + 8].try_into().unwrap()), 8);
        assert_eq!((word(c + 8), word(c + 12)), (0, 1));
        let o = at("<Lines>", "offsets", "Int32");
        assert_eq!(word(o + 8), 2);
    }

    /// A compressed array: the header counts the blocks, the block size and the last
    /// block's, and each block's compressed length; inflating the blocks in order gives
    /// the array's bytes back (200,000 doubles: three whole blocks and a partial one).
    #[test]
    fn zlib_blocks_inflate_to_the_array() {
        use std::io::Read;
        let v: Vec<f64> = (0..200_000).map(|k| (k as f64).sin()).collect();
        let raw: &[u8] = bytemuck::cast_slice(&v);
        let z = zlib_array(raw);
        let word = |k: usize| u64::from_le_bytes(z[8 * k..8 * k + 8].try_into().unwrap()) as usize;
        assert_eq!(raw.len(), 1_600_000);
        assert_eq!(
            (word(0), word(1), word(2)),
            (25, BLOCK, 1_600_000 - 24 * BLOCK)
        );
        let mut at = 8 * (3 + word(0));
        let mut back = Vec::new();
        for b in 0..word(0) {
            let n = word(3 + b);
            flate2::read::ZlibDecoder::new(&z[at..at + n])
                .read_to_end(&mut back)
                .unwrap();
            at += n;
        }
        assert_eq!(at, z.len());
        assert_eq!(back, raw);
        // An empty array: no block.
        assert_eq!(
            zlib_array(&[]),
            [0u64, BLOCK as u64, 0].map(u64::to_le_bytes).concat()
        );
    }
}
