//! Level-5 MAT-files built in memory for the tests of the MAT-file and Segment readers: the
//! elements as MathWorks documents them, little endian, variables compressed as MATLAB's `-v7`.

/// A MATLAB array ready to be a variable, a cell or a struct field.
#[derive(Clone)]
pub struct Array(pub Vec<u8>);

fn element(ty: u32, data: &[u8]) -> Vec<u8> {
    if !data.is_empty() && data.len() <= 4 && ty != 14 {
        let mut v = ((data.len() as u32) << 16 | ty).to_le_bytes().to_vec();
        v.extend_from_slice(data);
        v.resize(8, 0);
        return v;
    }
    let mut v = ty.to_le_bytes().to_vec();
    v.extend_from_slice(&(data.len() as u32).to_le_bytes());
    v.extend_from_slice(data);
    v.resize(8 + data.len().next_multiple_of(8), 0);
    v
}

fn matrix(name: &str, class: u8, dims: &[usize], content: &[u8]) -> Array {
    let mut body = element(6, &[class, 0, 0, 0, 0, 0, 0, 0]);
    let d: Vec<u8> = dims
        .iter()
        .flat_map(|&n| (n as i32).to_le_bytes())
        .collect();
    body.extend(element(5, &d));
    body.extend(element(1, name.as_bytes()));
    body.extend_from_slice(content);
    let mut v = 14u32.to_le_bytes().to_vec();
    v.extend_from_slice(&(body.len() as u32).to_le_bytes());
    v.extend(body);
    Array(v)
}

/// Doubles, column-major.
pub fn doubles(dims: &[usize], values: &[f64]) -> Array {
    let raw: Vec<u8> = values.iter().flat_map(|v| v.to_le_bytes()).collect();
    matrix("", 6, dims, &element(9, &raw))
}

pub fn scalar(v: f64) -> Array {
    doubles(&[1, 1], &[v])
}

/// Doubles with integral values stored as uint8, as MATLAB saves them.
pub fn small_integers(dims: &[usize], values: &[u8]) -> Array {
    matrix("", 6, dims, &element(2, values))
}

/// Singles (an image), every value `v`.
pub fn singles(dims: &[usize], v: f32) -> Array {
    let n: usize = dims.iter().product();
    let raw: Vec<u8> = std::iter::repeat_n(v.to_le_bytes(), n).flatten().collect();
    matrix("", 7, dims, &element(7, &raw))
}

/// A double array whose element ends after its name: MATLAB writes none with values.
pub fn no_data(dims: &[usize]) -> Array {
    matrix("", 6, dims, &[])
}

pub fn empty() -> Array {
    doubles(&[0, 0], &[])
}

pub fn text(s: &str) -> Array {
    let raw: Vec<u8> = s.encode_utf16().flat_map(|u| u.to_le_bytes()).collect();
    matrix("", 4, &[1, s.encode_utf16().count()], &element(4, &raw))
}

pub fn cell(items: &[Array]) -> Array {
    let content: Vec<u8> = items.iter().flat_map(|a| a.0.clone()).collect();
    matrix("", 1, &[1, items.len()], &content)
}

/// A 1xK struct array; `elements[e]` holds field `f`'s value at position `f`.
pub fn structs(fields: &[&str], elements: &[Vec<Array>]) -> Array {
    let names: Vec<u8> = fields
        .iter()
        .flat_map(|f| {
            let mut n = f.as_bytes().to_vec();
            n.resize(32, 0);
            n
        })
        .collect();
    let mut content = element(5, &32i32.to_le_bytes());
    content.extend(element(1, &names));
    for e in elements {
        assert_eq!(e.len(), fields.len());
        for a in e {
            content.extend_from_slice(&a.0);
        }
    }
    matrix("", 2, &[1, elements.len()], &content)
}

/// A file of named variables, each compressed (`compress`) or stored as is.
pub fn file(variables: &[(&str, Array)], compress: bool) -> Vec<u8> {
    let mut out = b"MATLAB 5.0 MAT-file, Platform: test".to_vec();
    out.resize(124, b' ');
    out.extend_from_slice(&[0x00, 0x01, b'I', b'M']);
    for (name, a) in variables {
        // Rename: the name element follows the flags (16 bytes) and dimensions.
        let renamed = rename(a, name);
        if compress {
            let z = miniz_oxide::deflate::compress_to_vec_zlib(&renamed, 6);
            out.extend_from_slice(&15u32.to_le_bytes());
            out.extend_from_slice(&(z.len() as u32).to_le_bytes());
            out.extend(z);
        } else {
            out.extend(renamed);
        }
    }
    out
}

/// The array with its name element replaced.
fn rename(a: &Array, name: &str) -> Vec<u8> {
    let body = &a.0[8..];
    let dims_len = u32::from_le_bytes(body[20..24].try_into().unwrap()) as usize;
    let name_at = 16 + 8 + dims_len.next_multiple_of(8);
    let old_name = element_len(&body[name_at..]);
    let mut new_body = body[..name_at].to_vec();
    new_body.extend(element(1, name.as_bytes()));
    new_body.extend_from_slice(&body[name_at + old_name..]);
    let mut v = 14u32.to_le_bytes().to_vec();
    v.extend_from_slice(&(new_body.len() as u32).to_le_bytes());
    v.extend(new_body);
    v
}

/// Bytes an element takes, tag and padding included.
fn element_len(b: &[u8]) -> usize {
    let tag = u32::from_le_bytes(b[..4].try_into().unwrap());
    if tag >> 16 != 0 {
        8
    } else {
        8 + (u32::from_le_bytes(b[4..8].try_into().unwrap()) as usize).next_multiple_of(8)
    }
}
