//! The closed loop one whisk at a time (module documentation of `closed_loop`): [`Episode`]
//! runs the iterations of [`super::run`] one [`Episode::step`] at a time, so that a caller
//! can look at the loop between whisks and choose the goal of the next one — Python's
//! Gymnasium environment (issue #65, `python/`). [`super::run`] is this loop stepped to its
//! end with the loop's own goals, so the two cannot drift apart.

use super::goal::GoalKind;
use super::log;
use super::state::{Loop, Outcome, Sensor, Tally};
use nalgebra::{Isometry3, Point3};
use whisker_scenario::Result;
use whisker_slam::rng::substream;
use whisker_slam::whisker_ratslam::posecells6d::Cell6;

/// What happens when the caller's goal is refused (unreachable, or the arm would enter the
/// object).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Refused {
    /// The strategy's next goals are tried, as in the loop of [`super::run`].
    Strategy,
    /// The array whisks where it is.
    Stay,
}

/// The last whisk, as the robot knows it (no ground truth but its own arm's pose).
#[derive(Debug, Clone)]
pub struct LastWhisk {
    /// The array's pose (world) while it whisked.
    pub pose: Isometry3<f64>,
    /// Each whisker's contact, if it touched: (whisker, point in the array frame, whisk
    /// angle at contact in rad, radial distance in m).
    pub contacts: Vec<(usize, Point3<f64>, f64, f64)>,
    /// The move's status (`reached`, `unreachable`, `collision`, `none`).
    pub status: &'static str,
    /// The goal's kind as `explore.csv` writes it (`face:3`, `spc`, `step:12`; empty: none).
    pub goal_kind: String,
    /// The loaded object WhiskerRatSLAM re-localised into, if any.
    pub onto: Option<String>,
}

/// A closed-loop run stepped from outside ([`Episode::step`]), ended by [`Episode::finish`].
pub struct Episode<'a> {
    state: Loop<'a>,
    tally: Tally,
    out: Outcome,
    seed: u64,
    iteration: usize,
    /// The goal the loop tries first at the next step, once taken ([`Episode::proposal`]).
    proposal: Option<Option<(Isometry3<f64>, GoalKind)>>,
    ended: bool,
    last: Option<LastWhisk>,
}

impl<'a> Episode<'a> {
    /// A run of the built loop `state` from the array's pose, its random draws from `seed`.
    pub(super) fn new(state: Loop<'a>, seed: u64) -> Self {
        let start = state.robot.array_pose();
        let objects: Vec<String> = state.config.maps.keys().cloned().collect();
        let out = Outcome {
            csv: log::header(&objects, state.robot.chain.dof()),
            summary: serde_json::Value::Null,
            map: None,
            poses: Vec::new(),
            contacts: Vec::new(),
            contacts_csv: crate::sensing::contact::HEADER.to_string(),
            times: Vec::new(),
            joints: Vec::new(),
            cycles: Vec::new(),
            odometry: Vec::new(),
            start,
            levels: match &state.sensing {
                Sensor::Physics(p) => Some(p.levels().to_vec()),
                Sensor::Kinematic(_) => None,
            },
        };
        let tally = Tally {
            odometry_rng: substream(seed, "explore/odometry"),
            previous: start,
            relocalisations: 0,
            truth_at_creation: Vec::new(),
            truth_at_revisit: Vec::new(),
            rc_sums: objects.iter().map(|o| (o.clone(), 0.0)).collect(),
            objects,
            pixels: whisker_sim::whisker::array::labels(),
        };
        let ended = state.config.max_iterations == 0;
        Self {
            state,
            tally,
            out,
            seed,
            iteration: 0,
            proposal: None,
            ended,
            last: None,
        }
    }

    /// Whether the run has ended: recognised (or every confidence at `stop_ic`), the map's
    /// loops done, or the whisk budget (`max_iterations`) spent.
    pub fn ended(&mut self) -> bool {
        if !self.ended && self.state.done() {
            self.ended = true;
        }
        self.ended
    }

    /// The goal the loop would try at the next step — the SPC's pending correction or the
    /// strategy's next goal — with its kind (`explore.csv`'s `goal_kind`); None once the
    /// run has ended or when the strategy has no goal (the array then whisks where it is).
    /// Asking twice gives the same goal.
    pub fn proposal(&mut self) -> Option<(Isometry3<f64>, String)> {
        if self.ended() {
            return None;
        }
        let state = &mut self.state;
        let p = *self.proposal.get_or_insert_with(|| state.next_goal());
        p.map(|(pose, kind)| (pose, kind.to_string()))
    }

    /// One iteration: the move to the proposed goal — its pose replaced by `goal` when
    /// given (the kind stays the proposal's; with no proposal `goal` is not used) — the
    /// whisk, WhiskerRatSLAM, recognition, the SPC and the strategy, and the row of
    /// `explore.csv`. Returns false, doing nothing, once the run has ended.
    pub fn step(&mut self, goal: Option<Isometry3<f64>>, refused: Refused) -> Result<bool> {
        if self.ended() {
            return Ok(false);
        }
        whisker_scenario::stop::check()?;
        self.proposal();
        let first = self
            .proposal
            .take()
            .flatten()
            .map(|(pose, kind)| (goal.unwrap_or(pose), kind));
        let (goal, status) = self.state.go(first, refused == Refused::Strategy);
        if self.ended() {
            return Ok(false);
        }
        let iteration = self.iteration;
        let w = self.state.whisk(iteration, self.seed, &mut self.tally);
        let decision = self.state.decide(&w);
        self.last = Some(LastWhisk {
            pose: w.pose,
            contacts: w
                .cycle
                .contacts
                .iter()
                .map(|c| (c.whisker, c.point, c.angle_rad, c.radial_distance))
                .collect(),
            status,
            goal_kind: goal.map(|(_, k)| k.to_string()).unwrap_or_default(),
            onto: w.onto.clone(),
        });
        self.state.log(
            iteration,
            (goal.as_ref(), status),
            w,
            decision,
            &mut self.tally,
            &mut self.out,
        )?;
        self.iteration += 1;
        if self.iteration >= self.state.config.max_iterations {
            self.ended = true;
        }
        Ok(true)
    }

    /// The seed of the run's random draws.
    pub fn seed(&self) -> u64 {
        self.seed
    }

    /// The whisks made so far.
    pub fn whisks(&self) -> usize {
        self.iteration
    }

    /// The last whisk (None before the first).
    pub fn last(&self) -> Option<&LastWhisk> {
        self.last.as_ref()
    }

    /// The array's pose now (world).
    pub fn array_pose(&self) -> Isometry3<f64> {
        self.state.robot.array_pose()
    }

    /// The loaded objects, in the order of [`Self::confidence`].
    pub fn objects(&self) -> &[String] {
        &self.tally.objects
    }

    /// The explored object's name (ground truth: for a reward, not for the robot).
    pub fn truth(&self) -> &str {
        &self.state.truth
    }

    /// Each loaded object's (raw confidence RC, integrated confidence IC) now (§6.1.2.4);
    /// zeros while building a map.
    pub fn confidence(&self) -> Vec<(f64, f64)> {
        self.tally
            .objects
            .iter()
            .map(|o| match &self.state.recognition {
                Some(r) => (r.raw.confidence[o], r.integrated[o]),
                None => (0.0, 0.0),
            })
            .collect()
    }

    /// The IC threshold of recognition (§6.2), if recognising.
    pub fn threshold(&self) -> Option<f64> {
        self.state.recognition.as_ref().map(|r| r.params.threshold)
    }

    /// The object recognised (the first whose IC crossed the threshold) and at which whisk.
    pub fn identified(&self) -> Option<(String, u64)> {
        let r = self.state.recognition.as_ref()?;
        r.identified().map(|(o, k)| (o.to_string(), k))
    }

    /// The 6-D pose cells' most active cell (x, y, z, α, β, γ in cells, Fig 5.4) and the
    /// number of experiences in the map.
    pub fn pose_cells(&self) -> (Cell6, usize) {
        (
            self.state.slam.cells.best(),
            self.state.slam.map.experiences.len(),
        )
    }

    /// The whisk budget (`explore.max_iterations`).
    pub fn budget(&self) -> usize {
        self.state.config.max_iterations
    }

    /// Ends the run: its summary (and the recording's end) and the map built.
    pub fn finish(mut self) -> Result<Outcome> {
        self.state.finish(self.tally, self.out)
    }
}
