//! The Lab's JSON inputs (web/src/lab/labProtocol.ts) turned into the core's simulation types:
//! the parametric LV (a truncated prolate spheroid, Streeter & Hanna 1973) and a CMR acquisition
//! as in the validation protocol of Villard, Grau & Zacur (J. Imaging 2018, section 3.1).
//!
//! Missing fields take the core's defaults, so the page only sends what the user changed; a field
//! that is present but not a finite number is an error naming it (never silently ignored).

use heartmesh_core::error::{CoreError, Result};
use heartmesh_core::sim::shapes::{Bulge, ParametricLv};
use heartmesh_core::sim::{AcquisitionSpec, Misalignment, SaxStack};
use serde_json::{Map, Value};

/// Parses a JSON object (the whole input must be one).
pub fn object(text: &str, what: &str) -> Result<Map<String, Value>> {
    match serde_json::from_str::<Value>(text) {
        Ok(Value::Object(map)) => Ok(map),
        Ok(_) => Err(invalid(what, "not a JSON object".into())),
        Err(e) => Err(invalid(what, format!("not a JSON object: {e}"))),
    }
}

fn invalid(name: &str, message: String) -> CoreError {
    CoreError::ParamInvalid {
        name: name.to_string(),
        message,
    }
}

/// The finite number under `key`, if present.
fn number(map: &Map<String, Value>, key: &str) -> Result<Option<f64>> {
    match map.get(key) {
        None | Some(Value::Null) => Ok(None),
        Some(v) => v
            .as_f64()
            .filter(|x| x.is_finite())
            .map(Some)
            .ok_or_else(|| invalid(key, format!("{v} is not a finite number"))),
    }
}

/// A whole number in [min, max] under `key`, if present.
fn whole(map: &Map<String, Value>, key: &str, min: f64, max: f64) -> Result<Option<usize>> {
    match number(map, key)? {
        None => Ok(None),
        Some(x) if x.fract() == 0.0 && (min..=max).contains(&x) => Ok(Some(x as usize)),
        Some(x) => Err(CoreError::ParamOutOfRange {
            name: key.to_string(),
            value: x,
            min,
            max,
        }),
    }
}

/// `{length_mm, radius_mm, base_radius_mm, bulge_mm, bulge_height, bulge_angle_deg,
/// bulge_width_mm}`; a bulge of 0 mm is no bulge. The base is closed with a flat lid so the truth
/// has a volume of its own (the comparison clips below it anyway).
pub fn parametric_lv(text: &str) -> Result<ParametricLv> {
    let map = object(text, "parametric LV")?;
    let d = ParametricLv::default();
    let bulge_mm = number(&map, "bulge_mm")?.unwrap_or(0.0);
    let bulge = (bulge_mm != 0.0)
        .then(|| -> Result<Bulge> {
            Ok(Bulge {
                amplitude_mm: bulge_mm,
                height_fraction: number(&map, "bulge_height")?.unwrap_or(0.5),
                angle_deg: number(&map, "bulge_angle_deg")?.unwrap_or(0.0),
                width_mm: number(&map, "bulge_width_mm")?.unwrap_or(10.0),
            })
        })
        .transpose()?;
    Ok(ParametricLv {
        length_mm: number(&map, "length_mm")?.unwrap_or(d.length_mm),
        radius_mm: number(&map, "radius_mm")?.unwrap_or(d.radius_mm),
        base_radius_mm: number(&map, "base_radius_mm")?.unwrap_or(d.base_radius_mm),
        bulge,
        closed_base: true,
    })
}

/// `{sax_count | sax_spacing_mm, lax_count, shift_mm, tilt_deg, noise_mm, seed}`; LAX planes take
/// the paper's angles in order (0, 90, 45, 135, 22.5, 157.5, 112.5, 67.5 degrees).
pub fn acquisition(text: &str) -> Result<AcquisitionSpec> {
    let map = object(text, "acquisition")?;
    let mut spec = AcquisitionSpec::default();
    match (
        whole(&map, "sax_count", 1.0, 60.0)?,
        number(&map, "sax_spacing_mm")?,
    ) {
        (Some(_), Some(_)) => {
            return Err(invalid(
                "sax_count",
                "give either a SAX count or a spacing, not both".into(),
            ))
        }
        (Some(n), None) => spec.sax = SaxStack::Count(n),
        (None, Some(s)) => spec.sax = SaxStack::SpacingMm(s),
        (None, None) => {}
    }
    if let Some(k) = whole(&map, "lax_count", 0.0, 8.0)? {
        spec.lax_count = k;
    }
    let shift = number(&map, "shift_mm")?.unwrap_or(0.0);
    let tilt = number(&map, "tilt_deg")?.unwrap_or(0.0);
    if shift != 0.0 || tilt != 0.0 {
        spec.misalignment = Some(Misalignment {
            shift_mm: shift,
            tilt_deg: tilt,
        });
    }
    if let Some(n) = number(&map, "noise_mm")? {
        spec.noise_mm = n;
    }
    if let Some(s) = whole(&map, "seed", 0.0, 9.007_199_254_740_991e15)? {
        spec.seed = s as u64;
    }
    Ok(spec)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn defaults_and_fields() {
        let lv = parametric_lv("{}").unwrap();
        assert_eq!(lv.length_mm, 80.0);
        assert!(lv.bulge.is_none() && lv.closed_base);
        let lv = parametric_lv(r#"{"length_mm": 70, "bulge_mm": 4}"#).unwrap();
        assert_eq!(lv.length_mm, 70.0);
        assert_eq!(lv.bulge.unwrap().amplitude_mm, 4.0);
        assert!(parametric_lv(r#"{"length_mm": "x"}"#).is_err());
        assert!(parametric_lv("[1]").is_err());
    }

    #[test]
    fn acquisition_fields() {
        let s =
            acquisition(r#"{"sax_count": 8, "lax_count": 2, "shift_mm": 2, "seed": 7}"#).unwrap();
        assert_eq!(s.sax, SaxStack::Count(8));
        assert_eq!(s.lax_count, 2);
        assert_eq!(s.misalignment.unwrap().shift_mm, 2.0);
        assert_eq!(s.seed, 7);
        assert!(acquisition(r#"{"sax_count": 8, "sax_spacing_mm": 10}"#).is_err());
        assert!(acquisition(r#"{"lax_count": 9}"#).is_err());
        assert!(acquisition(r#"{"sax_count": 2.5}"#).is_err());
        assert!(acquisition(r#"{"noise_mm": null}"#).unwrap().noise_mm == 0.0);
    }
}
