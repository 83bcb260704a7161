//! The myocardium wall (`mesh::wall::build_wall`, `heartmesh myocardium`): the cut, the base ring
//! and the minimum-thickness check between two finished reconstructions, without the
//! reconstructions themselves (each costs a `pipeline` benchmark). Biv-me patient 1 at
//! end-diastole, LV_ENDO and LV_EPI at the defaults, and the biventricular solid
//! (`build_biventricular`: BIV_EPI less LV_ENDO and RV_ENDO); data from ../shared/data beside
//! the repository (not shipped).
//!
//! Also the wall's AHA segments (`metrics::segments::of_file`: the check that the epicardium
//! does not ring the RV, the septum from the RV landmarks or contours, the 17 segments), which
//! `myocardium` and the app add to every LV wall; and the LV endocardium's anatomical layout
//! (`metrics::anatomical::of_file`, `reconstruct --anatomical-mesh`) at 24x48 and 48x96, and
//! the wall as hexahedra between the two surfaces' layouts (`myocardium --hex-mesh`, 24x48x3).
//!
//! `cargo bench --bench wall`

use criterion::{criterion_group, criterion_main, Criterion};
use heartmesh_core::mesh::hex_wall;
use heartmesh_core::mesh::wall::{build_biventricular, build_wall};
use heartmesh_core::metrics::anatomical::{self, Layout};
use heartmesh_core::metrics::compare::{basal_plane, common_basal_plane, common_basal_plane_all};
use heartmesh_core::metrics::segments;
use heartmesh_core::{io, Params, Reconstruction};
use std::path::PathBuf;

fn bench(c: &mut Criterion) {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../../../../shared/data/contours/bivme-example-patient1/patient1-ED.csv");
    let bytes = std::fs::read(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let set = io::read_contours("patient1-ED.csv", &bytes).expect("contours");
    let run = |surface: &str| {
        let params = Params {
            surface: Some(surface.to_string()),
            ..Params::default()
        };
        let mut r = Reconstruction::new(&set, params).expect("valid input");
        r.run().expect("reconstruction");
        r
    };
    let (endo, epi) = (run("LV_ENDO"), run("LV_EPI"));
    let base = common_basal_plane(&endo, &epi).expect("base plane");
    let mut g = c.benchmark_group("myocardium_wall");
    g.sample_size(20);
    for (name, depth) in [
        ("patient1-ED", Some(1.0)),
        ("patient1-ED-no-min-thickness", None),
    ] {
        g.bench_function(name, |b| {
            b.iter(|| build_wall(endo.mesh(), epi.mesh(), &base, depth).expect("wall"))
        });
    }
    let wall = build_wall(endo.mesh(), epi.mesh(), &base, Some(1.0)).expect("wall");
    g.bench_function("patient1-ED-segments", |b| {
        b.iter(|| segments::of_file(&set, &wall).expect("segments"))
    });
    let endo_base = basal_plane(&endo).expect("base plane");
    for (name, layout) in [
        ("patient1-ED-anatomical-24x48", Layout::DEFAULT),
        (
            "patient1-ED-anatomical-48x96",
            Layout::new(48, 96).expect("layout"),
        ),
    ] {
        g.bench_function(name, |b| {
            b.iter(|| {
                anatomical::of_file(&set, Some("LV_ENDO"), endo.mesh(), &endo_base, layout)
                    .expect("anatomical layout")
            })
        });
    }
    let orientation = anatomical::orientation_of(&set, endo.mesh(), &base).expect("septum");
    g.bench_function("patient1-ED-hex-24x48x3", |b| {
        b.iter(|| {
            let (inner, outer) = anatomical::build_pair(
                endo.mesh(),
                epi.mesh(),
                &base,
                &orientation,
                Layout::DEFAULT,
            )
            .expect("layouts");
            hex_wall::build(&inner, &outer, Layout::DEFAULT, &base, 3).expect("cells")
        })
    });
    let (rv, biv) = (run("RV_ENDO"), run("BIV_EPI"));
    let biv_base = common_basal_plane_all(&[&endo, &biv, &rv]).expect("base plane");
    g.bench_function("patient1-ED-biventricular", |b| {
        b.iter(|| {
            build_biventricular(endo.mesh(), rv.mesh(), biv.mesh(), &biv_base, Some(1.0))
                .expect("biventricular wall")
        })
    });
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
