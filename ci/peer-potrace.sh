#!/usr/bin/env bash
# make peer-potrace: potrace (Debian's, installed when missing) against
# `metabezier fit` on the same shapes, each scored by `metabezier score` /
# `fit`'s own two-sided distance, with the CPU time of whole processes
# (user + system, a loop of runs, divided). For each input: potrace; our fit
# to potrace's two-sided (Hausdorff) distance (`--tolerance`); our fit at
# potrace's segment count (`--segments`). Not part of `make test` (timing).
set -euo pipefail
BIN=${1:-target/release/metabezier}
PBM=${2:-target/release/examples/shape_pbm}
GLYPH_PNG=${3:-target/release/examples/glyph_png}
INPUTS=${PEER_POTRACE_INPUTS:-"data/outlines/horse.png data/outlines/coin.png data/outlines/logo.png"}
# FONT:CHARACTER, each drawn 200 px high into a PNG both tools read.
GLYPHS=${PEER_POTRACE_GLYPHS:-"DejaVuSans.ttf:g DejaVuSans.ttf:S DejaVuSans.ttf:& Cantarell-Regular.otf:a Cantarell-Regular.otf:R"}
if ! command -v potrace > /dev/null; then
  echo "peer-potrace: installing Debian's potrace" >&2
  (apt-get install -y potrace > /dev/null 2>&1 || { apt-get update > /dev/null && apt-get install -y potrace > /dev/null; })
fi
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
mkdir "$out/glyphs"
for g in $GLYPHS; do
  font=${g%%:*}
  c=${g#*:}
  name="${font%%[-.]*}-$c"
  "$GLYPH_PNG" "data/outlines/$font" "$c" 200 "$out/glyphs/$name.png" 2> /dev/null
  INPUTS="$INPUTS $out/glyphs/$name.png"
done
# CPU seconds (user + system) of running "$@" $2 times, per run, in ms.
cpu_ms() {
  local n=$1; shift
  local t
  t=$( { TIMEFORMAT='%U %S'; time (for ((k = 0; k < n; k++)); do "$@" > /dev/null 2>&1; done); } 2>&1 )
  awk -v t="$t" -v n="$n" 'BEGIN { split(t, a, " "); printf "%.2f", 1000 * (a[1] + a[2]) / n }'
}
# "segments hausdorff rms" from a `fit` summary line.
fit_figures() {
  sed -n 's/.* \([0-9]*\) segments, Hausdorff distance = \([^ ]*\) .*RMS distance = \([^,]*\),.*/\1 \2 \3/p' | head -1
}
echo "potrace $(potrace --version | head -1 | cut -d' ' -f2 | sed "s/\.$//") against metabezier fit (CPU per whole process)"
echo
echo "| input | tool | segments | two-sided max px | RMS px | CPU ms | CPU / potrace |"
echo "|---|---|---:|---:|---:|---:|---:|"
for input in $INPUTS; do
  name=$(basename "$input" .png)
  "$PBM" "$input" "$out/$name.pbm" 2> /dev/null
  potrace -s -t 25 -o "$out/$name.svg" "$out/$name.pbm"
  score=$("$BIN" score "$input" "$out/$name.svg" --offset -0.5,-0.5)
  p_seg=$(echo "$score" | sed -n '1s/.*: \([0-9]*\) segments$/\1/p')
  p_max=$(echo "$score" | sed -n 's/.*Hausdorff distance \([0-9.e-]*\)$/\1/p')
  p_rms=$(echo "$score" | awk '$1 == "all" { print $4 }')
  p_cpu=$(cpu_ms 40 potrace -s -t 25 -o "$out/p.svg" "$out/$name.pbm")
  echo "| $name | potrace | $p_seg | $p_max | $p_rms | $p_cpu | 1 |"
  modes=("--tolerance $p_max")
  # potrace's segment count as ours, where there is one contour to give it to.
  if [ "$(echo "$score" | awk '$1 ~ /^[0-9]+$/' | wc -l)" = 1 ]; then modes+=("--segments $p_seg"); fi
  for mode in "${modes[@]}"; do
    # shellcheck disable=SC2086
    read -r seg max rms < <("$BIN" fit "$input" $mode --out "$out/f" | fit_figures)
    # shellcheck disable=SC2086
    cpu=$(cpu_ms 5 "$BIN" fit "$input" $mode --out "$out/f")
    ratio=$(awk -v a="$cpu" -v b="$p_cpu" 'BEGIN { printf "%.1f", a / b }')
    echo "| $name | fit $mode | $seg | $max | $rms | $cpu | $ratio |"
  done
done
