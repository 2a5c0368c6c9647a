//! The whiskers' 2 kHz streams in a recording (`sensors/<label>`, `docs/recording.md`):
//! per whisker one row per sample of four scalars — the whisk angle (degrees), the x and
//! y deflections (ADC counts) and the RCP state (1 while the controller retracts early,
//! §3.2.2) — sent in columns, a chunk per whisker per simulated second, not a call per
//! sample. The values are those of `whiskers.csv` (the angle there in radians).

use super::{Recording, SIM_TIME};
use crate::error::CliResult;
use whisker_slam::sensor::Sample;

/// Values per row of `sensors/<label>`.
pub const VALUES: usize = 4;
/// The series' names, in row order.
pub const NAMES: [&str; VALUES] = ["angle_deg", "x_counts", "y_counts", "rcp"];
/// Samples buffered before they are sent (one simulated second at 2 kHz).
const BATCH: usize = 2000;

/// The samples not yet sent.
#[derive(Debug, Default)]
pub struct SensorColumns {
    times: Vec<f64>,
    /// Per whisker (module order), VALUES values per sample.
    values: Vec<Vec<f64>>,
    /// Each whisker's entity path.
    entities: Vec<String>,
}

impl SensorColumns {
    /// Columns for the whiskers labelled `labels` at `<prefix>/<label>` (`prefix`:
    /// `sensors`, or `sensors/<case>`), their series named on `rec` (static).
    pub fn new(rec: &Recording, prefix: &str, labels: &[String]) -> CliResult<Self> {
        let entities: Vec<String> = labels.iter().map(|l| format!("{prefix}/{l}")).collect();
        for e in &entities {
            rec.log_static(e.as_str(), &rerun::SeriesLines::new().with_names(NAMES))?;
        }
        Ok(Self {
            times: Vec::with_capacity(BATCH),
            values: vec![Vec::with_capacity(BATCH * VALUES); labels.len()],
            entities,
        })
    }

    /// Takes every whisker's sample of time `t` (s) and its RCP state (NaN in the
    /// recording when not known); sends a full batch.
    pub fn push(
        &mut self,
        rec: &Recording,
        t: f64,
        samples: &[Sample],
        rcp: Option<&[bool]>,
    ) -> CliResult {
        self.times.push(t);
        for (w, (v, s)) in self.values.iter_mut().zip(samples).enumerate() {
            let r = rcp.map_or(f64::NAN, |r| f64::from(u8::from(r[w])));
            v.extend([s.angle_rad.to_degrees(), s.x, s.y, r]);
        }
        if self.times.len() >= BATCH {
            self.send(rec)?;
        }
        Ok(())
    }

    /// Takes whole streams: `streams[w]` holds whisker w's samples of steps `first + 1`,
    /// `first + 2` … (step k at `start` + k × 0.5 ms; as many steps as the shortest
    /// stream), with their RCP states when known ([`Self::push`]).
    pub fn push_streams(
        &mut self,
        rec: &Recording,
        start: f64,
        first: usize,
        streams: &[Vec<Sample>],
        rcp: Option<&[bool]>,
    ) -> CliResult {
        let dt = 1.0 / whisker_slam::sensor::SAMPLE_RATE_HZ;
        let n = streams.iter().map(Vec::len).min().unwrap_or(0);
        for i in 0..n {
            let row: Vec<Sample> = streams.iter().map(|s| s[i]).collect();
            self.push(rec, start + (first + i + 1) as f64 * dt, &row, rcp)?;
        }
        Ok(())
    }

    /// Sends what is buffered (one chunk per whisker).
    pub fn send(&mut self, rec: &Recording) -> CliResult {
        let n = self.times.len();
        if n == 0 {
            return Ok(());
        }
        for (entity, values) in self.entities.iter().zip(&mut self.values) {
            let column = rerun::Scalars::new(std::mem::take(values))
                .columns(std::iter::repeat_n(VALUES, n))
                .map_err(|e| super::fail(rec.path(), e))?;
            rec.send_columns(
                entity.as_str(),
                [rerun::TimeColumn::new_duration_secs(
                    SIM_TIME,
                    self.times.iter().copied(),
                )],
                column,
            )?;
            values.reserve(BATCH * VALUES);
        }
        self.times.clear();
        Ok(())
    }
}
