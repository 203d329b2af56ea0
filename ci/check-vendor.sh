#!/bin/sh
# Checks the sha256 of every vendored third-party file against the sums its
# PROVENANCE.md states (kept beside it in SHA256SUMS), so that a vendored
# file changed by hand or by a bad checkout fails CI with its name.
set -eu
cd "$(dirname "$0")/.."
status=0
for sums in vendor/*/SHA256SUMS; do
    dir=$(dirname "$sums")
    if ! (cd "$dir" && sha256sum --check --quiet --strict SHA256SUMS); then
        echo "check-vendor: $sums: a vendored file does not match its recorded sha256 (see $dir/PROVENANCE.md)" >&2
        status=1
    fi
done
[ "$status" = 0 ] && echo "check-vendor: every vendored file matches its sha256"
exit "$status"
