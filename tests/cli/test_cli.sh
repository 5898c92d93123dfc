#!/usr/bin/env bash
# End-to-end tests of the houle command: each case runs the real binary and checks the exit code and
# the message. Usage: test_cli.sh <houle binary> <source dir>
set -uo pipefail
houle=$1 src=$2
. "$(dirname "$0")/expect.sh"
# scene <name> <toml>: writes a scene file and prints its path
scene() { printf '%s\n' "$2" >"$work/$1.toml"; echo "$work/$1.toml"; }

expect version 0 '^houle [0-9.]+ \(ISA [a-z0-9.]+; compiled: scalar' "$houle" --version
expect help 0 'usage: houle <command>' "$houle" --help
expect unknown-command 2 "unknown command 'frobnicate'" "$houle" frobnicate
expect unknown-option 2 "unknown option '--frob'" "$houle" info --frob
for f in "$src"/scenes/*.toml; do
  expect "shipped $(basename "$f")" 0 ': ok$' "$houle" validate "$f"
done
expect builtin-info 0 'trains: 3' "$houle" info
# The built-in coast and scenes/coast.toml are the same scene.
# (build time aside: it is measured)
if diff <("$houle" info | tail -n +2 | grep -v '^build time') <("$houle" info "$src/scenes/coast.toml" | tail -n +2 | grep -v '^build time') >/dev/null; then
  pass=$((pass + 1))
else
  fail=$((fail + 1)); echo "FAIL scenes/coast.toml differs from the built-in coast:"; diff <("$houle" info) <("$houle" info "$src/scenes/coast.toml")
fi

f=$(scene unknown-key '[camera]
positon = [1, 2, 3]')
expect unknown-key 2 "unknown-key.toml:2:1: error: camera.positon: unknown key" "$houle" validate "$f"
f=$(scene wrong-type '[[trains]]
period = "six"')
expect wrong-type 2 'wrong-type.toml:2:10: error: trains\[0\].period: expected a number, got a string' "$houle" validate "$f"
f=$(scene negative-period '[[trains]]
period = -3.0')
expect negative-period 2 'negative-period.toml:2:10: error: trains\[0\].period: a value in \[1, 60\] s, got -3' "$houle" validate "$f"
f=$(scene too-steep '[[trains]]
period = 4.0
amplitude = 3.0')
expect too-steep 2 'too-steep.toml:3:13: error: trains\[0\].amplitude: at most the deep-water breaking' "$houle" validate "$f"
f=$(scene camera-under-floor '[floor.base]
depth = 10.0
[camera]
position = [10.0, 10.0, -12.0]
look_at = [10.0, 50.0, 0.0]')
expect camera-under-floor 2 'camera-under-floor.toml:4:12: error: camera.position.z: a height above the sea floor' "$houle" validate "$f"
f=$(scene jetty-outside '[domain]
x_max = 100.0
y_max = 100.0
[[walls]]
points = [[200.0, 10.0], [300.0, 10.0]]')
expect jetty-outside 2 'jetty-outside.toml:5:.*walls\[0\].points\[1\]: a segment that meets the domain' "$houle" validate "$f"
f=$(scene syntax '[camera
position = 1')
expect toml-syntax 2 'syntax.toml:1:' "$houle" validate "$f"
expect missing-file 2 'nope.toml: error: cannot read the scene file' "$houle" validate "$work/nope.toml"
head -c 1100000 /dev/zero | tr '\0' '#' >"$work/huge.toml"
expect huge-file 2 'over the limit of 1048576' "$houle" validate "$work/huge.toml"
# Non-ASCII text: fine in comments and strings, refused elsewhere with its place (toml_ascii.hpp).
f=$(scene accents '# Côte sauvage, près du môle
[floor.base]
kind = "planar_béach"')
expect accents-in-string 2 'accents.toml:3:8: error: floor.base.kind: expected one of "flat", "planar_beach", got "planar_béach"' "$houle" validate "$f"
f=$(scene accents-ok '# Côte sauvage, près du môle
[sun]
elevation_deg = 20.0  # bas sur l’horizon')
expect accents-in-comment 0 ': ok$' "$houle" validate "$f"
f=$(scene accents-bare '[sun]
élévation = 20.0')
expect accents-in-key 2 'accents-bare.toml:2:1: error: a non-ASCII character outside a string or comment' "$houle" validate "$f"
printf '[sun]\nelevation_deg = 20.0 \xff\n' >"$work/bad-utf8.toml"
expect invalid-utf8 2 'bad-utf8.toml:2:22: error: invalid UTF-8' "$houle" validate "$work/bad-utf8.toml"

# Height maps from images, read through the image module (image_module.hpp).
printf 'P2\n4 3\n255\n0 64 128 255\n0 64 128 255\n0 64 128 255\n' >"$work/map.pgm"
printf 'P2\n1 1\n255\n0\n' >"$work/tiny.pgm"
hm() { scene "$1" "[domain]
x_max = 100.0
y_max = 100.0
[floor.height_map]
file = \"$2\"
cell = 30.0
[[trains]]
period = 5.0"; }
expect height-map 0 'height map' "$houle" info "$(hm height-map map.pgm)"
expect height-map-tiny 2 'height-map-tiny.toml:5:8: error: floor.height_map.file: a height map needs at least 2x2 pixels' "$houle" validate "$(hm height-map-tiny tiny.pgm)"
expect height-map-missing 2 'floor.height_map.file: height map: cannot open the image' "$houle" validate "$(hm height-map-missing nope.pgm)"
# Only regular files are read: a device or a FIFO would never end (bounded by timeout, since they hang).
mkfifo "$work/fifo.pgm"
for dev in /dev/zero /dev/urandom "$work/fifo.pgm"; do
  expect "height-map $dev" 2 'floor.height_map.file: height map: cannot open the image: not a regular file' \
    timeout 10 "$houle" validate "$(hm height-map-dev "$dev")"
done
expect scene-fifo 2 'fifo.pgm: error: cannot read the scene file: not a regular file' timeout 10 "$houle" validate "$work/fifo.pgm"
# validate prints each file's line as it is known: stopped while blocked on a later file's error
# (stderr into a pipe nobody reads), the earlier "ok" is already out.
mkfifo "$work/stalled"
exec 3<>"$work/stalled"
ok_scene=$(hm validate-ok map.pgm)
# shellcheck disable=SC2046
"$houle" validate "$ok_scene" $(for _ in $(seq 2000); do echo "$work/nope.toml"; done) >"$work/validate.out" 2>"$work/stalled" &
pid=$!
for _ in $(seq 100); do [ -s "$work/validate.out" ] && break; sleep 0.1; done  # at most 10 s
kill -KILL "$pid"
{ wait "$pid"; } 2>/dev/null
exec 3>&-
if grep -q 'validate-ok.toml: ok$' "$work/validate.out"; then pass=$((pass + 1)); else fail=$((fail + 1)); echo "FAIL validate lost the ok line of a run it did not finish"; fi

# Limits (docs/scenes.md): refused up front with what was expected, never an out-of-memory crash.
f=$(scene huge-domain '[domain]
x_max = 1000000.0')
expect limit-domain 2 'huge-domain.toml:2:9: error: domain.x_max: a side of at most 4000 m, got 1000000 m' "$houle" validate "$f"
f=$(scene many-trains "$(for i in $(seq 17); do printf '[[trains]]\nperiod = 5.0\n'; done)")
expect limit-trains 2 'many-trains.toml:1:1: error: trains: at most 16 entries, got 17' "$houle" validate "$f"
f=$(scene huge-caps '[dwt]
max_samples = 4000000000')
expect limit-samples 2 'huge-caps.toml:2:15: error: dwt.max_samples: a count in \[64, 16777216\]' "$houle" validate "$f"
# A trace that reaches a cap stops there: an error by default (the field beyond would be empty and a
# render would not say so), every command's warning with dwt.on_cap = "warn".
capped='[domain]
x_max = 100.0
y_max = 100.0
[floor.base]
kind = "planar_beach"
depth = 8.0
slope = 0.05
shoreline = [50.0, 110.0]
[[trains]]
period = 4.0
amplitude = 0.2
[dwt]
max_samples = 2000'
f=$(scene capped "$capped")
expect cap-error-probe 2 "capped.toml: dwt.on_cap: train 0's wave rays reached dwt.max_samples \(2000 samples\)" "$houle" probe "$f" --at 50,80
expect cap-error-render 2 "capped.toml: dwt.on_cap: train 0's wave rays reached dwt.max_samples" "$houle" render "$f" --frames 0:0 --size 32x18 --out "$work/capped/%04d.png"
f=$(scene capped-warn "$capped
on_cap = \"warn\"")
for cmd in "probe --at 50,80" "render --frames 0:0 --size 32x18 --out $work/capped/%04d.png" "bench --frames 1 --size 32x18"; do
  # shellcheck disable=SC2086 # the command's words
  expect "cap-warn-${cmd%% *}" 0 "houle ${cmd%% *}: .*capped-warn.toml: warning: the wave rays reached a cap" "$houle" $cmd "$f"
done
expect cap-warn-info 0 '^warning: the wave rays reached a cap' "$houle" info "$f"
# Valid (its draft build fits), but a traced train over 4 km at film quality would need tens of GiB:
# refused before the build. Sixteen of them fit no quality: validate refuses them.
huge() { scene "$1" "[domain]
x_max = 4000.0
y_max = 4000.0
[floor.base]
kind = \"planar_beach\"
depth = 30.0
shoreline = [0.0, 4000.0]
$(for i in $(seq "$2"); do printf '[[trains]]\nperiod = 8.0\n'; done)
[camera]
position = [2000.0, -20.0, 6.0]
look_at = [2000.0, 80.0, 0.0]"; }
f=$(huge huge-build 1)
expect limit-memory 2 'huge-build.toml: scene: needs an estimated [0-9]+ MiB at this quality and size .*over the limit of 4096 MiB' "$houle" render "$f" --quality film --frames 1 --raw "$work/never.rgb"
[ -e "$work/never.rgb" ] && { fail=$((fail + 1)); echo "FAIL limit-memory: opened the output"; }
expect limit-memory-validate 2 'huge-16.toml:1:1: error: scene: needs an estimated [0-9]+ MiB at the draft quality' "$houle" validate "$(huge huge-16 16)"
expect limit-size 2 'size expects WxH with each in 1..16384 and at most 64 Mpixels' "$houle" render --size 16384x16384 --frames 1 --raw "$work/never.rgb"
expect limit-size-bench 2 'size expects WxH with each in 1..16384 and at most 64 Mpixels' "$houle" bench --size 10000x10000
expect limit-frames 2 'frames expects .*at most 10000000 frames' "$houle" render --frames 0:99999999999 --raw "$work/never.rgb"
expect limit-frame-count 2 'frames expects .*at most 10000000 frames' "$houle" render --frames 20000000 --raw "$work/never.rgb"
expect limit-bench-frames 2 'frames expects a count in 1..10000000' "$houle" bench --frames 100000000
# Hard input (issue 22): messages that state the range and never contradict themselves, a byte order
# mark, a height map over the side limit, a trace likely to reach its cap warned of by validate.
f=$(scene near-one '[[trains]]
period = 4.0
steepness = 1.0000001')
expect round-trip 2 'near-one.toml:3:13: error: trains\[0\].steepness: a value in \[0, 1\], got 1.0000001$' "$houle" validate "$f"
f=$(scene int-range '[dwt]
max_rays = 5000000000')
expect int-range 2 'int-range.toml:2:12: error: dwt.max_rays: a count in \[2, 1048576\], got 5000000000$' "$houle" validate "$f"
f=$(scene initial-rays '[dwt]
initial_rays = 5000000')
expect initial-rays 2 'initial-rays.toml:2:16: error: dwt.initial_rays: a count in \[0, 1048576\], got 5000000$' "$houle" validate "$f"
f=$(scene initial-rays-cap '[dwt]
initial_rays = 40000')
expect initial-rays-cap 2 'initial-rays-cap.toml:2:16: error: dwt.initial_rays: at most dwt.max_rays = 32768, got 40000$' "$houle" validate "$f"
printf '\xef\xbb\xbf[sun]\nelevation_deg = 20.0\n' >"$work/bom.toml"
expect utf8-bom 0 'bom.toml: ok$' "$houle" validate "$work/bom.toml"
# png W H: a grey PNG image on stdout
png() { python3 -c 'import sys,zlib,struct
def chunk(t, d): return struct.pack(">I", len(d)) + t + d + struct.pack(">I", zlib.crc32(t + d))
w, h = int(sys.argv[1]), int(sys.argv[2])
raw = b"".join(b"\0" + bytes(range(256)) * (w // 256) + bytes(w % 256) for _ in range(h))
sys.stdout.buffer.write(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 8, 0, 0, 0, 0)) + chunk(b"IDAT", zlib.compress(raw)) + chunk(b"IEND", b""))' "$1" "$2"; }
png 70000 2 >"$work/wide.png"
expect height-map-wide 2 'floor.height_map.file: height map of 70000x2 pixels is over the limit of 8192x8192' "$houle" validate "$(hm height-map-wide wide.png)"
mkdir "$work/map-dir"
expect height-map-dir 2 'floor.height_map.file: height map: cannot open the image: not a regular file' "$houle" validate "$(hm height-map-dir map-dir)"
png 512 512 | head -c 200 >"$work/cut.png"
expect height-map-truncated 2 'floor.height_map.file: height map: cannot read the image: .*[a-z]' "$houle" validate "$(hm height-map-truncated cut.png)"
# lines <command...>: the number of lines the command prints, and its exit code
lines() { local out rc; out=$("$@" 2>&1); rc=$?; printf '%s lines\n' "$(printf '%s\n' "$out" | wc -l)"; return $rc; }
# The error is one line with its place: libpng's own complaints are folded into it.
expect height-map-truncated-one-line 2 '^1 lines$' lines "$houle" validate "$(hm height-map-truncated cut.png)"
printf 'P5\n64 64\n255\n0123456789' >"$work/cut.pgm"
expect height-map-truncated-pgm 2 'floor.height_map.file: height map: cannot read the image: the file ends before its last pixel' \
  "$houle" validate "$(hm height-map-truncated-pgm cut.pgm)"
f=$(scene many-samples '[domain]
x_max = 4000.0
y_max = 4000.0
[floor.base]
kind = "planar_beach"
shoreline = [0.0, 3900.0]
[[trains]]
period = 8.0
[dwt]
step = 0.05
insertion_distance = 0.05
max_rays = 1048576')
expect validate-cap-warning 0 "many-samples.toml:[0-9]+:[0-9]+: warning: dwt.max_samples: trains\[0\]'s 80001 initial rays cross the 4000 m domain in 80001 steps of dwt.step, about 6400160001 samples" "$houle" validate "$f"
# A wide frame number works up to the file system's 255 bytes a name, and beyond is blamed on the name.
expect pattern-wide 0 '1 frames written' "$houle" render --frames 0:0 --size 32x18 --quality draft --out "$work/wide/%037d.png"
[ -e "$work/wide/$(printf '%037d' 0).png" ] && pass=$((pass + 1)) || { fail=$((fail + 1)); echo "FAIL pattern-wide: no frame file"; }
expect pattern-too-wide 2 "%0300d.png: the frame number's width makes a file name of 304 bytes, over the 255" "$houle" render --frames 0:0 --out "$work/%0300d.png"
expect pattern-absurd 2 "%0999999999d.png: the frame number's width makes a file name longer than 255 bytes" "$houle" render --frames 0:0 --out "$work/%0999999999d.png"

# The scene fuzzer's finds (tests/robust/scene_regressions): each is refused by validate with its
# place, or renders and probes.
for f in "$src"/tests/robust/scene_regressions/*.toml; do
  if "$houle" validate "$f" >/dev/null 2>&1; then
    expect "regression-render $(basename "$f")" 0 '1 frames written' "$houle" render "$f" --frames 0:0 --size 48x27 --quality draft --raw "$work/regression.rgb"
    expect "regression-probe $(basename "$f")" 0 '^\(0, 0\) t=0 s: ' "$houle" probe "$f" --at 0,0
  else
    expect "regression-refused $(basename "$f")" 2 "$(basename "$f"):[0-9]+:[0-9]+: error: " "$houle" validate "$f"
  fi
done

f=$(scene bad-enum '[floor.base]
kind = "sloped"')
expect bad-enum 2 'floor.base.kind: expected one of "flat", "planar_beach", got "sloped"' "$houle" validate "$f"

# Rendering, small and quick: every shipped scene to PNG and to raw.
size=96x54
for f in "$src"/scenes/*.toml; do
  name=$(basename "$f" .toml)
  expect "render-png $name" 0 '2 frames written' "$houle" render "$f" --frames 2 --size $size --quality draft --out "$work/${name}_%02d.png"
  [ -s "$work/${name}_01.png" ] || { fail=$((fail + 1)); echo "FAIL render-png $name: no image"; }
  expect "render-raw $name" 0 '' "$houle" render "$f" --frames 2 --size $size --quality draft --raw "$work/$name.f32" --pixel-format rgbf32 --quiet
  if python3 "$src/tests/cli/check_raw.py" "$work/$name.f32" 96 54 2 >"$work/check.txt" 2>&1; then
    pass=$((pass + 1))
  else
    fail=$((fail + 1)); echo "FAIL raw content $name: $(cat "$work/check.txt")"
  fi
done
# A camera looking straight down (or up) renders: north is up in the image.
for look in 0 60; do
  f=$(scene "top-down-$look" "[camera]
position = [100.0, 50.0, 30.0]
look_at = [100.0, 50.0, $look.0]")
  expect "camera-vertical $look" 0 '' "$houle" render "$f" --frames 1 --size $size --quality draft --raw "$work/top.f32" --pixel-format rgbf32 --quiet
  if python3 "$src/tests/cli/check_raw.py" "$work/top.f32" 96 54 1 >"$work/check.txt" 2>&1; then
    pass=$((pass + 1))
  else
    fail=$((fail + 1)); echo "FAIL camera-vertical $look content: $(cat "$work/check.txt")"
  fi
done
# Determinism, on every shipped scene (coast.toml is the built-in coast) at the default quality, in linear floats:
# frames 0:3 in one run equal 0:1 and 2:3 in two (frame 2 rendered first, without the frames before
# it), and one render thread gives the bytes of two.
frame_bytes=$((96 * 54 * 3 * 4))
# render_f32 <scene> <name> <options...>: linear float frames into $work/<name>.f32
render_f32() { "$houle" render "$1" --size $size --raw "$work/$2.f32" --pixel-format rgbf32 --quiet "${@:3}"; }
for f in "$src"/scenes/*.toml; do
  name=$(basename "$f" .toml)
  render_f32 "$f" all --frames 0:3 && render_f32 "$f" a --frames 0:1 && render_f32 "$f" b --frames 2:3 &&
    render_f32 "$f" t1 --frames 0:3 --threads 1
  if cat "$work/a.f32" "$work/b.f32" | cmp -s - "$work/all.f32" && [ "$(stat -c %s "$work/all.f32")" -eq $((4 * frame_bytes)) ]; then
    pass=$((pass + 1))
  else
    fail=$((fail + 1)); echo "FAIL $name: split frame ranges differ from one run, or have the wrong size"
  fi
  if cmp -s "$work/all.f32" "$work/t1.f32"; then pass=$((pass + 1)); else fail=$((fail + 1)); echo "FAIL $name: 1 vs 2 threads differ"; fi
done
# A reader that closes the pipe early ends the run cleanly (exit 0, one line), not with SIGPIPE.
out=$( { "$houle" render --frames 100 --size $size --quality draft --raw - 2>"$work/err.txt"; echo "rc=$?" >"$work/rc.txt"; } | head -c 20000 | wc -c)
if [ "$out" -eq 20000 ] && grep -q 'rc=0' "$work/rc.txt" && grep -q 'output closed by its reader' "$work/err.txt"; then
  pass=$((pass + 1))
else
  fail=$((fail + 1)); echo "FAIL closed pipe: $(cat "$work/rc.txt") $(cat "$work/err.txt")"
fi
# SIGINT, SIGTERM and SIGHUP stop a render alike: after the current frame, "interrupted after N
# complete frames", exit 128 + the signal. Killed 100 times at random times (during the build too,
# before the handler is in place), a PNG sequence or a raw stream never keeps a temporary file or a
# partial frame.
kills=100 kill_started=0 kill_fail=0
quick=$(scene quick '[domain]
x_max = 100.0
y_max = 100.0
[floor.base]
depth = 300.0
[[trains]]
period = 5.0')
for i in $(seq $kills); do
  d="$work/kill$i"
  case $((i % 3)) in
    0) sig=INT code=130 ;;
    1) sig=TERM code=143 ;;
    2) sig=HUP code=129 ;;
  esac
  mkdir "$d"
  if [ $((i % 2)) -eq 0 ]; then out=(--out "$d/%04d.png"); else out=(--raw "$d/frames.rgb"); fi
  # env --default-signal: a background job of a script starts with SIGINT ignored.
  env --default-signal=INT "$houle" render "$quick" --frames 100000 --size 64x36 --quality draft --quiet "${out[@]}" 2>"$d/err" &
  pid=$!
  if [ $((i % 4)) -lt 2 ]; then  # half the kills once frames are coming out (loading OpenImageIO takes a while)
    for _ in $(seq 100); do [ -n "$(find "$d" -name '*.png' -o -name frames.rgb -size +0)" ] && break; sleep 0.05; done
  fi
  sleep "$(printf '0.%02d' $((RANDOM % 20)))"
  # A frame file (or a temporary one, or raw bytes) means the loop had begun, with the handler in place.
  started=$(find "$d" -name '*.png*' -o -name frames.rgb -size +0 | wc -l)
  kill -s "$sig" "$pid"
  { wait "$pid"; rc=$?; } 2>/dev/null  # without the shell's report of a process the signal ended
  frames=$(find "$d" -name '*.png' | wc -l)
  [ -e "$d/frames.rgb" ] && frames=$(($(stat -c %s "$d/frames.rgb") / (64 * 36 * 3)))
  why=""
  [ "$rc" -eq "$code" ] || why="exit $rc, want $code"
  [ -n "$(find "$d" -name '*.tmp*')" ] && why="$why; left $(find "$d" -name '*.tmp*')"
  [ -e "$d/frames.rgb" ] && [ $(($(stat -c %s "$d/frames.rgb") % (64 * 36 * 3))) -ne 0 ] && why="$why; a partial raw frame"
  if [ "$started" -gt 0 ]; then
    kill_started=$((kill_started + 1))
    grep -q "^houle render: interrupted after $frames complete frames in " "$d/err" || why="$why; want 'interrupted after $frames complete frames', got '$(cat "$d/err")'"
  fi
  [ -n "$why" ] && { kill_fail=$((kill_fail + 1)); echo "FAIL SIG$sig during render ${out[0]} (run $i): $why"; }
done
# shellcheck disable=SC2046
python3 "$src/tests/cli/check_png.py" 64 36 $(find "$work"/kill* -name '*.png') >"$work/check.txt" 2>&1 ||
  { kill_fail=$((kill_fail + 1)); echo "FAIL frames written before a signal: $(cat "$work/check.txt")"; }
# Half the kills at least land in the frame loop, else the handler went untested.
[ "$kill_started" -ge $((kills / 2)) ] ||
  { kill_fail=$((kill_fail + 1)); echo "FAIL only $kill_started of $kills kills came after the first frame"; }
if [ "$kill_fail" -eq 0 ]; then pass=$((pass + 1)); else fail=$((fail + 1)); fi

# houle info: the effect plan and the build's counts, as text and as JSON that parses.
f=$(scene deep-flat '[domain]
x_max = 100.0
y_max = 100.0
[floor.base]
depth = 300.0
[[trains]]
period = 5.0
[capillary]
amplitude = 0.0')
expect info-plan-deep 0 'ray tracing no, diffraction no, wall reflection no, capillary noise no' "$houle" info "$f"
expect info-analytic 0 'analytic: straight crests, no rays' "$houle" info "$f"
expect info-fig4 0 'ray tracing yes, diffraction yes, wall reflection yes' "$houle" info "$src/scenes/paper_fig4.toml"
expect info-fig4-counts 0 '^rays: [0-9]+ \([0-9]+ initial, [0-9]+ inserted, [1-9][0-9]* reflected\)' "$houle" info "$src/scenes/paper_fig4.toml"
expect info-fig4-diffraction 0 '^diffracted waves \(sea surface\): 1 \(pierheads x trains\), computed at [1-9][0-9]* grid nodes' "$houle" info "$src/scenes/paper_fig4.toml"
expect info-wave-model 0 '^wave model: parabolic \(auto: shoals' "$houle" info "$src/scenes/coast.toml"
{ cat "$src/scenes/coast.toml"; printf '\n[wave_model]\nkind = "rays"\n'; } >"$work/coast-rays.toml"
expect info-wave-model-chosen 0 '^wave model: rays \(wave_model.kind = "rays"\)' "$houle" info "$work/coast-rays.toml"
expect info-bad-quality 2 'info: --quality expects draft, realtime or film' "$houle" info --quality best
for args in "$f" "$src/scenes/paper_fig4.toml" ""; do
  # shellcheck disable=SC2086
  if "$houle" info $args --json >"$work/info.json" && python3 -m json.tool "$work/info.json" >/dev/null; then
    pass=$((pass + 1))
  else
    fail=$((fail + 1)); echo "FAIL info --json for '${args:-built-in}' does not parse: $(cat "$work/info.json")"
  fi
done
# The JSON says the same: no diffraction and no rays for the deep flat sea, the pierhead's diffracted
# wave computed by the sea surface for Fig. 4, whose straight rays never share a step between two
# lanes (a straight step is cheaper than the hand-off).
if "$houle" info "$f" --json | python3 -c 'import json,sys; d=json.load(sys.stdin); p=d["plan"]; t=d["totals"]
sys.exit(0 if not p["diffraction"] and not p["ray_tracing"] and t["rays"] == 0 and d["sea_diffraction"]["evaluations"] == 0
         and not d["trains"][0]["traced"] else 1)' &&
   "$houle" info "$src/scenes/paper_fig4.toml" --json | python3 -c 'import json,sys; d=json.load(sys.stdin)
sys.exit(0 if d["plan"]["diffraction"] and d["sea_diffraction"]["pierheads"] == 1 and d["sea_diffraction"]["evaluations"] > 0
         and d["build_ms"]["total"] > 0
         and d["totals"]["shared_steps"] == 0 else 1)'; then
  pass=$((pass + 1))
else
  fail=$((fail + 1)); echo "FAIL info --json facts"
fi
expect probe 0 'train 2: amplitude [0-9.]+ m' "$houle" probe --at 140,90 --at 145,110,2.5
expect probe-json 0 '"relative_amplitude"' "$houle" probe "$src/scenes/paper_fig4.toml" --at 25,75 --json
expect probe-bad 2 "probe: --at expects X,Y or X,Y,T" "$houle" probe --at 1
# Far from the domain float positions no longer hold the waves: refused, and JSON never holds NaN or inf.
for at in 1e9,0 1e12,0 1e30,0 0,-200001; do
  expect "probe-far $at" 2 "probe: --at .*: more than 100 km outside the domain" "$houle" probe --at "$at" --json
done
if "$houle" probe --at 0,0 --at 100200,-99000,1e6 --json | python3 -c 'import json,math,sys
def finite(v): return all(finite(x) for x in (v.values() if isinstance(v, dict) else v)) if isinstance(v, (dict, list)) else isinstance(v, str) or math.isfinite(v)
sys.exit(0 if finite(json.load(sys.stdin, parse_constant=lambda c: float(c))) else 1)'; then
  pass=$((pass + 1))
else
  fail=$((fail + 1)); echo "FAIL probe --json near the 100 km limit: not JSON, or not finite"
fi
# Where a probe lies, said plainly, and the depth (the coast's 1:30 beach: (170 - y) / 30 m).
expect probe-help 0 'x,y,t,where,depth,height,grad_x,grad_y,train,amplitude' "$houle" probe --help
"$houle" probe --at 100,185 --at 150,150 --at 300,50 --at 100,60 >"$work/where.txt"
if grep -q '^(100, 185) t=0 s: on land (floor 0.50 m above still water): no waves$' "$work/where.txt" &&
   grep -q '^(150, 150) t=0 s: inside a wall: no water$' "$work/where.txt" &&
   grep -q '^(300, 50) t=0 s: outside the domain (no rays traced; each train continues the wave at the edge), depth 4.00 m, height' "$work/where.txt" &&
   grep -q '^(100, 60) t=0 s: water 3.67 m deep, height' "$work/where.txt" && [ "$(grep -c '  train ' "$work/where.txt")" -eq 6 ]; then
  pass=$((pass + 1))
else
  fail=$((fail + 1)); echo "FAIL probe where (text): $(cat "$work/where.txt")"
fi
# A time series as JSON (point by point, time by time) and as CSV (a row per point, time and train).
if "$houle" probe --at 100,185 --at 100,60 --times 0:1:0.25 --json | python3 -c 'import json,sys
d = json.load(sys.stdin)
assert [(p["x"], p["y"], p["t"]) for p in d] == [(x, y, t) for x, y in ((100, 185), (100, 60)) for t in (0, 0.25, 0.5, 0.75, 1)]
assert [p["where"] for p in d] == ["land"] * 5 + ["water"] * 5
assert abs(d[0]["depth"] + 0.5) < 1e-5 and abs(d[5]["depth"] - 110 / 30) < 1e-5
assert all(len(p["trains"]) == 3 for p in d) and len({p["height"] for p in d[5:]}) == 5'; then
  pass=$((pass + 1))
else
  fail=$((fail + 1)); echo "FAIL probe --times --json"
fi
if "$houle" probe --at 150,150 --at 100,60 --times 2:3:0.5 --csv | python3 -c 'import csv,sys
rows = list(csv.reader(sys.stdin))
assert rows[0] == "x,y,t,where,depth,height,grad_x,grad_y,train,amplitude,relative_amplitude,diffraction,wavelength,direction_deg,phase,incident,diffracted,reflected".split(",")
assert len(rows) == 1 + 2 * 3 * 3 and all(len(r) == 18 for r in rows)
assert [(r[0], r[1], r[2], r[3], r[8]) for r in rows[1:4]] == [("150", "150", "2", "wall", k) for k in "012"]
assert [r[2] for r in rows[10::3]] == ["2", "2.5", "3"] and {r[3] for r in rows[10:]} == {"water"}
assert all(float(v) == float(v) for r in rows[1:] for v in r[4:8] + r[9:])'; then
  pass=$((pass + 1))
else
  fail=$((fail + 1)); echo "FAIL probe --times --csv"
fi
f=$(scene no-trains '[floor.base]
depth = 5.0')
expect probe-csv-no-trains 0 '^1,2,0\.5,water,5,0,0,0,,,,,,,,,,$' "$houle" probe "$f" --at 1,2 --times 0:0.5:0.5 --csv
expect probe-json-csv 2 'probe: --json and --csv exclude each other' "$houle" probe --at 1,2 --json --csv
# A sea state (docs/physics.md 2.9): houle probe --times at an offshore point of deep water, over half
# an hour, has Hs = 4 standard deviations of the height within 5 %; its components follow the written
# train in the probe's rows; a component over the Stokes limit and a sinking float are refused.
f=$(scene sea-state '[domain]
x_max = 300.0
y_max = 300.0
[floor.base]
depth = 80.0
[[trains]]
period = 12.0
amplitude = 0.0
[[sea_states]]
significant_height = 1.5
peak_period = 7.0
components = 24')
expect info-sea-state 0 '\[24\] period [0-9.]+ s, .*, of sea_states\[0\]' "$houle" info "$f"
expect info-floating 0 'boxes: 1, spheres: 1 \(2 floating\)' "$houle" info "$src/scenes/buoy.toml"
if "$houle" probe "$f" --at 150,150 --times 0:1800:0.5 --csv | python3 -c 'import csv,statistics,sys
rows = list(csv.DictReader(sys.stdin))
heights = {r["t"]: float(r["height"]) for r in rows}
trains = {r["train"] for r in rows}
hs = 4 * statistics.pstdev(heights.values())
assert len(heights) == 3601 and len(trains) == 25, (len(heights), len(trains))
assert abs(hs / 1.5 - 1) < 0.05, hs' >"$work/check.txt" 2>&1; then
  pass=$((pass + 1))
else
  fail=$((fail + 1)); echo "FAIL sea-state probe Hs: $(cat "$work/check.txt")"
fi
f=$(scene steep-sea '[[sea_states]]
significant_height = 9.0
peak_period = 5.0')
expect sea-state-stokes 2 'steep-sea.toml:2:22: error: sea_states\[0\].significant_height: at most what keeps every component under the deep-water breaking \(Stokes\) limit' "$houle" validate "$f"
f=$(scene sinking '[[spheres]]
float = true
density = 2000.0')
expect float-density 2 'sinking.toml:3:11: error: spheres\[0\].density: a value in \(0, 1025\) kg/m³, got 2000' "$houle" validate "$f"
expect probe-at-t-times 2 'probe: --at 1,2,3 gives its own time, and --times gives the times of every point' "$houle" probe --at 1,2,3 --times 0:1:0.5
expect probe-times-form 2 "probe: --times expects T0:T1:DT in s .*got '0:1'" "$houle" probe --at 1,2 --times 0:1
expect probe-times-step 2 'probe: --times 0:1:0: the step DT must be > 0 s' "$houle" probe --at 1,2 --times 0:1:0
expect probe-times-order 2 'probe: --times 1:0:0.1: T1 must be >= T0' "$houle" probe --at 1,2 --times 1:0:0.1
expect probe-times-many 2 'probe: --times 0:1e9:0.001: more than 1000000 times' "$houle" probe --at 1,2 --times 0:1e9:0.001
expect probe-times-points 2 'probe: --times 0:999999:1 at 2 points makes 2000000 probes \(points x times\), more than 1000000' "$houle" probe --at 1,2 --at 3,4 --times 0:999999:1
# info warns of an island (Plate 3's rock breaks the surface) and of a pierhead a wavelength from the edge.
expect info-island 0 '^warning: an island at \(70\.0, 88\.0\) m \(land rising through the surface' "$houle" info "$src/scenes/paper_plate3.toml"
f=$(scene edge-wall '[domain]
x_max = 200.0
y_max = 200.0
[floor.base]
depth = 60.0
[[walls]]
points = [[60.0, 100.0], [197.0, 100.0]]
[[trains]]
wavelength = 4.0
amplitude = 0.2
direction_deg = 270.0
[capillary]
amplitude = 0.0')
expect info-edge-pierhead 0 "^warning: walls\[0\] ends in the water at \(197\.0, 100\.0\) m, 3\.00 m from the domain's edge, within a wavelength \(4\.00 m, train 0\): waves pass between it and the edge, and diffract round it$" "$houle" info "$f"
if "$houle" info "$f" --json | python3 -c 'import json,sys; w = json.load(sys.stdin)["warnings"]; sys.exit(0 if len(w) == 1 and w[0].startswith("walls[0] ends") else 1)' &&
   "$houle" info --json | python3 -c 'import json,sys; sys.exit(0 if json.load(sys.stdin)["warnings"] == [] else 1)' &&
   ! "$houle" info | grep -q warning; then
  pass=$((pass + 1))
else
  fail=$((fail + 1)); echo "FAIL info warnings in JSON, or a warning for the built-in coast"
fi
expect bench 0 '^frame +[0-9.]+' "$houle" bench --frames 3 --warmup 1 --size $size --quality draft
expect bench-json 0 '"p99"' "$houle" bench --frames 2 --warmup 0 --size $size --quality draft --json
expect unwritable 2 'cannot open for writing' "$houle" render --frames 1 --size $size --raw /nonexistent-dir/x.rgb
# The output is checked before the scene is built: with a scene the build refuses (limit-memory's),
# the output's error comes first.
big=$work/huge-build.toml
touch "$work/plain"
# An image sequence's missing folders are made (once the scene is built); one that cannot be is refused before.
expect early-unmakeable-folder 2 "render: $work/plain/nodir/%04d.png: $work/plain is not a folder" "$houle" render "$big" --frames 1 --out "$work/plain/nodir/%04d.png"
expect early-raw-folder 2 "cannot open for writing: the folder $work/nodir does not exist" "$houle" render "$big" --frames 1 --raw "$work/nodir/x.rgb"
expect early-extension 2 'x_%04d.xyz: no image format for this file name' "$houle" render "$big" --frames 1 --out "$work/x_%04d.xyz"
expect early-not-folder 2 "$work/plain is not a folder" "$houle" render "$big" --frames 1 --out "$work/plain/%04d.png"
mkdir "$work/ro" && chmod 555 "$work/ro"
ro=$work/ro
[ -w "$ro" ] && ro=/proc/1  # root writes into a mode 555 folder, not into a process's /proc folder
if [ -w "$ro" ]; then
  echo "skipped early-unwritable: no unwritable folder found for $(id -un)"
else
  expect early-unwritable 2 "the folder $ro is not writable" "$houle" render "$big" --frames 1 --out "$ro/%04d.png"
  expect early-unwritable-raw 2 "cannot open for writing: the folder $ro is not writable" "$houle" render "$big" --frames 1 --raw "$ro/x.rgb"
fi
expect bad-size 2 "render: --size expects WxH" "$houle" render --size 0x10
expect bad-frames 2 "render: --frames expects A:B" "$houle" render --frames 5:2
expect out-and-raw 2 'render: --out and --raw exclude each other' "$houle" render --out x%d.png --raw -
expect bad-pattern 2 'needs exactly one frame-number conversion' "$houle" render --frames 1 --size $size --out "$work/x.png"
# The output pattern's folder is made with its parents, like the default frames/ (README's Fig. 4 example).
expect out-new-folder 0 '1 frames written' "$houle" render --frames 1 --size $size --quality draft --out "$work/fig4/a/%04d.png"
[ -s "$work/fig4/a/0000.png" ] || { fail=$((fail + 1)); echo "FAIL out-new-folder: no image"; }
# Float images hold the linear frame (the raw rgbf32 bytes) within their format's precision, whatever
# the extension's case; TIFF when --pixel-format rgbf32 asks for floats.
render_draft() { "$houle" render --frames 1 --size $size --quality draft --quiet "$@"; }
render_draft --raw "$work/linear.f32" --pixel-format rgbf32
for case in exr:half Exr:half hdr:rgbe tif:float; do
  ext=${case%%:*}
  extra=(); [ "$ext" = tif ] && extra=(--pixel-format rgbf32)
  if render_draft --out "$work/linear_%d.$ext" "${extra[@]}" && oiiotool --dumpdata "$work/linear_0.$ext" >"$work/dump.txt" &&
     python3 "$src/tests/cli/check_float_image.py" "$work/linear.f32" "$work/dump.txt" "${case##*:}" >"$work/check.txt" 2>&1; then
    pass=$((pass + 1))
  else
    fail=$((fail + 1)); echo "FAIL float image .$ext: $(cat "$work/check.txt")"
  fi
done
expect float-png 2 '32-bit float images need .exr, .hdr, .tif or .tiff' "$houle" render --frames 1 --size $size --out "$work/f%d.png" --pixel-format rgbf32
# --pixel-format is for raw frames: refused with images (but rgbf32); ffmpeg's names, the old ones as aliases.
expect pixel-format-out 2 'pixel-format rgba is for --raw; images take their format from the --out extension' "$houle" render --frames 1 --out "$work/p%d.png" --pixel-format rgba
for pf in rgb24:3 rgba:4 bgra:4 rgba8:4 bgra8:4; do
  render_draft --raw "$work/pf.raw" --pixel-format "${pf%%:*}"
  if [ "$(stat -c %s "$work/pf.raw")" -eq $((96 * 54 * ${pf##*:})) ]; then pass=$((pass + 1)); else fail=$((fail + 1)); echo "FAIL --pixel-format ${pf%%:*}"; fi
done
# The help's ffmpeg example makes a video players can show (4:2:0), as the README's does.
# A scene from standard input (-), and -- before a scene whose name starts with -.
expect stdin-validate 0 '^standard input: ok' sh -c '"$1" validate - <"$2"' sh "$houle" "$src/scenes/paper_fig4.toml"
expect stdin-error 2 '^standard input:1:8: error: ' sh -c 'printf "[trains\n" | "$1" validate -' sh "$houle"
expect stdin-render 0 '1 frames written' sh -c '"$1" render - --frames 0:0 --size 48x27 --quality draft --raw "$2" <"$3"' \
  sh "$houle" "$work/stdin.rgb" "$src/scenes/paper_fig4.toml"
cp "$src/scenes/paper_fig4.toml" "$work/-fig4.toml"
expect dash-dash 0 '^-fig4.toml: ok' sh -c 'cd "$1" && "$2" validate -- -fig4.toml' sh "$work" "$houle"
expect dash-name-without-dash-dash 2 "unknown option '-fig4.toml'" sh -c 'cd "$1" && "$2" validate -fig4.toml' sh "$work" "$houle"
# Frames are not written to a terminal (script gives the command one).
expect raw-to-terminal 2 'standard output is a terminal' script -qec "$houle render --frames 0:0 --size 48x27 --raw -" /dev/null
expect y4m-to-terminal 2 'standard output is a terminal' script -qec "$houle render --frames 0:0 --size 48x27 --y4m -" /dev/null
# --realtime says when rendering falls behind (1000 fps: every frame is late).
for pattern in 'warning: --realtime: frame 0 is late \(rendering is slower than 1000 fps\)' '\(4 late for --realtime\)$'; do
  expect "realtime-late /$pattern/" 0 "$pattern" \
    "$houle" render "$src/scenes/paper_fig4.toml" --frames 0:3 --size 160x90 --fps 1000 --realtime --raw "$work/late.rgb"
done
expect help-ffmpeg 0 'ffmpeg .*-pix_fmt yuv420p' "$houle" render --help
# Threads default to the machine's (frames do not depend on them: the 1-vs-2 check above).
expect help-threads 0 "--threads N .*default: the machine's hardware threads" "$houle" render --help
expect info-threads 0 "\"threads\": $(getconf _NPROCESSORS_ONLN)," "$houle" info --json
# Progress reaches a log too (a line, no carriage return), and every run ends with a summary, raw ones too.
"$houle" render --frames 3 --size $size --quality draft --raw "$work/p.raw" 2>"$work/err.txt"
if grep -qE '^frame 0 \(1/3\) +[0-9.]+ fps +ETA [0-9]+:[0-9]{2}:[0-9]{2}$' "$work/err.txt" && ! grep -q $'\r' "$work/err.txt" &&
   grep -qE "^houle render: 3 frames written to $work/p.raw in [0-9]+:[0-9]{2}:[0-9.]+ \([0-9.]+ fps\)$" "$work/err.txt"; then
  pass=$((pass + 1))
else
  fail=$((fail + 1)); echo "FAIL progress and summary to a log: $(cat -A "$work/err.txt")"
fi
expect quiet 0 '^$' "$houle" render --frames 2 --size $size --quality draft --raw "$work/p.raw" --quiet
# Scene errors start with file:line:col (gcc's form, for editors); a misspelt key gets a suggestion.
expect did-you-mean 2 "unknown-key.toml:2:1: error: camera.positon: unknown key; did you mean \`position\`\?" "$houle" validate "$(scene unknown-key '[camera]
positon = [1, 2, 3]')"
expect did-you-mean-train 2 "^[^ ]*typo.toml:2:1: error: trains\[0\].peroid: unknown key; did you mean \`period\`\?" "$houle" render "$(scene typo '[[trains]]
peroid = 5.0')"
expect did-you-mean-section 2 "section.toml:1:2: error: camra: unknown key; did you mean \`camera\`\?" "$houle" info "$(scene section '[camra]')"
expect no-suggestion 2 'far.toml:2:1: error: camera.zzzzzz: unknown key \(see' "$houle" validate "$(scene far '[camera]
zzzzzz = 1')"

echo "cli: ${pass} passed, ${fail} failed"
[ "$fail" -eq 0 ]
