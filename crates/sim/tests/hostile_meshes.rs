//! Mesh files that claim more than they hold or hold what no geometry code can use (#37):
//! each is refused with its place named, without allocating what a header claims and
//! without reaching parry with coordinates it cannot handle. Each case panicked, aborted
//! or ran for minutes before the checks it exercises.

use std::path::{Path, PathBuf};
use whisker_sim::environment::mesh::{MAX_COORDINATE_M, MeshOptions, Repair, Units, load};
use whisker_sim::environment::mesh_io::parse_ply;

const HEADER: &str = "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\n\
                      property float y\nproperty float z\n";

/// A tetrahedron in ASCII PLY with the corners scaled by `s`, after `extra` header lines
/// and with the face list's count type `count`.
fn tetrahedron(s: f64, extra: &str, count: &str) -> String {
    format!(
        "{HEADER}{extra}element face 4\nproperty list {count} int vertex_indices\nend_header\n\
         0 0 0\n{s} 0 0\n0 {s} 0\n0 0 {s}\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n"
    )
}

fn write(dir: &Path, name: &str, text: &[u8]) -> PathBuf {
    let p = dir.join(name);
    std::fs::write(&p, text).unwrap();
    p
}

fn refused(bytes: &[u8], expected: &[&str]) {
    let (at, message) = parse_ply(bytes).expect_err("refused");
    let text = format!("{at}: {message}");
    for e in expected {
        assert!(text.contains(e), "expected {e:?} in {text:?}");
    }
}

#[test]
fn the_reference_tetrahedron_loads() {
    let soup = parse_ply(tetrahedron(1.0, "", "uchar").as_bytes()).unwrap();
    assert_eq!((soup.positions.len(), soup.polygons.len()), (4, 4));
}

#[test]
fn a_list_length_is_a_claim_checked_against_the_file() {
    // 2^32 - 1 items of a 4-byte int: 34 GB asked of the allocator before.
    let ascii = tetrahedron(1.0, "", "uint").replacen("3 0 2 1", "4294967295 0 2 1", 1);
    refused(ascii.as_bytes(), &["face 0", "4294967295", "remain"]);
    let mut binary = String::from(
        "ply\nformat binary_little_endian 1.0\nelement vertex 0\nproperty float x\n\
         property float y\nproperty float z\nelement face 1\n\
         property list uint int vertex_indices\nend_header\n",
    )
    .into_bytes();
    binary.extend(u32::MAX.to_le_bytes());
    binary.extend([0u8; 12]);
    refused(&binary, &["face 0", "4294967295", "12 byte(s) remain"]);
    // Not a count at all: a fraction, a negative number, 1e300 (capacity overflow before).
    for bad in ["2.5", "-3", "1e300"] {
        let text = tetrahedron(1.0, "", "float").replacen("3 0 2 1", &format!("{bad} 0 2 1"), 1);
        refused(text.as_bytes(), &["face 0", "not a count"]);
    }
}

#[test]
fn an_element_count_is_a_claim_checked_against_the_file() {
    let claim =
        tetrahedron(1.0, "", "uchar").replace("element vertex 4", "element vertex 4000000000");
    refused(
        claim.as_bytes(),
        &["header", "\"vertex\"", "4000000000", "remain"],
    );
    let overflow = tetrahedron(1.0, "", "uchar").replace(
        "element vertex 4",
        &format!("element vertex {}", usize::MAX),
    );
    refused(overflow.as_bytes(), &["header", "remain"]);
    // An element without properties holds nothing, whatever it claims: it is skipped
    // (it ran for as long as its count before).
    let empty = tetrahedron(1.0, &format!("element junk {}\n", usize::MAX), "uchar");
    let soup = parse_ply(empty.as_bytes()).unwrap();
    assert_eq!(soup.polygons.len(), 4);
}

#[test]
fn coordinates_beyond_the_limit_are_refused_in_every_repair_mode() {
    let dir = tempfile::tempdir().unwrap();
    let far = write(
        dir.path(),
        "far.ply",
        tetrahedron(1e300, "", "uchar").as_bytes(),
    );
    let tiny = write(
        dir.path(),
        "tiny.ply",
        tetrahedron(1e-9, "", "uchar").as_bytes(),
    );
    let limit = MAX_COORDINATE_M.to_string();
    for repair in [
        Repair::Strict,
        Repair::Auto,
        Repair::Hull,
        Repair::Voxel,
        Repair::Soup,
    ] {
        let options = MeshOptions {
            repair,
            ..Default::default()
        };
        for (path, expected) in [(&far, "1.000e300 m"), (&tiny, "diagonal")] {
            let text = load(path, &options).expect_err("refused").to_string();
            for e in [path.to_str().unwrap(), "mesh:", expected, &limit] {
                assert!(text.contains(e), "{repair:?}: expected {e:?} in {text}");
            }
        }
    }
    // The limit applies after units: 1e5 mm is 100 m and loads; 1e7 mm does not.
    for (s, ok) in [(1e5, true), (1e7, false)] {
        let p = write(dir.path(), "mm.ply", tetrahedron(s, "", "uchar").as_bytes());
        let options = MeshOptions {
            units: Units::Millimetres,
            ..Default::default()
        };
        assert_eq!(load(&p, &options).is_ok(), ok, "{s} mm");
    }
}
