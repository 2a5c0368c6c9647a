//! Loop closures judged against the truth (issue #36): every re-localisation of the
//! planar map, by a tactile image or by a recognised object's landmark, is true when the
//! experience it lands on was made within a radius of where the base truly is, false
//! otherwise; and, for the kidnapped robot, when it first re-localised truly onto an
//! experience made before the carry.

use whisker_slam::pose::Pose2;
use whisker_slam::ratslam::experience_map::MapEvent;

/// True closures land within this of where the experience was made (m): three of the
/// office's 0.1 m pose cells.
pub const TRUE_WITHIN_M: f64 = 0.3;

/// One RatSLAM step as the evaluation sees it.
#[derive(Debug, Clone, Copy)]
pub struct StepRecord {
    /// The terrain update it belongs to.
    pub update: usize,
    /// The robot's clock at the step (s).
    pub time_s: f64,
    /// The current experience after the step and what the map did.
    pub experience: usize,
    pub event: MapEvent,
    /// The base's true pose.
    pub truth: Pose2,
    /// Whether it was a landmark's step (a recognised object) rather than an image's.
    pub landmark: bool,
}

impl StepRecord {
    /// The record of `step`, taken at update `update` and clock `time_s` with the base
    /// truly at `truth`; `landmark` if a recognised object made it.
    pub fn of(
        step: &whisker_slam::ratslam::Step,
        (update, time_s): (usize, f64),
        truth: Pose2,
        landmark: bool,
    ) -> Self {
        Self {
            update,
            time_s,
            experience: step.experience,
            event: step.event,
            truth,
            landmark,
        }
    }
}

/// The closures of a run.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Closures {
    /// By tactile images: true, false.
    pub image_true: usize,
    pub image_false: usize,
    /// By landmarks: true, false.
    pub landmark_true: usize,
    pub landmark_false: usize,
    /// The kidnapped robot's recovery, when it was kidnapped.
    pub kidnap: Option<Recovery>,
}

/// How the kidnapped robot found itself again.
#[derive(Debug, Clone, PartialEq)]
pub struct Recovery {
    /// The first update after the carry.
    pub after_update: usize,
    /// The update of the first true re-localisation onto an experience made before the
    /// carry (none: it never recovered), whether a landmark made it, and the time it took
    /// (s, stops included).
    pub recovered_at: Option<usize>,
    pub by_landmark: bool,
    pub time_s: Option<f64>,
    /// False re-localisations between the carry and the recovery (or the end).
    pub false_before: usize,
}

/// Judges every re-localisation in `steps` (in order; each experience's truth is where
/// the step that created it stood); `kidnap` the first update after a carry.
pub fn judge(steps: &[StepRecord], kidnap: Option<usize>) -> Closures {
    let mut made: Vec<(Pose2, usize)> = Vec::new();
    let mut out = Closures::default();
    let mut recovery = kidnap.map(|j| Recovery {
        after_update: j,
        recovered_at: None,
        by_landmark: false,
        time_s: None,
        false_before: 0,
    });
    let carried_at = kidnap.and_then(|j| steps.iter().find(|s| s.update >= j).map(|s| s.time_s));
    for s in steps {
        match s.event {
            MapEvent::Created => {
                debug_assert_eq!(s.experience, made.len());
                made.push((s.truth, s.update));
            }
            MapEvent::Relocalised => {
                let (at, when) = made[s.experience];
                let good = (at.x - s.truth.x).hypot(at.y - s.truth.y) <= TRUE_WITHIN_M;
                let tally = match (s.landmark, good) {
                    (false, true) => &mut out.image_true,
                    (false, false) => &mut out.image_false,
                    (true, true) => &mut out.landmark_true,
                    (true, false) => &mut out.landmark_false,
                };
                *tally += 1;
                if let Some(r) = &mut recovery
                    && r.recovered_at.is_none()
                    && s.update >= r.after_update
                {
                    if good && when < r.after_update {
                        r.recovered_at = Some(s.update);
                        r.by_landmark = s.landmark;
                        r.time_s = carried_at.map(|t0| s.time_s - t0);
                    } else if !good {
                        r.false_before += 1;
                    }
                }
            }
            MapEvent::Stay => {}
        }
    }
    out.kidnap = recovery;
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn step(
        update: usize,
        experience: usize,
        event: MapEvent,
        x: f64,
        landmark: bool,
    ) -> StepRecord {
        StepRecord {
            update,
            time_s: update as f64,
            experience,
            event,
            truth: Pose2 { x, y: 0.0, th: 0.0 },
            landmark,
        }
    }

    /// Experiences made at x = 0, 1, 2; back at 0.2 onto 0 (true, image), at 1.9 onto 1
    /// (false, landmark); the carry at update 5, then a false closure and a true one
    /// onto experience 2 by a landmark at update 7.
    #[test]
    fn closures_are_judged_by_where_their_experience_was_made() {
        use MapEvent::*;
        let steps = [
            step(0, 0, Created, 0.0, false),
            step(1, 1, Created, 1.0, false),
            step(2, 2, Created, 2.0, false),
            step(3, 0, Relocalised, 0.2, false),
            step(4, 1, Relocalised, 1.9, true),
            step(5, 3, Created, 5.0, false),
            step(6, 0, Relocalised, 1.0, false),
            step(6, 3, Relocalised, 5.1, false),
            step(7, 2, Relocalised, 2.25, true),
        ];
        let c = judge(&steps, Some(5));
        assert_eq!((c.image_true, c.image_false), (2, 1));
        assert_eq!((c.landmark_true, c.landmark_false), (1, 1));
        let r = c.kidnap.unwrap();
        // Experience 3 was made after the carry: its closure is true but no recovery.
        assert_eq!(r.recovered_at, Some(7));
        assert!(r.by_landmark);
        assert_eq!(r.time_s, Some(2.0));
        assert_eq!(r.false_before, 1);
        assert_eq!(
            judge(&steps[..7], Some(5)).kidnap.unwrap().recovered_at,
            None
        );
        assert!(judge(&steps, None).kidnap.is_none());
    }
}
