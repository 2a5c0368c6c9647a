//! `whisker radial` (thesis Ch 4): a small physics validation set around the Box, the
//! built-in svr10 model evaluated on it, training from a data set, and bad input.

use super::*;

#[test]
fn a_physics_validation_set_is_detected_near_the_anticipated_contacts_and_evaluates() {
    let tmp = tempfile::tempdir().unwrap();
    let data = tmp.path().join("validation.csv");
    let o = whisker(&[
        "radial",
        "generate",
        "--set",
        "validation",
        "--waypoints",
        "1",
        "--whisks",
        "1",
        "--out",
        data.to_str().unwrap(),
    ]);
    console::assert_console(&o, "Radial distance", &[], Some(tmp.path()));
    let set = rows(&data);
    assert!(set.len() >= 3, "{} contacts", set.len());
    // The recording beside the data set: each simulation's whisker streams, one whisk
    // (1 Hz: 2000 samples), and its ground-truth contact.
    let chunks = recording::checked(&tmp.path().join("validation.rrd"), &[]);
    let entities = whisker_recording::decode::entities(&chunks);
    let streams: Vec<&String> = entities
        .keys()
        .filter(|p| p.starts_with("/sensors/"))
        .collect();
    let truths = entities
        .keys()
        .filter(|p| p.ends_with("/contacts/true"))
        .count();
    assert!(!streams.is_empty());
    assert_eq!(streams.len(), truths);
    for p in streams {
        assert_eq!(
            whisker_recording::decode::scalars(&chunks, p).len(),
            2000,
            "{p}"
        );
    }
    for r in &set {
        let f = |k: usize| r[k].parse::<f64>().unwrap();
        let (truth, truth_angle, onset, wl) = (f(4), f(5), f(6), f(13));
        // The anticipated contact lies on the shaft, and the physics whisker's onset is
        // within a few degrees of the rigid whisker's contact angle.
        assert!((0.0..=wl + 1e-9).contains(&truth), "{r:?}");
        assert!(
            (onset - truth_angle).to_degrees().abs() < 5.0,
            "onset {}° vs anticipated {}°",
            onset.to_degrees(),
            truth_angle.to_degrees()
        );
        // Contact period and amplitude of a real contact.
        assert!(f(7) > 0.0 && f(8) > 500.0, "{r:?}");
    }
    // The committed default model and the two baselines, on the contacts at ≤ 0.9 L.
    let o = whisker(&[
        "radial",
        "eval",
        "--data",
        data.to_str().unwrap(),
        "--models",
        repo("assets/models").to_str().unwrap(),
        "--max-fraction",
        "1.0",
        "--json",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let v: serde_json::Value = serde_json::from_str(&stdout(&o)).unwrap();
    let models: Vec<&str> = v["models"]
        .as_array()
        .unwrap()
        .iter()
        .map(|m| m["model"].as_str().unwrap())
        .collect();
    assert_eq!(models, ["tip", "random", "svr10"]);
    for m in v["models"].as_array().unwrap() {
        // Localised contacts lie within a whisker's length of the Box.
        let d = m["face_distance_median_mm"].as_f64().unwrap();
        assert!((0.0..160.0).contains(&d), "{m}");
        let e = m["radial_error_median"].as_f64().unwrap();
        assert!((-1.0..=1.0).contains(&e), "{m}");
    }
    // The tip assumption never underestimates (the estimate is the whole length).
    assert!(v["models"][0]["radial_error_median"].as_f64().unwrap() >= 0.0);
    // On the console: the table's columns explained.
    let o = whisker(&[
        "radial",
        "eval",
        "--data",
        data.to_str().unwrap(),
        "--models",
        repo("assets/models").to_str().unwrap(),
    ]);
    console::assert_console(
        &o,
        "Validate trained regressors",
        &["model", "δr", "d", "p(tip), p(random)"],
        None,
    );
}

#[test]
fn training_writes_loadable_models_and_bad_input_is_refused() {
    let tmp = tempfile::tempdir().unwrap();
    // A synthetic training set where the radial distance is a smooth function of CP and CA.
    let mut csv = String::from(
        "case,object,whisker,frequency_hz,truth_radial_m,truth_angle_rad,onset_angle_rad,cp_s,\
         ca_counts,dv_counts_per_s,da_counts_per_s2,av_rad_per_s,aa_rad_per_s2,wl_m,base_x,\
         base_y,base_z,dir_x,dir_y,dir_z\n",
    );
    for k in 0..60 {
        let cp = 0.05 + 0.01 * (k % 10) as f64;
        let ca = 600.0 + 25.0 * (k / 10) as f64;
        let r = 0.02 + 0.3 * cp + 1e-5 * ca;
        csv.push_str(&format!(
            "c{k},rod,A1,1,{r},1.5,1.5,{cp},{ca},{},{},1.5,0,0.1,0,0,0,0,0,1\n",
            ca / cp,
            ca / cp / cp
        ));
    }
    let data = tmp.path().join("train.csv");
    std::fs::write(&data, csv).unwrap();
    let models = tmp.path().join("models");
    let o = whisker(&[
        "radial",
        "train",
        "--data",
        data.to_str().unwrap(),
        "--out",
        models.to_str().unwrap(),
        "--models",
        "poly8,svr12",
    ]);
    console::assert_console(
        &o,
        "Train the twelve regressors",
        &["PC1…", "R² train", "RMSE", "chosen"],
        Some(&models),
    );
    for name in ["poly8", "svr12"] {
        let text = std::fs::read_to_string(models.join(format!("{name}.json"))).unwrap();
        let v: serde_json::Value = serde_json::from_str(&text).unwrap();
        assert_eq!(v["features"], serde_json::json!(["Cp", "Ca", "Dv", "Da"]));
    }
    // The polynomial fits the (polynomial) function almost exactly.
    let line = stdout(&o)
        .lines()
        .find(|l| l.starts_with("poly8"))
        .unwrap()
        .to_string();
    let r2: f64 = line.split_whitespace().nth(2).unwrap().parse().unwrap();
    assert!(r2 > 0.99, "{line}");

    let bad_csv = tmp.path().join("bad.csv");
    std::fs::write(
        &bad_csv,
        std::fs::read_to_string(&data)
            .unwrap()
            .replacen(",rod,A1,1,", ",rod,A1,x,", 1),
    )
    .unwrap();
    let bad_model = tmp.path().join("badmodels");
    std::fs::create_dir_all(&bad_model).unwrap();
    std::fs::write(bad_model.join("svr10.json"), "{\"kind\": \"svr\"}").unwrap();
    // A trained model with a support vector of another length than its features (ran
    // and dropped the extra input before #37), and one whose JSON breaks on line 3.
    let inconsistent = tmp.path().join("inconsistent");
    std::fs::create_dir_all(&inconsistent).unwrap();
    let mut svr: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(models.join("svr12.json")).unwrap()).unwrap();
    svr["model"]["support"][1]
        .as_array_mut()
        .unwrap()
        .push(0.5.into());
    std::fs::write(inconsistent.join("svr12.json"), svr.to_string()).unwrap();
    let broken = tmp.path().join("broken");
    std::fs::create_dir_all(&broken).unwrap();
    std::fs::write(
        broken.join("poly8.json"),
        "{\n\"kind\": \"polynomial\",\n oops",
    )
    .unwrap();
    for (args, needles) in [
        (
            vec![
                "radial",
                "train",
                "--data",
                bad_csv.to_str().unwrap(),
                "--out",
                "x",
            ],
            vec!["bad.csv", "line 2", "frequency_hz"],
        ),
        (
            vec![
                "radial",
                "train",
                "--data",
                data.to_str().unwrap(),
                "--out",
                "x",
                "--models",
                "svr13",
            ],
            vec!["svr13", "Table 4.1"],
        ),
        (
            vec![
                "radial",
                "eval",
                "--data",
                data.to_str().unwrap(),
                "--models",
                bad_model.to_str().unwrap(),
            ],
            vec!["svr10.json", "not a radial-distance model", "missing field"],
        ),
        (
            vec![
                "radial",
                "eval",
                "--data",
                data.to_str().unwrap(),
                "--models",
                inconsistent.to_str().unwrap(),
            ],
            vec![
                "svr12.json",
                "field `model.support[1]`: 5 values, expected 4",
            ],
        ),
        (
            vec![
                "radial",
                "eval",
                "--data",
                data.to_str().unwrap(),
                "--models",
                broken.to_str().unwrap(),
            ],
            vec!["poly8.json", "line 3, column 2"],
        ),
        (
            vec![
                "radial",
                "eval",
                "--data",
                data.to_str().unwrap(),
                "--models",
                tmp.path().to_str().unwrap(),
            ],
            vec!["no model files"],
        ),
        (
            vec![
                "radial",
                "generate",
                "--set",
                "training",
                "--lengths",
                "5",
                "--out",
                "x",
            ],
            vec!["--lengths"],
        ),
    ] {
        let o = whisker(&args);
        assert_eq!(o.status.code(), Some(2), "{args:?}: {}", stderr(&o));
        for n in needles {
            assert!(
                stderr(&o).contains(n),
                "{args:?}: expected {n:?} in {}",
                stderr(&o)
            );
        }
    }
    assert!(!tmp.path().join("x").exists());
}

#[test]
fn scenario_front_end_settings_are_checked() {
    let tmp = tempfile::tempdir().unwrap();
    for (name, extra, needle) in [
        (
            "span",
            "[frontend.detection]\nsmoothing_span = 0\n",
            "frontend.detection.smoothing_span",
        ),
        (
            "model",
            "[frontend]\nradial_model = \"missing.json\"\n",
            "frontend.radial_model",
        ),
        ("unknown", "[frontend]\nradial = 1\n", "radial"),
        (
            "multiple",
            "[frontend]\nnoise_multiple = 0\n",
            "frontend.noise_multiple",
        ),
        ("levels", "[frontend]\nlevels = \"loud\"\n", "levels"),
        (
            "ignored count",
            "[frontend.detection]\nconfirm_counts = 100\n",
            "frontend.detection.confirm_counts",
        ),
    ] {
        let body = format!("sensing = \"physics\"\n{ARM}{extra}{WAYPOINT}{OUTPUT}");
        let (o, path) = run_bad(tmp.path(), name, &body);
        assert_eq!(o.status.code(), Some(2), "{name}: {}", stderr(&o));
        assert!(
            stderr(&o).contains(path.to_str().unwrap()),
            "{name}: {}",
            stderr(&o)
        );
        assert!(stderr(&o).contains(needle), "{name}: {}", stderr(&o));
    }
}
