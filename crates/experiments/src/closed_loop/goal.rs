//! Where a whisk's goal comes from and why goals are replaced: the kinds of `explore.csv`'s
//! `goal_kind` column and the fallbacks `summary.json` counts (see the module
//! documentation of `closed_loop`).

use std::fmt;

/// What set a whisk's goal.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum GoalKind {
    /// The surface placement controller's correction (§6.1.1).
    Spc,
    /// The default trajectory's next face of the goal mesh (§6.1.2).
    Face(usize),
    /// A segment of a step to an experience (FEH, LSR; §6.1.2.1): the experience, or none
    /// once the step was given up.
    Step(Option<usize>),
}

impl fmt::Display for GoalKind {
    /// `spc`, `face:<face>`, `step:<experience>` (`step:` without one).
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            GoalKind::Spc => f.write_str("spc"),
            GoalKind::Face(face) => write!(f, "face:{face}"),
            GoalKind::Step(Some(e)) => write!(f, "step:{e}"),
            GoalKind::Step(None) => f.write_str("step:"),
        }
    }
}

/// Why a goal was replaced or a whisk went without what it was meant to have.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Fallback {
    /// No IK solution within the joint limits: the goal is dropped.
    Unreachable,
    /// The arm or the array would enter the object: the goal is dropped.
    Collision,
    /// A face goal inside the object, pushed back along its axis until clear.
    PushedBack,
    /// A whisk touched nothing: FEH and LSR give way to the default trajectory.
    LostContact,
    /// The SPC left a region unsettled after its K adjustments.
    SpcLimit,
}

impl Fallback {
    /// Every fallback, in the order `summary.json` lists them.
    pub const ALL: [Fallback; 5] = [
        Fallback::Unreachable,
        Fallback::Collision,
        Fallback::PushedBack,
        Fallback::LostContact,
        Fallback::SpcLimit,
    ];

    /// Its key in `summary.json`'s `fallbacks`.
    pub fn name(self) -> &'static str {
        match self {
            Fallback::Unreachable => "unreachable",
            Fallback::Collision => "collision",
            Fallback::PushedBack => "pushed_back",
            Fallback::LostContact => "lost_contact",
            Fallback::SpcLimit => "spc_limit",
        }
    }
}

/// How often each [`Fallback`] happened in a run.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Fallbacks([usize; 5]);

impl Fallbacks {
    /// Counts one `f`.
    pub fn count(&mut self, f: Fallback) {
        self.0[f as usize] += 1;
    }

    /// How many `f` there were.
    pub fn get(&self, f: Fallback) -> usize {
        self.0[f as usize]
    }
}
