//! `reconstruct --surface all`: every surface of a biventricular file (LV endo- and epicardium,
//! RV, ...) in one command, each to its own files named after it. A modeller wants all of them;
//! looping over the file's labels in a shell script means reading them out of the error message.

use heartmesh_core::ContourSet;

use crate::error::CliError;

/// The `--surface` value that asks for every surface.
pub const ALL: &str = "all";

/// The surfaces to reconstruct one after the other when `surface` asks for all of them (in the
/// file's order; `[None]` for a file without surface labels), or None for a single run. A file
/// that names a surface "all" itself gets that surface.
pub fn requested(surface: Option<&str>, set: &ContourSet) -> Option<Vec<Option<String>>> {
    let wanted = surface.filter(|s| s.eq_ignore_ascii_case(ALL))?;
    let labels = set.surfaces();
    if labels.iter().any(|l| l == wanted) {
        return None;
    }
    if labels.is_empty() {
        return Some(vec![None]);
    }
    Some(labels.into_iter().map(Some).collect())
}

/// Runs `one` for each of `surfaces`. A surface that fails does not stop the others (its line is
/// printed at once, naming it); the last failure is returned, so the exit status still says that
/// something went wrong.
pub fn run(
    surfaces: &[Option<String>],
    mut one: impl FnMut(Option<&str>) -> Result<(), CliError>,
) -> Result<(), CliError> {
    let mut failed: Option<CliError> = None;
    for surface in surfaces {
        if let Err(e) = one(surface.as_deref()) {
            let e = match surface {
                Some(s) => CliError::Surface(Box::new(e), s.clone()),
                None => e,
            };
            if let Some(earlier) = failed.replace(e) {
                eprintln!("heartmesh: {}", earlier.message());
            }
        }
    }
    failed.map_or(Ok(()), Err)
}

/// `path` with `-SURFACE` before its extension (`out/mesh.obj` -> `out/mesh-LV_ENDO.obj`); the
/// label keeps letters, digits, `-`, `_` and `.` (anything else, a space or a slash, becomes `_`).
pub fn path_for(path: &str, surface: &str) -> String {
    let safe: String = surface
        .chars()
        .map(|c| {
            if c.is_alphanumeric() || "-_.".contains(c) {
                c
            } else {
                '_'
            }
        })
        .collect();
    let name_start = path.rfind(['/', '\\']).map_or(0, |i| i + 1);
    match path[name_start..].rfind('.').filter(|&i| i > 0) {
        Some(dot) => {
            let dot = name_start + dot;
            format!("{}-{safe}{}", &path[..dot], &path[dot..])
        }
        None => format!("{path}-{safe}"),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use heartmesh_core::contours::{Contour, Polyline};
    use heartmesh_core::geometry::v3;

    fn set(labels: &[Option<&str>]) -> ContourSet {
        ContourSet {
            contours: labels
                .iter()
                .enumerate()
                .map(|(i, l)| Contour {
                    id: format!("c{i}"),
                    surface: l.map(str::to_string),
                    pieces: vec![Polyline {
                        points: vec![v3(0.0, 0.0, i as f64)],
                        closed: false,
                    }],
                    first_line: 0,
                })
                .collect(),
            ..ContourSet::default()
        }
    }

    #[test]
    fn all_means_every_label_in_file_order_unless_a_surface_is_named_all() {
        let biv = set(&[
            Some("RV_ENDO"),
            Some("LV_ENDO"),
            Some("RV_ENDO"),
            Some("LV_EPI"),
        ]);
        let want: Vec<Option<String>> = ["RV_ENDO", "LV_ENDO", "LV_EPI"]
            .iter()
            .map(|s| Some(s.to_string()))
            .collect();
        assert_eq!(requested(Some("all"), &biv), Some(want.clone()));
        assert_eq!(requested(Some("ALL"), &biv), Some(want));
        assert_eq!(requested(Some("LV_ENDO"), &biv), None);
        assert_eq!(requested(None, &biv), None);
        assert_eq!(
            requested(Some("all"), &set(&[None, None])),
            Some(vec![None])
        );
        assert_eq!(
            requested(Some("all"), &set(&[Some("all"), Some("LV")])),
            None
        );
    }

    #[test]
    fn paths_get_the_label_before_the_extension() {
        assert_eq!(path_for("out/mesh.obj", "LV_ENDO"), "out/mesh-LV_ENDO.obj");
        assert_eq!(path_for("mesh", "RV"), "mesh-RV");
        assert_eq!(path_for("a.b/mesh", "RV"), "a.b/mesh-RV");
        assert_eq!(
            path_for("C:\\m\\r.json", "LV EPI/2"),
            "C:\\m\\r-LV_EPI_2.json"
        );
        assert_eq!(path_for(".hidden", "RV"), ".hidden-RV");
    }

    #[test]
    fn a_failed_surface_does_not_stop_the_next() {
        let surfaces: Vec<Option<String>> =
            vec![Some("A".into()), Some("B".into()), Some("C".into())];
        let mut ran = Vec::new();
        let r = run(&surfaces, |s| {
            ran.push(s.unwrap().to_string());
            if s == Some("B") {
                Err(CliError::usage("broken"))
            } else {
                Ok(())
            }
        });
        assert_eq!(ran, ["A", "B", "C"]);
        let e = r.unwrap_err();
        assert_eq!(e.exit_code(), 2);
        assert!(
            e.message().starts_with("surface B: broken"),
            "{}",
            e.message()
        );
    }
}
