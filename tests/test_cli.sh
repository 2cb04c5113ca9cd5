#!/usr/bin/env bash
# The squama program: help, version, usage errors (exit 2 with a hint), failures (exit 1
# with "squama: <what> (<where>)"), and the params/presets commands end to end.
set -u
SQ=$1 SRC=$2 TMP=$3
rm -rf "$TMP" && mkdir -p "$TMP"
fails=0
out="$TMP/out" err="$TMP/err"

run() { "$SQ" "$@" >"$out" 2>"$err"; echo $? >"$TMP/rc"; }
check() { # description, expected rc, [grep pattern on stdout|stderr] ...
  local what=$1 want=$2; shift 2
  local rc; rc=$(cat "$TMP/rc")
  if [ "$rc" != "$want" ]; then
    echo "FAIL: $what: exit $rc, want $want"; cat "$err"; fails=$((fails + 1)); return
  fi
  while [ $# -gt 0 ]; do
    if ! grep -qF -- "$2" "$TMP/$1"; then
      echo "FAIL: $what: $1 lacks '$2'"; echo "--- stdout"; cat "$out"; echo "--- stderr"; cat "$err"
      fails=$((fails + 1))
    fi
    shift 2
  done
  echo "ok: $what"
}

run --version;            check "version" 0 out "squama 0."
run --help;               check "help" 0 out "usage: squama <command>" out "params" out "presets"
run;                      check "no command" 2 err "squama: no command given (see 'squama --help')"
run frobnicate;           check "unknown command" 2 err "unknown command 'frobnicate' (see 'squama --help')"
run --frob;               check "unknown option" 2 err "unknown option '--frob'"
for c in params presets; do
  run $c --help;          check "$c --help" 0 out "usage: squama $c"
done
run params --bogus;       check "params bad option" 2 err "unknown option '--bogus' (see 'squama params --help')"
run params --json --markdown; check "params exclusive" 2 err "exclude each other"

run params;               check "params table" 0 out "Spots_Tiling" out "0.05..32" out "0.1..5" out "Transversal_BeginEnd4"
run params spots;         check "params filter" 0 out "Spots_Interstice"
grep -q "Scales_XAmount" "$out" && { echo "FAIL: filter kept Scales_XAmount"; fails=$((fails + 1)); }
run params --json
check "params --json" 0 out '"name": "Pattern_Type"'
if command -v python3 >/dev/null; then
  python3 - "$out" <<'PY' || { echo "FAIL: params --json content"; fails=$((fails + 1)); }
import json, sys
rows = json.load(open(sys.argv[1]))
names = {r["name"] for r in rows}
assert len(rows) == len(names) >= 65, len(rows)
thesis = [r for r in rows if r["origin"] in ("thesis", "thesis-d11") and not r["name"].startswith("CA_")]
assert len(thesis) == 59, len(thesis)
tiling = next(r for r in rows if r["name"] == "Spots_Tiling")
assert tiling["min"] == 0.05 and tiling["suggested_max"] == 5 and tiling["default"] == "1"
PY
fi

run presets;              check "presets without subcommand" 2 err "say what to do"
run presets list;         check "presets list" 0 out "thesis/table_4_1_transversal.json" out "thesis/ca/vipera_berus.ca" out "transversal"
run presets list --json;  check "presets list --json" 0 out '"kind": "ca"'
run presets list /nonexistent; check "presets list missing dir" 1 err "squama: no presets folder here (/nonexistent)"
run presets validate "$SRC"/presets/*/*.json "$SRC"/presets/thesis/ca/*.ca
check "validate shipped" 0 out "ok  $SRC/presets/thesis/d11_five_lined_skink.json  (longitudinal" out "ok  $SRC/presets/layered/garter_snake.json  (spots" \
    out "ok  $SRC/presets/scales/green_black_skin.json  (none"
run presets validate;     check "validate nothing" 2 err "validate needs at least one FILE"

printf '{"format": "squama-preset/1",\n "Spots_Tilling": 2}\n' >"$TMP/typo.json"
run presets validate "$TMP/typo.json"
check "unknown key" 1 err "squama: unknown key \"Spots_Tilling\" (did you mean \"Spots_Tiling\"?) ($TMP/typo.json:2)"
printf '{"format": "squama-preset/1", "Longitudinal_NumberOfStripes": 99}\n' >"$TMP/range.json"
run presets validate "$TMP/range.json" "$TMP/typo.json" "$SRC/presets/thesis/table_4_3_longitudinal.json"
check "out of range" 1 err "\"Longitudinal_NumberOfStripes\" is 99, outside its range [1, 64]; suggested 1 to 10" err "2 of 3 files failed validation" out "ok  $SRC/presets/thesis/table_4_3_longitudinal.json"
printf '0 1 1 0\nrectangular\n0\n6\n1110 1\n110 x\n' >"$TMP/bad.ca"
run presets validate "$TMP/bad.ca"
check "bad CA descriptor" 1 err "rectangular rules have 4 bits, \"110\" has 3 ($TMP/bad.ca:6)"
run presets validate "$TMP/none.json"; check "missing preset" 1 err "cannot open preset: No such file or directory ($TMP/none.json)"

run presets format "$SRC/presets/thesis/table_4_3_longitudinal.json" -o "$TMP/fmt.json"
check "format -o" 0
run presets validate "$TMP/fmt.json"; check "formatted preset validates" 0
grep -q '"Spots_Tiling": 1' "$TMP/fmt.json" || { echo "FAIL: format lacks defaults"; fails=$((fails + 1)); }
run presets format "$TMP/fmt.json"; check "format to stdout" 0 out '"Longitudinal_Pinch": 2.6'
cmp -s "$out" "$TMP/fmt.json" || { echo "FAIL: format is not idempotent"; fails=$((fails + 1)); }
run presets format "$TMP/typo.json" -o "$TMP/never.json"; check "format refuses bad input" 1
[ -e "$TMP/never.json" ] && { echo "FAIL: a failed format wrote a file"; fails=$((fails + 1)); }
run presets format "$TMP/fmt.json" -o /nonexistent/x.json; check "format unwritable" 1 err "(/nonexistent/x.json)"
run presets format a b;   check "format two files" 2 err "format takes exactly one FILE"
run presets format x -o;  check "format -o without file" 2 err "-o needs a value"
# a value missing, last on the line: named as typed, long or short, not "unknown"
run fit x.jpg -o "$TMP/never" --evals; check "fit --evals without a value" 2 err "squama: --evals needs a value (see 'squama fit --help')"
run render x.json -o "$TMP/never" --size; check "render --size without a value" 2 err "--size needs a value"
run fit x.jpg -o "$TMP/never" -b; check "fit -b without a value" 2 err "-b needs a value"
run fit -xq x.jpg -o "$TMP/never"; check "an unknown letter in a cluster" 2 err "unknown option '-x'"
run fit --seed=3 -xq x.jpg -o "$TMP/never"; check "an unknown letter in a cluster after a long option" 2 err "unknown option '-x'"
run fit --json -qx x.jpg -o "$TMP/never"; check "an unknown letter ending a cluster" 2 err "unknown option '-x'"
run fit x.jpg -o "$TMP/never" --json=1; check "a value for a flag" 2 err "--json takes no value"
run fit x.jpg -o "$TMP/never" --s=3; check "an ambiguous prefix" 2 err "ambiguous option '--s': --seed, --size, --start? (see 'squama fit --help')"
run fit x.jpg -o "$TMP/never" --sed 3; check "an unknown option" 2 err "unknown option '--sed'"
run presets frob;         check "presets unknown subcommand" 2 err "unknown subcommand 'frob'"
SQUAMA_PRESETS="$SRC/presets/thesis/ca" run presets list
check "SQUAMA_PRESETS" 0 out "daboia_russelii.ca"

# render
run render --help;        check "render --help" 0 out "usage: squama render"
run render "$SRC/presets/thesis/table_4_4_spots.json"; check "render without -o" 2 err "say where the maps go with -o DIR"
run render -o "$TMP/r";   check "render without preset" 2 err "give a PRESET or --ca FILE"
run render "$SRC/presets/thesis/table_4_4_spots.json" -o "$TMP/r" --size 5; check "render size too small" 2 err "--size must be N or WxH"
run render "$SRC/presets/thesis/table_4_4_spots.json" -o "$TMP/r" --format tga; check "render bad format" 2 err "--format must be png or exr"
run render "$SRC/presets/thesis/table_4_4_spots.json" -o "$TMP/r" --format exr --bits 8; check "render bits vs format" 2 err "does not fit"
run render "$SRC/presets/thesis/table_4_4_spots.json" -o "$TMP/r/deep" --size 64x48
check "render png" 0 out "wrote $TMP/r/deep/basecolor.png" out "64x48 spots pattern"
for m in basecolor height roughness normal; do
  [ -s "$TMP/r/deep/$m.png" ] || { echo "FAIL: $m.png missing"; fails=$((fails + 1)); }
done
# OpenImageIO is in a module opened at the first image (io/module.c): a command without
# images does not load it, one with images does; a squama beside a module that is not one
# says so and writes nothing
loads_oiio() {
  rm -f "$TMP"/ld.*
  LD_DEBUG=files LD_DEBUG_OUTPUT="$TMP/ld" "$SQ" "$@" >/dev/null 2>&1
  grep -qs "libOpenImageIO" "$TMP"/ld.*
}
loads_oiio params && { echo "FAIL: squama params loaded OpenImageIO"; fails=$((fails + 1)); }
loads_oiio render "$SRC/presets/thesis/table_4_4_spots.json" -o "$TMP/r/ld" --size 32 ||
  { echo "FAIL: squama render did not load OpenImageIO"; fails=$((fails + 1)); }
rm -f "$TMP"/ld.*
mkdir -p "$TMP/moved" && cp "$SQ" "$TMP/moved/squama" && echo "not a library" >"$TMP/moved/libsquama_image.so"
"$TMP/moved/squama" render "$SRC/presets/thesis/table_4_4_spots.json" -o "$TMP/r/moved" --size 32 >"$out" 2>"$err"
echo $? >"$TMP/rc"
check "render beside a broken image module" 1 err "cannot read or write images: squama's image module did not load: " \
  err "($TMP/moved/libsquama_image.so)"
[ -e "$TMP/r/moved" ] && { echo "FAIL: a render without its image module made its folder"; fails=$((fails + 1)); }
# the maps are a set: a render that cannot write one of them leaves the ones there before
cp -r "$TMP/r/deep" "$TMP/r/set" && rm "$TMP/r/set/normal.png" && mkdir "$TMP/r/set/normal.png"
cp "$TMP/r/set/basecolor.png" "$TMP/r/set_before.png"
run render "$SRC/presets/thesis/table_4_1_transversal.json" -o "$TMP/r/set" --size 32
check "render into a set it cannot finish" 1 err "a folder is where the map goes; no map was written ($TMP/r/set/normal.png)"
cmp -s "$TMP/r/set/basecolor.png" "$TMP/r/set_before.png" || { echo "FAIL: a failed render replaced basecolor.png"; fails=$((fails + 1)); }
[ "$(ls -A "$TMP/r/set" | tr '\n' ' ')" = "basecolor.png height.png normal.png roughness.png " ] || { echo "FAIL: a failed render left: $(ls -A "$TMP/r/set")"; fails=$((fails + 1)); }
# a disk that fills (here a file size limit of 8 KiB): the render fails, the old maps stay,
# nothing temporary is left (OIIO's PNG writer reports success on a PNG cut short)
rm -rf "$TMP/r/full" && cp -r "$TMP/r/deep" "$TMP/r/full"
(ulimit -f 8; "$SQ" render "$SRC/presets/complex/cheetah.json" -o "$TMP/r/full" --size 256 >"$out" 2>"$err"; echo $? >"$TMP/rc")
check "render onto a full disk" 1 err "the file came out cut short (is the disk full?) ($TMP/r/full/basecolor.png)"
cmp -s "$TMP/r/full/basecolor.png" "$TMP/r/deep/basecolor.png" || { echo "FAIL: a render onto a full disk replaced basecolor.png"; fails=$((fails + 1)); }
[ "$(ls -A "$TMP/r/full" | tr '\n' ' ')" = "basecolor.png height.png normal.png roughness.png " ] || { echo "FAIL: a render onto a full disk left: $(ls -A "$TMP/r/full")"; fails=$((fails + 1)); }
# OpenEXR's own message names the file it was writing: as the map it was to become
(ulimit -f 8; "$SQ" render "$SRC/presets/complex/cheetah.json" -o "$TMP/r/fullx" --size 256 -f exr >"$out" 2>"$err"; echo $? >"$TMP/rc")
check "render EXR maps onto a full disk" 1 err "image file \"$TMP/r/fullx/basecolor.exr\". File output failed. ($TMP/r/fullx/basecolor.exr)"
! grep -q 'tmp-' "$err" || { echo "FAIL: a temporary name in the error: $(cat "$err")"; fails=$((fails + 1)); }
[ ! -e "$TMP/r/fullx" ] || { echo "FAIL: a render onto a full disk left: $(ls -A "$TMP/r/fullx")"; fails=$((fails + 1)); }
# a map that cannot be replaced after another was (a sticky folder: another user's map):
# the one replaced is put back. Needs root to stage it, and a user who can run squama here.
if [ "$(id -u)" = 0 ] && command -v setpriv >/dev/null && chmod 1777 "$TMP/r" &&
   setpriv --reuid=65534 --regid=65534 --clear-groups "$SQ" --version >/dev/null 2>&1; then
  mkdir -m 1777 "$TMP/r/sticky" && cp "$TMP/r/deep/"*.png "$TMP/r/sticky/" && chmod 644 "$TMP/r/sticky/"*.png
  chown 65534 "$TMP/r/sticky/basecolor.png" && cp "$TMP/r/sticky/basecolor.png" "$TMP/r/sticky_before.png"
  setpriv --reuid=65534 --regid=65534 --clear-groups "$SQ" render "$SRC/presets/thesis/table_4_1_transversal.json" \
    -o "$TMP/r/sticky" --size 32 >"$out" 2>"$err"; echo $? >"$TMP/rc"
  check "render into a set it may not replace" 1 err "cannot replace the map: Operation not permitted; no map was written ($TMP/r/sticky/height.png)"
  cmp -s "$TMP/r/sticky/basecolor.png" "$TMP/r/sticky_before.png" || { echo "FAIL: a failed render left a new basecolor.png"; fails=$((fails + 1)); }
  [ "$(ls -A "$TMP/r/sticky" | tr '\n' ' ')" = "basecolor.png height.png normal.png roughness.png " ] || { echo "FAIL: a failed render left: $(ls -A "$TMP/r/sticky")"; fails=$((fails + 1)); }
else
  echo "skipped: the sticky-folder render (needs root, setpriv, and squama runnable by uid 65534)"
fi
# a render stopped (SIGTERM) at each of its renames, strace injecting the signal: the set
# is wholly old or wholly new, and nothing else is left
if command -v strace >/dev/null && strace -o /dev/null true 2>/dev/null; then
  "$SQ" render "$SRC/presets/scales/domed_dark_gaps.json" -o "$TMP/r/new_set" --size 64 -q
  for when in 1 2 3 4 5 6 7 8 9 10 11 12 13 14; do
    rm -rf "$TMP/r/k" && cp -r "$TMP/r/deep" "$TMP/r/k"
    ASAN_OPTIONS="${ASAN_OPTIONS:+$ASAN_OPTIONS:}detect_leaks=0" strace -o /dev/null -e inject=rename:signal=SIGTERM:when=$when \
      "$SQ" render "$SRC/presets/scales/domed_dark_gaps.json" -o "$TMP/r/k" --size 64 -q >/dev/null 2>&1
    o=0 n=0
    for m in basecolor height roughness normal; do
      cmp -s "$TMP/r/k/$m.png" "$TMP/r/deep/$m.png" && o=$((o + 1))
      cmp -s "$TMP/r/k/$m.png" "$TMP/r/new_set/$m.png" && n=$((n + 1))
    done
    { [ $o = 4 ] || [ $n = 4 ]; } && [ "$(ls -A "$TMP/r/k" | tr '\n' ' ')" = "basecolor.png height.png normal.png roughness.png " ] ||
      { echo "FAIL: a render stopped at rename $when left $o old and $n new maps: $(ls -A "$TMP/r/k")"; fails=$((fails + 1)); }
  done
  # a set that fails part way is taken back out; a new map that cannot be (strace makes its
  # unlink fail) is named, not left unsaid
  mkdir -p "$TMP/r/back/normal.png"
  ASAN_OPTIONS="${ASAN_OPTIONS:+$ASAN_OPTIONS:}detect_leaks=0" strace -f -o /dev/null -P "$TMP/r/back/basecolor.png" \
    -e trace=unlink,unlinkat -e inject=unlink,unlinkat:error=EACCES \
    "$SQ" render "$SRC/presets/thesis/table_4_1_transversal.json" -o "$TMP/r/back" --size 32 >"$out" 2>"$err"; echo $? >"$TMP/rc"
  check "a set taken back out but for one map" 1 err "a folder is where the map goes; no map was written ($TMP/r/back/normal.png)" \
    err "squama: warning: the new $TMP/r/back/basecolor.png stays (cannot remove it: Permission denied), though the rest of its set was not written"
  [ "$(ls -A "$TMP/r/back" | tr '\n' ' ')" = "basecolor.png normal.png " ] || { echo "FAIL: a set taken back out left: $(ls -A "$TMP/r/back")"; fails=$((fails + 1)); }
else
  echo "skipped: the interrupted render (needs strace)"
fi
# a JPEG onto a full disk: libjpeg ends the program itself; squama still says so in its own
# words and leaves nothing (leaks not checked: the program is ended mid-write)
mkdir -p "$TMP/fulljpg"
(ulimit -f 8; ASAN_OPTIONS="${ASAN_OPTIONS:+$ASAN_OPTIONS:}detect_leaks=0" "$SQ" photo "$SRC/presets/complex/cheetah.json" \
   -o "$TMP/fulljpg/ph.jpg" >"$out" 2>"$err"; echo $? >"$TMP/rc")
check "photo onto a full disk" 1 err "squama: cannot write image: the write failed (is the disk full?) ($TMP/fulljpg/ph.jpg)"
[ -z "$(ls -A "$TMP/fulljpg")" ] || { echo "FAIL: a photo onto a full disk left: $(ls -A "$TMP/fulljpg")"; fails=$((fails + 1)); }
run render "$TMP/complex_missing.json" -o "$TMP/r/new/deeper" --size 32
check "render of a missing preset" 1 err "cannot open preset"
[ -e "$TMP/r/new" ] && { echo "FAIL: a failed render left a folder"; fails=$((fails + 1)); }
run render "$SRC/presets/thesis/table_4_4_spots.json" -o "$TMP/r/exr" --size 32 --format exr -q
check "render exr" 0
[ -s "$TMP/r/exr/height.exr" ] || { echo "FAIL: height.exr missing"; fails=$((fails + 1)); }
run render --ca "$SRC/presets/thesis/ca/crotalus_viridis.ca" -o "$TMP/r/ca" --size 32
check "render --ca" 0 out "other_simple pattern"
run render --ca "$TMP/bad.ca" -o "$TMP/r/ca2" --size 32
check "render bad --ca" 1 err "($TMP/bad.ca:6)"
printf '{"format": "squama-preset/1", "Pattern_Type": "complex"}\n' >"$TMP/complex.json"
run render "$TMP/complex.json" -o "$TMP/r/cx" --size 32
check "render complex" 0 out "32x32 complex pattern"
[ -s "$TMP/r/cx/basecolor.png" ] || { echo "FAIL: complex basecolor.png missing"; fails=$((fails + 1)); }
printf '{"format": "squama-preset/1", "Pattern_Type": "complex", "RD_System": "waves"}\n' >"$TMP/complex_bad.json"
run render "$TMP/complex_bad.json" -o "$TMP/r/cx2" --size 32
check "render complex bad system" 1 err "RD_System"
printf '{"format": "squama-preset/1", "Pattern_Type": "spots",\n "Pattern_Layers": [{"Pattern_Type": "longitudinal", "Layer_Blend": "multiply"}]}\n' >"$TMP/layered.json"
run render "$TMP/layered.json" -o "$TMP/r/ly" --size 32
check "render layered" 0 out "32x32 spots pattern"
printf '{"format": "squama-preset/1",\n "Pattern_Layers": [{"Pattern_Type": "spots",\n   "Scales_XAmount": 4}]}\n' >"$TMP/layered_bad.json"
run presets validate "$TMP/layered_bad.json"
check "layer with a non-pattern key" 1 err "squama: \"Scales_XAmount\" (group scales) cannot be set in Pattern_Layers[0]" err "($TMP/layered_bad.json:3)"
[ -e "$TMP/r/cx2/basecolor.png" ] && { echo "FAIL: a failed render wrote a map"; fails=$((fails + 1)); }
run render "$TMP/typo.json" -o "$TMP/r/t";  check "render bad preset" 1 err "unknown key"
# contact sheets: a grid of presets, or nothing at all when one of them is bad
run render --sheet "$TMP/sheet.png" "$SRC/presets/thesis/table_4_4_spots.json" "$SRC/presets/thesis/table_4_1_transversal.json" \
  "$SRC/presets/thesis/d11_five_lined_skink.json" --size 48 --cols 2
check "render --sheet" 0 out "wrote $TMP/sheet.png: 3 presets, 2 x 2"
[ -s "$TMP/sheet.png" ] || { echo "FAIL: sheet.png missing"; fails=$((fails + 1)); }
run render --sheet "$TMP/sheet2.png" "$SRC/presets/thesis/table_4_4_spots.json" "$TMP/typo.json" --size 48
check "render --sheet bad preset" 1 err "unknown key"
[ -e "$TMP/sheet2.png" ] && { echo "FAIL: a failed sheet was written"; fails=$((fails + 1)); }
run render --sheet "$TMP/sheet3.png" "$SRC/presets/thesis/table_4_4_spots.json" -o "$TMP/r"
check "render --sheet with -o" 2 err "--sheet makes one PNG of base colours"
run render --cols 2 "$SRC/presets/thesis/table_4_4_spots.json" -o "$TMP/r"; check "render --cols without --sheet" 2 err "--cols is for --sheet"
run render --sheet "$TMP/sheet3.png"; check "render --sheet alone" 2 err "needs the PRESETs"
run render --sheet "$TMP/sheet3.png" --cols 3x "$SRC/presets/thesis/table_4_4_spots.json"; check "render --cols trailing garbage" 2 err "--cols must be 1 to 64, got '3x'"
run render "$SRC/presets/thesis/table_4_4_spots.json" -o "$TMP/r" --threads 0; check "render --threads 0" 2 err "--threads must be 1 to 1024, got '0'"

# photo and preview
run photo --help;         check "photo --help" 0 out "usage: squama photo"
run photo "$SRC/presets/thesis/table_4_4_spots.json"; check "photo without -o" 2 err "say where the photo goes"
run photo "$SRC/presets/thesis/table_4_4_spots.json" -o "$TMP/p.jpg" --coil 2; check "photo bad coil" 2 err "--coil must be in [0, 1]"
run photo "$SRC/presets/thesis/table_4_4_spots.json" -o "$TMP/p.jpg" --seed 1e3; check "photo --seed as a real" 2 err "--seed must be 0 to 2147483647, got '1e3'"
run photo "$SRC/presets/thesis/table_4_4_spots.json" -o "$TMP/p.jpg" --quality 50.5; check "photo --quality not whole" 2 err "--quality must be 1 to 100, got '50.5'"
run photo "$SRC/presets/thesis/table_4_4_spots.json" -o "$TMP/same.jpg" --mask "$TMP/same.jpg"
check "photo and mask one file" 2 err "must be three different files"
run photo "$SRC/presets/thesis/table_4_4_spots.json" -o "$TMP/same.jpg" --truth "$TMP/./same.jpg"
check "photo and truth one file" 2 err "must be three different files"
[ -e "$TMP/same.jpg" ] && { echo "FAIL: photo wrote a refused file"; fails=$((fails + 1)); }
run photo "$SRC/presets/thesis/table_4_4_spots.json" -o "$TMP/p.jpg" --size 320x240 --seed 4 --backdrop litter --noise 0.01
check "photo" 0 out "wrote $TMP/p.jpg, $TMP/p_mask.png, $TMP/p_truth.json"
[ -s "$TMP/p.jpg" ] && [ -s "$TMP/p_mask.png" ] || { echo "FAIL: photo files missing"; fails=$((fails + 1)); }
if command -v python3 >/dev/null; then
  python3 - "$TMP/p_truth.json" <<'PY' || { echo "FAIL: truth JSON"; fails=$((fails + 1)); }
import json, sys
t = json.load(open(sys.argv[1]))
assert t["format"] == "squama-photo-truth/1" and t["preset"]["Pattern_Type"] == "spots"
assert t["width"] == 320 and t["body_radius"] > 4 and len(t["centre_line"]) > 10
PY
fi
run render "$SRC/presets/thesis/table_4_4_spots.json" -o "$TMP/r/pv" --size 64 --preview
check "render --preview" 0 out "wrote $TMP/r/pv/preview.png"

# prepare and score (on the synthetic photo above)
run prepare "$TMP/p.jpg" --mask "$TMP/p_mask.png" -o "$TMP/prep" --debug
check "prepare" 0 out "given mask, body"
check "prepare names the light" 0 out "lit from"
for f in mask.png strip.png prepared.json line.json line.png debug/4_centre_line.png debug/6_strip.png; do
  [ -s "$TMP/prep/$f" ] || { echo "FAIL: prepare did not write $f"; fails=$((fails + 1)); }
done
# its outputs are a set: one it cannot write (a folder where prepared.json goes, the last)
# leaves the earlier ones whole, and a line given takes the earlier run's line.json only
# when the set goes in
cp -r "$TMP/prep" "$TMP/prepset" && rm "$TMP/prepset/prepared.json" && mkdir "$TMP/prepset/prepared.json"
run prepare "$TMP/p.jpg" --line "$TMP/prep/line.json" -o "$TMP/prepset"
check "prepare into a set it cannot finish" 1 err "a folder is where the output goes; no output was written ($TMP/prepset/prepared.json)"
for f in mask.png strip.png line.json line.png; do
  cmp -s "$TMP/prepset/$f" "$TMP/prep/$f" || { echo "FAIL: a failed prepare changed $f"; fails=$((fails + 1)); }
done
[ "$(ls -A "$TMP/prepset" | tr '\n' ' ')" = "debug line.json line.png mask.png prepared.json strip.png " ] ||
  { echo "FAIL: a failed prepare left: $(ls -A "$TMP/prepset")"; fails=$((fails + 1)); }
# a staging folder a killed run left is named, not removed
mkdir -p "$TMP/prepleft/.prepare.tmp-Ab12Cd" && touch "$TMP/prepleft/.prepare.tmp-Ab12Cd/old-mask.png"
run prepare "$TMP/p.jpg" --mask "$TMP/p_mask.png" -o "$TMP/prepleft"
check "a staging folder left by a killed run" 0 err "squama: warning: $TMP/prepleft/.prepare.tmp-Ab12Cd is another run's temporary folder (one that was stopped, or one under way); it holds outputs that run had set aside (old-*)"
[ -e "$TMP/prepleft/.prepare.tmp-Ab12Cd/old-mask.png" ] || { echo "FAIL: a killed run's staging folder was removed"; fails=$((fails + 1)); }
# the centre line followed comes out as a body line, and goes back in
[ -s "$TMP/prep/line.json" ] || { echo "FAIL: prepare did not write line.json"; fails=$((fails + 1)); }
run prepare "$TMP/p.jpg" --line "$TMP/prep/line.json" -o "$TMP/prepl"
check "prepare --line" 0 out "line mask, body"
[ -e "$TMP/prepl/line.json" ] && { echo "FAIL: prepare --line wrote line.json"; fails=$((fails + 1)); }
[ -s "$TMP/prepl/line.png" ] || { echo "FAIL: prepare --line did not draw line.png"; fails=$((fails + 1)); }
grep -q "warning" "$TMP/err" && { echo "FAIL: prepare warned of a whole body's strip"; cat "$TMP/err"; fails=$((fails + 1)); }
# a line along two body widths of the body (line.json: a point every half width): warned of
python3 - "$TMP/prep/line.json" "$TMP/short.json" <<'PY'
import json, sys
l = json.load(open(sys.argv[1]))
l["stretches"] = [l["stretches"][0][:5]]
json.dump(l, open(sys.argv[2], "w"))
PY
run prepare "$TMP/p.jpg" --line "$TMP/short.json" -o "$TMP/preps"
check "prepare --line along a short stretch" 0 err "squama: warning: the body line covers only" \
  err "body widths of clean body (3 at least to see a pattern repeat)"
run fit "$TMP/p.jpg" --line "$TMP/short.json" -o "$TMP/fs" --evals 100 --size 64 -j 2 --categories none,spots
check "fit along a short stretch" 0 err "squama: warning: the body line covers only"
grep -q '"warning": "the body line covers only' "$TMP/fs/fit.json" || { echo "FAIL: fit.json lacks the short strip's warning"; fails=$((fails + 1)); }
grep -q "<b>Warning:</b> the body line covers only" "$TMP/fs/report.html" || { echo "FAIL: report.html lacks the warning"; fails=$((fails + 1)); }
printf '{"format": "squama-body-line/1", "width": 30,\n "stretches": [[[10, 10], [9000, 10]]]}\n' >"$TMP/far.json"
run prepare "$TMP/p.jpg" --line "$TMP/far.json" -o "$TMP/prepf"
check "prepare --line outside" 1 err "stretches[0][1] (9000.0, 10.0) lies outside the 320x240 photo (body line)"
[ -e "$TMP/prepf/strip.png" ] && { echo "FAIL: a refused line wrote strip.png"; fails=$((fails + 1)); }
printf '{"format": "squama-body-line/1", "width": 30,\n "stretches": [[[10, 10]]]}\n' >"$TMP/one.json"
run score "$TMP/p.jpg" --line "$TMP/one.json" "$SRC/presets/thesis/table_4_4_spots.json"
check "score --line of one point" 1 err "$TMP/one.json: stretches[0]"
run fit "$TMP/p.jpg" --line "$TMP/nowhere.json" -o "$TMP/fl" --evals 100; check "fit --line missing" 1 err "$TMP/nowhere.json"
run prepare "$TMP/p.jpg" -o "$TMP/prepm" --line; check "prepare --line without a value" 2 err "--line needs a value"
run prepare "$TMP/p.jpg" --mask "$SRC/tests/data/orient6.jpg" -o "$TMP/prep2"
check "prepare mask of another size" 1 err "the mask is 4x8 but the photo is 320x240"
run prepare "$TMP/none.jpg" -o "$TMP/prep3"; check "prepare missing photo" 1 err "cannot open image"
mkdir -p "$TMP/afolder.jpg" "$TMP/afolder.json"
run prepare "$TMP/afolder.jpg" -o "$TMP/prep3"; check "prepare a folder" 1 err "cannot open image: it is a folder ($TMP/afolder.jpg)"
# a PNG cut short: one line that names it, not libpng's own line before it as well
head -c 300 "$TMP/p_mask.png" >"$TMP/cut.png"
# (OpenImageIO leaks its error string there; lsan.supp names it in the full stack)
ASAN_OPTIONS=fast_unwind_on_malloc=0:detect_leaks=1 run prepare "$TMP/p.jpg" --mask "$TMP/cut.png" -o "$TMP/prep3"
check "prepare a mask cut short" 1 err "corrupt or truncated image: " err "($TMP/cut.png)"
! grep -q "LeakSanitizer" "$err" || { echo "FAIL: a PNG cut short leaked:"; cat "$err"; fails=$((fails + 1)); }
! grep -q "libpng error" "$err" || { echo "FAIL: a PNG cut short printed libpng's line too:"; cat "$err"; fails=$((fails + 1)); }
head -c 3000 "$TMP/p.jpg" >"$TMP/cut.jpg" # named once, though the JPEG reader's message names it too
run prepare "$TMP/cut.jpg" -o "$TMP/prep3"; check "prepare a photo cut short" 1 err "corrupt or truncated image: JPEG error: "
[ "$(grep -o "$TMP/cut.jpg" "$err" | wc -l)" = 1 ] || { echo "FAIL: a JPEG cut short named more than once:"; cat "$err"; fails=$((fails + 1)); }
run presets validate "$TMP/afolder.json"; check "validate a folder" 1 err "cannot read preset: Is a directory"
printf '{"format": "squama-preset/1", "Seed": 2147483648}' >"$TMP/seed.json"
run presets validate "$TMP/seed.json"; check "an integer out of range, printed whole" 1 err '"Seed" is 2147483648, outside its range [0, 2147483647]'
run score "$TMP/p.jpg"; check "score without presets" 2 err "give a PHOTO and at least one PRESET"
run score "$TMP/p.jpg" --mask "$TMP/p_mask.png" "$SRC/presets/thesis/table_4_4_spots.json" "$SRC/presets/thesis/table_4_2_micrurus_altirostris.json"
check "score table" 0 out "palette histogram     shape     along    across  preset" out "table_4_4_spots.json"
run score "$TMP/p.jpg" --mask "$TMP/p_mask.png" --json "$SRC/presets/thesis/table_4_4_spots.json" "$SRC/presets/thesis/table_4_3_longitudinal.json"
check "score --json" 0 out '"rank": 0'
if command -v python3 >/dev/null; then
  python3 - "$out" <<'PY' || { echo "FAIL: score --json content"; fails=$((fails + 1)); }
import json, sys
rows = json.load(open(sys.argv[1]))
assert [r["preset"].split("/")[-1] for r in rows] == ["table_4_4_spots.json", "table_4_3_longitudinal.json"]
assert set(rows[0]["objectives"]) == {"palette", "histogram", "shape", "along", "across"}
assert rows[0]["rank"] == 0 and rows[0]["view_scale"] > 0
PY
fi
run score "$TMP/p.jpg" --mask "$TMP/p_mask.png" "$TMP/typo.json"; check "score bad preset" 1 err "unknown key"
run score "$TMP/p.jpg" --mask "$TMP/p_mask.png" --view 1.5 "$SRC/presets/thesis/table_4_4_spots.json"
check "score --view" 0 out "   1.50 "
run score "$TMP/p.jpg" --view 0 "$SRC/presets/thesis/table_4_4_spots.json"; check "score --view 0" 2 err "--view must be 0.05 to 64"
run score "$TMP/p.jpg" --view inf "$SRC/presets/thesis/table_4_4_spots.json"; check "score --view inf" 2 err "--view must be 0.05 to 64, got 'inf'"
run score "$TMP/p.jpg" --size 99999999999999999999 "$SRC/presets/thesis/table_4_4_spots.json"; check "score --size overflow" 2 err "--size must be 64 to 2048, got '99999999999999999999'"
# no way in through an int's wrap-around (4294967808 was read as 512)
run prepare "$TMP/p.jpg" -o "$TMP/prepx" --work-size 4294967808; check "prepare --work-size past int" 2 err "--work-size must be 128 to 8192, got '4294967808'"


# fit (on the same photo, with a small evaluation budget)
run fit --help;           check "fit --help" 0 out "usage: squama fit" out "report.html"
run fit "$TMP/p.jpg" --mask "$TMP/p_mask.png"; check "fit without -o" 2 err "say where the results go"
run fit "$TMP/p.jpg" -o "$TMP/fx" --budget soon; check "fit bad budget" 2 err "--budget"
run fit "$TMP/p.jpg" -o "$TMP/fx" --budget 99999999999999999999; check "fit budget past a week" 2 err "(a week at most), got '99999999999999999999'"
run fit "$TMP/p.jpg" -o "$TMP/fx" --method simplex; check "fit bad method" 2 err "simplex"
run fit "$TMP/p.jpg" -o "$TMP/fx" --seed ""; check "fit empty --seed" 2 err "--seed must be 0 to 2147483647, got ''"
run fit "$TMP/p.jpg" -o "$TMP/fx" --categories spots,stripes; check "fit bad kind" 2 err "layered, or all; got 'stripes'"
run fit "$TMP/none.jpg" -o "$TMP/fx" --evals 100; check "fit missing photo" 1 err "cannot open image"
run fit "$TMP/p.jpg" -o "$TMP/fx" --start "$TMP/nowhere.json"; check "fit --start missing" 1 err "no such starting preset or folder ($TMP/nowhere.json)"
run fit "$TMP/p.jpg" -o "$TMP/fx" --start "$SRC/presets/complex/viper_zigzag.json"
check "fit --start it cannot search" 1 err "the fit cannot start from this preset: no layered genome" err "viper_zigzag.json)"
printf '{"Pattern_Type": "spots",\n "Spots_Tilling": 3}\n' > "$TMP/typo.json"
run fit "$TMP/p.jpg" -o "$TMP/fx" --start "$SRC/presets/complex" --start "$TMP/typo.json"; check "fit --start malformed" 1 err "$TMP/typo.json:2"
run fit "$TMP/p.jpg" -o "$TMP/fx" --start "$TMP/typo.json" --no-starts; check "fit --start --no-starts" 2 err "contradict"
[ -e "$TMP/fx" ] && { echo "FAIL: a fit refused for its starts made its output folder"; fails=$((fails + 1)); }
[ -e "$TMP/fx/best.json" ] && { echo "FAIL: a failed fit wrote best.json"; fails=$((fails + 1)); }
# started from one complex preset and the layered folder (not fitted by default): the
# default starts, all the shipped complex ones, cost a sanitized run half as much again
run fit "$TMP/p.jpg" --mask "$TMP/p_mask.png" -o "$TMP/fit" --evals 300 --size 64 -j 2 \
  --start "$SRC/presets/complex/cheetah.json" --start "$SRC/presets/layered"
check "fit" 0 out "evaluations" out "report: $TMP/fit/report.html"
for f in best.json fit.json front/00.json basecolor.png height.png roughness.png normal.png \
         preview.png photo.jpg mask.png strip.png fitted_strip.png line.json line.png report.html \
         kinds.png kinds/none.json checkpoint/checkpoint.json; do
  [ -s "$TMP/fit/$f" ] || { echo "FAIL: fit did not write $f"; fails=$((fails + 1)); }
done
run render "$TMP/fit/best.json" -o "$TMP/fit/r" --size 32; check "render the fitted preset" 0
run render "$TMP/fit/kinds/none.json" -o "$TMP/fit/r" --size 32; check "render a kind's best" 0
if command -v python3 >/dev/null; then
  python3 - "$TMP/fit/fit.json" "$TMP/fit/report.html" <<'PY' || { echo "FAIL: fit.json content"; fails=$((fails + 1)); }
import json, os, sys
f = json.load(open(sys.argv[1]))
assert f["format"] == "squama-fit/1", f["format"]
assert set(f["objectives"]) == {"palette", "histogram", "shape", "along", "across"}
s = f["search"]
assert s["evaluations"] <= 300 and s["seed"] == 1 and f["view_scale"] > 0
# an evaluation budget alone: no time budget; the command's time in three parts
t = s["seconds"]
assert s["budget_s"] == 0 and s["search_budget_s"] == 0, s
assert all(t[x] >= 0 for x in ("prepare", "search", "outputs")), t
assert abs(t["prepare"] + t["search"] + t["outputs"] - t["total"]) < 1e-6, t
assert t["search"] >= sum(t[x] for x in ("screen", "evolve", "rescore", "layer", "polish", "recolour")), t
# the checkpoint's time, which a resume takes off its budget, counts the preparation
c = json.load(open(os.path.join(os.path.dirname(sys.argv[1]), "checkpoint", "checkpoint.json")))
assert t["prepare"] <= c["seconds"] <= t["prepare"] + t["search"], (c["seconds"], t)
assert f["category"] in f["category_scores"]
# picked again after the recolouring: the first pick named, and whether another kind leads now
assert f["first_pick"] in f["category_scores"] and f["repicked"] == (f["first_pick"] != f["category"]), f["first_pick"]
# the starts: a file, and a folder's presets; those of kinds fitted screened (layered is not by default)
st = s["starts"]
assert st["presets"][0].endswith("/complex/cheetah.json") and len(st["presets"]) > 1, st
assert all("/layered/" in x and os.path.isfile(x) for x in st["presets"][1:]), st
assert st["screened"] == 1, st
# each kind's best as a preset; the chosen kind's is best.json, the others' the scores compared
import os, struct
here = os.path.dirname(sys.argv[1])
k = f["kinds"]
assert set(f["category_scores"]) - {"layered"} <= set(k) <= set(f["category_scores"]) | {f["category"]}, (k, f["category_scores"])
def params(path):
    d = json.load(open(os.path.join(here, path)))
    return {x: v for x, v in d.items() if x not in ("name", "notes")}
assert [x for x in k] == sorted(k, key=lambda x: k[x]["rank"]) and k[f["category"]]["rank"] == 0, k
assert [k[x]["rank"] for x in k] == list(range(len(k))), k  # listed as offered: by score after the first
assert all(k[a]["score"] <= k[b]["score"] for a, b in zip(list(k)[1:], list(k)[2:])), k
for kind, e in k.items():
    assert e["preset"] == "kinds/%s.json" % kind and e["view_scale"] > 0, e
    assert set(e["objectives"]) == set(f["objectives"])
    if kind == f["category"]:
        assert e["score"] == f["score"] and params(e["preset"]) == params("best.json"), kind
        assert isinstance(e["recoloured"], bool), kind  # best.json recoloured too
    else:  # the pick's score, or a front member's after the polish (a recoloured one below it)
        assert e["score"] <= f["category_scores"][kind], (kind, e["score"])
        assert isinstance(e["recoloured"], bool) and (not e["recoloured"] or e["score"] < f["category_scores"][kind]), e
        assert all(e["score"] <= x["score"] for x in f["front"] if x["category"] == kind), kind
# the kinds' recolouring, beyond an evaluation budget: each kind tried once, best.json's too (4 renders, and
# the re-scoring of the better ones over 4 seeds)
assert len(k) * 4 <= s["recolour_evaluations"] <= len(k) * 8 and s["seconds"]["recolour"] >= 0, s
rc = f["recolour"]  # best.json's own: kept exactly when its recoloured way scored better, and then it is best.json
assert rc["score_before"] > 0 and rc["kept"] == k[f["category"]]["recoloured"], rc
assert not rc["kept"] or (rc["score_after"] == f["score"] < rc["score_before"]), (rc, f["score"])
assert rc["kept"] or f["score"] == rc["score_before"], (rc, f["score"])
assert f["front"][0]["score"] == f["score"] and f["front"][0]["category"] == f["category"], f["front"][0]
png = open(os.path.join(here, "kinds.png"), "rb").read(24)  # a row for the photo and each kind
assert png[:8] == b"\x89PNG\r\n\x1a\n" and struct.unpack(">I", png[20:24])[0] == 20 + (1 + len(k)) * 72 - 8
d = f["drops"]  # the niches dropped, in order, none of them a survivor
assert all(x["category"] in f["niches"] and x["judged"] > 0 for x in d), d
assert [x["evaluations"] for x in d] == sorted(x["evaluations"] for x in d), d
html = open(sys.argv[2]).read()
assert html.count("<svg") >= 2 and "fitted_strip.png" in html and "preview.png" in html and "at the fitted view scale" in html
assert "line.png" in html
assert "s of search (" in html and "the photo read and prepared" in html and "the outputs written" in html
assert "kinds.png" in html and all("kinds/%s.json" % x in html for x in k)
# the convergence plot: a dot for each generation's best, in its kind (the niches' and the layer's)
h = f["history"]
g = [x for x in h if "generation_best" in x]
assert g and all(x["stage"] in ("evolve", "layer") and x["generation_best"] >= x["best_score"] for x in g), g[:3]
assert all(x["category"] in f["niches"] or x["stage"] == "layer" for x in g), g
assert all("category" not in x for x in h if x["stage"] not in ("evolve", "layer")), h
assert html.count("a generation's best") == len(g), (html.count("a generation's best"), len(g))
assert "layer" in s["seconds"]
l = f.get("layer_search")  # a layer over the champion, when the budget left room for it
if l is not None:
    assert l["layer"] != l["base"] and l["evaluations"] > 0, l
    better = l["score"] * 1.2 < l["champion_score"]
    assert ("visibility" in l) == better, l  # measured only past the 20%
    assert l["leads"] == (better and l["visibility"] >= 0.05), l
    assert isinstance(l["kind_best"], bool) and (l["kind_best"] or not l["leads"]), l  # the layer that led is its kind's best
    assert "A layer of " + l["layer"] in html
PY
fi
[ -s "$TMP/fit/line.json" ] || { echo "FAIL: fit did not write line.json"; fails=$((fails + 1)); }
# fitted again into the same folder with fewer kinds: no preset of the first fit's is left
cp -r "$TMP/fit" "$TMP/fit2"
run fit "$TMP/p.jpg" --mask "$TMP/p_mask.png" -o "$TMP/fit2" --evals 100 --size 64 -j 2 -q --categories none,spots
check "fit again, fewer kinds" 0
if command -v python3 >/dev/null; then
  python3 - "$TMP/fit2" <<'PY' || { echo "FAIL: a refit left the first fit's presets"; fails=$((fails + 1)); }
import json, os, sys
d = sys.argv[1]
f = json.load(open(d + "/fit.json"))
assert sorted(os.listdir(d + "/kinds")) == sorted(x + ".json" for x in f["kinds"]), os.listdir(d + "/kinds")
assert set(f["kinds"]) <= {"none", "spots"}, f["kinds"]
assert sorted(os.listdir(d + "/front")) == ["%02d.json" % i for i in range(len(f["front"]))], os.listdir(d + "/front")
PY
fi
# the outputs are a set. One the fit cannot write (a folder where report.html goes, the
# last to move in) leaves the earlier fit's whole; so does a full disk (a file size limit
# of 8 KiB); a SIGTERM while they move in (strace sends it as best.json is set aside)
# waits until all are in. Nothing temporary is left.
run fit "$TMP/p.jpg" --mask "$TMP/p_mask.png" -o "$TMP/fnew" --evals 100 --size 64 -j 2 -q --seed 5 --categories none,spots --work-size 256
check "fit, seed 5" 0
cmp -s "$TMP/fnew/best.json" "$TMP/fit/best.json" && { echo "FAIL: fits of seeds 1 and 5 gave one best.json"; fails=$((fails + 1)); }
fit_set() { # description, folder, expected: old or new
  local f want
  want=$TMP/$([ "$3" = old ] && echo fit || echo fnew)
  for f in best.json front/00.json basecolor.png normal.png kinds.png strip.png; do
    cmp -s "$2/$f" "$want/$f" || { echo "FAIL: $1: $f is not the $3 one"; fails=$((fails + 1)); }
  done
  [ "$(cd "$2" && ls kinds front)" = "$(cd "$want" && ls kinds front)" ] ||
    { echo "FAIL: $1: kinds/ and front/ are not the $3 ones"; fails=$((fails + 1)); }
  [ "$(ls -A "$2" | grep -c '^\.')" = 0 ] || { echo "FAIL: $1 left: $(ls -A "$2")"; fails=$((fails + 1)); }
}
cp -r "$TMP/fit" "$TMP/fset" && rm "$TMP/fset/report.html" && mkdir "$TMP/fset/report.html"
run fit "$TMP/p.jpg" --mask "$TMP/p_mask.png" -o "$TMP/fset" --evals 100 --size 64 -j 2 -q --seed 5 --categories none,spots --work-size 256
check "fit into a set it cannot finish" 1 err "a folder is where the output goes; no output was written ($TMP/fset/report.html)"
fit_set "a fit into a set it cannot finish" "$TMP/fset" old
cp -r "$TMP/fit" "$TMP/ffull"
(ulimit -f 8; "$SQ" fit "$TMP/p.jpg" --mask "$TMP/p_mask.png" -o "$TMP/ffull" --evals 100 --size 64 -j 2 -q --seed 5 --categories none,spots --work-size 256 \
   >"$out" 2>"$err"; echo $? >"$TMP/rc")
check "fit onto a full disk" 1 err "(is the disk full?) ($TMP/ffull/"
fit_set "a fit onto a full disk" "$TMP/ffull" old
if command -v strace >/dev/null && strace -o /dev/null true 2>/dev/null; then
  cp -r "$TMP/fit" "$TMP/fterm"
  ASAN_OPTIONS="${ASAN_OPTIONS:+$ASAN_OPTIONS:}detect_leaks=0" strace -o /dev/null -P "$TMP/fterm/best.json" \
    -e trace=rename -e inject=rename:signal=SIGTERM:when=1 \
    "$SQ" fit "$TMP/p.jpg" --mask "$TMP/p_mask.png" -o "$TMP/fterm" --evals 100 --size 64 -j 2 -q --seed 5 --categories none,spots --work-size 256 >/dev/null 2>&1
  rc=$?
  [ $rc = 143 ] || { echo "FAIL: a fit stopped as its outputs move in: exit $rc, not 143"; fails=$((fails + 1)); }
  fit_set "a fit stopped as its outputs move in" "$TMP/fterm" new
  # the same sent from outside (kill), which lands on any of the fit's threads: strace
  # holds the setting aside of best.json for 1.5 s, and the signal comes meanwhile
  rm -rf "$TMP/fterm" && cp -r "$TMP/fit" "$TMP/fterm"
  ASAN_OPTIONS="${ASAN_OPTIONS:+$ASAN_OPTIONS:}detect_leaks=0" strace -f -o /dev/null -P "$TMP/fterm/best.json" \
    -e trace=rename -e inject=rename:delay_exit=1500000 \
    "$SQ" fit "$TMP/p.jpg" --mask "$TMP/p_mask.png" -o "$TMP/fterm" --evals 100 --size 64 -j 2 -q --seed 5 --categories none,spots --work-size 256 >/dev/null 2>&1 &
  sp=$!
  for i in $(seq 1200); do ls "$TMP"/fterm/.fit.tmp-*/old-best.json >/dev/null 2>&1 && break; sleep 0.05; done
  pkill -TERM -P $sp
  wait $sp; rc=$?
  [ $rc = 143 ] || { echo "FAIL: a fit killed as its outputs move in: exit $rc, not 143"; fails=$((fails + 1)); }
  fit_set "a fit killed as its outputs move in" "$TMP/fterm" new
else
  echo "skipped: the interrupted fit (needs strace)"
fi
run fit "$TMP/p.jpg" --line "$TMP/fit/line.json" -o "$TMP/fitl" --evals 100 --size 64 -j 2 -q --categories none
check "fit --line" 0
[ -e "$TMP/fitl/line.json" ] && { echo "FAIL: fit --line wrote line.json"; fails=$((fails + 1)); }
grep -q '"mask_source": "line"' "$TMP/fitl/fit.json" && grep -q "\"line\": \"$TMP/fit/line.json\"" "$TMP/fitl/fit.json" ||
  { echo "FAIL: fit.json does not name the line"; fails=$((fails + 1)); }
if command -v python3 >/dev/null; then # the default starts: the shipped presets the fit can search, none of a kind fitted here
  python3 - "$TMP/fitl/fit.json" <<'PY' || { echo "FAIL: the default starts"; fails=$((fails + 1)); }
import json, os, sys
st = json.load(open(sys.argv[1]))["search"]["starts"]
names = [os.path.relpath(x, os.path.dirname(os.path.dirname(x))) for x in st["presets"]]
assert "complex/cheetah.json" in names and "layered/garter_snake.json" in names, names
assert "complex/viper_zigzag.json" not in names, names  # a layer over reaction-diffusion: not searched
assert st["screened"] == 0, st
PY
fi
# a line given into a folder with an earlier automatic line.json: that one goes (it is not
# the line followed), the report says the line was given; the folder's own line.json given
# back stays as it is
cp -r "$TMP/fit" "$TMP/fitl2" && cp -r "$TMP/fit" "$TMP/fitl3"
run fit "$TMP/p.jpg" --line "$TMP/fit/line.json" -o "$TMP/fitl2" --evals 100 --size 64 -j 2 -q --categories none
check "fit --line over an earlier fit" 0
[ -e "$TMP/fitl2/line.json" ] && { echo "FAIL: a stale line.json left beside the line followed"; fails=$((fails + 1)); }
grep -q "the body line given" "$TMP/fitl2/report.html" || { echo "FAIL: report does not say the line was given"; fails=$((fails + 1)); }
run fit "$TMP/p.jpg" --line "$TMP/fitl3/line.json" -o "$TMP/fitl3" --evals 100 --size 64 -j 2 -q --categories none
check "fit --line DIR/line.json -o DIR" 0
cmp -s "$TMP/fit/line.json" "$TMP/fitl3/line.json" || { echo "FAIL: the line given was changed"; fails=$((fails + 1)); }
# the photo fitted is the folder's photo.jpg: not written over; mask.png at the photo's
# size (prepared at 256 px here), so it goes back with --mask
mkdir -p "$TMP/ow" && cp "$TMP/p.jpg" "$TMP/ow/photo.jpg"
run fit "$TMP/ow/photo.jpg" -o "$TMP/ow" --evals 100 --size 64 -j 2 -q --work-size 256 --categories none
check "fit DIR/photo.jpg -o DIR" 0
cmp -s "$TMP/p.jpg" "$TMP/ow/photo.jpg" || { echo "FAIL: fit wrote over the photo it fitted"; fails=$((fails + 1)); }
run prepare "$TMP/p.jpg" --mask "$TMP/ow/mask.png" -o "$TMP/owp"
check "a fit's mask.png given back" 0 out "given mask"
cp "$TMP/p.jpg" "$TMP/ow/preview.png"
run fit "$TMP/ow/preview.png" -o "$TMP/ow" --evals 100 --size 64 -j 2 -q --categories none
check "fit of a photo it would write over" 1 err "the fit writes preview.png over it: give another -o"
cmp -s "$TMP/p.jpg" "$TMP/ow/preview.png" || { echo "FAIL: fit wrote over the photo it was given"; fails=$((fails + 1)); }
# refused runs leave no folder they made (and keep one that was there)
run fit "$TMP/none.jpg" -o "$TMP/gone/fit" --evals 100; check "fit refused" 1 err "cannot open image"
run prepare "$TMP/none.jpg" -o "$TMP/gone/prep"; check "prepare refused" 1 err "cannot open image"
run score "$TMP/none.jpg" --debug "$TMP/gone/dbg" "$SRC/presets/thesis/table_4_4_spots.json"; check "score refused" 1 err "cannot open image"
run batch --merge "$TMP/nowhere" -o "$TMP/gone/merged"; check "merge refused" 1 err "cannot read the batch folder"
[ -e "$TMP/gone" ] && { echo "FAIL: a refused run left a folder"; ls -R "$TMP/gone"; fails=$((fails + 1)); }
mkdir -p "$TMP/kept"
run prepare "$TMP/none.jpg" -o "$TMP/kept"; check "prepare refused into a folder of yours" 1 err "cannot open image"
[ -d "$TMP/kept" ] || { echo "FAIL: a refused run removed a folder it did not make"; fails=$((fails + 1)); }
run fit "$TMP/p.jpg" --mask "$TMP/p_mask.png" -o "$TMP/fitj" --evals 200 --size 64 -j 2 --json --categories none,spots
check "fit --json" 0 out '"stage"'
if command -v python3 >/dev/null; then
  python3 - "$out" <<'PY' || { echo "FAIL: fit --json lines"; fails=$((fails + 1)); }
import json, sys
lines = [json.loads(l) for l in open(sys.argv[1]) if l.strip()]
assert len(lines) >= 3 and all("evaluations" in l for l in lines[:-1]), lines[:2]
assert "best" in lines[-1] and lines[-1]["best"].endswith("best.json"), lines[-1]
# a niche's generation says what it scored itself, beside the best so far; the other stages do not
gens = [l for l in lines[:-1] if l["stage"] == "evolve"]
assert gens and all(l["generation_best"] >= l["best_score"] for l in gens), gens[:2]
assert all("generation_best" not in l for l in lines[:-1] if l["stage"] not in ("evolve", "layer")), lines
PY
fi
# (two kinds resumed: every kind's presets in the checkpoint are read, two searched on)
run fit "$TMP/p.jpg" --mask "$TMP/p_mask.png" -o "$TMP/fitr" --evals 200 --size 64 -j 2 --resume "$TMP/fit" -q --categories none,spots
check "fit --resume" 0
[ -s "$TMP/fitr/best.json" ] && [ ! -s "$out" ] || { echo "FAIL: resumed quiet fit"; fails=$((fails + 1)); }
# an evaluation budget is charged for the evaluations the checkpoint spent, as a time budget is
run fit "$TMP/p.jpg" --mask "$TMP/p_mask.png" -o "$TMP/fitr4" --evals 400 --size 64 -j 2 --resume "$TMP/fit" --categories none,spots
check "fit --resume --evals" 0 err "resuming from $TMP/fit: "
if command -v python3 >/dev/null; then
  python3 - "$TMP/fit" "$TMP/fitr4" "$err" <<'PY' || { echo "FAIL: fit --resume charged the checkpoint's evaluations"; fails=$((fails + 1)); }
import json, sys
spent = json.load(open(sys.argv[1] + "/checkpoint/checkpoint.json"))["evaluations"]
fit = json.load(open(sys.argv[2] + "/fit.json"))["search"]
again = json.load(open(sys.argv[2] + "/checkpoint/checkpoint.json"))["evaluations"]
assert 0 < spent <= 300, spent  # the fit's own --evals; the resume has 400 less that left
assert fit["max_evaluations"] == 400 - spent, (fit["max_evaluations"], spent)
assert fit["resumed"]["evaluations"] == spent, fit["resumed"]
assert spent < again <= spent + fit["evaluations"], (spent, again, fit["evaluations"])
err = open(sys.argv[3]).read()
assert ("%d evaluations spent; %d evaluations left" % (spent, 400 - spent)) in err
# the checkpoint's presets of the two kinds go on (some of the front is of them)
import re
assert int(re.search(r"resuming from .*?: (\d+) presets", err).group(1)) > 0, err
PY
fi
sed 's/"evaluations": [0-9]*/"evaluations": -3/' "$TMP/fit/checkpoint/checkpoint.json" >"$TMP/negev.json"
mkdir -p "$TMP/negev/checkpoint" && cp "$TMP/fit/checkpoint/"*.json "$TMP/negev/checkpoint/" && mv "$TMP/negev.json" "$TMP/negev/checkpoint/checkpoint.json"
run fit "$TMP/p.jpg" -o "$TMP/fitr5" --evals 100 --resume "$TMP/negev"; check "fit --resume negative evaluations" 1 err "evaluations >= 0"
run fit "$TMP/p.jpg" -o "$TMP/fitr2" --evals 100 --resume "$TMP/nowhere"; check "fit --resume missing" 1 err "$TMP/nowhere"
mkdir -p "$TMP/cut/checkpoint" && head -c 60 "$TMP/fit/checkpoint/checkpoint.json" >"$TMP/cut/checkpoint/checkpoint.json"
run fit "$TMP/p.jpg" -o "$TMP/fitr3" --evals 100 --resume "$TMP/cut"; check "fit --resume cut short" 1 err "malformed JSON at the end of the text (unfinished?)" err "$TMP/cut/checkpoint/checkpoint.json:"
# a time budget is the whole command's: the search gets it less the photo's preparation and
# a reserve for the outputs (1 s, and 2 s times the maps' side over 1024 squared), at least a
# quarter of it, and says so when that leaves it less than half
run fit "$TMP/p.jpg" --mask "$TMP/p_mask.png" -o "$TMP/fitb" --budget 4s --size 64 -j 2 --categories none,spots
check "fit --budget" 0
run fit "$TMP/p.jpg" --mask "$TMP/p_mask.png" -o "$TMP/fitb1" --budget 1s --size 64 -j 2 --categories none,spots
check "fit --budget 1s" 0 err "leave the search 0.25 s of the 1.0 s budget"
if command -v python3 >/dev/null; then
  python3 - "$TMP/fitb/fit.json" "$TMP/fitb1/fit.json" <<'PY' || { echo "FAIL: the budget's share"; fails=$((fails + 1)); }
import json, sys
for path, budget in zip(sys.argv[1:], (4, 1)):
    s = json.load(open(path))["search"]
    t = s["seconds"]
    share = max(0.25 * budget, budget - t["prepare"] - (1 + 2 * (64 / 1024) ** 2))
    assert s["budget_s"] == budget and abs(s["search_budget_s"] - share) < 1e-9, (s, share)
    assert s["evaluations"] > 0 and s["max_evaluations"] == 0, s
    assert abs(t["prepare"] + t["search"] + t["outputs"] - t["total"]) < 1e-6, t
PY
fi

# seed: starting presets for artists
run seed --help;          check "seed --help" 0 out "usage: squama seed" out "farthest-point"
run seed -o "$TMP/sd";    check "seed without a mode" 2 err "say what to start from"
run seed --category stripes -o "$TMP/sd"; check "seed unknown category" 2 err "--category is one of none, longitudinal"
run seed --category spots -n 0 -o "$TMP/sd"; check "seed n too small" 2 err "-n must be 1 to 256, got '0'"
run seed --category spots -n 257 -o "$TMP/sd"; check "seed n too large" 2 err "-n must be 1 to 256"
run seed --category spots;  check "seed without -o" 2 err "say where the presets go"
run seed --category spots --near "$SRC/presets/thesis/table_4_4_spots.json" -o "$TMP/sd"; check "seed two modes" 2 err "exclude each other"
run seed --near "$SRC/presets/thesis/table_4_4_spots.json" --distance 2 -o "$TMP/sd"; check "seed distance out of range" 2 err "--distance must be 0.01 to 1, got '2'"
run seed --category spots --distance 0.2 -o "$TMP/sd"; check "seed distance without --near" 2 err "--distance is for --near"
run seed --near "$TMP/none.json" -o "$TMP/sd"; check "seed missing preset" 1 err "cannot open preset: No such file or directory ($TMP/none.json)"
run seed --near "$TMP/typo.json" -o "$TMP/sd"; check "seed malformed preset" 1 err "unknown key \"Spots_Tilling\"" err "($TMP/typo.json:2)"
[ -e "$TMP/sd" ] && { echo "FAIL: a failed seed wrote its folder"; fails=$((fails + 1)); }
mkdir -p "$TMP/busy" && touch "$TMP/busy/keep.txt"
run seed --category spots -n 2 -o "$TMP/busy"; check "seed into a folder in use" 1 err "the output folder is not empty" err "($TMP/busy)"
[ -e "$TMP/busy/00.json" ] && { echo "FAIL: seed wrote into a folder in use"; fails=$((fails + 1)); }
run seed --category layered -n 1 --pool 8 -o "$TMP/sdl" --size 32 -j 2
check "seed --category layered" 0 out "00.json  layered"
run seed --category longitudinal -n 3 -o "$TMP/sd" --size 32 -j 2
check "seed --category" 0 out "wrote $TMP/sd: 3 presets, seeds.json, sheet.png" out "00.json  longitudinal"
for f in 00.json 01.json 02.json seeds.json sheet.png; do
  [ -s "$TMP/sd/$f" ] || { echo "FAIL: seed did not write $f"; fails=$((fails + 1)); }
done
ls "$TMP" | grep -q "sd.tmp-" && { echo "FAIL: seed left its temporary folder"; fails=$((fails + 1)); }
mkdir "$TMP/sd_mode" && want=$(stat -c %a "$TMP/sd_mode") && rmdir "$TMP/sd_mode"
[ "$(stat -c %a "$TMP/sd")" = "$want" ] || { echo "FAIL: seed's folder is mode $(stat -c %a "$TMP/sd"), not $want"; fails=$((fails + 1)); }
run render "$TMP/sd/02.json" -o "$TMP/sd_r" --size 32; check "render a seeded preset" 0 out "longitudinal pattern"
run seed --category longitudinal -n 3 -o "$TMP/sd1" --size 32 -j 1 -q
check "seed on one thread" 0
[ -s "$out" ] && { echo "FAIL: seed -q printed"; fails=$((fails + 1)); }
for f in 00.json 01.json 02.json seeds.json; do
  cmp -s "$TMP/sd/$f" "$TMP/sd1/$f" || { echo "FAIL: seed $f differs between 2 threads and 1"; fails=$((fails + 1)); }
done
run seed --near "$SRC/presets/thesis/table_4_4_spots.json" -n 2 --distance 0.1 -o "$TMP/nested/sdn" --size 32 --json
check "seed --near --json" 0 out '"mode": "near"'
for f in 00.json 01.json seeds.json sheet.png; do
  [ -s "$TMP/nested/sdn/$f" ] || { echo "FAIL: seed --near did not write $f"; fails=$((fails + 1)); }
done
if command -v python3 >/dev/null; then
  python3 - "$TMP/sd/seeds.json" "$out" "$TMP/nested/sdn/00.json" <<'PY' || { echo "FAIL: seeds.json content"; fails=$((fails + 1)); }
import json, sys
s = json.load(open(sys.argv[1]))
assert s["format"] == "squama-seeds/1" and s["mode"] == "category" and s["category"] == "longitudinal"
assert [p["preset"] for p in s["presets"]] == ["00.json", "01.json", "02.json"]
assert all(p["category"] == "longitudinal" and p["nearest"] > 0 and 0 < p["coverage"] < 1 for p in s["presets"])
assert s["min_distance"] == min(p["nearest"] for p in s["presets"])
n = json.load(open(sys.argv[2]))
assert n["category"] == "spots" and n["gene_step"] == 0.1 and len(n["presets"]) == 2
assert all(p["to_origin"] > 0 for p in n["presets"])
v = json.load(open(sys.argv[3]))
assert v["Pattern_Type"] == "spots" and "variation 00" in v["name"] and "distance to the original" in v["notes"]
PY
fi
run seed --category spots --no-starts -o "$TMP/sd"; check "seed --no-starts without a photo" 2 err "--start and --no-starts are for --from-photo"
run seed --from-photo "$TMP/p.jpg" --start "$TMP/typo.json" --no-starts -o "$TMP/sd"; check "seed --start --no-starts" 2 err "contradict"
run seed --from-photo "$TMP/p.jpg" --start "$TMP/nowhere.json" --evals 150 -o "$TMP/sdst"
check "seed --start missing" 1 err "no such starting preset or folder ($TMP/nowhere.json)"
[ -e "$TMP/sdst" ] && { echo "FAIL: a seed refused for its starts wrote its folder"; fails=$((fails + 1)); }
run seed --from-photo "$TMP/p.jpg" --mask "$TMP/p_mask.png" --evals 150 -n 3 -o "$TMP/sdp" --size 32 -j 2 \
  --start "$SRC/presets/complex/cheetah.json"
check "seed --from-photo" 0 out "to photo" out "wrote $TMP/sdp:"
[ -s "$TMP/sdp/00.json" ] && [ -s "$TMP/sdp/sheet.png" ] || { echo "FAIL: seed --from-photo files"; fails=$((fails + 1)); }
if command -v python3 >/dev/null; then  # the champion, then other kinds' bests by score
  python3 - "$TMP/sdp/seeds.json" <<'PY' || { echo "FAIL: seed --from-photo offers"; fails=$((fails + 1)); }
import json, sys
s = json.load(open(sys.argv[1]))
p = s["presets"]
assert s["starts"]["presets"][0].endswith("/complex/cheetah.json") and len(s["starts"]["presets"]) == 1, s["starts"]
assert s["starts"]["screened"] == 1, s["starts"]  # the fit's own
assert len(p) == 3 and p[0].get("front_index") == 0, p
assert len({x["category"] for x in p}) == 3, p
assert p[1]["score"] <= p[2]["score"], p
assert all(("front_index" in x) != x.get("kind_best", False) for x in p), p
PY
fi
run seed --from-photo "$TMP/none.jpg" --evals 150 -o "$TMP/sdp2"; check "seed --from-photo missing photo" 1 err "cannot open image"
[ -e "$TMP/sdp2" ] && { echo "FAIL: a failed seed --from-photo wrote its folder"; fails=$((fails + 1)); }

[ "$fails" = 0 ] && echo "all CLI checks passed" || { echo "$fails CLI checks failed"; exit 1; }
