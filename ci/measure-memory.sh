#!/bin/sh
# Measures the memory guard's estimate against the peak resident set size
# of real campaigns (README, "Memory guard"): for each shape and thread
# count, the estimate `metabezier check` prints and the peak RSS that
# `/usr/bin/time -v` reports, both less those of the same campaign with one
# run per cell, so that the program, the spec and the working memory of the
# runs in flight cancel out.
#
#   ci/measure-memory.sh [BIN]        (default target/release/metabezier)
#
# The estimate counts every target as hit by every benchmark run (the hits
# a run reaches are known only once it ran); the column "reached" is the
# same model with the hits the runs did reach (hits.csv), which shows the
# model's accuracy apart from that bound.
#
# Shapes: experiments/quick.toml at 1,000 runs per cell (15,000 runs);
# 200,000 runs of 10 evaluations (10 cells x 2 problems); a fitting
# campaign from experiments/ch5_outlines.toml's horse and coin (16 fitting
# cases, three methods) at 20 evaluations per segment. Takes about two
# minutes on two cores; run it on an idle machine. Exits 1 when the model
# with the hits reached is off by more than 25 %, or the estimate is more
# than 25 % below the measured peak.
set -eu
ROOT=$(cd "$(dirname "$0")/.." && pwd)
BIN=${1:-$ROOT/target/release/metabezier}
TIME=/usr/bin/time
[ -x "$BIN" ] || { echo "measure-memory: $BIN is not built (cargo build --release)" >&2; exit 2; }
[ -x "$TIME" ] || { echo "measure-memory: needs GNU time at $TIME (apt-get install time)" >&2; exit 2; }
WORK=$(mktemp -d)
trap 'rm -rf "$WORK"' EXIT

# quick.toml with RUNS runs per cell.
quick() {
    sed -e "s/^runs = .*/runs = $1/" "$ROOT/experiments/quick.toml" > "$2"
}

# 10 cells × 2 problems at budget 10, RUNS runs per cell.
short() {
    sed -e "s/^runs = .*/runs = $1/" -e 's/^budget = .*/budget = 10/' \
        -e '/^\[\[problem\]\]$/,$d' "$ROOT/experiments/quick.toml" > "$2"
    cat >> "$2" <<SPEC
[[problem]]
function = ["sphere", "rastrigin"]
dim = 10

[[algorithm]]
name = "hs"
label = "HS"
hms = [5, 10]

[[algorithm]]
name = "ghs"
label = "GHS"
hms = [5, 10]

[[algorithm]]
name = "ga"
label = "GA"
pop = [10, 20]

[[algorithm]]
name = "pso"
label = "PSO"
swarm = [10, 20]

[[algorithm]]
name = "mhs"
label = "MHS"
hms = [5, 10]
SPEC
}

# Two outlines of ch5_outlines (eight fitting cases each) and three
# methods at 20 evaluations per segment, RUNS runs per cell.
fitting() {
    cat > "$2" <<SPEC
[experiment]
name = "memory_fitting"
seed = 2012
runs = $1
budget = 20
threshold = 0

[[fit]]
input = "$ROOT/data/outlines/horse.png"
function = ["quadratic", "cubic", "rational-quadratic", "rational-cubic"]
continuity = ["c1", "g1"]
closing = "smooth"
segments = 30

[[fit]]
input = "$ROOT/data/outlines/coin.png"
function = ["quadratic", "cubic", "rational-quadratic", "rational-cubic"]
continuity = ["c1", "g1"]
closing = "smooth"
segments = 8

[[algorithm]]
name = "hs"
label = "HS"

[[algorithm]]
name = "mhs"
label = "MHS"

[[algorithm]]
name = "pso"
label = "PSO"
SPEC
}

# The estimate in MiB that `metabezier check` prints.
estimate() {
    "$BIN" check "$1" | sed -n 's/^estimated memory of the results before they are written: \(.*\) MiB$/\1/p'
}

# The bytes the estimate counts for target hits the runs in DIR did not
# reach: 51 hits (832 bytes) per benchmark run, less 16 bytes per hit and
# per run with hits (records::record_heap) of hits.csv.
excess() {
    [ -f "$1/hits.csv" ] || { echo 0; return; }
    awk -F, -v runs="$(($(wc -l < "$1/runs.csv") - 1))" '
        NR > 1 { key = $1; for (i = 2; i <= NF - 2; i++) key = key "," $i; if (!(key in seen)) { seen[key]; n++ } rows++ }
        END { printf "%d", runs * 832 - 16 * (rows + n) }' "$1/hits.csv"
}

# The peak RSS in MiB of `run SPEC --threads T` into a fresh directory.
peak() {
    rm -rf "$WORK/out"
    "$TIME" -v "$BIN" run "$1" --out "$WORK/out" --threads "$2" --quiet \
        2> "$WORK/time.txt" > /dev/null || { cat "$WORK/time.txt" >&2; exit 1; }
    kib=$(sed -n 's/^\tMaximum resident set size (kbytes): //p' "$WORK/time.txt")
    awk -v k="$kib" 'BEGIN { printf "%.1f", k / 1024 }'
}

if [ "${SPECS_ONLY:-}" ]; then
    mkdir -p "$SPECS_ONLY"
    quick 1000 "$SPECS_ONLY/quick.toml"; short 10000 "$SPECS_ONLY/short.toml"; fitting 40 "$SPECS_ONLY/fitting.toml"
    exit 0
fi

status=0
printf '%-28s %7s %7s %9s %9s %9s %7s %7s\n' shape threads runs "est. MiB" "reached" "meas. MiB" "error" "reached"
for shape in "quick 1000 15000" "short 10000 200000" "fitting 40 1920"; do
    set -- $shape
    "$1" 1 "$WORK/base.toml"
    "$1" "$2" "$WORK/full.toml"
    est=$(awk -v a="$(estimate "$WORK/full.toml")" -v b="$(estimate "$WORK/base.toml")" 'BEGIN { printf "%.1f", a - b }')
    for threads in 1 2; do
        base=$(peak "$WORK/base.toml" "$threads")
        base_excess=$(excess "$WORK/out")
        full=$(peak "$WORK/full.toml" "$threads")
        full_excess=$(excess "$WORK/out")
        meas=$(awk -v a="$full" -v b="$base" 'BEGIN { printf "%.1f", a - b }')
        reached=$(awk -v e="$est" -v a="$full_excess" -v b="$base_excess" 'BEGIN { printf "%.1f", e - (a - b) / 1048576 }')
        err=$(awk -v e="$est" -v m="$meas" 'BEGIN { printf "%+.0f %%", 100 * (e - m) / m }')
        rerr=$(awk -v e="$reached" -v m="$meas" 'BEGIN { printf "%+.0f %%", 100 * (e - m) / m }')
        printf '%-28s %7s %7s %9s %9s %9s %7s %7s\n' "$1 ($2 runs/cell)" "$threads" "$3" "$est" "$reached" "$meas" "$err" "$rerr"
        awk -v e="$est" -v r="$reached" -v m="$meas" 'BEGIN { exit !(r < 0.75 * m || r > 1.25 * m || e < 0.75 * m) }' && status=1
    done
done
[ "$status" = 0 ] || echo "measure-memory: the estimate is off by more than 25 %" >&2
exit $status
