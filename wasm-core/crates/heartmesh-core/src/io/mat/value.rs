//! The variables of a MATLAB level-5 MAT-file ("MAT-File Format", MathWorks, version 5
//! documentation; MATLAB's `-v6` and default `-v7` saves) as a tree of values: numeric arrays,
//! text, cells and structs. Uncompressed and zlib-compressed (miCOMPRESSED) elements, either
//! byte order, numeric data in any of the file's types (MATLAB stores doubles with integral
//! values in smaller integer types).
//!
//! Compressed variables are parsed while they inflate, and numeric arrays above
//! [`Limits::kept_values`] are skipped as they stream past: a Segment study keeps its images
//! (hundreds of megabytes) in the same struct as its contours, and only the contours are needed.

use std::io::Read;

use crate::error::{CoreError, Result};

const MI_INT8: u32 = 1;
const MI_UINT8: u32 = 2;
const MI_UINT16: u32 = 4;
const MI_MATRIX: u32 = 14;
const MI_COMPRESSED: u32 = 15;
const MI_UTF8: u32 = 16;
const MX_CELL: u8 = 1;
const MX_STRUCT: u8 = 2;
const MX_CHAR: u8 = 4;
const MX_SPARSE: u8 = 5;

/// Nesting deeper than this is not data a contour reader needs.
const MAX_DEPTH: usize = 32;
/// Array flags, dimensions, names and field-name lists above this size are corrupt.
const MAX_HEADER_BYTES: usize = 1 << 16;
/// Text above this many bytes is skipped (notes, not contour data).
const MAX_TEXT_BYTES: usize = 1 << 20;

/// How much of a file is read into memory.
#[derive(Debug, Clone, Copy)]
pub struct Limits {
    /// Numeric arrays with more values than this are [`Value::Skipped`] (images).
    pub kept_values: usize,
    /// Bytes inflated from compressed variables, all together (a zip-bomb guard).
    pub inflated_bytes: u64,
}

impl Default for Limits {
    fn default() -> Self {
        Limits {
            kept_values: 1 << 21,
            inflated_bytes: 4 << 30,
        }
    }
}

/// One MATLAB value. Arrays are column-major, as MATLAB stores them.
#[derive(Debug, Clone, PartialEq)]
pub enum Value {
    /// A numeric or logical array's real part.
    Numeric {
        dims: Vec<usize>,
        data: Vec<f64>,
    },
    /// A char array's characters, in storage order (one row for the usual `1xN` text).
    Text(String),
    Cell {
        dims: Vec<usize>,
        items: Vec<Value>,
    },
    /// `items[e * fields.len() + f]` is field `f` of element `e`.
    Struct {
        dims: Vec<usize>,
        fields: Vec<String>,
        items: Vec<Value>,
    },
    /// An array not read: above the size limit, sparse, an object or a function handle.
    Skipped {
        dims: Vec<usize>,
        class: u8,
    },
}

impl Value {
    /// Number of elements (the product of the dimensions).
    pub fn len(&self) -> usize {
        match self {
            Value::Numeric { data, .. } => data.len(),
            Value::Text(s) => s.chars().count(),
            Value::Cell { items, .. } => items.len(),
            Value::Struct { dims, .. } | Value::Skipped { dims, .. } => dims.iter().product(),
        }
    }

    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Field `name` of struct element `element` (None: not a struct, no such field or element).
    pub fn field(&self, element: usize, name: &str) -> Option<&Value> {
        let Value::Struct { fields, items, .. } = self else {
            return None;
        };
        let f = fields.iter().position(|n| n == name)?;
        items.get(element * fields.len() + f)
    }

    /// The values of a numeric array, with its dimensions.
    pub fn numbers(&self) -> Option<(&[usize], &[f64])> {
        match self {
            Value::Numeric { dims, data } => Some((dims, data)),
            _ => None,
        }
    }

    /// The first value of a numeric array (a scalar's value).
    pub fn scalar(&self) -> Option<f64> {
        self.numbers().and_then(|(_, d)| d.first().copied())
    }

    pub fn text(&self) -> Option<&str> {
        match self {
            Value::Text(s) => Some(s),
            _ => None,
        }
    }
}

/// A named top-level variable.
#[derive(Debug, Clone, PartialEq)]
pub struct Variable {
    pub name: String,
    pub value: Value,
}

fn err(msg: impl Into<String>) -> CoreError {
    CoreError::parse(0, msg)
}

/// Bytes read in order, either from the file or from an inflating stream.
trait Source {
    /// Exactly `n` bytes (an error when the data ends first).
    fn take(&mut self, n: usize) -> Result<Vec<u8>>;
    fn skip(&mut self, n: usize) -> Result<()>;
    /// Bytes consumed so far.
    fn at(&self) -> u64;
    /// Whether nothing is left.
    fn done(&mut self) -> Result<bool>;
}

struct Bytes<'a> {
    b: &'a [u8],
    at: usize,
}

impl Bytes<'_> {
    fn span(&self, n: usize) -> Result<std::ops::Range<usize>> {
        let end = self.at.checked_add(n).filter(|&e| e <= self.b.len());
        end.map(|e| self.at..e).ok_or_else(|| {
            err(format!(
                "element at byte {} declares {n} bytes but the file ends first (truncated)",
                self.at
            ))
        })
    }
}

impl<'a> Bytes<'a> {
    /// The next `n` bytes, borrowed (a compressed variable, inflated from where it lies).
    fn slice(&mut self, n: usize) -> Result<&'a [u8]> {
        let r = self.span(n)?;
        self.at = r.end;
        Ok(&self.b[r])
    }
}

impl Source for Bytes<'_> {
    fn take(&mut self, n: usize) -> Result<Vec<u8>> {
        let r = self.span(n)?;
        self.at = r.end;
        Ok(self.b[r].to_vec())
    }
    fn skip(&mut self, n: usize) -> Result<()> {
        self.at = self.span(n)?.end;
        Ok(())
    }
    fn at(&self) -> u64 {
        self.at as u64
    }
    fn done(&mut self) -> Result<bool> {
        // Every element takes 8 bytes at least: fewer left over is padding.
        Ok(self.at + 8 > self.b.len())
    }
}

struct Inflating<'a> {
    z: flate2::read::ZlibDecoder<&'a [u8]>,
    at: u64,
    limit: u64,
    /// One byte read ahead by `done`.
    peeked: Option<u8>,
}

impl Inflating<'_> {
    fn corrupt(&self, e: std::io::Error) -> CoreError {
        err(format!(
            "compressed variable is corrupt or truncated after {} inflated bytes ({e})",
            self.at
        ))
    }

    fn count(&mut self, n: usize) -> Result<()> {
        self.at += n as u64;
        if self.at > self.limit {
            return Err(err(format!(
                "compressed variables inflate to more than {} MiB",
                self.limit >> 20
            )));
        }
        Ok(())
    }
}

impl Source for Inflating<'_> {
    fn take(&mut self, n: usize) -> Result<Vec<u8>> {
        self.count(n)?;
        let mut out = Vec::new();
        let mut rest = n;
        if rest > 0 {
            if let Some(b) = self.peeked.take() {
                out.push(b);
                rest -= 1;
            }
        }
        // Grows with the data actually there, whatever size the element declares.
        (&mut self.z)
            .take(rest as u64)
            .read_to_end(&mut out)
            .map_err(|e| self.corrupt(e))?;
        if out.len() < n {
            return Err(err(
                "compressed variable ends inside an element (truncated)",
            ));
        }
        Ok(out)
    }
    fn skip(&mut self, n: usize) -> Result<()> {
        self.count(n)?;
        let mut n = n as u64;
        if n > 0 && self.peeked.take().is_some() {
            n -= 1;
        }
        let copied = std::io::copy(&mut (&mut self.z).take(n), &mut std::io::sink())
            .map_err(|e| self.corrupt(e))?;
        if copied < n {
            return Err(err(
                "compressed variable ends inside an element (truncated)",
            ));
        }
        Ok(())
    }
    fn at(&self) -> u64 {
        self.at
    }
    fn done(&mut self) -> Result<bool> {
        if self.peeked.is_some() {
            return Ok(false);
        }
        let mut one = [0u8; 1];
        loop {
            match self.z.read(&mut one) {
                Ok(0) => return Ok(true),
                Ok(_) => {
                    self.peeked = Some(one[0]);
                    return Ok(false);
                }
                Err(e) if e.kind() == std::io::ErrorKind::Interrupted => {}
                Err(e) => return Err(self.corrupt(e)),
            }
        }
    }
}

struct Parser {
    big: bool,
    limits: Limits,
    /// Inflated bytes of the variables read before the current one.
    inflated: u64,
}

/// An element's tag: (data type, data size, bytes of padding after the data).
struct Tag {
    ty: u32,
    size: usize,
    /// The small-element form keeps its data in the tag's 8 bytes.
    small: bool,
}

impl Tag {
    fn padding(&self) -> usize {
        if self.small {
            4 - self.size
        } else {
            self.size.next_multiple_of(8) - self.size
        }
    }
}

impl Parser {
    fn u32(&self, b: &[u8]) -> u32 {
        let s: [u8; 4] = [b[0], b[1], b[2], b[3]];
        if self.big {
            u32::from_be_bytes(s)
        } else {
            u32::from_le_bytes(s)
        }
    }

    fn tag(&self, src: &mut dyn Source) -> Result<Tag> {
        let at = src.at();
        let head = src.take(4)?;
        let word = self.u32(&head);
        if word >> 16 != 0 {
            let size = (word >> 16) as usize;
            if size > 4 {
                return Err(err(format!("bad small element size {size} at byte {at}")));
            }
            return Ok(Tag {
                ty: word & 0xffff,
                size,
                small: true,
            });
        }
        let size = self.u32(&src.take(4)?) as usize;
        Ok(Tag {
            ty: word,
            size,
            small: false,
        })
    }

    /// A small sub-element's data (flags, dimensions, a name), padding consumed.
    fn small_data(&self, src: &mut dyn Source, what: &str) -> Result<(u32, Vec<u8>)> {
        let tag = self.tag(src)?;
        if tag.size > MAX_HEADER_BYTES {
            return Err(err(format!("array {what} of {} bytes", tag.size)));
        }
        let data = src.take(tag.size)?;
        src.skip(tag.padding())?;
        Ok((tag.ty, data))
    }

    /// The top-level elements of the file (after its 128-byte header).
    fn variables(&mut self, src: &mut Bytes) -> Result<Vec<Variable>> {
        let mut out = Vec::new();
        while !src.done()? {
            let tag = self.tag(src)?;
            match tag.ty {
                MI_COMPRESSED if !tag.small => {
                    let data = src.slice(tag.size)?;
                    let mut z = Inflating {
                        z: flate2::read::ZlibDecoder::new(data),
                        at: 0,
                        limit: self.limits.inflated_bytes.saturating_sub(self.inflated),
                        peeked: None,
                    };
                    while !z.done()? {
                        let inner = self.tag(&mut z)?;
                        if inner.ty == MI_MATRIX && !inner.small {
                            out.push(self.matrix(&mut z, inner.size, 0)?);
                        } else {
                            z.skip(inner.size + inner.padding())?;
                        }
                    }
                    self.inflated += z.at;
                }
                MI_MATRIX if !tag.small => {
                    out.push(self.matrix(src, tag.size, 0)?);
                    src.skip(tag.padding())?;
                }
                _ => src.skip(tag.size + tag.padding())?,
            }
        }
        Ok(out)
    }

    /// One miMATRIX of `size` bytes (its tag read): flags, dimensions, name, then its content.
    fn matrix(&self, src: &mut dyn Source, size: usize, depth: usize) -> Result<Variable> {
        if depth > MAX_DEPTH {
            return Err(err("arrays nested too deeply"));
        }
        let start = src.at();
        let end = start + size as u64;
        if size == 0 {
            // An empty cell's placeholder.
            let value = Value::Numeric {
                dims: vec![0, 0],
                data: Vec::new(),
            };
            return Ok(Variable {
                name: String::new(),
                value,
            });
        }
        let (_, flags) = self.small_data(src, "flags")?;
        if flags.len() < 4 {
            return Err(err("bad array flags"));
        }
        let class = (self.u32(&flags) & 0xff) as u8;
        let (_, dims_raw) = self.small_data(src, "dimensions")?;
        let dims: Vec<usize> = dims_raw
            .chunks_exact(4)
            .map(|c| self.u32(c) as usize)
            .collect();
        let count = dims
            .iter()
            .try_fold(1usize, |acc, &d| acc.checked_mul(d))
            .ok_or_else(|| err("array dimensions overflow"))?;
        let (_, name) = self.small_data(src, "name")?;
        let name = String::from_utf8_lossy(&name).into_owned();
        let left = |src: &dyn Source| -> Result<usize> {
            end.checked_sub(src.at())
                .map(|n| n as usize)
                .ok_or_else(|| err(format!("array {name:?} overruns its element")))
        };
        // Every element takes at least 8 bytes: a count above that is corrupt.
        let fits = |n: usize| n <= size / 8 + 1;
        // An array whose element ends after its name (no data element) is empty.
        let bare = src.at() >= end;
        let value = match class {
            MX_CHAR | 6..=15 if bare => {
                if count != 0 {
                    return Err(err(format!(
                        "array {name:?} declares {dims:?} dimensions but holds no data"
                    )));
                }
                Value::Numeric {
                    dims,
                    data: Vec::new(),
                }
            }
            MX_CELL => {
                if !fits(count) {
                    return Err(err(format!("cell array {name:?} declares {count} cells")));
                }
                let items = (0..count)
                    .map(|_| self.child(src, depth))
                    .collect::<Result<Vec<_>>>()?;
                Value::Cell { dims, items }
            }
            MX_STRUCT => {
                let (_, len_raw) = self.small_data(src, "field name length")?;
                let field_len = if len_raw.len() >= 4 {
                    self.u32(&len_raw) as usize
                } else {
                    0
                };
                let (_, names) = self.small_data(src, "field names")?;
                let fields: Vec<String> = if field_len == 0 {
                    Vec::new()
                } else {
                    names
                        .chunks(field_len)
                        .map(|c| {
                            let n = c.iter().position(|&b| b == 0).unwrap_or(c.len());
                            String::from_utf8_lossy(&c[..n]).into_owned()
                        })
                        .collect()
                };
                let total = count
                    .checked_mul(fields.len())
                    .filter(|&n| fits(n))
                    .ok_or_else(|| err(format!("struct {name:?} is too large")))?;
                let items = (0..total)
                    .map(|_| self.child(src, depth))
                    .collect::<Result<Vec<_>>>()?;
                Value::Struct {
                    dims,
                    fields,
                    items,
                }
            }
            MX_CHAR => {
                let tag = self.tag(src)?;
                if tag.size > MAX_TEXT_BYTES {
                    src.skip(tag.size)?;
                    Value::Skipped { dims, class }
                } else {
                    let raw = src.take(tag.size)?;
                    Value::Text(self.text(tag.ty, &raw))
                }
            }
            6..=15 if class != MX_SPARSE => {
                let tag = self.tag(src)?;
                let width = width(tag.ty).ok_or_else(|| {
                    err(format!(
                        "array {name:?} has unsupported numeric data type {}",
                        tag.ty
                    ))
                })?;
                if tag.size / width != count || tag.size % width != 0 {
                    return Err(err(format!(
                        "array {name:?} holds {} values for {dims:?} dimensions",
                        tag.size / width
                    )));
                }
                if count > self.limits.kept_values {
                    src.skip(tag.size)?;
                    Value::Skipped { dims, class }
                } else {
                    let raw = src.take(tag.size)?;
                    Value::Numeric {
                        dims,
                        data: self.numbers(tag.ty, &raw),
                    }
                }
            }
            _ => Value::Skipped { dims, class },
        };
        // The rest: padding, an imaginary part, a sparse array's content, an object's data.
        src.skip(left(src)?)?;
        Ok(Variable { name, value })
    }

    /// A cell's or a struct field's value: one miMATRIX element.
    fn child(&self, src: &mut dyn Source, depth: usize) -> Result<Value> {
        let tag = self.tag(src)?;
        if tag.ty != MI_MATRIX || tag.small {
            return Err(err(format!(
                "expected an array element, found data type {}",
                tag.ty
            )));
        }
        let v = self.matrix(src, tag.size, depth + 1)?;
        src.skip(tag.padding())?;
        Ok(v.value)
    }

    fn text(&self, ty: u32, raw: &[u8]) -> String {
        match ty {
            MI_UINT16 => {
                let units: Vec<u16> = raw
                    .chunks_exact(2)
                    .map(|c| {
                        if self.big {
                            u16::from_be_bytes([c[0], c[1]])
                        } else {
                            u16::from_le_bytes([c[0], c[1]])
                        }
                    })
                    .collect();
                String::from_utf16_lossy(&units)
            }
            MI_UTF8 | MI_INT8 => String::from_utf8_lossy(raw).into_owned(),
            // Latin-1 (MI_UINT8) and anything else byte-wide.
            _ => raw.iter().map(|&b| b as char).collect(),
        }
    }

    fn numbers(&self, ty: u32, b: &[u8]) -> Vec<f64> {
        let size = width(ty).unwrap_or(1);
        b.chunks_exact(size)
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
            .collect()
    }
}

/// Bytes per value of a numeric data type.
fn width(ty: u32) -> Option<usize> {
    match ty {
        MI_INT8 | MI_UINT8 => Some(1),
        3 | MI_UINT16 => Some(2),
        5..=7 => Some(4),
        9 | 12 | 13 => Some(8),
        _ => None,
    }
}

/// True when the bytes start like a MAT-file: level 5 (read) or 7.3 (HDF5, refused by name).
pub fn is_mat(bytes: &[u8]) -> bool {
    bytes.starts_with(b"MATLAB 5.0 MAT-file") || is_hdf5_mat(bytes)
}

/// MATLAB's `-v7.3` files: HDF5 behind a MAT-file text header.
pub fn is_hdf5_mat(bytes: &[u8]) -> bool {
    bytes.starts_with(b"MATLAB 7.3 MAT-file")
}

/// Whether a level-5 MAT-file has a top-level variable `name`: each variable's name only is read
/// (the first bytes of a compressed one inflated), so a study of any size is recognised at once.
pub fn has_variable(bytes: &[u8], name: &str) -> bool {
    if bytes.len() < 128 || !bytes.starts_with(b"MATLAB 5.0 MAT-file") {
        return false;
    }
    let p = Parser {
        big: &bytes[126..128] == b"MI",
        limits: Limits::default(),
        inflated: 0,
    };
    // An array element's name: after its tag, its flags and dimensions.
    let named = |b: &[u8]| -> bool {
        let mut src = Bytes { b, at: 0 };
        let mut read = || -> Result<bool> {
            let tag = p.tag(&mut src)?;
            if tag.ty != MI_MATRIX || tag.small {
                return Ok(false);
            }
            p.small_data(&mut src, "flags")?;
            p.small_data(&mut src, "dimensions")?;
            Ok(p.small_data(&mut src, "name")?.1 == name.as_bytes())
        };
        read().unwrap_or(false)
    };
    let mut at = 128;
    while at + 8 <= bytes.len() {
        let mut src = Bytes { b: bytes, at };
        let Ok(tag) = p.tag(&mut src) else {
            return false;
        };
        if tag.small {
            at += 8;
            continue;
        }
        let Some(data) = bytes.get(src.at..src.at.saturating_add(tag.size)) else {
            return false;
        };
        let found = if tag.ty == MI_COMPRESSED {
            let mut head = Vec::new();
            let _ = flate2::read::ZlibDecoder::new(data)
                .take(1024)
                .read_to_end(&mut head);
            named(&head)
        } else {
            named(&bytes[at..src.at + data.len()])
        };
        if found {
            return true;
        }
        at = src.at
            + if tag.ty == MI_COMPRESSED {
                tag.size
            } else {
                tag.size.next_multiple_of(8)
            };
    }
    false
}

/// Every top-level variable of a level-5 MAT-file, in file order.
pub fn read_variables(bytes: &[u8], limits: Limits) -> Result<Vec<Variable>> {
    if is_hdf5_mat(bytes) {
        return Err(err(
            "a MATLAB 7.3 (HDF5) MAT-file: not read; save it again in MATLAB with `save(..., \
             '-v7')` (Segment saves studies above 1.5 GB this way: crop the stacks or remove \
             those without contours, then save)",
        ));
    }
    if !bytes.starts_with(b"MATLAB 5.0 MAT-file") || bytes.len() < 128 {
        return Err(err("not a MATLAB 5 MAT-file"));
    }
    let big = match &bytes[126..128] {
        b"IM" => false,
        b"MI" => true,
        _ => return Err(err("MAT-file header has no byte-order mark")),
    };
    let mut p = Parser {
        big,
        limits,
        inflated: 0,
    };
    p.variables(&mut Bytes {
        b: &bytes[128..],
        at: 0,
    })
}
