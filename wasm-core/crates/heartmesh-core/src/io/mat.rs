//! MATLAB level-5 MAT-files ("MAT-File Format", MathWorks, version 5 documentation), as written
//! by the SurFCo toolbox: a cell array of Nx3 double matrices, one per contour. Uncompressed and
//! zlib-compressed (miCOMPRESSED) elements, either byte order, numeric arrays of any class
//! (MATLAB stores doubles with integral values in smaller integer types), cells and structs.

use super::builder::ContourBuilder;
use crate::contours::ContourSet;
use crate::error::{CoreError, Result};
use crate::geometry::v3;

const MI_INT8: u32 = 1;
const MI_MATRIX: u32 = 14;
const MI_COMPRESSED: u32 = 15;
const MX_CELL: u8 = 1;
const MX_STRUCT: u8 = 2;

/// Decompressed data above this size is refused (a zip bomb guard far above real contour files).
const MAX_INFLATED: usize = 512 << 20;
/// Nesting deeper than this is not a contour file.
const MAX_DEPTH: usize = 16;

fn err(msg: impl Into<String>) -> CoreError {
    CoreError::parse(0, msg)
}

/// True when the bytes start like a level-5 MAT-file.
pub fn is_mat(bytes: &[u8]) -> bool {
    bytes.starts_with(b"MATLAB 5.0 MAT-file")
}

struct Reader {
    big: bool,
    /// Nx3 matrices found, in file order.
    matrices: Vec<Vec<[f64; 3]>>,
}

impl Reader {
    fn u32_at(&self, b: &[u8], at: usize) -> Option<u32> {
        let s: [u8; 4] = b.get(at..at + 4)?.try_into().ok()?;
        Some(if self.big {
            u32::from_be_bytes(s)
        } else {
            u32::from_le_bytes(s)
        })
    }

    /// Splits `b` at `at` into (type, data, next offset), handling the small-element form.
    fn element<'a>(&self, b: &'a [u8], at: usize) -> Result<(u32, &'a [u8], usize)> {
        let tag = self
            .u32_at(b, at)
            .ok_or_else(|| err(format!("truncated element tag at byte {at}")))?;
        // Small data element: size in the upper 16 bits, data in the next 4 bytes.
        // (In big-endian files the halves are swapped accordingly by reading as u32.)
        let small = tag >> 16;
        if small != 0 {
            let n = small as usize;
            if n > 4 {
                return Err(err(format!("bad small element size {n} at byte {at}")));
            }
            let data = b
                .get(at + 4..at + 4 + n)
                .ok_or_else(|| err(format!("truncated element at byte {at}")))?;
            return Ok((tag & 0xffff, data, at + 8));
        }
        let n = self
            .u32_at(b, at + 4)
            .ok_or_else(|| err(format!("truncated element tag at byte {at}")))?
            as usize;
        let start = at + 8;
        let data = b.get(start..start.saturating_add(n)).ok_or_else(|| {
            err(format!(
                "element at byte {at} declares {n} bytes but the file ends first (truncated)"
            ))
        })?;
        // Compressed elements are not padded; everything else is padded to 8 bytes.
        let next = if tag == MI_COMPRESSED {
            start + n
        } else {
            start + n.div_ceil(8) * 8
        };
        Ok((tag, data, next))
    }

    /// Reads the elements of `b` (top level or an inflated block).
    fn elements(&mut self, b: &[u8], depth: usize) -> Result<()> {
        let mut at = 0;
        while at + 8 <= b.len() {
            let (ty, data, next) = self.element(b, at)?;
            match ty {
                MI_COMPRESSED => {
                    if depth > 1 {
                        return Err(err("nested compressed elements"));
                    }
                    let inflated =
                        miniz_oxide::inflate::decompress_to_vec_zlib_with_limit(data, MAX_INFLATED)
                            .map_err(|e| {
                                err(format!(
                                    "compressed element at byte {at} is corrupt ({:?})",
                                    e.status
                                ))
                            })?;
                    self.elements(&inflated, depth + 1)?;
                }
                MI_MATRIX => self.matrix(data, depth)?,
                _ => {}
            }
            at = next;
        }
        Ok(())
    }

    /// One miMATRIX: array flags, dimensions, name, then content by class.
    fn matrix(&mut self, b: &[u8], depth: usize) -> Result<()> {
        if depth > MAX_DEPTH {
            return Err(err("arrays nested too deeply"));
        }
        if b.is_empty() {
            return Ok(()); // an empty cell
        }
        let (_, flags, at) = self.element(b, 0)?;
        let flags0 = self
            .u32_at(flags, 0)
            .ok_or_else(|| err("bad array flags"))?;
        let class = (flags0 & 0xff) as u8;
        let (_, dims_raw, at) = self.element(b, at)?;
        let dims: Vec<usize> = (0..dims_raw.len() / 4)
            .filter_map(|k| self.u32_at(dims_raw, 4 * k))
            .map(|d| d as usize)
            .collect();
        let count = dims
            .iter()
            .try_fold(1usize, |acc, &d| acc.checked_mul(d))
            .ok_or_else(|| err("array dimensions overflow"))?;
        let (_, name, mut at) = self.element(b, at)?;
        let name = String::from_utf8_lossy(name).into_owned();
        match class {
            MX_CELL => {
                if count > b.len() / 8 {
                    return Err(err(format!("cell array {name} declares {count} cells")));
                }
                for _ in 0..count {
                    let (ty, data, next) = self.element(b, at)?;
                    if ty == MI_MATRIX {
                        self.matrix(data, depth + 1)?;
                    }
                    at = next;
                }
            }
            MX_STRUCT => {
                let (_, len_raw, a2) = self.element(b, at)?;
                let field_len = self.u32_at(len_raw, 0).unwrap_or(0) as usize;
                let (_, names, mut a3) = self.element(b, a2)?;
                let fields = names.len().checked_div(field_len).unwrap_or(0);
                let total = count
                    .checked_mul(fields)
                    .filter(|&n| n <= b.len() / 8)
                    .ok_or_else(|| err(format!("struct {name} is too large")))?;
                for _ in 0..total {
                    let (ty, data, next) = self.element(b, a3)?;
                    if ty == MI_MATRIX {
                        self.matrix(data, depth + 1)?;
                    }
                    a3 = next;
                }
            }
            4..=15 => {
                // Numeric classes (char = 4 and sparse = 5 are not contour data).
                if class == 4 || class == 5 || dims.len() != 2 {
                    return Ok(());
                }
                // The real part; an imaginary part (complex flag) would follow and is ignored.
                let (ty, real, _) = self.element(b, at)?;
                let values = self.numbers(ty, real)?;
                if values.len() != count {
                    return Err(err(format!(
                        "array {name:?} holds {} values for {}x{} dimensions",
                        values.len(),
                        dims[0],
                        dims[1]
                    )));
                }
                let (rows, cols) = (dims[0], dims[1]);
                let pts: Vec<[f64; 3]> = if cols == 3 {
                    (0..rows)
                        .map(|i| [values[i], values[i + rows], values[i + 2 * rows]])
                        .collect()
                } else if rows == 3 && cols > 3 {
                    (0..cols)
                        .map(|j| [values[3 * j], values[3 * j + 1], values[3 * j + 2]])
                        .collect()
                } else {
                    return Ok(());
                };
                if !pts.is_empty() {
                    self.matrices.push(pts);
                }
            }
            _ => {}
        }
        Ok(())
    }

    fn numbers(&self, ty: u32, b: &[u8]) -> Result<Vec<f64>> {
        let size = match ty {
            1 | 2 => 1,
            3 | 4 => 2,
            5..=7 => 4,
            9 | 12 | 13 => 8,
            other => return Err(err(format!("unsupported numeric data type {other}"))),
        };
        Ok(b.chunks_exact(size)
            .map(|c| {
                let mut a = [0u8; 8];
                a[..size].copy_from_slice(c);
                if self.big {
                    a[..size].reverse();
                }
                let u = u64::from_le_bytes(a);
                match ty {
                    MI_INT8 => u as u8 as i8 as f64,
                    3 => u as u16 as i16 as f64,
                    5 => u as u32 as i32 as f64,
                    7 => f32::from_bits(u as u32) as f64,
                    9 => f64::from_bits(u),
                    12 => u as i64 as f64,
                    _ => u as f64,
                }
            })
            .collect())
    }
}

/// Reads every Nx3 numeric matrix of the file as one contour, `c1`, `c2`, ... in file order.
pub fn read_mat(bytes: &[u8]) -> Result<ContourSet> {
    if !is_mat(bytes) || bytes.len() < 128 {
        return Err(err(
            "not a MATLAB 5 MAT-file (v7.3/HDF5 files are not supported)",
        ));
    }
    let big = match &bytes[126..128] {
        b"IM" => false,
        b"MI" => true,
        _ => return Err(err("MAT-file header has no byte-order mark")),
    };
    let mut r = Reader {
        big,
        matrices: Vec::new(),
    };
    r.elements(&bytes[128..], 1)?;
    if r.matrices.is_empty() {
        return Err(err("no Nx3 coordinate matrices found in the MAT-file"));
    }
    let mut b = ContourBuilder::new();
    for (k, m) in r.matrices.iter().enumerate() {
        let id = format!("c{}", k + 1);
        for p in m {
            if !p.iter().all(|c| c.is_finite()) {
                return Err(err(format!("contour {id} has a non-finite coordinate")));
            }
            b.push(&id, None, v3(p[0], p[1], p[2]), 0)?;
        }
        b.break_run();
    }
    b.finish()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::io::csv::read_csv;
    use crate::io::sample;

    #[test]
    fn surfco_mat_equals_its_csv() {
        let m = read_mat(&sample("contours/surfco-example.mat")).unwrap();
        let c = read_csv(&sample("contours/surfco-example.csv")).unwrap();
        assert_eq!(m.contours.len(), 8);
        assert_eq!(m.point_count(), c.point_count());
        for (a, b) in m.contours.iter().zip(&c.contours) {
            assert_eq!(a.id, b.id);
            assert_eq!(a.pieces.len(), 1);
            assert_eq!(a.pieces[0].closed, b.pieces[0].closed, "{}", a.id);
            for (p, q) in a.points().zip(b.points()) {
                assert!((p - q).amax() < 1e-5, "{}: {p:?} {q:?}", a.id);
            }
        }
    }

    /// An uncompressed, hand-built file: a 1x1 cell holding a 3x3 int8 matrix.
    #[test]
    fn uncompressed_cell_with_int8_data() {
        let mut f = b"MATLAB 5.0 MAT-file, test".to_vec();
        f.resize(124, b' ');
        f.extend_from_slice(&[0x00, 0x01, b'I', b'M']);
        let el = |ty: u32, data: &[u8]| {
            let mut v = ty.to_le_bytes().to_vec();
            v.extend_from_slice(&(data.len() as u32).to_le_bytes());
            v.extend_from_slice(data);
            v.resize(8 + data.len().div_ceil(8) * 8, 0);
            v
        };
        let dims = |r: u32, c: u32| [r.to_le_bytes(), c.to_le_bytes()].concat();
        let mut inner = el(6, &[6, 0, 0, 0, 0, 0, 0, 0]); // double class
        inner.extend(el(5, &dims(3, 3)));
        inner.extend(el(1, b""));
        inner.extend(el(1, &[0, 10, 0, 0, 0, 10, 5, 5, 5])); // int8, column-major
        let mut outer = el(6, &[1, 0, 0, 0, 0, 0, 0, 0]); // cell class
        outer.extend(el(5, &dims(1, 1)));
        outer.extend(el(1, b"C"));
        outer.extend(el(14, &inner));
        f.extend(el(14, &outer));
        let set = read_mat(&f).unwrap();
        assert_eq!(set.point_count(), 3);
        assert_eq!(set.contours[0].pieces[0].points[1], v3(10.0, 0.0, 5.0));
        // Truncation anywhere is an error, never a panic.
        for cut in 128..f.len() {
            let _ = read_mat(&f[..cut]);
        }
        assert!(read_mat(&f[..f.len() - 8]).is_err());
    }
}
