#!/bin/sh
# layers.sh - the layer rule of src/ (docs/architecture.md), checked.
#
#   tools/layers.sh [ROOT [BUILD]]
#
# ROOT (default .) holds src/ and include/rockfall/.  Every file in src/LAYER/ may
# include only headers of its own layer or of a layer below it; every public header
# include/rockfall/NAME.h belongs to the layer the table below names, and includes only
# its layer and those below.  Within the engine no two files depend on each other, even
# through others: the includes of engine headers (a header NAME.h stands for NAME.c)
# form no cycle.  No source file is over 1000 lines, no function over 120.  With BUILD (a build folder holding src/LAYER/NAME.o), the same two
# rules are checked on what the objects call: no object calls a layer above its own,
# and the engine's objects call each other without a cycle.
# Prints each violation with its file and line and exits 1; exits 0 when there is none.
set -u
ROOT=${1:-.}
BUILD=${2:-}
LAYERS="base input scene engine results run check report cli"

# The layer of each public header (include/rockfall/NAME.h).
PUBLIC="error:base vec3:base version:base units:base
project:input terrain:input body:input
records:scene empirical:scene
sim:engine
montecarlo:run"

rank() {
    i=0
    for l in $LAYERS; do
        [ "$l" = "$1" ] && { echo $i; return; }
        i=$((i + 1))
    done
    echo -1
}

public_layer() {
    for p in $PUBLIC; do
        [ "${p%%:*}" = "$1" ] && { echo "${p#*:}"; return; }
    done
    echo ""
}

bad=0
tmp=$(mktemp -d) || exit 2
trap 'rm -rf "$tmp"' EXIT

# ---- includes ------------------------------------------------------------------------
# One line per quoted include: FILE LINE LAYER-OF-FILE TARGET
for f in "$ROOT"/src/*/*.[ch] "$ROOT"/include/rockfall/*.h; do
    [ -f "$f" ] || continue
    rel=${f#"$ROOT"/}
    case $rel in
    src/*)
        layer=${rel#src/}
        layer=${layer%%/*}
        ;;
    include/rockfall/*)
        name=${rel##*/}
        layer=$(public_layer "${name%.h}")
        if [ -z "$layer" ]; then
            echo "$rel:1: public header without a layer (add it to tools/layers.sh and docs/architecture.md)" >>"$tmp/early"
            continue
        fi
        ;;
    esac
    if [ "$(rank "$layer")" -lt 0 ]; then
        echo "$rel:1: folder '$layer' is not a layer ($LAYERS)" >>"$tmp/early"
        continue
    fi
    awk -v f="$rel" -v l="$layer" '/^[ \t]*#[ \t]*include[ \t]*"/ {
        t = $0; sub(/^[^"]*"/, "", t); sub(/".*$/, "", t); print f, FNR, l, t }' "$f"
done >"$tmp/includes"
if [ -s "$tmp/early" ]; then
    cat "$tmp/early"
    bad=1
fi

while read -r file line layer target; do
    case $target in
    rockfall/*)
        name=${target#rockfall/}
        tl=$(public_layer "${name%.h}")
        ;;
    */*)
        tl=${target%%/*}
        ;;
    *)
        # a header beside the file, in its own folder
        tl=$layer
        ;;
    esac
    if [ -z "$tl" ] || [ "$(rank "$tl")" -lt 0 ]; then
        echo "$file:$line: includes \"$target\", which belongs to no layer"
        bad=1
    elif [ "$(rank "$tl")" -gt "$(rank "$layer")" ]; then
        echo "$file:$line: layer '$layer' includes \"$target\" of layer '$tl' above it"
        bad=1
    fi
done <"$tmp/includes"

# Engine include cycles: an edge from module A to module B when A.c or A.h includes
# engine/B.h (or B.h beside it).
awk '$3 == "engine" && $1 ~ /^src\/engine\// {
        a = $1; sub(/^.*\//, "", a); sub(/\.[ch]$/, "", a)
        b = $4; sub(/^engine\//, "", b)
        if (b ~ /\//) next
        sub(/\.h$/, "", b)
        if (a != b) print a, b
     }' "$tmp/includes" | sort -u >"$tmp/engine_includes"
if ! tsort "$tmp/engine_includes" >/dev/null 2>"$tmp/tsort"; then
    echo "src/engine: the engine's files include each other in a cycle:"
    sed 's/^/  /' "$tmp/tsort"
    bad=1
fi

# ---- sizes ---------------------------------------------------------------------------
# No source file over 1000 lines, no function body ({ to } at the first column) over 120.
for f in "$ROOT"/src/*/*.[ch]; do
    n=$(wc -l <"$f")
    if [ "$n" -gt 1000 ]; then
        echo "${f#"$ROOT"/}:1: $n lines (at most 1000)"
        bad=1
    fi
done
for f in "$ROOT"/src/*/*.c; do
    awk -v f="${f#"$ROOT"/}" '
        /^[A-Za-z_].*\(/ { sig = $0; sigline = FNR }
        /^\{/ { start = FNR; name = sig; sub(/\(.*/, "", name); sub(/.*[ *]/, "", name) }
        /^\}/ && start {
            len = FNR - start + 1
            if (len > 120) print f ":" sigline ": function " name " is " len " lines (at most 120)"
            start = 0
        }' "$f"
done >"$tmp/long"
if [ -s "$tmp/long" ]; then
    cat "$tmp/long"
    bad=1
fi

# ---- calls, from the objects ---------------------------------------------------------
if [ -n "$BUILD" ]; then
    for o in "$BUILD"/src/*/*.o; do
        [ -f "$o" ] || continue
        rel=${o#"$BUILD"/src/}
        nm --defined-only -g "$o" | awk -v o="$rel" 'NF == 3 && $2 ~ /[TDBRC]/ {print $3, o}'
    done | sort >"$tmp/defs"
    for o in "$BUILD"/src/*/*.o; do
        [ -f "$o" ] || continue
        rel=${o#"$BUILD"/src/}
        nm -u "$o" | awk -v o="$rel" '{print $NF, o}'
    done | sort >"$tmp/uses"
    join "$tmp/uses" "$tmp/defs" | awk '$2 != $3 {print $2, $3, $1}' | sort -u >"$tmp/calls"
    while read -r from to sym; do
        fl=${from%%/*}
        tl=${to%%/*}
        if [ "$(rank "$tl")" -gt "$(rank "$fl")" ]; then
            echo "src/${from%.o}.c: calls $sym of src/${to%.o}.c, layer '$tl' above '$fl'"
            bad=1
        fi
    done <"$tmp/calls"
    awk '$1 ~ /^engine\// && $2 ~ /^engine\// {print $1, $2}' "$tmp/calls" | sort -u >"$tmp/engine_calls"
    if ! tsort "$tmp/engine_calls" >/dev/null 2>"$tmp/tsort"; then
        echo "src/engine: the engine's objects call each other in a cycle:"
        sed 's/^/  /' "$tmp/tsort"
        bad=1
    fi
fi

exit $bad
