//! What `whisker fidelity` writes: the table (`fidelity.md`, printed), the levels table,
//! `fidelity.csv` (every contact), `summary.json` and `tip.svg` ([`super::figure`]).

use super::{Fidelity, Miss, Settings, compare};
use std::fmt::Write as _;
use whisker_scenario::{Error, Result};

impl Fidelity {
    /// The table printed and written as `fidelity.md`.
    pub fn table(&self) -> String {
        let mut s = String::from(
            "| object | mode | anticipated | detected | recall | precision | misses: start, end, tip, weak, other | onset ° (median, p90) | radial mm | point mm | slope |\n|---|---|---|---|---|---|---|---|---|---|---|\n",
        );
        let pair = |v: [f64; 2], digits: usize| format!("{:.digits$}, {:.digits$}", v[0], v[1]);
        for m in &self.summaries {
            let _ = writeln!(
                s,
                "| {} | {} | {} | {} | {:.1} % | {:.1} % | {} | {} | {} | {} | {} |",
                m.object,
                m.mode.name(),
                m.anticipated,
                m.detected,
                100.0 * m.recall,
                100.0 * m.precision,
                [Miss::Start, Miss::End, Miss::Tip, Miss::Weak, Miss::Other]
                    .map(|c| m.misses.get(&c).copied().unwrap_or(0).to_string())
                    .join(", "),
                pair(m.onset_deg, 1),
                pair(m.radial_mm, 1),
                pair(m.point_mm, 1),
                pair(m.slope, 2),
            );
        }
        s
    }

    /// The levels table: each mode's confirmation (counts) and span (samples) per whisker
    /// length.
    pub fn levels_table(&self) -> String {
        let mut s = String::from(
            "| mode | whisker mm | confirmation counts | span samples |\n|---|---|---|---|\n",
        );
        for l in &self.levels {
            let _ = writeln!(
                s,
                "| {} | {:.0} | {:.1} | {} |",
                l.mode.name(),
                l.length_mm,
                l.confirm_counts,
                l.smoothing_span
            );
        }
        s
    }

    /// `fidelity.csv`: one row per anticipated or detected contact.
    pub fn csv(&self) -> Result<String> {
        let mut w = csv::Writer::from_writer(Vec::new());
        for r in &self.rows {
            w.serialize(r)
                .map_err(|e| Error::Failure(format!("fidelity.csv: {e}")))?;
        }
        let bytes = w
            .into_inner()
            .map_err(|e| Error::Failure(format!("fidelity.csv: {e}")))?;
        Ok(String::from_utf8_lossy(&bytes).into_owned())
    }
}

/// `whisker fidelity`: compares (printing a line per object and mode), writes
/// `fidelity.md` (the table), `fidelity.csv` (every contact), `summary.json` and, with the
/// Box among the objects, `tip.svg` ([`super::figure`]) into `out`.
pub fn run(s: &Settings, out: &std::path::Path, ctx: crate::record::Context) -> Result<Fidelity> {
    if s.poses == 0 {
        return Err(Error::Input("--poses: expected at least 1".into()));
    }
    let model = whisker_scenario::radial_model::load_or_default(None)?;
    let f = compare(s, &model, ctx.reporter)?;
    whisker_scenario::files::create_dir(out)?;
    let md = format!(
        "# Front-end fidelity: physics against the anticipated contacts\n\n{} poses per object, noise seed {} (`whisker fidelity`); errors are |detected − anticipated| over the contacts both found on the same whisker.\n\n{}\n## Detection levels\n\nThe default rule (`[frontend] levels = \"noise\"`: 10 σ of each whisker's free whisking), fitted to each mode's RCP threshold.\n\n{}",
        f.poses,
        f.seed,
        f.table(),
        f.levels_table()
    );
    whisker_scenario::files::write_atomic(&out.join("fidelity.md"), md.as_bytes())?;
    whisker_scenario::files::write_atomic(&out.join("fidelity.csv"), f.csv()?.as_bytes())?;
    whisker_scenario::files::write_json(&out.join("summary.json"), &f)?;
    if !f.examples.is_empty() {
        let path = out.join("tip.svg");
        let svg = super::figure::svg(&path, &f.examples)?;
        whisker_scenario::files::write_atomic(&path, svg.as_bytes())?;
    }
    ctx.say(&f.levels_table());
    ctx.say(&f.table());
    Ok(f)
}
