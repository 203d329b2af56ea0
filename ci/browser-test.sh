#!/usr/bin/env bash
# report.html in a real browser: headless Chromium (Debian's package,
# installed when missing) opens the pages of a quick campaign's report, of
# a small implant run and of a small fitting campaign, and for each page
# checks that
#
#   (a) the page's script ran: the DOM after load has data-ready="1" on
#       <body>, and a crowded section shows one figure of its menu (the
#       others hidden by the mb-hidden class);
#   (b) the console stayed silent: Chromium logs every console message
#       (uncaught errors, blocked loads, console.error) to stderr under
#       --enable-logging=stderr as ":CONSOLE" lines, and there is none;
#   (c) clicking a header sorts a numeric column up then down, and choosing
#       a figure in the menu shows that figure alone (a script added to a
#       copy of the page clicks and records what it saw on <body>);
#   (d) a 1280x2000 screenshot is not blank: ci/png-colours.py decodes it
#       with the Python standard library and counts its colours.
#
# Before that the script checks its own detectors: a copy of the page with
# a deliberate `throw` must show a console error and no ready flag, and an
# empty page must make a blank screenshot. Any failure exits non-zero with
# the reason.
#
#   ci/browser-test.sh BINARY        (make test-browser)
set -euo pipefail

fail() {
    echo "browser-test: FAILED: $*" >&2
    exit 1
}

[ $# -eq 1 ] || { echo "usage: ci/browser-test.sh BINARY" >&2; exit 2; }
[ -x "$1" ] || fail "$1 is not an executable (run make build first)"
bin=$(cd "$(dirname "$1")" && pwd)/$(basename "$1")
root=$(cd "$(dirname "$0")/.." && pwd)

find_browser() { command -v chromium || command -v chromium-browser || true; }
browser=$(find_browser)
if [ -z "$browser" ]; then
    echo "browser-test: no chromium; installing Debian's package"
    sudo=""
    [ "$(id -u)" -eq 0 ] || sudo=sudo
    $sudo apt-get update -qq
    $sudo env DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends chromium
    browser=$(find_browser)
    [ -n "$browser" ] || fail "chromium is still not installed after apt-get install chromium"
fi
echo "browser-test: $("$browser" --version 2>/dev/null | head -n 1)"

work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

# Chromium, headless and offline; one fresh profile per launch.
launches=0
chromium() {
    launches=$((launches + 1))
    timeout 120 "$browser" --headless --no-sandbox --disable-gpu --disable-quic \
        --no-first-run --disable-background-networking --disable-component-update \
        --disable-sync --user-data-dir="$work/profile-$launches" "$@"
}

# The DOM of a page after its scripts ran (to $2), its console lines (to $3).
dump_dom() {
    if ! chromium --enable-logging=stderr --v=0 --dump-dom "file://$1" >"$2" 2>"$3.log"; then
        tail -n 20 "$3.log" >&2
        fail "chromium could not load $1"
    fi
    grep -a ':CONSOLE' "$3.log" >"$3" || true
}

ready() { grep -aqE '<body[^>]*data-ready="1"' "$1"; }

# The number of matches of the pattern $1 in the file $2.
count() { { grep -ao "$1" "$2" || true; } | wc -l; }

# The pages: a quick campaign (seven figures in its Plots section), a small
# implant run (text and tables) and a small fitting campaign (large inline
# SVGs of fitted glyphs).
echo "browser-test: making the pages"
"$bin" run "$root/experiments/quick.toml" --out "$work/quick" --quiet >/dev/null
"$bin" report "$work/quick" >/dev/null
cat >"$work/implant.toml" <<EOF
[implant]
volume = "$root/data/ct0051/ct0051_z040-100.inv3"
first_z = 40
midline_slices = [86, 92]
method = "mhs"
budget = 2000
seed = 7

[defect]
slices = [70, 72]
overlays = [72]
EOF
"$bin" implant "$work/implant.toml" --out "$work/implant" >/dev/null
font="$root/data/outlines/DejaVuSans.ttf"
cat >"$work/fit.toml" <<EOF
[experiment]
name = "fit"
seed = 5
runs = 1
budget = 2000
threshold = 0

[[fit]]
input = ["font:$font:a", "font:$font:S"]
function = ["cubic", "rational-cubic"]
continuity = "g1"
segments = 12

[[algorithm]]
name = "lm"
label = "LM"
EOF
"$bin" run "$work/fit.toml" --out "$work/fit" --quiet >/dev/null
"$bin" report "$work/fit" >/dev/null
pages=("$work/quick/report.html" "$work/implant/report.html" "$work/fit/report.html")
for page in "${pages[@]}"; do
    [ -s "$page" ] || fail "$page was not written"
done
# The same pages' reports read on a screen (what make check-reports checks
# on the full results): summary first, under 300 lines, pictures <= 3,000 px.
python3 "$root/ci/check-reports.py" "$work/quick" "$work/implant" "$work/fit" ||
    fail "a report does not read on a screen (ci/check-reports.py above)"

# The detectors first: a thrown error must be seen, a blank page must fail.
page=${pages[0]}
broken="$(dirname "$page")/broken.html"
sed 's|document.body.dataset.ready = "1";|throw new Error("deliberate browser-test error");|' \
    "$page" >"$broken"
grep -q 'deliberate browser-test error' "$broken" || fail "could not inject the deliberate error"
dump_dom "$broken" "$work/broken.dom" "$work/broken.console"
grep -q 'Uncaught Error: deliberate browser-test error' "$work/broken.console" \
    || fail "the console check missed a deliberate uncaught error (Chromium's logging changed?)"
! ready "$work/broken.dom" || fail "the ready check passed a page whose script threw"
rm -f "$broken"
printf '<!DOCTYPE html><html><body></body></html>\n' >"$work/blank.html"
chromium --screenshot="$work/blank.png" --window-size=1280,2000 "file://$work/blank.html" \
    >/dev/null 2>&1 || fail "chromium could not screenshot a blank page"
if python3 "$root/ci/png-colours.py" "$work/blank.png" >/dev/null 2>&1; then
    fail "the screenshot check passed a blank page"
fi
echo "browser-test: detectors ok (a deliberate error is caught, a blank page fails)"

# What a copy of the page does when clicked: sort the first numeric column
# with three or more values up and down, choose the second figure of the
# first menu; the outcome goes to <body data-check="...">.
read -r -d '' CLICKS <<'EOF' || true
<script>
(function () {
  var out = [];
  try {
    var done = false;
    document.querySelectorAll("table.mb-sortable").forEach(function (table) {
      var body = table.tBodies[0];
      if (done || !body || body.rows.length < 3) return;
      Array.prototype.forEach.call(table.tHead.rows[0].cells, function (th, c) {
        if (done) return;
        var values = function () {
          return Array.prototype.map.call(body.rows, function (r) {
            return r.cells[c] ? r.cells[c].textContent.trim() : "";
          });
        };
        var v = values();
        if (!v.every(function (x) { return /^-?\d+(\.\d+)?(e[+-]?\d+)?$/.test(x); })) return;
        if (new Set(v).size < 3) return;
        var nums = function () { return values().map(parseFloat); };
        th.click();
        var a = nums();
        var up = a.every(function (x, i) { return i === 0 || a[i - 1] <= x; });
        th.click();
        var d = nums();
        var down = d.every(function (x, i) { return i === 0 || d[i - 1] >= x; });
        out.push(up && down && th.getAttribute("aria-sort") === "descending" ? "sort-ok" : "sort-FAILED");
        done = true;
      });
    });
    if (!done) out.push("sort-none");
    var select = document.querySelector("select.mb-select");
    if (select) {
      select.value = "1";
      select.dispatchEvent(new Event("change"));
      var units = document.querySelectorAll('.mb-unit[data-group="' + select.getAttribute("data-group") + '"]');
      var shown = Array.prototype.filter.call(units, function (u) {
        return !u.classList.contains("mb-hidden") && u.offsetHeight > 0;
      });
      out.push(shown.length === 1 && shown[0].getAttribute("data-index") === "1" ? "select-ok" : "select-FAILED");
    } else {
      out.push("select-none");
    }
  } catch (e) {
    out.push("clicks-threw:" + e);
  }
  document.body.setAttribute("data-check", out.join(" "));
})();
</script>
EOF

n=0
for page in "${pages[@]}"; do
    n=$((n + 1))
    name="page$n"
    echo "browser-test: $page"
    # (a), (b): the page as it loads.
    dump_dom "$page" "$work/$name.dom" "$work/$name.console"
    if [ -s "$work/$name.console" ]; then
        cat "$work/$name.console" >&2
        fail "$page: console messages (above)"
    fi
    ready "$work/$name.dom" || fail "$page: no data-ready=\"1\" on <body>: its script did not finish"
    units=$(count '<div class="mb-unit[^"]*"' "$work/$name.dom")
    hidden=$(count '<div class="mb-unit mb-hidden"' "$work/$name.dom")
    menus=$(count '<select class="mb-select"' "$work/$name.dom")
    if [ "$units" -gt 0 ] && [ "$hidden" -ne $((units - menus)) ]; then
        fail "$page: $hidden of $units figures hidden after load, expected $((units - menus))"
    fi
    # (c): clicks on a copy.
    copy="$(dirname "$page")/clicks.html"
    CLICKS=$CLICKS awk '/^<\/body>$/ { print ENVIRON["CLICKS"] } { print }' "$page" >"$copy"
    dump_dom "$copy" "$work/$name.clicks.dom" "$work/$name.clicks.console"
    rm -f "$copy"
    if [ -s "$work/$name.clicks.console" ]; then
        cat "$work/$name.clicks.console" >&2
        fail "$page: console messages while clicking (above)"
    fi
    check=$(grep -aoE '<body[^>]*data-check="[^"]*"' "$work/$name.clicks.dom" | sed 's/.*data-check="//; s/"$//')
    case " $check " in
        *FAILED* | *threw* | "  ") fail "$page: clicks: '${check:-no result}'" ;;
    esac
    case " $check " in *" sort-ok "*) ;; *) fail "$page: no numeric column was sorted ('$check')" ;; esac
    if [ "$menus" -gt 0 ]; then
        case " $check " in *" select-ok "*) ;; *) fail "$page: the figure menu ('$check')" ;; esac
    fi
    # (d): the screenshot (taken again once if blank, in case Chromium shot
    # before painting; a page that renders blank is blank both times).
    shot() {
        chromium --screenshot="$work/$name.png" --window-size=1280,2000 "file://$page" \
            >/dev/null 2>&1 || fail "$page: chromium could not take the screenshot"
        python3 "$root/ci/png-colours.py" "$work/$name.png"
    }
    if ! shot; then
        echo "browser-test: blank screenshot of $page; taking it again"
        shot || fail "$page: the screenshot is blank"
    fi
    echo "browser-test: ok: ready, no console message, $units figure(s) in menus ($hidden hidden), clicks: $check"
done
echo "browser-test: ${#pages[@]} passed, 0 failed"
