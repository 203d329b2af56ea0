#!/usr/bin/env bash
# metabezier-core stands on no I/O, plotting, image, DICOM, CLI or C crate:
# its normal dependency tree (cargo tree -e normal) names none of them.
set -euo pipefail
cd "$(dirname "$0")/.."
tree=$(cargo tree --locked -p metabezier-core -e normal --prefix none)
bad=$(printf '%s\n' "$tree" | grep -E '^(dicom|plotters|image|png|ab_glyph|clap|indicatif|tar|flate2|cc|toml|rayon|metabezier-(files|bbob|fit|spec|plot|campaign|report|implant)) ' || true)
if [ -n "$bad" ]; then
    echo "check-core-deps: metabezier-core depends on:" >&2
    printf '%s\n' "$bad" >&2
    exit 1
fi
echo "check-core-deps: metabezier-core's dependencies: $(printf '%s\n' "$tree" | awk '{print $1}' | sort -u | tr '\n' ' ')"
