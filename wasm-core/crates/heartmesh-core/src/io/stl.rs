//! STL meshes, binary and ASCII. STL stores every triangle with its own corners, so reading merges
//! corners with bit-identical coordinates back into shared vertices (in order of first use).

use std::collections::HashMap;

use super::text::{decode, lines, parse_coord};
use super::{fmt_f32, header_lines, MeshData, MAX_MESH_ELEMENTS};
use crate::error::{CoreError, Result};
use crate::geometry::{v3, Vec3};
use crate::mesh::TriMesh;

/// Reads binary or ASCII STL. Binary is recognised by its size (84 + 50 bytes per triangle),
/// because binary headers written by many tools also begin with "solid".
pub fn read_stl(bytes: &[u8]) -> Result<MeshData> {
    if is_binary(bytes) {
        read_binary(bytes)
    } else if bytes.trim_ascii_start().starts_with(b"solid") {
        read_ascii(bytes)
    } else if bytes.len() >= 84 {
        Err(CoreError::parse(
            0,
            format!(
                "binary STL of {} bytes declares {} triangles (needs {} bytes): truncated or not STL",
                bytes.len(),
                declared_count(bytes),
                84 + 50 * declared_count(bytes) as u64
            ),
        ))
    } else {
        Err(CoreError::parse(
            0,
            "not an STL file (too short, no \"solid\")",
        ))
    }
}

fn declared_count(bytes: &[u8]) -> u32 {
    bytes
        .get(80..84)
        .and_then(|b| b.try_into().ok())
        .map(u32::from_le_bytes)
        .unwrap_or(0)
}

fn is_binary(bytes: &[u8]) -> bool {
    bytes.len() >= 84 && bytes.len() as u64 == 84 + 50 * declared_count(bytes) as u64
}

/// Merges corners into shared vertices.
#[derive(Default)]
struct Welder {
    mesh: TriMesh,
    seen: HashMap<[u64; 3], u32>,
}

impl Welder {
    fn vertex(&mut self, p: Vec3, line: usize) -> Result<u32> {
        let key = [p.x.to_bits(), p.y.to_bits(), p.z.to_bits()];
        if let Some(&i) = self.seen.get(&key) {
            return Ok(i);
        }
        if self.mesh.positions.len() >= MAX_MESH_ELEMENTS {
            return Err(CoreError::parse(
                line,
                format!("too many vertices: the limit is {MAX_MESH_ELEMENTS}"),
            ));
        }
        let i = self.mesh.positions.len() as u32;
        self.mesh.positions.push(p);
        self.seen.insert(key, i);
        Ok(i)
    }

    fn finish(self) -> Result<MeshData> {
        if self.mesh.triangles.is_empty() {
            return Err(CoreError::parse(0, "no triangles found"));
        }
        Ok(MeshData {
            mesh: self.mesh,
            point_data: None,
            regions: None,
            coordinate_system: None,
        })
    }
}

fn read_binary(bytes: &[u8]) -> Result<MeshData> {
    let n = declared_count(bytes) as usize;
    if n > MAX_MESH_ELEMENTS {
        return Err(CoreError::parse(
            0,
            format!("too many triangles ({n}): the limit is {MAX_MESH_ELEMENTS}"),
        ));
    }
    let mut w = Welder::default();
    for rec in bytes[84..].chunks_exact(50) {
        let mut tri = [0u32; 3];
        for (k, t) in tri.iter_mut().enumerate() {
            let at = 12 + 12 * k;
            let f = |o: usize| {
                let b = [
                    rec[at + o],
                    rec[at + o + 1],
                    rec[at + o + 2],
                    rec[at + o + 3],
                ];
                f32::from_le_bytes(b) as f64
            };
            let p = v3(f(0), f(4), f(8));
            if !p.iter().all(|c| c.is_finite()) {
                return Err(CoreError::parse(
                    0,
                    format!(
                        "triangle {} has a non-finite coordinate",
                        w.mesh.triangles.len()
                    ),
                ));
            }
            *t = w.vertex(p, 0)?;
        }
        w.mesh.triangles.push(tri);
    }
    w.finish()
}

fn read_ascii(bytes: &[u8]) -> Result<MeshData> {
    let text = decode(bytes)?;
    let mut w = Welder::default();
    let mut corners: Vec<u32> = Vec::with_capacity(3);
    for (line, row) in lines(&text) {
        let mut it = row.split_whitespace();
        match it.next() {
            Some("vertex") => {
                let mut c = [0.0; 3];
                for (k, v) in c.iter_mut().enumerate() {
                    let f = it
                        .next()
                        .ok_or_else(|| CoreError::parse(line, "vertex needs 3 coordinates"))?;
                    *v = parse_coord(f, line, &format!("vertex coordinate {}", k + 1))?;
                }
                let i = w.vertex(v3(c[0], c[1], c[2]), line)?;
                corners.push(i);
            }
            Some("outer") => corners.clear(),
            Some("endloop") => {
                if corners.len() != 3 {
                    return Err(CoreError::parse(
                        line,
                        format!("facet has {} vertices; STL needs 3", corners.len()),
                    ));
                }
                if w.mesh.triangles.len() >= MAX_MESH_ELEMENTS {
                    return Err(CoreError::parse(line, "too many triangles"));
                }
                w.mesh.triangles.push([corners[0], corners[1], corners[2]]);
                corners.clear();
            }
            _ => {}
        }
    }
    w.finish()
}

/// Unit normal of a triangle (zero for degenerate ones), which STL stores redundantly.
fn normal(a: Vec3, b: Vec3, c: Vec3) -> Vec3 {
    let n = (b - a).cross(&(c - a));
    let len = n.norm();
    if len > 0.0 {
        n / len
    } else {
        Vec3::zeros()
    }
}

/// Binary STL; the 80-byte header holds `heartmesh <version>` and the comment (never "solid" at
/// the start, which would make readers take it for ASCII).
pub fn write_stl_binary(mesh: &TriMesh, header_comment: &str) -> Vec<u8> {
    let mut out = Vec::with_capacity(84 + 50 * mesh.triangles.len());
    let header = header_lines(header_comment).join(" | ");
    let mut h = [b' '; 80];
    for (d, s) in h.iter_mut().zip(
        header
            .bytes()
            .filter(|b| b.is_ascii_graphic() || *b == b' '),
    ) {
        *d = s;
    }
    out.extend_from_slice(&h);
    out.extend_from_slice(&(mesh.triangles.len() as u32).to_le_bytes());
    for t in &mesh.triangles {
        let [a, b, c] = t.map(|i| mesh.positions[i as usize]);
        for p in [normal(a, b, c), a, b, c] {
            for x in p.iter() {
                out.extend_from_slice(&(*x as f32).to_le_bytes());
            }
        }
        out.extend_from_slice(&0u16.to_le_bytes());
    }
    out
}

/// ASCII STL; the comment goes into the solid's name (the only place the format has).
pub fn write_stl_ascii(mesh: &TriMesh, header_comment: &str) -> Vec<u8> {
    let name: String = header_lines(header_comment)
        .join(" | ")
        .chars()
        .filter(|c| !c.is_control())
        .collect();
    let mut out = format!("solid {name}\n");
    for t in &mesh.triangles {
        let [a, b, c] = t.map(|i| mesh.positions[i as usize]);
        let n = normal(a, b, c);
        out.push_str(&format!(
            "  facet normal {} {} {}\n    outer loop\n",
            fmt_f32(n.x),
            fmt_f32(n.y),
            fmt_f32(n.z)
        ));
        for p in [a, b, c] {
            out.push_str(&format!(
                "      vertex {} {} {}\n",
                fmt_f32(p.x),
                fmt_f32(p.y),
                fmt_f32(p.z)
            ));
        }
        out.push_str("    endloop\n  endfacet\n");
    }
    out.push_str("endsolid heartmesh\n");
    out.into_bytes()
}
