//! `whisker trials slurm SCENARIO --out DIR --shards K`: the scripts that run a batch on a
//! Slurm cluster as a job array of K shards plus a merge job that waits for it
//! (`afterok`). The shard comes from an
//! explicit `--shard ${SLURM_ARRAY_TASK_ID}/K` with K fixed in the script (re-running
//! failed tasks with `--array=3,7` splits the work the same way), outputs are named
//! `%A_%a`, and a task whose shard directory exists resumes it.
//!
//! Time limits and preemption (issue #68): the array asks for `--requeue` and
//! `--signal=B:TERM@60`, so Slurm sends SIGTERM to the task's script 60 s before its time
//! limit (and on preemption or `scancel --signal=TERM`). The script runs `whisker trials` in
//! the background and passes the signal on; `whisker trials` stops its running trials
//! cleanly within its grace (20 s) and exits 143, and the script then requeues its own
//! task (`scontrol requeue`), which, run again, resumes its shard. A preemption with
//! `PreemptMode=REQUEUE` requeues the task itself; the script's request is then redundant.
//!
//! Written into `DIR/slurm/`: `array.sh`, `merge.sh` and `submit.sh` (submits both and
//! prints the job IDs). Shards go to `DIR/shards/<I>/`, the merged batch to `DIR/`. On a
//! real cluster DIR must be on a filesystem every node sees.

use std::path::{Path, PathBuf};
use whisker_scenario::grid::{Batch, quote};
use whisker_scenario::{Error, Result};

/// Seconds before a time limit at which Slurm sends SIGTERM (`--signal=B:TERM@…`): the
/// grace of `whisker trials` (20 s) and the requeue, with room to spare.
pub const SIGNAL_S: u32 = 60;

/// `whisker trials slurm`.
#[derive(Debug, Clone)]
pub struct Settings {
    /// The scenario with `[trials]`.
    pub scenario: PathBuf,
    /// The batch directory (scripts in slurm/, shards in shards/, merged results here).
    pub out: PathBuf,
    /// Number of array tasks K (each runs every K-th trial).
    pub shards: usize,
    /// CPUs per task (worker threads of each shard).
    pub cpus_per_task: usize,
    /// Extra `#SBATCH` option for both jobs, e.g. `--sbatch=--partition=short`
    /// (repeatable).
    pub sbatch: Vec<String>,
    /// The `whisker` binary the jobs run [default: this one].
    pub whisker: Option<PathBuf>,
}

fn absolute(p: &Path) -> Result<PathBuf> {
    std::path::absolute(p).map_err(|e| Error::Input(format!("{}: {e}", p.display())))
}

/// Writes the scripts; returns the path of `submit.sh`.
pub fn write(o: &Settings) -> Result<PathBuf> {
    let batch = Batch::load(&o.scenario)?;
    if o.shards == 0 || o.shards > 1000 {
        return Err(Error::Input(format!(
            "--shards: expected 1 to 1000 (Slurm's default MaxArraySize is 1001), got {}",
            o.shards
        )));
    }
    if o.cpus_per_task == 0 {
        return Err(Error::Input("--cpus-per-task: expected at least 1".into()));
    }
    let k = o.shards.min(batch.trials.len());
    let whisker = match &o.whisker {
        Some(p) => absolute(p)?,
        None => std::env::current_exe()
            .map_err(|e| Error::Failure(format!("cannot find this binary: {e}")))?,
    };
    let scenario = absolute(&o.scenario)?;
    let out = absolute(&o.out)?;
    let dir = out.join("slurm");
    whisker_scenario::files::create_dir(&dir.join("logs"))?;
    whisker_scenario::files::create_dir(&out.join("shards"))?;
    let q = |p: &Path| quote(&p.display().to_string());
    let extra: String = o.sbatch.iter().map(|s| format!("#SBATCH {s}\n")).collect();
    let array = format!(
        "#!/bin/bash\n\
         # {n} trials of {scenario} in {k} shards (whisker trials slurm).\n\
         #SBATCH --job-name=whisker-trials\n\
         #SBATCH --array=0-{last}\n\
         #SBATCH --cpus-per-task={cpus}\n\
         #SBATCH --output={logs}/%A_%a.log\n\
         #SBATCH --requeue\n\
         #SBATCH --open-mode=append\n\
         #SBATCH --signal=B:TERM@{signal_s}\n\
         {extra}\
         set -uo pipefail\n\
         I=${{SLURM_ARRAY_TASK_ID:?not run as a Slurm array task}}\n\
         SHARD={shards}/$I\n\
         RESUME=()\n\
         [ -e \"$SHARD/trials.json\" ] && RESUME=(--resume)\n\
         # SIGTERM (time limit, preemption, scancel --signal=TERM) goes on to whisker, which\n\
         # stops its running trials cleanly and exits 143; the task then requeues itself.\n\
         {whisker} trials {scenario_q} --out \"$SHARD\" --shard \"$I/{k}\" \
         --jobs \"${{SLURM_CPUS_PER_TASK:-{cpus}}}\" --no-report \"${{RESUME[@]}}\" &\n\
         PID=$!\n\
         trap 'kill -TERM \"$PID\" 2>/dev/null' TERM\n\
         CODE=0\n\
         wait \"$PID\" || CODE=$?\n\
         while kill -0 \"$PID\" 2>/dev/null; do CODE=0; wait \"$PID\" || CODE=$?; done\n\
         if [ \"$CODE\" -eq 143 ]; then\n\
         \x20   echo \"whisker trials stopped by SIGTERM: requeueing task ${{SLURM_ARRAY_JOB_ID}}_$I\"\n\
         \x20   scontrol requeue \"${{SLURM_ARRAY_JOB_ID}}_$I\"\n\
         fi\n\
         exit \"$CODE\"\n",
        n = batch.trials.len(),
        scenario = scenario.display(),
        last = k - 1,
        cpus = o.cpus_per_task,
        signal_s = SIGNAL_S,
        logs = dir.join("logs").display(),
        shards = q(&out.join("shards")),
        whisker = q(&whisker),
        scenario_q = q(&scenario),
    );
    let shard_dirs: Vec<String> = (0..k)
        .map(|i| q(&out.join("shards").join(i.to_string())))
        .collect();
    let merge = format!(
        "#!/bin/bash\n\
         # Merges the {k} shards into {out} once every array task succeeded (afterok).\n\
         #SBATCH --job-name=whisker-trials-merge\n\
         #SBATCH --output={logs}/merge-%j.log\n\
         {extra}\
         set -euo pipefail\n\
         exec {whisker} trials merge {dirs} --out {out_q}\n",
        out = out.display(),
        logs = dir.join("logs").display(),
        whisker = q(&whisker),
        dirs = shard_dirs.join(" "),
        out_q = q(&out),
    );
    let submit = format!(
        "#!/bin/bash\n\
         # Submits the array, then the merge job that waits for it; prints both job IDs.\n\
         set -euo pipefail\n\
         ARRAY=$(sbatch --parsable {array})\n\
         MERGE=$(sbatch --parsable --dependency=afterok:${{ARRAY%%;*}} {merge})\n\
         echo \"${{ARRAY%%;*}} $MERGE\"\n",
        array = q(&dir.join("array.sh")),
        merge = q(&dir.join("merge.sh")),
    );
    for (name, text) in [
        ("array.sh", array),
        ("merge.sh", merge),
        ("submit.sh", submit),
    ] {
        let path = dir.join(name);
        whisker_scenario::files::write_atomic(&path, text.as_bytes())?;
        set_executable(&path)?;
    }
    Ok(dir.join("submit.sh"))
}

fn set_executable(path: &Path) -> Result {
    use std::os::unix::fs::PermissionsExt;
    std::fs::set_permissions(path, std::fs::Permissions::from_mode(0o755))
        .map_err(|e| Error::Failure(format!("{}: {e}", path.display())))
}
