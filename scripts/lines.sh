#!/usr/bin/env bash
# Rust lines per crate (sources and tests, vendored crates excluded) and each one's share:
# docs/design.md says no crate may hold more than 40 % of them.
set -euo pipefail
cd "$(dirname "$0")/.."
count() { find "$@" -name '*.rs' -print0 2>/dev/null | xargs -0 cat 2>/dev/null | wc -l; }
total=$(count crates src tests)
printf '%-20s %7s %6s\n' crate lines share
for c in crates/*; do
    n=$(count "$c")
    printf '%-20s %7d %5.1f%%\n' "$(basename "$c")" "$n" "$(echo "100 * $n / $total" | bc -l)"
done
n=$(count src tests)
printf '%-20s %7d %5.1f%%\n' "whisker (src, tests)" "$n" "$(echo "100 * $n / $total" | bc -l)"
printf '%-20s %7d\n' total "$total"
