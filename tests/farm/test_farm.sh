#!/usr/bin/env bash
# houle farm without Slurm: the script it writes, its tasks run here (--local), restarts after lost
# frames and killed runs, the final check and the join of raw parts, and its errors.
# Usage: test_farm.sh <houle binary> <source dir>
set -uo pipefail
houle=$(realpath "$1") src=$(realpath "$2")
. "$(dirname "$0")/../cli/expect.sh"
cd "$work" || exit 1
ok() { pass=$((pass + 1)); }
bad() { fail=$((fail + 1)); printf 'FAIL %s\n' "$*"; }
# Lines "houle render: N frames written" of task logs, added up.
written() { cat "$@" 2>/dev/null | sed -nE 's/^houle render: ([0-9]+) frames written.*/\1/p' | awk '{ s += $1 } END { print s + 0 }'; }

# A deep sea without rays builds in milliseconds: every task builds the scene (tests/farm/test_farm_slurm.sh
# renders Plate 3).
scene=$work/deep.toml
printf '[domain]\nx_max = 100.0\ny_max = 100.0\n[floor.base]\ndepth = 300.0\n[[trains]]\nperiod = 5.0\n' >"$scene"
opts=(--size 96x54 --quality draft --threads 1)

expect help 0 'houle farm slurm .*--chunk N' "$houle" farm --help
expect help-slurm 0 '--local J +without Slurm' "$houle" farm slurm --help
expect help-status 0 'Exit code: 0 complete, 1 frames or parts missing' "$houle" farm status --help
expect help-render 0 '--skip-existing +restart a stopped run' "$houle" render --help
expect usage-lists-farm 0 'farm slurm\|status' "$houle" --help
expect unknown-sub 2 "unknown subcommand 'submit'" "$houle" farm submit
expect no-chunk 2 'farm slurm: --chunk N \(frames per array task\) is required' "$houle" farm slurm "$scene"
expect bad-chunk 2 "farm slurm: --chunk expects a count in 1..10000000, got '0'" "$houle" farm slurm --chunk 0
expect bad-frames 2 "farm slurm: --frames expects A:B" "$houle" farm slurm --chunk 5 --frames 9:3
expect render-option 2 "farm slurm: --quality expects draft, realtime or film, got 'best'" "$houle" farm slurm --chunk 5 --quality best
expect unknown-option 2 "farm slurm: unknown option '--frob' \(see houle farm slurm --help\)" "$houle" farm slurm --chunk 5 --frob
expect raw-stdout 2 'farm slurm: --raw needs a file' "$houle" farm slurm --chunk 5 --raw -
expect two-actions 2 'farm slurm: --dry-run, --submit and --local exclude each other' "$houle" farm slurm --chunk 5 --dry-run --local 2
expect sbatch-array 2 'farm slurm: --sbatch may not set --array' "$houle" farm slurm --chunk 5 --sbatch '-p x -a 1-3' --dry-run
# As houle render: an image sequence's folder is made (by the tasks), a raw file's must be there.
expect new-folder 0 'array=0-9' "$houle" farm slurm --chunk 5 --frames 0:49 --out 'nowhere/%04d.png' --dry-run
[ -e nowhere ] && { fail=$((fail + 1)); echo "FAIL new-folder: made by --dry-run"; }
touch plain-file
expect no-folder 2 'farm slurm: plain-file/x/%04d.png: plain-file is not a folder' "$houle" farm slurm --chunk 5 --out 'plain-file/x/%04d.png'
expect no-raw-folder 2 'farm slurm: nowhere/x.rgb: cannot open for writing: the folder nowhere does not exist' "$houle" farm slurm --chunk 5 --raw 'nowhere/x.rgb'
expect bad-pattern 2 'needs exactly one frame-number conversion' "$houle" farm slurm --chunk 5 --out x.png
expect bad-scene 2 'nope.toml: error: cannot read the scene file' "$houle" farm slurm nope.toml --chunk 5
expect status-args 2 'farm status: --out PATTERN or --raw PATH is required' "$houle" farm status --frames 0:9
expect status-raw-chunk 2 'farm status: --raw needs --chunk N' "$houle" farm status --frames 0:9 --raw x.rgb
expect skip-stdout 2 'render: --skip-existing needs a file' "$houle" render --skip-existing --raw -
[ -e houle-farm.sbatch ] && bad "a refused command wrote the script"

# --dry-run: the script on standard output, nothing written; it parses, and says what it does.
mkdir frames
"$houle" farm slurm "$scene" --frames 0:23 --chunk 5 --out 'frames/%04d.png' "${opts[@]}" \
  --sbatch "--time=10 --job-name='a b'" --dry-run >dry.txt 2>&1 || bad "dry run: $(cat dry.txt)"
[ -e houle-farm.sbatch ] && bad "--dry-run wrote the script"
if bash -n dry.txt && grep -qx '#SBATCH --array=0-4' dry.txt && grep -qx "#SBATCH --time=10 --job-name='a b'" dry.txt &&
   grep -qE "^exec \"\\\$houle\" render $scene --out frames/%04d.png --size 96x54 --quality draft --threads 1 --frames \"\\\$first:\\\$last\" --skip-existing$" dry.txt &&
   grep -qE '^  exec "\$houle" farm status --frames 0:23 --chunk 5 --out frames/%04d.png$' dry.txt; then
  ok
else
  bad "dry-run script:"; cat dry.txt
fi

# --local: the tasks of the script, two at a time, then the check; byte-identical to one render.
"$houle" render "$scene" --frames 0:23 --out 'ref_%04d.png' "${opts[@]}" --quiet || bad "reference render"
expect local 0 'status: frames 0:23 complete \(24 frames in frames/%04d.png\)' \
  "$houle" farm slurm "$scene" --frames 0:23 --chunk 5 --out 'frames/%04d.png' "${opts[@]}" --local 2
[ "$(written houle-farm-local_*.out)" -eq 24 ] || bad "local: $(written houle-farm-local_*.out) frames written, want 24"
same() { for n in $(seq -f %04g 0 23); do cmp -s "ref_$n.png" "frames/$n.png" || { echo "frame $n differs"; return 1; }; done; }
same && ok || bad "local frames differ from one render"

# Lost frames and temporary files of killed runs: the check lists them; the same command renders only
# those frames, removes the temporary files and leaves the complete frames untouched.
rm frames/0007.png frames/0011.png frames/0012.png
echo partial >frames/0011.png.tmp4242
echo partial >frames/0003.png.tmp4243
stat -c '%n %i %Y' frames/*.png >before.txt
expect status-missing 1 'status: 21 of 24 frames complete in frames/%04d.png; missing 3: 7, 11:12' \
  "$houle" farm status --frames 0:23 --chunk 5 --out 'frames/%04d.png'
expect status-tasks 1 'array tasks to run again: 1-2 ' "$houle" farm status --frames 0:23 --chunk 5 --out 'frames/%04d.png'
expect status-temps 1 '2 temporary files of stopped tasks' "$houle" farm status --frames 0:23 --chunk 5 --out 'frames/%04d.png'
sleep 1  # a rewritten frame would get a new mtime
expect local-again 0 'status: frames 0:23 complete' \
  "$houle" farm slurm "$scene" --frames 0:23 --chunk 5 --out 'frames/%04d.png' "${opts[@]}" --local 2
[ "$(written houle-farm-local_*.out)" -eq 3 ] || bad "restart: $(written houle-farm-local_*.out) frames written, want the 3 missing"
grep -q 'frames 0:4 already complete' houle-farm-local_0.out || bad "restart: task 0 did not skip its chunk"
stat -c '%n %i %Y' frames/*.png | grep -Fxf before.txt | cmp -s - before.txt || bad "restart: complete frames were rewritten"
ls frames | grep -q tmp && bad "restart left temporary files: $(ls frames | grep tmp)"
same && ok || bad "restarted frames differ from one render"

# A run stopped by SIGTERM (a cancelled job) ends after its current frame (exit 128 + 15); with --skip-existing a raw
# file is written whole, so none is left, and neither is its temporary file.
"$houle" render "$scene" --frames 0:99 "${opts[@]}" --realtime --fps 20 --raw stopped.rgb --skip-existing 2>stopped.txt &
pid=$!
# Once the first frame is in the temporary file, the run is in its frame loop.
until [ -s "$(ls stopped.rgb.tmp* 2>/dev/null | head -n 1)" ] || ! kill -0 $pid 2>/dev/null; do sleep 0.05; done
kill -TERM $pid
wait $pid; rc=$?
if [ $rc -eq 143 ] && grep -q 'interrupted after [0-9]* complete frames.* (not kept' stopped.txt && ! ls stopped.rgb* >/dev/null 2>&1; then
  ok
else
  bad "SIGTERM: exit $rc, $(cat stopped.txt), files: $(ls stopped.rgb* 2>&1)"
fi

# Raw: each task writes its part whole; the check joins them in order into the one file.
"$houle" render "$scene" --frames 0:23 "${opts[@]}" --raw ref.rgb --quiet || bad "reference raw render"
"$houle" farm slurm "$scene" --frames 0:23 --chunk 5 --raw clip.rgb "${opts[@]}" --script raw.sbatch >raw.txt 2>&1 ||
  bad "raw: writing the script: $(cat raw.txt)"
# The script by hand, as sbatch would run it: two tasks only, then the check finds the others missing.
for t in 1 3; do SLURM_ARRAY_TASK_ID=$t bash raw.sbatch 2>/dev/null || bad "raw: task $t"; done
expect raw-missing 1 'clip.rgb: parts missing for 14 of 24 frames: 0:4, 10:14, 20:23; array tasks to run again: 0,2,4' \
  env HOULE_FARM_STEP=status bash raw.sbatch
[ -e clip.rgb ] && bad "raw: joined with parts missing"
expect raw-local 0 'joined 5 parts \(frames 0:23\) into clip.rgb' \
  "$houle" farm slurm "$scene" --frames 0:23 --chunk 5 --raw clip.rgb "${opts[@]}" --script raw.sbatch --local 2
[ "$(written raw-local_*.out)" -eq 14 ] || bad "raw restart: $(written raw-local_*.out) frames written, want 14"
cmp -s ref.rgb clip.rgb && ok || bad "raw: joined file differs from one render"
ls clip.rgb.* >/dev/null 2>&1 && bad "raw: parts left after the join: $(ls clip.rgb.*)"
expect raw-joined 0 'clip.rgb complete \(frames 0:23, its parts joined\)' \
  "$houle" farm slurm "$scene" --frames 0:23 --chunk 5 --raw clip.rgb "${opts[@]}" --script raw.sbatch --local 2
[ "$(written raw-local_*.out)" -eq 0 ] || bad "raw: a joined file was rendered again"

echo "farm: ${pass} passed, ${fail} failed"
[ "$fail" -eq 0 ]
