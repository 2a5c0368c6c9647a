//! `whisker urdf` on any standard UR5 description, and broken URDFs.

use super::*;

#[test]
fn urdf_fk_gives_the_published_ur5_poses_for_any_standard_description() {
    let cases = [
        ("0,0,0,0,0,0", [0.817250, 0.191450, -0.005491]),
        (
            "0,-1.5707963267948966,0,-1.5707963267948966,0,0",
            [0.0, 0.191450, 1.001059],
        ),
        ("0.1,-0.5,0.8,-1.2,1.5,0.3", [0.857037, 0.201539, 0.182468]),
    ];
    for urdf in [
        "assets/urdf/ur5_whisker_array.urdf",
        "tests/fixtures/ur5_ros_style.urdf",
    ] {
        let path = repo(urdf);
        for (q, expected) in cases {
            let o = whisker(&[
                "urdf",
                "fk",
                path.to_str().unwrap(),
                "--joints",
                q,
                "--json",
            ]);
            assert!(o.status.success(), "{}", stderr(&o));
            let v: serde_json::Value = serde_json::from_str(&stdout(&o)).unwrap();
            assert_eq!(v["base"], "base_link");
            assert_eq!(v["link"], "tool0");
            for i in 0..3 {
                let got = v["position_m"][i].as_f64().unwrap();
                assert!(
                    (got - expected[i]).abs() < 1e-6,
                    "{urdf} q={q}: {got} vs {}",
                    expected[i]
                );
                assert_eq!(v["matrix"][i][3].as_f64().unwrap(), got);
            }
            let quat: Vec<f64> = (0..4)
                .map(|i| v["quaternion_xyzw"][i].as_f64().unwrap())
                .collect();
            assert!((quat.iter().map(|x| x * x).sum::<f64>() - 1.0).abs() < 1e-12);
        }
    }
    // --base and --link choose the frames; the array mount is 60 mm beyond tool0.
    let path = repo("assets/urdf/ur5_whisker_array.urdf");
    let o = whisker(&[
        "urdf",
        "fk",
        path.to_str().unwrap(),
        "--joints",
        "0,0,0,0,0,0",
        "--base",
        "base_link",
        "--link",
        "whisker_array",
        "--json",
    ]);
    let v: serde_json::Value = serde_json::from_str(&stdout(&o)).unwrap();
    assert!((v["position_m"][1].as_f64().unwrap() - (0.191450 + 0.060)).abs() < 1e-6);
    let info = whisker(&["urdf", "info", path.to_str().unwrap()]);
    assert!(info.status.success());
    assert!(stdout(&info).contains("chain  base_link -> tool0: 6 joints"));
}

#[test]
fn broken_urdfs_exit_2_naming_file_and_element() {
    let tmp = tempfile::tempdir().unwrap();
    let j = |name: &str, parent: &str, child: &str, extra: &str| {
        format!(
            r#"<joint name="{name}" type="revolute"><parent link="{parent}"/><child link="{child}"/><axis xyz="0 0 1"/><limit lower="-1" upper="1" effort="1" velocity="1"/>{extra}</joint>"#
        )
    };
    let links = r#"<link name="a"/><link name="b"/><link name="c"/>"#;
    let cases = [
        (
            "missing_parent",
            format!("{links}{}{}", j("j1", "x", "b", ""), j("j2", "b", "c", "")),
            "<joint name=\"j1\">",
        ),
        (
            "cycle",
            format!(
                "{links}{}{}{}",
                j("j1", "a", "b", ""),
                j("j2", "b", "c", ""),
                j("j3", "c", "a", "")
            ),
            "cycle",
        ),
        (
            "two_roots",
            format!("{links}{}", j("j1", "a", "b", "")),
            "root links (a, c)",
        ),
        (
            "nan",
            format!(
                "{links}{}{}",
                j("j1", "a", "b", ""),
                j("j2", "b", "c", r#"<origin xyz="0 nan 0"/>"#)
            ),
            "<joint name=\"j2\">",
        ),
        (
            "bad_number",
            format!(
                "{links}{}{}",
                j("j1", "a", "b", ""),
                j("j2", "b", "c", r#"<origin rpy="0 0 1.5.7"/>"#)
            ),
            "rpy=\"0 0 1.5.7\"",
        ),
    ];
    for (name, body, needle) in cases {
        let path = tmp.path().join(format!("{name}.urdf"));
        std::fs::write(&path, format!("<robot name=\"r\">{body}</robot>")).unwrap();
        for args in [
            vec!["urdf", "info", path.to_str().unwrap()],
            vec!["urdf", "fk", path.to_str().unwrap(), "--joints", "0,0"],
        ] {
            let o = whisker(&args);
            let err = stderr(&o);
            assert_eq!(o.status.code(), Some(2), "{name}: {err}");
            assert!(
                err.contains(&format!("{name}.urdf")) && err.contains(needle),
                "{name}: {err}"
            );
        }
    }
}
