#!/usr/bin/env bash
# Golden outputs: proof that a refactor changes no behaviour (issue #33). Record the outputs
# of a fixed set of commands before the change and after it, then compare them.
#
#   scripts/golden.sh record DIR [--no-suite]   run the commands with target/release/whisker
#                                               (build it first) and keep their outputs in DIR
#   scripts/golden.sh compare A B               every file byte for byte, recordings (.rrd) by
#                                               content; exit 1 at any difference
#
# The commands: the quickstart (closed loop); object-slam --seed 0 --json; a kinematic
# maze-slam seed; a physics `run` of scenarios/whisking.toml; datasets of the three
# experiments (a kinematic and a physics maze, object walks, a closed loop), `dataset
# noise` and `slam` on each; the office (seed 0) run, its dataset and its replay; a 6-trial batch (scripts/golden/trials6.toml) and its report;
# radial generate/train/eval on small sets; characterize, urdf info/fk and `check` of every
# scenario. Console output is kept with wall-clock times masked (stderr sorted: parallel work
# prints in no fixed order). Unless --no-suite, `cargo test --release --test cli` also runs
# with WHISKER_REFUSALS set, which keeps every refused invocation of the suite (arguments,
# exit code, message; tests/cli/main.rs, `keep_refusal`) — every malformed-input case.
#
# Outputs are made in a fixed scratch directory and then moved to DIR, so that absolute
# paths printed or stored in them are the same in every recording. About 4 minutes on 2
# cores without the suite.
set -euo pipefail
cd "$(dirname "$0")/.."
export RERUN_LOG_TIME=0

usage() {
    sed -n '5,8p' "$0" >&2
    exit 2
}

# Masks wall-clock times in console output.
mask() {
    sed -E \
        -e 's/[0-9]+(\.[0-9]+)? s wall/<T> s wall/g' \
        -e 's/written in [0-9.]+ s \([0-9.]+ MB\/s\)/written in <T>/g' \
        -e 's/; [0-9]+ s$/; <T> s/' \
        -e 's/\([0-9]+ s\)$/(<T> s)/' \
        -e 's/\([0-9.]+ s; elapsed [^)]*\)/(<T>)/' \
        -e 's/^trials     [0-9]+\/([0-9]+) /trials     <n>\/\1 /' \
        -e 's/\([^()]* elapsed, about [^()]* left\)/(<T>)/'
}

record() {
    local dest=$1 suite=$2
    [ -e "$dest" ] && { echo "$dest exists: choose a new directory" >&2; exit 2; }
    local W=target/release/whisker
    [ -x "$W" ] || { echo "$W missing: cargo build --release first" >&2; exit 2; }
    local D=${TMPDIR:-/tmp}/whisker-golden-work
    rm -rf "$D"
    mkdir -p "$D/console"
    # step NAME ARGS…: runs `whisker ARGS…`, keeping its exit code and masked console output.
    step() {
        local name=$1
        shift
        local code=0
        "$W" "$@" >"$D/console/$name.stdout" 2>"$D/console/$name.stderr.raw" || code=$?
        echo "$code" >"$D/console/$name.exit"
        mask <"$D/console/$name.stdout" >"$D/console/$name.stdout.masked"
        mv "$D/console/$name.stdout.masked" "$D/console/$name.stdout"
        mask <"$D/console/$name.stderr.raw" | LC_ALL=C sort >"$D/console/$name.stderr"
        rm "$D/console/$name.stderr.raw"
        echo "  $name: exit $code" >&2
    }
    step quickstart run scenarios/quickstart.toml --out "$D/quickstart"
    step object-slam object-slam --seed 0 --json --out "$D/object-slam"
    step maze-kinematic maze-slam scenarios/maze_kinematic.toml --seeds 0 --out "$D/maze-kinematic" --json
    step whisking run scenarios/whisking.toml --out "$D/whisking"
    step dataset-maze dataset scenarios/maze_kinematic.toml --seed 1 --out "$D/dataset-maze"
    step slam-maze slam "$D/dataset-maze" --out "$D/slam-maze" --json
    step dataset-clean dataset scenarios/maze_kinematic.toml --seed 2 --clean --out "$D/dataset-clean"
    step dataset-noise dataset noise "$D/dataset-clean" --seed 7 --out "$D/dataset-noise"
    step slam-noise slam "$D/dataset-noise" --out "$D/slam-noise" --json
    step dataset-physics dataset scenarios/maze_short.toml --seed 1 --out "$D/dataset-physics"
    step slam-physics slam "$D/dataset-physics" --out "$D/slam-physics" --json
    step dataset-object dataset object-slam --objects mug,box --seed 0 --out "$D/dataset-object"
    step slam-object slam "$D/dataset-object" --out "$D/slam-object" --json
    step dataset-loop dataset scenarios/quickstart.toml --set explore.max_iterations=100 --out "$D/dataset-loop"
    step slam-loop slam "$D/dataset-loop" --out "$D/slam-loop" --json
    step office run scenarios/office.toml --seed 0 --out "$D/office"
    step dataset-office dataset scenarios/office.toml --seed 0 --out "$D/dataset-office"
    step slam-office slam "$D/dataset-office" --out "$D/slam-office" --json
    step trials trials scripts/golden/trials6.toml --out "$D/trials" --jobs 2
    step radial-training radial generate --set training --lengths 65,94 --frequencies 1 --seed 0 --out "$D/radial/training.csv"
    step radial-validation radial generate --set validation --waypoints 2 --whisks 1 --seed 0 --out "$D/radial/validation.csv"
    step radial-train radial train --data "$D/radial/training.csv" --out "$D/radial/models" --models poly5,svr10,nn1 --seed 0
    step radial-eval radial eval --data "$D/radial/validation.csv" --models "$D/radial/models" --json
    step characterize characterize --json
    step urdf-info urdf info assets/urdf/ur5_whisker_array.urdf
    step urdf-fk urdf fk assets/urdf/ur5_whisker_array.urdf --joints 0,-1.5708,0,-1.5708,0,0 --json
    for s in scenarios/*.toml; do
        step "check-$(basename "$s" .toml)" check "$s"
    done
    # Wall-clock records of the batch: not outputs.
    rm -f "$D/trials/journal.jsonl" "$D/trials/log.txt"
    for f in "$D"/trials/runs/*/stdout.txt; do
        mask <"$f" >"$f.masked" && mv "$f.masked" "$f"
    done
    if [ "$suite" = yes ]; then
        echo "  the CLI suite, keeping its refusals (several minutes)" >&2
        WHISKER_REFUSALS="$D/refusals" cargo test --release --test cli -q >"$D/console/suite.log" 2>&1 ||
            { tail -30 "$D/console/suite.log" >&2; echo "the suite failed" >&2; exit 1; }
        rm "$D/console/suite.log"
    fi
    mkdir -p "$(dirname "$dest")"
    mv "$D" "$dest"
    echo "recorded $(find "$dest" -type f | wc -l) files in $dest" >&2
}

compare() {
    local a=$1 b=$2 bad=0
    cargo build --release -q -p whisker-recording --examples
    local same=target/release/examples/rrd_same
    while IFS= read -r f; do
        if [ ! -e "$b/$f" ]; then
            echo "only in $a: $f"
            bad=1
        elif [[ $f == *.rrd ]]; then
            "$same" "$a/$f" "$b/$f" || bad=1
        elif ! cmp -s "$a/$f" "$b/$f"; then
            echo "differs: $f"
            diff <(head -c 100000 "$a/$f") <(head -c 100000 "$b/$f") | head -10 || true
            bad=1
        fi
    done < <(cd "$a" && find . -type f | LC_ALL=C sort)
    while IFS= read -r f; do
        [ -e "$a/$f" ] || { echo "only in $b: $f"; bad=1; }
    done < <(cd "$b" && find . -type f | LC_ALL=C sort)
    local n
    n=$(cd "$a" && find . -type f | wc -l)
    if [ "$bad" = 0 ]; then
        echo "identical: $n files ($(cd "$a" && find . -name '*.rrd' | wc -l) recordings by content)"
    else
        echo "golden outputs differ"
        exit 1
    fi
}

case "${1:-}" in
record)
    [ $# -ge 2 ] || usage
    suite=yes
    [ "${3:-}" = --no-suite ] && suite=no
    record "$2" "$suite"
    ;;
compare)
    [ $# -eq 3 ] || usage
    compare "$2" "$3"
    ;;
*) usage ;;
esac
