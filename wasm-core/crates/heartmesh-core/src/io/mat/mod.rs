//! MATLAB MAT-files (level 5: MATLAB's `-v6` and default `-v7` saves): the SurFCo toolbox's
//! cell array of Nx3 double matrices, one per contour, or a Segment (Medviso) study
//! ([`super::segment`]), told apart by Segment's `setstruct` variable.

#[cfg(test)]
pub mod test_files;
pub mod value;

use super::builder::ContourBuilder;
use super::frame_choice::FrameChoice;
use crate::contours::ContourSet;
use crate::error::{CoreError, Result};
use crate::geometry::v3;
pub use value::{has_variable, is_hdf5_mat, is_mat, read_variables, Limits, Value, Variable};

/// Reads a MAT-file's contours: a Segment study's at its default frame, else every Nx3 matrix.
pub fn read_mat(bytes: &[u8]) -> Result<ContourSet> {
    read_mat_frame(bytes, None)
}

/// [`read_mat`], a Segment study's time frame chosen (SurFCo files have one frame).
pub fn read_mat_frame(bytes: &[u8], frame: Option<&FrameChoice>) -> Result<ContourSet> {
    let variables = read_variables(bytes, Limits::default())?;
    if super::segment::is_segment(&variables) {
        return super::segment::read_segment(&variables, frame);
    }
    read_matrices(&variables)
}

/// The Nx3 (or 3xN) numeric matrices under `v`, in file order (cells and structs walked).
fn matrices(v: &Value, out: &mut Vec<Vec<[f64; 3]>>) {
    match v {
        Value::Cell { items, .. } | Value::Struct { items, .. } => {
            for item in items {
                matrices(item, out);
            }
        }
        Value::Numeric { dims, data } if dims.len() == 2 => {
            let (rows, cols) = (dims[0], dims[1]);
            let pts: Vec<[f64; 3]> = if cols == 3 {
                (0..rows)
                    .map(|i| [data[i], data[i + rows], data[i + 2 * rows]])
                    .collect()
            } else if rows == 3 && cols > 3 {
                data.chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect()
            } else {
                return;
            };
            if !pts.is_empty() {
                out.push(pts);
            }
        }
        _ => {}
    }
}

/// Every Nx3 numeric matrix of the file as one contour, `c1`, `c2`, ... in file order.
fn read_matrices(variables: &[Variable]) -> Result<ContourSet> {
    let mut found = Vec::new();
    for v in variables {
        matrices(&v.value, &mut found);
    }
    if found.is_empty() {
        return Err(CoreError::parse(
            0,
            "no Nx3 coordinate matrices found in the MAT-file",
        ));
    }
    let mut b = ContourBuilder::new();
    for (k, m) in found.iter().enumerate() {
        let id = format!("c{}", k + 1);
        for p in m {
            if !p.iter().all(|c| c.is_finite()) {
                return Err(CoreError::parse(
                    0,
                    format!("contour {id} has a non-finite coordinate"),
                ));
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

    /// Every kind of value, compressed or not, reads back as written; arrays over the limit
    /// are skipped with their sizes.
    #[test]
    fn values_read_back_and_big_arrays_are_skipped() {
        use test_files::*;
        let person = structs(
            &["Name", "Size", "Tags"],
            &[
                vec![
                    text("Åsa"),
                    doubles(&[1, 2], &[1.5, -2.0]),
                    cell(&[text("a"), empty()]),
                ],
                vec![text(""), small_integers(&[2, 1], &[7, 9]), cell(&[])],
            ],
        );
        for compress in [false, true] {
            let bytes = file(
                &[
                    ("people", person.clone()),
                    ("image", singles(&[20, 10], 0.5)),
                ],
                compress,
            );
            let limits = Limits {
                kept_values: 100,
                ..Limits::default()
            };
            let vars = read_variables(&bytes, limits).unwrap();
            assert_eq!(vars.len(), 2);
            assert_eq!(
                (vars[0].name.as_str(), vars[1].name.as_str()),
                ("people", "image")
            );
            let p = &vars[0].value;
            assert_eq!(p.len(), 2);
            assert_eq!(p.field(0, "Name").and_then(Value::text), Some("Åsa"));
            assert_eq!(p.field(1, "Name").and_then(Value::text), Some(""));
            assert_eq!(
                p.field(0, "Size").and_then(Value::numbers),
                Some((&[1usize, 2][..], &[1.5, -2.0][..]))
            );
            assert_eq!(
                p.field(1, "Size").and_then(Value::numbers),
                Some((&[2usize, 1][..], &[7.0, 9.0][..]))
            );
            assert!(
                matches!(p.field(0, "Tags"), Some(Value::Cell { items, .. }) if items.len() == 2)
            );
            assert_eq!(p.field(2, "Name"), None);
            assert_eq!(p.field(0, "Age"), None);
            assert_eq!(
                vars[1].value,
                Value::Skipped {
                    dims: vec![20, 10],
                    class: 7
                }
            );
            assert!(has_variable(&bytes, "image") && has_variable(&bytes, "people"));
            assert!(!has_variable(&bytes, "peopl") && !has_variable(&bytes[..200], "image"));
            let all = read_variables(&bytes, Limits::default()).unwrap();
            assert_eq!(all[1].value.numbers().map(|(_, d)| d.len()), Some(200));
        }
    }

    /// A v7.3 file is named as one, with what to do; the inflated-size guard holds.
    #[test]
    fn hdf5_files_and_bombs_are_refused_by_name() {
        let mut h = b"MATLAB 7.3 MAT-file, Platform: GLNXA64, HDF5 schema 1.00 .".to_vec();
        h.resize(512, 0);
        assert!(is_mat(&h));
        let e = read_mat(&h).unwrap_err().to_string();
        assert!(e.contains("MATLAB 7.3 (HDF5)") && e.contains("-v7"), "{e}");
        let bytes = test_files::file(&[("image", test_files::singles(&[100, 100], 0.0))], true);
        let limits = Limits {
            kept_values: 10,
            inflated_bytes: 1000,
        };
        let e = read_variables(&bytes, limits).unwrap_err().to_string();
        assert!(e.contains("inflate to more than"), "{e}");
        // An array without its data element: empty when its dimensions say so, else refused
        // (the fuzzer's find: a curve array of 80 x 2 with no values).
        let ok = test_files::file(&[("a", test_files::no_data(&[0, 0]))], false);
        assert_eq!(
            read_variables(&ok, Limits::default()).unwrap()[0]
                .value
                .len(),
            0
        );
        let bad = test_files::file(&[("a", test_files::no_data(&[80, 2]))], false);
        let e = read_variables(&bad, Limits::default())
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("declares [80, 2] dimensions but holds no data"),
            "{e}"
        );
    }
}
