//! The generated object catalogue (`assets/meshes`) and the primitive shapes it is built
//! from: the committed files are the generator's output, closed, outward and of their
//! documented size.

use nalgebra::Point3;
use std::path::{Path, PathBuf};
use whisker_sim::environment::assets::{CATALOGUE, obj};
use whisker_sim::environment::mesh::{MeshOptions, load};
use whisker_sim::environment::shapes::cuboid;

fn repo() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

#[test]
fn catalogue_assets_are_closed_outward_and_of_their_documented_size() {
    for asset in &CATALOGUE {
        let path = repo().join(format!("assets/meshes/{}.obj", asset.name));
        let committed = std::fs::read_to_string(&path).unwrap();
        assert!(
            committed == obj(asset),
            "{} differs from the generator's output: run `whisker assets generate`",
            path.display()
        );
        let loaded = load(&path, &MeshOptions::default()).unwrap_or_else(|e| panic!("{e}"));
        assert!(
            loaded.repairs.is_empty(),
            "{}: {:?}",
            asset.name,
            loaded.repairs
        );
        let m = &loaded.mesh;
        assert!(m.is_closed_and_consistent(), "{}", asset.name);
        assert!(
            m.component_volumes().iter().all(|&v| v > 0.0),
            "{}",
            asset.name
        );
        let s = m.size();
        for k in 0..3 {
            // Written with 6 decimals (1 µm).
            assert!(
                (s[k] - asset.size[k]).abs() < 2e-6,
                "{}: size {s:?}",
                asset.name
            );
        }
        let lo = m.vertices.iter().fold(f64::INFINITY, |a, v| a.min(v.z));
        assert!(lo.abs() < 1e-6, "{} stands on z = 0", asset.name);
        whisker_sim::environment::solids::shape(m)
            .unwrap_or_else(|e| panic!("{}: {e}", asset.name));
    }
    // Box-Stack is Box with a protrusion: same upper region, larger volume.
    let volume = |name: &str| {
        let p = repo().join(format!("assets/meshes/{name}.obj"));
        load(&p, &MeshOptions::default()).unwrap().mesh.volume()
    };
    assert!((volume("box") - 0.2 * 0.2 * 0.35).abs() < 1e-9);
    assert!((volume("box_stack") - (0.2 * 0.2 * 0.35 + 0.1 * 0.14 * 0.12)).abs() < 1e-9);
}

#[test]
fn box_union_and_cuboid_are_exact() {
    let m = cuboid(Point3::new(-1.0, -2.0, -3.0), Point3::new(1.0, 2.0, 3.0));
    assert!(m.is_closed_and_consistent());
    assert!((m.volume() - 48.0).abs() < 1e-12);
    assert_eq!(m.triangles.len(), 12);
}
