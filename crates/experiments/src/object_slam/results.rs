//! Results of `whisker object-slam`: typed rows (printed as tables or JSON by the
//! command line), CSV files and object maps in `--out`.

use super::settings::{Combo, Settings};
use super::trajectory::Trajectory;
use super::walk::{Event, Sensed};
use serde::Serialize;
use std::collections::BTreeMap;
use std::fmt;
use whisker_scenario::Result;
use whisker_slam::stats::{median, percentile};
use whisker_slam::whisker_ratslam::object_map::ObjectMap;

/// One localisation run: an object (index into the sensed data) with a parameter set,
/// the re-localisations on A's second lap and on B, and the object map A built.
pub struct LocalisationRun {
    pub object: usize,
    pub combo: Combo,
    pub on_a: Vec<Event>,
    pub on_b: Vec<Event>,
    pub map: ObjectMap,
}

/// One identification run: an object (index into the sensed data) explored along one
/// trajectory, the re-localisations, and the confidence in each mapped object per whisk.
pub struct IdentificationRun {
    pub object: usize,
    pub which: Trajectory,
    pub events: Vec<Event>,
    pub series: Vec<BTreeMap<String, f64>>,
}

/// The median, 75th percentile and maximum of a list of errors.
#[derive(Debug, Clone, Serialize)]
pub struct Summary {
    pub median: f64,
    pub p75: f64,
    pub max: f64,
}

/// One walk's re-localisations and their errors; errors are absent without ground truth.
#[derive(Debug, Clone, Serialize)]
pub struct WalkStats {
    pub relocalisations: usize,
    pub position_error_m: Option<Summary>,
    pub rotation_error_deg: Option<Summary>,
    pub perceived_position_error_m: Option<Summary>,
    pub perceived_rotation_error_deg: Option<Summary>,
    /// Re-localisations within the thesis' step of where the experience was made.
    pub true_revisits: Option<usize>,
    pub true_revisit_share: Option<f64>,
}

/// Localisation on one object with one of Table 5.1's parameter sets (Fig 5.15).
#[derive(Debug, Clone, Serialize)]
pub struct LocalisationRow {
    pub object: &'static str,
    pub parameters: String,
    pub experiences: usize,
    pub step_m: Option<f64>,
    pub step_deg: Option<f64>,
    pub thesis_step_m: f64,
    pub thesis_step_deg: f64,
    #[serde(rename = "A")]
    pub a: WalkStats,
    #[serde(rename = "B")]
    pub b: WalkStats,
}

/// Identification while exploring one object along one trajectory (Figs 5.16–5.17).
#[derive(Debug, Clone, Serialize)]
pub struct IdentificationRow {
    pub object: &'static str,
    pub trajectory: &'static str,
    pub relocalisations: usize,
    pub onto_the_right_object: usize,
    pub mean_confidence: BTreeMap<String, f64>,
    pub final_confidence: BTreeMap<String, f64>,
}

/// What `whisker object-slam` found.
#[derive(Debug, Clone, Serialize)]
pub struct Report {
    pub seed: u64,
    pub localisation: Vec<LocalisationRow>,
    pub identification: Vec<IdentificationRow>,
    /// The mapped objects, in the order of the confidence columns.
    #[serde(skip)]
    pub mapped: Vec<String>,
}

/// The statistics of one walk's re-localisations, for an object whose thesis step is
/// `thesis` (m, degrees); `known` whether the walks had ground truth.
fn walk_stats(events: &[Event], thesis: (f64, f64), known: bool) -> WalkStats {
    // Null without ground truth (no errors to summarise), not zeros.
    let summary = |v: Vec<f64>| {
        (!v.is_empty() || known).then(|| Summary {
            median: median(v.clone()),
            p75: percentile(v.clone(), 75.0),
            max: percentile(v, 100.0),
        })
    };
    let perceived: Vec<(f64, f64)> = events.iter().filter_map(|e| e.perceived).collect();
    let revisits = perceived
        .iter()
        .filter(|(t, r)| *t <= thesis.0 && *r <= thesis.1)
        .count();
    let errors: Vec<(f64, f64)> = events.iter().filter_map(|e| e.error).collect();
    WalkStats {
        relocalisations: events.len(),
        position_error_m: summary(errors.iter().map(|e| e.0).collect()),
        rotation_error_deg: summary(errors.iter().map(|e| e.1).collect()),
        perceived_position_error_m: summary(perceived.iter().map(|p| p.0).collect()),
        perceived_rotation_error_deg: summary(perceived.iter().map(|p| p.1).collect()),
        true_revisits: known.then_some(revisits),
        true_revisit_share: (!perceived.is_empty())
            .then(|| revisits as f64 / perceived.len() as f64),
    }
}

/// Localisation errors per object and parameter set (Fig 5.15); CSV `localisation.csv`
/// and the best set's object maps `maps/<object>.json` in `--out`.
pub fn localisation(
    o: &Settings,
    data: &[Sensed],
    runs: &[LocalisationRun],
) -> Result<Vec<LocalisationRow>> {
    let mut csv = String::from(
        "object,parameters,trajectory,sample,position_error_m,rotation_error_deg,perceived_position_error_m,perceived_rotation_error_deg\n",
    );
    let mut rows = Vec::new();
    for LocalisationRun {
        object,
        combo,
        on_a,
        on_b,
        map,
    } in runs
    {
        let Sensed { asset, step, .. } = &data[*object];
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
        let thesis = super::settings::thesis_step(asset.name);
        rows.push(LocalisationRow {
            object: asset.name,
            parameters: combo.name(),
            experiences: map.experiences.len(),
            step_m: step.map(|s| s.0),
            step_deg: step.map(|s| s.1.to_degrees()),
            thesis_step_m: thesis.0,
            thesis_step_deg: thesis.1,
            a: walk_stats(on_a, thesis, step.is_some()),
            b: walk_stats(on_b, thesis, step.is_some()),
        });
        if let Some(dir) = &o.out
            && *combo == Combo::BEST
        {
            let maps = dir.join("maps");
            whisker_scenario::files::create_dir(&maps)?;
            whisker_scenario::files::write_json(&maps.join(format!("{}.json", asset.name)), &map)?;
        }
    }
    if let Some(dir) = &o.out {
        whisker_scenario::files::write_atomic(&dir.join("localisation.csv"), csv.as_bytes())?;
    }
    Ok(rows)
}

/// Identification confidence per explored object and mapped object (Figs 5.16–5.17); CSV
/// `identification.csv` in `--out`.
pub fn identification(
    o: &Settings,
    data: &[Sensed],
    mapped: &[String],
    runs: &[IdentificationRun],
) -> Result<Vec<IdentificationRow>> {
    let mut csv = format!("object,trajectory,sample,{}\n", mapped.join(","));
    let mut rows = Vec::new();
    for IdentificationRun {
        object,
        which,
        events,
        series,
    } in runs
    {
        let name = data[*object].asset.name;
        for (k, c) in series.iter().enumerate() {
            let values: Vec<String> = mapped.iter().map(|m| c[m].to_string()).collect();
            csv += &format!("{name},{},{k},{}\n", which.name(), values.join(","));
        }
        let n = series.len().max(1) as f64;
        let mean = mapped
            .iter()
            .map(|m| (m.clone(), series.iter().map(|c| c[m]).sum::<f64>() / n))
            .collect();
        let right = events
            .iter()
            .filter(|e| e.object.as_deref() == Some(name))
            .count();
        rows.push(IdentificationRow {
            object: name,
            trajectory: which.name(),
            relocalisations: events.len(),
            onto_the_right_object: right,
            mean_confidence: mean,
            final_confidence: series.last().cloned().unwrap_or_default(),
        });
    }
    if let Some(dir) = &o.out {
        whisker_scenario::files::write_atomic(&dir.join("identification.csv"), csv.as_bytes())?;
    }
    Ok(rows)
}

impl fmt::Display for Report {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        writeln!(
            f,
            "Localisation (§5.2.2.1, Fig 5.15): errors at re-localisations, median / 75th percentile; true = true revisits (perceived-pose error within the thesis' step)"
        )?;
        writeln!(
            f,
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
        )?;
        for r in &self.localisation {
            // Absent (no ground truth) reads n/a.
            let cell = |s: &Option<Summary>, scale: f64| match s {
                None => "n/a".to_string(),
                Some(s) => format!("{:.1} / {:.1}", s.median * scale, s.p75 * scale),
            };
            let count = |w: &WalkStats| {
                format!(
                    "{}/{}",
                    w.relocalisations,
                    w.true_revisits.map_or("n/a".into(), |n| n.to_string())
                )
            };
            let step = match (r.step_m, r.step_deg) {
                (Some(m), Some(d)) => format!("{:>5.1}cm {d:>3.0}°", m * 100.0),
                _ => format!("{:>12}", "n/a"),
            };
            writeln!(
                f,
                "  {:<10} {:<20} {:>5} {step} {:>7} {:>17} {:>15} {:>7} {:>17} {:>15}",
                r.object,
                r.parameters,
                r.experiences,
                count(&r.a),
                cell(&r.a.position_error_m, 100.0),
                cell(&r.a.rotation_error_deg, 1.0),
                count(&r.b),
                cell(&r.b.position_error_m, 100.0),
                cell(&r.b.rotation_error_deg, 1.0),
            )?;
        }
        writeln!(
            f,
            "Identification (§5.2.2.2, Figs 5.16-5.17): mean confidence over one lap (maps: best set; {} unmapped)",
            super::settings::UNMAPPED
        )?;
        write!(
            f,
            "  {:<10} {:<4} {:>7} {:>6}",
            "object", "traj", "reloc", "right"
        )?;
        for m in &self.mapped {
            write!(f, " {m:>8}")?;
        }
        writeln!(f)?;
        for r in &self.identification {
            write!(
                f,
                "  {:<10} {:<4} {:>7} {:>6}",
                r.object, r.trajectory, r.relocalisations, r.onto_the_right_object
            )?;
            for m in &self.mapped {
                write!(
                    f,
                    " {:>8.3}",
                    r.mean_confidence.get(m).copied().unwrap_or(f64::NAN)
                )?;
            }
            writeln!(f)?;
        }
        f.write_str(&whisker_scenario::console::legend(
            "columns",
            &[
                ("parameters", "features / merging / contact points (Table 5.1): pfh = point feature histogram, sda = slope distribution array, both; merged = a re-localisation averages the matched experience's features with the observed ones (Table 5.1 \"feature update\"); tip = the whisker tip at the contact angle, svr = the radial-distance estimate"),
                ("exps", "experiences in the object map built on lap 1 of trajectory A"),
                ("step", "the thesis' step between poses (§5.2.2.1); a re-localisation within it is a true revisit"),
                ("nA/true", "trajectory A's second lap (the mapped path again): re-localisations / true revisits among them"),
                ("nB/true", "trajectory B (a novel path, A's map as prior): the same"),
                ("position, rotation", "error of the re-localised experience's map pose against the true pose, median / 75th percentile (cm, °); lower is better (Fig 5.15)"),
                ("reloc, right", "re-localisations over one lap, and those onto the true object's map"),
                ("confidence", "per mapped object, the leaky-integrated share of re-localisations onto it, 0–1 (decay 0.9 per whisk); the true object's should be the highest"),
            ],
        ))
    }
}
