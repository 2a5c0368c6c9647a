//! `whisker trials report DIR` (also run at the end of every batch): `report.md` and
//! `figures/*.svg` from a batch directory.
//!
//! For every factor, the trials are grouped by its level within each combination of the
//! other factors' levels (a stratum: comparing strategies on the Box-Stack, not pooled
//! over objects). Per metric and group: n, median, IQR, mean (quartiles by MATLAB's
//! `prctile`, as the thesis' box plots); a notched box plot; Mann–Whitney U between two
//! levels or Kruskal–Wallis H between more, then pairwise Mann–Whitney with Holm's
//! correction. Text metrics with few values (the recognition outcome) are counted. Closed
//! loop trials also get their integrated confidence over iterations: median and IQR band
//! per level (a trial that stopped keeps its last value; `confidence`).

mod confidence;

use super::journal::{self, Entry, Meta, RUNS, Status};
use crate::plots::{BoxGroup, Reference, notched_boxes};
use serde_json::Value;
use std::collections::{BTreeMap, BTreeSet};
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use whisker_scenario::{Error, Result};
use whisker_slam::stats::boxplot::BoxStats;
use whisker_slam::stats::rank_tests::{holm, kruskal_wallis, mann_whitney};

/// The report file.
pub const REPORT: &str = "report.md";
/// The figures' directory.
pub const FIGURES: &str = "figures";
/// At most this many distinct values make a text metric a category.
const MAX_CATEGORIES: usize = 6;
/// The SRT metric (§6.2): the true object's IC crossing, whatever crossed first.
const SRT: &str = "recognition.srt";
/// SRT over the runs that identified the true object (outcome `correct`) only.
const SRT_CORRECT: &str = "recognition.srt[correct]";
/// SRT with each censored run counted at its censoring whisk (its last).
const SRT_WITH_CENSORED: &str = "recognition.srt[with censored]";

/// One group of trials: a stratum (the other factors' levels) and a level.
struct Group<'a> {
    stratum: String,
    level: String,
    level_index: usize,
    entries: Vec<&'a Entry>,
}

/// `whisker trials report DIR`: [`write`], refused (exit 2) while another process works on
/// the batch ([`crate::lock`]).
pub fn command(dir: &Path) -> Result<PathBuf> {
    Meta::read(dir)?;
    let _lock = crate::lock::Lock::exclusive(dir)?;
    write(dir)
}

/// Writes `dir/report.md` and `dir/figures/`; returns the report's path.
pub fn write(dir: &Path) -> Result<PathBuf> {
    let meta = Meta::read(dir)?;
    let mut entries = journal::read(dir)?;
    entries.sort_by_key(|e| e.index);
    let ok: Vec<&Entry> = entries.iter().filter(|e| e.status == Status::Ok).collect();
    let figures = dir.join(FIGURES);
    // The report owns figures/: a new report leaves none of an older one's.
    if figures.is_dir() {
        std::fs::remove_dir_all(&figures)
            .map_err(|e| Error::Failure(format!("cannot clear {}: {e}", figures.display())))?;
    }
    whisker_scenario::files::create_dir(&figures)?;
    let mut md = String::new();
    let _ = writeln!(md, "# Batch report: {}\n", meta.scenario);
    let failed: Vec<&Entry> = entries
        .iter()
        .filter(|e| e.status == Status::Failed)
        .collect();
    let _ = writeln!(
        md,
        "{} of {} trials finished ({} ok, {} failed){}. Factors: {}. Rows: `{}`.\n",
        entries.len(),
        meta.keys.len(),
        ok.len(),
        failed.len(),
        meta.shard.map_or(String::new(), |s| format!(", shard {s}")),
        if meta.factors.is_empty() {
            "none (seeds only)".to_string()
        } else {
            meta.factors
                .iter()
                .map(|f| format!("`{f}`"))
                .collect::<Vec<_>>()
                .join(", ")
        },
        journal::CSV
    );
    md.push_str(
        "Quartiles as MATLAB's `prctile`; notches median ± 1.57·IQR/√n (non-overlapping notches: \
         medians differ at about the 5 % level). p-values two-sided; *exact* is the permutation \
         test on midranks (Mann–Whitney up to 60 values, Kruskal–Wallis up to 2·10⁶ assignments), \
         otherwise normal (with tie and continuity correction) or χ² (tie-corrected). Pairwise \
         p-values are Holm-corrected within each stratum.\n\n",
    );
    if !failed.is_empty() {
        md.push_str("## Failed trials\n\n| key | error |\n|---|---|\n");
        for e in &failed {
            let _ = writeln!(
                md,
                "| `{}` | {} |",
                e.key,
                e.error.as_deref().unwrap_or("").replace('|', "\\|")
            );
        }
        md.push('\n');
    }
    let (mut numeric, mut categorical) = metrics(&ok);
    if !meta.report.is_empty() {
        numeric.retain(|m| meta.report.contains(m));
        categorical.retain(|m| meta.report.contains(m));
    }
    // SRT mixes runs that identified the true object with runs that took another one
    // first: beside it, SRT over the correct runs alone.
    if let Some(i) = numeric.iter().position(|m| m == SRT) {
        numeric.insert(i + 1, SRT_CORRECT.to_owned());
        numeric.insert(i + 2, SRT_WITH_CENSORED.to_owned());
        md.push_str(
            "`recognition.srt` is the whisk at which the true object's IC reached the threshold, \
             whatever crossed first (a wrong identification may precede it); \
             `recognition.srt[correct]` is the same over the runs whose outcome is `correct` only. \
             Runs in which the true object never crossed (censored, `recognition.srt_censored_at`) \
             are missing from both — the thesis' reading, a time to a *successful* recognition, \
             which selects the runs that succeeded. `recognition.srt[with censored]` counts each \
             censored run at its censoring whisk (its last): with runs of one length, the \
             slowest rank, so its tests compare every run.\n\n",
        );
    }
    // Factors with one level (a base's factor narrowed) compare nothing.
    let varied: Vec<usize> = (0..meta.factors.len())
        .filter(|&f| meta.levels.get(f).is_none_or(|l| l.len() > 1))
        .collect();
    let groupings: Vec<Option<usize>> = if varied.is_empty() {
        vec![None]
    } else {
        varied.iter().copied().map(Some).collect()
    };
    for &f in &groupings {
        let groups = group(&ok, f, &meta.factors, &varied);
        let name = f.map_or("all trials", |f| meta.factors[f].as_str());
        let _ = writeln!(md, "## By `{name}`\n");
        if f.is_none() {
            // Seeds only: one table of every metric.
            overall(&mut md, &numeric, &groups);
        } else {
            for metric in &numeric {
                section(&mut md, &figures, name, metric, &groups)?;
            }
        }
        for metric in &categorical {
            counts(&mut md, metric, &groups);
        }
        confidence::curves(&mut md, dir, &figures, name, &groups)?;
    }
    let path = dir.join(REPORT);
    whisker_scenario::files::write_atomic(&path, md.as_bytes())?;
    Ok(path)
}

/// The numeric and the text metrics worth reporting: those that vary between trials of
/// one cell (all factors equal) or between cells, numeric ones as numbers, text ones
/// with at most [`MAX_CATEGORIES`] values.
fn metrics(ok: &[&Entry]) -> (Vec<String>, Vec<String>) {
    let keys: BTreeSet<&String> = ok.iter().flat_map(|e| e.metrics.keys()).collect();
    let mut numeric = Vec::new();
    let mut text = Vec::new();
    for k in keys {
        if k == "seed" {
            continue;
        }
        // Null is a missing value (a censored SRT), not a kind of its own.
        let values: Vec<&Value> = ok
            .iter()
            .filter_map(|e| e.metrics.get(k))
            .filter(|v| !v.is_null())
            .collect();
        let distinct: BTreeSet<String> = values.iter().map(|v| v.to_string()).collect();
        if distinct.len() < 2 {
            continue;
        }
        if values.iter().all(|v| v.is_number()) {
            numeric.push(k.clone());
        } else if values.iter().all(|v| v.is_string()) && distinct.len() <= MAX_CATEGORIES {
            // Only if it varies within some cell: else it just echoes a factor.
            let mut by_cell: BTreeMap<&Vec<String>, BTreeSet<String>> = BTreeMap::new();
            for e in ok {
                if let Some(v) = e.metrics.get(k) {
                    by_cell.entry(&e.levels).or_default().insert(v.to_string());
                }
            }
            if by_cell.values().any(|s| s.len() > 1) {
                text.push(k.clone());
            }
        }
    }
    (numeric, text)
}

/// The groups of `ok` by factor `f` within strata of the other `varied` factors (all in
/// one group without a factor), in level order.
fn group<'a>(
    ok: &[&'a Entry],
    f: Option<usize>,
    factors: &[String],
    varied: &[usize],
) -> Vec<Group<'a>> {
    let mut groups: Vec<Group<'a>> = Vec::new();
    // Level order: as the levels first appear in the trial order (the batch's order).
    let mut level_order: Vec<String> = Vec::new();
    for e in ok {
        let (stratum, level) = match f {
            None => (String::new(), "all".to_string()),
            Some(f) => {
                let others: Vec<String> = e
                    .levels
                    .iter()
                    .enumerate()
                    .filter(|&(i, _)| i != f && varied.contains(&i))
                    .map(|(i, l)| format!("{}={l}", factors[i]))
                    .collect();
                (others.join(", "), e.levels[f].clone())
            }
        };
        if !level_order.contains(&level) {
            level_order.push(level.clone());
        }
        let level_index = level_order.iter().position(|l| *l == level).expect("added");
        match groups
            .iter_mut()
            .find(|g| g.stratum == stratum && g.level == level)
        {
            Some(g) => g.entries.push(e),
            None => groups.push(Group {
                stratum,
                level,
                level_index,
                entries: vec![e],
            }),
        }
    }
    groups.sort_by(|a, b| {
        a.stratum
            .cmp(&b.stratum)
            .then(a.level_index.cmp(&b.level_index))
    });
    groups
}

fn values(g: &Group, metric: &str) -> Vec<f64> {
    if metric == SRT_WITH_CENSORED {
        return g
            .entries
            .iter()
            .filter_map(|e| {
                let at = |m: &str| e.metrics.get(m).and_then(Value::as_f64);
                at(SRT).or_else(|| at("recognition.srt_censored_at"))
            })
            .collect();
    }
    if metric == SRT_CORRECT {
        return g
            .entries
            .iter()
            .filter(|e| {
                e.metrics.get("recognition.outcome").and_then(Value::as_str) == Some("correct")
            })
            .filter_map(|e| e.metrics.get(SRT).and_then(Value::as_f64))
            .collect();
    }
    g.entries
        .iter()
        .filter_map(|e| e.metrics.get(metric).and_then(Value::as_f64))
        .collect()
}

/// The reference line of `metric`'s box plot, where one applies: the recognition
/// threshold on a final IC (Fig 6.7), 0 on IM (Fig 6.8: above it the true object crossed
/// first), the 2 cm tolerance on map errors, 1 (perfect) on ARR and ARCR (§3.2.3.1).
fn reference(metric: &str, groups: &[Group]) -> Option<Reference> {
    let threshold = || {
        groups
            .iter()
            .flat_map(|g| &g.entries)
            .find_map(|e| e.metrics.get("recognition.threshold")?.as_f64())
    };
    let (value, label) = if metric.starts_with("recognition.final_ic.") {
        (threshold()?, "IC threshold (Fig 6.7)".to_owned())
    } else if metric == "recognition.im" {
        (0.0, "0: above, the true object crossed first".to_owned())
    } else if metric.starts_with("map_accuracy.") && metric.ends_with("error_m") {
        (0.02, "2 cm tolerance".to_owned())
    } else if metric.ends_with(".arr") || metric.ends_with(".arcr") {
        (1.0, "perfect score (§3.2.3.1)".to_owned())
    } else {
        return None;
    };
    Some(Reference { value, label })
}

/// A file-name-safe version of `s`.
fn slug(s: &str) -> String {
    s.chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || c == '.' || c == '-' {
                c
            } else {
                '_'
            }
        })
        .collect()
}

/// A number for a table: 4 significant digits.
fn num(v: f64) -> String {
    if v.is_nan() {
        "–".into()
    } else if v != 0.0 && (v.abs() >= 1e5 || v.abs() < 1e-3) {
        format!("{v:.3e}")
    } else {
        let digits = (3 - v.abs().log10().floor() as i32).clamp(0, 6) as usize;
        format!("{v:.digits$}")
    }
}

fn p_text(p: f64, exact: bool) -> String {
    format!("{}{}", num(p), if exact { " (exact)" } else { "" })
}

/// One metric's table, tests and box plot.
fn section(
    md: &mut String,
    figures: &Path,
    factor: &str,
    metric: &str,
    groups: &[Group],
) -> Result {
    let _ = writeln!(md, "### {metric}\n");
    let (boxes, colours) = table(md, metric, groups);
    let strata: BTreeSet<&str> = groups.iter().map(|g| g.stratum.as_str()).collect();
    for stratum in strata {
        let in_stratum: Vec<(&Group, Vec<f64>)> = groups
            .iter()
            .filter(|g| g.stratum == stratum)
            .map(|g| (g, values(g, metric)))
            .filter(|(_, v)| !v.is_empty())
            .collect();
        tests(md, stratum, &in_stratum);
    }
    if !boxes.is_empty() {
        let name = format!("{}--by--{}.svg", slug(metric), slug(factor));
        notched_boxes(
            &figures.join(&name),
            &format!("{metric} by {factor}"),
            metric,
            &boxes,
            &colours,
            reference(metric, groups).as_ref(),
        )?;
        let _ = writeln!(md, "![{metric} by {factor}]({FIGURES}/{name})\n");
    }
    Ok(())
}

/// A metric's table (n, median, IQR, mean per stratum and level); returns the box of each
/// row and its level's colour index.
fn table(md: &mut String, metric: &str, groups: &[Group]) -> (Vec<BoxGroup>, Vec<usize>) {
    md.push_str("| stratum | level | n | median | IQR | mean |\n|---|---|---:|---:|---:|---:|\n");
    let mut boxes = Vec::new();
    let mut colours = Vec::new();
    for g in groups {
        let v = values(g, metric);
        let Some(b) = BoxStats::of(&v) else { continue };
        let _ = writeln!(
            md,
            "| {} | {} | {} | {} | {} | {} |",
            g.stratum,
            g.level,
            b.n,
            num(b.median),
            num(b.iqr()),
            num(b.mean)
        );
        boxes.push(BoxGroup {
            label: g.level.clone(),
            stratum: g.stratum.clone(),
            stats: b,
        });
        colours.push(g.level_index);
    }
    md.push('\n');
    (boxes, colours)
}

/// The tests between the levels of one stratum: Mann–Whitney for two levels; for more,
/// Kruskal–Wallis and the pairwise Mann–Whitney tests with Holm's adjustment.
fn tests(md: &mut String, stratum: &str, in_stratum: &[(&Group, Vec<f64>)]) {
    let at = if stratum.is_empty() {
        String::new()
    } else {
        format!(" ({stratum})")
    };
    match in_stratum.len() {
        0 | 1 => {}
        2 => {
            if let Some(t) = mann_whitney(&in_stratum[0].1, &in_stratum[1].1) {
                let _ = writeln!(
                    md,
                    "Mann–Whitney{at}: {} vs {}: U = {}, p = {}\n",
                    in_stratum[0].0.level,
                    in_stratum[1].0.level,
                    num(t.u),
                    p_text(t.p(), t.p_exact.is_some())
                );
            }
        }
        _ => {
            let refs: Vec<&[f64]> = in_stratum.iter().map(|(_, v)| v.as_slice()).collect();
            if let Some(t) = kruskal_wallis(&refs) {
                let _ = writeln!(
                    md,
                    "Kruskal–Wallis{at}: H = {} (df {}), p = {}\n",
                    num(t.h),
                    t.df,
                    p_text(t.p(), t.p_exact.is_some())
                );
            }
            pairwise(md, in_stratum);
        }
    }
}

/// The table of pairwise Mann–Whitney tests, with Holm-adjusted p.
fn pairwise(md: &mut String, in_stratum: &[(&Group, Vec<f64>)]) {
    let mut pairs = Vec::new();
    for i in 0..in_stratum.len() {
        for j in i + 1..in_stratum.len() {
            if let Some(t) = mann_whitney(&in_stratum[i].1, &in_stratum[j].1) {
                pairs.push((i, j, t));
            }
        }
    }
    let adjusted = holm(&pairs.iter().map(|(_, _, t)| t.p()).collect::<Vec<_>>());
    md.push_str("| pair | U | p | Holm p |\n|---|---:|---:|---:|\n");
    for ((i, j, t), a) in pairs.iter().zip(adjusted) {
        let _ = writeln!(
            md,
            "| {} vs {} | {} | {} | {} |",
            in_stratum[*i].0.level,
            in_stratum[*j].0.level,
            num(t.u),
            p_text(t.p(), t.p_exact.is_some()),
            num(a)
        );
    }
    md.push('\n');
}

/// A batch without factors: n, median, IQR and mean of every metric over all trials.
fn overall(md: &mut String, numeric: &[String], groups: &[Group]) {
    md.push_str("| metric | n | median | IQR | mean |\n|---|---:|---:|---:|---:|\n");
    for metric in numeric {
        let v: Vec<f64> = groups.iter().flat_map(|g| values(g, metric)).collect();
        if let Some(b) = BoxStats::of(&v) {
            let _ = writeln!(
                md,
                "| {metric} | {} | {} | {} | {} |",
                b.n,
                num(b.median),
                num(b.iqr()),
                num(b.mean)
            );
        }
    }
    md.push('\n');
}

/// How often each value of a text metric occurs per group.
fn counts(md: &mut String, metric: &str, groups: &[Group]) {
    let values: BTreeSet<&str> = groups
        .iter()
        .flat_map(|g| {
            g.entries
                .iter()
                .filter_map(|e| e.metrics.get(metric)?.as_str())
        })
        .collect();
    let _ = writeln!(md, "### {metric} (counts)\n");
    let _ = write!(md, "| stratum | level | n |");
    for v in &values {
        let _ = write!(md, " {v} |");
    }
    let _ = write!(md, "\n|---|---|---:|");
    for _ in &values {
        md.push_str("---:|");
    }
    md.push('\n');
    for g in groups {
        let _ = write!(md, "| {} | {} | {} |", g.stratum, g.level, g.entries.len());
        for v in &values {
            let c = g
                .entries
                .iter()
                .filter(|e| e.metrics.get(metric).and_then(Value::as_str) == Some(v))
                .count();
            let _ = write!(md, " {c} |");
        }
        md.push('\n');
    }
    md.push('\n');
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde_json::json;

    fn entry(index: usize, outcome: &str, srt: Option<f64>) -> Entry {
        let mut metrics = serde_json::Map::new();
        metrics.insert("recognition.outcome".into(), json!(outcome));
        metrics.insert("recognition.srt".into(), json!(srt));
        if srt.is_none() {
            metrics.insert("recognition.srt_censored_at".into(), json!(1000.0));
        }
        metrics.insert("recognition.threshold".into(), json!(250.0));
        Entry {
            index,
            key: format!("t{index}"),
            seed: index as u64,
            levels: vec![],
            status: Status::Ok,
            error: None,
            metrics,
            wall_s: 0.0,
        }
    }

    #[test]
    fn srt_of_correct_runs_leaves_out_wrong_and_censored_runs_and_srt_with_censored_counts_them() {
        let e = [
            entry(0, "correct", Some(120.0)),
            entry(1, "wrong", Some(400.0)),
            entry(2, "correct", Some(80.0)),
            entry(3, "none", None),
        ];
        let g = Group {
            stratum: String::new(),
            level: "all".into(),
            level_index: 0,
            entries: e.iter().collect(),
        };
        assert_eq!(values(&g, SRT), [120.0, 400.0, 80.0]);
        assert_eq!(values(&g, SRT_CORRECT), [120.0, 80.0]);
        assert_eq!(values(&g, SRT_WITH_CENSORED), [120.0, 400.0, 80.0, 1000.0]);
        // Reference lines: the batch's own threshold on a final IC, 0 on IM, 2 cm on map
        // errors, 1 on ARCR; none on SRT.
        let groups = [g];
        let at = |m: &str| reference(m, &groups).map(|r| r.value);
        assert_eq!(at("recognition.final_ic.box"), Some(250.0));
        assert_eq!(at("recognition.im"), Some(0.0));
        assert_eq!(at("map_accuracy.aligned.median_error_m"), Some(0.02));
        assert_eq!(at("normal.max_angle.arcr"), Some(1.0));
        assert_eq!(at(SRT), None);
    }
}
