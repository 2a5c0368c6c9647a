//! The whiskers' 2 kHz streams in a recording (`sensors/<label>`, `docs/recording.md`):
//! per whisker one row per sample of four scalars — the whisk angle (degrees), the x and
//! y deflections (ADC counts) and the RCP state (1 while the controller retracts early,
//! §3.2.2) — sent in columns (`whisker_experiments::record::SensorColumns` buffers a simulated second),
//! not a call per sample.

use super::{Recording, SIM_TIME};
use whisker_experiments::record::{SENSOR_SERIES, SENSOR_VALUES};
use whisker_scenario::Result;

impl Recording {
    /// Names the series of the stream at `entity` (static).
    pub fn sensor_series(&self, entity: &str) -> Result {
        self.log_static(entity, &rerun::SeriesLines::new().with_names(SENSOR_SERIES))
    }

    /// Sends the rows of `times` (s) at `entity`, [`SENSOR_VALUES`] of `values` each, as
    /// one chunk.
    pub fn sensor_columns(&self, entity: &str, times: &[f64], values: Vec<f64>) -> Result {
        let column = rerun::Scalars::new(values)
            .columns(std::iter::repeat_n(SENSOR_VALUES, times.len()))
            .map_err(|e| super::fail(self.path(), e))?;
        self.send_columns(
            entity,
            [rerun::TimeColumn::new_duration_secs(
                SIM_TIME,
                times.iter().copied(),
            )],
            column,
        )
    }
}
