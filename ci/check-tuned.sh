#!/bin/sh
# Checks that the "-tuned" cells of campaigns carry the settings picked by
# the equal-effort tuning (experiments/ch4_tuning.toml).
#
#   ci/check-tuned.sh TUNING_RESULTS CAMPAIGN_RESULTS...
#
# TUNING_RESULTS is the reported results directory of ch4_tuning: its
# tables/tuning_picks_<slug>.csv name the pick of every grid (columns
# algorithm and params). Every CAMPAIGN_RESULTS directory's runs.csv must
# hold at least one "<Label>-tuned" cell, and the params column of each
# must equal the picked params of <Label>. Exits 1 with a message naming
# the campaign, the cell, the spec's params and the pick otherwise.
# POSIX sh and awk only.
set -eu

if [ "$#" -lt 2 ]; then
    echo "usage: $0 TUNING_RESULTS CAMPAIGN_RESULTS..." >&2
    exit 2
fi
tuning=$1
shift

picks=$(ls "$tuning"/tables/tuning_picks_*.csv 2>/dev/null || true)
if [ -z "$picks" ]; then
    echo "check-tuned: no tuning picks in $tuning/tables (tuning_picks_*.csv); run the ch4_tuning campaign and its report first:" >&2
    echo "  metabezier run experiments/ch4_tuning.toml --resume && metabezier report $tuning" >&2
    exit 1
fi

for campaign in "$@"; do
    if [ ! -f "$campaign/runs.csv" ]; then
        echo "check-tuned: $campaign has no runs.csv; run its campaign first" >&2
        exit 1
    fi
done

# One awk program reads every picks file, then every runs.csv. A CSV
# record is split with RFC 4180 quoting (no line breaks inside fields,
# which these files do not have).
# shellcheck disable=SC2086
awk -v tuning="$tuning" '
function split_csv(line, out,    n, i, c, field, quoted) {
    n = 0; field = ""; quoted = 0
    for (i = 1; i <= length(line); i++) {
        c = substr(line, i, 1)
        if (quoted) {
            if (c == "\"") {
                if (substr(line, i + 1, 1) == "\"") { field = field "\""; i++ }
                else quoted = 0
            } else field = field c
        } else if (c == "\"") quoted = 1
        else if (c == ",") { out[++n] = field; field = "" }
        else field = field c
    }
    out[++n] = field
    return n
}
function column(name, header, n,    i) {
    for (i = 1; i <= n; i++) if (header[i] == name) return i
    return 0
}
FNR == 1 {
    sub(/\r$/, "")
    nh = split_csv($0, header)
    ca = column("algorithm", header, nh); cp = column("params", header, nh)
    if (ca == 0 || cp == 0) {
        printf "check-tuned: %s has no algorithm and params columns\n", FILENAME > "/dev/stderr"
        bad = 1; exit 1
    }
    is_picks = (FILENAME ~ /\/tables\/tuning_picks_[^\/]*\.csv$/)
    if (!is_picks) {
        campaign = FILENAME; sub(/\/runs\.csv$/, "", campaign)
        campaigns[++ncampaigns] = campaign
    }
    next
}
{
    if (!is_picks && index($0, "-tuned") == 0) next
    sub(/\r$/, "")
    split_csv($0, f)
    if (is_picks) {
        if (f[ca] in pick && pick[f[ca]] != f[cp]) {
            printf "check-tuned: %s names two picks for %s\n", tuning, f[ca] > "/dev/stderr"
            bad = 1; exit 1
        }
        pick[f[ca]] = f[cp]
        next
    }
    label = f[ca]
    if (label !~ /-tuned$/) next
    key = campaign SUBSEP label SUBSEP f[cp]
    if (key in seen) next
    seen[key] = 1
    tuned[campaign]++
    base = substr(label, 1, length(label) - length("-tuned"))
    if (!(base in pick)) {
        printf "check-tuned: campaign %s: cell %s (params %s) has no pick of %s in %s/tables/tuning_picks_*.csv\n", campaign, label, f[cp], base, tuning > "/dev/stderr"
        bad = 1
    } else if (pick[base] != f[cp]) {
        printf "check-tuned: campaign %s: cell %s runs params\n    %s\n  but the tuning picked for %s\n    %s\n  (update the spec to the pick, or rerun the campaign)\n", campaign, label, f[cp], base, pick[base] > "/dev/stderr"
        bad = 1
    } else checked[campaign] = checked[campaign] " " label
}
END {
    if (bad) exit 1
    for (i = 1; i <= ncampaigns; i++) {
        c = campaigns[i]
        if (!(c in tuned)) {
            printf "check-tuned: campaign %s has no -tuned cell to check\n", c > "/dev/stderr"
            exit 1
        }
        printf "check-tuned: %s:%s carry the picks of %s\n", c, checked[c], tuning
    }
}
' $picks $(for c in "$@"; do printf '%s/runs.csv\n' "$c"; done)
