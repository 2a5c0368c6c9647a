//! The report's integrated confidence over iterations (Fig 6.4's IC, per group): each
//! closed-loop trial's `ic_<object>` columns of `explore.csv`, median and IQR band per
//! level, one figure per object and stratum (a trial that stopped keeps its last value).

use super::{FIGURES, Group, RUNS, reference, slug};
use crate::plots::{Curve, band_curves};
use std::collections::BTreeMap;
use std::fmt::Write as _;
use std::path::Path;
use whisker_scenario::{Error, Result};
use whisker_slam::stats::prctile;

/// The `ic_<object>` columns of a closed-loop trial's `explore.csv`.
fn ic_series(dir: &Path, key: &str) -> Option<BTreeMap<String, Vec<f64>>> {
    let text = std::fs::read_to_string(dir.join(RUNS).join(key).join("explore.csv")).ok()?;
    let header = whisker_slam::csv_records::header(&text);
    let columns: Vec<(usize, String)> = header
        .iter()
        .enumerate()
        .filter_map(|(i, h)| Some((i, h.strip_prefix("ic_")?.to_string())))
        .collect();
    if columns.is_empty() {
        return None;
    }
    let mut out: BTreeMap<String, Vec<f64>> = BTreeMap::new();
    for (_, cells) in whisker_slam::csv_records::records(&text) {
        for (i, name) in &columns {
            let v = cells
                .get(*i)
                .and_then(|c| c.parse().ok())
                .unwrap_or(f64::NAN);
            out.entry(name.clone()).or_default().push(v);
        }
    }
    Some(out)
}

/// Integrated confidence over iterations per group, one figure per object.
pub(super) fn curves(
    md: &mut String,
    dir: &Path,
    figures: &Path,
    factor: &str,
    groups: &[Group],
) -> Result {
    // One figure per object and stratum, a curve per level (coloured by level).
    let mut per_object: BTreeMap<(String, String), Vec<Curve>> = BTreeMap::new();
    for g in groups {
        let series: Vec<BTreeMap<String, Vec<f64>>> = g
            .entries
            .iter()
            .filter_map(|e| ic_series(dir, &e.key))
            .collect();
        let Some(first) = series.first() else {
            continue;
        };
        for object in first.keys() {
            let runs: Vec<&Vec<f64>> = series.iter().filter_map(|s| s.get(object)).collect();
            let len = runs.iter().map(|r| r.len()).max().unwrap_or(0);
            if len == 0 {
                continue;
            }
            // At most ~400 points per curve.
            let stride = len.div_ceil(400).max(1);
            let mut curve = Curve {
                label: format!("{} (n={})", g.level, runs.len()),
                colour: g.level_index,
                x: vec![],
                median: vec![],
                q1: vec![],
                q3: vec![],
            };
            for k in (0..len).step_by(stride).chain(std::iter::once(len - 1)) {
                let mut v: Vec<f64> = runs
                    .iter()
                    .filter(|r| !r.is_empty())
                    .map(|r| r[k.min(r.len() - 1)])
                    .filter(|x| !x.is_nan())
                    .collect();
                if v.is_empty() {
                    continue;
                }
                v.sort_by(f64::total_cmp);
                curve.x.push((k + 1) as f64);
                curve.median.push(prctile(&v, 50.0));
                curve.q1.push(prctile(&v, 25.0));
                curve.q3.push(prctile(&v, 75.0));
            }
            per_object
                .entry((object.clone(), g.stratum.clone()))
                .or_default()
                .push(curve);
        }
    }
    if per_object.is_empty() {
        return Ok(());
    }
    let _ = writeln!(md, "### Integrated confidence over iterations\n");
    for ((object, stratum), curves) in per_object {
        let (at, file_at) = if stratum.is_empty() {
            (String::new(), String::new())
        } else {
            (format!(", {stratum}"), format!("--{}", slug(&stratum)))
        };
        let name = format!(
            "ic_{}-over-iterations--by--{}{file_at}.svg",
            slug(&object),
            slug(factor)
        );
        let threshold = reference(&format!("recognition.final_ic.{object}"), groups);
        band_curves(
            &figures.join(&name),
            (
                &format!("integrated confidence of {object} by {factor}{at} (median, IQR band)"),
                "whisk (iteration)",
                &format!("IC {object}"),
            ),
            &curves,
            threshold.as_ref(),
        )
        .map_err(|e| Error::Failure(e.to_string()))?;
        let _ = writeln!(md, "![IC of {object} by {factor}{at}]({FIGURES}/{name})\n");
    }
    Ok(())
}
