#!/bin/sh
# rockgis_bench.sh - rockfall beside RockGIS on the same slope and inputs: trajectories
# per second on one core and simulated seconds per trajectory (docs/terrain.md, "Against
# RockGIS").
#
#   RF_ROCKGIS=/path/to/RockGIS_Linux tools/rockgis_bench.sh DEM.asc X Y [COUNT]
#
# RF_ROCKGIS is the RockGIS executable built outside this repository (or the folder
# holding RockGIS_Linux).  DEM.asc is an ESRI ASCII grid with the six-line header RockGIS
# reads (ncols, nrows, xllcenter, yllcenter, cellsize, NODATA_value); (X, Y) the release
# point; COUNT trajectories each (default 200).  The inputs, with their defaults (the
# rolling slope of the benchmark: a 4 500 kg rock, restitution 0.15, friction 0.30):
#   RF_MASS=4500 RF_DENSITY=2650 RF_RESTITUTION=0.15 RF_RESTITUTION_SD=0.05
#   RF_FRICTION=0.30 RF_FRICTION_SD=0.05 RF_HEIGHT=0 (lowest point above the ground, m)
#   RF_STOP_SPEED=0.1 RF_APRON=0 RF_APRON_DEG=14 (rows of a counter-slope rising at
#   RF_APRON_DEG added south of the DEM, so that rocks stop on it: RockGIS ends the whole
#   program when a block leaves its DEM) RF_ROCKGIS_SLOPEVAR=0.7
#   RF_ROCKGIS_ASPECTVAR=0.25 (RockGIS's random tilt of the impact normal, rad, its study
#   case's: without it its blocks crawl down in many tiny rebounds or stop at the first) RF_ROCKGIS_DRAG=0 (RockGIS's
#   deceleration near the ground below 5 m/s, m/s^2, its study case's 0)
#   RF_ROCKFALL=build/rockfall RF_TIMEOUT=600 (s per program run).
# RockGIS has no friction coefficient: its tangential loss at an impact is its own
# hyperbolic law (Kta 200, KtRough 0.5, its study case's), and it has no rolling phase.
# RockGIS starts its blocks at 0.01 m/s along x, as its own study case does: a block
# falling exactly vertically gets no impact frame there (its velocity becomes NaN).
# Each program runs COUNT trajectories and one trajectory; the time per trajectory is
# the difference over COUNT - 1, so loading the DEM counts in neither.  Events per
# trajectory: rockfall's flights, surface segments, impacts and edge transitions (its
# run summary); RockGIS's steps (simulated seconds over dt).  Microseconds per event:
# the time per trajectory over them.
set -eu

usage() {
    echo "usage: RF_ROCKGIS=/path/to/RockGIS_Linux $0 DEM.asc X Y [COUNT]" >&2
    exit 2
}
[ $# -ge 3 ] || usage
[ -n "${RF_ROCKGIS:-}" ] || usage
DEM=$1 X=$2 Y=$3 COUNT=${4:-200}
exe=$RF_ROCKGIS
[ -d "$exe" ] && exe=$exe/RockGIS_Linux
[ -x "$exe" ] || { echo "$0: no RockGIS executable at '$exe'" >&2; exit 2; }
[ -r "$DEM" ] || { echo "$0: cannot read '$DEM'" >&2; exit 2; }
case $COUNT in '' | *[!0-9]* | 0 | 1) echo "$0: COUNT must be a whole number >= 2" >&2; exit 2 ;; esac
command -v sqlite3 > /dev/null ||
    { echo "$0: needs the sqlite3 command (Debian: apt-get install sqlite3)" >&2; exit 2; }
ROCKFALL=${RF_ROCKFALL:-build/rockfall}
[ -x "$ROCKFALL" ] || { echo "$0: no rockfall executable at '$ROCKFALL'" >&2; exit 2; }
MASS=${RF_MASS:-4500} DENSITY=${RF_DENSITY:-2650}
REST=${RF_RESTITUTION:-0.15} REST_SD=${RF_RESTITUTION_SD:-0.05}
FRIC=${RF_FRICTION:-0.30} FRIC_SD=${RF_FRICTION_SD:-0.05}
HEIGHT=${RF_HEIGHT:-0} STOP=${RF_STOP_SPEED:-0.1} APRON=${RF_APRON:-0}
APRON_DEG=${RF_APRON_DEG:-14} DRAG=${RF_ROCKGIS_DRAG:-0}
SLOPEVAR=${RF_ROCKGIS_SLOPEVAR:-0.7} ASPECTVAR=${RF_ROCKGIS_ASPECTVAR:-0.25}
TIMEOUT=${RF_TIMEOUT:-600}

work=$(mktemp -d "${TMPDIR:-/tmp}/rockgis-bench.XXXXXX")
if [ -n "${RF_KEEP:-}" ]; then
    echo "work files kept in $work" >&2
else
    trap 'rm -rf "$work"' EXIT INT TERM
fi

# The DEM both programs read: the given one, with APRON rows of a counter-slope rising
# southwards at RF_APRON_DEG degrees from the southern row (its lowest node) when asked; and
# RockGIS's barrier raster of the same shape, all 0 (no barriers).
awk -v apron="$APRON" -v deg="$APRON_DEG" -v dem="$work/dem.asc" -v obj="$work/objects.asc" '
    function hdr(k) { return tolower(k) }
    NR <= 6 { key[NR] = hdr($1); val[NR] = $2; next }
    { rows[++n] = $0 }
    END {
        for (i = 1; i <= 6; i++) h[key[i]] = val[i]
        if (!("ncols" in h) || !("nrows" in h) || !("xllcenter" in h) || !("yllcenter" in h) ||
            !("cellsize" in h)) { print "the DEM needs the header ncols, nrows, xllcenter, yllcenter, cellsize, NODATA_value" > "/dev/stderr"; exit 2 }
        split(rows[n], last)
        low = last[1]; for (i = 2; i <= h["ncols"]; i++) if (last[i] < low) low = last[i]
        rise = h["cellsize"] * sin(deg * atan2(0, -1) / 180) / cos(deg * atan2(0, -1) / 180)
        printf "ncols %s\nnrows %d\nxllcenter %s\nyllcenter %.10g\ncellsize %s\nNODATA_value %s\n",
            h["ncols"], h["nrows"] + apron, h["xllcenter"], h["yllcenter"] - apron * h["cellsize"],
            h["cellsize"], ("nodata_value" in h) ? h["nodata_value"] : -9999 > dem
        printf "ncols %s\nnrows %d\nxllcenter %s\nyllcenter %.10g\ncellsize %s\nNODATA_value -9999\n",
            h["ncols"], h["nrows"] + apron, h["xllcenter"], h["yllcenter"] - apron * h["cellsize"],
            h["cellsize"] > obj
        for (r = 1; r <= n; r++) print rows[r] > dem
        for (a = 1; a <= apron; a++) {
            line = ""
            for (i = 1; i <= h["ncols"]; i++) line = line (i > 1 ? " " : "") sprintf("%.3f", low + a * rise)
            print line > dem
        }
        zero = "0"; for (i = 2; i <= h["ncols"]; i++) zero = zero " 0"
        for (r = 1; r <= h["nrows"] + apron; r++) print zero > obj
    }' "$DEM"

now() { date +%s.%N; }
volume=$(awk -v m="$MASS" -v d="$DENSITY" 'BEGIN { printf "%.10g", m / d }')
radius=$(awk -v v="$volume" 'BEGIN { printf "%.10g", (3 * v / (4 * atan2(0, -1))) ^ (1 / 3) }')

# ---- RockGIS: its parameter and source files ---------------------------------------
rockgis_run() { # dt count -> prints "seconds simulated_seconds_mean stopped"
    dt=$1 n=$2 d=$work/rg-$1-$2
    mkdir -p "$d"
    cat > "$d/parameters.txt" <<EOF
DEM_path = $work/dem.asc
OBJECTS_path = $work/objects.asc
Sources_path = $d/sources.txt
Trajectories_path = $d/trajectories.csv
Stoppages_path = $d/stoppages.csv
Passages_path = $d/passages.txt
Impacts_path = $d/impacts.csv
TimeStep = $dt
StopVelocity = $STOP
Kna = $REST
Knb = 0.0
Kta = 200.0
KtRough = 0.5
RockDensity = $DENSITY
DragLayerHeigh = 1.0
DragSpeedLimit = 5.0
DragCoeficient = $DRAG
r_variant = 0.0
na1 = 0.0031
na2 = 0.7562
b1 = -1.6125
b2 = 2.4875
q1 = -0.5125
q2 = 1.0
MinAreaRatio = 9999
VminFrag = 0.0001
Cone = 50.0
LimitAngle = 5.0
Ep1 = 3000
Hp1 = 5
Ep2 = 3000
Hp2 = 5
Ep3 = 3000
Hp3 = 5
InitialSeed = 12345
AspectVar = $ASPECTVAR
SlopeVar = $SLOPEVAR
PrintMode = 0
StoreTrajectories = 0
EOF
    cat > "$d/sources.txt" <<EOF
##
ID = 1
Rx = $X
Ry = $Y
Hz = $(awk -v h="$HEIGHT" -v r="$radius" 'BEGIN { printf "%.10g", h + r }')
Vx = 0.01
Vy = 0.0
Vz = 0.0
NumBlocks = $n
$volume
%%
EOF
    t0=$(now)
    timeout "$TIMEOUT" "$exe" "$d/parameters.txt" > "$d/log" 2>&1 || true
    t1=$(now)
    awk -F, -v t0="$t0" -v t1="$t1" 'NR > 1 && NF >= 9 { s += $9; k++ }
        END { printf "%.6f %.6g %d\n", t1 - t0, k ? s / k : 0, k }' "$d/stoppages.csv" 2>/dev/null ||
        echo "$(awk -v a="$t0" -v b="$t1" 'BEGIN { print b - a }') 0 0"
}

# ---- rockfall: the same slope, rock and surface --------------------------------------
cat > "$work/project.yaml" <<EOF
name: rockgis-bench
seed: 2009
terrain:
  dem: $work/dem.asc
  surface:
    restitution: {mean: $REST, sd: $REST_SD}
    friction: {mean: $FRIC, sd: $FRIC_SD}
rocks:
  - {name: rock, mass: $MASS, density: $DENSITY}
releases:
  - {name: release, point: [$X, $Y], height: $HEIGHT, rock: rock, count: 1}
simulation: {stop_speed: $STOP, max_time: 300, paths: 0}
EOF
rockfall_run() { # tag simulation-keys count -> "seconds simulated_seconds_mean impacts_mean events_mean"
    n=$3 p=$work/project-$1.yaml db=$work/rf-$1-$3.gpkg
    sed "s/paths: 0}/paths: 0, $2}/" "$work/project.yaml" > "$p"
    t0=$(now)
    "$ROCKFALL" run "$p" -o "$db" --count "$n" --threads 1 > "$work/rf-$1-$3.log"
    t1=$(now)
    # the run's summary: "engine events per trajectory: F flights, S surface segments,
    # I impacts, E edge transitions"
    events=$(awk '/engine events per trajectory:/ { sub(/.*trajectory: /, ""); split($0, f, ", ");
        s = 0; for (i in f) { split(f[i], w, " "); s += w[1] } printf "%.1f", s }' "$work/rf-$1-$3.log")
    sqlite3 "$db" "SELECT printf('%.6f %.6g %.1f ${events:-0}', $t1 - $t0, avg(duration_s), avg(n_impacts)) FROM trajectories"
}

row() { # name "seconds sim impacts events" of one trajectory, the same of COUNT, COUNT, dt
    # (RockGIS: its events are its steps, simulated seconds over dt)
    awk -v name="$1" -v one="$2" -v all="$3" -v n="$4" -v dt="${5:-0}" -v ref="${REF:-0}" 'BEGIN {
        split(one, a, " "); split(all, b, " ")
        per = (b[1] - a[1]) / (n - 1); if (per <= 0) per = b[1] / n
        rate = 1 / per
        ev = dt > 0 ? b[2] / dt : b[4]
        printf "| %s | %.1f | %.0f | %.2f | %s | %.0f | %.2f | %s |\n", name, 1e3 * per, rate, b[2], b[3],
            ev, (ev > 0 ? 1e6 * per / ev : 0), (ref > 0 ? sprintf("%.2fx", rate / ref) : "1")
    }'
}

echo "Against RockGIS on $(basename "$DEM")${APRON:+ (+$APRON rows of counter-slope)}: release ($X, $Y), $COUNT trajectories,"
echo "one core each; $MASS kg (RockGIS: $volume m^3 at $DENSITY kg/m^3), restitution $REST"
echo "(RockGIS: Kna $REST, Knb 0), friction $FRIC (RockGIS: none; its tangential law, drag $DRAG m/s^2),"
echo "stop speed $STOP m/s; rockfall's restitution and friction sd $REST_SD and $FRIC_SD."
echo
echo "| program | ms per trajectory | trajectories/s per core | simulated s per trajectory | impacts per trajectory | events per trajectory | us per event | against RockGIS dt 0.01 s |"
echo "|---|---:|---:|---:|---:|---:|---:|---:|"
REF=0
for dt in 0.01 0.001; do
    one=$(rockgis_run "$dt" 1)
    all=$(rockgis_run "$dt" "$COUNT")
    stopped=${all##* }
    [ "$stopped" -eq "$COUNT" ] ||
        echo "note: RockGIS at dt $dt s stopped $stopped of $COUNT blocks (it ends the program when a block leaves the DEM; each run may time out at $TIMEOUT s)" >&2
    if [ "$dt" = 0.01 ]; then
        REF=$(awk -v a="${one%% *}" -v b="${all%% *}" -v n="$COUNT" \
            'BEGIN { p = (b - a) / (n - 1); if (p <= 0) p = b / n; printf "%.10g", 1 / p }')
    fi
    row "RockGIS dt $dt s" "${one% *} - 0" "${all% *} - 0" "$COUNT" "$dt" # it counts no impacts
done
for setting in "full:model: sphere, contact: full:sphere, full contact" \
    "centre:model: sphere, contact: centre:sphere, centre contact" "point:model: point:point mass"; do
    tag=${setting%%:*} rest=${setting#*:} label=${setting##*:}
    keys=${rest%:*}
    one=$(rockfall_run "$tag" "$keys" 1)
    all=$(rockfall_run "$tag" "$keys" "$COUNT")
    row "rockfall, $label" "$one" "$all" "$COUNT"
done
