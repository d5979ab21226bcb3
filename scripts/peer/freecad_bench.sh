#!/usr/bin/env bash
# FreeCAD Path (the open peer) on millnet's roughing benchmark (issue 11), judged by millnet simulate.
#
#   bash scripts/peer/freecad_bench.sh            # everything: FreeCAD programs, calibration, table
#
# Environment (all optional):
#   WORK=/tmp/peer            scratch; programs and parts in $WORK/out
#   POCKETS="four_islands comb eight_islands"
#   POCKET_DIR=../shared/bench/pockets (or $MILLNET_SHARED_DIR/bench/pockets)
#   MILLNET=<repo>/build/app/millnet
#   DEFAULT_STOCK=1           also run FreeCAD with its own default stock (model + 1 mm all round, so every
#                             op starts at Z +1) into $WORK/out/default_stock/ (0 = skip)
#
# What it does, per pocket:
#  1. FreeCADCmd scripts/peer/freecad_bench.py: builds the part (block Z -10..0 over the boundary's bounding
#     box + 10 mm, pocket 5 mm deep, arcs as true arcs), a Path Job (stock = part, ExtZpos 0), a 10 mm endmill
#     ToolController (1500 / 300 mm/min), a PocketShape op (Offset, 50 %, climb) and an Adaptive op (clearing,
#     50 %), each posted separately with linuxcnc_post -> $WORK/out/<pocket>.freecad_{offset,adaptive}.nc,
#     the part -> $WORK/out/<pocket>.stl (MeshPart, linear deflection 0.001 mm).
#  2. The frame: millnet simulate recentres the mesh (its minimum corner -> X 0 Y 0) and puts program Z 0 at
#     the mesh top + /rough/top_allowance_mm (default 1 mm). So the part is built with the block's corner at
#     X 0 Y 0 (the pocket translated by "shift" in <pocket>.freecad.json) and simulate gets a copy of the
#     bench config with /rough/top_allowance_mm = 0 ($WORK/roughing-issue11.frame0.json): program Z 0 =
#     part top = stock top. The /machine block (the time model) is the bench config's, unchanged.
#  3. millnet's G-code reader refuses G54, G40, G49, G80, G43 and H words (modal setup: work offset 1,
#     cutter compensation off, tool length offset cancel / apply, canned cycle cancel). A copy without those
#     words (and nothing else) goes to $WORK/sim_in/; the script checks that every G0-G3 line is unchanged.
#  4. millnet simulate each program on the flat stock, plus millnet's own offset and adaptive planners on
#     the same (translated) pocket as a reference. Retractions and the lateral wall penetration are counted
#     from the G-code by `python3 freecad_bench.py check`.
#  Calibration (four_islands): millnet's offset program must simulate without a gouge on the FreeCAD part,
#  with the time_kinematic_min of its own pocket metrics.
set -euo pipefail

HERE=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
ROOT=$(cd "$HERE/../.." && pwd)
WORK=${WORK:-/tmp/peer}
OUT=$WORK/out
POCKETS=${POCKETS:-"four_islands comb eight_islands"}
POCKET_DIR=${POCKET_DIR:-${MILLNET_SHARED_DIR:-$ROOT/../shared}/bench/pockets}
MILLNET=${MILLNET:-$ROOT/build/app/millnet}
CONFIG=$ROOT/configs/bench/roughing-issue11.json
DEFAULT_STOCK=${DEFAULT_STOCK:-1}
PY=$HERE/freecad_bench.py

say() { printf '%s\n' "$*" >&2; }
die() { say "freecad_bench: $*"; exit 1; }

[ -x "$MILLNET" ] || die "millnet not built at $MILLNET (scripts/build.sh)"
command -v python3 >/dev/null || die "python3 is needed"

# --- FreeCAD ---------------------------------------------------------------------------------------
FC=$(command -v FreeCADCmd || command -v freecadcmd || true)
if [ -z "$FC" ]; then
  say "installing FreeCAD (apt-get install -y freecad)"
  export DEBIAN_FRONTEND=noninteractive
  apt-get update -qq
  apt-get install -y freecad
  FC=$(command -v FreeCADCmd || command -v freecadcmd) || die "no FreeCADCmd after apt-get install freecad"
fi
FC_VERSION=$(dpkg-query -W -f='${Version}' freecad 2>/dev/null || echo unknown)
say "FreeCAD: $FC (package $FC_VERSION)"

mkdir -p "$OUT" "$WORK/sim_in" "$WORK/sim" "$WORK/ref"

# --- the simulate config: the bench config with Z 0 at the mesh top ---------------------------------
SIMCFG=$WORK/roughing-issue11.frame0.json
python3 - "$CONFIG" "$SIMCFG" <<'EOF'
import json, sys
c = json.load(open(sys.argv[1]))
c.setdefault("rough", {})["top_allowance_mm"] = 0
c["comment"] = c.get("comment", "") + " | scripts/peer: /rough/top_allowance_mm 0 so that simulate's Z 0 is the mesh top"
json.dump(c, open(sys.argv[2], "w"), indent=1)
EOF

# Strips the words millnet's reader refuses (none of them moves the tool); comments untouched.
sanitize() {
  sed -E '/^[[:space:]]*\(/!{:a; s/(^|[[:space:]])(G54|G40|G49|G80|G43|H[0-9]+)([[:space:]]|$)/\1\3/; ta}' "$1" >"$2"
  cmp -s <(grep -E '^[[:space:]]*G[0-3][[:space:]]' "$1") <(grep -E '^[[:space:]]*G[0-3][[:space:]]' "$2") ||
    die "sanitizing $1 changed a motion line"
}

# simulate NC PART DIR -> DIR/<stem>.sim.json
simulate() {
  "$MILLNET" simulate --config "$SIMCFG" --gcode "$1" --tool flat:10 --mesh "$2" --stock flat --out "$3" \
    --quiet --no-preview
}

# translated copy of a pocket JSON (the FreeCAD / simulate frame)
shift_pocket() {  # SRC DST SX SY
  python3 - "$@" <<'EOF'
import json, sys
src, dst, sx, sy = sys.argv[1], sys.argv[2], float(sys.argv[3]), float(sys.argv[4])
p = json.load(open(src))
mv = lambda loop: [[v[0] + sx, v[1] + sy] + list(v[2:]) for v in loop]
p["boundary"] = mv(p["boundary"])
p["islands"] = [mv(l) for l in p.get("islands", [])]
p["note"] = p.get("note", "") + " | translated by (%g, %g) into the FreeCAD part's frame" % (sx, sy)
json.dump(p, open(dst, "w"), indent=1)
EOF
}

json_get() { python3 -c 'import json,sys; d=json.load(open(sys.argv[1])); print(eval(sys.argv[2], {}, {"d": d}))' "$@"; }

# --- 1. FreeCAD ------------------------------------------------------------------------------------
for p in $POCKETS; do
  src=$POCKET_DIR/$p.json
  [ -f "$src" ] || die "no pocket $src"
  say "FreeCAD: $p"
  log=$OUT/$p.freecad.log
  PEER_POCKET=$src PEER_OUT=$OUT PEER_STOCK_ZPOS=0 "$FC" "$PY" >"$log" 2>&1 || die "FreeCADCmd failed on $p (see $log)"
  grep -q "^PEER_DONE $p" "$log" || die "FreeCADCmd did not finish $p (see $log)"
  if [ "$DEFAULT_STOCK" = 1 ]; then
    mkdir -p "$OUT/default_stock"
    PEER_POCKET=$src PEER_OUT=$OUT/default_stock PEER_STOCK_ZPOS=1 "$FC" "$PY" >"$OUT/default_stock/$p.freecad.log" 2>&1 ||
      die "FreeCADCmd failed on $p with the default stock"
  fi
done

# --- 2. calibration on four_islands -----------------------------------------------------------------
CAL=
if [[ " $POCKETS " == *" four_islands "* ]]; then
  say "calibration: millnet offset program on the FreeCAD part"
  "$MILLNET" pocket --config "$CONFIG" --planner offset --pocket "$POCKET_DIR/four_islands.json" --out "$WORK/mill" --quiet --no-preview
  read -r sx sy < <(json_get "$OUT/four_islands.freecad.json" '"%r %r" % tuple(d["shift"])')
  shift_pocket "$POCKET_DIR/four_islands.json" "$WORK/ref/four_islands.json" "$sx" "$sy"
  "$MILLNET" pocket --config "$CONFIG" --planner offset --pocket "$WORK/ref/four_islands.json" --out "$WORK/mill_shift" --quiet --no-preview
  simulate "$WORK/mill_shift/four_islands.nc" "$OUT/four_islands.stl" "$WORK/sim/calibration"
  CAL=$(python3 - "$WORK/mill/four_islands.metrics.json" "$WORK/mill_shift/four_islands.metrics.json" \
      "$WORK/sim/calibration/four_islands.sim.json" <<'EOF'
import json, sys
t0 = json.load(open(sys.argv[1]))["time_kinematic_min"]
t1 = json.load(open(sys.argv[2]))["time_kinematic_min"]
s = json.load(open(sys.argv[3]))
ts = s["programs"][0]["time_kinematic_min"]
ok = s["max_gouge_mm"] == 0 and abs(ts - t1) < 1e-5 and abs(t1 - t0) < 1e-5
print("calibration %s: millnet offset four_islands time_kinematic_min pocket %.6f (translated copy %.6f), "
      "simulate %.6f; max_gouge_mm %g; uncut %.3f mm2, rest %.3f mm2"
      % ("OK" if ok else "FAILED", t0, t1, ts, s["max_gouge_mm"], s["uncut_area_mm2"], s["rest_area_mm2"]))
sys.exit(0 if ok else 1)
EOF
) || die "$CAL"
  say "$CAL"
fi

# --- 3. judge every program -------------------------------------------------------------------------
ROWS=$WORK/rows.jsonl
: >"$ROWS"
judge() {  # POCKET LABEL NC PART SHIFTED_POCKET_JSON
  local p=$1 label=$2 nc=$3 part=$4 pj=$5 stem dir
  stem=$(basename "$nc" .nc)
  cp "$nc" "$WORK/sim_in/$stem.raw.nc"
  sanitize "$nc" "$WORK/sim_in/$stem.nc"
  dir=$WORK/sim/$label.$p
  rm -rf "$dir"
  simulate "$WORK/sim_in/$stem.nc" "$part" "$dir"
  python3 "$PY" check "$pj" "$WORK/sim_in/$stem.nc" 0 0 >"$dir/check.json"
  python3 - "$p" "$label" "$nc" "$dir/$(basename "$part" .stl).sim.json" "$dir/check.json" >>"$ROWS" <<'EOF'
import json, sys
p, label, nc, simf, chkf = sys.argv[1:6]
s, c = json.load(open(simf)), json.load(open(chkf))
pr = s["programs"][0]
print(json.dumps({"pocket": p, "program": label, "nc": nc,
  "time_kinematic_min": pr["time_kinematic_min"], "time_feed_min": pr["time_feed_min"], "path_length_mm": pr["path_length_mm"],
  "max_gouge_mm": s["max_gouge_mm"], "gouge_line": s.get("gouge_line"), "cutting_rapids": pr["cutting_rapids"],
  "uncut_area_mm2": s["uncut_area_mm2"], "rest_area_mm2": s["rest_area_mm2"], "remaining_area_mm2": s["remaining_area_mm2"],
  "wall_penetration_mm": c["max_wall_penetration_mm"], "wall_penetration_line": c["penetration_line"],
  "retractions": c["retractions"], "plunges": c["plunges"], "rapids_below_top": c["rapids_below_top"],
  "rapid_len_below_top_mm": c["rapid_len_below_top_mm"]}))
EOF
}

for p in $POCKETS; do
  read -r sx sy < <(json_get "$OUT/$p.freecad.json" '"%r %r" % tuple(d["shift"])')
  pj=$WORK/ref/$p.json
  shift_pocket "$POCKET_DIR/$p.json" "$pj" "$sx" "$sy"
  say "judging: $p"
  judge "$p" freecad_offset "$OUT/$p.freecad_offset.nc" "$OUT/$p.stl" "$pj"
  judge "$p" freecad_adaptive "$OUT/$p.freecad_adaptive.nc" "$OUT/$p.stl" "$pj"
  if [ "$DEFAULT_STOCK" = 1 ]; then
    for v in offset adaptive; do
      cp "$OUT/default_stock/$p.freecad_$v.nc" "$OUT/default_stock/$p.freecad_${v}_stock1.nc"
      judge "$p" "freecad_${v}_stock1" "$OUT/default_stock/$p.freecad_${v}_stock1.nc" "$OUT/$p.stl" "$pj"
    done
  fi
  for planner in offset adaptive; do  # millnet's own planners on the same part, for reference
    "$MILLNET" pocket --config "$CONFIG" --planner "$planner" --pocket "$pj" --out "$WORK/ref/$planner" --quiet --no-preview
    cp "$WORK/ref/$planner/$p.nc" "$WORK/ref/$p.millnet_$planner.nc"
    judge "$p" "millnet_$planner" "$WORK/ref/$p.millnet_$planner.nc" "$OUT/$p.stl" "$pj"
  done
done

# --- 4. table -----------------------------------------------------------------------------------------
python3 - "$ROWS" "$OUT" "$FC_VERSION" "$CAL" <<'EOF'
import json, sys
rows = [json.loads(l) for l in open(sys.argv[1])]
out, ver, cal = sys.argv[2], sys.argv[3], sys.argv[4]
ref = {"four_islands": 1.49, "comb": 1.41, "eight_islands": 2.65}
L = ["# FreeCAD Path (%s) on millnet's roughing bench, judged by millnet simulate" % ver, "",
     cal, "",
     "time = millnet simulate time_kinematic_min (500 mm/s2, junction deviation 0.01 mm, rapids 5000 mm/min); "
     "gouge = simulate max_gouge_mm (z-map, 0.02 mm cells; a cut into a vertical wall reads as the wall's height); "
     "wall pen. = largest lateral penetration of the tool into the design walls, from the G-code geometry; "
     "uncut / rest / remaining = simulate's uncut_area_mm2 / rest_area_mm2 / remaining_area_mm2; "
     "retr. = G0 retractions to the safe height between cuts; G0<0 = rapids below the stock top (count / length).", "",
     "| pocket | program | time min | issue ref. | gouge mm | wall pen. mm | uncut mm2 | rest mm2 | remaining mm2 | retr. | plunges | G0<0 | cutting rapids |",
     "|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|"]
for r in rows:
    L.append("| %s | %s | %.3f | %s | %.3f | %.3f | %.2f | %.2f | %.2f | %d | %d | %d / %.0f mm | %d |" % (
        r["pocket"], r["program"], r["time_kinematic_min"],
        ("%.2f" % ref[r["pocket"]]) if r["program"] == "freecad_offset" and r["pocket"] in ref else "",
        r["max_gouge_mm"], r["wall_penetration_mm"], r["uncut_area_mm2"], r["rest_area_mm2"], r["remaining_area_mm2"],
        r["retractions"], r["plunges"], r["rapids_below_top"], r["rapid_len_below_top_mm"], r["cutting_rapids"]))
text = "\n".join(L) + "\n"
open(out + "/table.md", "w").write(text)
json.dump(rows, open(out + "/results.json", "w"), indent=1)
print(text)
EOF
