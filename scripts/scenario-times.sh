#!/usr/bin/env bash
# The wall time of every shipped scenario, run as a user runs it (target/release/whisker,
# seed 0, outputs in a scratch directory): a Markdown table for the README. Batches
# (trials_*.toml, office_trials.toml) are not run: their time is their trial count times a
# trial's. `--quick` leaves out the physics maze runs (~8 min each).
set -euo pipefail
cd "$(dirname "$0")/.."
W=target/release/whisker
[ -x "$W" ] || { echo "$W missing: cargo build --release first" >&2; exit 2; }
quick=no
[ "${1:-}" = --quick ] && quick=yes
scratch=$(mktemp -d)
trap 'rm -rf "$scratch"' EXIT
echo "| scenario | command | wall (s) |"
echo "|---|---|---|"
for s in scenarios/*.toml; do
    name=$(basename "$s" .toml)
    case $name in
    trials_* | office_trials) continue ;;
    maze | maze_rcp | maze_kidnapped)
        [ $quick = yes ] && continue
        cmd=(maze-slam "$s" --seeds 0 --no-rrd --out "$scratch/$name") ;;
    maze_kinematic | maze_short) cmd=(maze-slam "$s" --seeds 0 --no-rrd --out "$scratch/$name") ;;
    *) cmd=(run "$s" --no-rrd --out "$scratch/$name") ;;
    esac
    start=$(date +%s.%N)
    "$W" "${cmd[@]}" >/dev/null 2>&1 || { echo "| $name | whisker ${cmd[0]} | failed |"; continue; }
    end=$(date +%s.%N)
    printf '| %s | `whisker %s` | %.1f |\n' "$name" "${cmd[0]}" "$(echo "$end - $start" | bc -l)"
done
