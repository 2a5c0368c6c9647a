//! Broken URDF files give errors naming the file and the element, never a panic; the
//! things real descriptions carry (gazebo, transmissions, world link, massless links,
//! package:// meshes) are tolerated.

mod common;

use std::path::Path;
use whisker_sim::kinematics::urdf::Geometry;
use whisker_sim::kinematics::{PackagePaths, RobotModel, UrdfError};

fn parse(text: &str) -> Result<RobotModel, UrdfError> {
    RobotModel::parse(
        text,
        Path::new("broken.urdf"),
        Path::new("."),
        &PackagePaths::default(),
    )
}

fn robot(body: &str) -> String {
    format!("<robot name=\"r\">{body}</robot>")
}

const LINKS: &str = r#"<link name="a"/><link name="b"/><link name="c"/>"#;

fn joint(name: &str, parent: &str, child: &str, extra: &str) -> String {
    format!(
        r#"<joint name="{name}" type="revolute"><parent link="{parent}"/><child link="{child}"/>
           <axis xyz="0 0 1"/><limit lower="-1" upper="1" effort="1" velocity="1"/>{extra}</joint>"#
    )
}

/// (description, URDF text, text the element must contain, text the message must contain)
fn cases() -> Vec<(&'static str, String, &'static str, &'static str)> {
    let ab = joint("j1", "a", "b", "");
    vec![
        (
            "missing parent",
            robot(&format!(
                "{LINKS}{}{}",
                joint("j1", "nope", "b", ""),
                joint("j2", "b", "c", "")
            )),
            "j1",
            "nope",
        ),
        (
            "missing child",
            robot(&format!("{LINKS}{ab}{}", joint("j2", "b", "ghost", ""))),
            "j2",
            "ghost",
        ),
        (
            "cycle",
            robot(&format!(
                "{LINKS}{}{}{}",
                joint("j1", "a", "b", ""),
                joint("j2", "b", "c", ""),
                joint("j3", "c", "a", "")
            )),
            "joint",
            "cycle",
        ),
        (
            "a cycle below a chain",
            robot(&format!(
                "{LINKS}<link name=\"d\"/>{}{}{}",
                joint("j1", "b", "c", ""),
                joint("j2", "c", "b", ""),
                joint("j3", "b", "d", "")
            )),
            "joint",
            "cycle",
        ),
        (
            // A stack overflow (SIGABRT) in the XML reader before #37.
            "elements nested 100,000 deep",
            robot(&format!(
                "<link name=\"a\"/>\n<gazebo>{}{}</gazebo>",
                "<a>".repeat(100_000),
                "</a>".repeat(100_000)
            )),
            "<robot>",
            "line 2: elements nested 65 deep: expected at most 64",
        ),
        (
            "two roots",
            robot(&format!("{LINKS}{ab}")),
            "<robot>",
            "root",
        ),
        (
            "two parents",
            robot(&format!("{LINKS}{ab}{}", joint("j2", "c", "b", ""))),
            "j2",
            "one parent",
        ),
        (
            "unparsable number",
            robot(&format!(
                "{LINKS}{ab}{}",
                joint("j2", "b", "c", r#"<origin xyz="0 0 zero"/>"#)
            )),
            "j2",
            "<origin xyz=\"0 0 zero\">: expected 3 numbers",
        ),
        (
            "unparsable limit",
            robot(&format!(
                "{LINKS}{ab}{}",
                r#"<joint name="j2" type="revolute"><parent link="b"/><child link="c"/><limit lower="-1" upper="1,5" effort="1" velocity="1"/></joint>"#
            )),
            "j2",
            "upper=\"1,5\"",
        ),
        (
            "NaN origin",
            robot(&format!(
                "{LINKS}{ab}{}",
                joint("j2", "b", "c", r#"<origin xyz="0 NaN 0"/>"#)
            )),
            "j2",
            "non-finite",
        ),
        (
            "zero axis",
            robot(&format!(
                "{LINKS}{ab}{}",
                r#"<joint name="j2" type="continuous"><parent link="b"/><child link="c"/><axis xyz="0 0 0"/></joint>"#
            )),
            "j2",
            "zero vector",
        ),
        (
            "limits upside down",
            robot(&format!(
                "{LINKS}{ab}{}",
                r#"<joint name="j2" type="revolute"><parent link="b"/><child link="c"/><axis xyz="1 0 0"/><limit lower="2" upper="1" effort="1" velocity="1"/></joint>"#
            )),
            "j2",
            "above upper",
        ),
        (
            "duplicate link",
            robot(r#"<link name="a"/><link name="a"/>"#),
            "<link name=\"a\">",
            "same name",
        ),
        (
            "negative box",
            robot(
                r#"<link name="a"><collision><geometry><box size="1 -1 1"/></geometry></collision></link>"#,
            ),
            "<link name=\"a\">",
            "positive",
        ),
        ("no links", robot(""), "<robot>", "no <link>"),
        (
            "not XML",
            "<robot name=\"r\"><link name=\"a\">".to_string(),
            "<robot>",
            "URDF",
        ),
    ]
}

#[test]
fn malformed_urdfs_are_reported_with_file_and_element() {
    for (what, text, element, message) in cases() {
        match parse(&text) {
            Ok(_) => panic!("{what}: accepted"),
            Err(e) => {
                assert_eq!(e.file, Path::new("broken.urdf"), "{what}");
                assert!(
                    e.element.contains(element),
                    "{what}: element {:?} lacks {element:?}",
                    e.element
                );
                let full = e.to_string();
                assert!(
                    full.contains(message),
                    "{what}: message {full:?} lacks {message:?}"
                );
                assert!(full.starts_with("broken.urdf: "), "{what}: {full}");
            }
        }
    }
}

#[test]
fn a_long_chain_loads_in_linear_time() {
    // The cycle check walked from every link to the root: quadratic before #37.
    let n = 20_000;
    let links: String = (0..n).map(|i| format!("<link name=\"l{i}\"/>")).collect();
    let joints: String = (1..n)
        .map(|i| {
            joint(
                &format!("j{i}"),
                &format!("l{}", i - 1),
                &format!("l{i}"),
                "",
            )
        })
        .collect();
    let model = parse(&robot(&format!("{links}{joints}"))).unwrap();
    assert_eq!(
        (model.links.len(), model.joints.len(), model.root),
        (n, n - 1, 0)
    );
}

#[test]
fn a_missing_file_is_an_error_naming_it() {
    let e =
        RobotModel::load(Path::new("/no/such/robot.urdf"), &PackagePaths::default()).unwrap_err();
    assert!(e.to_string().contains("/no/such/robot.urdf") && e.to_string().contains("cannot read"));
}

#[test]
fn real_world_descriptions_are_tolerated() {
    let model = common::ur5_ros_style();
    assert_eq!(model.links[model.root].name, "world");
    // Mesh references stay unresolved (the meshes are not shipped) without failing.
    let base = &model.links[model.link("base_link").unwrap()];
    match &base.collisions[0].geometry {
        Geometry::Mesh {
            filename, resolved, ..
        } => {
            assert!(filename.starts_with("package://ur_description/"));
            assert!(resolved.is_none());
        }
        other => panic!("expected a mesh, got {other:?}"),
    }
    // ... and resolve once a package directory holding them is given.
    let dir = std::env::temp_dir().join(format!("whisker-urdf-pkg-{}", std::process::id()));
    let meshes = dir.join("ur_description/meshes/ur5/collision");
    std::fs::create_dir_all(&meshes).unwrap();
    std::fs::write(meshes.join("base.stl"), "solid base\nendsolid base\n").unwrap();
    let path = common::repo("tests/fixtures/ur5_ros_style.urdf");
    let model = RobotModel::load(&path, &PackagePaths::new([dir.clone()])).unwrap();
    let base = &model.links[model.link("base_link").unwrap()];
    assert!(
        matches!(&base.collisions[0].geometry, Geometry::Mesh { resolved: Some(p), .. } if p.ends_with("collision/base.stl"))
    );
    let _ = std::fs::remove_dir_all(dir);
}
