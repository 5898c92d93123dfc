#!/usr/bin/env bash
# The data houle gives other tools: y4m streams into ffmpeg and ffprobe, EXR headers (deterministic,
# camera matrices, frame and time) and AOV channels, houle map's grids, houle bench's JSON.
# Usage: test_data_out.sh <houle binary> <source dir>
set -uo pipefail
houle=$1 src=$2
. "$(dirname "$0")/expect.sh"
# check <name> <command...>: passes when the command succeeds
check() {
  local name=$1; shift
  local out
  if out=$("$@" 2>&1); then pass=$((pass + 1)); else fail=$((fail + 1)); printf 'FAIL %s:\n%s\n' "$name" "$out"; fi
}
for tool in ffmpeg ffprobe oiiotool python3; do
  command -v $tool >/dev/null || { echo "test_data_out: $tool is missing: run scripts/setup"; exit 1; }
done
render() { "$houle" render --size 64x36 --quality draft --quiet "$@"; }

# ---- y4m -------------------------------------------------------------------------------------------
# ffprobe reads the size, the rate, the subsampling and the range from the stream alone.
probe_y4m() { ffprobe -v error -show_entries stream=width,height,r_frame_rate,pix_fmt,color_range -of csv=p=0 "$@"; }
render --frames 3 --y4m - | probe_y4m - >"$work/probe.txt" 2>&1
check y4m-ffprobe-420 grep -qx '64,36,yuv420p,tv,30/1' "$work/probe.txt"
render --frames 3 --fps 29.97 --y4m "$work/clip444.y4m" --y4m-chroma 444
probe_y4m "$work/clip444.y4m" >"$work/probe.txt" 2>&1
check y4m-ffprobe-444 grep -qx '64,36,yuv444p,tv,30000/1001' "$work/probe.txt"
# Into ffmpeg without a size or a rate (the README's and --help's example): H.264 in 4:2:0, every frame,
# tagged BT.709 in limited range.
render --frames 5 --y4m - | ffmpeg -v error -i - -colorspace bt709 -color_primaries bt709 -color_trc bt709 -y "$work/coast.mp4"
ffprobe -v error -count_frames -show_entries stream=codec_name,width,height,pix_fmt,color_range,color_space,nb_read_frames \
  -of csv=p=0 "$work/coast.mp4" >"$work/probe.txt" 2>&1
check y4m-ffmpeg-mp4 grep -qx 'h264,64,36,yuv420p,tv,bt709,5' "$work/probe.txt"
expect y4m-help 0 'houle render --frames 240 --y4m - \| ffmpeg -i - -colorspace bt709' "$houle" render --help
# The planes are ffmpeg's own BT.709 limited-range conversion of the same frames' rgb24 codes, to
# within its fixed-point rounding (one code).
render --frames 2 --raw "$work/clip.rgb"
ffmpeg -v error -f rawvideo -pix_fmt rgb24 -s 64x36 -i "$work/clip.rgb" \
  -vf scale=out_color_matrix=bt709:out_range=tv:flags=accurate_rnd+full_chroma_int,format=yuv444p -f rawvideo -y "$work/ffmpeg.yuv"
render --frames 2 --y4m "$work/clip2.y4m" --y4m-chroma 444
check y4m-vs-ffmpeg python3 - "$work/clip2.y4m" "$work/ffmpeg.yuv" <<'PY'
import sys
y4m, ref = open(sys.argv[1], "rb").read(), open(sys.argv[2], "rb").read()
header, rest = y4m.split(b"\n", 1)
frames = rest.split(b"FRAME\n")[1:]
assert len(frames) == 2 and all(len(f) == 64 * 36 * 3 for f in frames), "two 4:4:4 frames"
ours = b"".join(frames)
assert len(ours) == len(ref), (len(ours), len(ref))
worst = max(abs(a - b) for a, b in zip(ours, ref))
assert worst <= 1, f"off ffmpeg's conversion by {worst} codes"
PY
# --y4m is a stream like --raw: --skip-existing writes it whole; refused beside other outputs.
render --frames 2 --y4m "$work/whole.y4m" --skip-existing
check y4m-whole test "$(head -c 9 "$work/whole.y4m")" = YUV4MPEG2
expect y4m-and-raw 2 'render: --y4m and --raw exclude each other' "$houle" render --y4m - --raw x.rgb
expect y4m-and-out 2 'render: --y4m and --out exclude each other' "$houle" render --y4m - --out 'x%d.png'
expect y4m-chroma 2 "render: --y4m-chroma expects 444 or 420, got '422'" "$houle" render --y4m - --y4m-chroma 422
expect y4m-chroma-alone 2 'render: --y4m-chroma is for --y4m' "$houle" render --y4m-chroma 444 --raw -
expect y4m-pixel-format 2 'render: --pixel-format is for --raw: --y4m writes' "$houle" render --y4m - --pixel-format rgba
expect y4m-farm 2 'farm slurm: --y4m' "$houle" farm slurm --frames 0:9 --chunk 5 --y4m clip.y4m --dry-run

# ---- EXR headers and AOVs ----------------------------------------------------------------------------
cat >"$work/calm.toml" <<'TOML'
[domain]
x_max = 200.0
y_max = 200.0
[floor.base]
depth = 50.0
[[trains]]
period = 5.0
amplitude = 0.2
[capillary]
amplitude = 0.0
[camera]
position = [100.0, 10.0, 6.0]
look_at = [100.0, 80.0, 0.0]
TOML
# Two renders of a frame are the same bytes (no date), EXR with AOVs and PNG alike.
for ext in exr png; do
  aov=(); [ $ext = exr ] && aov=(--aov z,normal,alpha,sea)
  render "$work/calm.toml" --frames 7:7 --out "$work/a_%d.$ext" "${aov[@]}"
  sleep 1.1  # a date in seconds would differ
  render "$work/calm.toml" --frames 7:7 --out "$work/b_%d.$ext" "${aov[@]}"
  check "deterministic-$ext" cmp "$work/a_7.$ext" "$work/b_7.$ext"
done
render "$work/calm.toml" --frames 7:7 --fps 24 --out "$work/c_%d.exr"
check exr-header python3 "$src/tests/cli/check_exr_header.py" "$work/c_7.exr" 7 24/1 100,10,6 100,80,0
check exr-header-aovs python3 "$src/tests/cli/check_exr_header.py" "$work/a_7.exr" 7 30/1 100,10,6 100,80,0
expect exr-channels 0 'channel list: R \(half\), G \(half\), B \(half\), A \(half\), Z \(float\), .*N.X \(half\), N.Y \(half\), N.Z \(half\)' oiiotool --info -v "$work/a_7.exr"
expect exr-channel-sea 0 'channel list: .*sea \(half\)' oiiotool --info -v "$work/a_7.exr"
expect exr-no-aovs 0 'channel list: R, G, B$' oiiotool --info -v "$work/c_7.exr"
# The AOVs agree with the image's own matrices: Z is the depth along the view axis of a point on the
# sea (a 0.2 m train: within 0.25 m of z = 0), uncovered pixels have Z = inf and no normal.
{ oiiotool --info -v "$work/a_7.exr"; oiiotool --dumpdata "$work/a_7.exr"; } >"$work/dump.txt"
check exr-aovs python3 "$src/tests/cli/check_aovs.py" "$work/a_7.exr" "$work/dump.txt" 0.25
render "$work/calm.toml" --frames 7:7 --out "$work/z_%d.exr" --aov z
expect exr-aov-z 0 'channel list: R \(half\), G \(half\), B \(half\), Z \(float\)$' oiiotool --info -v "$work/z_7.exr"
expect aov-png 2 "render: --aov needs EXR images \(--out NAME%04d.exr\): '.*x_%d.png' have no place for extra channels" "$houle" render --aov z --out "$work/x_%d.png"
expect aov-raw 2 'render: --aov needs EXR images .*--raw frames have no place' "$houle" render --aov z --raw -
expect aov-y4m 2 'render: --aov needs EXR images .*--y4m streams have no place' "$houle" render --aov alpha --y4m -
expect aov-name 2 "render: --aov expects a list of z, normal, alpha and sea \(e.g. z,normal\), got 'depth'" "$houle" render --aov z,depth --out "$work/x_%d.exr"

# ---- houle map ---------------------------------------------------------------------------------------
# A deep flat sea of two straight trains: every point has the trains' own amplitudes, K' = 1, no
# reflection, the deep-water wavelengths g T^2 / 2 pi (39.03 and 14.05 m) and their directions, and
# Hs = 4 sqrt((0.2^2 + 0.1^2) / 2) = 0.63246 m.
cat >"$work/two.toml" <<'TOML'
[domain]
x_max = 200.0
y_max = 200.0
[floor.base]
depth = 300.0
[[trains]]
period = 5.0
amplitude = 0.2
direction_deg = 60.0
[[trains]]
period = 3.0
amplitude = 0.1
[capillary]
amplitude = 0.0
TOML
expect map-csv 0 'houle map: 3 x 3 points, 12 channels written to' "$houle" map "$work/two.toml" --grid 0:200:100,0:200:100 \
  --fields depth,hs,amplitude,kd,reflected,wavelength,direction --out "$work/two.csv"
check map-analytic python3 - "$work/two.csv" <<'PY'
import csv, math, sys
rows = list(csv.reader(open(sys.argv[1])))
assert rows[0] == "x,y,depth,hs,amplitude.0,amplitude.1,kd.0,kd.1,reflected.0,reflected.1,wavelength.0,wavelength.1,direction.0,direction.1".split(","), rows[0]
assert [(r[0], r[1]) for r in rows[1:]] == [(x, y) for y in ("0", "100", "200") for x in ("0", "100", "200")]
want = [300, 4 * math.sqrt((0.2**2 + 0.1**2) / 2), 0.2, 0.1, 1, 1, 0, 0, 9.81 * 25 / (2 * math.pi), 9.81 * 9 / (2 * math.pi), 60, 90]
for r in rows[1:]:
    for got, w in zip(map(float, r[2:]), want):
        assert abs(got - w) <= 1e-4 * max(1, abs(w)), (r, want)
PY
# On the built-in coast the map reads what houle probe reads at the same points.
"$houle" map --grid 20:180:80,20:140:60 --fields depth,amplitude,kd,reflected,wavelength,direction --out "$work/coast.csv" 2>/dev/null
"$houle" probe --at 20,20 --at 180,80 --at 100,140 --csv >"$work/probe.csv"
check map-vs-probe python3 - "$work/coast.csv" "$work/probe.csv" <<'PY'
import csv, sys
m = {(r["x"], r["y"]): r for r in csv.DictReader(open(sys.argv[1]))}
p = list(csv.DictReader(open(sys.argv[2])))
assert len(p) == 9
for r in p:
    row, k = m[(r["x"], r["y"])], r["train"]
    pairs = [("depth", "depth"), ("amplitude", f"amplitude.{k}"), ("diffraction", f"kd.{k}"), ("reflected", f"reflected.{k}"),
             ("wavelength", f"wavelength.{k}"), ("direction_deg", f"direction.{k}")]
    for a, b in pairs:
        assert float(r[a]) == float(row[b]), (r["x"], r["y"], a, r[a], row[b])
PY
# EXR: a float channel per field, north up: the top-left pixel is (X0, Y1). The coast's 1:30 beach
# is (170 - y) / 30 m deep.
expect map-exr 0 'written to' "$houle" map --grid 0:100:50,0:150:50 --fields depth,hs --out "$work/coast.exr"
expect map-exr-channels 0 '3 x +4, 2 channel, float openexr' oiiotool --info "$work/coast.exr"
expect map-exr-header 0 'houle:grid: "0:100:50,0:150:50"' oiiotool --info -v "$work/coast.exr"
oiiotool --dumpdata "$work/coast.exr" >"$work/dump.txt"
check map-exr-north-up python3 - "$work/dump.txt" <<'PY'
import re, sys
px = {(int(a), int(b)): [float(v) for v in c.split()] for a, b, c in re.findall(r"Pixel \((\d+), (\d+)\): (.*)", open(sys.argv[1]).read())}
assert abs(px[(0, 0)][0] - 20 / 30) < 1e-5 and abs(px[(2, 3)][0] - 170 / 30) < 1e-5, (px[(0, 0)], px[(2, 3)])
PY
expect map-help 0 'hs +significant wave height, m: 4 sqrt\(sum of a_i\^2 / 2\)' "$houle" map --help
expect map-no-grid 2 'map: expects --grid X0:X1:DX,Y0:Y1:DY' "$houle" map --out "$work/x.csv"
expect map-bad-grid 2 "map: --grid expects X0:X1:DX,Y0:Y1:DY in m, got '0:1:1'" "$houle" map --grid 0:1:1 --out "$work/x.csv"
expect map-grid-order 2 'map: --grid: Y1 must be >= Y0, got 5:0:1' "$houle" map --grid 0:1:1,5:0:1 --out "$work/x.csv"
expect map-grid-step 2 'map: --grid: the step DX must be > 0 m' "$houle" map --grid 0:1:0,0:1:1 --out "$work/x.csv"
expect map-grid-size 2 'map: --grid: more than 16384 points along X' "$houle" map --grid 0:1e6:1,0:1:1 --out "$work/x.csv"
expect map-grid-far 2 'map: --grid .*: the point \(200000, 0\) lies more than 100 km outside the domain' "$houle" map --grid 0:200000:20000,0:1:1 --out "$work/x.csv"
expect map-field 2 "map: --fields expects a list of depth, hs, amplitude, kd, reflected, wavelength and direction, got 'height'" "$houle" map --grid 0:1:1,0:1:1 --fields depth,height --out "$work/x.csv"
expect map-field-twice 2 'map: --fields names hs twice' "$houle" map --grid 0:1:1,0:1:1 --fields hs,depth,hs --out "$work/x.csv"
expect map-extension 2 "map: --out expects a .exr or .csv file, got '.*x.png'" "$houle" map --grid 0:1:1,0:1:1 --out "$work/x.png"
expect map-no-out 2 'map: expects --out FILE.exr or FILE.csv' "$houle" map --grid 0:1:1,0:1:1
expect map-no-trains 2 'has no trains: the per-train fields kd make no channel' "$houle" map "$(printf '[floor.base]\ndepth = 5.0\n' >"$work/calm0.toml"; echo "$work/calm0.toml")" --grid 0:1:1,0:1:1 --fields kd --out "$work/x.csv"
expect map-folder 2 'cannot open for writing: the folder .*/nodir does not exist' "$houle" map --grid 0:1:1,0:1:1 --out "$work/nodir/x.csv"

# ---- houle bench --json and --gbench-json --------------------------------------------------------------
bench() { "$houle" bench --frames 3 --warmup 1 --size 32x18 --quality draft "$@"; }
bench --json --gbench-json "$work/g1.json" >"$work/bench.json" && bench --gbench-json "$work/g2.json" >/dev/null
check bench-json-schema python3 - "$work/bench.json" "$(getconf _NPROCESSORS_ONLN)" <<'PY'
import json, re, sys
d = json.load(open(sys.argv[1]))
assert d["schema"] == 1
c = d["context"]
assert set(c) == {"houle_version", "isa", "threads", "host_cpu", "date", "scene", "size", "quality", "frames", "warmup"}, c
assert re.fullmatch(r"\d+\.\d+\.\d+", c["houle_version"]) and c["isa"] and c["host_cpu"]
assert re.fullmatch(r"\d{4}-\d\d-\d\dT\d\d:\d\d:\d\dZ", c["date"]), c["date"]
assert c["threads"] == int(sys.argv[2]) and c["scene"] == "built-in coast" and c["size"] == [32, 18]
assert c["quality"] == "draft" and c["frames"] == 3 and c["warmup"] == 1
assert d["build_ms"] > 0 and 0 <= d["primary_reused"] <= 1 and 0 < d["render_busy"] <= 1
assert list(d["stages_ms"]) == ["frame", "surface", "noise", "march", "intersect", "shade"]
assert all(set(s) == {"median", "p90", "p99", "max"} and s["median"] <= s["p90"] <= s["p99"] <= s["max"] for s in d["stages_ms"].values())
PY
# Google Benchmark's format as tools/compare.py reads it: entries it can compare (time_unit, real_time,
# cpu_time), matched by name across two runs, every frame a repetition, then the aggregates; the
# median aggregate is the --json report's median of the same run.
check bench-gbench python3 - "$work/g1.json" "$work/g2.json" "$work/bench.json" <<'PY'
import json, sys
a, b, report = (json.load(open(p)) for p in sys.argv[1:])
assert a["context"]["executable"] == "houle bench" and a["context"]["houle_version"] == report["context"]["houle_version"]
for run in (a, b):
    for e in run["benchmarks"]:
        assert {"name", "run_name", "run_type", "repetitions", "repetition_index", "threads", "iterations", "real_time", "cpu_time", "time_unit"} <= set(e), e
        assert e["time_unit"] == "ms" and e["iterations"] == 1 and e["real_time"] >= 0 and e["cpu_time"] == e["real_time"]
        assert e["run_type"] in ("iteration", "aggregate") and (e["run_type"] == "iteration") == ("aggregate_name" not in e)
names = lambda run: list(dict.fromkeys(e["name"] for e in run["benchmarks"]))
stages = ["frame", "surface", "noise", "march", "intersect", "shade"]
want = [f"built-in coast/32x18/draft/{s}{agg}" for s in stages for agg in ("", "_mean", "_median", "_stddev")]
assert names(a) == names(b) == want, names(a)
for name in names(a):
    lhs = [e for e in a["benchmarks"] if e["name"] == name]
    assert len(lhs) == (1 if "_" in name.rsplit("/", 1)[1] else 3), (name, len(lhs))
for s in stages:
    median = next(e for e in a["benchmarks"] if e["name"] == f"built-in coast/32x18/draft/{s}_median")
    assert median["aggregate_name"] == "median" and abs(median["real_time"] - report["stages_ms"][s]["median"]) < 1e-3, s
PY
expect bench-gbench-folder 2 'bench: --gbench-json .*/nodir/g.json: cannot open for writing' "$houle" bench --frames 1 --size 32x18 --gbench-json "$work/nodir/g.json"

echo "data_out: ${pass} passed, ${fail} failed"
[ "$fail" -eq 0 ]
