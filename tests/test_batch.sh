#!/usr/bin/env bash
# squama batch on synthetic photos: a malformed manifest (exit 1, nothing written), bad rows
# (listed, never stopping the batch), the catalogue and index.html, resuming after a crash,
# shards and their merge, and (PART=mpi) the MPI work queue against a local run.
# Usage: test_batch.sh SQUAMA SRC TMP [local|shard|mpi]
set -u
SQ=$1 SRC=$2 TMP=$3 PART=${4:-local}
rm -rf "$TMP" && mkdir -p "$TMP"
fails=0
out="$TMP/out" err="$TMP/err"
# a start of a kind not fitted: passed on to each row's fit and in its settings, never screened
FIT=(--evals 100 --size 64 --work-size 256 --categories transversal,longitudinal
     --start "$SRC/presets/complex/cheetah.json")

run() { "$SQ" "$@" >"$out" 2>"$err"; echo $? >"$TMP/rc"; }
fail() { echo "FAIL: $*"; fails=$((fails + 1)); }
check() { # description, expected rc, [file pattern] ...
  local what=$1 want=$2; shift 2
  local rc; rc=$(cat "$TMP/rc")
  if [ "$rc" != "$want" ]; then
    fail "$what: exit $rc, want $want"; cat "$err"; return
  fi
  while [ $# -gt 0 ]; do
    grep -qF -- "$2" "$TMP/$1" || { fail "$what: $1 lacks '$2'"; echo "--- stdout"; cat "$out"; echo "--- stderr"; cat "$err"; }
    shift 2
  done
  echo "ok: $what"
}
# the ids of catalogue.csv's rows with a status, sorted: catalogue_ids DIR [STATUS]
catalogue_ids() {
  python3 - "$1/catalogue.csv" "${2:-}" <<'PY'
import csv, sys
rows = list(csv.DictReader(open(sys.argv[1], newline="")))
print(" ".join(sorted(r["id"] for r in rows if not sys.argv[2] or r["status"] == sys.argv[2])))
PY
}

# whether a `squama fit` writing into a folder starting with $1 is running (from /proc:
# no procps on a bare machine); with a second argument, killed as well
fits_running() {
  PREFIX=$1 KILL=${2:-} python3 - <<'PY'
import glob, os, sys
for f in glob.glob("/proc/[0-9]*/cmdline"):
    try:
        a = open(f, "rb").read().split(b"\0")
    except OSError:
        continue
    if len(a) > 4 and a[1] == b"fit" and any(x.startswith(os.environ["PREFIX"].encode()) for x in a):
        if os.environ.get("KILL"):  # kill it too (a test that failed leaves nothing running)
            os.kill(int(f.split("/")[2]), 9)
        sys.exit(0)
sys.exit(1)
PY
}

# two synthetic snakes, one banded, one striped
P="$SRC/presets/thesis"
mkdir -p "$TMP/photos"
run photo "$P/table_4_1_transversal.json" -o "$TMP/photos/bands.jpg" --size 240x160 --seed 3; check "photo bands" 0
run photo "$P/table_4_3_longitudinal.json" -o "$TMP/photos/stripes.jpg" --size 240x160 --seed 3; check "photo stripes" 0

if [ "$PART" = local ]; then
  run batch --help;       check "batch --help" 0 out "usage: squama batch MANIFEST" out "--shard I/N" out "mpirun"
  run batch "$TMP/m.csv"; check "batch without -o" 2 err "say where the results go with -o DIR"
  run batch -o "$TMP/x";  check "batch without manifest" 2 err "give one MANIFEST"
  run batch "$TMP/m.csv" -o "$TMP/x" --shard 2/2; check "batch bad shard" 2 err "--shard takes I/N"
  run batch "$TMP/m.csv" -o "$TMP/x" --jobs 0; check "batch bad jobs" 2 err "--jobs must be 1 to 64"
  run batch "$TMP/m.csv" -o "$TMP/x" --evals 5; check "batch bad evals" 2 err "--evals must be"

  # malformed manifests: a clear error naming file and line, exit 1, nothing written
  run batch "$TMP/none.csv" -o "$TMP/x"; check "batch missing manifest" 1 err "($TMP/none.csv)"
  printf 'b1,photos/bands.jpg\nb2,photos/stripes.jpg\n' >"$TMP/nohead.csv"
  run batch "$TMP/nohead.csv" -o "$TMP/x"; check "manifest without header" 1 err "squama: the manifest's header has no 'id' column" err "($TMP/nohead.csv:1)"
  printf 'id,picture\nb1,photos/bands.jpg\n' >"$TMP/nophoto.csv"
  run batch "$TMP/nophoto.csv" -o "$TMP/x"; check "manifest without photo column" 1 err "no 'photo' (or 'file') column" err "($TMP/nophoto.csv:1)"
  printf 'id,photo,species\nb1,photos/bands.jpg,"Boa\nb2,photos/stripes.jpg,x\n' >"$TMP/quote.csv"
  run batch "$TMP/quote.csv" -o "$TMP/x"; check "manifest with an unterminated quote" 1 err "squama: unterminated quoted field ($TMP/quote.csv:2)"
  : >"$TMP/empty.csv"
  run batch "$TMP/empty.csv" -o "$TMP/x"; check "empty manifest" 1 err "the manifest is empty"
  [ -e "$TMP/x" ] && fail "a malformed manifest wrote $TMP/x"

  # good rows and every kind of bad row; columns in another order, aliases, quoting, CRLF
  echo "not an image" >"$TMP/photos/text.jpg"
  printf '%s\r\n' 'Species,FILE,ID,Category,mask,notes' \
    '"Banded, synthetic",photos/bands.jpg,bands,transversal,photos/bands_mask.png,"a ""quoted"" note"' \
    'Striped,photos/stripes.jpg,stripes,spots,,' \
    'Gone,photos/gone.jpg,gone,none,,' \
    'Text,photos/text.jpg,text,,,' \
    'Masked,photos/bands.jpg,badmask,,'"$SRC"'/tests/data/orient6.jpg,' \
    'Again,photos/stripes.jpg,stripes,longitudinal,,' \
    'No id,photos/bands.jpg,,,,' \
    'Slash,photos/bands.jpg,../up,,,' \
    'Odd,photos/bands.jpg,odd,zigzag,,' >"$TMP/m.csv"
  run batch "$TMP/m.csv" -o "$TMP/b" "${FIT[@]}" --json
  check "batch with bad rows" 0 out '"rows":9' out '"ok":2' out '"errors":7'
  [ "$(catalogue_ids "$TMP/b" ok)" = "bands stripes" ] || fail "ok rows: $(catalogue_ids "$TMP/b" ok)"
  python3 - "$TMP/b" <<'PY' || fail "catalogue content"
import csv, json, os, sys
d = sys.argv[1]
rows = list(csv.DictReader(open(d + "/catalogue.csv", newline="")))
assert [r["id"] for r in rows] == ["bands", "stripes", "gone", "text", "badmask", "stripes", "", "../up", "odd"], [r["id"] for r in rows]
by = {(r["id"], r["line"]): r for r in rows}
head = ["id", "species", "expected", "fitted", "score", "palette", "histogram", "shape", "along", "across",
        "preset", "status", "error", "line", "seconds", "evaluations", "strip_widths"]
assert list(rows[0]) == head, list(rows[0])
b = by["bands", "2"]
assert b["species"] == "Banded, synthetic" and b["expected"] == "transversal" and b["preset"] == "bands/best.json"
assert b["fitted"] in ("transversal", "longitudinal") and float(b["score"]) > 0 and float(b["shape"]) >= 0
errors = {r["id"] + ":" + r["line"]: r["error"] for r in rows if r["status"] == "error"}
want = {"gone:4": "cannot open image", "text:5": "text.jpg", "badmask:6": "the mask is 4x8 but the photo is 240x160",
        "stripes:7": "the id stripes is repeated (first on line 3)", ":8": "the row has no id",
        "../up:9": "cannot name a folder", "odd:10": "the expected category \"zigzag\""}
for k, w in want.items():
    assert w in errors.get(k, ""), (k, errors.get(k))
for f in ["best.json", "fit.json", "front/00.json", "basecolor.png", "height.png", "roughness.png", "normal.png",
          "preview.png", "photo.jpg", "mask.png", "strip.png", "fitted_strip.png", "report.html",
          "thumb_photo.png", "thumb_strips.png", "thumb_texture.png", "thumb_preview.png", "done.json",
          "kinds.png", "kinds/transversal.json"]:
    for row in ("bands", "stripes"):
        assert os.path.getsize(f"{d}/{row}/{f}") > 0, (row, f)
assert not [n for n in os.listdir(d) if n.startswith(".tmp-")], os.listdir(d)
html = open(d + "/index.html").read()
assert "bands/thumb_texture.png" in html and "stripes/report.html" in html and "bands/thumb_strips.png" in html
assert "expected \\ fitted" in html and "Overall:" in html and "data-f='spots'" in html and "<script>" in html
assert "http" not in html.replace("http-equiv", ""), "index.html must not load anything from the network"
assert "the mask is 4x8" in html
# a row fitted to another kind than expected links to each kind's best, and to the expected
# kind's best exactly when the fit searched that kind (spots were not: the stripes row)
for r in rows:
    if r["status"] == "ok" and r["expected"] and r["expected"] != r["fitted"]:
        kinds = json.load(open(d + "/" + r["id"] + "/fit.json"))["kinds"]
        assert "category differs, <a href='%s/kinds.png'>" % r["id"] in html, r["id"]
        assert (("%s/kinds/%s.json" % (r["id"], r["expected"])) in html) == (r["expected"] in kinds), r["id"]
assert "category differs, <a href='stripes/kinds.png'>" in html and "stripes/kinds/spots.json" not in html
for row in ("bands", "stripes"):  # the batch's --start reached each row's fit, and its settings
    st = json.load(open(f"{d}/{row}/fit.json"))["search"]["starts"]
    assert [os.path.basename(x) for x in st["presets"]] == ["cheetah.json"] and st["screened"] == 0, st
    assert " starts=1:" in json.load(open(f"{d}/{row}/done.json"))["settings"], row
PY
  grep -q '"id":"gone".*"status":"error"' "$out" || fail "no JSON line for the missing photo"
  # a merge keeps the manifest's bad rows (no folder of their own), in place and elsewhere
  cut -d, -f1,12-14 "$TMP/b/catalogue.csv" >"$TMP/b_rows.csv"
  run batch --merge "$TMP/b" -o "$TMP/bm"; check "merge with bad rows" 0 out "9 rows: 2 ok, 7 failed"
  cut -d, -f1,12-14 "$TMP/bm/catalogue.csv" | cmp -s - "$TMP/b_rows.csv" || fail "merged elsewhere: $(cut -d, -f1,12,14 "$TMP/bm/catalogue.csv")"
  run batch --merge "$TMP/b" -o "$TMP/b"; check "merge in place with bad rows" 0 out "9 rows: 2 ok, 7 failed"
  cut -d, -f1,12-14 "$TMP/b/catalogue.csv" | cmp -s - "$TMP/b_rows.csv" || fail "merged in place: $(cut -d, -f1,12,14 "$TMP/b/catalogue.csv")"

  # resume: a row killed before its rename (its folder still .tmp-); that row is fitted
  # again (and the 3 rows that failed to load are tried again), the finished one read back
  mv "$TMP/b/stripes" "$TMP/b/.tmp-stripes"
  touch -d '2001-01-01' "$TMP/b/bands/best.json"
  rm "$TMP/b/bands/thumb_strips.png" # as an older squama left it: made when read back
  run batch "$TMP/m.csv" -o "$TMP/b" "${FIT[@]}" --json
  check "batch resumed" 0 out '"fitted_now":4' out '"resumed":1'
  grep -q '"id":"stripes","line":3,"status":"ok".*"resumed":false' "$out" || fail "stripes was not fitted again"
  grep -q '"id":"bands"' "$out" && grep '"id":"bands"' "$out" | grep -q '"resumed":false' && fail "bands was fitted again"
  [ "$(stat -c %Y "$TMP/b/bands/best.json")" -lt 1000000000 ] || fail "bands/best.json was rewritten"
  [ -s "$TMP/b/bands/thumb_strips.png" ] || fail "bands read back without its strips' thumbnail"
  [ -e "$TMP/b/.tmp-stripes" ] && fail "the partial row was left behind"
  [ -s "$TMP/b/stripes/done.json" ] || fail "stripes has no done.json after the resume"
  [ "$(catalogue_ids "$TMP/b" ok)" = "bands stripes" ] || fail "resumed catalogue: $(catalogue_ids "$TMP/b" ok)"
  run batch "$TMP/m.csv" -o "$TMP/b" "${FIT[@]}"
  check "batch rerun fits only the failed rows" 0 err "2 done before, 3 to fit"
  # rows are known by their photos' contents and the fit's settings, not by the paths'
  # spelling: the manifest named relatively (its photos then resolve to relative paths)
  (cd "$TMP" && run batch m.csv -o b "${FIT[@]}")
  check "batch resumed through another spelling of the paths" 0 err "2 done before, 3 to fit"
  run photo "$P/table_4_1_transversal.json" -o "$TMP/photos/bands.jpg" --size 240x160 --seed 4
  run batch "$TMP/m.csv" -o "$TMP/b" "${FIT[@]}" --json
  check "a photo changed in place is fitted again" 0 out '"resumed":1'
  grep '"id":"bands"' "$out" | grep -q '"resumed":false' || fail "bands' new photo was not fitted"
  grep -Eq '"photo_digest": ?"[0-9a-f]{16}"' "$TMP/b/bands/done.json" || fail "done.json has no photo digest"

  # body lines: a row followed along its line, a row whose line is refused listed with
  # the line's error; the line's contents count as the mask's do
  run prepare "$TMP/photos/stripes.jpg" -o "$TMP/lp" --work-size 256; check "prepare for a body line" 0
  printf '{"format": "squama-body-line/1", "width": 20, "stretches": [[[5, 5]]]}\n' >"$TMP/photos/short.json"
  # a row along two body widths of the body: fitted, and listed as fitted on a short strip
  python3 - "$TMP/lp/line.json" "$TMP/photos/brief.json" <<'PY'
import json, sys
l = json.load(open(sys.argv[1]))
l["stretches"] = [l["stretches"][0][:5]]
json.dump(l, open(sys.argv[2], "w"))
PY
  printf 'id,photo,body_line\nlined,photos/stripes.jpg,lp/line.json\nshort,photos/stripes.jpg,photos/short.json\nbrief,photos/stripes.jpg,photos/brief.json\n' >"$TMP/l.csv"
  run batch "$TMP/l.csv" -o "$TMP/bl" "${FIT[@]}" --json
  check "batch with body lines" 0 out '"ok":2' out '"errors":1' out '"short_strips":1'
  grep -q '"mask_source": "line"' "$TMP/bl/lined/fit.json" || fail "the lined row was not followed along its line"
  grep '"id":"short"' "$out" | grep -q 'stretches\[0\]' || fail "the short line's error is not listed"
  python3 - "$TMP/bl" <<'PY' || fail "the short strip is not listed"
import csv, sys
d = sys.argv[1]
w = {r["id"]: r["strip_widths"] for r in csv.DictReader(open(d + "/catalogue.csv", newline=""))}
assert float(w["lined"]) >= 3 and 1 <= float(w["brief"]) < 3 and w["short"] == "", w
html = open(d + "/index.html").read()
assert html.count("<b>short strip</b>") == 1 and "href='brief/line.png'" in html, html
PY
  grep -Eq '"line_digest": ?"[0-9a-f]{16}"' "$TMP/bl/lined/done.json" || fail "done.json has no line digest"
  run batch "$TMP/l.csv" -o "$TMP/bl" "${FIT[@]}" --json
  check "batch with body lines resumed" 0 out '"resumed":2' out '"short_strips":1'
  sed -i 's/"width": [0-9.]*/"width": 18/' "$TMP/lp/line.json"
  run batch "$TMP/l.csv" -o "$TMP/bl" "${FIT[@]}" --json
  check "a line changed in place is fitted again" 0 out '"resumed":1'
  grep '"id":"lined"' "$out" | grep -q '"resumed":false' || fail "the changed line's row was not fitted again"

  # scripts/manifest-photos: the shared photos' manifest made a batch manifest, each row
  # with its drawn body line (refs/photo_lines) where one is drawn, and with --no-lines none
  printf 'file,species,pattern_category_guess\ncharina_bottae__jv0266.jpg,charina_bottae,none\nnone_such__x1.jpg,none_such,spots\n' >"$TMP/shared.csv"
  for v in lined no_lines; do
    python3 "$SRC/scripts/manifest-photos" "$TMP/shared.csv" -o "$TMP/mp_$v.csv" $([ $v = no_lines ] && echo --no-lines) \
      2>"$err" || { fail "manifest-photos ($v)"; cat "$err"; }
  done
  python3 - "$TMP" "$SRC" <<'PY' || fail "manifest-photos' manifests"
import csv, os, sys
t, src = sys.argv[1:]
lined = list(csv.DictReader(open(t + "/mp_lined.csv", newline="")))
assert [r["id"] for r in lined] == ["charina_bottae__jv0266", "none_such__x1"], lined
assert os.path.samefile(os.path.join(t, lined[0]["body_line"]), src + "/refs/photo_lines/charina_bottae__jv0266.json"), lined
assert lined[1]["body_line"] == "" and lined[1]["expected"] == "spots" and lined[1]["species"] == "none such", lined
bare = list(csv.DictReader(open(t + "/mp_no_lines.csv", newline="")))
assert list(bare[0]) == ["id", "photo", "expected", "species"] and len(bare) == 2, bare
PY

  # a real crash: the batch killed (SIGKILL) once its first row is done; that row is read
  # back, the one it was fitting is fitted again, nothing half-written is listed
  printf 'id,photo\n' >"$TMP/k.csv"
  for k in 1 2; do echo "k$k,photos/bands.jpg" >>"$TMP/k.csv"; done
  # every row after the first fitted for ever ($SQUAMA_FIT_PROGRAM adds a huge evaluation
  # budget, the last --evals counting), so the fit running at the kill must die with the
  # batch rather than finish
  cat >"$TMP/slow" <<EOF
#!/usr/bin/env bash
a=(); for x in "\$@"; do [ "\$x" = -- ] && [[ "\$*" != *.tmp-k1* ]] && a+=(--evals 100000000); a+=("\$x"); done
exec "$SQ" "\${a[@]}"
EOF
  chmod +x "$TMP/slow"
  SQUAMA_FIT_PROGRAM="$TMP/slow" "$SQ" batch "$TMP/k.csv" -o "$TMP/k" "${FIT[@]}" -q --jobs 1 -j 1 &
  pid=$!
  for _ in $(seq 600); do [ -e "$TMP/k/k1/done.json" ] && fits_running "$TMP/k/.tmp-k2" && break; sleep 0.1; done
  fits_running "$TMP/k/.tmp-k2" || fail "no fit was running when the batch was killed"
  kill -9 $pid 2>/dev/null; wait $pid 2>/dev/null
  for _ in $(seq 50); do fits_running "$TMP/k/.tmp-" || break; sleep 0.1; done
  fits_running "$TMP/k/.tmp-" kill && fail "a row's fit outlived the batch killed"
  [ -s "$TMP/k/k1/done.json" ] || fail "the first row was not done before the kill"
  run batch "$TMP/k.csv" -o "$TMP/k" "${FIT[@]}" --json --jobs 1 -j 1
  check "batch after kill -9" 0 out '"rows":2' out '"ok":2'
  grep '"id":"k1"' "$out" | grep -q '"resumed":true' || fail "k1 was fitted again after the kill"
  [ "$(catalogue_ids "$TMP/k" ok)" = "k1 k2" ] || fail "after the kill: $(catalogue_ids "$TMP/k" ok)"
  ls -a "$TMP/k" | grep -q '^\.tmp-' && fail "a partial row was left after the rerun"
  # the fits are spawned, and set their own death with the batch (SQUAMA_BATCH_PARENT): one
  # whose batch has gone before it got that far ends at once; a wrapper in between is no batch gone
  sh -c 'exit 0' & dead=$!; wait $dead
  SQUAMA_BATCH_PARENT=$dead "$SQ" --version >/dev/null 2>&1; rc=$?
  [ $rc = 127 ] || fail "a fit whose batch had gone went on (exit $rc, not 127)"
  SQUAMA_BATCH_PARENT=1 "$SQ" --version >/dev/null 2>&1 || fail "a fit under a wrapper of its batch did not run"

  # a fit that crashes (a library's failed assertion aborts it) costs its row, not the
  # batch: each row is fitted in a process of its own ($SQUAMA_FIT_PROGRAM stands in for
  # squama here, aborting on the striped photo); the crash is listed with the fit's last
  # words. A rerun with other settings fits every row again, the crashed one among them
  cat >"$TMP/crashy" <<EOF
#!/bin/sh
case "\$*" in *stripes.jpg*) echo "squama: Assertion 'm_valid' failed." >&2; kill -ABRT \$\$ ;; esac
exec "$SQ" "\$@"
EOF
  chmod +x "$TMP/crashy"
  printf 'id,photo\nbands,photos/bands.jpg\nstripes,photos/stripes.jpg\n' >"$TMP/c.csv"
  SQUAMA_FIT_PROGRAM="$TMP/crashy" run batch "$TMP/c.csv" -o "$TMP/c" "${FIT[@]}" --json --jobs 2 -j 1
  check "batch with a crashing fit" 0 out '"rows":2' out '"ok":1' out '"errors":1'
  grep '"id":"stripes"' "$out" | grep -q "the fit crashed (signal 6, Aborted): Assertion 'm_valid' failed." ||
    fail "the crash is not listed with its signal and message"
  [ "$(catalogue_ids "$TMP/c" ok)" = "bands" ] || fail "after the crash: $(catalogue_ids "$TMP/c" ok)"
  ls -a "$TMP/c" | grep -q '^\.tmp-' && fail "the crash left a partial row or its log"
  run batch "$TMP/c.csv" -o "$TMP/c" "${FIT[@]/100/120}" --json
  check "other settings fit every row again, the crashed one too" 0 out '"ok":2' out '"resumed":0' out '"fitted_now":2'
  for row in bands stripes; do
    grep -Eq '"settings": ?"budget=0 evals=120 ' "$TMP/c/$row/done.json" || fail "$row's done.json lacks the new settings"
  done
fi

if [ "$PART" = shard ]; then
  printf 'id,photo,expected,mask\nbands,photos/bands.jpg,transversal,photos/bands_mask.png\nstripes,photos/stripes.jpg,longitudinal,photos/stripes_mask.png\ngone,photos/gone.jpg,none,\n' >"$TMP/m.csv"
  run batch "$TMP/m.csv" -o "$TMP/s0" "${FIT[@]}" --shard 0/2 -q; check "shard 0/2" 0
  SLURM_ARRAY_TASK_ID=5 SLURM_ARRAY_TASK_MIN=4 SLURM_ARRAY_TASK_COUNT=2 run batch "$TMP/m.csv" -o "$TMP/s1" "${FIT[@]}"
  check "shard 1/2 from Slurm's variables" 0 err "1 rows in this shard: 0 done before, 1 to fit"
  [ "$(ls "$TMP/s0" | grep -v '\.' | tr '\n' ' ')" = "bands gone " ] || fail "shard 0 fitted: $(ls "$TMP/s0")"
  [ "$(ls "$TMP/s1" | grep -v '\.' | tr '\n' ' ')" = "stripes " ] || fail "shard 1 fitted: $(ls "$TMP/s1")"
  SLURM_ARRAY_TASK_ID=9 SLURM_ARRAY_TASK_COUNT=2 run batch "$TMP/m.csv" -o "$TMP/s9"
  check "Slurm task outside the array" 2 err "SLURM_ARRAY_TASK_ID 9"
  SLURM_ARRAY_TASK_ID=abc SLURM_ARRAY_TASK_COUNT=2 run batch "$TMP/m.csv" -o "$TMP/s9"
  check "Slurm task not a number" 2 err "SLURM_ARRAY_TASK_ID abc"
  run batch --merge "$TMP/s0" "$TMP/s1" -o "$TMP/merged"; check "merge two shards" 0 out "3 rows: 2 ok, 1 failed"
  [ "$(catalogue_ids "$TMP/merged" ok)" = "bands stripes" ] || fail "merged: $(catalogue_ids "$TMP/merged")"
  [ "$(catalogue_ids "$TMP/merged" error)" = "gone" ] || fail "merged failures: $(catalogue_ids "$TMP/merged" error)"
  [ -L "$TMP/merged/bands" ] && [ -s "$TMP/merged/stripes/thumb_preview.png" ] || fail "merged rows are not linked"
  grep -q "bands/thumb_photo.png" "$TMP/merged/index.html" || fail "merged index.html lacks the thumbnails"
  grep -q "different settings" "$err" && fail "shards with the same settings were said to differ"
  # a shard fitted with another budget: merged, with a warning naming both settings
  run batch "$TMP/m.csv" -o "$TMP/s1b" "${FIT[@]/100/120}" --shard 1/2 -q; check "shard 1/2 with --evals 120" 0
  run batch --merge "$TMP/s0" "$TMP/s1b" -o "$TMP/mixed"
  check "merge shards of different settings" 0 out "3 rows: 2 ok, 1 failed" err "fitted with different settings" \
    err "2 rows (bands, ...): budget=0 evals=100" err "1 row (stripes, ...): budget=0 evals=120"
  # shards sharing one folder: each lists the other's rows, failures included
  cp -r "$TMP/s1/stripes" "$TMP/s0/"
  run batch "$TMP/m.csv" -o "$TMP/s0" "${FIT[@]}" --shard 1/2; check "a shard in a shared folder" 0 err "1 done before, 0 to fit"
  [ "$(catalogue_ids "$TMP/s0")" = "bands gone stripes" ] || fail "shared folder: $(catalogue_ids "$TMP/s0")"
  run batch --merge "$TMP/s0" -o "$TMP/s0"; check "merge in place" 0 out "3 rows: 2 ok, 1 failed"
  run batch "$TMP/m.csv" -o "$TMP/s0" "${FIT[@]}"; check "whole catalogue after shards" 0 err "2 done before, 1 to fit"
  [ "$(catalogue_ids "$TMP/s0" ok)" = "bands stripes" ] || fail "shared folder: $(catalogue_ids "$TMP/s0")"
  run batch --merge "$TMP/nowhere" -o "$TMP/m2"; check "merge a missing folder" 1 err "($TMP/nowhere)"
fi

if [ "$PART" = mpi ]; then
  if ! command -v mpirun >/dev/null; then echo "mpirun absent: skipped"; exit 77; fi
  export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_rmaps_base_oversubscribe=1
  # with their masks: the queue is tested here, not the automatic mask (a best effort in
  # grass, which these 240x160 photos are not always found in)
  printf 'id,photo,expected,mask\nbands,photos/bands.jpg,transversal,photos/bands_mask.png\nstripes,photos/stripes.jpg,longitudinal,photos/stripes_mask.png\nbands2,photos/bands.jpg,transversal,photos/bands_mask.png\n' >"$TMP/m.csv"
  mpirun --oversubscribe -np 2 "$SQ" batch "$TMP/m.csv" -o "$TMP/mpi" "${FIT[@]}" --json >"$out" 2>"$err"
  echo $? >"$TMP/rc"
  check "mpirun -np 2 squama batch" 0 out '"fitted_now":3'
  for id in bands stripes bands2; do
    [ "$(grep -c "\"id\":\"$id\"" "$out")" = 1 ] || fail "$id was reported $(grep -c "\"id\":\"$id\"" "$out") times"
  done
  echo "rows per rank:"; grep -o '"rank":[0-9]*' "$out" | sort | uniq -c
  [ "$(grep -c '"rank":[01]' "$out")" = 3 ] || fail "the row lines do not say which of the 2 ranks fitted them"
  grep -q '"rank":1' "$out" || fail "rank 1 fitted no row: the queue handed it nothing"
  # resumed under mpirun as well: every row read back, none fitted
  mpirun --oversubscribe -np 2 "$SQ" batch "$TMP/m.csv" -o "$TMP/mpi" "${FIT[@]}" --json >"$out" 2>"$err"
  echo $? >"$TMP/rc"
  check "mpirun -np 2 squama batch, again" 0 out '"fitted_now":0' out '"resumed":3'
  # the same batch locally: a comparison of results, which the plain build alone runs (as
  # the C tests' sq_sanitized); under the sanitizers' slow unwinder it costs a third of the part
  if [ -n "${SQUAMA_SANITIZED:-}" ]; then
    echo "skipped under the sanitizers: the same batch locally (the plain build runs it)"
  else
    run batch "$TMP/m.csv" -o "$TMP/local" "${FIT[@]}" -q; check "the same batch locally" 0
    [ "$(catalogue_ids "$TMP/mpi" ok)" = "$(catalogue_ids "$TMP/local" ok)" ] ||
      fail "MPI catalogue $(catalogue_ids "$TMP/mpi" ok) differs from local $(catalogue_ids "$TMP/local" ok)"
    # an evaluation budget makes each fit depend on its seed only: the same categories
    cut -d, -f1-4 "$TMP/mpi/catalogue.csv" >"$TMP/a" && cut -d, -f1-4 "$TMP/local/catalogue.csv" >"$TMP/b"
    cmp -s "$TMP/a" "$TMP/b" || { fail "MPI and local categories differ"; diff "$TMP/a" "$TMP/b"; }
  fi
fi

[ "$fails" = 0 ] && echo "all batch checks passed" || { echo "$fails batch checks failed"; exit 1; }
