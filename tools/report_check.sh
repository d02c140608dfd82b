#!/bin/sh
# report_check.sh BUILD DB - the demo's reports rendered by headless chromium, to look at
# (make report-check):
#   BUILD/report/screenshot.png            the report of the newest run, the whole page
#   BUILD/report/shot-NAME.png             its hazard maps and the passing-height figure
#                                          of each structure, one each
#   BUILD/report-compare/screenshot.png    runs 3 and 4 (noto-3.2, no structures, and
#                                          noto-3.3, the layout) side by side
set -e
build=$1
db=$2
flags="--headless --no-sandbox --disable-gpu --disable-quic --no-first-run
       --disable-background-networking --disable-component-update --disable-sync
       --hide-scrollbars"

# shot SIZE PNG FILE: FILE rendered in a window of SIZE (w,h) into PNG
shot() {
    profile=$(mktemp -d)
    status=0
    timeout 300 chromium $flags --window-size="$1" --user-data-dir="$profile" \
        --screenshot="$2" "file://$(realpath "$3")" 2>/dev/null || status=$?
    rm -rf "$profile"
    [ "$status" = 0 ] && [ -s "$2" ] || { echo "report_check: no screenshot of $3" >&2; exit 1; }
    echo "$2"
}

rm -rf "$build/report" "$build/report-compare"
"$build/rockfall" report "$db" --out "$build/report"
"$build/rockfall" report "$db" --runs 3,4 --out "$build/report-compare"
shot 1200,16000 "$build/report/screenshot.png" "$build/report/index.html"
for f in "$build"/report/hazard-*.svg "$build"/report/measure-*-height.svg; do
    name=$(basename "$f" .svg)
    size=$(sed -n '1s/.* width="\([0-9]*\)" height="\([0-9]*\)".*/\1,\2/p' "$f")
    shot "$size" "$build/report/shot-$name.png" "$f"
done
shot 1200,4000 "$build/report-compare/screenshot.png" "$build/report-compare/index.html"
