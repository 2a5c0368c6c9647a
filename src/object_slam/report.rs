//! Reports of `whisker object-slam`: tables (or JSON values), CSV files and object maps.

use super::{Combo, IdentificationRun, LocalisationRun, Options, Sensed};
use crate::error::{CliError, CliResult};
use serde_json::{Value, json};
use whisker_slam::stats::median;

/// Percentile `p` (0–100) of a list, by nearest rank (NaN when empty).
fn percentile(mut v: Vec<f64>, p: f64) -> f64 {
    if v.is_empty() {
        return f64::NAN;
    }
    v.sort_by(f64::total_cmp);
    let rank = ((p / 100.0) * v.len() as f64).ceil().max(1.0) as usize;
    v[rank.min(v.len()) - 1]
}

/// Localisation errors per object and parameter set (Fig 5.15): JSON, CSV
/// `localisation.csv` and the best set's object maps `maps/<object>.json` in `--out`.
pub fn localisation(o: &Options, data: &[Sensed], runs: &[LocalisationRun]) -> CliResult<Value> {
    let mut csv = String::from(
        "object,parameters,trajectory,sample,position_error_m,rotation_error_deg,perceived_position_error_m,perceived_rotation_error_deg\n",
    );
    let mut rows = Vec::new();
    for (i, combo, on_a, on_b, map) in runs {
        let (asset, _, _, step) = &data[*i];
        for (name, events) in [("A", on_a), ("B", on_b)] {
            for e in events {
                // Errors need ground truth: empty cells without it.
                let pair =
                    |v: Option<(f64, f64)>| v.map_or(",".into(), |(a, b)| format!("{a},{b}"));
                csv += &format!(
                    "{},{},{name},{},{},{}\n",
                    asset.name,
                    combo.name(),
                    e.sample,
                    pair(e.error),
                    pair(e.perceived)
                );
            }
        }
        let (thesis_m, thesis_deg) = super::thesis_step(asset.name);
        // Null without ground truth (no errors to summarise), not zeros.
        let summary = |v: Vec<f64>| {
            if v.is_empty() && step.is_none() {
                return Value::Null;
            }
            json!({ "median": median(v.clone()), "p75": percentile(v.clone(), 75.0), "max": percentile(v, 100.0) })
        };
        let stats = |events: &[super::Event]| {
            let perceived: Vec<(f64, f64)> = events.iter().filter_map(|e| e.perceived).collect();
            let revisits = perceived
                .iter()
                .filter(|(t, r)| *t <= thesis_m && *r <= thesis_deg)
                .count();
            let errors: Vec<(f64, f64)> = events.iter().filter_map(|e| e.error).collect();
            json!({
                "relocalisations": events.len(),
                "position_error_m": summary(errors.iter().map(|e| e.0).collect()),
                "rotation_error_deg": summary(errors.iter().map(|e| e.1).collect()),
                "perceived_position_error_m": summary(perceived.iter().map(|p| p.0).collect()),
                "perceived_rotation_error_deg": summary(perceived.iter().map(|p| p.1).collect()),
                "true_revisits": if step.is_none() { Value::Null } else { json!(revisits) },
                "true_revisit_share": if perceived.is_empty() { Value::Null } else { json!(revisits as f64 / perceived.len() as f64) },
            })
        };
        rows.push(json!({
            "object": asset.name,
            "parameters": combo.name(),
            "experiences": map.experiences.len(),
            "step_m": step.map(|s| s.0),
            "step_deg": step.map(|s| s.1.to_degrees()),
            "thesis_step_m": thesis_m,
            "thesis_step_deg": thesis_deg,
            "A": stats(on_a),
            "B": stats(on_b),
        }));
        if let Some(dir) = &o.out
            && *combo == Combo::BEST
        {
            let maps = dir.join("maps");
            crate::output::create_dir(&maps)?;
            map.save(&maps.join(format!("{}.json", asset.name)))
                .map_err(CliError::Failure)?;
        }
    }
    if let Some(dir) = &o.out {
        crate::output::write_atomic(&dir.join("localisation.csv"), csv.as_bytes())?;
    }
    if !o.json {
        println!(
            "Localisation (§5.2.2.1, Fig 5.15): errors at re-localisations, median / 75th percentile; true = true revisits (perceived-pose error within the thesis' step)"
        );
        println!(
            "  {:<10} {:<20} {:>5} {:>12} {:>7} {:>17} {:>15} {:>7} {:>17} {:>15}",
            "object",
            "parameters",
            "exps",
            "step",
            "nA/true",
            "A position cm",
            "A rotation °",
            "nB/true",
            "B position cm",
            "B rotation °"
        );
        for r in &rows {
            // Null (no ground truth) reads n/a.
            let cell = |t: &str, k: &str, scale: f64| {
                if r[t][k].is_null() {
                    return "n/a".to_string();
                }
                format!(
                    "{:.1} / {:.1}",
                    r[t][k]["median"].as_f64().unwrap_or(f64::NAN) * scale,
                    r[t][k]["p75"].as_f64().unwrap_or(f64::NAN) * scale
                )
            };
            let count = |t: &str| {
                let revisits = r[t]["true_revisits"].as_u64();
                format!(
                    "{}/{}",
                    r[t]["relocalisations"].as_u64().unwrap_or(0),
                    revisits.map_or("n/a".into(), |n| n.to_string())
                )
            };
            let step = match (r["step_m"].as_f64(), r["step_deg"].as_f64()) {
                (Some(m), Some(d)) => format!("{:>5.1}cm {d:>3.0}°", m * 100.0),
                _ => format!("{:>12}", "n/a"),
            };
            println!(
                "  {:<10} {:<20} {:>5} {step} {:>7} {:>17} {:>15} {:>7} {:>17} {:>15}",
                r["object"].as_str().unwrap_or(""),
                r["parameters"].as_str().unwrap_or(""),
                r["experiences"].as_u64().unwrap_or(0),
                count("A"),
                cell("A", "position_error_m", 100.0),
                cell("A", "rotation_error_deg", 1.0),
                count("B"),
                cell("B", "position_error_m", 100.0),
                cell("B", "rotation_error_deg", 1.0),
            );
        }
    }
    Ok(Value::Array(rows))
}

/// Identification confidence per explored object and mapped object (Figs 5.16–5.17):
/// JSON, CSV `identification.csv` in `--out`.
pub fn identification(
    o: &Options,
    data: &[Sensed],
    mapped: &[String],
    runs: &[IdentificationRun],
) -> CliResult<Value> {
    let mut csv = format!("object,trajectory,sample,{}\n", mapped.join(","));
    let mut rows = Vec::new();
    for (i, which, events, series) in runs {
        let name = data[*i].0.name;
        for (k, c) in series.iter().enumerate() {
            let values: Vec<String> = mapped.iter().map(|m| c[m].to_string()).collect();
            csv += &format!("{name},{},{k},{}\n", which.name(), values.join(","));
        }
        let n = series.len().max(1) as f64;
        let mean: serde_json::Map<String, Value> = mapped
            .iter()
            .map(|m| {
                (
                    m.clone(),
                    json!(series.iter().map(|c| c[m]).sum::<f64>() / n),
                )
            })
            .collect();
        let right = events
            .iter()
            .filter(|e| e.object.as_deref() == Some(name))
            .count();
        rows.push(json!({
            "object": name,
            "trajectory": which.name(),
            "relocalisations": events.len(),
            "onto_the_right_object": right,
            "mean_confidence": mean,
            "final_confidence": series.last().cloned().unwrap_or_default(),
        }));
    }
    if let Some(dir) = &o.out {
        crate::output::write_atomic(&dir.join("identification.csv"), csv.as_bytes())?;
    }
    if !o.json {
        println!(
            "Identification (§5.2.2.2, Figs 5.16-5.17): mean confidence over one lap (maps: best set; {} unmapped)",
            super::UNMAPPED
        );
        print!(
            "  {:<10} {:<4} {:>7} {:>6}",
            "object", "traj", "reloc", "right"
        );
        for m in mapped {
            print!(" {:>8}", m);
        }
        println!();
        for r in &rows {
            print!(
                "  {:<10} {:<4} {:>7} {:>6}",
                r["object"].as_str().unwrap_or(""),
                r["trajectory"].as_str().unwrap_or(""),
                r["relocalisations"].as_u64().unwrap_or(0),
                r["onto_the_right_object"].as_u64().unwrap_or(0)
            );
            for m in mapped {
                print!(
                    " {:>8.3}",
                    r["mean_confidence"][m].as_f64().unwrap_or(f64::NAN)
                );
            }
            println!();
        }
    }
    Ok(Value::Array(rows))
}
