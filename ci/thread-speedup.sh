#!/bin/sh
# Five alternating 1-thread / 2-thread runs of experiments/thread_speedup.toml;
# prints each wall time, checks that both thread counts give the same
# runs.csv, and prints the median of the five speed-ups. Run it on an
# otherwise idle machine (`make speedup`).
set -eu
BIN=${1:-target/release/metabezier}
SPEC=experiments/thread_speedup.toml
TMP=$(mktemp -d)
trap 'rm -rf "$TMP"' EXIT
for i in 1 2 3 4 5; do
  for t in 1 2; do
    rm -rf "$TMP/out$t"
    s=$(date +%s.%N)
    "$BIN" run "$SPEC" --out "$TMP/out$t" --threads "$t" --quiet > /dev/null
    e=$(date +%s.%N)
    awk -v s="$s" -v e="$e" 'BEGIN { printf "%.3f\n", e - s }' > "$TMP/t$t"
  done
  cmp -s "$TMP/out1/runs.csv" "$TMP/out2/runs.csv" || { echo "runs.csv differs between 1 and 2 threads" >&2; exit 1; }
  one=$(cat "$TMP/t1"); two=$(cat "$TMP/t2")
  r=$(awk -v a="$one" -v b="$two" 'BEGIN { printf "%.3f", a / b }')
  echo "$i: 1 thread $one s, 2 threads $two s, speed-up $r"
  echo "$r" >> "$TMP/ratios"
done
echo "median speed-up: $(sort -n "$TMP/ratios" | sed -n 3p)"
